// stitch_mesh.h — stitch meshes (issue 3, deliverable 1): one polygon face per
// stitch, read from OBJ (plus an optional sidecar of stitch types), built-in
// flat patches, built-in affine deformations, and the per-face 2D deformation
// gradient that drives knot interpolation (001_dce8d4d1f783b802.txt §5.2).
//
// Convention (docs/stitch-meshes.md has figures). Vertices run counter-clockwise
// seen from the front, the side the face normal points to. The course is the
// direction a row of stitches is knitted in, the wale the direction rows stack
// in (one column of stitches). v0->v1 runs along the course (bar the triangle):
//   knit, purl, yarn-over quad   v0 bottom-left, v1 bottom-right, v2 top-right,
//                                v3 top-left; v1->v2 runs up the wale.
//   increase (pentagon)          one loop in at the bottom, two out at the top:
//                                v0 BL, v1 BR, v2 TR, v3 top-middle, v4 TL.
//   decrease (pentagon)          two loops in at the bottom, one out at the top:
//                                v0 BL, v1 bottom-middle, v2 BR, v3 TR, v4 TL.
//   yarn-over triangle           no loop below, so the bottom collapses to a
//                                point: v0 bottom, v1 top-right, v2 top-left.
// courseEdge() gives, per face, the two corners whose difference is the face's
// course direction (v0->v1, v0->v2 for a decrease, v2->v1 for a triangle); the
// 2D face frame puts e1 along it.
//
// Every error about bad input is an ft::InputError that names the file (or the
// built-in source) and the element: faces and vertices are counted from 0, like
// the arrays below, with the OBJ line of the face alongside.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ft {

enum class StitchType { Knit, Purl, Decrease, Increase, YarnOver };

// "knit", "purl", "decrease", "increase", "yarnover": the OBJ group and JSON names.
std::string_view stitchTypeName(StitchType type);
// nullopt for any other spelling (names are case-sensitive).
std::optional<StitchType> parseStitchType(std::string_view name);
// Whether a face of `count` vertices can hold a stitch of `type`: knit and purl
// take 4, increase and decrease 5, yarn-over 3 or 4.
bool stitchTypeAcceptsCount(StitchType type, uint32_t count);

// Unused entries of StitchFace::v (count < 5) hold this value.
inline constexpr uint32_t kNoVertex = 0xffffffffu;

struct StitchFace {
  std::array<uint32_t, 5> v;  // vertex indices (0-based), counter-clockwise
  uint32_t count;             // 3 to 5
  StitchType type;
  uint32_t objLine;  // 1-based OBJ line of the `f`; 0 for generated meshes
};

struct StitchMesh {
  std::string name;  // the file name (or built-in source) used in every message
  std::vector<glm::dvec3> vertices;
  std::vector<StitchFace> faces;
};

// Local indices (into StitchFace::v) of the corners whose difference is the
// face's course direction; see the convention above.
std::pair<uint32_t, uint32_t> courseEdge(const StitchFace& face);

// Checks everything readStitchObj checks on a mesh made elsewhere (face sizes,
// types, indices, finite coordinates, degenerate faces, manifold and
// consistently oriented edges, unused vertices). Throws InputError naming mesh.name.
void validateStitchMesh(const StitchMesh& mesh);

// OBJ: `v`, `f` (a, a/b, a//c, a/b/c; negative = relative), `g` groups as stitch
// types (a face before any group is knit; `g` alone or `g default` resets to
// knit). `vt`, `vn`, `vp`, `o`, `s`, `usemtl`, `mtllib` and comments are ignored;
// any other statement is an error. `types`, when given, overrides the groups
// (one per face; group names are then not checked); `typesSource` names it in errors.
StitchMesh parseStitchObj(std::string_view text, std::string_view sourceName,
                          const std::vector<StitchType>* types = nullptr, std::string_view typesSource = {});
// The sidecar: {"types": ["knit", "purl", ...]}, one entry per face.
std::vector<StitchType> parseStitchTypesJson(std::string_view text, std::string_view sourceName);
// The sidecar path read next to an OBJ: "<obj path>.stitches.json".
std::filesystem::path stitchSidecarPath(const std::filesystem::path& obj);
// Reads the OBJ and, when it exists, its sidecar.
StitchMesh readStitchObj(const std::filesystem::path& path);
// Animation frames: every frame must have the first frame's vertex count, faces
// (same vertex indices) and stitch types.
std::vector<StitchMesh> readStitchObjSequence(const std::vector<std::filesystem::path>& paths);
// Writes full-precision vertices and `g <type>` groups, keeping face order, so
// readStitchObj returns the same mesh.
void writeStitchObj(const StitchMesh& mesh, const std::filesystem::path& path);
std::string formatStitchObj(const StitchMesh& mesh);

// Default stitch size in cm. The paper gives no dimensions; 0.5 wide x 0.45
// tall is a plausible worsted-weight gauge (20 stitches, 22 rows per 10 cm),
// a choice of this project.
inline constexpr double kDefaultStitchWidth = 0.5;
inline constexpr double kDefaultStitchHeight = 0.45;

// Flat rows x cols patch in z = 0, normal +z, courses along +x, wales along +y,
// bottom-left corner at the origin; faces row by row from the bottom, vertex
// (row r, column c) at index r * (cols + 1) + c. All knit.
StitchMesh makeStockinette(int rows, int cols, double stitchWidth = kDefaultStitchWidth,
                           double stitchHeight = kDefaultStitchHeight);
// Same layout; columns alternate knit (even) and purl (odd).
StitchMesh makeRibbing1x1(int rows, int cols, double stitchWidth = kDefaultStitchWidth,
                          double stitchHeight = kDefaultStitchHeight);
// Stockinette with every stitch type, on the same vertex grid: in rows
// r % 4 == 1, at columns c % 5 == 1, an eyelet (a decrease pentagon over
// columns c, c+1 and a yarn-over triangle standing on vertex c+2); in rows
// r % 4 == 3, at columns c % 5 == 2, an increase pentagon (top split at c+1)
// beside a decrease pentagon (bottom split at c+2). Every row keeps `cols`
// loops, so the rows stack.
StitchMesh makeLacePatch(int rows, int cols, double stitchWidth = kDefaultStitchWidth,
                         double stitchHeight = kDefaultStitchHeight);

// Built-in deformations, affine about the bottom-left corner of the mesh's
// bounding box (min x, min y), with the course along +x and the wale along +y as
// the generators make them. Stretch: factor in [1.0, 1.6] along that axis.
// Shear: angle in degrees in [0, 30], x += tan(angle) * (y - ymin) (wales lean
// towards +x). None: identity, amount ignored.
struct Deformation {
  enum Kind { None, StretchCourse, StretchWale, Shear } kind = None;
  double amount = 0.0;
};
std::string_view deformationKindName(Deformation::Kind kind);  // "none", "stretch-course", ...
// "none", "stretch-course=1.4", "stretch-wale=1.2", "shear=30"; validated.
Deformation parseDeformation(std::string_view spec);
// Throws InputError naming the option (e.g. "stretch-course") when out of range.
void validateDeformation(const Deformation& d);
glm::dmat3 deformationMatrix(const Deformation& d);  // the linear part (validated)
StitchMesh deform(const StitchMesh& rest, const Deformation& d);
// frames >= 2 meshes; frame i applies the amount interpolated linearly from
// identity (stretch 1, shear 0 degrees) at i = 0 to `final` at i = frames - 1.
std::vector<StitchMesh> animate(const StitchMesh& rest, const Deformation& final, int frames);

// A face in its own orthonormal 2D frame: e1 along the course edge (projected
// into the plane), e2 = normal x e1, normal the face's best-fit plane normal
// (Newell's vector area; oriented by the surrounding faces, see below).
struct FaceFrame2D {
  glm::dvec3 origin;  // the face's vertex 0
  glm::dvec3 e1, e2, normal;
  std::array<glm::dvec2, 5> p;  // vertex positions in (e1, e2), p[0] = 0
  uint32_t count;
  double area;  // signed area in the frame: negative for a flipped face
};
// The frame of one face. The normal's sign follows the faces sharing a vertex
// with it (their summed vector areas), so a face folded over against its
// neighbours comes out clockwise with negative area; a face without neighbours
// keeps its own orientation. Throws InputError on a degenerate face.
FaceFrame2D faceFrame2D(const StitchMesh& mesh, uint32_t face);
// F with deformed edge ~= F * rest edge in the two faces' own frames (least
// squares over the face's edge vectors: exact for an affine map). Throws
// InputError naming the face when the meshes' topologies differ, a face is
// degenerate, self-intersecting, flipped (det F <= 0) or collapsed (det F < 1e-6).
glm::dmat2 faceDeformationGradient(const StitchMesh& rest, const StitchMesh& deformed, uint32_t face);
// All faces at once (linear time: neighbour normals are summed once).
std::vector<glm::dmat2> faceDeformationGradients(const StitchMesh& rest, const StitchMesh& deformed);
// The same, with both faces' frames (same checks and errors).
struct FaceDeformation {
  FaceFrame2D rest, deformed;
  glm::dmat2 F;
};
std::vector<FaceDeformation> faceDeformations(const StitchMesh& rest, const StitchMesh& deformed);

}  // namespace ft
