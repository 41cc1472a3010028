// sh.h — real spherical harmonics up to band L = 5 (36 coefficients) and
// their rotation, for the multiple scattering of Khungurn et al. 2017 (004)
// §4.2–§5.3 (common/prt_multiple_scattering.h, docs/prt-multiple-scattering.md).
// Shared by the CPU reference (double) and the GPU twin (float): the scalar
// and vector types shreal/shvec3 are double/dvec3 in C++ and float/vec3 in
// GLSL (one instance per language, so an include guard is fine).
//
// Convention (one, both sides): real SH WITHOUT the Condon–Shortley phase,
// single index j = l(l + 1) + m,
//   Y_l0  = K_l0 P_l(z),
//   Y_lm  = √2 K_lm P_l^m(z) cos(mφ),   m > 0,
//   Y_l−m = √2 K_lm P_l^m(z) sin(mφ),   m > 0,
// K_lm = √((2l + 1)/(4π) · (l − m)!/(l + m)!), P_l^m(z) = (1 − z²)^{m/2}
// d^m P_l/dz^m (no (−1)^m), so band 1 is √(3/4π)·(y, z, x) and every Y_ll is
// positive along +x. Evaluated from (x, y, z) with polynomial recurrences only
// (no trigonometry): sin^mθ cos mφ, sin^mθ sin mφ by complex multiplication,
// P_l^m / sin^mθ by the three-term recurrence in l.
//
// Rotation (Ivanic & Ruedenberg 1996, J. Phys. Chem. 100(15) 6342, with the
// 1998 erratum; the recurrence in l of their Tables 1–2, no trigonometry,
// usable in GLSL): for a 3 × 3 rotation R (rows rx, ry, rz: Rω = (rx·ω,
// ry·ω, rz·ω)) the per-band matrices M^l, (2l + 1)² entries each, 286 in
// all, with M^l Y_l(ω) = Y_l(Rω). Then M c holds the coefficients of the
// rotated function g(Rω) = f(ω) (f = Σ c_j Y_j): SH coefficients transform
// like the basis because M is orthogonal.
// Zonal vectors need no matrix (addition theorem): the zonal c_l0 about +z
// turned to the axis ξ is c_lm = √(4π/(2l + 1)) c_l0 Y_lm(ξ).
#ifndef FT_SH_H
#define FT_SH_H
#include "prelude.h"

// Planted faults (validation/faults.def). Shared (both sides, run-time
// switch in C++, define in GLSL): the Legendre recurrence of shEval with
// (l + m) for (l + m − 1). GPU only (define): the Condon–Shortley phase
// (−1)^m on the GPU's Y_lm, the CPU without.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultMsShLegendre = false;
}
#define FT_FAULT_MS_SH_LEGENDRE_ON ::ft::ftFaultMsShLegendre
#elif defined(FT_FAULT_MS_SH_LEGENDRE)
#define FT_FAULT_MS_SH_LEGENDRE_ON true
#else
#define FT_FAULT_MS_SH_LEGENDRE_ON false
#endif

#define FT_SH_BANDS 6          // l = 0..5
#define FT_SH_COEFFS 36        // (L + 1)²
#define FT_SH_ROTATION_SIZE 286  // Σ_l (2l + 1)²

#ifdef __cplusplus
FT_NAMESPACE_BEGIN
typedef double shreal;
typedef glm::dvec3 shvec3;
FT_NAMESPACE_END
#define SHR(x) ::ft::shreal(x)
#else
#define shreal float
#define shvec3 vec3
#define SHR(x) float(x)
#endif

FT_NAMESPACE_BEGIN

struct ShCoeffs {
  shreal c[FT_SH_COEFFS];
};

// Per-band rotation matrices, band l at shRotationOffset(l), row-major,
// entry (m, n), m, n ∈ [−l, l].
struct ShRotation {
  shreal m[FT_SH_ROTATION_SIZE];
};

FT_FUNC int shIndex(int l, int m) { return l * (l + 1) + m; }
FT_FUNC int shRotationOffset(int l) { return l * (4 * l * l - 1) / 3; }
FT_FUNC int shRotationIndex(int l, int m, int n) { return shRotationOffset(l) + (m + l) * (2 * l + 1) + (n + l); }

FT_FUNC ShCoeffs shZero() {
  ShCoeffs r;
  for (int j = 0; j < FT_SH_COEFFS; ++j) r.c[j] = SHR(0.0);
  return r;
}

// K_lm of the header (m ≥ 0), index l(l + 1)/2 + m, written out: a loop over
// the factorials would count against llvmpipe's per-invocation loop budget
// (docs/llvmpipe-notes.md) in the GPU's quadrature loops.
const shreal kFtShNorm[21] = {
    SHR(0.28209479177387814),   SHR(0.48860251190291992),  SHR(0.3454941494713355),   SHR(0.63078313050504009),
    SHR(0.25751613468212642),   SHR(0.12875806734106321),  SHR(0.7463526651802308),   SHR(0.21545345607610045),
    SHR(0.068132365095552164),  SHR(0.027814921575518941), SHR(0.84628437532163447),  SHR(0.18923493915151202),
    SHR(0.044603102903819275),  SHR(0.011920680675222404), SHR(0.0042145970709045969), SHR(0.9356025796273888),
    SHR(0.17081687924064806),   SHR(0.032281355871636178), SHR(0.0065894041742255282), SHR(0.0015531374585246044),
    SHR(0.00049114518882630498)};
FT_FUNC shreal shNorm(int l, int m) { return kFtShNorm[l * (l + 1) / 2 + m]; }

// Y_j(ω), j < 36, ω a unit vector.
FT_FUNC ShCoeffs shEval(shvec3 w) {
  ShCoeffs r;
  shreal cm = SHR(1.0), sm = SHR(0.0);  // sin^mθ cos mφ, sin^mθ sin mφ
  shreal pmm = SHR(1.0);                // (2m − 1)!!
  for (int m = 0; m < FT_SH_BANDS; ++m) {
    if (m > 0) {
      shreal cn = w.x * cm - w.y * sm;
      sm = w.x * sm + w.y * cm;
      cm = cn;
      pmm *= shreal(2 * m - 1);
    }
    shreal p1 = SHR(0.0), p2 = SHR(0.0);  // P̂_{l−1}^m, P̂_{l−2}^m (P̂ = P_l^m / sin^mθ)
    for (int l = m; l < FT_SH_BANDS; ++l) {
      shreal p;
      if (l == m) p = pmm;
      else if (l == m + 1) p = w.z * shreal(2 * m + 1) * pmm;
      else {
        int k = FT_FAULT_MS_SH_LEGENDRE_ON ? l + m : l + m - 1;  // planted: (l + m)
        p = (shreal(2 * l - 1) * w.z * p1 - shreal(k) * p2) / shreal(l - m);
      }
      p2 = p1;
      p1 = p;
      shreal kp = shNorm(l, m) * p;
      if (m == 0) {
        r.c[shIndex(l, 0)] = kp;
      } else {
        shreal s = SHR(1.4142135623730950488) * kp;
#ifdef FT_FAULT_MS_SH_CONDON_SHORTLEY
        if (m % 2 == 1) s = -s;  // planted (GPU only): the (−1)^m phase
#endif
        r.c[shIndex(l, m)] = s * cm;
        r.c[shIndex(l, -m)] = s * sm;
      }
    }
  }
  return r;
}

// ---- Rotation (Ivanic & Ruedenberg 1996) --------------------------------------
FT_FUNC shreal shComponent(shvec3 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }
// Axis of the band-1 index m ∈ {−1, 0, 1}: Y_1 = √(3/4π)(y, z, x).
FT_FUNC int shBand1Axis(int m) { return m == -1 ? 1 : (m == 0 ? 2 : 0); }

// P^l_{i; a, b} of Ivanic & Ruedenberg Table 2 from band 1 and band l − 1, as
// a macro: a function taking the 286-entry ShRotation by value makes GLSL
// copy it at every call site (llvmpipe then compiles for minutes). Indices
// are clamped into the array: GLSL may evaluate both arms of ?:.
// Storage of the matrices: the struct's array, unless the includer (a GLSL
// shader) redirects it first. llvmpipe turns every dynamically indexed
// access to a private array into a branch ladder over its elements (286
// here): compiling the rotation took 20+ s; a shader maps these to a scratch
// storage buffer instead (prt_multiple_scattering.comp.glsl).
#ifndef SH_ROT_LOAD
#define SH_ROT_LOAD(R_, I_) (R_).m[I_]
#define SH_ROT_STORE(R_, I_, V_) (R_).m[I_] = (V_)
#endif
#define SH_ROT_AT(R_, L_, M_, N_) SH_ROT_LOAD(R_, clamp(shRotationIndex((L_), (M_), (N_)), 0, FT_SH_ROTATION_SIZE - 1))
#define SH_ROT_P(R_, I_, A_, B_, L_)                                                                    \
  ((B_) == (L_) ? SH_ROT_AT(R_, 1, I_, 1) * SH_ROT_AT(R_, (L_) - 1, A_, (L_) - 1) -                    \
                      SH_ROT_AT(R_, 1, I_, -1) * SH_ROT_AT(R_, (L_) - 1, A_, -(L_) + 1)                \
                : ((B_) == -(L_) ? SH_ROT_AT(R_, 1, I_, 1) * SH_ROT_AT(R_, (L_) - 1, A_, -(L_) + 1) +  \
                                       SH_ROT_AT(R_, 1, I_, -1) * SH_ROT_AT(R_, (L_) - 1, A_, (L_) - 1) \
                                 : SH_ROT_AT(R_, 1, I_, 0) * SH_ROT_AT(R_, (L_) - 1, A_, B_)))

// The matrices M^0..M^{bands−1} of the rotation ω ↦ (rx·ω, ry·ω, rz·ω).
FT_FUNC ShRotation shRotation(shvec3 rx, shvec3 ry, shvec3 rz, int bands) {
  ShRotation r;
  for (int i = 0; i < FT_SH_ROTATION_SIZE; ++i) SH_ROT_STORE(r, i, SHR(0.0));
  SH_ROT_STORE(r, 0, SHR(1.0));
  if (bands < 2) return r;
  for (int m = -1; m <= 1; ++m) {
    int am = shBand1Axis(m);
    shvec3 row = am == 0 ? rx : (am == 1 ? ry : rz);
    for (int n = -1; n <= 1; ++n) SH_ROT_STORE(r, shRotationIndex(1, m, n), shComponent(row, shBand1Axis(n)));
  }
  for (int l = 2; l < bands; ++l) {
    for (int m = -l; m <= l; ++m) {
      int am = m < 0 ? -m : m;
      shreal d = m == 0 ? SHR(1.0) : SHR(0.0);
      for (int n = -l; n <= l; ++n) {
        int an = n < 0 ? -n : n;
        shreal denom = an == l ? shreal(2 * l * (2 * l - 1)) : shreal((l + n) * (l - n));
        shreal value = SHR(0.0);
        if (am < l) value += sqrt(shreal((l + m) * (l - m)) / denom) * SH_ROT_P(r, 0, m, n, l);  // u U
        shreal v = SHR(0.5) * sqrt((SHR(1.0) + d) * shreal((l + am - 1) * (l + am)) / denom) * (SHR(1.0) - SHR(2.0) * d);
        shreal vv;
        if (m == 0) vv = SH_ROT_P(r, 1, 1, n, l) + SH_ROT_P(r, -1, -1, n, l);
        else if (m > 0)
          vv = SH_ROT_P(r, 1, m - 1, n, l) * (m == 1 ? SHR(1.4142135623730950488) : SHR(1.0)) -
               (m == 1 ? SHR(0.0) : SH_ROT_P(r, -1, -m + 1, n, l));
        else
          vv = (m == -1 ? SHR(0.0) : SH_ROT_P(r, 1, m + 1, n, l)) +
               SH_ROT_P(r, -1, -m - 1, n, l) * (m == -1 ? SHR(1.4142135623730950488) : SHR(1.0));
        value += v * vv;
        if (m != 0 && am <= l - 2) {
          shreal w = SHR(-0.5) * sqrt(shreal((l - am - 1) * (l - am)) / denom);
          shreal ww = m > 0 ? SH_ROT_P(r, 1, m + 1, n, l) + SH_ROT_P(r, -1, -m - 1, n, l)
                            : SH_ROT_P(r, 1, m - 1, n, l) - SH_ROT_P(r, -1, -m + 1, n, l);
          value += w * ww;
        }
        SH_ROT_STORE(r, shRotationIndex(l, m, n), value);
      }
    }
  }
  return r;
}

// M c, band by band, for the first `bands` bands (the rest copied as 0).
FT_FUNC ShCoeffs shRotate(ShRotation r, ShCoeffs c, int bands) {
  ShCoeffs o = shZero();
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) {
      shreal s = SHR(0.0);
      for (int n = -l; n <= l; ++n) s += SH_ROT_LOAD(r, shRotationIndex(l, m, n)) * c.c[shIndex(l, n)];
      o.c[shIndex(l, m)] = s;
    }
  return o;
}

// Three functions (rgb) at once: M c per channel, one pass over the matrix.
struct ShCoeffs3 {
  shvec3 c[FT_SH_COEFFS];
};
FT_FUNC ShCoeffs3 shRotate3(ShRotation r, ShCoeffs3 c, int bands) {
  ShCoeffs3 o;
  for (int j = 0; j < FT_SH_COEFFS; ++j) o.c[j] = shvec3(SHR(0.0));
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) {
      shvec3 s = shvec3(SHR(0.0));
      for (int n = -l; n <= l; ++n) s += SH_ROT_LOAD(r, shRotationIndex(l, m, n)) * c.c[shIndex(l, n)];
      o.c[shIndex(l, m)] = s;
    }
  return o;
}

// A zonal vector z (z[l] = c_l0 about +z) turned to the axis ξ, given
// y = Y(ξ) (addition theorem): c_lm = √(4π/(2l + 1)) z_l Y_lm(ξ).
FT_FUNC ShCoeffs shZonalFromY(shreal z[FT_SH_BANDS], ShCoeffs y, int bands) {
  ShCoeffs o = shZero();
  for (int l = 0; l < bands; ++l) {
    shreal s = sqrt(SHR(12.566370614359172953850573533118) / shreal(2 * l + 1)) * z[l];
    for (int m = -l; m <= l; ++m) o.c[shIndex(l, m)] = s * y.c[shIndex(l, m)];
  }
  return o;
}
FT_FUNC ShCoeffs shRotateZonal(shreal z[FT_SH_BANDS], shvec3 xi, int bands) { return shZonalFromY(z, shEval(xi), bands); }

FT_NAMESPACE_END
#endif  // FT_SH_H
