// srbf_bcsdf.h — the I_M table of Huang et al. 2025 (001) §4.5 eq. 15–16: the
// fiber BCSDF (common/bcsdf.h) convolved with one SRBF,
//   I(θ_o, θ_j, Δφ, λ) = ∫_{S²} G(ω_i; ω_j, λ) f(ω_i, ω_o) cos θ_i dω_i,
// shared by the CPU bake (reference/srbf_table.h: the 1D analytic reduction),
// the GPU bake (gpu/srbf_table_gpu.h: brute-force 2D quadrature) and the
// lookup. 001 writes I_M(cos θ_j, cos θ_o, cos(θ_j − θ_o), 1/λ_j); that loses
// the sign of θ and has no azimuth, so fibertwin tabulates (notes A10 [F])
//   θ_o, θ_j: n values uniform in sin θ over [−1, 1] (ends included);
//   Δφ = φ_o − φ_j: n values over [0, π] (I is even in Δφ; ends included);
//   λ: n values log-uniform over [FT_SRBF_LAMBDA_MIN, FT_SRBF_LAMBDA_MAX].
// Storage: rgb (w = 0) at index ((i_o·N_j + i_j)·N_Δφ + i_Δφ)·N_λ + i_λ.
// Lookup: quadrilinear over the 16 surrounding texels, clamped at the ends
// (no sampler filtering): ftSrbfTableLookup gives the continuous texel
// coordinates, ftSrbfTableTap each of the 16 taps (index, weight).
#ifndef FT_SRBF_BCSDF_H
#define FT_SRBF_BCSDF_H
#include "prelude.h"
#include "bcsdf.h"

#ifdef __cplusplus
namespace ft {
inline bool ftFaultSrbfTableNoCosine = false;
inline bool ftFaultSrbfTableCosIndex = false;
inline bool ftFaultSrbfTableLambdaInverse = false;
}
#define FT_FAULT_SRBF_TABLE_NO_COSINE_ON ::ft::ftFaultSrbfTableNoCosine
#define FT_FAULT_SRBF_TABLE_COS_INDEX_ON ::ft::ftFaultSrbfTableCosIndex
#define FT_FAULT_SRBF_TABLE_LAMBDA_INVERSE_ON ::ft::ftFaultSrbfTableLambdaInverse
#else
#if defined(FT_FAULT_SRBF_TABLE_NO_COSINE)
#define FT_FAULT_SRBF_TABLE_NO_COSINE_ON true
#else
#define FT_FAULT_SRBF_TABLE_NO_COSINE_ON false
#endif
#if defined(FT_FAULT_SRBF_TABLE_COS_INDEX)
#define FT_FAULT_SRBF_TABLE_COS_INDEX_ON true
#else
#define FT_FAULT_SRBF_TABLE_COS_INDEX_ON false
#endif
#if defined(FT_FAULT_SRBF_TABLE_LAMBDA_INVERSE)
#define FT_FAULT_SRBF_TABLE_LAMBDA_INVERSE_ON true
#else
#define FT_FAULT_SRBF_TABLE_LAMBDA_INVERSE_ON false
#endif
#endif

#define FT_SRBF_LAMBDA_MIN 0.5f
#define FT_SRBF_LAMBDA_MAX 512.0f

FT_NAMESPACE_BEGIN

// Table dimensions (N_θo, N_θj, N_Δφ, N_λ), each ≥ 2.
FT_FUNC int ftSrbfTableSize(ivec4 dims) { return dims.x * dims.y * dims.z * dims.w; }
FT_FUNC int ftSrbfTableIndex(ivec4 dims, ivec4 k) { return ((k.x * dims.y + k.y) * dims.z + k.z) * dims.w + k.w; }
FT_FUNC ivec4 ftSrbfTableTexel(ivec4 dims, int index) {
  int l = index % dims.w;
  int rest = index / dims.w;
  int p = rest % dims.z;
  rest /= dims.z;
  return ivec4(rest / dims.y, rest % dims.y, p, l);
}

// The cos θ_i of eq. 15 (the measure's own cos θ_i of dω = cos θ dθ dφ is
// separate). Planted fault: dropped, the plain dω of eq. 15 without it.
FT_FUNC float ftSrbfCosine(float thetaI) { return FT_FAULT_SRBF_TABLE_NO_COSINE_ON ? 1.0f : cos(thetaI); }

// Angle of texel k of a θ axis of n values: sin θ_k = −1 + 2k/(n − 1).
FT_FUNC float ftSrbfTableTheta(int k, int n) {
  float s = clamp(-1.0f + 2.0f * float(k) / float(n - 1), -1.0f, 1.0f);
  return ftAtan2(s, sqrt(max(0.0f, 1.0f - s * s)));  // asin: GLSL's is good to 4e-4 rad only (bcsdf.h)
}
FT_FUNC float ftSrbfTableDeltaPhi(int k, int n) { return FT_PI * float(k) / float(n - 1); }
// λ of texel k: log-uniform (planted fault: uniform in 1/λ, while the lookup stays log).
FT_FUNC float ftSrbfTableLambda(int k, int n) {
  float t = float(k) / float(n - 1);
  if (FT_FAULT_SRBF_TABLE_LAMBDA_INVERSE_ON)
    return 1.0f / mix(1.0f / FT_SRBF_LAMBDA_MIN, 1.0f / FT_SRBF_LAMBDA_MAX, t);
  return FT_SRBF_LAMBDA_MIN * exp(t * log(FT_SRBF_LAMBDA_MAX / FT_SRBF_LAMBDA_MIN));
}

// Continuous texel coordinates of (θ_o, θ_j, Δφ, λ), clamped to [0, n − 1].
// Δφ may be any angle (folded into [0, π]); λ outside the axis clamps.
FT_FUNC vec4 ftSrbfTableLookup(ivec4 dims, float thetaO, float thetaJ, float deltaPhi, float lambda) {
  float so = sin(thetaO), sj = sin(thetaJ);
  if (FT_FAULT_SRBF_TABLE_COS_INDEX_ON) {  // planted: indexed by cos θ, the literal 001 form: the sign is lost
    so = sqrt(max(0.0f, 1.0f - cos(thetaO) * cos(thetaO)));
    sj = sqrt(max(0.0f, 1.0f - cos(thetaJ) * cos(thetaJ)));
  }
  float p = abs(deltaPhi - FT_TWO_PI * floor(deltaPhi / FT_TWO_PI + 0.5f));  // |Δφ wrapped into [−π, π)|
  float l = log(clamp(lambda, FT_SRBF_LAMBDA_MIN, FT_SRBF_LAMBDA_MAX) / FT_SRBF_LAMBDA_MIN) /
            log(FT_SRBF_LAMBDA_MAX / FT_SRBF_LAMBDA_MIN);
  vec4 u = vec4(0.5f * (so + 1.0f) * float(dims.x - 1), 0.5f * (sj + 1.0f) * float(dims.y - 1),
                p / FT_PI * float(dims.z - 1), l * float(dims.w - 1));
  return clamp(u, vec4(0.0f), vec4(dims - ivec4(1)));
}

// Tap c ∈ [0, 16) of the quadrilinear lookup at coordinates u: bit a of c
// picks the upper texel along axis a. x = flat index, y = weight.
FT_FUNC vec2 ftSrbfTableTap(ivec4 dims, vec4 u, int c) {
  ivec4 k0 = min(ivec4(floor(u)), dims - ivec4(2));
  vec4 f = u - vec4(k0);
  ivec4 bit = ivec4(c & 1, (c >> 1) & 1, (c >> 2) & 1, (c >> 3) & 1);
  vec4 w = mix(vec4(1.0f) - f, f, vec4(bit));
  return vec2(float(ftSrbfTableIndex(dims, k0 + bit)), w.x * w.y * w.z * w.w);
}

FT_NAMESPACE_END
#endif  // FT_SRBF_BCSDF_H
