// prt_multiple_scattering.h — local multiple scattering of Khungurn et al.
// 2017 (004) §4.2, §4.3, §5.3.1 in spherical harmonics (common/sh.h), shared
// by the CPU reference (double, reference/prt_multiple_scattering.h) and the
// GPU twin (float, gpu/prt_multiple_scattering_gpu.h,
// prt_multiple_scattering.comp.glsl); docs/prt-multiple-scattering.md.
//
// ω_o-space (004 §4.3): x = the fiber tangent t, y = the part of ω_o normal
// to t (any normal of t when ω_o ∥ t), z = x × y; a direction there is
// (sin θ, cos θ cos φ, cos θ sin φ), θ the longitudinal angle of bcsdf.h and
// φ the signed azimuth from ω_o's half-plane (the BCSDF sees |φ|).
//
// Tables (bake):
//   C_S[θ_o, j] = ∫ Y_j(ω_i) S(ω_i, ω_o) cos θ_i dω_i (004 §4.3a), rgb, at
//     FT_MS_THETA_O = 512 angles θ_k = −π/2 + kπ/511 (both ends included);
//     dω = cos θ dθ dφ, so the integrand carries cos²θ_i. Separable: S =
//     F M_R/(2π) + (1 − F) C_TT M_TT N_TT(φ), so the φ integrals
//     Φ_p,j(θ_i) = ∫ Y_j N_p dφ do not depend on θ_o (pass 0), and C_S is one
//     θ_i sum per θ_o (pass 1). Midpoint rules: θ_i at (i + ½)π/n − π/2
//     (n ≥ 2,048: 11 nodes per σ of silk's 1° R lobe), φ at 2π(k + ½)/n_φ.
//   C_G[λ, l] = ∫ G(ω; +z, λ)/M(λ) Y_l0(ω) dω (004 §4.3b), zonal, on the grid
//     u = λ/(1 + λ) = k/(n − 1), k = 0..n − 1 [F: the supplementary is
//     missing]: u = 0 is λ = 0 (C_G = δ_l0 /√(4π)), u = 1 the λ → ∞ limit
//     √((2l + 1)/4π); C_G is smooth in u at both ends; lookups lerp in u.
//     Each entry by μ = 1 − τ/λ: C_l = ∫_0^{2λ} e^{−τ} K_l P_l(1 − τ/λ) dτ /
//     (1 − e^{−2λ}), τ ≤ 60 (e^{−60} ≈ 1e-26), 8 panels of 16-point
//     Gauss–Legendre.
// Per frame (004 §5.3.1): c_d = Y(ω_d) (or c_G turned to ξ for an SG light),
// c_T = A_C c_d, A_C stored row j1, column j0 (entry a_C[j0, j1] of 004
// §4.2a: c_T[j1] = Σ_j0 a[j0, j1] c_d[j0], the incoming radiance's
// coefficients), R_ωo c_T (sh.h rotation by the frame rows above), then the dot
// with C_S[θ_o] lerped between the two nearest rows.
#ifndef FT_PRT_MULTIPLE_SCATTERING_H
#define FT_PRT_MULTIPLE_SCATTERING_H
#include "prelude.h"
#include "bcsdf.h"
#include "constants.h"
#include "sh.h"

// Planted fault (validation/faults.def), shared (C++ run-time switch, GLSL
// define): V̄_glo's σ_glo taken in texels instead of fabric units.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultMsVgloSigmaTexels = false;
}
#define FT_FAULT_MS_VGLO_SIGMA_TEXELS_ON ::ft::ftFaultMsVgloSigmaTexels
#elif defined(FT_FAULT_MS_VGLO_SIGMA_TEXELS)
#define FT_FAULT_MS_VGLO_SIGMA_TEXELS_ON true
#else
#define FT_FAULT_MS_VGLO_SIGMA_TEXELS_ON false
#endif

#define FT_MS_THETA_O 512          // C_S rows (004 §4.3)
#define FT_MS_THETA_I_NODES 2048   // default θ_i nodes of C_S
#define FT_MS_PHI_NODES 512        // default φ nodes of C_S
#define FT_MS_LAMBDA_NODES 256     // C_G rows [F]

// Passes of prt_multiple_scattering.comp.glsl (PrtMsParams.mode).
#define FT_PRT_MS_PHI 0u      // Φ_p,j(θ_i): one invocation per (lobe, θ_i)
#define FT_PRT_MS_CS 1u       // C_S[θ_o, ·] partial sums: one per (θ_o, chunk of FT_MS_CS_CHUNK θ_i)
#define FT_PRT_MS_CG 2u       // C_G[λ, ·]: one per λ node
#define FT_PRT_MS_FRAME 3u    // L̃^multi per query
#define FT_PRT_MS_SH_PROBE 4u // Y(ω) and M(R)Y(ω) per query (identity checks)
#define FT_PRT_MS_CS_SUM 5u   // C_S[θ_o, j]: one per (θ_o, j), the chunks' partial sums in order
// θ_i nodes per GPU invocation of the C_S pass: llvmpipe ends an invocation's
// loops after 65,535 iterations in all (docs/llvmpipe-notes.md); 256 θ_i ×
// (36 + the lobes' quadrature loops) stays well below.
#define FT_MS_CS_CHUNK 256

FT_NAMESPACE_BEGIN

// The GPU twin's parameters (std140 UBO FT_UBO_PRT_MS).
struct PrtMsParams {
  uint mode;          // FT_PRT_MS_*
  uint bands;         // L + 1 (≤ FT_SH_BANDS)
  uint count;         // items of this dispatch
  uint thetaINodes;   // C_S quadrature
  uint phiNodes;
  uint thetaONodes;   // C_S rows
  uint lambdaNodes;   // C_G rows
  uint cells;         // A_C matrices bound
  FabricParams fabric;
};
FT_ASSERT_OFFSET(PrtMsParams, fabric, 32)
FT_ASSERT_SIZE(PrtMsParams, 80)

// One per-frame query (std430, FT_SSBO_PRT_REQUESTS): wo.xyz towards the eye,
// tangent.xyz the fiber, light.xyz ω_d or the SG axis ξ with light.w = λ
// (0: directional), cell.x the IIRTF cell. Result: vec4 rgb L̃^multi.
struct PrtMsQuery {
  vec4 wo;
  vec4 tangent;
  vec4 light;
  uvec4 cell;
};
FT_ASSERT_SIZE(PrtMsQuery, 64)

// ---- table grids ----------------------------------------------------------
FT_FUNC shreal prtMsThetaONode(int k, int n) {
  return SHR(-1.5707963267948966192) + shreal(k) * SHR(3.1415926535897932385) / shreal(n - 1);
}
FT_FUNC shreal prtMsThetaINode(int i, int n) {
  return SHR(-1.5707963267948966192) + (shreal(i) + SHR(0.5)) * SHR(3.1415926535897932385) / shreal(n);
}
FT_FUNC shreal prtMsPhiNode(int k, int n) { return SHR(6.283185307179586477) * (shreal(k) + SHR(0.5)) / shreal(n); }
FT_FUNC shvec3 prtMsOmegaOSpaceDirection(shreal theta, shreal phi) {
  return shvec3(sin(theta), cos(theta) * cos(phi), cos(theta) * sin(phi));
}

// Lookup of θ_o in the C_S rows: x the row below, y the row above, z the weight of y.
FT_FUNC shvec3 prtMsCsLookup(shreal thetaO, int n) {
  shreal u = (thetaO + SHR(1.5707963267948966192)) / SHR(3.1415926535897932385) * shreal(n - 1);
  u = clamp(u, SHR(0.0), shreal(n - 1));
  shreal k0 = min(floor(u), shreal(n - 2));
  return shvec3(k0, k0 + SHR(1.0), u - k0);
}
// Lookup of λ ≥ 0 (any value, +∞ included) in the C_G rows, as above.
FT_FUNC shvec3 prtMsCgLookup(shreal lambda, int n) {
  shreal u = lambda >= SHR(1e30) ? SHR(1.0) : lambda / (SHR(1.0) + lambda);
  u = clamp(u, SHR(0.0), SHR(1.0)) * shreal(n - 1);
  shreal k0 = min(floor(u), shreal(n - 2));
  return shvec3(k0, k0 + SHR(1.0), u - k0);
}

// ---- C_G ------------------------------------------------------------------
// 16-point Gauss–Legendre on [−1, 1], positive half (double literals in C++).
const shreal kFtMsGl16X[8] = {SHR(0.095012509837637441), SHR(0.28160355077925892), SHR(0.45801677765722737),
                              SHR(0.61787624440264377),  SHR(0.755404408355003),   SHR(0.86563120238783176),
                              SHR(0.9445750230732326),   SHR(0.98940093499164994)};
const shreal kFtMsGl16W[8] = {SHR(0.18945061045506847), SHR(0.18260341504492361), SHR(0.16915651939500256),
                              SHR(0.14959598881657682), SHR(0.12462897125553395), SHR(0.095158511682492897),
                              SHR(0.062253523938647776), SHR(0.027152459411754058)};

// Legendre P_l(x), l < FT_SH_BANDS, all at once.
struct PrtMsZonal {
  shreal c[FT_SH_BANDS];
};
FT_FUNC PrtMsZonal prtMsLegendre(shreal x) {
  PrtMsZonal p;
  p.c[0] = SHR(1.0);
  p.c[1] = x;
  for (int l = 2; l < FT_SH_BANDS; ++l) p.c[l] = (shreal(2 * l - 1) * x * p.c[l - 1] - shreal(l - 1) * p.c[l - 2]) / shreal(l);
  return p;
}

// C_G at u = λ/(1 + λ) ∈ [0, 1] (the header's quadrature; exact limits at the ends).
FT_FUNC PrtMsZonal prtMsZonalSg(shreal u) {
  PrtMsZonal r;
  for (int l = 0; l < FT_SH_BANDS; ++l) r.c[l] = SHR(0.0);
  if (u <= SHR(0.0)) {
    r.c[0] = shNorm(0, 0);
    return r;
  }
  if (u >= SHR(1.0)) {
    for (int l = 0; l < FT_SH_BANDS; ++l) r.c[l] = shNorm(l, 0);
    return r;
  }
  shreal lambda = u / (SHR(1.0) - u);
  shreal top = min(SHR(2.0) * lambda, SHR(60.0));
  shreal h = top / SHR(8.0);
  for (int panel = 0; panel < 8; ++panel) {
    shreal mid = (shreal(panel) + SHR(0.5)) * h;
    for (int k = 0; k < 16; ++k) {
      shreal x = k < 8 ? -kFtMsGl16X[7 - k] : kFtMsGl16X[k - 8];
      shreal w = k < 8 ? kFtMsGl16W[7 - k] : kFtMsGl16W[k - 8];
      shreal tau = mid + SHR(0.5) * h * x;
      PrtMsZonal p = prtMsLegendre(max(SHR(-1.0), SHR(1.0) - tau / lambda));
      shreal e = SHR(0.5) * h * w * exp(-tau);
      for (int l = 0; l < FT_SH_BANDS; ++l) r.c[l] += e * p.c[l];
    }
  }
  // 1 − e^{−2λ} without cancellation for small λ.
  shreal twoL = SHR(2.0) * lambda;
  shreal norm = twoL < SHR(1e-3) ? twoL * (SHR(1.0) - twoL * (SHR(0.5) - twoL / SHR(6.0))) : SHR(1.0) - exp(-twoL);
  for (int l = 0; l < FT_SH_BANDS; ++l) r.c[l] *= shNorm(l, 0) / norm;
  return r;
}

// ---- C_S --------------------------------------------------------------------
// The φ-independent factors of the two lobes at (θ_i, θ_o): R = F M_R / (2π)
// (N_R = 1/2π folded in), TT = (1 − F) C_TT M_TT, rgb; bcsdf.h's pieces.
FT_FUNC vec3 prtMsLobeR(FabricParams p, shreal thetaI, shreal thetaO) {
  FiberAngles a;
  a.thetaI = float(thetaI);
  a.thetaO = float(thetaO);
  a.phi = 0.0f;
  return ftBcsdfR(p, a);
}
FT_FUNC vec3 prtMsLobeTT(FabricParams p, shreal thetaI, shreal thetaO) {
  vec3 transmitted = (vec3(1.0f) - ftFiberFresnel(vec3(p.colorR), float(thetaI))) * vec3(p.colorTT);
  return transmitted * ftLongitudinal(float(thetaI), float(thetaO), p.colorTT.w);
}
// The azimuthal weights of Φ: R 1 (its 1/2π is in prtMsLobeR), TT N_TT(φ).
FT_FUNC shreal prtMsAzimuthTT(FabricParams p, shreal phi) { return shreal(ftAzimuthalTT(float(phi), p.lobes.y)); }

// ---- per frame --------------------------------------------------------------
// θ_o of ω_o about t (bcsdf.h's well-conditioned angle).
FT_FUNC shreal prtMsThetaO(shvec3 t, shvec3 wo) {
  shreal s = dot(wo, t);
  shvec3 perp = wo - s * t;
  return shreal(ftAtan2(float(s), float(sqrt(dot(perp, perp)))));
}
// R_ωo: the SH rotation taking object space to ω_o-space (the frame rows).
FT_FUNC ShRotation prtMsOmegaORotation(shvec3 t, shvec3 wo, int bands) {
  shvec3 x = t / sqrt(dot(t, t));
  shvec3 y = wo - dot(wo, x) * x;
  shreal yy = dot(y, y);
  if (yy < SHR(1e-12)) {  // ω_o ∥ t: any normal of t (C_S is symmetric about x there)
    y = abs(x.z) < SHR(0.9) ? shvec3(-x.y, x.x, SHR(0.0)) : shvec3(SHR(0.0), -x.z, x.y);
    yy = dot(y, y);
  }
  y = y / sqrt(yy);
  shvec3 z = cross(x, y);
  return shRotation(x, y, z, bands);
}
// c_T (rgb) in ω_o-space (the planted GPU fault keeps object space).
FT_FUNC ShCoeffs3 prtMsToOmegaOSpace(ShRotation r, ShCoeffs3 cT, int bands) {
#ifdef FT_FAULT_MS_NO_OMEGA_O_ROTATION
  return cT;  // planted: R_ωo skipped, the dot taken in object space
#else
  return shRotate3(r, cT, bands);
#endif
}
// The light's coefficients from y = Y(ω_d or ξ): y itself (directional), or
// the C_G row g lerped at λ and turned to ξ (SG, λ > 0).
FT_FUNC ShCoeffs prtMsLightCoeffs(ShCoeffs y, PrtMsZonal g, bool sg, int bands) {
  return sg ? shZonalFromY(g.c, y, bands) : y;
}

// ---- V̄_glo (004 §5.3.2) ---------------------------------------------------
// V̄_glo(x) = ∫_A K(x, x′) V_glo(x′) dx′ / ∫_A K(x, x′) dx′, K a 2D Gaussian of
// std σ_glo in the flat fabric's plane. On a grid of V_glo (one value per texel
// of side `texel` fabric units, A = the grid) the Gaussian is separable and so
// is the normalisation (A a rectangle): one pass per axis, each normalised by
// its own weight sum. Truncated at FT_MS_VGLO_SIGMAS σ [F] (mass beyond 4σ:
// 6e-5). The GPU pass: prt_ms_visibility.comp.glsl.
#define FT_MS_VGLO_SIGMAS 4.0
#define FT_MS_VGLO_MAX_RADIUS 8192  // taps each side (llvmpipe's 65,535 loop iterations per invocation)

// UBO FT_UBO_PRT_MS of the V̄_glo pass (std140): grid = (width, height, axis 0 = x / 1 = y, 0),
// sigma = (σ_glo, texel side, 0, 0) in fabric units.
struct PrtMsVgloParams {
  uvec4 grid;
  vec4 sigma;
};
FT_ASSERT_SIZE(PrtMsVgloParams, 32)

// σ_glo in texels (the planted fault keeps fabric units).
FT_FUNC shreal prtMsVgloSigmaTexels(shreal sigmaFabric, shreal texel) {
  return FT_FAULT_MS_VGLO_SIGMA_TEXELS_ON ? sigmaFabric : sigmaFabric / texel;
}
// Taps each side of the centre.
FT_FUNC int prtMsVgloRadius(shreal sigmaTexels) {
  return int(min(ceil(SHR(FT_MS_VGLO_SIGMAS) * max(sigmaTexels, SHR(0.0))), SHR(FT_MS_VGLO_MAX_RADIUS)));
}
// Unnormalised weight of the tap d texels from the centre (σ → 0: the centre alone).
FT_FUNC shreal prtMsVgloWeight(int d, shreal sigmaTexels) {
  if (d == 0) return SHR(1.0);
  if (!(sigmaTexels > SHR(1e-6))) return SHR(0.0);
  shreal x = shreal(d) / sigmaTexels;
  return exp(SHR(-0.5) * x * x);
}

// ---- GPU accumulation of the IIRTF estimator (004 §4.2c) --------------------
// The path tracer stays on the CPU (Embree); its samples (ω0, ω1, T rgb) go to
// prt_ms_accumulate.comp.glsl: pass 0 one invocation per sample writes Y(ω0),
// Y(ω1) (72 floats); pass 1 one invocation per (chunk of FT_MS_ACC_CHUNK
// samples, entry j1·36 + j0) writes Σ T Y_j1(ω1) Y_j0(ω0) rgb of its chunk;
// the CPU adds the chunks in order and scales by 1/(N p(ω0) p(ω1)).
#define FT_MS_ACC_CHUNK 2048
struct PrtMsSample {
  vec4 w0;  // xyz ω0 (towards the light, upper hemisphere)
  vec4 w1;  // xyz ω1
  vec4 t;   // rgb T(ω0, ω1, μ_k)
};
FT_ASSERT_SIZE(PrtMsSample, 48)
// UBO FT_UBO_PRT_MS of the accumulation (std140): sizes = (pass, samples, chunks, 0).
struct PrtMsAccumParams {
  uvec4 sizes;
};
FT_ASSERT_SIZE(PrtMsAccumParams, 16)

FT_NAMESPACE_END
#endif  // FT_PRT_MULTIPLE_SCATTERING_H
