// yarn_density.h — the ply-density field ρ of a yarn cross-section and its
// exact line integral: the one definition of "how many fibers are in the
// way" that the self-shadow slices (000 §4.1) and the ambient-occlusion
// texture (000 §4.2) are baked from (notes-rendering §0.3).
//
// Wu & Yuksel 2019 (000) §4.1–4.2 shadow with "the density function that we
// use for placing the fibers": Zhao et al. 2016's p(R), the acceptance
// probability of a uniform-disk proposal, so the fibers' spatial density in
// the unit ply disk is ∝ p(R) for R ≤ R_max (reference-data §2). In the
// yarn cross-section (coordinates (x, y) along the yarn frame's (N̂, B̂)),
// ply j of n_ply sits at c_j = (R^ply/2)(cos ϑ_j, sin ϑ_j), ϑ_j = 2πj/n_ply + ψ
// with ψ the ply twist angle of the slice, its short semi-axis e_N along c_j
// (000 §3.1, fiber_geometry.h ftPlyFrame). The number density (fibers per
// unit area) is
//   ρ(x) = Σ_j n_f p(r_j(x)) / (e_N e_B Z),   Z = ∫_0^{R_max} p(r) 2πr dr,
//   r_j(x) = |((x − c_j)·N̂_j / e_N, (x − c_j)·B̂_j / e_B)|,  r_j ≤ R_max,
// so ∫ρ dA = n_ply n_f. Migration, hair and loop fibers are not in it
// (000 §4.2 ignores flyaways for AO; notes §0.3).
//
// τ(x, d) = ∫_0^∞ ρ(x + s d) ds (fibers per unit length crossed) is exact up
// to Gauss–Legendre quadrature of a smooth integrand: per ply, the chord of
// the ellipse r_j ≤ R_max is found in closed form (p jumps to 0 at the
// boundary when ε > 0, so no quadrature crosses it), split at the point of
// closest approach to the ply centre (where r_j(s) has a corner when the
// line passes through the centre), and each piece integrated with 16-point
// Gauss–Legendre.
#ifndef FT_YARN_DENSITY_H
#define FT_YARN_DENSITY_H
#include "prelude.h"

FT_NAMESPACE_BEGIN

// The density model of one preset, in the units of the fitted yarn (std140).
struct YarnDensityParams {
  uint plyCount;          // n^ply
  uint fiberCount;        // n_f: fibers per ply
  float plyRadius;        // |c_j| = yarn_radius / 2
  float ellipseN;         // e_N (ellipse_short)
  float ellipseB;         // e_B (ellipse_long)
  float epsilon;          // ε of p(R)
  float beta;             // β of p(R)
  float rMax;             // R_max of p(R) (unit ply disk)
  float normalization;    // n_f / (e_N e_B Z): ρ_j = normalization · p(r_j); ftDensityNormalization
  float plyTwistSign;     // ±1: direction of the ply twist (YarnParams.plyTwistSign)
  float supportRadius;    // W = plyRadius + max(e_N, e_B) R_max: ρ = 0 for |x| > W
  float pad0;
};
FT_ASSERT_OFFSET(YarnDensityParams, normalization, 32)
FT_ASSERT_OFFSET(YarnDensityParams, supportRadius, 40)
FT_ASSERT_SIZE(YarnDensityParams, 48)

// 16-point Gauss–Legendre on [−1, 1]: positive nodes and their weights.
const float kFtGaussLegendre16X[8] = {0.0950125098376374f, 0.2816035507792589f, 0.4580167776572274f,
                                      0.6178762444026438f, 0.7554044083550030f, 0.8656312023878318f,
                                      0.9445750230732326f, 0.9894009349916499f};
const float kFtGaussLegendre16W[8] = {0.1894506104550685f, 0.1826034150449236f, 0.1691565193950025f,
                                      0.1495959888165767f, 0.1246289712555339f, 0.0951585116824928f,
                                      0.0622535239386479f, 0.0271524594117541f};

// Zhao et al. 2016's fiber-placement density p(R), R in unit-ply-disk units
// (reference-data §2); 0 outside [0, R_max].
FT_FUNC float ftFiberPlacementDensity(YarnDensityParams d, float r) {
  if (r > d.rMax) return 0.0f;
  const float e = 2.71828182845904523536f;
  float t = max((e - exp(r / d.rMax)) / (e - 1.0f), 0.0f);
  return (1.0f - 2.0f * d.epsilon) * pow(t, d.beta) + d.epsilon;
}

// Z = ∫_0^{R_max} p(r) 2πr dr by 4 × 16-point Gauss–Legendre (p is smooth on
// [0, R_max]; its derivative is unbounded only at R_max when β < 1).
FT_FUNC float ftFiberPlacementMass(YarnDensityParams d) {
  float sum = 0.0f;
  for (int piece = 0; piece < 4; ++piece) {
    float a = d.rMax * float(piece) * 0.25f;
    float h = d.rMax * 0.125f;  // half-width of the piece
    float m = a + h;
    for (int k = 0; k < 8; ++k) {
      float dx = h * kFtGaussLegendre16X[k];
      float rl = m - dx, rr = m + dx;
      sum += kFtGaussLegendre16W[k] * h *
             (ftFiberPlacementDensity(d, rl) * rl + ftFiberPlacementDensity(d, rr) * rr);
    }
  }
  return FT_TWO_PI * sum;
}

FT_FUNC float ftDensityNormalization(YarnDensityParams d) {
  return float(d.fiberCount) / (d.ellipseN * d.ellipseB * ftFiberPlacementMass(d));
}

// Centre of ply j at slice angle ψ (radians), and its (N̂_j, B̂_j): N̂_j points
// from the yarn centre to the ply centre, B̂_j = rot90(N̂_j) (T̂ × N̂ in 3D).
FT_FUNC vec2 ftPlyDirection(YarnDensityParams d, uint ply, float psi) {
  float angle = FT_TWO_PI * float(ply) / float(d.plyCount) + psi;
  return vec2(cos(angle), sin(angle));
}

// Number density of ply j at cross-section point x.
FT_FUNC float ftPlyDensity(YarnDensityParams d, uint ply, float psi, vec2 x) {
  vec2 n = ftPlyDirection(d, ply, psi);
  vec2 q = x - d.plyRadius * n;
  vec2 local = vec2(dot(q, n) / d.ellipseN, (q.y * n.x - q.x * n.y) / d.ellipseB);
  return d.normalization * ftFiberPlacementDensity(d, length(local));
}

FT_FUNC float ftYarnDensity(YarnDensityParams d, float psi, vec2 x) {
  float rho = 0.0f;
  for (uint j = 0u; j < d.plyCount; ++j) rho += ftPlyDensity(d, j, psi, x);
  return rho;
}

// ∫ p(|q0 + s q1|) ds over [s0, s1] with 16-point Gauss–Legendre (local,
// unit-disk coordinates; the interval lies inside the R_max ellipse).
FT_FUNC float ftPlacementDensityIntegral(YarnDensityParams d, vec2 q0, vec2 q1, float s0, float s1) {
  float h = 0.5f * (s1 - s0);
  if (!(h > 0.0f)) return 0.0f;
  float m = 0.5f * (s0 + s1);
  float sum = 0.0f;
  for (int k = 0; k < 8; ++k) {
    float dx = h * kFtGaussLegendre16X[k];
    // Inside the chord by construction; the min keeps rounding at its ends off the p = 0 branch.
    float rl = min(length(q0 + (m - dx) * q1), d.rMax);
    float rr = min(length(q0 + (m + dx) * q1), d.rMax);
    sum += kFtGaussLegendre16W[k] * (ftFiberPlacementDensity(d, rl) + ftFiberPlacementDensity(d, rr));
  }
  return sum * h;
}

// ∫_{sA}^{sB} ρ_j(x + s dir) ds for one ply, dir a unit vector, sA < sB
// (sB may be large: only the chord inside the ply counts).
FT_FUNC float ftPlyLineIntegral(YarnDensityParams d, uint ply, float psi, vec2 x, vec2 dir, float sA, float sB) {
  vec2 n = ftPlyDirection(d, ply, psi);
  vec2 q = x - d.plyRadius * n;
  // Local unit-disk coordinates: q(s) = q0 + s q1.
  vec2 q0 = vec2(dot(q, n) / d.ellipseN, (q.y * n.x - q.x * n.y) / d.ellipseB);
  vec2 q1 = vec2(dot(dir, n) / d.ellipseN, (dir.y * n.x - dir.x * n.y) / d.ellipseB);
  // |q0 + s q1|² = R_max²: a s² + 2 b s + c = 0.
  float a = dot(q1, q1);
  float b = dot(q0, q1);
  float c = dot(q0, q0) - d.rMax * d.rMax;
  float disc = b * b - a * c;
  if (!(disc > 0.0f) || !(a > 0.0f)) return 0.0f;
  float root = sqrt(disc);
  // Roots without cancellation (Numerical Recipes §5.6).
  float qq = -(b + (b >= 0.0f ? root : -root));
  float r0 = qq / a;
  float r1 = qq != 0.0f ? c / qq : -r0;
  float sIn = max(min(r0, r1), sA);
  float sOut = min(max(r0, r1), sB);
  if (!(sOut > sIn)) return 0.0f;
  // Closest approach to the ply centre (in local units), clamped into the chord.
  float sMid = clamp(-b / a, sIn, sOut);
  return d.normalization * (ftPlacementDensityIntegral(d, q0, q1, sIn, sMid) +
                            ftPlacementDensityIntegral(d, q0, q1, sMid, sOut));
}

// τ(x, dir) = ∫_0^∞ ρ(x + s dir) ds: fibers per unit length crossed by the
// half-line from x along the unit vector dir, at slice angle ψ.
FT_FUNC float ftDensityLineIntegral(YarnDensityParams d, float psi, vec2 x, vec2 dir) {
  float tau = 0.0f;
  for (uint j = 0u; j < d.plyCount; ++j) tau += ftPlyLineIntegral(d, j, psi, x, dir, 0.0f, 3.0e38f);
  return tau;
}

FT_NAMESPACE_END
#endif  // FT_YARN_DENSITY_H
