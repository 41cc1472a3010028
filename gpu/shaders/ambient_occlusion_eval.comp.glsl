// The two run-time AO lookups of 000 §4.2 at given cross-section points
// (AmbientOcclusionGpu::evaluate): x = ftAoCubic (distance-based, from the
// yarn centre), y = the texture turned by −θ_ply,0 with a manual bilinear fetch.
#include "common/constants.h"
#include "common/ambient_occlusion.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_AO) in;
layout(std140, binding = FT_UBO_AMBIENT_OCCLUSION) uniform AoBlock { AmbientOcclusionParams ao; };
// Two vec4 per request: (ply offset, fiber offset), (θ_ply,0, 0, 0, 0).
layout(std430, binding = FT_SSBO_AO_POINTS) readonly buffer AoPoints { vec4 points[]; };
layout(std430, binding = FT_SSBO_AO_TEXTURE) readonly buffer AoTexture { float texels[]; };
layout(std430, binding = FT_SSBO_AO_OUTPUT) writeonly buffer AoOutput { vec2 results[]; };
uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_AO);
  if (k >= itemCount) return;
  vec4 offsets = points[2u * k];
  float theta = points[2u * k + 1u].x;
  float cubic = ftAoCubic(ao, offsets.xy, offsets.zw);
  vec2 p = offsets.xy + offsets.zw;
  AoTexelLookup t = ftAoTextureLookup(ao, p, vec2(cos(theta), sin(theta)));
  uint n = ao.resolution;
  float tex = ftAoBilinear(texels[t.lo.y * n + t.lo.x], texels[t.lo.y * n + t.hi.x], texels[t.hi.y * n + t.lo.x],
                           texels[t.hi.y * n + t.hi.x], t.weight);
  results[k] = vec2(cubic, tex);
}
