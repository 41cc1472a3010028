// The per-frame dual-scattering function of common/dual_scattering.h on a
// list of requests (DualScatteringGpu::evaluate), one invocation each: the
// table read at θ_d (ftDsLookup, two texels, ftDsMix), then ftDsEvaluate.
#include "common/constants.h"
#include "common/dual_scattering.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_DS) in;
// Per request: (θ_i, θ_o, φ, 0), (V, n, 0, 0).
layout(std430, binding = FT_SSBO_DS_INPUT) readonly buffer DsInput {
  FabricParams fabric;
  vec4 requests[];
};
layout(std430, binding = FT_SSBO_DS_TABLE) readonly buffer DsTable { vec4 table[]; };
// Per request: F, f_back^dir, f_back^sc, f_s^sc, T_f, σ̄_f² (rgb).
layout(std430, binding = FT_SSBO_DS_OUTPUT) writeonly buffer DsOutput { vec4 results[]; };
uniform uint groupsX;
uniform uint requestCount;
uniform uint texels;

DsTexel texelOf(int k) {
  int o = k * FT_DS_ROWS;
  DsTexel t;
  t.aF = table[o + FT_DS_ROW_A_F].xyz;
  t.aB = table[o + FT_DS_ROW_A_B].xyz;
  t.alphaF = table[o + FT_DS_ROW_ALPHA_F].xyz;
  t.alphaB = table[o + FT_DS_ROW_ALPHA_B].xyz;
  t.betaF2 = table[o + FT_DS_ROW_BETA_F2].xyz;
  t.betaB2 = table[o + FT_DS_ROW_BETA_B2].xyz;
  t.ab = table[o + FT_DS_ROW_AB].xyz;
  t.deltaB = table[o + FT_DS_ROW_DELTA_B].xyz;
  t.sigmaB2 = table[o + FT_DS_ROW_SIGMA_B2].xyz;
  return t;
}

void main() {
  uint j = flatInvocationIndex(groupsX, FT_WG_DS);
  if (j >= requestCount) return;
  FiberAngles a;
  a.thetaI = requests[2u * j].x;
  a.thetaO = requests[2u * j].y;
  a.phi = requests[2u * j].z;
#ifdef FT_FAULT_DS_GPU_LOOKUP_THETA_I
  float thetaLookup = a.thetaI;  // the table read at θ_i instead of θ_d (GPU only)
#else
  float thetaLookup = ftDsThetaD(a);
#endif
  vec3 l = ftDsLookup(thetaLookup, int(texels));
  DsTexel t = ftDsMix(texelOf(int(l.x)), texelOf(int(l.y)), l.z);
  DsFrame r = ftDsEvaluate(fabric, t, a, requests[2u * j + 1u].x, requests[2u * j + 1u].y);
  uint o = 6u * j;
  results[o] = vec4(r.value, 0.0);
  results[o + 1u] = vec4(r.backDirect, 0.0);
  results[o + 2u] = vec4(r.backScattered, 0.0);
  results[o + 3u] = vec4(r.forwardScattered, 0.0);
  results[o + 4u] = vec4(r.transmittance, 0.0);
  results[o + 5u] = vec4(r.forwardVariance, 0.0);
}
