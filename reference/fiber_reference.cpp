#include "reference/fiber_reference.h"

#include <numeric>

#include <tbb/parallel_for.h>

#include "common/fiber_generation.h"
#include "common/lod.h"
#include "common/yarn_frame.h"

namespace ft {

namespace {

YarnSegment fetchSegment(const YarnBuffers& yarn, const CurveInfo& c, uint32_t local) {
  SegmentIndices idx = ftSegmentIndices(c, local);
  const auto& p = yarn.points;
  return ftMakeSegment(c, local, idx, p[idx.i0].positionLength, p[idx.i1].positionLength,
                       p[idx.i2].positionLength, p[idx.i3].positionLength);
}

}  // namespace

Knot knotCpu(const YarnBuffers& yarn, const CurveInfo& c, uint32_t k) {
  return ftCurveKnot(c, k, fetchSegment(yarn, c, ftKnotSegmentBefore(c, k)),
                     fetchSegment(yarn, c, ftKnotSegmentAfter(c, k)));
}

std::vector<FrameNormal> computeKnotFramesCpu(const YarnBuffers& yarn) {
  std::vector<FrameNormal> frames(yarn.knotCount, FrameNormal{glm::vec4(0.0f)});
  tbb::parallel_for(size_t(0), yarn.curves.size(), [&](size_t ci) {
    // Mirrors gpu/shaders/yarn_frames.comp.glsl statement by statement (the
    // GPU splits the loop into chunks; the values are the same).
    const CurveInfo c = yarn.curves[ci];
    const uint32_t segments = ftCurveSegmentCount(c);
    YarnSegment after = fetchSegment(yarn, c, ftKnotSegmentAfter(c, 0));
    Knot a = ftCurveKnot(c, 0, fetchSegment(yarn, c, ftKnotSegmentBefore(c, 0)), after);
    const Knot k0 = a;
    vec3 r = ftStartNormal(a);
    frames[c.frameBase].normal = vec4(ftStoredFromLeaving(a, r), 0.0f);
    for (uint32_t k = 0; k < segments; ++k) {
      const YarnSegment before = after;
      after = fetchSegment(yarn, c, ftKnotSegmentAfter(c, k + 1));
      const Knot b = ftCurveKnot(c, k + 1, before, after);
      const FrameStep f = ftCarryFrame(a, r, b);
      if (k + 1 < ftCurveKnotCount(c)) frames[c.frameBase + k + 1].normal = vec4(f.stored, 0.0f);
      r = f.leaving;
      a = b;
    }
    if (c.closed != 0u) {
      // r is now the start normal carried once around the loop.
      const float holonomy = ftSignedAngle(r, ftStartNormal(k0), k0.tangent);
      for (uint32_t k = 1; k < segments; ++k) {
        const Knot kk = knotCpu(yarn, c, k);
        frames[c.frameBase + k].normal = vec4(
            ftCloseFrame(vec3(frames[c.frameBase + k].normal), ftKnotAxis(kk), holonomy, kk.s, c.totalLength), 0.0f);
      }
    }
  });
  return frames;
}

YarnSegment loadSegmentCpu(const YarnBuffers& yarn, std::span<const FrameNormal> frames, uint32_t segment) {
  const SegmentRef ref = yarn.segments[segment];
  const CurveInfo& c = yarn.curves[ref.curve];
  YarnSegment seg = fetchSegment(yarn, c, ref.local);
  seg.n0 = frames[ftKnotFrameIndex(c, ref.local)].normal;
  seg.n1 = frames[ftKnotFrameIndex(c, ref.local + 1)].normal;
  return seg;
}

FiberGeometry generateFibersCpu(const FiberInput& input, std::span<const FrameNormal> frames,
                                std::span<const uint32_t> segments) {
  const YarnBuffers& yarn = *input.yarn;
  const std::vector<FiberCoord>& table = *input.fiberTable;
  const YarnParams& p = input.params;
  FiberGeometry out;
  if (segments.empty()) {
    out.segments.resize(yarn.segments.size());
    std::iota(out.segments.begin(), out.segments.end(), 0u);
  } else {
    out.segments.assign(segments.begin(), segments.end());
  }
  const size_t count = out.segments.size();
  out.decisions.resize(count);
  tbb::parallel_for(size_t(0), count, [&](size_t i) {
    out.decisions[i] = ftDecideSegment(p, input.view, loadSegmentCpu(yarn, frames, out.segments[i]));
  });
  std::vector<size_t> offsets(count + 1, 0);
  for (size_t i = 0; i < count; ++i) offsets[i + 1] = offsets[i] + out.decisions[i].vertexCount;
  out.vertices.resize(offsets[count]);

  tbb::parallel_for(size_t(0), count, [&](size_t i) {
    const SegmentDecision d = out.decisions[i];
    if (d.vertexCount == 0) return;
    const uint32_t segment = out.segments[i];
    const SegmentRef ref = yarn.segments[segment];
    const YarnSegment seg = loadSegmentCpu(yarn, frames, segment);
    const TwistRates rates = ftTwistRates(p, yarn.curves[ref.curve]);
    const FiberCoord none{0.0f, 0.0f};
    // Same two stages as the compute path: yarn samples once per segment, then fibers.
    YarnSample samples[2 * FT_MAX_SUBDIVISIONS + 2];  // the fibers' and the cores' (ftSampleCount)
    for (uint32_t k = 0; k < ftSampleCount(d); ++k) samples[k] = ftYarnSample(seg, d, k);
    for (uint32_t ply = 0; ply < p.plyCount; ++ply)
      for (uint32_t slot = 0; slot < ftSlotsPerPly(d); ++slot) {
        const FiberCoord fc = slot == 0 ? none : table[ftSlotFiber(p, slot)];
        PeriodCache cache = ftEmptyPeriodCache();
        for (uint32_t v = 0; v < ftStripVertexCount(d, slot); ++v) {
          const CachedFiberVertex cv = ftFiberVertexAt(p, rates, samples[ftStripSample(d, slot, v)], d, ref.curve,
                                                       segment, ply, slot, fc, v, cache);
          cache = cv.cache;
          out.vertices[offsets[i] + ftVertexOffset(d, ply, slot, v)] = cv.vertex;
        }
      }
  });
  return out;
}

}  // namespace ft
