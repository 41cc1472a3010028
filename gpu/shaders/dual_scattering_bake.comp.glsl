// The dual-scattering table of common/dual_scattering.h (DualScatteringGpu::bakeTable):
// one invocation per texel θ_k integrates the four lobe integrals
//   a_{H,p}(θ_k) = 2 ∫_{φ-range of H} ∫ f_p(θ_k, θ_o, φ) cos²θ_o dθ_o dφ
// in float, θ_o by the midpoint rule (`steps` over [−π/2, π/2], summed
// pairwise), φ by 20-point Gauss–Legendre on each quarter (bcsdf.h's nodes),
// and derives the table's rows from them with ftDsTexelFromLobes.
#include "common/constants.h"
#include "common/dual_scattering.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_DS) in;
layout(std430, binding = FT_SSBO_DS_INPUT) readonly buffer DsInput { FabricParams fabric; };
// Per texel: the FT_DS_ROWS rows of the table, then a_{f,R}, a_{f,TT}, a_{b,R}, a_{b,TT}.
layout(std430, binding = FT_SSBO_DS_OUTPUT) writeonly buffer DsOutput { vec4 results[]; };
uniform uint groupsX;
uniform uint texels;
uniform uint steps;

// ∫ over a φ range of the two integrands at θ_o: 20-point Gauss–Legendre.
void phiIntegral(vec2 range, float theta, float thetaO, vec2 z, out vec3 r, out vec3 tt) {
  float c = 0.5 * (range.x + range.y), h = 0.5 * (range.y - range.x);
  r = vec3(0.0);
  tt = vec3(0.0);
  for (int j = 0; j < 10; ++j) {
    float d = h * kFtGaussLegendre20X[j], w = h * kFtGaussLegendre20W[j];
    r += w * (ftDsIntegrandR(fabric, theta, thetaO, c - d, z.x) + ftDsIntegrandR(fabric, theta, thetaO, c + d, z.x));
#ifdef FT_FAULT_DS_GPU_BAKE_PHI_MIRROR
    // Both nodes taken on one side of the range's centre (GPU only): exact for R, wrong for TT.
    tt += w * (2.0 * ftDsIntegrandTT(fabric, theta, thetaO, c + d, z.y));
#else
    tt += w * (ftDsIntegrandTT(fabric, theta, thetaO, c - d, z.y) + ftDsIntegrandTT(fabric, theta, thetaO, c + d, z.y));
#endif
  }
}

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_DS);
  if (k >= texels) return;
  float theta = ftDsTexelAngle(int(k), int(texels));
  vec2 z = ftLobeNorms(fabric, theta);
  float h = FT_PI / float(steps);
  // Pairwise sums (a binary counter: partial[l] holds 2^l terms), so rounding
  // grows with log2(steps), not steps. 16 levels: steps < 65,536.
  vec3 pFR[16], pFTT[16], pBR[16], pBTT[16];
  for (uint s = 0u; s < steps; ++s) {
    float thetaO = -0.5 * FT_PI + (float(s) + 0.5) * h;
    vec3 fR, fTT, bR, bTT;
    phiIntegral(ftDsForwardPhiRange(), theta, thetaO, z, fR, fTT);
    phiIntegral(ftDsBackwardPhiRange(), theta, thetaO, z, bR, bTT);
    fR *= h;
    fTT *= h;
    bR *= h;
    bTT *= h;
    uint level = 0u;
    for (uint n = s; (n & 1u) != 0u; n >>= 1u) {
      fR += pFR[level];
      fTT += pFTT[level];
      bR += pBR[level];
      bTT += pBTT[level];
      ++level;
    }
    pFR[level] = fR;
    pFTT[level] = fTT;
    pBR[level] = bR;
    pBTT[level] = bTT;
  }
  vec3 aFR = vec3(0.0), aFTT = vec3(0.0), aBR = vec3(0.0), aBTT = vec3(0.0);
  for (uint level = 0u; level < 16u; ++level)
    if ((steps & (1u << level)) != 0u) {
      aFR += pFR[level];
      aFTT += pFTT[level];
      aBR += pBR[level];
      aBTT += pBTT[level];
    }
  DsTexel t = ftDsTexelFromLobes(fabric, aFR, aFTT, aBR, aBTT);
  uint o = k * uint(FT_DS_ROWS + 4);
  results[o + uint(FT_DS_ROW_A_F)] = vec4(t.aF, 0.0);
  results[o + uint(FT_DS_ROW_A_B)] = vec4(t.aB, 0.0);
  results[o + uint(FT_DS_ROW_ALPHA_F)] = vec4(t.alphaF, 0.0);
  results[o + uint(FT_DS_ROW_ALPHA_B)] = vec4(t.alphaB, 0.0);
  results[o + uint(FT_DS_ROW_BETA_F2)] = vec4(t.betaF2, 0.0);
  results[o + uint(FT_DS_ROW_BETA_B2)] = vec4(t.betaB2, 0.0);
  results[o + uint(FT_DS_ROW_AB)] = vec4(t.ab, 0.0);
  results[o + uint(FT_DS_ROW_DELTA_B)] = vec4(t.deltaB, 0.0);
  results[o + uint(FT_DS_ROW_SIGMA_B2)] = vec4(t.sigmaB2, 0.0);
  o += uint(FT_DS_ROWS);
  results[o] = vec4(aFR, 0.0);
  results[o + 1u] = vec4(aFTT, 0.0);
  results[o + 2u] = vec4(aBR, 0.0);
  results[o + 3u] = vec4(aBTT, 0.0);
}
