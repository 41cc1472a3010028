// yarn_curve.h — evaluation of one cubic yarn-curve segment.
//
// Two bases (000_cc9bd0fbd0e08a03.txt §3.1: "cubic Bézier or Catmull-Rom"):
//  * uniform Catmull-Rom (BCC curve type C0): segment k of a curve is the
//    piece between control points k and k+1, shaped by k-1..k+2. Closed
//    curves wrap; open curves reflect the end points (P_-1 = 2P_0 - P_1,
//    P_n = 2P_n-1 - P_n-2), which keeps the end tangent equal to the chord.
//  * cubic Bézier: segment k uses control points 3k..3k+3 (open curves only).
// Both are converted to Bézier form once per segment; all evaluation goes
// through that form (the convex hull of Bézier points bounds the segment,
// which the frustum test uses).
#ifndef FT_YARN_CURVE_H
#define FT_YARN_CURVE_H
#include "prelude.h"
#include "yarn_buffers.h"

#define FT_BASIS_CATMULL_ROM 0u
#define FT_BASIS_BEZIER 1u

FT_NAMESPACE_BEGIN

FT_FUNC uint ftCurveSegmentCount(CurveInfo c) {
  if (c.basis == FT_BASIS_BEZIER) return (c.pointCount - 1u) / 3u;
  return c.closed != 0u ? c.pointCount : c.pointCount - 1u;
}

// Which control points shape a segment; reflect flags mark synthesized ends.
struct SegmentIndices {
  uint i0;
  uint i1;
  uint i2;
  uint i3;
  uint reflectStart;  // P0 := 2 P1 - P2
  uint reflectEnd;    // P3 := 2 P2 - P1
};

FT_FUNC SegmentIndices ftSegmentIndices(CurveInfo c, uint local) {
  SegmentIndices s;
  s.reflectStart = 0u;
  s.reflectEnd = 0u;
  if (c.basis == FT_BASIS_BEZIER) {
    s.i0 = c.firstPoint + 3u * local;
    s.i1 = s.i0 + 1u;
    s.i2 = s.i0 + 2u;
    s.i3 = s.i0 + 3u;
    return s;
  }
  uint n = c.pointCount;
  if (c.closed != 0u) {
    s.i0 = c.firstPoint + (local + n - 1u) % n;
    s.i1 = c.firstPoint + local;
    s.i2 = c.firstPoint + (local + 1u) % n;
    s.i3 = c.firstPoint + (local + 2u) % n;
    return s;
  }
  s.i1 = c.firstPoint + local;
  s.i2 = s.i1 + 1u;
  s.i0 = local == 0u ? s.i1 : s.i1 - 1u;
  s.i3 = local + 2u >= n ? s.i2 : s.i2 + 1u;
  s.reflectStart = local == 0u ? 1u : 0u;
  s.reflectEnd = local + 2u >= n ? 1u : 0u;
  return s;
}

// A segment in Bézier form plus the data the fiber model needs along it.
struct YarnSegment {
  vec4 b0;  // xyz Bézier control points; w unused
  vec4 b1;
  vec4 b2;
  vec4 b3;
  vec4 n0;  // frame normal at t = 0 (xyz)
  vec4 n1;  // frame normal at t = 1
  float s0;  // length coordinate at t = 0
  float s1;  // length coordinate at t = 1
};

// Builds the Bézier form from the four fetched control points (already in
// the order of ftSegmentIndices; reflection is applied here).
FT_FUNC YarnSegment ftMakeSegment(CurveInfo c, uint local, SegmentIndices idx, vec4 q0, vec4 q1, vec4 q2,
                                  vec4 q3) {
  YarnSegment seg;
  vec3 p0 = vec3(q0);
  vec3 p1 = vec3(q1);
  vec3 p2 = vec3(q2);
  vec3 p3 = vec3(q3);
  if (c.basis == FT_BASIS_BEZIER) {
    seg.b0 = vec4(p0, 1.0f);
    seg.b1 = vec4(p1, 1.0f);
    seg.b2 = vec4(p2, 1.0f);
    seg.b3 = vec4(p3, 1.0f);
    seg.s0 = q0.w;
    seg.s1 = q3.w;
  } else {
    if (idx.reflectStart != 0u) p0 = 2.0f * p1 - p2;
    if (idx.reflectEnd != 0u) p3 = 2.0f * p2 - p1;
    // Uniform Catmull-Rom → Bézier: B1 = P1 + (P2 - P0)/6, B2 = P2 - (P3 - P1)/6.
    seg.b0 = vec4(p1, 1.0f);
    seg.b1 = vec4(p1 + (p2 - p0) * (1.0f / 6.0f), 1.0f);
    seg.b2 = vec4(p2 - (p3 - p1) * (1.0f / 6.0f), 1.0f);
    seg.b3 = vec4(p2, 1.0f);
    seg.s0 = q1.w;
    // The closing segment of a closed curve ends at the full length, not at 0.
    bool wraps = c.closed != 0u && local + 1u == c.pointCount;
    seg.s1 = wraps ? c.totalLength : q2.w;
  }
  seg.n0 = vec4(0.0f);
  seg.n1 = vec4(0.0f);
  return seg;
}

FT_FUNC uint ftCurveKnotCount(CurveInfo c) {
  return c.closed != 0u ? ftCurveSegmentCount(c) : ftCurveSegmentCount(c) + 1u;
}

// Frame-buffer index of knot k (k may equal the segment count: it wraps on
// closed curves).
FT_FUNC uint ftKnotFrameIndex(CurveInfo c, uint k) {
  return c.frameBase + (k == ftCurveKnotCount(c) ? 0u : k);
}

FT_FUNC vec3 ftBezierPoint(YarnSegment s, float t) {
  float u = 1.0f - t;
  return vec3(s.b0) * (u * u * u) + vec3(s.b1) * (3.0f * u * u * t) + vec3(s.b2) * (3.0f * u * t * t) +
         vec3(s.b3) * (t * t * t);
}

FT_FUNC vec3 ftBezierDerivative(YarnSegment s, float t) {
  float u = 1.0f - t;
  return (vec3(s.b1) - vec3(s.b0)) * (3.0f * u * u) + (vec3(s.b2) - vec3(s.b1)) * (6.0f * u * t) +
         (vec3(s.b3) - vec3(s.b2)) * (3.0f * t * t);
}

// Direct uniform Catmull-Rom evaluation; used by tests to check the Bézier
// conversion above, not by the generators.
FT_FUNC vec3 ftCatmullRomPoint(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
  float t2 = t * t;
  float t3 = t2 * t;
  return 0.5f * (2.0f * p1 + (p2 - p0) * t + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * t2 +
                 (3.0f * p1 - p0 - 3.0f * p2 + p3) * t3);
}

FT_NAMESPACE_END
#endif  // FT_YARN_CURVE_H
