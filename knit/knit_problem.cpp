#include "knit/knit_problem.h"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <tuple>
#include <utility>

#include "scene/input_error.h"

namespace ft {
namespace {

using knit64::KnitProblem;

constexpr uint32_t kNone = 0xffffffffu;

using Edge = std::pair<uint32_t, uint32_t>;  // directed, counter-clockwise in its face

// A face's edges by role (docs/stitch-meshes.md): bottom edges carry the loops
// coming in from below, top edges the loops going out above; each list runs
// counter-clockwise (bottom left to right, top right to left).
struct FaceEdges {
  std::vector<Edge> bottom, top;
  Edge right, left;
};

FaceEdges faceEdges(const StitchFace& f) {
  const auto& v = f.v;
  if (f.count == 3) return {{}, {{v[1], v[2]}}, {v[0], v[1]}, {v[2], v[0]}};  // yarn-over triangle
  if (f.count == 4) return {{{v[0], v[1]}}, {{v[2], v[3]}}, {v[1], v[2]}, {v[3], v[0]}};
  if (f.type == StitchType::Increase) return {{{v[0], v[1]}}, {{v[2], v[3]}, {v[3], v[4]}}, {v[1], v[2]}, {v[4], v[0]}};
  return {{{v[0], v[1]}, {v[1], v[2]}}, {{v[3], v[4]}}, {v[2], v[3]}, {v[4], v[0]}};  // decrease
}

// Stitch tiles: every tile is a quad with one knit tile (knit_stitch.h) on
// it. Knit, purl and yarn-over quads are one tile; a pentagon is split into
// a left and a right tile (an increase at the middle of its bottom edge, a
// decrease at the middle of its top edge: two loops out, or two loops in); a
// yarn-over triangle gets a quad whose bottom edge is half its top edge,
// centred on its bottom corner. New vertices are affine in the face's own, so
// rest and deformed tiles stay consistent.
struct TileQuad {
  std::array<glm::dvec3, 4> rest, deformed;
  uint32_t face;
};

glm::dvec3 mid(const glm::dvec3& a, const glm::dvec3& b) { return 0.5 * (a + b); }

std::vector<TileQuad> faceTiles(const StitchMesh& rest, const StitchMesh& def, uint32_t f) {
  const StitchFace& face = rest.faces[f];
  auto quads = [&](const StitchMesh& m) -> std::vector<std::array<glm::dvec3, 4>> {
    std::array<glm::dvec3, 5> x;
    for (uint32_t i = 0; i < face.count; ++i) x[i] = m.vertices[face.v[i]];
    if (face.count == 3) return {{x[0] + 0.25 * (x[2] - x[1]), x[0] + 0.25 * (x[1] - x[2]), x[1], x[2]}};
    if (face.count == 4) return {{x[0], x[1], x[2], x[3]}};
    if (face.type == StitchType::Increase) {
      const glm::dvec3 m01 = mid(x[0], x[1]);
      return {{x[0], m01, x[3], x[4]}, {m01, x[1], x[2], x[3]}};
    }
    const glm::dvec3 m34 = mid(x[3], x[4]);
    return {{x[0], x[1], m34, x[4]}, {x[1], x[2], x[3], m34}};
  };
  const auto r = quads(rest), d = quads(def);
  std::vector<TileQuad> out;
  for (size_t i = 0; i < r.size(); ++i) out.push_back({r[i], d[i], f});
  return out;
}

// The top edge of a quad extruded by its mean wale edge: a ghost stitch (a
// parallelogram, never degenerate, even over a slanted pentagon half) so the
// top row's heads have a tile to live in.
std::array<glm::dvec3, 4> ghostAbove(const std::array<glm::dvec3, 4>& q) {
  const glm::dvec3 wale = 0.5 * ((q[3] - q[0]) + (q[2] - q[1]));
  return {q[3], q[2], q[2] + wale, q[3] + wale};
}

// Rest and deformed tile meshes with the same vertex indices: corners are
// shared where their rest positions coincide (the deformed ones may not).
std::pair<StitchMesh, StitchMesh> quadMeshes(const std::string& restName, const std::string& defName,
                                             const std::vector<TileQuad>& quads) {
  std::pair<StitchMesh, StitchMesh> m;
  m.first.name = restName;
  m.second.name = defName;
  std::map<std::tuple<double, double, double>, uint32_t> index;
  for (const TileQuad& q : quads) {
    StitchFace f{{kNoVertex, kNoVertex, kNoVertex, kNoVertex, kNoVertex}, 4, StitchType::Knit, 0};
    for (int i = 0; i < 4; ++i) {
      auto [it, added] =
          index.try_emplace({q.rest[i].x, q.rest[i].y, q.rest[i].z}, static_cast<uint32_t>(m.first.vertices.size()));
      if (added) {
        m.first.vertices.push_back(q.rest[i]);
        m.second.vertices.push_back(q.deformed[i]);
      }
      f.v[i] = it->second;
    }
    m.first.faces.push_back(f);
    m.second.faces.push_back(f);
  }
  return m;
}

// Bilinear map of normalized stitch coordinates over a quad's 2D corners;
// extrapolates outside [0, 1]², which the halo points use.
struct Bilinear {
  glm::dvec2 p[4];
  glm::dvec2 at(double u, double v) const {
    return (1 - u) * (1 - v) * p[0] + u * (1 - v) * p[1] + u * v * p[2] + (1 - u) * v * p[3];
  }
  glm::dvec2 dv(double u) const { return (1 - u) * (p[3] - p[0]) + u * (p[2] - p[1]); }
};

double sideOf(StitchType t) { return t == StitchType::Purl ? -1.0 : 1.0; }

glm::dvec2 centroid(const FaceFrame2D& f) {
  glm::dvec2 c(0.0);
  for (uint32_t i = 0; i < f.count; ++i) c += f.p[i];
  return c / double(f.count);
}

// Where a knot (or anything attached to one) goes in the deformed frame: the
// mesh-interpolated offset from the face centre, its length blended by β (§6.1).
struct TileMap {
  glm::dmat2 F;
  glm::dvec2 c0, c1;
  double beta;
  glm::dvec2 point(glm::dvec2 x) const { return c1 + F * (x - c0); }
  glm::dvec2 knot(glm::dvec2 k) const {
    const glm::dvec2 o0 = k - c0, o1 = F * o0;
    const double l0 = glm::length(o0), l1 = glm::length(o1);
    if (l1 == 0.0) return c1;
    return c1 + o1 * ((l0 + beta * (l1 - l0)) / l1);
  }
};

// Rest template of one tile and its deformed problem. sides: own, left,
// right, up, down neighbour (own side where there is none).
struct TileSides {
  double own, left, right, up, down;
};

void buildTile(const FaceFrame2D& restFrame, const TileMap& map, const TileSides& sides, const KnitOptions& o,
               KnitProblem& restOut, KnitProblem& defOut) {
  const KnitTemplate& t = o.tile;
  const double r = o.yarnRadius, l0 = t.halfLength * r;
  Bilinear B{{restFrame.p[0], restFrame.p[1], restFrame.p[2], restFrame.p[3]}};
  const double uL = 0.5 - t.knotOffset, uR = 0.5 + t.knotOffset, vk = t.knotHeight;
  auto knotAt = [&](double u, double v) { return B.at(u, v); };
  auto dirAt = [&](double u) { return glm::normalize(B.dv(u)); };
  const glm::dvec2 kL = knotAt(uL, vk), kR = knotAt(uR, vk);
  const glm::dvec2 dL = dirAt(uL), dR = dirAt(uR);

  KnitProblem& rp = restOut;
  rp.knot[0] = kL;
  rp.knot[1] = kR;
  rp.theta0 = glm::dvec4(std::atan2(dL.y, dL.x), std::atan2(dR.y, dR.x), l0, l0);
  rp.radius = r;
  rp.side = sides.own;
  const double back = -t.backOffset * r;
  // Fixed slots: S, A, halo 14..19 (knit_stitch.h).
  const glm::dvec2 S = B.at(0.0, t.sinkerHeight), A = B.at(0.5, t.apexHeight);
  struct Halo {
    double u, v, sd, sn, side;  // neighbour knot at (u, v), offset sd·l0·d, normal sn·r·side
  };
  const Halo halo[5] = {
      {uR - 1.0, vk, -1, -1, sides.left},  // 14: left tile's 13 (c1-, R)
      {uL, vk + 1.0, -1, +1, sides.up},    // 15: upper tile's 4 (c1+, L)
      {uL, vk - 1.0, +1, +1, sides.down},  // 16: lower tile's 3 (c0+, L)
      {uR, vk - 1.0, +1, +1, sides.down},  // 17: lower tile's 11 (c0+, R)
      {uR, vk + 1.0, -1, +1, sides.up},    // 18: upper tile's 10 (c1+, R)
  };
  rp.fixedXY[0] = S;
  rp.fixedH[0] = back * sides.own;
  rp.fixedXY[1] = A;
  rp.fixedH[1] = back * sides.own;
  KnitProblem& dp = defOut;
  dp.fixedXY[0] = map.point(S);
  dp.fixedXY[1] = map.point(A);
  for (int h = 0; h < 5; ++h) {
    const glm::dvec2 k = B.at(halo[h].u, halo[h].v), d = glm::normalize(B.dv(halo[h].u));
    rp.fixedXY[2 + h] = k + halo[h].sd * l0 * d;
    rp.fixedH[2 + h] = halo[h].sn * r * halo[h].side;
    dp.fixedXY[2 + h] = map.knot(k) + map.F * (halo[h].sd * l0 * d);
  }
  const glm::dvec2 S1 = B.at(1.0, t.sinkerHeight);  // 19: right tile's sinker
  rp.fixedXY[7] = S1;
  rp.fixedH[7] = back * sides.right;
  dp.fixedXY[7] = map.point(S1);
  {  // 20: right tile's 1 (c1-, L)
    const glm::dvec2 k = B.at(uL + 1.0, vk), d = glm::normalize(B.dv(uL + 1.0));
    rp.fixedXY[8] = k - l0 * d;
    rp.fixedH[8] = -r * sides.right;
    dp.fixedXY[8] = map.knot(k) + map.F * (-l0 * d);
  }

  const knit64::KnitMeasures rest = knit64::knitMeasure(rp, rp.theta0);
  for (int i = 0; i < FT_KNIT_LENGTH_RESIDUALS; ++i) rp.restLength[i] = rest.segment[i];
  for (int i = 0; i < FT_KNIT_ANGLE_RESIDUALS; ++i) rp.restCosine[i] = rest.cosine[i];

  dp.knot[0] = map.knot(kL);
  dp.knot[1] = map.knot(kR);
  const glm::dvec2 fL = map.F * dL, fR = map.F * dR;
  dp.theta0 = glm::dvec4(std::atan2(fL.y, fL.x), std::atan2(fR.y, fR.x), l0 * glm::length(fL),
                         l0 * glm::length(fR));
  for (int i = 0; i < FT_KNIT_FIXED_POINTS; ++i) dp.fixedH[i] = rp.fixedH[i];
  for (int i = 0; i < FT_KNIT_LENGTH_RESIDUALS; ++i) dp.restLength[i] = rp.restLength[i];
  for (int i = 0; i < FT_KNIT_ANGLE_RESIDUALS; ++i) dp.restCosine[i] = rp.restCosine[i];
  dp.radius = r;
  dp.side = sides.own;
}

KnitFrame worldFrame(const FaceFrame2D& f) { return {f.origin, f.e1, f.e2, f.normal}; }

bool finiteIn(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }

}  // namespace

void validateKnitOptions(const KnitOptions& o) {
  auto check = [](bool ok, const char* name, double v, const char* range) {
    if (!ok) throw InputError(fmt::format("{}: {} is out of range ({})", name, v, range));
  };
  check(std::isfinite(o.yarnRadius) && o.yarnRadius > 0, "--yarn-radius", o.yarnRadius, "> 0");
  check(finiteIn(o.beta, 0.0, 1.0), "--beta", o.beta, "0 to 1");
  check(std::isfinite(o.wAngle) && o.wAngle >= 0, "--w-angle", o.wAngle, ">= 0");
  check(std::isfinite(o.wLength) && o.wLength >= 0, "--w-length", o.wLength, ">= 0");
  check(o.wAngle + o.wLength > 0, "--w-angle + --w-length", o.wAngle + o.wLength, "> 0");
  check(o.iterations >= 0 && o.iterations <= FT_KNIT_MAX_ITERATIONS, "--iterations", o.iterations, "0 to 8");
}

KnitSetup buildKnitSetup(const StitchMesh& restIn, const StitchMesh& deformedIn, const KnitOptions& options) {
  validateKnitOptions(options);
  // Frames, gradients and every degenerate-face check on the meshes as given.
  (void)faceDeformations(restIn, deformedIn);
  for (uint32_t f = 0; f < restIn.faces.size(); ++f) {
    const StitchFace& face = restIn.faces[f];
    if (!stitchTypeAcceptsCount(face.type, face.count))
      throw InputError(fmt::format("{}: face {}: a {} stitch cannot have {} vertices", restIn.name, f,
                                   stitchTypeName(face.type), face.count));
  }
  const uint32_t faces = static_cast<uint32_t>(restIn.faces.size());

  // Edges by role, and who is across each.
  std::vector<FaceEdges> edges(faces);
  std::map<Edge, uint32_t> owner;
  for (uint32_t f = 0; f < faces; ++f) {
    edges[f] = faceEdges(restIn.faces[f]);
    for (const Edge& e : edges[f].bottom) owner[e] = f;
    for (const Edge& e : edges[f].top) owner[e] = f;
    owner[edges[f].right] = f;
    owner[edges[f].left] = f;
  }
  auto across = [&](const Edge& e) {
    auto it = owner.find({e.second, e.first});
    return it == owner.end() ? kNone : it->second;
  };
  auto isBottomOf = [&](uint32_t g, const Edge& e) {  // e (reversed) is one of g's bottom edges
    for (const Edge& b : edges[g].bottom)
      if (b.first == e.second && b.second == e.first) return true;
    return false;
  };

  // Tiles of every face, then the ghosts.
  std::vector<TileQuad> tiles;
  std::vector<uint32_t> firstTile(faces), tileCount(faces);
  for (uint32_t f = 0; f < faces; ++f) {
    firstTile[f] = static_cast<uint32_t>(tiles.size());
    for (TileQuad& t : faceTiles(restIn, deformedIn, f)) tiles.push_back(t);
    tileCount[f] = static_cast<uint32_t>(tiles.size()) - firstTile[f];
  }
  // Tiles of face f below its top edge e (left to right), and above a bottom edge.
  auto tilesBelowTop = [&](uint32_t f, const Edge& e) -> std::vector<uint32_t> {
    const StitchFace& face = restIn.faces[f];
    if (face.count == 5 && face.type == StitchType::Increase)
      return {firstTile[f] + (e.first == face.v[3] ? 0u : 1u)};  // (v3,v4) is the left tile's
    if (face.count == 5) return {firstTile[f], firstTile[f] + 1};
    return {firstTile[f]};
  };
  // e is the top edge of the face below, so f's bottom edge reversed.
  auto tilesAboveBottom = [&](uint32_t f, const Edge& e) -> std::vector<uint32_t> {
    const StitchFace& face = restIn.faces[f];
    if (face.count == 5 && face.type == StitchType::Decrease) return {firstTile[f] + (e.second == face.v[0] ? 0u : 1u)};
    if (face.count == 5) return {firstTile[f], firstTile[f] + 1};
    return {firstTile[f]};
  };

  KnitSetup s;
  s.name = deformedIn.name;
  s.options = options;
  s.faceCount = faces;
  s.stitchCount = static_cast<uint32_t>(tiles.size());
  auto range = [](uint32_t tile, uint32_t from, uint32_t to) {
    std::vector<uint32_t> out;
    for (uint32_t i = from; i <= to; ++i) out.push_back(tile * FT_KNIT_TILE_POINTS + i);
    return out;
  };
  // The head path of each tile: the green points (4..10) of the tile(s) above
  // its loop that its head runs through (knit_stitch.h).
  std::vector<std::vector<uint32_t>> head(s.stitchCount);
  std::vector<bool> greensUsed(s.stitchCount, false);
  std::vector<uint32_t> ghostFor;
  for (uint32_t f = 0; f < faces; ++f) {
    for (const Edge& e : edges[f].top) {
      const std::vector<uint32_t> below = tilesBelowTop(f, e);
      const uint32_t g = across(e);
      if (g == kNone || !isBottomOf(g, e)) {
        for (uint32_t t : below) {  // bind-off: a ghost above each tile
          const uint32_t ghost = static_cast<uint32_t>(tiles.size());
          tiles.push_back({ghostAbove(tiles[t].rest), ghostAbove(tiles[t].deformed), f});
          ghostFor.push_back(t);
          head[t] = range(ghost, 4, 10);
        }
        continue;
      }
      const std::vector<uint32_t> above = tilesAboveBottom(g, e);
      for (uint32_t t : above) greensUsed[t] = true;
      if (below.size() == 1) {
        for (uint32_t t : above)
          for (uint32_t p : range(t, 4, 10)) head[below[0]].push_back(p);  // one loop through one or two
      } else if (above.size() == 1) {
        head[below[0]] = range(above[0], 4, 7);  // two loops through one: the left head takes the apex
        head[below[1]] = range(above[0], 8, 10);
      } else {
        head[below[0]] = range(above[0], 4, 10);
        head[below[1]] = range(above[1], 4, 10);
      }
    }
  }

  // Problems for every tile (stitch tiles, then ghosts).
  const auto [restTiles, defTiles] =
      quadMeshes(restIn.name + " (stitch tiles)", deformedIn.name + " (stitch tiles)", tiles);
  const std::vector<FaceDeformation> fd = faceDeformations(restTiles, defTiles);
  s.problems.resize(tiles.size());
  s.frames.resize(tiles.size());
  for (uint32_t t = 0; t < tiles.size(); ++t) {
    const uint32_t f = tiles[t].face;
    s.tileFace.push_back(f);
    const double own = sideOf(restIn.faces[f].type);
    TileSides sides{own, own, own, own, own};
    auto sideAcross = [&](const Edge& e, double& out) {
      const uint32_t g = across(e);
      if (g != kNone) out = sideOf(restIn.faces[g].type);
    };
    if (t < s.stitchCount) {
      sideAcross(edges[f].left, sides.left);
      sideAcross(edges[f].right, sides.right);
      if (!edges[f].top.empty()) sideAcross(edges[f].top[0], sides.up);
      if (!edges[f].bottom.empty()) sideAcross(edges[f].bottom[0], sides.down);
    }
    const FaceDeformation& d = fd[t];
    TileMap map{d.F, centroid(d.rest), centroid(d.deformed), options.beta};
    KnitProblem restProblem;
    buildTile(d.rest, map, sides, options, restProblem, s.problems[t]);
    s.frames[t] = worldFrame(d.deformed);
  }

  // Row yarns: faces linked through their right edges, from a face with no
  // face on its left (or round a tube); per tile S, red L, head, red R.
  std::vector<bool> visited(faces, false);
  auto rightOf = [&](uint32_t f) {
    const uint32_t g = across(edges[f].right);
    return g != kNone && edges[g].left == Edge{edges[f].right.second, edges[f].right.first} ? g : kNone;
  };
  auto leftOf = [&](uint32_t f) {
    const uint32_t g = across(edges[f].left);
    return g != kNone && edges[g].right == Edge{edges[f].left.second, edges[f].left.first} ? g : kNone;
  };
  auto walkRow = [&](uint32_t start) {
    std::vector<uint32_t> row;
    uint32_t f = start;
    while (f != kNone && !visited[f]) {
      visited[f] = true;
      row.push_back(f);
      f = rightOf(f);
    }
    return std::make_pair(row, f == start);
  };
  std::vector<std::pair<std::vector<uint32_t>, bool>> rows;
  for (uint32_t f = 0; f < faces; ++f)
    if (leftOf(f) == kNone && !visited[f]) rows.push_back(walkRow(f));
  for (uint32_t f = 0; f < faces; ++f)
    if (!visited[f]) rows.push_back(walkRow(f));  // rows closed round a tube
  for (const auto& [row, closed] : rows) {
    KnitYarn y;
    y.closed = closed;
    for (uint32_t f : row)
      for (uint32_t t = firstTile[f]; t < firstTile[f] + tileCount[f]; ++t) {
        for (uint32_t p : range(t, 0, 3)) y.points.push_back(p);
        for (uint32_t p : head[t]) y.points.push_back(p);
        for (uint32_t p : range(t, 11, 13)) y.points.push_back(p);
      }
    s.yarns.push_back(std::move(y));
  }
  // Cast-on yarns: the heads in tiles with no loop coming in from below, run
  // by run (a yarn-over's tile has none: nothing passes through its legs).
  for (const auto& [row, closed] : rows) {
    KnitYarn y;
    size_t runTiles = 0, rowTiles = 0;
    auto flush = [&] {
      if (!y.points.empty()) s.yarns.push_back(std::move(y));
      y = KnitYarn{};
    };
    for (uint32_t f : row)
      for (uint32_t t = firstTile[f]; t < firstTile[f] + tileCount[f]; ++t) {
        ++rowTiles;
        if (greensUsed[t] || restIn.faces[f].count == 3) {
          flush();
          continue;
        }
        for (uint32_t p : range(t, 4, 10)) y.points.push_back(p);
        ++runTiles;
      }
    y.closed = closed && runTiles == rowTiles;
    flush();
  }
  return s;
}

std::vector<glm::dvec3> liftKnitPoints(const KnitSetup& s, const std::vector<glm::dvec3>& p) {
  std::vector<glm::dvec3> out(p.size());
  for (size_t i = 0; i < p.size(); ++i) {
    out[i] = s.frames[i / FT_KNIT_TILE_POINTS].toWorld(p[i]);
  }
  return out;
}

std::vector<glm::dvec3> initialKnitPoints(const KnitSetup& s) {
  std::vector<glm::dvec3> out;
  out.reserve(size_t(s.tileCount()) * FT_KNIT_TILE_POINTS);
  for (const KnitProblem& p : s.problems)
    for (int i = 0; i < FT_KNIT_TILE_POINTS; ++i) out.push_back(knit64::knitPoint(p, p.theta0, i));
  return out;
}

YarnModel knitYarnModel(const KnitSetup& s, const std::vector<glm::dvec3>& world, bool upsample) {
  YarnModel m;
  m.name = s.name;
  for (const KnitYarn& y : s.yarns) {
    YarnCurve c;
    c.closed = y.closed;
    const int n = static_cast<int>(y.points.size());
    auto at = [&](int i) -> glm::dvec3 {
      if (y.closed) return world[y.points[(i % n + n) % n]];
      if (i < 0) return 2.0 * world[y.points[0]] - world[y.points[1]];
      if (i >= n) return 2.0 * world[y.points[n - 1]] - world[y.points[n - 2]];
      return world[y.points[i]];
    };
    const int segments = y.closed ? n : n - 1;
    for (int i = 0; i < segments; ++i) {
      if (!upsample) {
        c.points.push_back(glm::vec3(at(i)));
        continue;
      }
      for (int k = 0; k < FT_KNIT_UPSAMPLE; ++k)
        c.points.push_back(
            glm::vec3(knit64::knitCatmullRom(at(i - 1), at(i), at(i + 1), at(i + 2), double(k) / FT_KNIT_UPSAMPLE)));
    }
    if (!y.closed) c.points.push_back(glm::vec3(at(n - 1)));
    m.curves.push_back(std::move(c));
  }
  return m;
}

std::vector<glm::uvec4> knitYarnList(const KnitSetup& s) {
  std::vector<glm::uvec4> out;
  for (const KnitYarn& y : s.yarns) {
    const uint32_t first = static_cast<uint32_t>(out.size()), n = static_cast<uint32_t>(y.points.size());
    for (uint32_t p : y.points) out.emplace_back(p, first, n, y.closed ? 1u : 0u);
  }
  return out;
}

YarnModel knitYarnModelFromVertices(const KnitSetup& s, const std::vector<glm::vec4>& vertices) {
  YarnModel m;
  m.name = s.name;
  size_t first = 0;
  for (const KnitYarn& y : s.yarns) {
    YarnCurve c;
    c.closed = y.closed;
    const size_t n = y.points.size();
    const size_t segments = y.closed ? n : n - 1;
    for (size_t i = 0; i < segments; ++i)
      for (int k = 0; k < FT_KNIT_UPSAMPLE; ++k) c.points.push_back(glm::vec3(vertices[(first + i) * FT_KNIT_UPSAMPLE + k]));
    if (!y.closed) c.points.push_back(glm::vec3(vertices[(first + n - 1) * FT_KNIT_UPSAMPLE]));
    m.curves.push_back(std::move(c));
    first += n;
  }
  return m;
}

std::vector<KnitStitchGpu> knitGpuRecords(const KnitSetup& s) {
  std::vector<KnitStitchGpu> out(s.tileCount());
  for (uint32_t t = 0; t < s.tileCount(); ++t) {
    const KnitProblem& p = s.problems[t];
    const KnitFrame& f = s.frames[t];
    KnitStitchGpu& g = out[t];
    g = KnitStitchGpu{};
    g.origin = glm::vec4(glm::vec3(f.origin), 0.0f);
    g.e1 = glm::vec4(glm::vec3(f.e1), 0.0f);
    g.e2 = glm::vec4(glm::vec3(f.e2), 0.0f);
    g.normal = glm::vec4(glm::vec3(f.n), 0.0f);
    g.knots = glm::vec4(p.knot[0].x, p.knot[0].y, p.knot[1].x, p.knot[1].y);
    g.theta0 = glm::vec4(p.theta0);
    for (int i = 0; i < FT_KNIT_FIXED_POINTS; ++i) {
      g.fixedXY[i / 2][(i % 2) * 2] = float(p.fixedXY[i].x);
      g.fixedXY[i / 2][(i % 2) * 2 + 1] = float(p.fixedXY[i].y);
      g.fixedH[i / 4][i % 4] = float(p.fixedH[i]);
    }
    for (int i = 0; i < FT_KNIT_LENGTH_RESIDUALS; ++i) g.restLength[i / 4][i % 4] = float(p.restLength[i]);
    for (int i = 0; i < FT_KNIT_ANGLE_RESIDUALS; ++i) g.restCosine[i / 4][i % 4] = float(p.restCosine[i]);
    g.misc = glm::vec4(float(p.radius), float(p.side), 0.0f, 0.0f);
  }
  return out;
}

KnitSolveParams knitSolveParams(const KnitSetup& s) {
  return KnitSolveParams{float(s.options.wAngle), float(s.options.wLength), uint32_t(s.options.iterations),
                         s.tileCount()};
}

KnitConstraintResiduals knitConstraintResiduals(const KnitSetup& s, uint32_t tile, const glm::dvec3* x) {
  const KnitProblem& p = s.problems[tile];
  const KnitFrame& f = s.frames[tile];
  const double r = p.radius;
  KnitConstraintResiduals out;
  // Per knot: the tile indices of c0+, c0-, c1+, c1-, p0, p1.
  const int idx[2][6] = {{3, 6, 4, 1, 2, 5}, {11, 8, 10, 13, 9, 12}};
  for (int j = 0; j < 2; ++j) {
    const glm::dvec3 k = f.origin + p.knot[j].x * f.e1 + p.knot[j].y * f.e2;
    const glm::dvec3 c0 = 0.5 * (x[idx[j][0]] + x[idx[j][1]]), c1 = 0.5 * (x[idx[j][2]] + x[idx[j][3]]);
    const glm::dvec3 p0 = x[idx[j][4]], p1 = x[idx[j][5]];
    const double l = glm::length(c0 - k);
    out.midpointContact = std::max(out.midpointContact, glm::length(0.5 * (c0 + c1) - k));
    out.midpointControl = std::max(out.midpointControl, glm::length(0.5 * (p0 + p1) - k));
    out.controlDistance = std::max(out.controlDistance, std::abs(glm::length(p0 - p1) - 2.0 * r));
    out.perpendicularity = std::max(out.perpendicularity, std::abs(glm::dot(k - p0, c0 - k)) / (r * l));
  }
  return out;
}

}  // namespace ft
