// prt_single_scattering.h — single scattering of the fabric PRT of Khungurn
// et al. 2017 (004) §5.2 and App. A, shared by the CPU reference (double,
// reference/prt_single_scattering.h), its GPU twin (float,
// gpu/prt_single_scattering_gpu.h, prt_single_scattering.comp.glsl) and a
// later deferred PRT frame (docs/prt-single-scattering.md):
//   * directional light (004 §5.2.1): L = V_glo [d_k(ω_d) > 0] S(ω_d, ω_o) cos θ_d;
//   * SG light G(ω; ξ, λ)/M(λ) (004 eq. 1), V_glo scaling its power:
//       λ ≤ 100  sum of SGs: Σ_q w_q Γ(ξ̂ˢᵘᵐ_q, ‖ξˢᵘᵐ_q‖, ω_o)/(M(λ_svf) e^{λ_svf + λ − ‖ξˢᵘᵐ_q‖}),
//                ξˢᵘᵐ_q = λ_svf ξ_k,q + λ ξ (004 §5.2.2, product of two SGs);
//       λ ≥ 200  SSDF + erf: Ṽ_loc Γ(ξ, λ, ω_o), Ṽ_loc = ½(erf(√(λ/2) d_k(ξ)) + 1);
//       between  linear in λ, weight (λ − 100)/100 on the SSDF result;
//     all divided by M(λ) (the light is normalised);
//   * Γ of 004 eq. 2 with App. A's B_R, B_TT; the garbled parts read as
//     notes-appearance §6.1 [derived]: a_p = exp(−β_p⁻² λ (θ_o + θ′)²/(2(β_p⁻² + λ))),
//     θ_p = (−β_p⁻² θ_o + λ θ′)/(β_p⁻² + λ), λ_p = β_p⁻²/2 + λ/2, F_R Schlick "+",
//     the Bessel argument λ cos θ′ cos θ_p; everything where λ appears in log
//     space (one exponent per lobe: a_p, the sum-of-SGs renormalisation, the
//     TT Bessel ratio): e^{λ_svf + λ − ‖ξˢᵘᵐ‖} reaches e^{256}, I0 overflows
//     float at 88;
//   * the tables 𝒢(μ; β_p⁻²/2) of App. A per fabric and lobe. 𝒢(−θ; β⁻²/2) is
//     bcsdf.h's lobe normaliser Z(θ) = ∫ g(x + θ; β) cos²x dx, so the table is
//     indexed by θ: texel k at θ_k = −π/2 + kπ/(N − 1), N = 1024, linear
//     interpolation [F notes §6.8]; row (2·fabric + lobe), lobe 0 R, 1 TT.
// Fiber frame (004 §4.3, notes §6.1): x = the segment direction t, y such that
// ω_o lies in the xy-plane (ϕ_o = 0); θ = atan2(ω·t, |ω − (ω·t)t|), ϕ = the
// azimuth about t from ω_o's perpendicular part, in [0, π] (Γ depends on cos ϕ).
//
// Precision-generic (as common/knit_solver.h): the part after the layouts has
// no include guard and uses kreal/kvec3/KR(x) and, from its includer,
//   FT_PRT_SS_ERF(x), FT_PRT_SS_I0E(x) (= I0(x)e^{−x}), FT_PRT_SS_ATAN2(y, x),
//   FT_PRT_SS_TABLE_DECL / FT_PRT_SS_TABLE_PASS: the table parameter (C++: a
//   `const kreal* prtSsTable` argument; GLSL: nothing — the shader declares the
//   buffer `prtSsTable[]` before including this file).
// GLSL gets float defaults below; C++ instantiates it in
// reference/prt_single_scattering.h (ft::prtss64 double, ft::prtss32 float),
// defining FT_PRT_SS_INSTANTIATE.
#ifndef FT_PRT_SINGLE_SCATTERING_LAYOUT_H
#define FT_PRT_SINGLE_SCATTERING_LAYOUT_H
#include "prelude.h"
#include "bcsdf.h"
#include "segment_visibility.h"
#include "special_fn.h"
#include "srbf.h"

// Planted faults (validation/faults.def). The shared one runs on both sides:
// a_p without the 2 of its denominator (the garbled text's reading).
#ifdef __cplusplus
namespace ft {
inline bool ftFaultSsARNoTwo = false;
}
#define FT_FAULT_SS_A_R_NO_TWO_ON ::ft::ftFaultSsARNoTwo
#else
#if defined(FT_FAULT_SS_A_R_NO_TWO)
#define FT_FAULT_SS_A_R_NO_TWO_ON true
#else
#define FT_FAULT_SS_A_R_NO_TWO_ON false
#endif
#endif

#define FT_PRT_SS_TABLE_SIZE 1024   // texels of 𝒢 per fabric and lobe
#define FT_PRT_SS_MAX_FABRICS 8
#define FT_PRT_SS_LAMBDA_SOSG 100.0f  // λ ≤ this: sum of SGs only (004 §5.2.2)
#define FT_PRT_SS_LAMBDA_SSDF 200.0f  // λ ≥ this: SSDF + erf only
// A sum-of-SGs term whose renormalisation exponent λ_svf + λ − ‖ξˢᵘᵐ‖ exceeds
// this is skipped: e^{−80} ≈ 2e-35 of Γ, below float's normal range.
#define FT_PRT_SS_SKIP_EXPONENT 80.0f

FT_NAMESPACE_BEGIN

// The GPU twin's parameters (std140 UBO FT_UBO_PRT_SS).
struct PrtSsParams {
  FabricParams fabrics[FT_PRT_SS_MAX_FABRICS];
  uint count;        // texels (mode 0) or requests (mode 1)
  uint mode;         // 0 bake the 𝒢 tables, 1 evaluate requests
  uint fabricCount;
  uint axes;         // Q of the weights buffer
  float lambdaSvf;   // λ_svf (004 §4.1: 128)
  uint tableSize;    // N
  uint pad0, pad1;
};
FT_ASSERT_OFFSET(PrtSsParams, count, 384)
FT_ASSERT_SIZE(PrtSsParams, 416)

// One shading query (std430, FT_SSBO_PRT_REQUESTS); the result is an rgb vec4.
struct PrtSsRequest {
  vec4 tangent;   // xyz the segment's unit direction t, w fabric index
  vec4 outgoing;  // xyz unit ω_o (towards the eye), w V_glo
  vec4 light;     // xyz unit ξ (SG axis) or ω_d (towards the light), w λ (≤ 0: directional)
  vec4 segment;   // x d_k(ξ) (decoded SSDF at the light axis, rad), y R_k angle, z weights row, w unused
};
FT_ASSERT_SIZE(PrtSsRequest, 64)

// Angle of 𝒢 texel k of n (θ; the table holds 𝒢(−θ; β⁻²/2) = Z(θ)).
FT_FUNC float ftPrtSsTexelAngle(int k, int n) { return -0.5f * FT_PI + float(k) * FT_PI / float(n - 1); }

// The GPU bake of a texel: bcsdf.h's Z (closed form inside, 20-point
// Gauss–Legendre over the clipped ±6β window at the ends), float.
FT_FUNC float ftPrtSsTexelGpu(int k, int n, float beta) { return ftLongitudinalNorm(ftPrtSsTexelAngle(k, n), beta); }

FT_NAMESPACE_END
#endif  // FT_PRT_SINGLE_SCATTERING_LAYOUT_H

#if !defined(__cplusplus) || defined(FT_PRT_SS_INSTANTIATE)
#ifndef __cplusplus
#ifndef kreal
#define kreal float
#define kvec2 vec2
#define kvec3 vec3
#define kvec4 vec4
#define KR(x) float(x)
#endif
#define FT_PRT_SS_ERF(x) ftErf(x)
#define FT_PRT_SS_I0E(x) ftBesselI0e(x)
#define FT_PRT_SS_ATAN2(y, x) ftAtan2(y, x)
#define FT_PRT_SS_TABLE_DECL
#define FT_PRT_SS_TABLE_PASS
#endif

// 𝒢(−θ; β_row⁻²/2) = Z(θ) from row `row` of the table, linear between texels.
FT_FUNC kreal ftPrtSsTableZ(FT_PRT_SS_TABLE_DECL int row, kreal theta) {
  int n = FT_PRT_SS_TABLE_SIZE;
  kreal u = clamp((theta + KR(0.5) * KR(FT_PI)) / KR(FT_PI) * KR(n - 1), KR(0.0), KR(n - 1));
  int k0 = min(int(floor(u)), n - 2);
  kreal t = u - kreal(k0);
  return mix(kreal(prtSsTable[row * n + k0]), kreal(prtSsTable[row * n + k0 + 1]), t);
}

// Longitudinal angle of ω about the unit tangent t (well conditioned at the poles).
FT_FUNC kreal ftPrtSsTheta(kvec3 t, kvec3 w) {
  kreal s = dot(w, t);
  kvec3 p = w - s * t;
  return FT_PRT_SS_ATAN2(s, sqrt(dot(p, p)));
}

// Azimuth ϕ ∈ [0, π] of ω about t, measured from ω_o (ϕ_o = 0); 0 when either
// is parallel to t (where the azimuth is undefined and cos θ vanishes).
FT_FUNC kreal ftPrtSsPhi(kvec3 t, kvec3 w, kvec3 wo) {
  kvec3 pw = w - dot(w, t) * t;
  kvec3 po = wo - dot(wo, t) * t;
  if (dot(pw, pw) * dot(po, po) <= KR(1e-24)) return KR(0.0);
  return FT_PRT_SS_ATAN2(length(cross(pw, po)), dot(pw, po));
}

// Γ(ξ, λ, ω_o) of 004 eq. 2 times e^{logScale} (the caller's renormalisation,
// folded into each lobe's one exponent), ξ at fiber-frame angles (θ′, ϕ′),
// for fabric `fabric` (table rows 2·fabric, 2·fabric + 1). Valid for λ ≥ 100.
FT_FUNC kvec3 ftPrtSsGamma(FT_PRT_SS_TABLE_DECL FabricParams p, int fabric, kreal thetaO, kreal thetaX, kreal phiX,
                           kreal lambda, kreal logScale) {
  kreal halfPi = KR(0.5) * KR(FT_PI);
  kreal sqrtTwoPi = KR(2.50662827463100050);
  kreal cosX = cos(thetaX);
  kvec3 result = kvec3(KR(0.0));
  for (int lobe = 0; lobe < 2; ++lobe) {
    kreal beta = lobe == 0 ? kreal(p.colorR.w) : kreal(p.colorTT.w);
    kreal s = KR(1.0) / (beta * beta);  // β⁻²
    kreal lambdaP = KR(0.5) * (s + lambda);
    kreal thetaP = (-s * thetaO + lambda * thetaX) / (s + lambda);
    kreal d = thetaO + thetaX;
    // log a_p; the planted fault drops the 2 of the denominator.
    kreal logA = -s * lambda * d * d / ((FT_FAULT_SS_A_R_NO_TWO_ON ? KR(1.0) : KR(2.0)) * (s + lambda));
    kreal r = sqrt(lambdaP);
    kreal erfSpan = FT_PRT_SS_ERF(r * (halfPi - thetaP)) - FT_PRT_SS_ERF(r * (-halfPi - thetaP));
    kreal integral = KR(0.5) * sqrt(KR(FT_PI) / lambdaP) * erfSpan;
    kreal cosP = cos(thetaP);
    kreal z = max(ftPrtSsTableZ(FT_PRT_SS_TABLE_PASS 2 * fabric + lobe, thetaP), KR(1e-30));
    kreal lobeScale = integral * cosP * cosP / (sqrtTwoPi * beta * z);
    kvec3 fresnel = kvec3(ftFiberFresnel(vec3(p.colorR), float(thetaP)));
    // B's Bessel part: the SG's azimuthal width on the cone, λ cos θ′ cos θ_p.
    kreal kappaSg = max(lambda * cosX * cosP, KR(0.0));
    if (lobe == 0) {
      // B_R: I0(κ_sg)/e^{κ_sg} = I0e(κ_sg).
#ifdef FT_FAULT_SS_I0_UNSCALED
      kreal bessel = (FT_PRT_SS_I0E(kappaSg) * exp(kappaSg)) / exp(kappaSg);  // planted: I0 and e^x apart (GPU)
#else
      kreal bessel = FT_PRT_SS_I0E(kappaSg);
#endif
      result += fresnel * (exp(logA + logScale) * lobeScale * bessel);
    } else {
      // B_TT: I0(λ_m)/(e^{κ_sg} I0(κ)), κ = γ_TT⁻², λ_m² = κ² + κ_sg² − 2κκ_sg cos ϕ′
      // = I0e(λ_m)/I0e(κ) · e^{λ_m − κ_sg − κ} (exponent ≤ 0).
      // λ_m − κ_sg as (κ² − 2κκ_sg cos ϕ′)/(λ_m + κ_sg): no cancellation of
      // two numbers near 10⁴ in float.
      kreal kappa = kreal(p.lobes.y);
      kreal kappaTerm = kappa * kappa - KR(2.0) * kappa * kappaSg * cos(phiX);
      kreal lm = sqrt(max(kappaSg * kappaSg + kappaTerm, KR(0.0)));
      kreal lmMinusSg = lm + kappaSg > KR(0.0) ? kappaTerm / (lm + kappaSg) : KR(0.0);
#ifdef FT_FAULT_SS_I0_UNSCALED
      kreal bessel = (FT_PRT_SS_I0E(lm) * exp(lm)) / (exp(kappaSg) * FT_PRT_SS_I0E(kappa) * exp(kappa)) *
                     exp(logA + logScale);  // planted: the factors apart (GPU)
#else
      kreal bessel = FT_PRT_SS_I0E(lm) / FT_PRT_SS_I0E(kappa) * exp(logA + logScale + lmMinusSg - kappa);
#endif
      kvec3 colorTT = kvec3(KR(p.colorTT.x), KR(p.colorTT.y), KR(p.colorTT.z));
      result += (kvec3(KR(1.0)) - fresnel) * colorTT * (lobeScale * bessel);
    }
  }
  return result;
}

// Γ at a light axis ξ (any length > 0 is normalised), from directions.
FT_FUNC kvec3 ftPrtSsGammaAt(FT_PRT_SS_TABLE_DECL FabricParams p, int fabric, kvec3 t, kvec3 wo, kvec3 xi,
                             kreal lambda, kreal logScale) {
  return ftPrtSsGamma(FT_PRT_SS_TABLE_PASS p, fabric, ftPrtSsTheta(t, wo), ftPrtSsTheta(t, xi), ftPrtSsPhi(t, xi, wo),
                      lambda, logScale);
}

// Ṽ_loc(x, ξ) = ½(erf(√(λ/2) d_k(ξ)) + 1) (004 §5.2.2; the formula's σ = 1/√λ).
FT_FUNC kreal ftPrtSsSmoothVisibility(kreal ssdf, kreal lambda) {
  return KR(0.5) * (FT_PRT_SS_ERF(sqrt(KR(0.5) * lambda) * ssdf) + KR(1.0));
}

// One term of the sum of SGs (004 §5.2.2): w_q Γ(ξ̂ˢᵘᵐ, ‖ξˢᵘᵐ‖, ω_o)/(M(λ_svf)
// e^{λ_svf + λ − ‖ξˢᵘᵐ‖}), the SG axis ξ_k,q = `axis`; not yet divided by M(λ).
FT_FUNC kvec3 ftPrtSsSosgTerm(FT_PRT_SS_TABLE_DECL FabricParams p, int fabric, kvec3 t, kvec3 wo, kvec3 xi,
                              kreal lambda, kreal weight, kvec3 axis, kreal lambdaSvf) {
  kvec3 sum = lambdaSvf * axis + lambda * xi;
  kreal norm = length(sum);
  // ‖ξˢᵘᵐ‖ − λ_svf − λ = −λ_svf λ |ξ_q − ξ|²/(‖ξˢᵘᵐ‖ + λ_svf + λ) (≤ 0), without
  // the cancellation of the difference (|ξ_q − ξ|² = 2(1 − ξ_q·ξ) for unit axes).
  kvec3 d = axis - xi;
  kreal logRenorm = -lambdaSvf * lambda * dot(d, d) / (norm + lambdaSvf + lambda);
  if (!(weight > KR(0.0)) || -logRenorm > KR(FT_PRT_SS_SKIP_EXPONENT)) return kvec3(KR(0.0));
#ifdef FT_FAULT_SS_SOSG_NO_RENORM
  logRenorm = KR(0.0);  // planted: 1/e^{λ_svf + λ − ‖ξˢᵘᵐ‖} dropped (GPU)
#endif
  kreal m = kreal(ftSrbfIntegral(float(lambdaSvf)));
  return (weight / m) * ftPrtSsGammaAt(FT_PRT_SS_TABLE_PASS p, fabric, t, wo, sum / norm, norm, logRenorm);
}

// Blend weight on the SSDF result (004 §5.2.2): 0 for λ ≤ 100, 1 for λ ≥ 200.
FT_FUNC kreal ftPrtSsBlendWeight(kreal lambda) {
  return clamp((lambda - KR(FT_PRT_SS_LAMBDA_SOSG)) / KR(FT_PRT_SS_LAMBDA_SSDF - FT_PRT_SS_LAMBDA_SOSG), KR(0.0), KR(1.0));
}

// The two branches' blend (weight ftPrtSsBlendWeight on the SSDF result).
FT_FUNC kvec3 ftPrtSsBlend(kvec3 sosg, kvec3 ssdf, kreal lambda) {
  kreal w = ftPrtSsBlendWeight(lambda);
#ifdef FT_FAULT_SS_BLEND_REVERSED
  w = KR(1.0) - w;  // planted: the weight (λ − 100)/100 on the sum of SGs (GPU)
#endif
  return (KR(1.0) - w) * sosg + w * ssdf;
}

// Radiance of one shading point under the normalised SG light G(ω; ξ, λ)/M(λ)
// (004 eq. 1 with V_glo scaling its power): t the segment's unit direction,
// ξ and ω_o unit, ssdf = d_k(ξ), weights/axes/angle the segment's sum of SGs
// (w_k,q, Q, R_k), λ_svf its sharpness.
FT_FUNC kvec3 ftPrtSsSgLight(FT_PRT_SS_TABLE_DECL FabricParams p, int fabric, kvec3 t, kvec3 wo, kvec3 xi,
                             kreal lambda, kreal ssdf, kreal weights[FT_SVF_MAX_AXES], int axes, kreal angle,
                             kreal lambdaSvf, kreal vGlo) {
  kreal w = ftPrtSsBlendWeight(lambda);
  kvec3 sosg = kvec3(KR(0.0));
  kvec3 sharp = kvec3(KR(0.0));
#ifndef FT_FAULT_SS_BLEND_REVERSED
  if (w < KR(1.0))
#endif
  {
    for (int q = 0; q < axes; ++q) {
      kvec3 axis = kvec3(ftSvfAxis(q + 1, axes, float(angle)));
      sosg += ftPrtSsSosgTerm(FT_PRT_SS_TABLE_PASS p, fabric, t, wo, xi, lambda, weights[q], axis, lambdaSvf);
    }
  }
#ifndef FT_FAULT_SS_BLEND_REVERSED
  if (w > KR(0.0))
#endif
    sharp = ftPrtSsSmoothVisibility(ssdf, lambda) * ftPrtSsGammaAt(FT_PRT_SS_TABLE_PASS p, fabric, t, wo, xi, lambda, KR(0.0));
  kreal m = kreal(ftSrbfIntegral(float(lambda)));
  return (vGlo / m) * ftPrtSsBlend(sosg, sharp, lambda);
}

// Radiance under a directional light of unit radiance from ω_d (004 §5.2.1):
// V_glo [d_k(ω_d) > 0] S(ω_d, ω_o) cos θ_d, S the BCSDF of bcsdf.h (float,
// exact lobe normalisation).
FT_FUNC kvec3 ftPrtSsDirectional(FabricParams p, kvec3 t, kvec3 wo, kvec3 wd, kreal ssdf, kreal vGlo) {
  if (!(ssdf > KR(0.0))) return kvec3(KR(0.0));
  FiberAngles a = ftFiberAngles(vec3(t), vec3(wd), vec3(wo));
  return kvec3(ftBcsdf(p, a)) * (vGlo * kreal(cos(a.thetaI)));
}
#endif  // instantiation
