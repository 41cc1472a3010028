// fiber_resources.glsl — GLSL-only include: the buffers every fiber shader
// reads, and loadSegment(), the GPU twin of loadSegmentCpu() in
// reference/fiber_reference.cpp. Not a stage of its own.
#include "common/constants.h"
#include "common/fiber_generation.h"
#include "common/lod.h"
#include "common/yarn_frame.h"

layout(std140, binding = FT_UBO_YARN_PARAMS) uniform YarnBlock { YarnParams yarn; };
layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(std430, binding = FT_SSBO_CONTROL_POINTS) readonly buffer ControlPointBuffer { ControlPoint controlPoints[]; };
layout(std430, binding = FT_SSBO_CURVES) readonly buffer CurveBuffer { CurveInfo curves[]; };
layout(std430, binding = FT_SSBO_SEGMENTS) readonly buffer SegmentBuffer { SegmentRef segmentRefs[]; };
layout(std430, binding = FT_SSBO_FIBER_TABLE) readonly buffer FiberTableBuffer { FiberCoord fiberTable[]; };
layout(std430, binding = FT_SSBO_SEGMENT_LIST) readonly buffer SegmentListBuffer { uint segmentList[]; };
#ifndef FT_FRAMES_WRITABLE
layout(std430, binding = FT_SSBO_FRAMES) readonly buffer FrameBuffer { FrameNormal frames[]; };
#endif

YarnSegment fetchSegment(CurveInfo c, uint local) {
  SegmentIndices idx = ftSegmentIndices(c, local);
  return ftMakeSegment(c, local, idx, controlPoints[idx.i0].positionLength, controlPoints[idx.i1].positionLength,
                       controlPoints[idx.i2].positionLength, controlPoints[idx.i3].positionLength);
}

#ifndef FT_FRAMES_WRITABLE
YarnSegment loadSegment(uint segment) {
  SegmentRef ref = segmentRefs[segment];
  CurveInfo c = curves[ref.curve];
  YarnSegment seg = fetchSegment(c, ref.local);
  seg.n0 = frames[ftKnotFrameIndex(c, ref.local)].normal;
  seg.n1 = frames[ftKnotFrameIndex(c, ref.local + 1u)].normal;
  return seg;
}

// The fiber-table row a regular slot reads (slot 0, the core, reads none).
FiberCoord slotFiberCoord(uint slot) {
  if (slot == 0u) return FiberCoord(0.0f, 0.0f);
#ifdef FT_FAULT_FIBER_INDEX
  return fiberTable[min(ftSlotFiber(yarn, slot) + 1u, yarn.fiberCount - 1u)];  // reads the neighbour's row
#else
  return fiberTable[ftSlotFiber(yarn, slot)];
#endif
}
#endif
