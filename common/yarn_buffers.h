// yarn_buffers.h — the procedural input the GPU receives (std430 storage
// buffers): yarn control points with their length coordinate (§5 of
// 000_cc9bd0fbd0e08a03.txt), a curve table, a segment table, and the fiber
// coordinate table sorted by R_i. Nothing else describes the geometry.
#ifndef FT_YARN_BUFFERS_H
#define FT_YARN_BUFFERS_H
#include "prelude.h"

FT_NAMESPACE_BEGIN

// One yarn control point: xyz position, w = length coordinate (arc length of
// the control polygon from the curve start, fixed when the model is loaded).
struct ControlPoint {
  vec4 positionLength;
};
FT_ASSERT_SIZE(ControlPoint, 16)

struct CurveInfo {
  uint firstPoint;    // index of the curve's first control point
  uint pointCount;    // >= 2 (open) or >= 3 (closed)
  uint closed;        // 1: the curve wraps from its last point to its first
  uint firstSegment;  // index of its first segment in the segment table
  float totalLength;  // length coordinate at the end of the last segment
  uint basis;         // FT_BASIS_CATMULL_ROM or FT_BASIS_BEZIER (yarn_curve.h)
  uint frameBase;     // index of the curve's first knot frame in the frame buffer
  uint pad0;
};
FT_ASSERT_OFFSET(CurveInfo, totalLength, 16)
FT_ASSERT_OFFSET(CurveInfo, frameBase, 24)
FT_ASSERT_SIZE(CurveInfo, 32)

// Segment k of a curve runs from its control point k to k+1 (k+1 wraps to 0
// on a closed curve). Open curves have pointCount-1 segments, closed ones
// pointCount.
struct SegmentRef {
  uint curve;
  uint local;
};
FT_ASSERT_SIZE(SegmentRef, 8)

// Rotation-minimizing normal at one segment end point ("knot"); a curve has
// segments+1 knots when open, `segments` when closed (see yarn_frame.h).
struct FrameNormal {
  vec4 normal;  // xyz unit normal ⟂ tangent; w unused
};
FT_ASSERT_SIZE(FrameNormal, 16)

// One row of the 1D fiber-coordinate table (§5): sorted by R ascending.
struct FiberCoord {
  float radius;       // R_i in the unit ply disk
  float thetaTurns;   // θ_i / 2π in [0, 1)
};
FT_ASSERT_SIZE(FiberCoord, 8)

FT_NAMESPACE_END
#endif  // FT_YARN_BUFFERS_H
