// sh_test.cpp — real spherical harmonics and their rotation (common/sh.h) in
// double, against what this file computes without common/: std::sph_legendre
// (C++17, which carries the Condon–Shortley phase; removed here), its own
// Gauss–Legendre nodes (Newton on P_n) times a trapezoid in φ, random
// rotations from quaternions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "common/sh.h"
#include "validation/draw_order.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The oracle: real Y_lm without the Condon–Shortley phase.
double oracleY(int l, int m, glm::dvec3 w) {
  const double theta = std::acos(std::clamp(w.z, -1.0, 1.0));
  const double phi = std::atan2(w.y, w.x);
  const int am = std::abs(m);
  const double p = std::sph_legendre(unsigned(l), unsigned(am), theta) * ((am % 2) ? -1.0 : 1.0);
  if (m == 0) return p;
  return std::sqrt(2.0) * p * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}

// n-point Gauss–Legendre on [−1, 1] by Newton's method on P_n.
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.resize(size_t(n));
  w.resize(size_t(n));
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[size_t(i)] = z;
    w[size_t(i)] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  const glm::dvec3 v = drawVec3<glm::dvec3>(n, rng);
  return v / glm::length(v);
}

// A random rotation as its three rows.
struct Rot {
  glm::dvec3 r[3];
  glm::dvec3 apply(glm::dvec3 v) const { return {glm::dot(r[0], v), glm::dot(r[1], v), glm::dot(r[2], v)}; }
};
Rot randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  double q[4] = {n(rng), n(rng), n(rng), n(rng)};
  const double s = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double a = q[0] / s, b = q[1] / s, c = q[2] / s, d = q[3] / s;
  Rot R;
  R.r[0] = {a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)};
  R.r[1] = {2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)};
  R.r[2] = {2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d};
  return R;
}
Rot compose(const Rot& A, const Rot& B) {  // A·B
  Rot C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 3; ++k) s += A.r[i][k] * B.r[k][j];
      C.r[i][j] = s;
    }
  return C;
}
ShRotation shRot(const Rot& R) { return shRotation(R.r[0], R.r[1], R.r[2], FT_SH_BANDS); }

TEST(Sh, ConventionMatchesOracleWithoutCondonShortley) {
  std::mt19937_64 rng(1);
  double worst = 0.0;
  for (int t = 0; t < 500; ++t) {
    const glm::dvec3 w = randomUnit(rng);
    const ShCoeffs y = shEval(w);
    for (int l = 0; l < FT_SH_BANDS; ++l)
      for (int m = -l; m <= l; ++m) worst = std::max(worst, std::abs(y.c[shIndex(l, m)] - oracleY(l, m, w)));
  }
  EXPECT_LT(worst, 1e-13);
  // Band 1 is √(3/4π)(y, z, x): Y_11 > 0 on +x (no (−1)^m).
  const ShCoeffs x = shEval(glm::dvec3(1, 0, 0));
  EXPECT_NEAR(x.c[shIndex(1, 1)], std::sqrt(3.0 / (4.0 * kPi)), 1e-15);
  EXPECT_GT(x.c[shIndex(5, 5)], 0.0);
  const ShCoeffs z = shEval(glm::dvec3(0, 0, 1));
  for (int l = 0; l < FT_SH_BANDS; ++l) EXPECT_NEAR(z.c[shIndex(l, 0)], std::sqrt((2 * l + 1) / (4 * kPi)), 1e-14);
}

TEST(Sh, OrthonormalByQuadrature) {
  // 32 Gauss–Legendre nodes in z (exact to degree 63) × 64 φ nodes (exact for
  // trigonometric degree < 64): the products (degree ≤ 10) integrate exactly.
  std::vector<double> gx, gw;
  gaussLegendre(32, gx, gw);
  const int nphi = 64;
  std::vector<double> gram(FT_SH_COEFFS * FT_SH_COEFFS, 0.0), proj(FT_SH_COEFFS, 0.0);
  for (size_t i = 0; i < gx.size(); ++i)
    for (int k = 0; k < nphi; ++k) {
      const double z = gx[i], s = std::sqrt(1.0 - z * z), phi = 2.0 * kPi * (k + 0.5) / nphi;
      const double wt = gw[i] * 2.0 * kPi / nphi;
      const ShCoeffs y = shEval(glm::dvec3(s * std::cos(phi), s * std::sin(phi), z));
      for (int a = 0; a < FT_SH_COEFFS; ++a) {
        proj[size_t(a)] += wt * y.c[a];
        for (int b = 0; b < FT_SH_COEFFS; ++b) gram[size_t(a * FT_SH_COEFFS + b)] += wt * y.c[a] * y.c[b];
      }
    }
  double worst = 0.0;
  for (int a = 0; a < FT_SH_COEFFS; ++a)
    for (int b = 0; b < FT_SH_COEFFS; ++b)
      worst = std::max(worst, std::abs(gram[size_t(a * FT_SH_COEFFS + b)] - (a == b ? 1.0 : 0.0)));
  EXPECT_LT(worst, 1e-12);
  // Projection of f ≡ 1: (√(4π), 0, …).
  EXPECT_NEAR(proj[0], std::sqrt(4.0 * kPi), 1e-12);
  for (int a = 1; a < FT_SH_COEFFS; ++a) EXPECT_NEAR(proj[size_t(a)], 0.0, 1e-12) << "j = " << a;
}

TEST(Sh, RotationIsPointwiseAndOrthogonal) {
  std::mt19937_64 rng(7);
  double pointwise = 0.0, orth = 0.0;
  for (int t = 0; t < 50; ++t) {
    const Rot R = randomRotation(rng);
    const ShRotation M = shRot(R);
    for (int s = 0; s < 20; ++s) {
      const glm::dvec3 w = randomUnit(rng);
      const ShCoeffs a = shRotate(M, shEval(w), FT_SH_BANDS);
      const ShCoeffs b = shEval(R.apply(w));
      for (int j = 0; j < FT_SH_COEFFS; ++j) pointwise = std::max(pointwise, std::abs(a.c[j] - b.c[j]));
    }
    for (int l = 0; l < FT_SH_BANDS; ++l)
      for (int i = -l; i <= l; ++i)
        for (int k = -l; k <= l; ++k) {
          double s = 0.0;
          for (int n = -l; n <= l; ++n) s += M.m[shRotationIndex(l, i, n)] * M.m[shRotationIndex(l, k, n)];
          orth = std::max(orth, std::abs(s - (i == k ? 1.0 : 0.0)));
        }
  }
  EXPECT_LT(pointwise, 1e-12);
  EXPECT_LT(orth, 1e-12);
}

TEST(Sh, RotationKeepsBandNormsAndComposes) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n;
  double normErr = 0.0, compErr = 0.0;
  for (int t = 0; t < 30; ++t) {
    const Rot A = randomRotation(rng), B = randomRotation(rng);
    ShCoeffs c;
    for (double& v : c.c) v = n(rng);
    const ShCoeffs a = shRotate(shRot(A), c, FT_SH_BANDS);
    for (int l = 0; l < FT_SH_BANDS; ++l) {
      double n0 = 0.0, n1 = 0.0;
      for (int m = -l; m <= l; ++m) n0 += c.c[shIndex(l, m)] * c.c[shIndex(l, m)], n1 += a.c[shIndex(l, m)] * a.c[shIndex(l, m)];
      normErr = std::max(normErr, std::abs(std::sqrt(n1) - std::sqrt(n0)));
    }
    const ShCoeffs ba = shRotate(shRot(B), a, FT_SH_BANDS);
    const ShCoeffs direct = shRotate(shRot(compose(B, A)), c, FT_SH_BANDS);
    for (int j = 0; j < FT_SH_COEFFS; ++j) compErr = std::max(compErr, std::abs(ba.c[j] - direct.c[j]));
  }
  EXPECT_LT(normErr, 1e-12);
  EXPECT_LT(compErr, 1e-12);
}

TEST(Sh, RotatedFunctionIsTheFunctionRotated) {
  // M c are the coefficients of g(Rω) = f(ω): check g at sample points.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n;
  ShCoeffs c;
  for (double& v : c.c) v = n(rng);
  const Rot R = randomRotation(rng);
  const ShCoeffs g = shRotate(shRot(R), c, FT_SH_BANDS);
  for (int s = 0; s < 50; ++s) {
    const glm::dvec3 w = randomUnit(rng);
    const ShCoeffs y0 = shEval(w), y1 = shEval(R.apply(w));
    double f = 0.0, gv = 0.0;
    for (int j = 0; j < FT_SH_COEFFS; ++j) f += c.c[j] * y0.c[j], gv += g.c[j] * y1.c[j];
    EXPECT_NEAR(gv, f, 1e-12);
  }
}

TEST(Sh, ZonalRotationByAdditionTheorem) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n;
  for (int t = 0; t < 20; ++t) {
    double z[FT_SH_BANDS];
    ShCoeffs c = shZero();
    for (int l = 0; l < FT_SH_BANDS; ++l) z[l] = n(rng), c.c[shIndex(l, 0)] = z[l];
    // A rotation taking +z to ξ: its third column is ξ.
    const Rot R = randomRotation(rng);
    const glm::dvec3 xi(R.r[0].z, R.r[1].z, R.r[2].z);
    const ShCoeffs full = shRotate(shRot(R), c, FT_SH_BANDS);
    const ShCoeffs zonal = shRotateZonal(z, xi, FT_SH_BANDS);
    for (int j = 0; j < FT_SH_COEFFS; ++j) EXPECT_NEAR(zonal.c[j], full.c[j], 1e-12) << "j = " << j;
  }
}

}  // namespace
}  // namespace ft
