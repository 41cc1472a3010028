// The I_M table looked up as the renderer will (SrbfTableGpu::lookup): one
// invocation per request (θ_o, θ_j, Δφ, λ), ftSrbfTableLookup and its 16 taps.
#include "common/constants.h"
#include "common/srbf_bcsdf.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SRBF) in;
layout(std430, binding = FT_SSBO_SRBF_INPUT) readonly buffer SrbfInput { vec4 requests[]; };
layout(std430, binding = FT_SSBO_SRBF_TABLE) readonly buffer SrbfTable { vec4 table[]; };
layout(std430, binding = FT_SSBO_SRBF_OUTPUT) writeonly buffer SrbfOutput { vec4 results[]; };
uniform uint groupsX;
uniform uint requestCount;
uniform ivec4 dims;

void main() {
  uint i = flatInvocationIndex(groupsX, FT_WG_SRBF);
  if (i >= requestCount) return;
  vec4 r = requests[i];
  vec4 u = ftSrbfTableLookup(dims, r.x, r.y, r.z, r.w);
  vec3 sum = vec3(0.0);
  for (int c = 0; c < 16; ++c) {
    vec2 tap = ftSrbfTableTap(dims, u, c);
    sum += tap.y * table[int(tap.x)].xyz;
  }
  results[i] = vec4(sum, 0.0);
}
