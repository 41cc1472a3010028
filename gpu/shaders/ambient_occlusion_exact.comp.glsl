// The AO texture (or AO at points) with the exact line integral of the ply
// density: ftAoExact of common/ambient_occlusion.h, as the CPU reference
// computes it (000 §4.2; AmbientOcclusionGpu::bakeExact / exactAt).
#include "common/constants.h"
#include "common/ambient_occlusion.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_AO) in;
layout(std140, binding = FT_UBO_AMBIENT_OCCLUSION) uniform AoBlock { AmbientOcclusionParams ao; };
layout(std430, binding = FT_SSBO_AO_POINTS) readonly buffer AoPoints { vec4 points[]; };  // x, y, ψ
layout(std430, binding = FT_SSBO_AO_OUTPUT) writeonly buffer AoOutput { float results[]; };
uniform uint groupsX;
uniform uint itemCount;
uniform uint pointMode;  // 0: texel centres (ψ = 0), 1: points

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_AO);
  if (k >= itemCount) return;
  vec2 x;
  float psi = 0.0;
  if (pointMode == 0u) {
    uint n = ao.resolution;
    x = vec2(ftAoTexelCentre(ao.halfWidth, n, k % n), ftAoTexelCentre(ao.halfWidth, n, k / n));
  } else {
    x = points[k].xy;
    psi = points[k].z;
  }
  results[k] = ftAoExact(ao, psi, x, k);
}
