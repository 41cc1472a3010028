// stitch_mesh.cpp — stitch mesh input, generators, deformations and face
// deformation gradients (conventions: stitch_mesh.h, docs/stitch-meshes.md).
#include "knit/stitch_mesh.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <numeric>
#include <sstream>

#include "scene/input_error.h"

namespace ft {
namespace {

constexpr std::array<std::string_view, 5> kTypeNames = {"knit", "purl", "decrease", "increase", "yarnover"};
constexpr std::string_view kTypeList = "knit, purl, decrease, increase, yarnover";

// Shape tolerances are relative to the face's longest edge: meshes come in any
// unit (cm, m, mm), so an absolute area threshold would be wrong for some of
// them; area / longest edge^2 measures the shape alone. Below 1e-6 the face is a
// sliver whose in-plane frame (e2) and deformation gradient are rounding noise.
constexpr double kMinEdgeRatio = 1e-6;
constexpr double kMinAreaRatio = 1e-6;
// det F below this means the face lost all but a millionth of its rest area:
// no knit survives that, and the knot interpolation would divide by it.
constexpr double kMinAreaScale = 1e-6;
// Generated patches: large enough for the 50K-stitch bench, small enough that
// a typo (rows = 1e9) fails before allocating.
constexpr int kMaxGeneratedStitches = 1 << 24;

[[noreturn]] void fail(const std::string& what) { throw InputError(what); }

std::string faceTag(uint32_t f, uint32_t line) {
  return line ? fmt::format("face {} (line {})", f, line) : fmt::format("face {}", f);
}
std::string faceTag(const StitchMesh& m, uint32_t f) { return faceTag(f, m.faces[f].objLine); }

// Messages count vertices from 0; a mesh read from OBJ also gets the 1-based
// index its file uses.
bool fromObj(const StitchMesh& m) { return !m.faces.empty() && m.faces[0].objLine != 0; }
std::string vtx(const StitchMesh& m, uint32_t v) {
  return fromObj(m) ? fmt::format("vertex {} (OBJ {})", v, v + 1) : fmt::format("vertex {}", v);
}
std::string edge(const StitchMesh& m, uint32_t a, uint32_t b, const char* sep) {
  return fromObj(m) ? fmt::format("edge {}{}{} (OBJ {}{}{})", a, sep, b, a + 1, sep, b + 1)
                    : fmt::format("edge {}{}{}", a, sep, b);
}

std::array<glm::dvec3, 5> facePoints(const StitchMesh& m, const StitchFace& face) {
  std::array<glm::dvec3, 5> x{};
  for (uint32_t i = 0; i < face.count; ++i) x[i] = m.vertices[face.v[i]];
  return x;
}

// Newell's vector area: the best-fit plane normal times the (projected) area.
glm::dvec3 vectorArea(const std::array<glm::dvec3, 5>& x, uint32_t n) {
  glm::dvec3 a(0.0);
  for (uint32_t i = 1; i + 1 < n; ++i) a += glm::cross(x[i] - x[0], x[i + 1] - x[0]);
  return 0.5 * a;
}

double cross2(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// Whether two non-adjacent edges of the polygon cross properly.
bool selfIntersects(const std::array<glm::dvec2, 5>& p, uint32_t n) {
  for (uint32_t i = 0; i < n; ++i) {
    for (uint32_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      const glm::dvec2 a = p[i], b = p[(i + 1) % n], c = p[j], d = p[(j + 1) % n];
      const double o1 = cross2(b - a, c - a), o2 = cross2(b - a, d - a);
      const double o3 = cross2(d - c, a - c), o4 = cross2(d - c, b - c);
      if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    }
  }
  return false;
}

// Empty when the face has a usable shape; else what is wrong with it.
std::string shapeProblem(const StitchMesh& m, const std::array<glm::dvec3, 5>& x, const StitchFace& face) {
  const uint32_t n = face.count;
  double maxEdge = 0;
  for (uint32_t i = 0; i < n; ++i) maxEdge = std::max(maxEdge, glm::length(x[(i + 1) % n] - x[i]));
  for (uint32_t i = 0; i < n; ++i) {
    const double len = glm::length(x[(i + 1) % n] - x[i]);
    if (!(len > kMinEdgeRatio * maxEdge)) {
      return fmt::format("degenerate: {} (corners {}->{}) has length {:.3g}, longest edge {:.3g}",
                         edge(m, face.v[i], face.v[(i + 1) % n], "->"), i, (i + 1) % n, len, maxEdge);
    }
  }
  const double area = glm::length(vectorArea(x, n));
  if (!(area > kMinAreaRatio * maxEdge * maxEdge)) {
    return fmt::format("degenerate: zero area ({:.3g}, longest edge {:.3g}; tolerance 1e-6 x edge^2)", area,
                       maxEdge);
  }
  return {};
}

struct Frame {
  FaceFrame2D f;
  std::string problem;  // non-empty: degenerate or self-intersecting
};

// The face in its plane; `orient` picks the normal's sign (zero: the face's own).
Frame makeFrame(const StitchMesh& m, uint32_t fi, glm::dvec3 orient) {
  const StitchFace& face = m.faces[fi];
  const auto x = facePoints(m, face);
  Frame out{};
  out.problem = shapeProblem(m, x, face);
  if (!out.problem.empty()) return out;
  glm::dvec3 n = glm::normalize(vectorArea(x, face.count));
  if (glm::dot(n, orient) < 0) n = -n;
  const auto [a, b] = courseEdge(face);
  glm::dvec3 c = x[b] - x[a];
  c -= glm::dot(c, n) * n;
  if (!(glm::length(c) > kMinEdgeRatio * glm::length(x[b] - x[a]))) {
    out.problem = "degenerate: its course edge is perpendicular to the face's plane";
    return out;
  }
  FaceFrame2D& f = out.f;
  f.origin = x[0];
  f.normal = n;
  f.e1 = glm::normalize(c);
  f.e2 = glm::cross(n, f.e1);
  f.count = face.count;
  f.p = {};
  for (uint32_t i = 0; i < face.count; ++i)
    f.p[i] = {glm::dot(x[i] - x[0], f.e1), glm::dot(x[i] - x[0], f.e2)};
  f.area = 0;
  for (uint32_t i = 0; i < face.count; ++i) f.area += 0.5 * cross2(f.p[i], f.p[(i + 1) % face.count]);
  if (selfIntersects(f.p, face.count)) out.problem = "self-intersecting: two of its edges cross";
  return out;
}

// Sum over the face's corners of the vector areas of the other faces at that
// corner's vertex; per-vertex sums `vsum` include the face itself once.
glm::dvec3 neighbourOrientation(const StitchMesh& m, uint32_t fi, const std::vector<glm::dvec3>& vsum,
                                const std::vector<uint32_t>& vertexIndex) {
  const StitchFace& face = m.faces[fi];
  const glm::dvec3 own = vectorArea(facePoints(m, face), face.count);
  glm::dvec3 s(0.0);
  for (uint32_t i = 0; i < face.count; ++i) s += vsum[vertexIndex[face.v[i]]] - own;
  return s;
}

std::string readText(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail(name + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(name + ": cannot open for reading: " + std::strerror(errno));
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) fail(name + ": read error");
  return s.str();
}

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

std::optional<double> parseDouble(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  double v;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::optional<int64_t> parseInt(std::string_view s) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  int64_t v;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::string quoteText(std::string_view s) {
  if (s.size() > 40) return fmt::format("'{}...'", s.substr(0, 40));
  return fmt::format("'{}'", s);
}

}  // namespace

std::string_view stitchTypeName(StitchType type) { return kTypeNames.at(static_cast<size_t>(type)); }

std::optional<StitchType> parseStitchType(std::string_view name) {
  for (size_t i = 0; i < kTypeNames.size(); ++i) {
    if (kTypeNames[i] == name) return static_cast<StitchType>(i);
  }
  return std::nullopt;
}

bool stitchTypeAcceptsCount(StitchType type, uint32_t count) {
  switch (type) {
    case StitchType::Knit:
    case StitchType::Purl:
      return count == 4;
    case StitchType::Decrease:
    case StitchType::Increase:
      return count == 5;
    case StitchType::YarnOver:
      return count == 3 || count == 4;
  }
  return false;
}

namespace {
std::string_view acceptedCounts(StitchType type) {
  switch (type) {
    case StitchType::Knit:
    case StitchType::Purl:
      return "4 (a quad)";
    case StitchType::Decrease:
    case StitchType::Increase:
      return "5 (a pentagon)";
    case StitchType::YarnOver:
      return "3 or 4";
  }
  return "?";
}
}  // namespace

std::pair<uint32_t, uint32_t> courseEdge(const StitchFace& face) {
  if (face.count == 3) return {2, 1};                    // yarn-over triangle: top edge, left to right
  if (face.type == StitchType::Decrease) return {0, 2};  // the whole split bottom edge
  return {0, 1};
}

void validateStitchMesh(const StitchMesh& m) {
  const std::string& name = m.name;
  if (m.faces.empty()) fail(name + ": empty stitch mesh: no faces");
  if (m.vertices.size() >= kNoVertex)
    fail(fmt::format("{}: {} vertices; at most 2^32-2", name, m.vertices.size()));
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    const glm::dvec3& p = m.vertices[i];
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k]))
        fail(fmt::format("{}: vertex {}: coordinate {} is {}", name, i, "xyz"[k], p[k]));
    }
  }
  const uint32_t nv = static_cast<uint32_t>(m.vertices.size());
  size_t corners = 0;
  for (uint32_t f = 0; f < m.faces.size(); ++f) {
    const StitchFace& face = m.faces[f];
    const std::string tag = name + ": " + faceTag(m, f);
    if (face.count < 3 || face.count > 5) {
      fail(fmt::format("{}: {} vertices; a stitch face has 3 to 5", tag, face.count));
    }
    for (uint32_t i = 0; i < face.count; ++i) {
      if (face.v[i] >= nv) {
        fail(fmt::format("{}: corner {}: vertex {} out of range (the mesh has {} vertices)", tag, i,
                         face.v[i], nv));
      }
      for (uint32_t j = 0; j < i; ++j) {
        if (face.v[j] == face.v[i]) {
          fail(fmt::format("{}: repeats {} (corners {} and {})", tag, vtx(m, face.v[i]), j, i));
        }
      }
    }
    if (!stitchTypeAcceptsCount(face.type, face.count)) {
      fail(fmt::format("{}: {} vertices, but a {} stitch has {}", tag, face.count, stitchTypeName(face.type),
                       acceptedCounts(face.type)));
    }
    corners += face.count;
  }
  for (uint32_t f = 0; f < m.faces.size(); ++f) {
    const std::string problem = makeFrame(m, f, glm::dvec3(0.0)).problem;
    if (!problem.empty()) fail(name + ": " + faceTag(m, f) + ": " + problem);
  }

  // Edges: every undirected edge once or twice, and twice only in opposite
  // directions (the two faces agree on the front side).
  struct HalfEdge {
    uint32_t lo, hi, face, corner;
    bool forward;  // lo -> hi
  };
  std::vector<HalfEdge> edges;
  std::vector<uint32_t> cornerBase(m.faces.size());
  edges.reserve(corners);
  uint32_t base = 0;
  for (uint32_t f = 0; f < m.faces.size(); ++f) {
    const StitchFace& face = m.faces[f];
    cornerBase[f] = base;
    base += face.count;
    for (uint32_t i = 0; i < face.count; ++i) {
      const uint32_t a = face.v[i], b = face.v[(i + 1) % face.count];
      edges.push_back({std::min(a, b), std::max(a, b), f, i, a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return std::tie(x.lo, x.hi, x.face) < std::tie(y.lo, y.hi, y.face);
  });
  // Corners of the same vertex joined across shared edges: one fan per vertex.
  std::vector<uint32_t> parent(corners);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t c) {
    while (parent[c] != c) c = parent[c] = parent[parent[c]];
    return c;
  };
  auto cornerOf = [&](uint32_t f, uint32_t vertex) {
    const StitchFace& face = m.faces[f];
    uint32_t i = 0;
    while (face.v[i] != vertex) ++i;
    return cornerBase[f] + i;
  };
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const HalfEdge& e = edges[i];
    if (j - i > 2) {
      std::string list;
      for (size_t k = i; k < j; ++k) list += (k > i ? ", " : "") + faceTag(m, edges[k].face);
      fail(fmt::format("{}: non-manifold: {} is used by {} faces: {}", name, edge(m, e.lo, e.hi, "-"), j - i,
                       list));
    }
    if (j - i == 2) {
      const HalfEdge& g = edges[i + 1];
      if (e.face == g.face) {
        fail(fmt::format("{}: {} uses {} twice", name, faceTag(m, e.face), edge(m, e.lo, e.hi, "-")));
      }
      if (e.forward == g.forward) {
        const uint32_t from = e.forward ? e.lo : e.hi, to = e.forward ? e.hi : e.lo;
        fail(
            fmt::format("{}: inconsistent orientation: {} and {} both run along {} in the same direction "
                        "(one of them is flipped; faces are counter-clockwise seen from the front)",
                        name, faceTag(m, e.face), faceTag(m, g.face), edge(m, from, to, "->")));
      }
      for (uint32_t v : {e.lo, e.hi}) {
        const uint32_t a = find(cornerOf(e.face, v)), b = find(cornerOf(g.face, v));
        if (a != b) parent[a] = b;
      }
    }
    i = j;
  }
  std::vector<uint32_t> fanRoot(nv, kNoVertex);
  std::vector<uint32_t> fanFace(nv, kNoVertex);
  for (uint32_t f = 0; f < m.faces.size(); ++f) {
    const StitchFace& face = m.faces[f];
    for (uint32_t i = 0; i < face.count; ++i) {
      const uint32_t v = face.v[i], root = find(cornerBase[f] + i);
      if (fanRoot[v] == kNoVertex) {
        fanRoot[v] = root;
        fanFace[v] = f;
      } else if (fanRoot[v] != root) {
        fail(fmt::format(
            "{}: non-manifold: {} joins faces that share no edge around it ({} and {}: a bow-tie)", name,
            vtx(m, v), faceTag(m, fanFace[v]), faceTag(m, f)));
      }
    }
  }
  for (uint32_t v = 0; v < nv; ++v) {
    if (fanRoot[v] == kNoVertex) fail(fmt::format("{}: {} is used by no face", name, vtx(m, v)));
  }
}

StitchMesh parseStitchObj(std::string_view text, std::string_view sourceName,
                          const std::vector<StitchType>* types, std::string_view typesSource) {
  const std::string name(sourceName);
  StitchMesh mesh;
  mesh.name = name;
  std::vector<uint32_t> vertexLine;
  // Positive indices may refer to vertices defined later: resolved at the end.
  struct RawFace {
    std::array<int64_t, 5> idx;
    uint32_t count;
    StitchType type;
    uint32_t line;
  };
  std::vector<RawFace> raw;
  StitchType current = StitchType::Knit;
  uint32_t lineNo = 0;
  size_t pos = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++lineNo;
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const auto tok = tokens(line);
    if (tok.empty()) continue;
    const std::string_view key = tok[0];
    const std::string at = fmt::format("{}: line {}", name, lineNo);
    if (key == "v") {
      if (tok.size() < 4)
        fail(fmt::format("{}: vertex {}: {} coordinates; needs x y z", at, mesh.vertices.size(),
                         tok.size() - 1));
      glm::dvec3 p;
      for (size_t k = 1; k < tok.size(); ++k) {
        const auto value = parseDouble(tok[k]);
        if (!value)
          fail(fmt::format("{}: vertex {}: {} is not a number", at, mesh.vertices.size(), quoteText(tok[k])));
        if (k <= 3) {
          if (!std::isfinite(*value)) {
            fail(fmt::format("{}: vertex {}: coordinate {} is {} (non-finite)", at, mesh.vertices.size(),
                             "xyz"[k - 1], tok[k]));
          }
          p[static_cast<int>(k - 1)] = *value;
        }
      }
      if (mesh.vertices.size() + 1 >= kNoVertex) fail(at + ": more than 2^32-2 vertices");
      mesh.vertices.push_back(p);
      vertexLine.push_back(lineNo);
    } else if (key == "f") {
      const uint32_t fi = static_cast<uint32_t>(raw.size());
      const std::string tag = fmt::format("{}: {}", name, faceTag(fi, lineNo));
      const size_t n = tok.size() - 1;
      if (n < 3 || n > 5) fail(fmt::format("{}: {} vertices; a stitch face has 3 to 5", tag, n));
      RawFace rf{};
      rf.count = static_cast<uint32_t>(n);
      rf.type = current;
      rf.line = lineNo;
      for (size_t k = 0; k < n; ++k) {
        const std::string_view t = tok[k + 1];
        const auto idx = parseInt(t.substr(0, t.find('/')));
        if (!idx) fail(fmt::format("{}: corner {}: {} is not a vertex index", tag, k, quoteText(t)));
        if (*idx == 0) fail(fmt::format("{}: corner {}: OBJ index 0 (OBJ indices start at 1)", tag, k));
        if (*idx < 0) {
          const int64_t resolved = static_cast<int64_t>(mesh.vertices.size()) + *idx;
          if (resolved < 0) {
            fail(
                fmt::format("{}: corner {}: relative OBJ index {} reaches before the first vertex "
                            "({} defined so far)",
                            tag, k, *idx, mesh.vertices.size()));
          }
          rf.idx[k] = resolved;
        } else {
          rf.idx[k] = *idx - 1;
        }
      }
      raw.push_back(rf);
    } else if (key == "g") {
      if (types) continue;  // the sidecar decides; group names are free-form then
      if (tok.size() > 2) {
        fail(fmt::format("{}: group line names {} groups; a stitch face takes one type ({})", at,
                         tok.size() - 1, kTypeList));
      }
      if (tok.size() == 1 || tok[1] == "default") {
        current = StitchType::Knit;
      } else if (const auto t = parseStitchType(tok[1])) {
        current = *t;
      } else {
        fail(fmt::format("{}: unknown group {}: stitch types are {} (or give a {{\"types\": [...]}} sidecar)",
                         at, quoteText(tok[1]), kTypeList));
      }
    } else if (key == "vt" || key == "vn" || key == "vp" || key == "o" || key == "s" || key == "usemtl" ||
               key == "mtllib") {
      continue;
    } else {
      fail(fmt::format("{}: unsupported statement {} (a stitch mesh holds v, f and g)", at, quoteText(key)));
    }
  }
  if (raw.empty()) {
    fail(fmt::format("{}: empty stitch mesh: no faces ({} vertices)", name, mesh.vertices.size()));
  }
  const int64_t nv = static_cast<int64_t>(mesh.vertices.size());
  mesh.faces.reserve(raw.size());
  for (uint32_t f = 0; f < raw.size(); ++f) {
    const RawFace& rf = raw[f];
    StitchFace face{};
    face.v.fill(kNoVertex);
    face.count = rf.count;
    face.type = rf.type;
    face.objLine = rf.line;
    for (uint32_t k = 0; k < rf.count; ++k) {
      if (rf.idx[k] >= nv) {
        fail(fmt::format("{}: {}: corner {}: OBJ index {} out of range (the file has {} vertices)", name,
                         faceTag(f, rf.line), k, rf.idx[k] + 1, nv));
      }
      face.v[k] = static_cast<uint32_t>(rf.idx[k]);
    }
    mesh.faces.push_back(face);
  }
  if (types) {
    if (types->size() != mesh.faces.size()) {
      fail(fmt::format("{}: {} types for the {} faces of {}", typesSource, types->size(), mesh.faces.size(),
                       name));
    }
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
      const StitchType t = (*types)[f];
      if (!stitchTypeAcceptsCount(t, mesh.faces[f].count)) {
        fail(fmt::format("{}: {}: {} vertices, but {} types[{}] is {}, which has {}", name,
                         faceTag(mesh, static_cast<uint32_t>(f)), mesh.faces[f].count, typesSource, f,
                         stitchTypeName(t), acceptedCounts(t)));
      }
      mesh.faces[f].type = t;
    }
  } else {
    for (uint32_t f = 0; f < mesh.faces.size(); ++f) {
      const StitchFace& face = mesh.faces[f];
      if (!stitchTypeAcceptsCount(face.type, face.count)) {
        const bool ungroupedPentagon = face.count == 5 && face.type == StitchType::Knit;
        fail(fmt::format("{}: {}: {} vertices, but a {} stitch has {}{}", name, faceTag(mesh, f), face.count,
                         stitchTypeName(face.type), acceptedCounts(face.type),
                         ungroupedPentagon ? " (put pentagons in group increase or decrease)" : ""));
      }
    }
  }
  validateStitchMesh(mesh);
  return mesh;
}

std::vector<StitchType> parseStitchTypesJson(std::string_view text, std::string_view sourceName) {
  const std::string name(sourceName);
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::parse_error& e) {
    fail(fmt::format("{}: byte {}: not valid JSON ({})", name, e.byte, e.what()));
  }
  if (!doc.is_object() || !doc.contains("types")) fail(name + ": expected an object {\"types\": [...]}");
  const auto& list = doc["types"];
  if (!list.is_array()) fail(name + ": \"types\" is not an array");
  std::vector<StitchType> out;
  out.reserve(list.size());
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_string()) fail(fmt::format("{}: types[{}] is not a string", name, i));
    const auto& s = list[i].get_ref<const std::string&>();
    const auto t = parseStitchType(s);
    if (!t)
      fail(fmt::format("{}: types[{}]: unknown stitch type {} (types are {})", name, i, quoteText(s),
                       kTypeList));
    out.push_back(*t);
  }
  return out;
}

std::filesystem::path stitchSidecarPath(const std::filesystem::path& obj) {
  std::filesystem::path p = obj;
  p += ".stitches.json";
  return p;
}

StitchMesh readStitchObj(const std::filesystem::path& path) {
  const std::string text = readText(path);
  const std::filesystem::path sidecar = stitchSidecarPath(path);
  std::error_code ec;
  if (std::filesystem::exists(sidecar, ec)) {
    const std::vector<StitchType> types = parseStitchTypesJson(readText(sidecar), sidecar.string());
    return parseStitchObj(text, path.string(), &types, sidecar.string());
  }
  return parseStitchObj(text, path.string());
}

std::vector<StitchMesh> readStitchObjSequence(const std::vector<std::filesystem::path>& paths) {
  if (paths.empty()) fail("stitch mesh sequence: no frames");
  std::vector<StitchMesh> frames;
  frames.reserve(paths.size());
  for (size_t i = 0; i < paths.size(); ++i) {
    StitchMesh m = readStitchObj(paths[i]);
    if (i > 0) {
      const StitchMesh& first = frames[0];
      const std::string tag = fmt::format("{} (frame {})", m.name, i);
      if (m.vertices.size() != first.vertices.size()) {
        fail(fmt::format("{}: {} vertices, but frame 0 ({}) has {}: frames must share the topology", tag,
                         m.vertices.size(), first.name, first.vertices.size()));
      }
      if (m.faces.size() != first.faces.size()) {
        fail(fmt::format("{}: {} faces, but frame 0 ({}) has {}: frames must share the topology", tag,
                         m.faces.size(), first.name, first.faces.size()));
      }
      for (uint32_t f = 0; f < m.faces.size(); ++f) {
        const StitchFace &a = m.faces[f], &b = first.faces[f];
        const bool same = a.count == b.count && std::equal(a.v.begin(), a.v.begin() + a.count, b.v.begin());
        if (!same) {
          fail(fmt::format("{}: {}: vertices differ from frame 0 ({}, {}): frames must share the topology",
                           tag, faceTag(m, f), first.name, faceTag(first, f)));
        }
        if (a.type != b.type) {
          fail(fmt::format("{}: {}: type {}, but frame 0 ({}) has {}", tag, faceTag(m, f),
                           stitchTypeName(a.type), first.name, stitchTypeName(b.type)));
        }
      }
    }
    frames.push_back(std::move(m));
  }
  return frames;
}

std::string formatStitchObj(const StitchMesh& m) {
  std::string out = fmt::format("# fibertwin stitch mesh: {} ({} vertices, {} faces)\n", m.name,
                                m.vertices.size(), m.faces.size());
  // fmt's default double format is the shortest text that reads back exactly.
  for (const glm::dvec3& p : m.vertices) out += fmt::format("v {} {} {}\n", p.x, p.y, p.z);
  std::optional<StitchType> group;
  for (const StitchFace& face : m.faces) {
    if (group != face.type) {
      out += fmt::format("g {}\n", stitchTypeName(face.type));
      group = face.type;
    }
    out += "f";
    for (uint32_t i = 0; i < face.count; ++i) out += fmt::format(" {}", face.v[i] + 1);
    out += "\n";
  }
  return out;
}

void writeStitchObj(const StitchMesh& mesh, const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::string text = formatStitchObj(mesh);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw InputError(name + ": cannot open for writing: " + std::strerror(errno));
  f.write(text.data(), static_cast<std::streamsize>(text.size()));
  f.close();
  if (!f) throw InputError(name + ": write error");
}

namespace {
enum class PatchKind { Stockinette, Ribbing, Lace };

StitchMesh makePatch(std::string_view kind, int rows, int cols, double w, double h, PatchKind pattern) {
  const bool ribbing = pattern == PatchKind::Ribbing;
  const std::string name = fmt::format("built-in {} {}x{}", kind, rows, cols);
  if (rows < 1 || cols < 1) fail(fmt::format("{}: rows and columns must be at least 1", name));
  if (int64_t{rows} * cols > kMaxGeneratedStitches) {
    fail(fmt::format("{}: {} stitches; at most {}", name, int64_t{rows} * cols, kMaxGeneratedStitches));
  }
  if (!(w > 0) || !std::isfinite(w))
    fail(fmt::format("{}: stitch width {} must be positive and finite", name, w));
  if (!(h > 0) || !std::isfinite(h))
    fail(fmt::format("{}: stitch height {} must be positive and finite", name, h));
  StitchMesh m;
  m.name = name;
  const uint32_t stride = static_cast<uint32_t>(cols) + 1;
  m.vertices.reserve(size_t(rows + 1) * stride);
  for (int r = 0; r <= rows; ++r) {
    for (int c = 0; c <= cols; ++c) m.vertices.emplace_back(c * w, r * h, 0.0);
  }
  m.faces.reserve(size_t(rows) * cols);
  for (uint32_t r = 0; r < uint32_t(rows); ++r) {
    const uint32_t B = r * stride, T = B + stride;  // first vertex of the row's bottom and top lines
    for (uint32_t c = 0; c < uint32_t(cols); ++c) {
      if (pattern == PatchKind::Lace && r % 4 == 1 && c % 5 == 1 && c + 2 < uint32_t(cols)) {
        // Eyelet: a decrease (two loops in, one out) and a yarn-over beside it.
        m.faces.push_back({{B + c, B + c + 1, B + c + 2, T + c + 1, T + c}, 5, StitchType::Decrease, 0});
        m.faces.push_back({{B + c + 2, T + c + 2, T + c + 1, kNoVertex, kNoVertex}, 3, StitchType::YarnOver, 0});
        c += 1;
        continue;
      }
      if (pattern == PatchKind::Lace && r % 4 == 3 && c % 5 == 2 && c + 3 < uint32_t(cols)) {
        // An increase (one loop in, two out) and a decrease to its right.
        m.faces.push_back({{B + c, B + c + 1, T + c + 2, T + c + 1, T + c}, 5, StitchType::Increase, 0});
        m.faces.push_back({{B + c + 1, B + c + 2, B + c + 3, T + c + 3, T + c + 2}, 5, StitchType::Decrease, 0});
        c += 2;
        continue;
      }
      const uint32_t v0 = r * stride + c;
      const StitchType type = ribbing && (c % 2 == 1) ? StitchType::Purl : StitchType::Knit;
      m.faces.push_back({{v0, v0 + 1, v0 + 1 + stride, v0 + stride, kNoVertex}, 4, type, 0});
    }
  }
  return m;
}
}  // namespace

StitchMesh makeStockinette(int rows, int cols, double w, double h) {
  return makePatch("stockinette", rows, cols, w, h, PatchKind::Stockinette);
}
StitchMesh makeRibbing1x1(int rows, int cols, double w, double h) {
  return makePatch("ribbing1x1", rows, cols, w, h, PatchKind::Ribbing);
}
StitchMesh makeLacePatch(int rows, int cols, double w, double h) {
  return makePatch("lace", rows, cols, w, h, PatchKind::Lace);
}

std::string_view deformationKindName(Deformation::Kind kind) {
  switch (kind) {
    case Deformation::None:
      return "none";
    case Deformation::StretchCourse:
      return "stretch-course";
    case Deformation::StretchWale:
      return "stretch-wale";
    case Deformation::Shear:
      return "shear";
  }
  return "?";
}

void validateDeformation(const Deformation& d) {
  const std::string_view opt = deformationKindName(d.kind);
  switch (d.kind) {
    case Deformation::None:
      return;
    case Deformation::StretchCourse:
    case Deformation::StretchWale:
      if (!(d.amount >= 1.0 && d.amount <= 1.6)) {
        fail(fmt::format("deformation {}: factor {} is outside [1.0, 1.6]", opt, d.amount));
      }
      return;
    case Deformation::Shear:
      if (!(d.amount >= 0.0 && d.amount <= 30.0)) {
        fail(fmt::format("deformation {}: angle {} degrees is outside [0, 30]", opt, d.amount));
      }
      return;
  }
  fail(fmt::format("deformation: unknown kind {}", static_cast<int>(d.kind)));
}

Deformation parseDeformation(std::string_view spec) {
  if (spec == "none") return {};
  const size_t eq = spec.find('=');
  const std::string_view kind = spec.substr(0, eq);
  Deformation d;
  if (kind == "stretch-course") {
    d.kind = Deformation::StretchCourse;
  } else if (kind == "stretch-wale") {
    d.kind = Deformation::StretchWale;
  } else if (kind == "shear") {
    d.kind = Deformation::Shear;
  } else {
    fail(fmt::format("deformation {}: unknown kind (none, stretch-course=F, stretch-wale=F, shear=DEG)",
                     quoteText(spec)));
  }
  const auto amount = eq == std::string_view::npos ? std::nullopt : parseDouble(spec.substr(eq + 1));
  if (!amount) fail(fmt::format("deformation {}: expected {}=<number>", kind, kind));
  d.amount = *amount;
  validateDeformation(d);
  return d;
}

glm::dmat3 deformationMatrix(const Deformation& d) {
  validateDeformation(d);
  glm::dmat3 m(1.0);  // column-major: m[col][row]
  switch (d.kind) {
    case Deformation::None:
      break;
    case Deformation::StretchCourse:
      m[0][0] = d.amount;
      break;
    case Deformation::StretchWale:
      m[1][1] = d.amount;
      break;
    case Deformation::Shear:
      m[1][0] = std::tan(d.amount * std::numbers::pi / 180.0);
      break;
  }
  return m;
}

StitchMesh deform(const StitchMesh& rest, const Deformation& d) {
  const glm::dmat3 m = deformationMatrix(d);
  StitchMesh out = rest;
  if (d.kind != Deformation::None)
    out.name = fmt::format("{} ({}={})", rest.name, deformationKindName(d.kind), d.amount);
  if (rest.vertices.empty()) return out;
  glm::dvec3 corner(std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : rest.vertices) corner = glm::min(corner, p);
  corner.z = 0;
  for (glm::dvec3& p : out.vertices) p = corner + m * (p - corner);
  return out;
}

std::vector<StitchMesh> animate(const StitchMesh& rest, const Deformation& final, int frames) {
  validateDeformation(final);
  if (frames < 2) fail(fmt::format("animation frames: {}; needs at least 2 (rest and final)", frames));
  const double identity = final.kind == Deformation::Shear ? 0.0 : 1.0;
  std::vector<StitchMesh> out;
  out.reserve(frames);
  for (int i = 0; i < frames; ++i) {
    const double t = double(i) / double(frames - 1);
    Deformation d = final;
    d.amount = i == frames - 1 ? final.amount : identity + t * (final.amount - identity);
    StitchMesh m = deform(rest, d);
    m.name = fmt::format("{} frame {}/{}", m.name, i, frames);
    out.push_back(std::move(m));
  }
  return out;
}

namespace {

// Index range and finite positions of one face: nothing below reads past them.
void checkIndices(const StitchMesh& m, uint32_t f) {
  if (f >= m.faces.size())
    fail(fmt::format("{}: face {} out of range ({} faces)", m.name, f, m.faces.size()));
  const StitchFace& face = m.faces[f];
  if (face.count < 3 || face.count > 5)
    fail(fmt::format("{}: {}: {} vertices", m.name, faceTag(m, f), face.count));
  for (uint32_t i = 0; i < face.count; ++i) {
    if (face.v[i] >= m.vertices.size()) {
      fail(fmt::format("{}: {}: vertex {} out of range", m.name, faceTag(m, f), face.v[i]));
    }
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(m.vertices[face.v[i]][k])) {
        fail(fmt::format("{}: {}: vertex {} is not finite", m.name, faceTag(m, f), face.v[i]));
      }
    }
  }
}

// Per-vertex sums of the vector areas of the faces at each vertex, for the
// vertices of `only` (all when null); vertexIndex maps a vertex to its sum.
void vertexAreaSums(const StitchMesh& m, std::vector<glm::dvec3>& vsum, std::vector<uint32_t>& vertexIndex,
                    const StitchFace* only) {
  vertexIndex.assign(m.vertices.size(), kNoVertex);
  vsum.clear();
  if (only) {
    for (uint32_t i = 0; i < only->count; ++i) {
      if (vertexIndex[only->v[i]] == kNoVertex) {
        vertexIndex[only->v[i]] = static_cast<uint32_t>(vsum.size());
        vsum.emplace_back(0.0);
      }
    }
  } else {
    std::iota(vertexIndex.begin(), vertexIndex.end(), 0u);
    vsum.assign(m.vertices.size(), glm::dvec3(0.0));
  }
  for (uint32_t f = 0; f < m.faces.size(); ++f) {
    checkIndices(m, f);  // every face feeds some vertex's sum
    const StitchFace& face = m.faces[f];
    const glm::dvec3 a = vectorArea(facePoints(m, face), face.count);
    for (uint32_t i = 0; i < face.count; ++i) {
      if (vertexIndex[face.v[i]] != kNoVertex) vsum[vertexIndex[face.v[i]]] += a;
    }
  }
}

FaceFrame2D orientedFrame(const StitchMesh& m, uint32_t f, glm::dvec3 orient) {
  Frame fr = makeFrame(m, f, orient);
  if (!fr.problem.empty()) fail(m.name + ": " + faceTag(m, f) + ": " + fr.problem);
  return fr.f;
}

glm::dmat2 gradient(const StitchMesh& rest, const StitchMesh& deformed, uint32_t f, const FaceFrame2D& r,
                    const FaceFrame2D& d) {
  if (!(r.area > 0)) {
    fail(fmt::format(
        "{}: {}: flipped in the rest mesh (signed area {:.3g}): folded over against its neighbours",
        rest.name, faceTag(rest, f), r.area));
  }
  glm::dmat2 rr(0.0), dr(0.0);
  for (uint32_t i = 0; i < r.count; ++i) {
    const uint32_t j = (i + 1) % r.count;
    const glm::dvec2 re = r.p[j] - r.p[i], de = d.p[j] - d.p[i];
    rr += glm::outerProduct(re, re);
    dr += glm::outerProduct(de, re);
  }
  const glm::dmat2 F = dr * glm::inverse(rr);
  const double det = glm::determinant(F);
  if (!(det > 0) || !(d.area > 0)) {
    fail(fmt::format(
        "{}: {}: flipped (det F = {:.3g}, signed area {:.3g}): folded over against its neighbours",
        deformed.name, faceTag(deformed, f), det, d.area));
  }
  if (!(det >= kMinAreaScale)) {
    fail(fmt::format("{}: {}: collapsed to {:.3g} of its rest area", deformed.name, faceTag(deformed, f),
                     det));
  }
  return F;
}

void checkSameFace(const StitchMesh& rest, const StitchMesh& deformed, uint32_t f) {
  const StitchFace &a = rest.faces[f], &b = deformed.faces[f];
  if (a.count != b.count || !std::equal(a.v.begin(), a.v.begin() + a.count, b.v.begin())) {
    fail(fmt::format("{}: {}: vertices differ from the rest mesh {}", deformed.name, faceTag(deformed, f),
                     rest.name));
  }
}

void checkSameSizes(const StitchMesh& rest, const StitchMesh& deformed) {
  if (rest.vertices.size() != deformed.vertices.size() || rest.faces.size() != deformed.faces.size()) {
    fail(fmt::format("{}: {} vertices and {} faces, but the rest mesh {} has {} and {}", deformed.name,
                     deformed.vertices.size(), deformed.faces.size(), rest.name, rest.vertices.size(),
                     rest.faces.size()));
  }
}

}  // namespace

FaceFrame2D faceFrame2D(const StitchMesh& mesh, uint32_t face) {
  checkIndices(mesh, face);
  std::vector<glm::dvec3> vsum;
  std::vector<uint32_t> index;
  vertexAreaSums(mesh, vsum, index, &mesh.faces[face]);
  return orientedFrame(mesh, face, neighbourOrientation(mesh, face, vsum, index));
}

glm::dmat2 faceDeformationGradient(const StitchMesh& rest, const StitchMesh& deformed, uint32_t face) {
  checkSameSizes(rest, deformed);
  checkIndices(rest, face);
  checkIndices(deformed, face);
  checkSameFace(rest, deformed, face);
  const FaceFrame2D r = faceFrame2D(rest, face);
  const FaceFrame2D d = faceFrame2D(deformed, face);
  return gradient(rest, deformed, face, r, d);
}

std::vector<FaceDeformation> faceDeformations(const StitchMesh& rest, const StitchMesh& deformed) {
  checkSameSizes(rest, deformed);
  for (uint32_t f = 0; f < rest.faces.size(); ++f) {
    checkIndices(rest, f);
    checkIndices(deformed, f);
    checkSameFace(rest, deformed, f);
  }
  std::vector<glm::dvec3> rsum, dsum;
  std::vector<uint32_t> rindex, dindex;
  vertexAreaSums(rest, rsum, rindex, nullptr);
  vertexAreaSums(deformed, dsum, dindex, nullptr);
  std::vector<FaceDeformation> out(rest.faces.size());
  for (uint32_t f = 0; f < rest.faces.size(); ++f) {
    FaceDeformation& o = out[f];
    o.rest = orientedFrame(rest, f, neighbourOrientation(rest, f, rsum, rindex));
    o.deformed = orientedFrame(deformed, f, neighbourOrientation(deformed, f, dsum, dindex));
    o.F = gradient(rest, deformed, f, o.rest, o.deformed);
  }
  return out;
}

std::vector<glm::dmat2> faceDeformationGradients(const StitchMesh& rest, const StitchMesh& deformed) {
  std::vector<glm::dmat2> out;
  for (const FaceDeformation& d : faceDeformations(rest, deformed)) out.push_back(d.F);
  return out;
}

}  // namespace ft
