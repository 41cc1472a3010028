// srbf_lighting.h — the per-frame half of the SRBF environment lighting of
// Huang et al. 2025 (001) §4.5, eq. 16 (docs/srbf-lighting.md), shared by the
// fragment stage (gpu/shaders/fiber_strip.frag.glsl) and its CPU twin:
//   L_o = Σ_j W_j T̃_j [(1 − k_d) I(θ_o, θ_j, Δφ_j, λ_j) + k_d D_j(n)/π]
//         + W_0 V_0 [(1 − k_d) A(θ_o) + k_d]
// with (θ_j, Δφ_j) the angles of lobe j's axis μ_j in the fiber's frame (its
// longitudinal angle from the normal plane of the tangent t, and its azimuth
// about t relative to ω_o's: ftFiberAngles(t, μ_j, ω_o)), I the I_M table
// (common/srbf_bcsdf.h, quadrilinear), A the ambient table (000 eq. 8, the
// table's λ → 0 limit) and k_d the frame's diffuse share (fiber_shading.h).
// T̃_j is the one per-lobe transmittance of eq. 17: the caller's (the frame's
// self-shadow T along μ_j, or 1; PCSS's T̃^Yarn multiplies in there); V_0 the
// DC term's visibility (the frame's AO, as for the uniform ambient).
// D_j(n) = ∫ G_j(ω) max(0, n·ω) dω: the SG's irradiance on the round fiber's
// normal, by Hill's fitted clamped-cosine convolution (Hill 2016, "SG series"
// of M. Pettineo), with the exact ∫G (srbf.h).
//
// With dual scattering (001 eq. 17, read as notes-rendering A11 says: c_j →
// ω_j, ξ_n → ξ_N, I_m → I_M) each lobe also carries the DS correction and the
// fiber-level shadowing of eq. 11 evaluated at ω_d := μ_j
// (ftSrbfFrameRadianceXi):
//   L_o = Σ_j W_j T̃_j [(1 − k_d) ξ_M ξ_N Ψ_M Ψ_N I_j + k_d Ψ_M Ψ_N D_j(n)/π] + DC
// — the BCSDF part corrected as a directional light's (f + d_b f_back) is in
// the DS frame, the diffuse part shadowed only (as that light's diffuse part);
// T̃_j is then T̃^Yarn_j alone when a ξ bake is bound (its Ψ replaces the
// self-shadow T) and T_self(μ_j) T̃^Yarn_j with the identity textures of plain
// dual scattering. Eq. 17 as printed has neither the (1 + Ψ_L) of eq. 11 nor
// the D lobe; the f_back part of the directional light is not added either.
// The ξ textures are read through their logarithms (ftXiEncode): C++ takes the
// four encoded arrays as arguments, GLSL the includer's xiM, xiN, psiM, psiN.
//
// The table is read through FT_SRBF_TABLE_AT(i): in C++ the functions take
// the table (a vec3 array, ftSrbfTableIndex order) as their last argument;
// in GLSL the includer declares `srbfTable` (vec4 per texel) first.
#ifndef FT_SRBF_LIGHTING_H
#define FT_SRBF_LIGHTING_H
#include "prelude.h"
#include "ds_correction.h"
#include "fiber_shading.h"
#include "srbf.h"
#include "srbf_bcsdf.h"

// Planted faults (validation/faults.def), shared: run-time switch in C++,
// define in GLSL.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultSrbfFrameAxisWorld = false;
inline bool ftFaultSrbfFrameNoDc = false;
inline bool ftFaultSrbfFrameLambdaNext = false;
inline bool ftFaultSrbfFrameXiDirectionsSwapped = false;
inline bool ftFaultSrbfFrameXiOnDiffuse = false;
}
#define FT_FAULT_SRBF_FRAME_XI_DIRECTIONS_SWAPPED_ON ::ft::ftFaultSrbfFrameXiDirectionsSwapped
#define FT_FAULT_SRBF_FRAME_XI_ON_DIFFUSE_ON ::ft::ftFaultSrbfFrameXiOnDiffuse
#define FT_XI_TEXTURES_PARAM , const vec4 *xiM, const vec4 *xiN, const vec4 *psiM, const vec4 *psiN
#define FT_XI_TEXTURES_ARG , xiM, xiN, psiM, psiN
#define FT_FAULT_SRBF_FRAME_AXIS_WORLD_ON ::ft::ftFaultSrbfFrameAxisWorld
#define FT_FAULT_SRBF_FRAME_NO_DC_ON ::ft::ftFaultSrbfFrameNoDc
#define FT_FAULT_SRBF_FRAME_LAMBDA_NEXT_ON ::ft::ftFaultSrbfFrameLambdaNext
#define FT_SRBF_TABLE_PARAM , const vec3* srbfTable
#define FT_SRBF_TABLE_ARG , srbfTable
#define FT_SRBF_TABLE_AT(i) srbfTable[i]
#else
#if defined(FT_FAULT_SRBF_FRAME_AXIS_WORLD)
#define FT_FAULT_SRBF_FRAME_AXIS_WORLD_ON true
#else
#define FT_FAULT_SRBF_FRAME_AXIS_WORLD_ON false
#endif
#if defined(FT_FAULT_SRBF_FRAME_NO_DC)
#define FT_FAULT_SRBF_FRAME_NO_DC_ON true
#else
#define FT_FAULT_SRBF_FRAME_NO_DC_ON false
#endif
#if defined(FT_FAULT_SRBF_FRAME_LAMBDA_NEXT)
#define FT_FAULT_SRBF_FRAME_LAMBDA_NEXT_ON true
#else
#define FT_FAULT_SRBF_FRAME_LAMBDA_NEXT_ON false
#endif
#if defined(FT_FAULT_SRBF_FRAME_XI_DIRECTIONS_SWAPPED)
#define FT_FAULT_SRBF_FRAME_XI_DIRECTIONS_SWAPPED_ON true
#else
#define FT_FAULT_SRBF_FRAME_XI_DIRECTIONS_SWAPPED_ON false
#endif
#if defined(FT_FAULT_SRBF_FRAME_XI_ON_DIFFUSE)
#define FT_FAULT_SRBF_FRAME_XI_ON_DIFFUSE_ON true
#else
#define FT_FAULT_SRBF_FRAME_XI_ON_DIFFUSE_ON false
#endif
#define FT_SRBF_TABLE_PARAM
#define FT_SRBF_TABLE_ARG
#define FT_SRBF_TABLE_AT(i) srbfTable[i].xyz
#define FT_XI_TEXTURES_PARAM
#define FT_XI_TEXTURES_ARG
#endif

FT_NAMESPACE_BEGIN

// (θ_o, θ_j, Δφ_j) of lobe axis μ in the frame of tangent t seen from ω_o.
// Planted fault: the axis left in world coordinates (its elevation from the
// horizontal plane and its azimuth about +y, as if every fiber ran along +y).
FT_FUNC vec3 ftSrbfLobeAngles(vec3 t, vec3 mu, vec3 wo) {
  if (FT_FAULT_SRBF_FRAME_AXIS_WORLD_ON) t = vec3(0.0f, 1.0f, 0.0f);
  FiberAngles a = ftFiberAngles(t, mu, wo);
  return vec3(a.thetaO, a.thetaI, a.phi);
}

// D(n)/∫G: Hill's fit of the clamped cosine convolved with a normalised SG
// of sharpness λ, at μ·n.
FT_FUNC float ftSrbfClampedCosine(float muDotN, float lambda) {
  float eml = exp(-lambda), em2l = eml * eml, rl = 1.0f / lambda;
  float scale = 1.0f + 2.0f * em2l - rl;
  float bias = (eml - em2l) * rl - em2l;
  float x = sqrt(max(0.0f, 1.0f - scale));
  float x0 = 0.36f * muDotN, x1 = x / (4.0f * 0.36f);
  float s = x0 + x1;
  float y = abs(x0) <= x1 ? s * s / max(x, 1e-30f) : clamp(muDotN, 0.0f, 1.0f);
  return max(0.0f, scale * y + bias);
}

// The I_M table at (θ_o, θ_j, Δφ, λ): quadrilinear over 16 taps.
FT_FUNC vec3 ftSrbfTableValue(ivec4 dims, float thetaO, float thetaJ, float deltaPhi, float lambda FT_SRBF_TABLE_PARAM) {
  vec4 u = ftSrbfTableLookup(dims, thetaO, thetaJ, deltaPhi, lambda);
  vec3 sum = vec3(0.0f);
  for (int c = 0; c < 16; ++c) {
    vec2 tap = ftSrbfTableTap(dims, u, c);
    sum += tap.y * FT_SRBF_TABLE_AT(int(tap.x));
  }
  return sum;
}

// Lobe j's two parts, without W_j and T̃_j: the BCSDF's I (0 for the simple
// model, as its ambient term, fiber_shading.h) and the diffuse D_j(n)/π.
struct SrbfLobeParts {
  vec3 bcsdf;
  float diffuse;
};
FT_FUNC SrbfLobeParts ftSrbfLobeParts(ShadingParams s, SrbfEnvironment env, int j, ivec4 dims, vec3 t, vec3 n, vec3 wo
                                      FT_SRBF_TABLE_PARAM) {
  vec3 mu = vec3(env.lobes[j].axisLambda);
  int jl = FT_FAULT_SRBF_FRAME_LAMBDA_NEXT_ON ? (j + 1) % FT_SRBF_LOBES : j;  // planted: λ of the next lobe
  float lambda = env.lobes[jl].axisLambda.w;
  vec3 ang = ftSrbfLobeAngles(t, mu, wo);
  SrbfLobeParts p;
  p.bcsdf = s.flags.y == FT_SHADING_SIMPLE ? vec3(0.0f)
                                           : ftSrbfTableValue(dims, ang.x, ang.y, ang.z, lambda FT_SRBF_TABLE_ARG);
  p.diffuse = ftSrbfIntegral(lambda) * ftSrbfClampedCosine(dot(mu, n), lambda) / FT_PI;
  return p;
}

// Lobe j's term, without W_j and T̃_j: (1 − k_d) I + k_d D_j(n)/π.
FT_FUNC vec3 ftSrbfLobeResponse(ShadingParams s, SrbfEnvironment env, int j, ivec4 dims, vec3 t, vec3 n, vec3 wo
                                FT_SRBF_TABLE_PARAM) {
  SrbfLobeParts p = ftSrbfLobeParts(s, env, j, dims, t, n, wo FT_SRBF_TABLE_ARG);
  return (vec3(1.0f) - vec3(s.diffuse)) * p.bcsdf + vec3(s.diffuse) * p.diffuse;
}

// Eq. 16 with the DC term: the environment's radiance towards ω_o from the
// fiber point with tangent t and normal n. ambientA: A(θ_o) from the ambient
// table; transmittance[j]: T̃_j; dcVisibility: V_0.
FT_FUNC vec3 ftSrbfFrameRadiance(ShadingParams s, SrbfEnvironment env, ivec4 dims, vec3 t, vec3 n, vec3 wo,
                                 vec3 ambientA, float dcVisibility, float transmittance[FT_SRBF_LOBES]
                                 FT_SRBF_TABLE_PARAM) {
  vec3 sum = vec3(0.0f);
  for (int j = 0; j < FT_SRBF_LOBES; ++j) {
    vec3 w = vec3(env.lobes[j].weight);
    if (w.x + w.y + w.z <= 0.0f) continue;  // NNLS leaves most lobes at 0
    sum += w * transmittance[j] * ftSrbfLobeResponse(s, env, j, dims, t, n, wo FT_SRBF_TABLE_ARG);
  }
  if (FT_FAULT_SRBF_FRAME_NO_DC_ON) return sum;  // planted: the DC term dropped
  vec3 a = s.flags.y == FT_SHADING_SIMPLE ? vec3(0.0f) : ambientA;
  return sum + vec3(env.constant) * dcVisibility * ((vec3(1.0f) - vec3(s.diffuse)) * a + vec3(s.diffuse));
}

// ---- 001 eq. 17: ξ and Ψ^Fiber per lobe ----

// ξ_M ξ_N Ψ_M Ψ_N (xiPsi) and Ψ_M Ψ_N (psi) of lobe axis μ at texture
// coordinate uv, the angles of μ (as ω_d) and ω_o about the yarn tangent T
// (common/ds_correction.h), interpolated geometrically as the directional
// light's (log ξ + log Ψ summed per corner).
// Planted fault: the lobe taken as the view and ω_o as the light (θ and φ
// change sign).
struct SrbfLobeXi {
  vec3 xiPsi;
  vec3 psi;
};
FT_FUNC SrbfLobeXi ftSrbfLobeXi(DsCorrectionLayout l, vec2 uv, vec3 T, vec3 mu, vec3 wo FT_XI_TEXTURES_PARAM) {
  vec2 angles = FT_FAULT_SRBF_FRAME_XI_DIRECTIONS_SWAPPED_ON ? ftXiRelativeAngles(T, wo, mu) : ftXiRelativeAngles(T, mu, wo);
  XiLookup q = ftXiLookup(l, uv, angles);
  vec3 m = vec3(0.0f), n = vec3(0.0f), pm = vec3(0.0f), pn = vec3(0.0f);
  for (int c = 0; c < 8; ++c) {
    float wm = ftXiCornerWeight(q, q.theta, c), wn = ftXiCornerWeight(q, q.phi, c);
    uint im = ftXiCorner(l, q, q.theta, c), iN = ftXiCorner(l, q, q.phi, c);
    vec3 lpm = vec3(psiM[im]), lpn = vec3(psiN[iN]);
    m += wm * (vec3(xiM[im]) + lpm);
    n += wn * (vec3(xiN[iN]) + lpn);
    pm += wm * lpm;
    pn += wn * lpn;
  }
  SrbfLobeXi r;
  r.xiPsi = ftXiDecode(m + n);
  r.psi = ftXiDecode(pm + pn);
  return r;
}

// Eq. 17 (with the DC term and the diffuse part, as eq. 16 above): each
// lobe's BCSDF part times ξ_M ξ_N Ψ_M Ψ_N at ω_d := μ_j, its diffuse part
// times Ψ_M Ψ_N; the point's ξ coordinate uv and yarn tangent T as the
// directional light's lookup forms them. transmittance[j]: the rest of T̃_j.
// Planted fault: the diffuse part corrected by ξ too.
FT_FUNC vec3 ftSrbfFrameRadianceXi(ShadingParams s, SrbfEnvironment env, ivec4 dims, vec3 t, vec3 n, vec3 wo,
                                   vec3 ambientA, float dcVisibility, float transmittance[FT_SRBF_LOBES],
                                   DsCorrectionLayout xiLayout, vec2 uv, vec3 T FT_SRBF_TABLE_PARAM
                                   FT_XI_TEXTURES_PARAM) {
  vec3 sum = vec3(0.0f);
  for (int j = 0; j < FT_SRBF_LOBES; ++j) {
    vec3 w = vec3(env.lobes[j].weight);
    if (w.x + w.y + w.z <= 0.0f) continue;  // NNLS leaves most lobes at 0
    SrbfLobeParts p = ftSrbfLobeParts(s, env, j, dims, t, n, wo FT_SRBF_TABLE_ARG);
    SrbfLobeXi x = ftSrbfLobeXi(xiLayout, uv, T, vec3(env.lobes[j].axisLambda), wo FT_XI_TEXTURES_ARG);
    vec3 diffuseFactor = FT_FAULT_SRBF_FRAME_XI_ON_DIFFUSE_ON ? x.xiPsi : x.psi;
    sum += w * transmittance[j] *
           ((vec3(1.0f) - vec3(s.diffuse)) * x.xiPsi * p.bcsdf + vec3(s.diffuse) * diffuseFactor * p.diffuse);
  }
  if (FT_FAULT_SRBF_FRAME_NO_DC_ON) return sum;  // planted: the DC term dropped
  vec3 a = s.flags.y == FT_SHADING_SIMPLE ? vec3(0.0f) : ambientA;
  return sum + vec3(env.constant) * dcVisibility * ((vec3(1.0f) - vec3(s.diffuse)) * a + vec3(s.diffuse));
}

FT_NAMESPACE_END
#endif  // FT_SRBF_LIGHTING_H
