// yarn_frame.h — the frame (T, N, B) along a yarn curve.
//
// Choice: a rotation-minimizing frame (RMF) sampled at the knots (segment
// end points) by the double-reflection method of Wang, Jüttler, Zheng & Liu,
// "Computation of Rotation Minimizing Frames" (ACM TOG 2008), started from a
// fixed, branch-free orthonormal basis at the first knot (Duff et al.,
// "Building an Orthonormal Basis, Revisited", JCGT 2017). On a closed curve
// the propagated normal generally fails to meet the start normal (holonomy);
// the mismatch angle is spread linearly over the length coordinate, so the
// frame is continuous around the loop.
// Inside a segment N(t) is the knot normals blended linearly and projected
// onto the plane ⟂ T(t). T is continuous at knots (C1 curve) and both
// segments meeting at a knot use that knot's normal, so the frame is
// continuous there: it never flips. Unlike a Frenet frame it is defined on
// straight pieces and does not spin at inflections. Unlike a fixed
// "up vector" frame it has no pole where the yarn points up.
// Both sides compute the knot normals with these functions, the CPU in
// reference/, the GPU in gpu/shaders/yarn_frames.comp.glsl, one curve per
// invocation (the propagation is sequential along a curve).
#ifndef FT_YARN_FRAME_H
#define FT_YARN_FRAME_H
#include "prelude.h"
#include "yarn_curve.h"

FT_NAMESPACE_BEGIN

// Any unit vector ⟂ n, continuous except where n.z changes sign.
FT_FUNC vec3 ftPerpendicular(vec3 n) {
  float sgn = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (sgn + n.z);
  float b = n.x * n.y * a;
  return vec3(1.0f + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
}

// Projects r onto the plane ⟂ unit t and normalizes.
FT_FUNC vec3 ftOrthonormalize(vec3 r, vec3 t) { return ftNormalize(r - t * dot(r, t)); }

// One double-reflection step: frame normal r0 at (x0, t0) carried to (x1, t1).
FT_FUNC vec3 ftRmfStep(vec3 x0, vec3 t0, vec3 r0, vec3 x1, vec3 t1) {
  vec3 v1 = x1 - x0;
  float c1 = dot(v1, v1);
  if (c1 <= 0.0f) return ftOrthonormalize(r0, t1);
  vec3 rL = r0 - v1 * (2.0f / c1 * dot(v1, r0));
  vec3 tL = t0 - v1 * (2.0f / c1 * dot(v1, t0));
  vec3 v2 = t1 - tL;
  float c2 = dot(v2, v2);
#ifdef FT_FAULT_RMF_ONE_REFLECTION
  vec3 r1 = rL;  // forgets the second reflection: the frame drifts about the tangent
#else
  vec3 r1 = c2 <= 0.0f ? rL : rL - v2 * (2.0f / c2 * dot(v2, rL));
#endif
  return ftOrthonormalize(r1, t1);
}

// Rodrigues rotation of v about unit axis k.
FT_FUNC vec3 ftRotateAbout(vec3 v, vec3 k, float angle) {
  float c = cos(angle);
  float s = sin(angle);
  return v * c + cross(k, v) * s + k * (dot(k, v) * (1.0f - c));
}

// Signed angle about unit axis k that turns a onto b (both ⟂ k).
FT_FUNC float ftSignedAngle(vec3 a, vec3 b, vec3 k) { return atan(dot(cross(a, b), k), dot(a, b)); }

// Knot k of a curve: position, unit tangent, length coordinate. The last knot
// of an open curve is the end of its last segment.
struct Knot {
  vec3 position;
  vec3 tangent;
  float s;
};

FT_FUNC Knot ftSegmentStartKnot(YarnSegment seg) {
  Knot k;
  k.position = vec3(seg.b0);
  k.tangent = ftNormalize(ftBezierDerivative(seg, 0.0f));
  k.s = seg.s0;
  return k;
}

FT_FUNC Knot ftSegmentEndKnot(YarnSegment seg) {
  Knot k;
  k.position = vec3(seg.b3);
  k.tangent = ftNormalize(ftBezierDerivative(seg, 1.0f));
  k.s = seg.s1;
  return k;
}

// The knot after the last segment: the first knot again (at the full
// length) on a closed curve, the end of the last segment on an open one.
FT_FUNC Knot ftLastKnot(CurveInfo c, Knot first, YarnSegment last) {
  if (c.closed == 0u) return ftSegmentEndKnot(last);
  Knot k = first;
  k.s = c.totalLength;
  return k;
}

// Closed curves: angle correction to apply at length coordinate s, given the
// holonomy angle measured after one full turn (see the header comment).
FT_FUNC vec3 ftCloseFrame(vec3 r, vec3 t, float holonomy, float s, float totalLength) {
  return ftOrthonormalize(ftRotateAbout(r, t, holonomy * (s / totalLength)), t);
}

// Frame at parameter t of a segment whose n0/n1 hold the knot normals.
struct YarnFrame {
  vec3 center;
  vec3 T;
  vec3 N;
  vec3 B;
};

FT_FUNC YarnFrame ftYarnFrameAt(YarnSegment seg, float t) {
  YarnFrame f;
  f.center = ftBezierPoint(seg, t);
  f.T = ftNormalize(ftBezierDerivative(seg, t));
  f.N = ftOrthonormalize(mix(vec3(seg.n0), vec3(seg.n1), t), f.T);
  f.B = cross(f.T, f.N);
  return f;
}

FT_NAMESPACE_END
#endif  // FT_YARN_FRAME_H
