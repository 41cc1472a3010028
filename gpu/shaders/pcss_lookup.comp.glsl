// PCSS soft-shadow lookups at points (common/pcss.h, docs/soft-shadows.md):
// the frame's T̃ functions, run for the harness's requests (p, light or lobe
// index) on the maps FiberRenderer drew. FiberRenderer::pcssLookup.
#include "common/constants.h"
#include "common/shadow_map.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PCSS) in;

layout(std140, binding = FT_UBO_SHADOW_MAP) uniform ShadowMapBlock { ShadowMapParams shadowMap; };
layout(std430, binding = FT_SSBO_SHADOW_MAP) readonly buffer ShadowMapTexels { float shadowMapTexels[]; };
layout(std430, binding = FT_SSBO_PCSS_LOBE_MAPS) readonly buffer PcssLobeTexels { float pcssLobeTexels[]; };
layout(std430, binding = FT_SSBO_PCSS_REQUESTS) readonly buffer PcssRequests { vec4 requests[]; };
layout(std430, binding = FT_SSBO_PCSS_RESULTS) writeonly buffer PcssResults { float results[]; };

#include "common/pcss.h"

float ftPcssFetch(int source, uint i) { return source == FT_PCSS_SOURCE_LOBES ? pcssLobeTexels[i] : shadowMapTexels[i]; }

layout(std140, binding = FT_UBO_PCSS) uniform PcssBlock { PcssParams pcss; };

uniform uint groupsX;
uniform uint itemCount;
uniform uint lobes;  // 1: requests name lobes j of the lobe maps; 0: lights i of the shadow map

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_PCSS);
  if (k >= itemCount) return;
  vec4 r = requests[k];
  results[k] = lobes != 0u ? ftPcssLobeVisibility(pcss, int(r.w), r.xyz) : ftPcssLightVisibility(shadowMap, pcss, int(r.w), r.xyz);
}
