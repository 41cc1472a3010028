// The temporary density texture of 000 §4.2 (Fig. 8a): ρ (fibers per unit
// area, common/yarn_density.h) at the centres of an m × m grid over [−W, W]²,
// ψ = 0 (AmbientOcclusionGpu::bakeMarched).
#include "common/constants.h"
#include "common/ambient_occlusion.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_AO) in;
layout(std140, binding = FT_UBO_AMBIENT_OCCLUSION) uniform AoBlock { AmbientOcclusionParams ao; };
layout(std430, binding = FT_SSBO_AO_DENSITY) writeonly buffer AoDensity { float grid[]; };
uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_AO);
  if (k >= itemCount) return;
  uint m = ao.densityResolution;
  vec2 x = vec2(ftAoTexelCentre(ao.halfWidth, m, k % m), ftAoTexelCentre(ao.halfWidth, m, k / m));
  grid[k] = ftYarnDensity(ao.density, 0.0, x);
}
