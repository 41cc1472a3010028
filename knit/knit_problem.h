// knit_problem.h — from a rest and a deformed stitch mesh to one Gauss–Newton
// problem per stitch (001_dce8d4d1f783b802.txt §3, §5.2, §6.1), and from solved
// tiles back to yarn curves. Shared by the CPU reference and the GPU twin: both
// solve exactly these problems (the GPU gets them as KnitStitchGpu records).
//
// Stitch template (deliverable 2): a closed-form tile in normalized stitch
// coordinates (u along the course, v along the wale, both 0..1 over the face),
// built from the knot model itself rather than relaxed: two knots at
// (0.5 ∓ κ, v_k) with their contact axis d along the wale, half-length l0,
// contacts offset ±r along the normal (eq. 1–2), a sinker at (0, v_s) and the
// head's apex at (0.5, v_a), both one radius behind the face (the knit side shows
// the legs, the purl side the heads and sinkers). Purl is the knit tile seen
// from the back: every normal offset negated. Every other type uses the same
// tile on a quad cut from its face. docs/knit-deformation.md has the figure
// and the numbers.
#pragma once
#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "common/knit_stitch.h"
#include "knit/knit_solver.h"
#include "knit/stitch_mesh.h"
#include "scene/yarn_model.h"

namespace ft {

struct KnitTemplate {
  double knotOffset = 0.2;     // κ: knots at u = 0.5 ∓ κ
  double knotHeight = 0.3;     // v_k
  double halfLength = 1.6;     // l0, in yarn radii
  double sinkerHeight = -0.1;  // v_s of the sinker at u = 0
  double apexHeight = 0.6;     // v_a of the head's apex at u = 0.5
  double backOffset = 1.0;     // sinker and apex depth behind the face, in yarn radii
};

struct KnitOptions {
  double yarnRadius = 0.05;  // r of eq. 1–2, in mesh units (cm for the built-in patches)
  double beta = 1.0;         // §6.1 knot spacing blend: d = d0 + β (d1 − d0)
  double wAngle = 1.0;       // eq. 3 (paper: 1)
  double wLength = 100.0;    // eq. 3 (paper: 100)
  int iterations = 3;        // Gauss–Newton iterations (paper: 3)
  KnitTemplate tile;
};
// Throws InputError naming the option for values out of range.
void validateKnitOptions(const KnitOptions& o);

// A face frame in world space: point = origin + x e1 + y e2 + z n.
struct KnitFrame {
  glm::dvec3 origin, e1, e2, n;
  glm::dvec3 toWorld(const glm::dvec3& p) const { return origin + p.x * e1 + p.y * e2 + p.z * n; }
};

// One yarn: global control-point indices (tile * 14 + point) in yarn order.
struct KnitYarn {
  std::vector<uint32_t> points;
  bool closed = false;
};

struct KnitSetup {
  std::string name;
  KnitOptions options;
  uint32_t faceCount = 0;   // stitches: the mesh's faces
  uint32_t stitchCount = 0;  // tiles [0, stitchCount) lie on faces (a pentagon has two)
  // Tiles past stitchCount are ghost stitches above tiles with nothing above
  // them: they only carry the heads of the top row (bind-off).
  std::vector<knit64::KnitProblem> problems;
  std::vector<KnitFrame> frames;         // deformed face frames, per tile
  std::vector<uint32_t> tileFace;        // the face of a tile (for a ghost: the face below it)
  std::vector<KnitYarn> yarns;           // row yarns, then cast-on yarns
  uint32_t tileCount() const { return static_cast<uint32_t>(problems.size()); }
};

// Builds every tile's problem and the yarns through them: one tile per knit,
// purl or yarn-over face, two per increase or decrease pentagon (split at the
// middle of its bottom or top edge), plus ghost tiles above the top row
// (docs/knit-deformation.md). Throws InputError naming the mesh and face for a
// stitch type that does not fit its face, for degenerate, flipped or collapsed
// faces (faceDeformations) and for mismatched topologies.
KnitSetup buildKnitSetup(const StitchMesh& rest, const StitchMesh& deformed, const KnitOptions& options);

// Face-frame points (tile * 14 + i) to world space.
std::vector<glm::dvec3> liftKnitPoints(const KnitSetup& setup, const std::vector<glm::dvec3>& framePoints);
// The interpolated initial guess of every tile (Θ0), in the face frame: the
// naive "move the template with the mesh" baseline of Fig. 9.
std::vector<glm::dvec3> initialKnitPoints(const KnitSetup& setup);

// Yarn curves through the world points: with upsample, FT_KNIT_UPSAMPLE
// Catmull–Rom vertices per control-point segment (56 per stitch, §5.2).
YarnModel knitYarnModel(const KnitSetup& setup, const std::vector<glm::dvec3>& worldPoints, bool upsample);

// The GPU up-sampling list: per yarn point, (tile point index, first entry of
// its yarn, yarn length, closed); yarns back to back. Vertex k of the segment
// starting at entry j is vertex FT_KNIT_UPSAMPLE * j + k of the GPU output.
std::vector<glm::uvec4> knitYarnList(const KnitSetup& setup);
// knitYarnModel's curves (upsampled) read out of that GPU vertex layout.
YarnModel knitYarnModelFromVertices(const KnitSetup& setup, const std::vector<glm::vec4>& vertices);

// The GPU records (float) of every tile.
std::vector<KnitStitchGpu> knitGpuRecords(const KnitSetup& setup);
KnitSolveParams knitSolveParams(const KnitSetup& setup);

// Eq. 4 residuals of one solved tile (world points of the tile, 14): the
// largest of |(c0 + c1)/2 − x_k|, |(p0 + p1)/2 − x_k|, | |p0 − p1| − 2r | and
// |(x_k − p0)·(c0 − x_k)| / (r l), over both knots; c0 and c1 are the means of
// their ± control points. In mesh units except the last (dimensionless).
struct KnitConstraintResiduals {
  double midpointContact = 0, midpointControl = 0, controlDistance = 0, perpendicularity = 0;
};
KnitConstraintResiduals knitConstraintResiduals(const KnitSetup& setup, uint32_t tile, const glm::dvec3* tilePoints);

}  // namespace ft
