// GPU accumulation of the IIRTF estimator of Khungurn et al. 2017 (004) §4.2c
// over a CPU-produced sample list (notes-appearance §7.5; common/
// prt_multiple_scattering.h, PrtMultipleScatteringGpu::accumulateIirtf).
// Pass 0, one invocation per sample: Y(ω0) then Y(ω1) (72 floats).
// Pass 1, one invocation per (chunk, entry j1·36 + j0): Σ over the chunk's
// samples of T Y_j1(ω1) Y_j0(ω0), rgb (float[chunk][1296][4]); chunks of
// FT_MS_ACC_CHUNK keep an invocation's loop under llvmpipe's 65,535 iterations.
#include "common/constants.h"
#include "common/prt_multiple_scattering.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_MS) in;
layout(std140, binding = FT_UBO_PRT_MS) uniform PrtMsAccumBlock { PrtMsAccumParams acc; };
layout(std430, binding = FT_SSBO_PRT_REQUESTS) readonly buffer PrtMsSamples { PrtMsSample samples[]; };
layout(std430, binding = FT_SSBO_PRT_MS_TABLES) readonly buffer PrtMsY { float ys[]; };
layout(std430, binding = FT_SSBO_PRT_RESULTS) writeonly buffer PrtMsAccOut { float outv[]; };
uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint item = flatInvocationIndex(groupsX, FT_WG_PRT_MS);
  if (item >= itemCount) return;
  if (acc.sizes.x == 0u) {
    ShCoeffs y0 = shEval(samples[item].w0.xyz), y1 = shEval(samples[item].w1.xyz);
    for (int j = 0; j < FT_SH_COEFFS; ++j) {
      outv[item * 72u + uint(j)] = y0.c[j];
      outv[item * 72u + 36u + uint(j)] = y1.c[j];
    }
    return;
  }
  const uint entries = uint(FT_SH_COEFFS * FT_SH_COEFFS);
  uint chunk = item / entries, e = item % entries;
  uint j1 = e / uint(FT_SH_COEFFS), j0 = e % uint(FT_SH_COEFFS);
  uint first = chunk * uint(FT_MS_ACC_CHUNK), last = min(acc.sizes.y, first + uint(FT_MS_ACC_CHUNK));
  vec3 s = vec3(0.0f);
  for (uint i = first; i < last; ++i) {
#ifdef FT_FAULT_MS_ACC_SWAPPED_DIRECTIONS
    float yy = ys[i * 72u + 36u + j0] * ys[i * 72u + j1];  // planted: Y_j0(ω1) Y_j1(ω0), the roles swapped
#else
    float yy = ys[i * 72u + 36u + j1] * ys[i * 72u + j0];
#endif
    s += samples[i].t.xyz * yy;
  }
  outv[item * 4u] = s.x;
  outv[item * 4u + 1u] = s.y;
  outv[item * 4u + 2u] = s.z;
  outv[item * 4u + 3u] = 0.0f;
}
