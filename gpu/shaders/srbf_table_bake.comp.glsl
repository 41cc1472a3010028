// The I_M table of 001 §4.5 eq. 15–16 (SrbfTableGpu::bake), one invocation
// per texel, by brute-force 2D quadrature over the incident direction,
// independent of the CPU's analytic reduction (reference/srbf_table.h):
//   I = ∫∫ G(ω_i) f(θ_i, θ_o, Δφ − ψ) cos θ_i · cos θ_i dψ dθ_i,
//   G = e^{λ(cos θ_i cos θ_j cos ψ + sin θ_i sin θ_j − 1)}, ψ = φ_i − φ_j,
// f from common/bcsdf.h (R and TT evaluated per node, Z once per θ_i).
//   ψ ∈ [−π, π]: 20-point Gauss–Legendre on 6 panels, the four inner ones
//     over ±min(6w_ψ, π), w_ψ = (λ cos θ_i cos θ_j)^−½ the SG's azimuthal width;
//   θ_i ∈ [−π/2, π/2]: split at −θ_o, −θ_o ± 6β_p, ±(π/2 − 6β_p) (Z's switch),
//     θ_j, θ_j ± 6/√λ; each piece in sub-panels of 20-point Gauss–Legendre no
//     wider than β_p (inside a lobe's window), 1/√λ (inside the SG's), else 0.4.
// Sums per panel (20 nodes), then over the ~30 panels.
#include "common/constants.h"
#include "common/srbf_bcsdf.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SRBF) in;
layout(std430, binding = FT_SSBO_SRBF_INPUT) readonly buffer SrbfInput { FabricParams fabric; };
layout(std430, binding = FT_SSBO_SRBF_TABLE) writeonly buffer SrbfTable { vec4 table[]; };
uniform uint groupsX;
uniform ivec4 dims;

float glNode(int i) { return i < 10 ? -kFtGaussLegendre20X[9 - i] : kFtGaussLegendre20X[i - 10]; }
float glWeight(int i) { return i < 10 ? kFtGaussLegendre20W[9 - i] : kFtGaussLegendre20W[i - 10]; }

// Node q of the 20-point rule on ψ ∈ [pa, pb]: (w G, w G N_TT(Δφ − ψ)).
vec2 psiNode(float pa, float pb, int q, float lambda, float c, float sTerm, float dphi, float kappa) {
  float plen = pb - pa;
  float psi = 0.5 * (pa + pb) + 0.5 * plen * glNode(q);
  float g = exp(lambda * (c * cos(psi) + sTerm - 1.0)) * (0.5 * plen * glWeight(q));
  return vec2(g, g * ftAzimuthalTT(dphi - psi, kappa));
}

void main() {
  uint index = flatInvocationIndex(groupsX, FT_WG_SRBF);
  if (index >= uint(ftSrbfTableSize(dims))) return;
  ivec4 k = ftSrbfTableTexel(dims, int(index));
  float thetaO = ftSrbfTableTheta(k.x, dims.x);
  float thetaJ = ftSrbfTableTheta(k.y, dims.y);
  float dphi = ftSrbfTableDeltaPhi(k.z, dims.z);
  float lambda = ftSrbfTableLambda(k.w, dims.w);
  float betaR = fabric.colorR.w, betaTT = fabric.colorTT.w, kappa = fabric.lobes.y;
  float halfPi = 0.5 * FT_PI;
  float sgWidth = 1.0 / sqrt(lambda);
  float cj = cos(thetaJ), sj = sin(thetaJ);

  float cuts[16];
  cuts[0] = -halfPi; cuts[1] = halfPi; cuts[2] = -thetaO; cuts[3] = thetaJ;
  cuts[4] = -thetaO - 6.0 * betaR; cuts[5] = -thetaO + 6.0 * betaR;
  cuts[6] = -thetaO - 6.0 * betaTT; cuts[7] = -thetaO + 6.0 * betaTT;
  cuts[8] = halfPi - 6.0 * betaR; cuts[9] = -(halfPi - 6.0 * betaR);
  cuts[10] = halfPi - 6.0 * betaTT; cuts[11] = -(halfPi - 6.0 * betaTT);
  cuts[12] = thetaJ - 6.0 * sgWidth; cuts[13] = thetaJ + 6.0 * sgWidth;
  cuts[14] = thetaJ - 2.0 * sgWidth; cuts[15] = thetaJ + 2.0 * sgWidth;
  // Panels from −π/2 upwards: each ends at the next cut or after the width
  // wanted at its start (no sort of the cuts: a scan for the next one).
  vec3 sum = vec3(0.0);
  float a = -halfPi;
  for (int guard = 0; guard < 8192 && a < halfPi; ++guard) {
    float next = halfPi;
    for (int i = 0; i < 16; ++i)
      if (cuts[i] > a + 1e-6 && cuts[i] < next) next = cuts[i];
    float m = 0.5 * (a + next), h = 0.4;
    if (abs(m + thetaO) < 6.0 * betaR) h = min(h, betaR);
    if (abs(m + thetaO) < 6.0 * betaTT) h = min(h, betaTT);
    if (abs(m - thetaJ) < 6.0 * sgWidth) h = min(h, sgWidth);
    float b = min(next, a + h);
    if (next - b < 0.25 * h) b = next;  // no sliver before a cut
    float len = b - a, c0 = 0.5 * (a + b);
    vec3 panel = vec3(0.0);
    {
      for (int n = 0; n < 20; ++n) {
        float thetaI = c0 + 0.5 * len * glNode(n);
        float wTheta = 0.5 * len * glWeight(n);
        vec2 z = ftLobeNorms(fabric, ftLobeNormAngle(FiberAngles(thetaI, thetaO, FT_PI)));
        vec3 fR = ftBcsdfRNormed(fabric, FiberAngles(thetaI, thetaO, FT_PI), z.x);
        vec3 ttBase = ftBcsdfTTNormed(fabric, FiberAngles(thetaI, thetaO, FT_PI), z.y) / ftAzimuthalTT(FT_PI, kappa);
        float ci = cos(thetaI), si = sin(thetaI);
        float c = ci * cj, sTerm = si * sj;
        float edge = FT_PI;
        if (lambda * c > 1e-6) edge = min(FT_PI, 6.0 / sqrt(lambda * c));
        // The six ψ panels written out (a loop over them nested in the node
        // loops would pass gallivm's 65,535-iteration limit, which counts a
        // loop's iterations over the whole invocation: docs/srbf.md).
        vec2 sums = vec2(0.0);
        for (int q = 0; q < 20; ++q) {
          sums += psiNode(-FT_PI, -edge, q, lambda, c, sTerm, dphi, kappa);
          sums += psiNode(-edge, -0.5 * edge, q, lambda, c, sTerm, dphi, kappa);
          sums += psiNode(-0.5 * edge, 0.0, q, lambda, c, sTerm, dphi, kappa);
          sums += psiNode(0.0, 0.5 * edge, q, lambda, c, sTerm, dphi, kappa);
          sums += psiNode(0.5 * edge, edge, q, lambda, c, sTerm, dphi, kappa);
          sums += psiNode(edge, FT_PI, q, lambda, c, sTerm, dphi, kappa);
        }
        float sumR = sums.x, sumTT = sums.y;
        panel += (fR * sumR + ttBase * sumTT) * (ftSrbfCosine(thetaI) * ci * wTheta);
      }
    }
    sum += panel;
    a = b;
  }
  table[index] = vec4(sum, 0.0);
}
