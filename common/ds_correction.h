// ds_correction.h — the per-frame lookup of the dual-scattering correction ξ
// and the fiber-level shadowing Ψ_G^Fiber of Huang et al. 2025 (001) §4.3,
// eq. 9–11, baked by path tracing one yarn (reference/ds_correction.cpp,
// docs/ds-correction.md; notes-rendering A7):
//   Ψ ≈ ξ_M(x, θ) ξ_N(x, φ) Ψ^Yarn_G Ψ^Fiber_{G,M}(x, θ) Ψ^Fiber_{G,N}(x, φ) (1 + Ψ^Fiber_L)   (eq. 11)
// with θ = θ_d − θ_o the longitudinal and φ = φ_d − φ_o the azimuthal angle
// between the light ω_d and the view ω_o about the yarn tangent. The text
// names the factors the other way round ("azimuthal Ψ_{G,M}(x, θ)"); we keep
// the M ↔ θ, N ↔ φ convention of the BCSDF's M_p and N_p, as the arguments
// of eq. 10 say.
//
// Texture space x = (u, v): u = the yarn's length coordinate over one ply
// twist period P (yarn_alpha), repeated; v = the offset across the yarn as
// seen from the eye, along T × ω_o⊥, over [−W, W], clamped. Each of the four
// 3D textures holds rgb per texel (vec4, std430): ξ_M and Ψ_M over N_θ
// longitudinal samples θ_a = −π/2 + (a + ½)π/N_θ (clamped), ξ_N and Ψ_N over
// N_φ azimuthal samples φ_b = 2πb/N_φ (repeated: φ is periodic). Texel
// (i, j, k) is element (k·N_v + j)·N_u + i, centred at ((i + ½)/N_u, (j + ½)/N_v).
#ifndef FT_DS_CORRECTION_H
#define FT_DS_CORRECTION_H
#include "prelude.h"
#include "bcsdf.h"

// Planted faults (validation/faults.def), shared: a C++ run-time switch, a GLSL define.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultXiAxesSwapped = false;
inline bool ftFaultXiPhiClamped = false;
// The frame's ξ layout left at the bake's (preset's own) scale instead of the
// model's (scene/shading_inputs.cpp frameDsCorrection; host side only).
inline bool ftFaultFrameDsUnscaled = false;
}
#define FT_FAULT_XI_AXES_SWAPPED_ON ::ft::ftFaultXiAxesSwapped
#define FT_FAULT_XI_PHI_CLAMPED_ON ::ft::ftFaultXiPhiClamped
#define FT_FAULT_FRAME_DS_UNSCALED_ON ::ft::ftFaultFrameDsUnscaled
#else
#if defined(FT_FAULT_XI_AXES_SWAPPED)
#define FT_FAULT_XI_AXES_SWAPPED_ON true
#else
#define FT_FAULT_XI_AXES_SWAPPED_ON false
#endif
#if defined(FT_FAULT_XI_PHI_CLAMPED)
#define FT_FAULT_XI_PHI_CLAMPED_ON true
#else
#define FT_FAULT_XI_PHI_CLAMPED_ON false
#endif
#endif

FT_NAMESPACE_BEGIN

// The textures' shape (std140/std430).
struct DsCorrectionLayout {
  uvec4 size;  // x N_u, y N_v, z N_θ, w N_φ
  vec4 yarn;   // x period P (length units), y half-width W, zw unused
};
FT_ASSERT_OFFSET(DsCorrectionLayout, yarn, 16)
FT_ASSERT_SIZE(DsCorrectionLayout, 32)

// The direction samples of the bake (and the texel centres of the lookup).
FT_FUNC float ftXiThetaSample(int a, int n) { return -0.5f * FT_PI + (float(a) + 0.5f) * FT_PI / float(n); }
FT_FUNC float ftXiPhiSample(int b, int n) { return FT_TWO_PI * float(b) / float(n); }

// θ = θ_d − θ_o and φ = φ_d − φ_o ∈ [0, 2π) of light ω_d and view ω_o about
// the unit tangent t; φ runs from ω_o⊥ towards t × ω_o⊥. φ = 0 when either
// direction is parallel to t (where φ is undefined).
FT_FUNC vec2 ftXiRelativeAngles(vec3 t, vec3 wd, vec3 wo) {
  float sd = dot(wd, t), so = dot(wo, t);
  vec3 pd = wd - sd * t, po = wo - so * t;
  float thetaD = ftAtan2(sd, length(pd)), thetaO = ftAtan2(so, length(po));
  float phi = dot(pd, pd) * dot(po, po) > 1e-24f ? ftAtan2(dot(cross(po, pd), t), dot(po, pd)) : 0.0f;
  if (phi < 0.0f) phi += FT_TWO_PI;
  return vec2(thetaD - thetaO, phi);
}

// The texture coordinates of a point: u from the length coordinate s, v from
// the signed offset across the yarn (world units).
FT_FUNC vec2 ftXiTexCoord(DsCorrectionLayout l, float s, float across) {
  return vec2(fract(s / l.yarn.x), clamp(0.5f + 0.5f * across / l.yarn.y, 0.0f, 1.0f));
}

// Linear interpolation along one axis of n texels: x = the texel below,
// y = the one above, z = the weight of y. `periodic`: texel k is centred at
// k/n of the period and the axis wraps (φ); otherwise centred at (k + ½)/n
// and clamped (u is periodic with centres (k + ½)/n: pass offset ½).
// FT_XI_PRECISE: a fused x·n − offset rounds once where the CPU rounds
// twice; the weight then differs by an ulp of c, times the log ratio between
// neighbouring texels (up to ~20) in the product: 1.1e-4 on NVIDIA's GLSL.
// The lookup check's kernel (ds_correction_eval.comp.glsl) defines it
// `precise`, so that it compares the formulas, not two compilers' fusing;
// the frame leaves it empty: compiled precise, llvmpipe's fragment and
// compute stages shaded dual scattering up to 4 % apart (462 pixels of
// shading/deferred/closeup/compute/extras), a discrepancy not run down.
#ifndef FT_XI_PRECISE
#define FT_XI_PRECISE
#endif
FT_FUNC vec3 ftXiAxisLookup(float x, int n, bool periodic, float offset) {
  FT_XI_PRECISE float c = x * float(n) - offset;
  if (periodic) {
    float k0 = floor(c);
    FT_XI_PRECISE float w = c - k0;
    // Into [0, n). GLSL's division may be off by 2.5 ulp, so n/n can floor
    // to 0: the two corrections keep k0 in range whatever it rounds to.
    k0 = k0 - float(n) * floor(k0 / float(n));
    if (k0 >= float(n)) k0 = k0 - float(n);
    if (k0 < 0.0f) k0 = k0 + float(n);
    float k1 = k0 + 1.0f >= float(n) ? 0.0f : k0 + 1.0f;
    return vec3(k0, k1, w);
  }
  c = clamp(c, 0.0f, float(n - 1));
  float k0 = min(floor(c), float(n - 1));
  return vec3(k0, min(k0 + 1.0f, float(n - 1)), c - k0);
}

// Where the four textures are read for one point and angle pair: the
// trilinear corners of the θ textures (M) and of the φ textures (N).
struct XiLookup {
  vec3 u, v, theta, phi;  // ftXiAxisLookup of each axis
};

FT_FUNC XiLookup ftXiLookup(DsCorrectionLayout l, vec2 uv, vec2 thetaPhi) {
  XiLookup r;
  int nu = int(l.size.x), nv = int(l.size.y), nt = int(l.size.z), np = int(l.size.w);
  r.u = ftXiAxisLookup(uv.x, nu, true, 0.5f);
  r.v = ftXiAxisLookup(uv.y, nv, false, 0.5f);
  float theta = FT_FAULT_XI_AXES_SWAPPED_ON ? thetaPhi.y - FT_PI : thetaPhi.x;  // the paper's naming swap
  float phi = FT_FAULT_XI_AXES_SWAPPED_ON ? thetaPhi.x + FT_PI : thetaPhi.y;
  // θ ∈ [−π, π] (a difference of two angles in [−π/2, π/2]); the samples cover [−π/2, π/2].
  // Times the reciprocal, not divided: GLSL's division may be off by 2.5 ulp,
  // a product of two floats is rounded exactly as the CPU rounds it.
  r.theta = ftXiAxisLookup((theta + 0.5f * FT_PI) * FT_INV_PI, nt, false, 0.5f);
  r.phi = ftXiAxisLookup(phi * FT_INV_TWO_PI, np, !FT_FAULT_XI_PHI_CLAMPED_ON, 0.0f);
  return r;
}

// The factors are multiplicative and span decades between neighbouring
// texels (ξ ≈ 1e4 where Ψ ≈ 1e-4 and their product is ~1), so the lookup
// interpolates their logarithms: the buffers a lookup reads hold
// ftXiEncode(value) (the host encodes at upload, on both sides), the caller
// sums weight × encoded corner, and ftXiDecode of the sum of the four
// textures' sums is the product ξ_M ξ_N Ψ_M Ψ_N — the geometric
// interpolation of the product, which linear interpolation of each factor
// is not (it turned a product of ~1 into 1e4 between two such texels).
const float kFtXiMinValue = 1e-30f;
FT_FUNC vec3 ftXiEncode(vec3 value) { return log(max(value, vec3(kFtXiMinValue))); }
FT_FUNC vec3 ftXiDecode(vec3 sum) { return exp(sum); }

// Element index of texel (i, j, k) and the weight of corner c (bit 0: u,
// bit 1: v, bit 2: the angle axis) of a lookup along `angle`.
FT_FUNC uint ftXiTexel(DsCorrectionLayout l, float i, float j, float k) {
  return (uint(k) * l.size.y + uint(j)) * l.size.x + uint(i);
}
FT_FUNC uint ftXiCorner(DsCorrectionLayout l, XiLookup q, vec3 angle, int c) {
  return ftXiTexel(l, (c & 1) != 0 ? q.u.y : q.u.x, (c & 2) != 0 ? q.v.y : q.v.x, (c & 4) != 0 ? angle.y : angle.x);
}
FT_FUNC float ftXiCornerWeight(XiLookup q, vec3 angle, int c) {
  return ((c & 1) != 0 ? q.u.z : 1.0f - q.u.z) * ((c & 2) != 0 ? q.v.z : 1.0f - q.v.z) *
         ((c & 4) != 0 ? angle.z : 1.0f - angle.z);
}

FT_NAMESPACE_END
#endif  // FT_DS_CORRECTION_H
