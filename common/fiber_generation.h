// fiber_generation.h — one fiber vertex, as every generator emits it.
//
// Canonical order inside a segment (the CPU reference writes it; the GPU
// paths are compared against it after sorting by their id tags):
//   for ply j in [0, n^ply):
//     slot 0 = the ply's core fiber, slots 1..regularCount = regular fibers,
//     outermost first (fiber-table row fiberCount - slot);
//       for vertex v in [0, subdivisions]: t = v / subdivisions.
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
  return (ply * ftSlotsPerPly(d) + slot) * (d.subdivisions + 1u) + vertex;
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

// `fc` is the fiber-table row ftSlotFiber(p, slot) for a regular slot and is
// ignored for the core (slot 0).
FT_FUNC FiberVertex ftFiberVertex(YarnParams p, TwistRates r, YarnSegment seg, SegmentDecision d, uint yarn,
                                  uint segment, uint ply, uint slot, FiberCoord fc, uint vertex) {
  FT_PRECISE float t = float(vertex) / float(d.subdivisions);
  YarnFrame f = ftYarnFrameAt(seg, t);
  float s = ftLengthAt(seg, t);
  FiberVertex out_;
  out_.id.x = yarn;
  out_.id.y = segment;
  if (slot == 0u) {
    out_.position = vec4(ftCorePosition(p, r, f, s, ply), d.coreHalfWidth);
    out_.id.z = ftPackFiberId(ply, FT_CORE_FIBER_ID);
    out_.id.w = ftPackTypeVertex(FT_FIBER_CORE, vertex, 0u);
  } else {
    uint fiber = ftSlotFiber(p, slot);
    FiberSample fs = ftFiberSample(p, r, f, s, yarn, ply, fiber, fc);
    out_.position = vec4(fs.position, p.fiberRadius);
    out_.id.z = ftPackFiberId(ply, fiber);
    out_.id.w = ftPackTypeVertex(fs.type, vertex, fs.period);
  }
  return out_;
}

FT_NAMESPACE_END
#endif  // FT_FIBER_GENERATION_H
