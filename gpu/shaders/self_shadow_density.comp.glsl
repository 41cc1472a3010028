// The paper's density slices of 000 §4.1 (Fig. 6, top row): ρ_{ψ_k} at every
// texel centre (SelfShadowGpu::bakeGrid, first pass), one invocation per texel.
#include "common/constants.h"
#include "common/self_shadow.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SELF_SHADOW) in;
layout(std140, binding = FT_UBO_SELF_SHADOW) uniform SelfShadowBlock {
  SelfShadowParams shadow;
  YarnDensityParams density;
};
layout(std430, binding = FT_SSBO_SELF_SHADOW_DENSITY) writeonly buffer SelfShadowDensity { float rho[]; };
uniform uint groupsX;

void main() {
  uint t = flatInvocationIndex(groupsX, FT_WG_SELF_SHADOW);
  if (t >= shadow.width * shadow.height * shadow.slices) return;
  uint i = t % shadow.width, j = (t / shadow.width) % shadow.height, k = t / (shadow.width * shadow.height);
  rho[t] = ftYarnDensity(density, ftSelfShadowSliceAngle(shadow, k), ftSelfShadowTexelCenter(shadow, i, j));
}
