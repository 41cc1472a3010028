// exemplar.cpp — the plain-weave exemplar block of 004 §2 / notes A1 and its
// tiling (reference/exemplar.h).
#include "reference/exemplar.h"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <utility>

#include "common/constants.h"
#include "reference/fiber_reference.h"
#include "scene/camera.h"
#include "scene/input_error.h"
#include "scene/yarn_preset.h"
#include "scene/yarn_radius.h"

namespace ft {

Exemplar makePlainWeaveExemplar(const ExemplarSettings& s) {
  if (s.fibersPerPly < 0 || s.fibersPerPly > int(FT_MAX_FIBERS_PER_PLY))
    throw InputError(fmt::format("--fibers-per-ply: {} (0 = the preset's, else 1..{})", s.fibersPerPly,
                                 FT_MAX_FIBERS_PER_PLY));
  if (s.spansPerYarn < 2 || s.spansPerYarn > 256)
    throw InputError(fmt::format("--spans: {} (2..256 Catmull-Rom spans per yarn)", s.spansPerYarn));
  if (s.subdivisions < 1 || s.subdivisions > int(FT_MAX_SUBDIVISIONS))
    throw InputError(fmt::format("--subdivisions: {} (1..{})", s.subdivisions, FT_MAX_SUBDIVISIONS));
  if (!(s.fiberRadius > 0.0f) || !std::isfinite(s.fiberRadius))
    throw InputError(fmt::format("--fiber-radius: {} (a finite number > 0)", s.fiberRadius));
  // Regular fibers only: flyaways are not part of 004's CT exemplars' segment set [F].
  std::vector<std::string> sets = s.sets;
  sets.insert(sets.end(), {"hair_density=0", "loop_density=0"});
  if (s.fibersPerPly > 0) sets.push_back(fmt::format("fiber_num={}", s.fibersPerPly));
  const YarnPreset preset = overrideYarnPreset(findYarnPreset(s.yarn), sets);

  Exemplar e;
  e.reach = float(preset.yarnRadius + std::max(preset.ellipseLong, preset.ellipseShort) * preset.rMax);
  e.period = 4.0f * e.reach;
  e.amplitude = e.reach;
  const float P = e.period, h = e.amplitude;
  YarnModel model;
  model.name = "plain-weave block";
  for (int j = 0; j < 2; ++j) {  // warp along x
    YarnCurve c;
    const float sign = j == 0 ? 1.0f : -1.0f;
    for (int k = 0; k <= s.spansPerYarn; ++k) {
      const float x = P * float(k) / float(s.spansPerYarn);
      c.points.emplace_back(x, (float(j) + 0.5f) * 0.5f * P, sign * h * std::sin(2.0f * float(M_PI) * x / P));
    }
    model.curves.push_back(c);
  }
  for (int i = 0; i < 2; ++i) {  // weft along y
    YarnCurve c;
    const float sign = i == 0 ? -1.0f : 1.0f;
    for (int k = 0; k <= s.spansPerYarn; ++k) {
      const float y = P * float(k) / float(s.spansPerYarn);
      c.points.emplace_back((float(i) + 0.5f) * 0.5f * P, y, sign * h * std::sin(2.0f * float(M_PI) * y / P));
    }
    model.curves.push_back(c);
  }
  const YarnBuffers buffers = buildYarnBuffers(model);
  FiberOptions fo;
  fo.allFibers = true;  // every fiber explicit, no core (docs/ground-truth.md)
  fo.maxSubdivisions = uint32_t(s.subdivisions);
  fo.fiberRadius = s.fiberRadius;
  fo.seed = s.seed;
  const FittedFibers fibers = fitFibers(preset, 0.0, "the preset's own scale", fo);
  // LoD off, no culling, chord error 0: every span at the subdivision cap.
  Camera camera;
  const ViewParams view = makeViewParams(camera, 1.0f, false, false, 0.0f);
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(buffers);
  const FiberInput input{&buffers, &fibers.table, fibers.params, view};
  const FiberGeometry g = generateFibersCpu(input, frames);

  // Consecutive vertices of one strip (same yarn, yarn segment, ply/fiber,
  // consecutive vertex index) are a straight segment.
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> ids;
  for (size_t v = 0; v + 1 < g.vertices.size(); ++v) {
    const FiberVertex& p = g.vertices[v];
    const FiberVertex& q = g.vertices[v + 1];
    if ((p.id.z & 0xFFFFu) == FT_CORE_FIBER_ID) continue;
    if (p.id.x != q.id.x || p.id.y != q.id.y || p.id.z != q.id.z) continue;
    if (((q.id.w >> 8) & 0xFFu) != ((p.id.w >> 8) & 0xFFu) + 1u) continue;
    ExemplarSegment seg;
    seg.a = glm::vec3(p.position);
    seg.b = glm::vec3(q.position);
    if (glm::distance(seg.a, seg.b) <= 0.0f) continue;
    seg.radius = 0.5f * (p.position.w + q.position.w);
    seg.fiber = ids.try_emplace({p.id.x, p.id.z}, uint32_t(ids.size())).first->second;
    e.segments.push_back(seg);
  }
  e.fibers = uint32_t(ids.size());
  e.label = fmt::format("plain-weave {} ({} fibers/ply × {} plies, {} spans × {} subdivisions; P = {:.4g}, h = {:.4g})",
                        s.yarn, preset.fiberNum, preset.plyNum, s.spansPerYarn, s.subdivisions, P, h);
  return e;
}

void checkExemplarSegment(const ExemplarSegment& s, size_t k, bool distinct) {
  const bool finite = std::isfinite(s.a.x) && std::isfinite(s.a.y) && std::isfinite(s.a.z) && std::isfinite(s.b.x) &&
                      std::isfinite(s.b.y) && std::isfinite(s.b.z) && std::isfinite(s.radius);
  if (!finite || !(s.radius > 0.0f) || (distinct && glm::distance(s.a, s.b) <= 0.0f))
    throw InputError(fmt::format("segment {}: ({}, {}, {}) – ({}, {}, {}), radius {}: needs finite {}endpoints and a "
                                 "radius > 0",
                                 k, s.a.x, s.a.y, s.a.z, s.b.x, s.b.y, s.b.z, s.radius, distinct ? "distinct " : ""));
}

std::vector<ExemplarSegment> tileExemplar(const Exemplar& block, int tiles) {
  if (tiles < 1 || tiles > 63) throw InputError(fmt::format("--tiles: {} (1..63)", tiles));
  std::vector<ExemplarSegment> out;
  out.reserve(block.segments.size() * size_t(tiles) * size_t(tiles));
  for (int j = 0; j < tiles; ++j)
    for (int i = 0; i < tiles; ++i) {
      const uint32_t copy = uint32_t(j * tiles + i);
      const glm::vec3 offset(float(i - tiles / 2) * block.period, float(j - tiles / 2) * block.period, 0.0f);
      for (ExemplarSegment s : block.segments) {
        s.a += offset;
        s.b += offset;
        s.fiber += copy * block.fibers;
        out.push_back(s);
      }
    }
  return out;
}

}  // namespace ft
