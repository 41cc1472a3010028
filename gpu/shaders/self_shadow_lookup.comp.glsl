// The self-shadow texture looked up per request (SelfShadowGpu::lookup), as
// a fragment would: ftSelfShadowSample, the 8 texels, ftSelfShadowBlend,
// ftSelfShadowTransmittance (common/self_shadow.h).
#include "common/constants.h"
#include "common/self_shadow.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SELF_SHADOW) in;
layout(std140, binding = FT_UBO_SELF_SHADOW) uniform SelfShadowBlock {
  SelfShadowParams shadow;
  YarnDensityParams density;
};
layout(std430, binding = FT_SSBO_SELF_SHADOW_TEXTURE) readonly buffer SelfShadowTexture { float texels[]; };
// (x, ℓ⊥) and (θ_ply,0, 0, 0, 0) per request.
layout(std430, binding = FT_SSBO_SELF_SHADOW_REQUESTS) readonly buffer SelfShadowRequests { vec4 requests[]; };
// (D, T, ψ, 0) per request.
layout(std430, binding = FT_SSBO_SELF_SHADOW_RESULTS) writeonly buffer SelfShadowResults { vec4 results[]; };
uniform uint requestCount;
uniform uint groupsX;

float texel(uint i, uint j, uint k) { return texels[ftSelfShadowIndex(shadow, i, j, k)]; }
vec4 corners(SelfShadowSample s, uint k) {
  return vec4(texel(s.u.x, s.u.z, k), texel(s.u.y, s.u.z, k), texel(s.u.x, s.u.w, k), texel(s.u.y, s.u.w, k));
}

void main() {
  uint q = flatInvocationIndex(groupsX, FT_WG_SELF_SHADOW);
  if (q >= requestCount) return;
  vec4 a = requests[2u * q], b = requests[2u * q + 1u];
  SelfShadowSample s = ftSelfShadowSample(shadow, a.xy, a.zw, b.x);
  float d = ftSelfShadowBlend(s, corners(s, s.r.x), corners(s, s.r.y));
  results[q] = vec4(d, ftSelfShadowTransmittance(shadow, s, d), s.w.w, 0.0);
}
