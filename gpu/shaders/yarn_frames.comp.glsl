// Rotation-minimizing knot normals, one invocation per curve: the GPU twin of
// computeKnotFramesCpu() (reference/fiber_reference.cpp), same statements.
#define FT_FRAMES_WRITABLE
#include "shaders/fiber_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_FRAMES) in;
layout(std430, binding = FT_SSBO_FRAMES) buffer FrameBuffer { FrameNormal frames[]; };
uniform uint curveCount;
uniform uint groupsX;  // work groups along x per y row

void main() {
  uint ci = flatInvocationIndex(groupsX, FT_WG_FRAMES);
  if (ci >= curveCount) return;
  CurveInfo c = curves[ci];
  uint segments = ftCurveSegmentCount(c);
  Knot k0 = ftSegmentStartKnot(fetchSegment(c, 0u));
  vec3 r = ftPerpendicular(k0.tangent);
  frames[c.frameBase].normal = vec4(r, 0.0f);
  Knot prev = k0;
  for (uint k = 0u; k < segments; ++k) {
    Knot next = k + 1u < segments ? ftSegmentStartKnot(fetchSegment(c, k + 1u))
                                   : ftLastKnot(c, k0, fetchSegment(c, k));
    r = ftRmfStep(prev.position, prev.tangent, r, next.position, next.tangent);
    if (k + 1u < ftCurveKnotCount(c)) frames[c.frameBase + k + 1u].normal = vec4(r, 0.0f);
    prev = next;
  }
  if (c.closed != 0u) {
    float holonomy = ftSignedAngle(r, vec3(frames[c.frameBase].normal), k0.tangent);
    for (uint k = 1u; k < segments; ++k) {
      Knot kk = ftSegmentStartKnot(fetchSegment(c, k));
      vec3 n = vec3(frames[c.frameBase + k].normal);
      frames[c.frameBase + k].normal = vec4(ftCloseFrame(n, kk.tangent, holonomy, kk.s, c.totalLength), 0.0f);
    }
  }
}
