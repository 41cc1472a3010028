// The paper's accumulation of 000 §4.1 (Fig. 6, bottom row): "for each pixel
// of each slice, we accumulate the total density on the left side of the
// pixel (in the opposite direction to the light direction)" — a prefix sum
// along u with the midpoint rule, D[i] = Σ_{i'<i} ρ[i']Δ + ½ρ[i]Δ
// (SelfShadowGpu::bakeGrid, second pass), one invocation per row (v_j, ψ_k).
#include "common/constants.h"
#include "common/self_shadow.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SELF_SHADOW) in;
layout(std140, binding = FT_UBO_SELF_SHADOW) uniform SelfShadowBlock {
  SelfShadowParams shadow;
  YarnDensityParams density;
};
layout(std430, binding = FT_SSBO_SELF_SHADOW_DENSITY) readonly buffer SelfShadowDensity { float rho[]; };
layout(std430, binding = FT_SSBO_SELF_SHADOW_TEXTURE) writeonly buffer SelfShadowTexture { float texels[]; };
uniform uint groupsX;

void main() {
  uint row = flatInvocationIndex(groupsX, FT_WG_SELF_SHADOW);
  if (row >= shadow.height * shadow.slices) return;
  uint base = row * shadow.width;
  float delta = 2.0 * shadow.halfWidth / float(shadow.width);
  float sum = 0.0;  // Σ_{i'<i} ρ[i'] (in units of ρ; times Δ on output)
  for (uint n = 0u; n < shadow.width; ++n) {
#ifdef FT_FAULT_SELF_SHADOW_PREFIX_FAR
    uint i = shadow.width - 1u - n;  // planted fault: accumulated from the side away from the light
#else
    uint i = n;
#endif
    float r = rho[base + i];
    texels[base + i] = (sum + 0.5 * r) * delta;
    sum += r;
  }
}
