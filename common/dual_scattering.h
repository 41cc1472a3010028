// dual_scattering.h — the dual-scattering approximation of Zinke et al. 2008
// ("Dual scattering approximation for fast multiple scattering in hair", ACM
// TOG 27(3) 32), as Huang et al. 2025 (001) §4.1 eq. 8 uses it:
// Ψ_DS = Ψ_G (1 + Ψ_L). Shared by the CPU bake (reference/dual_scattering.cpp),
// the GPU bake (gpu/shaders/dual_scattering_bake.comp.glsl), the GPU per-frame
// evaluation and, later, the ξ bake of notes-rendering A7 (docs/dual-scattering.md).
// Zinke's equation numbers are those of notes-rendering A6 (checked there
// against a public pbrt-v3 reimplementation; the paper is not in the given texts).
//
// Conventions: bcsdf.h's. φ ∈ [0, π] (f is even in φ), φ = 0 backward, TT
// peaks at φ = π. The forward half is H_f = {cos φ < 0} = φ ∈ [π/2, π], the
// backward half H_b = φ ∈ [0, π/2]; each is half of a full-circle half, so the
// integrals over them carry a factor 2.
//
// Part 1, the bake: per texel θ (the incident longitudinal angle) and RGB channel
//   a_{f,p}(θ) = ∫_{H_f} ∫ f_p(θ, θ_o, φ) cos²θ_o dθ_o dφ   (Zinke eq. 6; H_b: a_{b,p}, eq. 12)
// for p ∈ {R, TT}, then ā = Σ_p a_p, ᾱ = Σ_p a_p α_p / ā, β̄² = Σ_p a_p β_p² / ā
// (β_p in Zinke's θ_h units: Khungurn lobes are Gaussians in θ_i + θ_o = 2θ_h,
// so β^Z = β/2; this BCSDF has no shifts: α_p = 0), and A_b (eq. 14), Δ_b
// (eq. 16), σ̄_b² (eq. 17 squared). The table: FT_DS_TABLE_SIZE texels at
// θ_k = −π/2 + (k + ½)π/N, FT_DS_ROWS vec4 (rgb, w unused) per texel, texel-major.
//
// Part 2, per frame (one directional light): given the table's values at θ_d,
// the visibility fraction V and the number n of fibers crossed towards the
// light (notes A6 "Per frame"):
//   T_f = d_f ā_f^n,  σ̄_f² = n β̄_f²
//   f_back^dir = 2 A_b g(θ_h − Δ_b; σ̄_b²) / (π cos²θ_d),  f_back^sc: variance σ̄_b² + σ̄_f²
//   f_s^sc = Σ_p A_p M_p^G N_p^G
//   F = V (f + d_b f_back^dir) + (1 − V) T_f (f_s^sc + π d_b f_back^sc),  L_o = L_d F cos θ_i
// and the runtime expression of A7, f + k_fly d_b f_back^dir (ftDsRuntime).
#ifndef FT_DUAL_SCATTERING_H
#define FT_DUAL_SCATTERING_H
#include "bcsdf.h"

// Planted faults (validation/faults.def), all shared: a run-time switch in
// C++, a define in GLSL.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultDsAbDenominator = false;
inline bool ftFaultDsForwardVariance = false;
inline bool ftFaultDsHemispheresSwapped = false;
inline bool ftFaultDsBetaThetaO = false;
}
#define FT_FAULT_DS_AB_DENOMINATOR_ON ::ft::ftFaultDsAbDenominator
#define FT_FAULT_DS_FORWARD_VARIANCE_ON ::ft::ftFaultDsForwardVariance
#define FT_FAULT_DS_HEMISPHERES_SWAPPED_ON ::ft::ftFaultDsHemispheresSwapped
#define FT_FAULT_DS_BETA_THETA_O_ON ::ft::ftFaultDsBetaThetaO
namespace ft {
using glm::exp2;
using glm::log2;
}
#else
#if defined(FT_FAULT_DS_AB_DENOMINATOR)
#define FT_FAULT_DS_AB_DENOMINATOR_ON true
#else
#define FT_FAULT_DS_AB_DENOMINATOR_ON false
#endif
#if defined(FT_FAULT_DS_FORWARD_VARIANCE)
#define FT_FAULT_DS_FORWARD_VARIANCE_ON true
#else
#define FT_FAULT_DS_FORWARD_VARIANCE_ON false
#endif
#if defined(FT_FAULT_DS_HEMISPHERES_SWAPPED)
#define FT_FAULT_DS_HEMISPHERES_SWAPPED_ON true
#else
#define FT_FAULT_DS_HEMISPHERES_SWAPPED_ON false
#endif
#if defined(FT_FAULT_DS_BETA_THETA_O)
#define FT_FAULT_DS_BETA_THETA_O_ON true
#else
#define FT_FAULT_DS_BETA_THETA_O_ON false
#endif
#endif

// Texels of each table over θ ∈ [−π/2, π/2] (notes A6 [F]: public
// implementations use 64–128).
#define FT_DS_TABLE_SIZE 64
// vec4 rows per texel, in this order (rgb per channel, w unused).
#define FT_DS_ROWS 9
#define FT_DS_ROW_A_F 0       // ā_f
#define FT_DS_ROW_A_B 1       // ā_b
#define FT_DS_ROW_ALPHA_F 2   // ᾱ_f (radians, θ_h units)
#define FT_DS_ROW_ALPHA_B 3   // ᾱ_b
#define FT_DS_ROW_BETA_F2 4   // β̄_f² (radians², θ_h units)
#define FT_DS_ROW_BETA_B2 5   // β̄_b²
#define FT_DS_ROW_AB 6        // A_b, eq. 14
#define FT_DS_ROW_DELTA_B 7   // Δ_b, eq. 16
#define FT_DS_ROW_SIGMA_B2 8  // σ̄_b², eq. 17 squared

FT_NAMESPACE_BEGIN

// Zinke's density factors d_f = d_b = 0.7 (notes A6).
const float kFtDsDensityForward = 0.7f;
const float kFtDsDensityBack = 0.7f;
// Longitudinal shifts α_p of the lobes: the BCSDF of bcsdf.h has none.
const float kFtDsAlphaR = 0.0f;
const float kFtDsAlphaTT = 0.0f;
// Guard of the geometric series in eq. 14 and 16: 1 − ā_f² ≥ 1e-4 (notes A6).
const float kFtDsMinOneMinusAf2 = 1e-4f;
// f_back divides by cos²θ_d, which vanishes when θ_i and θ_o are opposite
// poles (where the cos θ_i of the measure vanishes too): held at ≥ 1e-4.
const float kFtDsMinCos2ThetaD = 1e-4f;
// N_p^G of f_s^sc [F]: constant 1/(2π) for both lobes. With the notes'
// N_p^G(φ) = (1/π)∫_{H_f} N_p(φ − φ') dφ' it is exact for R (N_R is constant)
// and, for TT, the convolution's mean over φ (its integral is 1): the
// scattered light's azimuth is taken as uniform, so f_s^sc keeps f's albedo.
const float kFtDsAzimuthScattered = 0.15915494309189533577f;  // 1/(2π)

// The values of one texel (or a lookup between two).
struct DsTexel {
  vec3 aF, aB;          // ā_f, ā_b
  vec3 alphaF, alphaB;  // ᾱ_f, ᾱ_b
  vec3 betaF2, betaB2;  // β̄_f², β̄_b² (θ_h units)
  vec3 ab;              // A_b
  vec3 deltaB;          // Δ_b
  vec3 sigmaB2;         // σ̄_b²
};

// ---- The bake ------------------------------------------------------------------

// θ_k of texel k (the ambient table's layout).
FT_FUNC float ftDsTexelAngle(int k, int n) { return -0.5f * FT_PI + (float(k) + 0.5f) * FT_PI / float(n); }

// The φ range, within [0, π], of the forward half H_f = {cos φ < 0} and of
// the backward half H_b (x from, y to). The planted fault swaps them.
FT_FUNC vec2 ftDsForwardPhiRange() {
  return FT_FAULT_DS_HEMISPHERES_SWAPPED_ON ? vec2(0.0f, 0.5f * FT_PI) : vec2(0.5f * FT_PI, FT_PI);
}
FT_FUNC vec2 ftDsBackwardPhiRange() {
  return FT_FAULT_DS_HEMISPHERES_SWAPPED_ON ? vec2(0.5f * FT_PI, FT_PI) : vec2(0.0f, 0.5f * FT_PI);
}

// The integrands of a_{H,p}(θ) over (θ_o, φ ∈ one of the ranges above):
// 2 f_p(θ, θ_o, φ) cos²θ_o, the 2 for the mirror half φ → −φ (f is even).
// z = (Z_R, Z_TT) at θ (ftLobeNorms: the lobes' exact normalisation).
FT_FUNC vec3 ftDsIntegrandR(FabricParams p, float theta, float thetaO, float phi, float zR) {
  FiberAngles a;
  a.thetaI = theta;
  a.thetaO = thetaO;
  a.phi = phi;
  float c = cos(thetaO);
  return ftBcsdfRNormed(p, a, zR) * (2.0f * c * c);
}
FT_FUNC vec3 ftDsIntegrandTT(FabricParams p, float theta, float thetaO, float phi, float zTT) {
  FiberAngles a;
  a.thetaI = theta;
  a.thetaO = thetaO;
  a.phi = phi;
  float c = cos(thetaO);
  return ftBcsdfTTNormed(p, a, zTT) * (2.0f * c * c);
}

// Zinke's lobe width from a Khungurn β: the lobes here are Gaussians in
// θ_i + θ_o = 2θ_h, Zinke's in θ_h, so β^Z = β/2 (notes A6's trap; the
// planted fault leaves β in θ_o units).
FT_FUNC float ftDsBetaZ(float beta) { return FT_FAULT_DS_BETA_THETA_O_ON ? beta : 0.5f * beta; }

// A_b of eq. 14: ā_b ā_f²/(1 − ā_f²) + ā_b³ ā_f²/(1 − ā_f²)³, the backscatter
// of one and of three backward events between any number of forward ones.
// The planted fault writes the cube as (1 − ā_f²) (a public GLSL port's bug).
FT_FUNC vec3 ftDsAb(vec3 aF, vec3 aB) {
  vec3 af2 = aF * aF;
  vec3 d = max(vec3(1.0f) - af2, vec3(kFtDsMinOneMinusAf2));
  vec3 d3 = FT_FAULT_DS_AB_DENOMINATOR_ON ? d : d * d * d;
  return aB * af2 / d + aB * aB * aB * af2 / d3;
}

// Δ_b of eq. 16: ᾱ_b(1 − 2ā_b²/(1 − ā_f²)²) + ᾱ_f(2(1 − ā_f²)² + 4ā_f²ā_b²)/(1 − ā_f²)³.
// Linear in ᾱ_f and ᾱ_b, so 0 here (α_p = 0) wherever the factors are finite.
FT_FUNC vec3 ftDsDeltaB(vec3 aF, vec3 aB, vec3 alphaF, vec3 alphaB) {
  vec3 d = max(vec3(1.0f) - aF * aF, vec3(kFtDsMinOneMinusAf2));
  return alphaB * (vec3(1.0f) - 2.0f * aB * aB / (d * d)) + alphaF * (2.0f * d * d + 4.0f * aF * aF * aB * aB) / (d * d * d);
}

// σ̄_b² from eq. 17 as published:
//   σ̄_b = (1 + d_b ā_f²)(ā_b√(2β̄_f² + β̄_b²) + ā_b³√(2β̄_f² + 3β̄_b²)) / (ā_b + ā_b³(2β̄_f + 3β̄_b)).
// The denominator's β̄ are unsquared (a weighted mean of the two widths would
// have ā_b + ā_b³ there); kept for fidelity to the paper (notes A6).
FT_FUNC vec3 ftDsSigmaB2(vec3 aF, vec3 aB, vec3 betaF2, vec3 betaB2) {
  vec3 ab3 = aB * aB * aB;
  vec3 num = (vec3(1.0f) + kFtDsDensityBack * aF * aF) *
             (aB * sqrt(2.0f * betaF2 + betaB2) + ab3 * sqrt(2.0f * betaF2 + 3.0f * betaB2));
  vec3 den = max(aB + ab3 * (2.0f * sqrt(betaF2) + 3.0f * sqrt(betaB2)), vec3(1e-30f));
  vec3 s = num / den;
  return s * s;
}

// A texel from its four lobe integrals a_{f,R}, a_{f,TT}, a_{b,R}, a_{b,TT}.
FT_FUNC DsTexel ftDsTexelFromLobes(FabricParams p, vec3 aFR, vec3 aFTT, vec3 aBR, vec3 aBTT) {
  DsTexel t;
  t.aF = aFR + aFTT;
  t.aB = aBR + aBTT;
  vec3 invF = vec3(1.0f) / max(t.aF, vec3(1e-30f)), invB = vec3(1.0f) / max(t.aB, vec3(1e-30f));
  float bR = ftDsBetaZ(p.colorR.w), bTT = ftDsBetaZ(p.colorTT.w);
  t.alphaF = (aFR * kFtDsAlphaR + aFTT * kFtDsAlphaTT) * invF;
  t.alphaB = (aBR * kFtDsAlphaR + aBTT * kFtDsAlphaTT) * invB;
  t.betaF2 = (aFR * (bR * bR) + aFTT * (bTT * bTT)) * invF;
  t.betaB2 = (aBR * (bR * bR) + aBTT * (bTT * bTT)) * invB;
  t.ab = ftDsAb(t.aF, t.aB);
  t.deltaB = ftDsDeltaB(t.aF, t.aB, t.alphaF, t.alphaB);
  t.sigmaB2 = ftDsSigmaB2(t.aF, t.aB, t.betaF2, t.betaB2);
  return t;
}

// ---- The lookup ------------------------------------------------------------------

// Lookup coordinate of θ: x = the texel below, y = the one above (clamped),
// z = the weight of y. Callers fetch both texels' rows and ftDsMix them (no
// sampler filtering: its weight precision is implementation-defined).
FT_FUNC vec3 ftDsLookup(float theta, int n) {
  float u = clamp((theta + 0.5f * FT_PI) / FT_PI * float(n) - 0.5f, 0.0f, float(n - 1));
  float k0 = min(floor(u), float(n - 1));
  float k1 = min(k0 + 1.0f, float(n - 1));
  return vec3(k0, k1, u - k0);
}
FT_FUNC DsTexel ftDsMix(DsTexel a, DsTexel b, float w) {
  DsTexel t;
  t.aF = mix(a.aF, b.aF, w);
  t.aB = mix(a.aB, b.aB, w);
  t.alphaF = mix(a.alphaF, b.alphaF, w);
  t.alphaB = mix(a.alphaB, b.alphaB, w);
  t.betaF2 = mix(a.betaF2, b.betaF2, w);
  t.betaB2 = mix(a.betaB2, b.betaB2, w);
  t.ab = mix(a.ab, b.ab, w);
  t.deltaB = mix(a.deltaB, b.deltaB, w);
  t.sigmaB2 = mix(a.sigmaB2, b.sigmaB2, w);
  return t;
}

// ---- Per frame -------------------------------------------------------------------

// The table is read at θ_d = (θ_o − θ_i)/2 (Zinke; the tables are even in θ).
FT_FUNC float ftDsThetaD(FiberAngles a) { return 0.5f * (a.thetaO - a.thetaI); }

// Gaussian of variance v, per channel: exp(−x²/2v)/√(2πv).
FT_FUNC vec3 ftDsGaussianVar(vec3 x, vec3 v) {
  v = max(v, vec3(1e-12f));
  return exp(-0.5f * x * x / v) / sqrt(FT_TWO_PI * v);
}

// T_f(n) = d_f ā_f^n: the fraction through n fibers (written as exp2(n log2 ā_f),
// GLSL's pow, on both sides).
FT_FUNC vec3 ftDsForwardTransmittance(DsTexel t, float n) {
  return kFtDsDensityForward * exp2(n * log2(max(t.aF, vec3(1e-30f))));
}
// σ̄_f²(n) = n β̄_f²: the forward spread through n fibers (variances add). The
// planted fault adds the unsquared width.
FT_FUNC vec3 ftDsForwardVariance(DsTexel t, float n) {
  return FT_FAULT_DS_FORWARD_VARIANCE_ON ? n * sqrt(t.betaF2) : n * t.betaF2;
}

// f_back = 2 A_b g(θ_h − Δ_b; σ̄_b² + extra) / (π cos²θ_d): extra = 0 for
// f_back^dir, σ̄_f² for f_back^sc.
FT_FUNC vec3 ftDsBackscatter(DsTexel t, FiberAngles a, vec3 extraVariance) {
  float thetaH = 0.5f * (a.thetaI + a.thetaO);
  float c = cos(ftDsThetaD(a));
  float c2 = max(c * c, kFtDsMinCos2ThetaD);
  return 2.0f * t.ab * ftDsGaussianVar(vec3(thetaH) - t.deltaB, t.sigmaB2 + extraVariance) / (FT_PI * c2);
}

// M_p^G: lobe p broadened to variance β_p^Z² + σ² in θ_h units (Zinke),
// g(θ_h − α; b)/(2 Z(θ_i; 2b)), b = √(β^Z² + σ²): g(θ_h; b)/2 = g(θ_i + θ_o; 2b),
// so M^G has unit energy over θ_o like M, and equals M at σ = 0 (check C6).
FT_FUNC float ftDsBroadenedLobe(float thetaI, float thetaO, float betaZ, float alpha, float variance) {
  float b = sqrt(betaZ * betaZ + variance);
  return 0.5f * ftGaussian(0.5f * (thetaI + thetaO) - alpha, b) / ftLongitudinalNorm(thetaI, 2.0f * b);
}

// f_s^sc = Σ_p A_p M_p^G N_p^G, A_R = F, A_TT = (1 − F) C_TT, N_p^G = 1/(2π).
FT_FUNC vec3 ftDsForwardScattered(FabricParams p, FiberAngles a, vec3 sigmaF2) {
  vec3 fr = ftFiberFresnel(vec3(p.colorR), a.thetaI);
  vec3 att = (vec3(1.0f) - fr) * vec3(p.colorTT);
  float bR = ftDsBetaZ(p.colorR.w), bTT = ftDsBetaZ(p.colorTT.w);
  vec3 mR, mTT;
  for (int c = 0; c < 3; ++c) {
    mR[c] = ftDsBroadenedLobe(a.thetaI, a.thetaO, bR, kFtDsAlphaR, sigmaF2[c]);
    mTT[c] = ftDsBroadenedLobe(a.thetaI, a.thetaO, bTT, kFtDsAlphaTT, sigmaF2[c]);
  }
  return (fr * mR + att * mTT) * kFtDsAzimuthScattered;
}

// Everything one evaluation yields (rgb each).
struct DsFrame {
  vec3 value;           // F: L_o = L_d F cos θ_i
  vec3 backDirect;      // f_back^dir
  vec3 backScattered;   // f_back^sc
  vec3 forwardScattered;  // f_s^sc
  vec3 transmittance;   // T_f(n)
  vec3 forwardVariance;  // σ̄_f²(n)
};

// F of notes A6 "Per frame" [F: the continuous-V form, not Zinke's
// pseudo-code (T_f − directFraction) d_f (…)]:
//   F = V (f + d_b f_back^dir) + (1 − V) T_f (f_s^sc + π d_b f_back^sc),
// t = the table's values at θ_d (ftDsLookup + ftDsMix), f = f of eq. 6
// (bcsdf.h, exact Z), V ∈ [0, 1] the direct visibility, n ≥ 0 the fibers
// crossed towards the light.
FT_FUNC DsFrame ftDsEvaluate(FabricParams p, DsTexel t, FiberAngles a, float visibility, float n) {
  DsFrame r;
  vec3 f = ftBcsdf(p, a);
  r.transmittance = ftDsForwardTransmittance(t, n);
  r.forwardVariance = ftDsForwardVariance(t, n);
  r.backDirect = ftDsBackscatter(t, a, vec3(0.0f));
  r.backScattered = ftDsBackscatter(t, a, r.forwardVariance);
  r.forwardScattered = ftDsForwardScattered(p, a, r.forwardVariance);
  r.value = visibility * (f + kFtDsDensityBack * r.backDirect) +
            (1.0f - visibility) * r.transmittance * (r.forwardScattered + FT_PI * kFtDsDensityBack * r.backScattered);
  return r;
}

// The runtime expression of notes A7 (the ξ bake and the frame), before ξ and
// Ψ_G: (f + k_fly d_b f_back^dir); L_o = L_d ξ Ψ_G (this) cos θ_d there.
FT_FUNC vec3 ftDsRuntime(vec3 f, vec3 backDirect, float kFly) { return f + kFly * kFtDsDensityBack * backDirect; }

FT_NAMESPACE_END
#endif  // FT_DUAL_SCATTERING_H
