// fiber_generation.h — one fiber vertex, as every generator emits it.
//
// Canonical order inside a segment (the CPU reference writes it; the GPU
// paths are compared against it after sorting by their id tags):
//   for ply j in [0, n^ply):
//     slot 0 = the ply's core fiber, slots 1..regularCount = regular fibers,
//     outermost first (fiber-table row fiberCount - slot);
//       for vertex v in [0, ftStripVertexCount): t = v / subdivisions for a
//       regular fiber, v / coreLines for the core.
// Segments follow each other in segment-table order.
#ifndef FT_FIBER_GENERATION_H
#define FT_FIBER_GENERATION_H
#include "prelude.h"
#include "constants.h"
#include "fiber_geometry.h"
#include "fiber_vertex.h"
#include "yarn_frame.h"

FT_NAMESPACE_BEGIN

FT_FUNC uint ftSlotsPerPly(SegmentDecision d) { return 1u + d.regularCount; }

// Fiber-table row of a regular slot (slot >= 1): the LoD drops inner fibers first (§5).
FT_FUNC uint ftSlotFiber(YarnParams p, uint slot) { return p.fiberCount - slot; }

// Offset of (ply, slot, vertex) inside its segment's vertex range.
FT_FUNC uint ftVertexOffset(SegmentDecision d, uint ply, uint slot, uint vertex) {
  uint inPly = slot == 0u ? 0u : ftStripVertexCount(d, 0u) + (slot - 1u) * (d.subdivisions + 1u);
  return ply * ftPlyVertexCount(d) + inPly + vertex;
}

// Offset of a strip's first index inside its segment's index range: its
// vertices are preceded by those of the strips before it, each strip
// followed by one restart index.
FT_FUNC uint ftStripIndexOffset(SegmentDecision d, uint ply, uint slot) {
  return ftVertexOffset(d, ply, slot, 0u) + ply * ftSlotsPerPly(d) + slot;
}

// Length coordinate at parameter t: linear between the knots' fixed values,
// so the twist is continuous from one segment to the next (§5).
FT_FUNC float ftLengthAt(YarnSegment seg, float t) {
#ifdef FT_FAULT_LENGTH_IGNORED
  FT_PRECISE float s = t * (seg.s1 - seg.s0);
#else
  FT_PRECISE float s = seg.s0 + t * (seg.s1 - seg.s0);
#endif
  return s;
}

// Per-strip memo of the last period's random draws: consecutive vertices of
// a fiber usually share a period, and the draws (three hashes, four normal
// deviates) are the most expensive part of a vertex. Purely an optimization:
// ftFiberPeriod is a pure function, so the vertices are the same with or
// without it.
struct PeriodCache {
  uint valid;
  uint index;
  FiberPeriod period;
};

FT_FUNC PeriodCache ftEmptyPeriodCache() {
  PeriodCache c;
  c.valid = 0u;
  c.index = 0u;
  c.period.type = FT_FIBER_MIGRATION;
  c.period.loopPeak = 0.0f;
  c.period.hairEnd = 0.0f;
  c.period.hairRoot = 0.0f;
  c.period.hairSpan = 0.0f;
  c.period.hairAngle = 0.0f;
  c.period.hairAtEnd = 0u;
  return c;
}

struct CachedFiberVertex {
  FiberVertex vertex;
  PeriodCache cache;
};

// The yarn at sample `sampleIndex` of the segment (t = ftSampleT).
FT_FUNC YarnSample ftYarnSample(YarnSegment seg, SegmentDecision d, uint sampleIndex) {
  FT_PRECISE float t = ftSampleT(d, sampleIndex);
  YarnFrame f = ftYarnFrameAt(seg, t);
  YarnSample ys;
  ys.centerLength = vec4(f.center, ftLengthAt(seg, t));
  ys.tangent = vec4(f.T, 0.0f);
  ys.normal = vec4(f.N, 0.0f);
  ys.binormal = vec4(f.B, 0.0f);
  return ys;
}

// `fc` is the fiber-table row ftSlotFiber(p, slot) for a regular slot and is
// ignored for the core (slot 0); `ys` is the yarn at ftStripSample(d, slot,
// vertex).
FT_FUNC CachedFiberVertex ftFiberVertexAt(YarnParams p, TwistRates r, YarnSample ys, SegmentDecision d,
                                          uint yarn, uint segment, uint ply, uint slot, FiberCoord fc, uint vertex,
                                          PeriodCache cache) {
  YarnFrame f;
  f.center = vec3(ys.centerLength);
  f.T = vec3(ys.tangent);
  f.N = vec3(ys.normal);
  f.B = vec3(ys.binormal);
  float s = ys.centerLength.w;
  PlyFrame pf = ftPlyFrame(p, r, f, s, ply);
  CachedFiberVertex out_;
  out_.cache = cache;
  out_.vertex.id.x = yarn;
  out_.vertex.id.y = segment;
  if (slot == 0u) {  // the core fiber runs along the ply centre (§3.2)
    FT_PRECISE float t = ftSampleT(d, ftStripSample(d, slot, vertex));
    out_.vertex.position = vec4(f.center + pf.offset, mix(d.coreHalfWidth, d.coreHalfWidthEnd, t));
    out_.vertex.id.z = ftPackFiberId(ply, FT_CORE_FIBER_ID);
    out_.vertex.id.w = ftPackTypeVertex(FT_FIBER_CORE, vertex, 0u);
    return out_;
  }
  uint fiber = ftSlotFiber(p, slot);
  PeriodPhase ph = ftPeriodPhase(p, r, s, ftMigrationPhaseTurns(p, yarn, ply, fiber, fc));
  if (cache.valid == 0u || cache.index != ph.index) {
    out_.cache.valid = 1u;
    out_.cache.index = ph.index;
    out_.cache.period = ftFiberPeriod(p, r, yarn, ply, fiber, ph.index);
  }
  out_.vertex.position = vec4(ftFiberPosition(p, r, f, pf, s, fc, ph, out_.cache.period), p.fiberRadius);
  out_.vertex.id.z = ftPackFiberId(ply, fiber);
  out_.vertex.id.w = ftPackTypeVertex(out_.cache.period.type, vertex, ph.index);
  return out_;
}

FT_FUNC CachedFiberVertex ftFiberVertexCached(YarnParams p, TwistRates r, YarnSegment seg, SegmentDecision d,
                                              uint yarn, uint segment, uint ply, uint slot, FiberCoord fc,
                                              uint vertex, PeriodCache cache) {
  return ftFiberVertexAt(p, r, ftYarnSample(seg, d, ftStripSample(d, slot, vertex)), d, yarn, segment, ply, slot, fc,
                         vertex, cache);
}

// One vertex on its own (the tessellation evaluation shader's case).
FT_FUNC FiberVertex ftFiberVertex(YarnParams p, TwistRates r, YarnSegment seg, SegmentDecision d, uint yarn,
                                  uint segment, uint ply, uint slot, FiberCoord fc, uint vertex) {
  return ftFiberVertexCached(p, r, seg, d, yarn, segment, ply, slot, fc, vertex, ftEmptyPeriodCache()).vertex;
}

FT_NAMESPACE_END
#endif  // FT_FIBER_GENERATION_H
