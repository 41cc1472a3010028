// bcsdf.h — the fiber scattering function every shaded picture uses, on the
// CPU (reference, Embree ground truth, tables) and in GLSL (fragment and
// compute shaders). Wu & Yuksel 2019 (000) §4.3:
//   * eq. 6: the two-lobe R/TT BCSDF of Khungurn et al. 2015 (TRT omitted),
//       f = F(θ_i) M_R N_R + (1 − F(θ_i)) C_TT M_TT N_TT(φ),
//     with the fabric presets of data/fabric-bcsdf.tsv;
//   * eq. 5: the simple model f_spec = k_s cos(φ/2) exp(−θ_h²/2β²);
//   * eq. 7–10: the ambient integral A(θ_o), baked as a 1D table over θ_o.
// Conventions (docs/shading.md): directions point away from the fiber (ω_i
// towards the light, ω_o towards the eye); sin θ = ω·t; φ is the azimuth
// between ω_i and ω_o around t, in [0, π] (f is even in φ); TT peaks at
// φ = π, the specular cone is θ_o = −θ_i.
//
// Numerics: the R lobe of silk and cotton is 1° wide, so every function takes
// angles, not directions (an angle error of 1e-6 rad is 2e-4 of the lobe at
// β = 1°), and directions become angles through an arctangent written out
// here (ftAtan2: GLSL's asin is good to only 4e-4 rad on Mesa); the
// longitudinal normaliser Z(θ_i) is exact (closed form where the lobe is
// inside (−π/2, π/2), 20-point Gauss–Legendre over ±6β otherwise) and the von
// Mises normaliser uses the exponentially scaled Bessel function I0e (GLSL has
// no I0; I0(κ) overflows float at κ ≈ 90).
#ifndef FT_BCSDF_H
#define FT_BCSDF_H
#include "prelude.h"

// Planted faults (validation/faults.def). The shared one lives here and so runs
// on both sides: the C++ side reads a run-time switch (the harness turns it
// on), the GLSL side the define.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultBcsdfNormThetaI = false;
inline bool ftFaultLobeNormTexelAngle = false;
}
#define FT_FAULT_BCSDF_NORM_THETA_I_ON ::ft::ftFaultBcsdfNormThetaI
#define FT_FAULT_LOBE_NORM_TEXEL_ANGLE_ON ::ft::ftFaultLobeNormTexelAngle
#else
#if defined(FT_FAULT_BCSDF_NORM_THETA_I)
#define FT_FAULT_BCSDF_NORM_THETA_I_ON true
#else
#define FT_FAULT_BCSDF_NORM_THETA_I_ON false
#endif
#if defined(FT_FAULT_LOBE_NORM_TEXEL_ANGLE)
#define FT_FAULT_LOBE_NORM_TEXEL_ANGLE_ON true
#else
#define FT_FAULT_LOBE_NORM_TEXEL_ANGLE_ON false
#endif
#endif

FT_NAMESPACE_BEGIN

// One fabric of data/fabric-bcsdf.tsv, angles in radians (std140).
struct FabricParams {
  vec4 colorR;   // rgb C_R (Fresnel reflectance at normal incidence), w β_R
  vec4 colorTT;  // rgb C_TT (transmittance colour), w β_TT
  vec4 lobes;    // x γ_TT (azimuthal width of TT), y κ = γ_TT^−2, zw unused
};
FT_ASSERT_OFFSET(FabricParams, colorTT, 16)
FT_ASSERT_OFFSET(FabricParams, lobes, 32)
FT_ASSERT_SIZE(FabricParams, 48)

// Fiber-local angles of a pair of directions.
struct FiberAngles {
  float thetaI;  // incident longitudinal angle, [−π/2, π/2]
  float thetaO;  // outgoing longitudinal angle
  float phi;     // relative azimuth, [0, π]
};

// 20-point Gauss–Legendre on [−1, 1]: the positive nodes and their weights.
const float kFtGaussLegendre20X[10] = {0.0765265211334973f, 0.2277858511416451f, 0.3737060887154195f,
                                       0.5108670019508271f, 0.6360536807265150f, 0.7463319064601508f,
                                       0.8391169718222189f, 0.9122344282513259f, 0.9639719272779138f,
                                       0.9931285991850949f};
const float kFtGaussLegendre20W[10] = {0.1527533871307260f, 0.1491729864726038f, 0.1420961093183819f,
                                       0.1316886384491765f, 0.1181945319615183f, 0.1019301198172405f,
                                       0.0832767415767047f, 0.0626720483341090f, 0.0406014298003870f,
                                       0.0176140071391523f};

// Half-width of the window, in lobe widths, outside which a Gaussian lobe is
// taken as zero: e^(−18) ≈ 1.5e-8 of its peak.
const float kFtLobeWindow = 6.0f;

// I0(x)·e^(−x), x ≥ 0 (Abramowitz & Stegun 9.8.1 and 9.8.2: relative error
// below 1.6e-7 and 4.8e-7; in float 2.6e-7 and 5.5e-7, tests/bcsdf_test.cpp).
FT_FUNC float ftBesselI0e(float x) {
  x = abs(x);
  if (x < 3.75f) {
    float t = x / 3.75f;
    t = t * t;
    float i0 = 1.0f + t * (3.5156229f + t * (3.0899424f + t * (1.2067492f + t * (0.2659732f + t * (0.0360768f +
                                                                                             t * 0.0045813f)))));
    return i0 * exp(-x);
  }
  float u = 3.75f / x;
  float s = 0.39894228f + u * (0.01328592f + u * (0.00225319f + u * (-0.00157565f + u * (0.00916281f +
            u * (-0.02057706f + u * (0.02635537f + u * (-0.01647633f + u * 0.00392377f)))))));
  return s / sqrt(x);
}

// Normalised Gaussian g(x; β) of the longitudinal lobes.
FT_FUNC float ftGaussian(float x, float beta) {
  float r = x / beta;
  return exp(-0.5f * r * r) / (2.50662827463100050f * beta);
}

// Z(θ_i) = ∫_{−π/2}^{π/2} g(θ + θ_i; β) cos²θ dθ, so that M = g/Z carries unit
// energy over the outgoing θ for every θ_i (notes-rendering §0.2 [F]).
// Closed form ½(1 + e^(−2β²) cos 2θ_i) of the untruncated Gaussian while the
// lobe's ±6β window stays inside (−π/2, π/2); quadrature over the window
// clipped to it otherwise.
FT_FUNC float ftLongitudinalNormClosed(float thetaI, float beta) {
  return 0.5f * (1.0f + exp(-2.0f * beta * beta) * cos(2.0f * thetaI));
}
FT_FUNC float ftLongitudinalNorm(float thetaI, float beta) {
  float halfPi = 0.5f * FT_PI;
  if (abs(thetaI) + kFtLobeWindow * beta <= halfPi) return ftLongitudinalNormClosed(thetaI, beta);
  float lo = max(-halfPi, -thetaI - kFtLobeWindow * beta);
  float hi = min(halfPi, -thetaI + kFtLobeWindow * beta);
  float c = 0.5f * (lo + hi), h = 0.5f * (hi - lo);
  float sum = 0.0f;
  for (int k = 0; k < 10; ++k) {
    float d = h * kFtGaussLegendre20X[k];
    float ca = cos(c - d), cb = cos(c + d);
    sum += kFtGaussLegendre20W[k] * (ftGaussian(c - d + thetaI, beta) * ca * ca + ftGaussian(c + d + thetaI, beta) * cb * cb);
  }
  return max(h * sum, 1e-30f);
}

// The angle the lobes are normalised at: θ_i (the planted fault takes θ_o).
FT_FUNC float ftLobeNormAngle(FiberAngles a) { return FT_FAULT_BCSDF_NORM_THETA_I_ON ? a.thetaO : a.thetaI; }

// (Z_R, Z_TT) at θ, exact (ftLongitudinalNorm).
FT_FUNC vec2 ftLobeNorms(FabricParams p, float theta) {
  return vec2(ftLongitudinalNorm(theta, p.colorR.w), ftLongitudinalNorm(theta, p.colorTT.w));
}

// Longitudinal lobe M_p(θ_i, θ_o) = g(θ_o + θ_i; β_p) / Z_p(θ_i), Z given.
FT_FUNC float ftLongitudinalNormed(float thetaI, float thetaO, float beta, float z) {
  return ftGaussian(thetaO + thetaI, beta) / z;
}
FT_FUNC float ftLongitudinal(float thetaI, float thetaO, float beta) {
  float z = FT_FAULT_BCSDF_NORM_THETA_I_ON ? ftLongitudinalNorm(thetaO, beta)  // normalised over θ_i: wrong
                                           : ftLongitudinalNorm(thetaI, beta);
  return ftLongitudinalNormed(thetaI, thetaO, beta, z);
}

// ---- The lobe-normalisation table Z_p(|θ_i|) -------------------------------
// Z is even in θ_i and has the closed form while |θ_i| + 6β ≤ π/2; beyond, the
// 20-point quadrature above, which a fragment stage would run per light and
// lobe (on llvmpipe, which runs both sides of a branch, always: 0.8 s of a
// 7 s glove frame). The frame looks Z up instead: row p of the table holds Z_p
// at n angles evenly over [θ_lo, π/2], θ_lo = max(0, π/2 − 6β_p), where the
// quadrature applies; below θ_lo the closed form stays. Linear interpolation
// over a window of 6β in 255 steps is within 1.3e-4 of Z for every β
// (docs/shading.md). The ground truth (reference/fiber_trace.cpp) keeps the
// exact Z.
FT_FUNC float ftLobeNormTableStart(float beta) { return max(0.0f, 0.5f * FT_PI - kFtLobeWindow * beta); }
FT_FUNC float ftLobeNormTexelAngle(int k, int n, float beta) {
  float lo = ftLobeNormTableStart(beta);
  // The planted fault spaces the texels by 1/n: the last one short of π/2.
  return lo + float(k) * (0.5f * FT_PI - lo) / float(FT_FAULT_LOBE_NORM_TEXEL_ANGLE_ON ? n : n - 1);
}
// Lookup of |θ| in the row of β: x = the texel below, y = the one above
// (clamped), z = the weight of y; w = 1 where the closed form applies
// (|θ| below the row), 0 where the two texels are to be mixed.
FT_FUNC vec4 ftLobeNormLookup(float theta, float beta, int n) {
  float lo = ftLobeNormTableStart(beta);
  float a = abs(theta);
  if (a + kFtLobeWindow * beta <= 0.5f * FT_PI) return vec4(0.0f, 0.0f, 0.0f, 1.0f);
  float u = clamp((a - lo) / (0.5f * FT_PI - lo) * float(n - 1), 0.0f, float(n - 1));
  float k0 = min(floor(u), float(n - 1));
  float k1 = min(k0 + 1.0f, float(n - 1));
  return vec4(k0, k1, u - k0, 0.0f);
}
// Z from a lookup and the row's two texels.
FT_FUNC float ftLobeNormFromTable(vec4 lookup, float theta, float beta, float z0, float z1) {
  if (lookup.w != 0.0f) return ftLongitudinalNormClosed(theta, beta);
  return mix(z0, z1, lookup.z);
}

// Azimuthal TT lobe: a von Mises distribution centred at φ = π,
// N_TT(φ) = exp(κ cos(φ − π)) / (2π I0(κ)) = exp(−κ(1 + cos φ)) / (2π I0e(κ)).
FT_FUNC float ftAzimuthalTT(float phi, float kappa) {
#ifdef FT_FAULT_BCSDF_TT_FORWARD
  float c = -cos(phi);  // centred at φ = 0: TT scatters backwards
#else
  float c = cos(phi);
#endif
  return exp(-kappa * (1.0f + c)) / (FT_TWO_PI * ftBesselI0e(kappa));
}

// Schlick's Fresnel of 000 / the TSV: F = C_R + (1 − C_R)(1 − |cos θ_i|)^5, per channel.
FT_FUNC vec3 ftFiberFresnel(vec3 colorR, float thetaI) {
  float m = 1.0f - abs(cos(thetaI));
  float m2 = m * m;
  return colorR + (vec3(1.0f) - colorR) * (m2 * m2 * m);
}

// The R lobe F·M_R·N_R and the TT lobe (1 − F)·C_TT·M_TT·N_TT of eq. 6, with
// the lobes' normalisations z = (Z_R, Z_TT) at ftLobeNormAngle given (exact:
// ftLobeNorms; the frame's: its table).
FT_FUNC vec3 ftBcsdfRNormed(FabricParams p, FiberAngles a, float z) {
  return ftFiberFresnel(vec3(p.colorR), a.thetaI) * (ftLongitudinalNormed(a.thetaI, a.thetaO, p.colorR.w, z) / FT_TWO_PI);
}
FT_FUNC vec3 ftBcsdfTTNormed(FabricParams p, FiberAngles a, float z) {
  vec3 transmitted = (vec3(1.0f) - ftFiberFresnel(vec3(p.colorR), a.thetaI)) * vec3(p.colorTT);
#ifdef FT_FAULT_BCSDF_TT_STRONG
  transmitted *= 1.2f;  // TT lobe 20 % too strong (GLSL only: the GPU side)
#endif
  return transmitted * (ftLongitudinalNormed(a.thetaI, a.thetaO, p.colorTT.w, z) * ftAzimuthalTT(a.phi, p.lobes.y));
}
FT_FUNC vec3 ftBcsdfR(FabricParams p, FiberAngles a) {
  return ftBcsdfRNormed(p, a, ftLobeNorms(p, ftLobeNormAngle(a)).x);
}
FT_FUNC vec3 ftBcsdfTT(FabricParams p, FiberAngles a) {
  return ftBcsdfTTNormed(p, a, ftLobeNorms(p, ftLobeNormAngle(a)).y);
}

// f(ω_i, ω_o) of eq. 6, per RGB channel.
FT_FUNC vec3 ftBcsdfNormed(FabricParams p, FiberAngles a, vec2 z) {
  return ftBcsdfRNormed(p, a, z.x) + ftBcsdfTTNormed(p, a, z.y);
}
FT_FUNC vec3 ftBcsdf(FabricParams p, FiberAngles a) { return ftBcsdfNormed(p, a, ftLobeNorms(p, ftLobeNormAngle(a))); }

// Its albedo ∫∫ f cos²θ_o dθ_o dφ = F + (1 − F) C_TT (invariant B1): what the
// ambient table tends to as the lobes narrow.
FT_FUNC vec3 ftBcsdfAlbedo(FabricParams p, float thetaI) {
  vec3 f = ftFiberFresnel(vec3(p.colorR), thetaI);
  return f + (vec3(1.0f) - f) * vec3(p.colorTT);
}

// Simple model, eq. 5: k_s cos(φ/2) exp(−θ_h²/2β²), θ_h = (θ_i + θ_o)/2.
FT_FUNC float ftSimpleSpecular(float ks, float beta, FiberAngles a) {
#ifdef FT_FAULT_BCSDF_THETA_D
  float thetaH = 0.5f * (a.thetaO - a.thetaI);  // θ_d, not θ_h: the highlight leaves the specular cone
#else
  float thetaH = 0.5f * (a.thetaI + a.thetaO);
#endif
  float r = thetaH / beta;
  return ks * cos(0.5f * a.phi) * exp(-0.5f * r * r);
}

// atan2(y, x) in [−π, π] from arithmetic and one division only (Cephes atanf:
// reduction to |a| ≤ tan(π/8), degree-9 odd polynomial; error ≤ 3e-7 rad).
// GLSL leaves the precision of asin, acos and atan open, and Mesa's are
// polynomials good to 3.9e-4, 1.6e-4 and 3.3e-6 rad: 2% of the 1° lobe for
// asin. Written out here, the two sides agree to rounding. atan2(0, 0) = 0.
FT_FUNC float ftAtan2(float y, float x) {
  float ax = abs(x), ay = abs(y);
  float hi = max(ax, ay), lo = min(ax, ay);
  float a = hi > 0.0f ? lo / hi : 0.0f;  // [0, 1]
  float base = 0.0f;
  if (a > 0.41421356f) {  // atan(a) = π/4 + atan((a − 1)/(a + 1))
    a = (a - 1.0f) / (a + 1.0f);
    base = 0.25f * FT_PI;
  }
  float z = a * a;
  float r = base + ((((0.0805374449538f * z - 0.138776856032f) * z + 0.199777106478f) * z - 0.333329491539f) * z * a + a);
  if (ay > ax) r = 0.5f * FT_PI - r;
  if (x < 0.0f) r = FT_PI - r;
  return y < 0.0f ? -r : r;
}

// Angles of (ω_i, ω_o) about the unit tangent t (ω_i, ω_o of any length):
// θ = atan2(ω·t, |ω⊥|) and φ = atan2(|ω_i⊥ × ω_o⊥|, ω_i⊥·ω_o⊥), well
// conditioned everywhere, unlike asin(ω·t) near the poles and acos near
// φ = 0, π. φ = 0 when either direction is parallel to t, where φ is
// undefined (and the cos θ of the measure vanishes).
FT_FUNC FiberAngles ftFiberAngles(vec3 t, vec3 wi, vec3 wo) {
  FiberAngles a;
  float si = dot(wi, t);
  float so = dot(wo, t);
  vec3 pi = wi - si * t;
  vec3 po = wo - so * t;
  float pi2 = dot(pi, pi), po2 = dot(po, po);
  a.thetaI = ftAtan2(si, sqrt(pi2));
  a.thetaO = ftAtan2(so, sqrt(po2));
  a.phi = pi2 * po2 > 1e-24f ? ftAtan2(length(cross(pi, po)), dot(pi, po)) : 0.0f;
  return a;
}

// ---- The ambient table A(θ_o) of eq. 7–10 ---------------------------------
// A(θ_o) = ∫ [F M_R + (1 − F) C_TT M_TT](θ_i, θ_o) cos²θ_i dθ_i (the
// azimuthal integrals are 1, B4); texel k holds θ_k = −π/2 + (k + ½)π/N.
FT_FUNC float ftAmbientTexelAngle(int k, int n) { return -0.5f * FT_PI + (float(k) + 0.5f) * FT_PI / float(n); }

// Lookup coordinate of θ_o: x = the texel below, y = the one above (clamped),
// z = the weight of y. Callers fetch the two texels and mix (no sampler
// filtering: its weight precision is implementation-defined).
FT_FUNC vec3 ftAmbientLookup(float thetaO, int n) {
#ifdef FT_FAULT_AMBIENT_TEXEL_OFFSET
  float u = (thetaO + 0.5f * FT_PI) / FT_PI * float(n);  // no half-texel shift: off by half a texel
#else
  float u = (thetaO + 0.5f * FT_PI) / FT_PI * float(n) - 0.5f;
#endif
  u = clamp(u, 0.0f, float(n - 1));
  float k0 = min(floor(u), float(n - 1));
  float k1 = min(k0 + 1.0f, float(n - 1));
  return vec3(k0, k1, u - k0);
}

FT_NAMESPACE_END
#endif  // FT_BCSDF_H
