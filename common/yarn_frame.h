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
// reference/, the GPU in gpu/shaders/yarn_frames.comp.glsl (the propagation
// is sequential along a curve; the GPU runs it in chunks of FT_FRAME_CHUNK
// knots, one dispatch per chunk, carrying the normal across).
//
// Zero tangents (cusps). Real models contain exact back-tracks,
// p[i+1] == p[i-1], where the Catmull-Rom derivative at knot i vanishes.
// Fallback, identical on both sides:
//  * the tangent at a segment end is its one-sided limit: the first
//    non-negligible of B1-B0, B2-B0, B3-B0 (mirrored at t = 1). A Bézier
//    curve's first non-vanishing derivative at an end point is a positive
//    multiple of that difference; B3-B0 is the chord, never zero (the BCC
//    reader rejects coincident points and spacing below 1e-12). "Negligible"
//    is shorter than 1e-6 of the chord: such a direction is rounding noise.
//  * a knot whose leaving derivative is negligible is a cusp with two
//    tangents: tangentIn (the previous segment's end) and tangent (the next
//    segment's start). The frame arrives with tangentIn (a well-conditioned
//    double reflection), then turns to tangent by one reflection about the
//    knot's axis a: the bisector of the two tangents when they are less than
//    90° apart (the turn is then the minimal rotation, composed with the
//    reflection ⟂ tangentIn that leaves the normal unchanged), their
//    difference when more (a back-track: the normal is kept, only its part
//    along a flips). Each choice is far from its own singular configuration.
//    The stored normal is the arriving one projected ⟂ a, at most 45° from ⟂
//    either tangent, so both segments' frames at the knot stay defined.
//    Closed curves: the holonomy correction rotates it about a.
#ifndef FT_YARN_FRAME_H
#define FT_YARN_FRAME_H
#include "prelude.h"
#include "yarn_curve.h"

// Planted fault "tangent-fallback" (validation/faults.h): the zero-tangent
// fallback dropped, as before issue 8. It lives in shared math, so it must
// act on both sides: the C++ side switches it at run time (the harness sets
// ftFaultTangentFallback for --inject), the GLSL side at compile time.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultTangentFallback = false;
}
#define FT_FAULT_TANGENT_FALLBACK_ON ::ft::ftFaultTangentFallback
#elif defined(FT_FAULT_TANGENT_FALLBACK)
#define FT_FAULT_TANGENT_FALLBACK_ON true
#else
#define FT_FAULT_TANGENT_FALLBACK_ON false
#endif

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
  // Not <= 0: a denormal c2 (flushed to zero on the GPU) would overflow 2/c2 on the CPU.
  float c2 = dot(v2, v2);
#ifdef FT_FAULT_RMF_ONE_REFLECTION
  vec3 r1 = rL;  // forgets the second reflection: the frame drifts about the tangent
#else
  vec3 r1 = c2 <= 1e-30f ? rL : rL - v2 * (2.0f / c2 * dot(v2, rL));
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

// True when d is too short next to the segment chord to give a direction.
FT_FUNC bool ftNegligible(vec3 d, vec3 chord) {
  FT_PRECISE float dd = dot(d, d);
  FT_PRECISE float cc = dot(chord, chord);
  return dd <= 1e-12f * cc;
}

// Unit tangent where a segment starts / ends: the derivative, or its
// one-sided limit where the derivative vanishes (see the header comment).
FT_FUNC vec3 ftSegmentStartTangent(YarnSegment s) {
  vec3 chord = vec3(s.b3) - vec3(s.b0);
  vec3 d = ftBezierDerivative(s, 0.0f);
  if (FT_FAULT_TANGENT_FALLBACK_ON) return ftNormalize(d);  // 0/0 = NaN at a back-track
  if (ftNegligible(d, chord)) d = vec3(s.b2) - vec3(s.b0);
  if (ftNegligible(d, chord)) d = chord;
  return ftNormalize(d);
}

FT_FUNC vec3 ftSegmentEndTangent(YarnSegment s) {
  vec3 chord = vec3(s.b3) - vec3(s.b0);
  vec3 d = ftBezierDerivative(s, 1.0f);
  if (FT_FAULT_TANGENT_FALLBACK_ON) return ftNormalize(d);
  if (ftNegligible(d, chord)) d = vec3(s.b3) - vec3(s.b1);
  if (ftNegligible(d, chord)) d = chord;
  return ftNormalize(d);
}

// Unit tangent at t; inside a segment a vanishing derivative (only a
// degenerate control polygon has one) falls back to the chord.
FT_FUNC vec3 ftTangentAt(YarnSegment s, float t) {
  vec3 d = ftBezierDerivative(s, t);
  if (FT_FAULT_TANGENT_FALLBACK_ON) return ftNormalize(d);
  if (!ftNegligible(d, vec3(s.b3) - vec3(s.b0))) return ftNormalize(d);
  if (t <= 0.0f) return ftSegmentStartTangent(s);
  if (t >= 1.0f) return ftSegmentEndTangent(s);
  return ftNormalize(vec3(s.b3) - vec3(s.b0));
}

// Knot k of a curve (0 <= k <= segments; k == segments is the end of an open
// curve, the first knot again at the full length on a closed one).
struct Knot {
  vec3 position;
  vec3 tangent;    // leaving the knot (arriving, at the end of an open curve)
  vec3 tangentIn;  // arriving; differs from tangent only at a cusp
  float s;
  uint cusp;       // 1: the derivative vanishes here (see the header comment)
};

// The segments a knot needs: segment k-1 (before) and k (after), wrapped on
// closed curves, clamped at the ends of open ones.
FT_FUNC uint ftKnotSegmentBefore(CurveInfo c, uint k) {
  uint segments = ftCurveSegmentCount(c);
  if (k == 0u) return c.closed != 0u ? segments - 1u : 0u;
  return k - 1u;
}

FT_FUNC uint ftKnotSegmentAfter(CurveInfo c, uint k) {
  uint segments = ftCurveSegmentCount(c);
  if (k < segments) return k;
  return c.closed != 0u ? 0u : segments - 1u;
}

FT_FUNC Knot ftCurveKnot(CurveInfo c, uint k, YarnSegment before, YarnSegment after) {
  Knot kn;
  kn.cusp = 0u;
  if (c.closed == 0u && k == ftCurveSegmentCount(c)) {
    kn.position = vec3(before.b3);
    kn.tangent = ftSegmentEndTangent(before);
    kn.tangentIn = kn.tangent;
    kn.s = before.s1;
    return kn;
  }
  kn.position = vec3(after.b0);
  kn.tangent = ftSegmentStartTangent(after);
  kn.tangentIn = kn.tangent;
  kn.s = k == ftCurveSegmentCount(c) ? c.totalLength : after.s0;
  bool hasBefore = c.closed != 0u || k > 0u;
  if (hasBefore && ftNegligible(ftBezierDerivative(after, 0.0f), vec3(after.b3) - vec3(after.b0))) {
    kn.cusp = 1u;
    kn.tangentIn = ftSegmentEndTangent(before);
  }
  return kn;
}

// The axis the stored knot normal is ⟂ to: the tangent, or at a cusp the
// bisector (turn < 90°) or the difference (turn > 90°) of its two tangents.
FT_FUNC vec3 ftKnotAxis(Knot k) {
  if (k.cusp == 0u) return k.tangent;
  FT_PRECISE float d = dot(k.tangentIn, k.tangent);
  return d >= 0.0f ? ftNormalize(k.tangentIn + k.tangent) : ftNormalize(k.tangent - k.tangentIn);
}

// What one propagation step produces at the knot it arrives at: the normal
// stored for the knot and the normal that leaves it (⟂ its leaving tangent).
struct FrameStep {
  vec3 stored;
  vec3 leaving;
};

// The normal a curve's propagation starts from at knot 0 (leaving it).
FT_FUNC vec3 ftStartNormal(Knot k0) { return ftPerpendicular(k0.tangent); }

// The normal stored for a knot whose leaving normal is r.
FT_FUNC vec3 ftStoredFromLeaving(Knot k, vec3 r) {
  return k.cusp == 0u ? r : ftOrthonormalize(r, ftKnotAxis(k));
}

// Carries the leaving normal r at knot a to knot b.
FT_FUNC FrameStep ftCarryFrame(Knot a, vec3 r, Knot b) {
  FrameStep f;
  vec3 rin = ftRmfStep(a.position, a.tangent, r, b.position, b.tangentIn);
  f.stored = rin;
  f.leaving = rin;
  if (b.cusp != 0u) {
    vec3 ax = ftKnotAxis(b);
    f.stored = ftOrthonormalize(rin, ax);
    f.leaving = ftOrthonormalize(rin - ax * (2.0f * dot(ax, rin)), b.tangent);
  }
  return f;
}

// Closed curves: angle correction to apply at length coordinate s, given the
// holonomy angle measured after one full turn (see the header comment); r is
// a stored knot normal, axis its ftKnotAxis.
FT_FUNC vec3 ftCloseFrame(vec3 r, vec3 axis, float holonomy, float s, float totalLength) {
  return ftOrthonormalize(ftRotateAbout(r, axis, holonomy * (s / totalLength)), axis);
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
  f.T = ftTangentAt(seg, t);
  f.N = ftOrthonormalize(mix(vec3(seg.n0), vec3(seg.n1), t), f.T);
  f.B = cross(f.T, f.N);
  return f;
}

FT_NAMESPACE_END
#endif  // FT_YARN_FRAME_H
