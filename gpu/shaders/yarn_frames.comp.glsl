// Rotation-minimizing knot normals: the GPU twin of computeKnotFramesCpu()
// (reference/fiber_reference.cpp), same statements. The propagation is
// sequential along a curve, and gallivm ends a loop after 65,535 iterations,
// so it runs in chunks: dispatch `chunk` (mode 0) takes knots
// [chunk·FT_FRAME_CHUNK, (chunk+1)·FT_FRAME_CHUNK] of every curve, one
// invocation per curve, starting from the leaving normal the previous
// dispatch left in carry[curve].xyz; the last chunk of a closed curve leaves
// the holonomy in carry[curve].w. Mode 1 then spreads the holonomy, one
// invocation per segment.
#define FT_FRAMES_WRITABLE
#include "shaders/fiber_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_FRAMES) in;
layout(std430, binding = FT_SSBO_FRAMES) buffer FrameBuffer { FrameNormal frames[]; };
layout(std430, binding = FT_SSBO_FRAME_CARRY) buffer CarryBuffer { vec4 carry[]; };
uniform uint mode;        // 0: propagate one chunk; 1: closed-curve correction
uniform uint chunk;       // mode 0: which chunk
uniform uint itemCount;   // mode 0: curves; mode 1: segments
uniform uint groupsX;     // work groups along x per y row

Knot curveKnot(CurveInfo c, uint k) {
  return ftCurveKnot(c, k, fetchSegment(c, ftKnotSegmentBefore(c, k)), fetchSegment(c, ftKnotSegmentAfter(c, k)));
}

void propagate(uint ci) {
  CurveInfo c = curves[ci];
  uint segments = ftCurveSegmentCount(c);
  uint first = chunk * FT_FRAME_CHUNK;
  if (first >= segments) return;
  uint last = min(first + FT_FRAME_CHUNK, segments);
  YarnSegment after = fetchSegment(c, ftKnotSegmentAfter(c, first));
  Knot a = ftCurveKnot(c, first, fetchSegment(c, ftKnotSegmentBefore(c, first)), after);
  vec3 r;
  if (first == 0u) {
    r = ftStartNormal(a);
    frames[c.frameBase].normal = vec4(ftStoredFromLeaving(a, r), 0.0f);
  } else {
    r = vec3(carry[ci]);
  }
  for (uint k = first; k < last; ++k) {
    YarnSegment before = after;  // segment k = ftKnotSegmentBefore(c, k + 1)
    after = fetchSegment(c, ftKnotSegmentAfter(c, k + 1u));
    Knot b = ftCurveKnot(c, k + 1u, before, after);
    FrameStep f = ftCarryFrame(a, r, b);
    if (k + 1u < ftCurveKnotCount(c)) frames[c.frameBase + k + 1u].normal = vec4(f.stored, 0.0f);
    r = f.leaving;
    a = b;
  }
  float holonomy = 0.0f;
  if (last == segments && c.closed != 0u) {
    // r is now the start normal carried once around the loop.
    Knot k0 = curveKnot(c, 0u);
    holonomy = ftSignedAngle(r, ftStartNormal(k0), k0.tangent);
  }
  carry[ci] = vec4(r, holonomy);
}

void closeLoop(uint segment) {
  SegmentRef ref = segmentRefs[segment];
  CurveInfo c = curves[ref.curve];
  if (c.closed == 0u || ref.local == 0u) return;
  Knot kk = curveKnot(c, ref.local);
  vec3 n = vec3(frames[c.frameBase + ref.local].normal);
#ifdef FT_FAULT_CLOSURE_AXIS
  vec3 axis = ftNormalize(kk.tangent - kk.tangentIn);  // the back-track axis at every knot: 0/0 off cusps
#else
  vec3 axis = ftKnotAxis(kk);
#endif
  frames[c.frameBase + ref.local].normal = vec4(ftCloseFrame(n, axis, carry[ref.curve].w, kk.s, c.totalLength), 0.0f);
}

void main() {
  uint i = flatInvocationIndex(groupsX, FT_WG_FRAMES);
  if (i >= itemCount) return;
  if (mode == 0u)
    propagate(i);
  else
    closeLoop(i);
}
