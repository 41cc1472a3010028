// self_shadow.h — the self-shadow 3D texture of Wu & Yuksel 2019 (000) §4.1
// (Fig. 6; notes-rendering A2): the ply density accumulated along the light,
// in slices of the relative angle between the light and the ply twist.
//
// 000 §4.1 shadows within a yarn with "the density function that we use for
// placing the fibers" (common/yarn_density.h), on the 2D cross-section, the
// light taken perpendicular to the yarn. Each slice k holds one rotation of
// the cross-section, the light travelling along +u in every slice; by the
// n_ply-fold symmetry of the plies the slices only cover [0, 2π/n_ply).
//
// Conventions (shared by the bake and the lookup):
//   * cross-section coordinates x = ((P − c)·N̂, (P − c)·B̂) in the yarn frame;
//   * slice k holds ψ_k = k Δψ, Δψ = (2π/n_ply)/N_s: ply j's centre at angle
//     2πj/n_ply + ψ_k, its short axis e_N along the centre (yarn_density.h);
//   * texel (i, j) sits at u_i = −W + (i + ½)Δ, v_j = −W + (j + ½)Δ,
//     Δ = 2W/N; W = S N/(N − 2) with S = YarnDensityParams.supportRadius,
//     so the first and last texel centres lie half a texel outside the
//     support: a lookup clamped to the edge texels is exact outside;
//   * D_k(i, j) = ∫_{−∞}^{u_i} ρ_{ψ_k}(u, v_j) du = τ((u_i, v_j), (−1, 0))
//     (fibers per unit length crossed by light travelling +u);
//   * the lookup rotates the cross-section so that the light's propagation
//     direction d (the unit −ℓ⊥, ℓ towards the light) becomes +u:
//     u = x·d, v = x·rot90(d), and ψ = θ_ply,0 − atan2(d), reduced modulo
//     2π/n_ply, where θ_ply,0 is the angle of ply 0's N̂ in (N̂, B̂) — for
//     ftPlyFrame (fiber_geometry.h) 2π·plyTwistSign·fract(s·r.ply);
//   * trilinear interpolation written out (texel fetches + weights, notes §0.4:
//     hardware filter weights are 8 bits), periodic in ψ, clamped in u, v;
//   * transmittance T = exp(−κ D), κ = 2 r_f (notes §0.3: the expected number
//     of fibers of radius r_f crossed per unit of ρ·length).
// Texel (i, j, k) is element (k N_v + j) N_u + i of a flat float array.
#ifndef FT_SELF_SHADOW_H
#define FT_SELF_SHADOW_H
#include "prelude.h"
#include "bcsdf.h"  // ftAtan2
#include "yarn_density.h"

// Planted faults (validation/faults.def) that live here run on both sides: the
// C++ side reads a run-time switch (the harness turns it on), GLSL the define.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultSelfShadowSliceRange = false;
inline bool ftFaultSelfShadowPsiSign = false;
}  // namespace ft
#define FT_FAULT_SELF_SHADOW_SLICE_RANGE_ON ::ft::ftFaultSelfShadowSliceRange
#define FT_FAULT_SELF_SHADOW_PSI_SIGN_ON ::ft::ftFaultSelfShadowPsiSign
#else
#ifdef FT_FAULT_SELF_SHADOW_SLICE_RANGE
#define FT_FAULT_SELF_SHADOW_SLICE_RANGE_ON true
#else
#define FT_FAULT_SELF_SHADOW_SLICE_RANGE_ON false
#endif
#ifdef FT_FAULT_SELF_SHADOW_PSI_SIGN
#define FT_FAULT_SELF_SHADOW_PSI_SIGN_ON true
#else
#define FT_FAULT_SELF_SHADOW_PSI_SIGN_ON false
#endif
#endif

// Sizes: notes A2 propose 128 × 128 × 16 for rendering; CI runs 64 × 64 × 8.
#define FT_SELF_SHADOW_DEFAULT_SIZE 128u
#define FT_SELF_SHADOW_DEFAULT_SLICES 16u
#define FT_SELF_SHADOW_CI_SIZE 64u
#define FT_SELF_SHADOW_CI_SLICES 8u
// Below this |ℓ⊥| the light runs along the yarn and has no direction in the
// cross-section: d falls back to N̂ (notes A2).
#define FT_SELF_SHADOW_MIN_PERP 1.0e-4f
// ftSelfShadowTransmittance's path mode: the paper's D as is, or D/max(|ℓ⊥|, 0.1),
// the path through a straight yarn for light that is not perpendicular to it.
#define FT_SELF_SHADOW_PATH_LITERAL 0u
#define FT_SELF_SHADOW_PATH_SCALED 1u

FT_NAMESPACE_BEGIN

// The texture's layout and use (std140).
struct SelfShadowParams {
  uint width;       // N_u: texels along the light
  uint height;      // N_v
  uint slices;      // N_s: slices over ψ ∈ [0, 2π/n_ply)
  uint plyCount;    // n_ply (the period of ψ is 2π/n_ply)
  float halfWidth;  // W: texel centres at ±(W − Δ/2)
  float kappa;      // κ of T = exp(−κ D)
  uint pathMode;    // FT_SELF_SHADOW_PATH_*
  float pad0;
};
FT_ASSERT_OFFSET(SelfShadowParams, halfWidth, 16)
FT_ASSERT_OFFSET(SelfShadowParams, pathMode, 24)
FT_ASSERT_SIZE(SelfShadowParams, 32)

// Fiber radius of notes §0.3 when the preset gives none: a quarter of the
// radius of a disk holding one fiber's share of the ply's area,
// r_f = ¼ √(π e_N e_B R_max² / n_f) (R_max = 1 in every preset).
FT_FUNC float ftSelfShadowFiberRadius(YarnDensityParams d) {
  return 0.25f * sqrt(FT_PI * d.ellipseN * d.ellipseB * d.rMax * d.rMax / float(d.fiberCount));
}

// The layout for `d` at the given size (width, height ≥ 3, slices ≥ 1).
FT_FUNC SelfShadowParams ftSelfShadowParams(YarnDensityParams d, uint width, uint height, uint slices, float kappa) {
  SelfShadowParams p;
  p.width = width;
  p.height = height;
  p.slices = slices;
  p.plyCount = d.plyCount;
  // One texel of margin on each side along the coarser axis: S = W − 2W/N.
  uint n = min(width, height);
  p.halfWidth = d.supportRadius * float(n) / float(n - 2u);
  p.kappa = kappa;
  p.pathMode = FT_SELF_SHADOW_PATH_LITERAL;
  p.pad0 = 0.0f;
  return p;
}

// 2π/n_ply: the period of the density in ψ.
FT_FUNC float ftSelfShadowPeriod(SelfShadowParams p) { return FT_TWO_PI / float(p.plyCount); }

// ψ_k of slice k.
FT_FUNC float ftSelfShadowSliceAngle(SelfShadowParams p, uint k) {
  // Planted fault: the slices spread over a whole turn instead of one period.
  float range = FT_FAULT_SELF_SHADOW_SLICE_RANGE_ON ? FT_TWO_PI : ftSelfShadowPeriod(p);
  return range * float(k) / float(p.slices);
}

// Texel centre (u_i, v_j).
FT_FUNC vec2 ftSelfShadowTexelCenter(SelfShadowParams p, uint i, uint j) {
  float du = 2.0f * p.halfWidth / float(p.width), dv = 2.0f * p.halfWidth / float(p.height);
  return vec2(-p.halfWidth + (float(i) + 0.5f) * du, -p.halfWidth + (float(j) + 0.5f) * dv);
}

FT_FUNC uint ftSelfShadowIndex(SelfShadowParams p, uint i, uint j, uint k) {
  return (k * p.height + j) * p.width + i;
}

// One texel of the exact bake: the density accumulated from the light side
// (−u) up to the texel centre, at ψ.
FT_FUNC float ftSelfShadowExactAt(SelfShadowParams p, YarnDensityParams d, uint i, uint j, float psi) {
  return ftDensityLineIntegral(d, psi, ftSelfShadowTexelCenter(p, i, j), vec2(-1.0f, 0.0f));
}

FT_FUNC float ftSelfShadowExact(SelfShadowParams p, YarnDensityParams d, uint i, uint j, uint k) {
  return ftSelfShadowExactAt(p, d, i, j, ftSelfShadowSliceAngle(p, k));
}

// Where a fragment reads the texture: the 2 × 2 × 2 texels and the weights.
struct SelfShadowSample {
  uvec4 u;    // i0, i1 (clamped), j0, j1 (clamped)
  uvec4 r;    // k0, k1 (periodic), unused
  vec4 w;     // fractions along u, v, ψ; ψ (radians, in [0, 2π/n_ply)), for diagnostics
  vec4 uvd;   // u, v in the light frame; |ℓ⊥|; unused
};

// x: cross-section point; toLight: ℓ⊥ = (ℓ·N̂, ℓ·B̂) of the unit vector ℓ
// towards the light; plyAngle: θ_ply,0 (radians, any value).
FT_FUNC SelfShadowSample ftSelfShadowSample(SelfShadowParams p, vec2 x, vec2 toLight, float plyAngle) {
  SelfShadowSample s;
  float len = length(toLight);
  // Propagation direction: away from the light.
  vec2 d = len > FT_SELF_SHADOW_MIN_PERP ? -toLight / len : vec2(1.0f, 0.0f);
  float u = dot(x, d);
  float v = x.y * d.x - x.x * d.y;  // x·rot90(d), rot90(d) = (−d.y, d.x)
  float period = ftSelfShadowPeriod(p);
  // Rotating by −atan2(d) brings d onto +u and ply 0 to θ_ply,0 − atan2(d).
  float angle = FT_FAULT_SELF_SHADOW_PSI_SIGN_ON ? plyAngle + ftAtan2(d.y, d.x) : plyAngle - ftAtan2(d.y, d.x);
  float psi = angle - period * floor(angle / period);
  float du = 2.0f * p.halfWidth / float(p.width), dv = 2.0f * p.halfWidth / float(p.height);
  float fu = clamp((u + p.halfWidth) / du - 0.5f, 0.0f, float(p.width - 1u));
  float fv = clamp((v + p.halfWidth) / dv - 0.5f, 0.0f, float(p.height - 1u));
  float fr = psi / period * float(p.slices);
  float iu = min(floor(fu), float(p.width - 2u));
  float iv = min(floor(fv), float(p.height - 2u));
  float ir = floor(fr);
  uint k0 = uint(ir) % p.slices;  // fr may round up to N_s: slice 0 again
  s.u = uvec4(uint(iu), uint(iu) + 1u, uint(iv), uint(iv) + 1u);
  s.r = uvec4(k0, (k0 + 1u) % p.slices, 0u, 0u);
  s.w = vec4(fu - iu, fv - iv, fr - ir, psi);
  s.uvd = vec4(u, v, len, 0.0f);
  return s;
}

// Trilinear blend of the 8 texels: lo = slice k0, hi = slice k1, each
// (i0 j0, i1 j0, i0 j1, i1 j1).
FT_FUNC float ftSelfShadowBlend(SelfShadowSample s, vec4 lo, vec4 hi) {
  vec4 c = mix(lo, hi, s.w.z);
  float a = mix(c.x, c.y, s.w.x), b = mix(c.z, c.w, s.w.x);
  return mix(a, b, s.w.y);
}

// T = exp(−κ D) (notes A2), D scaled to the 3D path when asked.
FT_FUNC float ftSelfShadowTransmittance(SelfShadowParams p, SelfShadowSample s, float density) {
  float path = p.pathMode == FT_SELF_SHADOW_PATH_SCALED ? density / max(s.uvd.z, 0.1f) : density;
  return exp(-p.kappa * path);
}

FT_NAMESPACE_END
#endif  // FT_SELF_SHADOW_H
