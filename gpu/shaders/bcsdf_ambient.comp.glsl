// The ambient table A(θ_o) of 000 §4.3 eq. 7–10 (BcsdfGpu::bakeAmbientTable),
// one invocation per texel.
#include "common/constants.h"
#include "common/fiber_shading.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_BCSDF) in;
layout(std430, binding = FT_SSBO_BCSDF_INPUT) readonly buffer BcsdfInput { FabricParams fabric; };
layout(std430, binding = FT_SSBO_BCSDF_OUTPUT) writeonly buffer BcsdfOutput { vec4 results[]; };  // rgb A(θ_k)
uniform uint groupsX;
uniform uint texels;  // n: θ_k = ftAmbientTexelAngle(k, n)
uniform uint steps;   // midpoint steps over θ_i ∈ [−π/2, π/2]

// A(θ_o) = ∫ [F M_R + (1 − F) C_TT M_TT](θ_i, θ_o) cos²θ_i dθ_i (eq. 8; the
// azimuthal integrals of eq. 9–10 are 1), midpoint rule. The terms are summed
// pairwise (a binary counter of partial sums: partial[l] holds the sum of 2^l
// terms), so rounding grows with log2(steps) rather than with steps.
void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_BCSDF);
  if (k >= texels) return;
  float thetaO = ftAmbientTexelAngle(int(k), int(texels));
  float h = FT_PI / float(steps);
  vec3 colorR = vec3(fabric.colorR), colorTT = vec3(fabric.colorTT);
  vec3 partial[32];
  for (uint s = 0u; s < steps; ++s) {
    float thetaI = -0.5 * FT_PI + (float(s) + 0.5) * h;
    vec3 f = ftFiberFresnel(colorR, thetaI);
    float c = cos(thetaI);
    vec3 v = (f * ftLongitudinal(thetaI, thetaO, fabric.colorR.w) +
              (vec3(1.0) - f) * colorTT * ftLongitudinal(thetaI, thetaO, fabric.colorTT.w)) * (c * c * h);
    uint level = 0u;
    for (uint n = s; (n & 1u) != 0u; n >>= 1u) v += partial[level++];
    partial[level] = v;
  }
  vec3 sum = vec3(0.0);
  for (uint level = 0u; level < 32u; ++level)
    if ((steps & (1u << level)) != 0u) sum += partial[level];
  results[k] = vec4(sum, 0.0);
}

