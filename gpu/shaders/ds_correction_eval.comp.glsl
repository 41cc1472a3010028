// The DS correction textures looked up per request (DsCorrectionGpu::evaluate),
// as a fragment would: ftXiLookup, the eight log-encoded corners of each
// texture (ftXiEncode, done on the host), ftXiDecode of their weighted sums:
// the product ξ_M ξ_N Ψ_M Ψ_N of 001 eq. 11 (common/ds_correction.h).
// The lookup's coordinates unfused, as the CPU rounds them (common/ds_correction.h).
#define FT_XI_PRECISE precise
#include "common/constants.h"
#include "common/ds_correction.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_XI) in;
layout(std140, binding = FT_UBO_XI) uniform DsCorrectionBlock { DsCorrectionLayout dsLayout; };
layout(std430, binding = FT_SSBO_XI_M) readonly buffer DsXiM { vec4 xiM[]; };
layout(std430, binding = FT_SSBO_XI_N) readonly buffer DsXiN { vec4 xiN[]; };
layout(std430, binding = FT_SSBO_XI_PSI_M) readonly buffer DsPsiM { vec4 psiM[]; };
layout(std430, binding = FT_SSBO_XI_PSI_N) readonly buffer DsPsiN { vec4 psiN[]; };
layout(std430, binding = FT_SSBO_XI_REQUESTS) readonly buffer DsRequests { vec4 requests[]; };  // (u, v, θ, φ)
layout(std430, binding = FT_SSBO_XI_RESULTS) writeonly buffer DsResults { vec4 results[]; };
uniform uint requestCount;
uniform uint groupsX;

void main() {
  uint r = flatInvocationIndex(groupsX, FT_WG_XI);
  if (r >= requestCount) return;
  vec4 q = requests[r];
  XiLookup l = ftXiLookup(dsLayout, q.xy, q.zw);
  // Per corner log ξ + log Ψ first: the two run to ±15 and cancel, and a
  // float sum of the parts would keep their rounding (common/ds_correction.h).
  // precise: summed as the CPU sums them (reference/ds_correction.cpp), not
  // fused into w·x + m, so the two sides differ by GLSL's exp alone.
  precise vec3 m = vec3(0.0), n = vec3(0.0);
  for (int c = 0; c < 8; ++c) {
    float wm = ftXiCornerWeight(l, l.theta, c), wn = ftXiCornerWeight(l, l.phi, c);
    uint im = ftXiCorner(dsLayout, l, l.theta, c), iN = ftXiCorner(dsLayout, l, l.phi, c);
#ifdef FT_FAULT_XI_GPU_PSI_N_FROM_M
    vec3 psiNCorner = psiM[iN].rgb;  // Ψ_N read from the Ψ_M texture (GPU only)
#else
    vec3 psiNCorner = psiN[iN].rgb;
#endif
    m += wm * (xiM[im].rgb + psiM[im].rgb);
    n += wn * (xiN[iN].rgb + psiNCorner);
  }
  results[r] = vec4(ftXiDecode(m + n), 0.0);
}
