// The self-shadow texture of 000 §4.1 by the exact line integral of the
// shared density field (SelfShadowGpu::bakeExact), one invocation per texel:
// the same float function as the CPU reference (common/self_shadow.h).
#include "common/constants.h"
#include "common/self_shadow.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SELF_SHADOW) in;
layout(std140, binding = FT_UBO_SELF_SHADOW) uniform SelfShadowBlock {
  SelfShadowParams shadow;
  YarnDensityParams density;
};
layout(std430, binding = FT_SSBO_SELF_SHADOW_TEXTURE) writeonly buffer SelfShadowTexture { float texels[]; };
uniform uint groupsX;

void main() {
  uint t = flatInvocationIndex(groupsX, FT_WG_SELF_SHADOW);
  if (t >= shadow.width * shadow.height * shadow.slices) return;
  uint i = t % shadow.width, j = (t / shadow.width) % shadow.height, k = t / (shadow.width * shadow.height);
#ifdef FT_FAULT_SELF_SHADOW_ELLIPSE_SWAP
  // Planted fault: the ply's semi-axes exchanged (e_N across the ply direction).
  YarnDensityParams d = density;
  d.ellipseN = density.ellipseB;
  d.ellipseB = density.ellipseN;
  texels[t] = ftSelfShadowExact(shadow, d, i, j, k);
#else
  texels[t] = ftSelfShadowExact(shadow, density, i, j, k);
#endif
}
