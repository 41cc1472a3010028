// srbf_test.cpp — SRBF environment lighting (001 §4.5; common/srbf.h,
// common/srbf_bcsdf.h, reference/srbf_fit.h, reference/srbf_table.h) on the
// CPU, against expectations written here: the documented conventions, the
// closed forms of reference-data §7, brute-force NNLS, the ambient table, and
// the shipped environment map (docs/srbf.md). The GPU twins and the oracle
// are exercised by the srbf/* harness cases.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "image/image_io.h"
#include "reference/bcsdf_tables.h"
#include "reference/srbf_fit.h"
#include "reference/srbf_table.h"
#include "scene/fabric.h"
#include "test_data.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(SrbfMath, BesselI0eDoubleMatchesStd) {
  for (double x = 0.0; x <= 700.0; x += (x < 30 ? 0.37 : 11.3)) {
    const double ref = std::cyl_bessel_i(0.0, x) * std::exp(-x);
    EXPECT_NEAR(besselI0eDouble(x), ref, 2e-14 * ref) << "x = " << x;
  }
  // Continuous across the switch to the asymptotic series at 20.
  EXPECT_NEAR(besselI0eDouble(20.0 - 1e-12), besselI0eDouble(20.0), 1e-14);
}

TEST(SrbfMath, KernelAndIntegral) {
  const vec3 mu = ftNormalize(vec3(0.3f, 0.5f, -0.8f));
  EXPECT_FLOAT_EQ(ftSrbfKernel(mu, 3.0f, mu), 1.0f);
  EXPECT_NEAR(ftSrbfKernel(mu, 3.0f, -mu), std::exp(-6.0), 1e-8);
  for (double l : {0.0, 1e-5, 1e-3, 0.01, 0.0999, 0.1, 0.5, 1.885, 30.0, 512.0}) {
    const double ref = l == 0.0 ? 4 * kPi : 2 * kPi * -std::expm1(-2 * l) / l;
    // float: exp within a few ulp, 1 − e^{−2λ} cancels at small λ (series there)
    EXPECT_NEAR(ftSrbfIntegral(float(l)), ref, 2e-6 * ref) << "λ = " << l;
  }
}

// The documented equirect convention (docs/srbf.md), pixel by pixel.
TEST(SrbfMath, EquirectConvention) {
  const int w = 64, h = 32;
  double total = 0.0;
  for (int y = 0; y < h; ++y) {
    const double t0 = kPi * y / h, t1 = kPi * (y + 1) / h;
    EXPECT_NEAR(ftEquirectSolidAngle(y, w, h), 2 * kPi / w * (std::cos(t0) - std::cos(t1)), 1e-7);
    total += w * double(ftEquirectSolidAngle(y, w, h));
    for (int x = 0; x < w; ++x) {
      const double theta = kPi * (y + 0.5) / h, phi = 2 * kPi * (x + 0.5) / w - kPi;
      const vec3 d = ftEquirectDirection(x, y, w, h);
      EXPECT_NEAR(d.x, std::sin(theta) * std::cos(phi), 1e-6);
      EXPECT_NEAR(d.y, std::cos(theta), 1e-6);
      EXPECT_NEAR(d.z, std::sin(theta) * std::sin(phi), 1e-6);
      const vec2 uv = ftEquirectUv(d);
      EXPECT_NEAR(uv.x, (x + 0.5) / w, 1e-5);
      EXPECT_NEAR(uv.y, (y + 0.5) / h, 1e-5);
    }
  }
  EXPECT_NEAR(total, 4 * kPi, 1e-5);
  // Row 0 looks up; the centre column along +x; u = ¾ along +z (φ = atan2(z, x)).
  EXPECT_GT(ftEquirectDirection(10, 0, w, h).y, 0.99f);
  EXPECT_GT(ftEquirectDirection(w / 2, h / 2, w, h).x, 0.99f);
  EXPECT_GT(ftEquirectDirection(3 * w / 4, h / 2, w, h).z, 0.99f);
}

TEST(SrbfMath, FibonacciCentresAndLambda0) {
  const double golden = 0.5 * (1 + std::sqrt(5.0));
  for (int j = 0; j < 16; ++j) {
    const vec3 p = ftSrbfFibonacci(j, 16);
    const double y = 1 - (2 * j + 1) / 16.0;
    double f = j * (golden - 1);
    f -= std::floor(f);
    const double r = std::sqrt(1 - y * y);
    EXPECT_NEAR(p.x, r * std::cos(2 * kPi * f), 2e-6);
    EXPECT_NEAR(p.y, y, 1e-7);
    EXPECT_NEAR(p.z, r * std::sin(2 * kPi * f), 2e-6);
  }
  EXPECT_NEAR(ftSrbfInitialLambda(16), std::log(2.0) / (1 - std::cos(std::sqrt(kPi / 4))), 1e-5);
  EXPECT_NEAR(ftSrbfInitialLambda(16), 1.885, 1e-3);  // notes A9
}

// Lawson–Hanson against the exact NNLS optimum found by enumerating every
// active set (2^6 subproblems, each solved by Eigen and checked for KKT).
TEST(SrbfFit, NnlsMatchesEnumeration) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  const int n = 6;
  for (int trial = 0; trial < 40; ++trial) {
    Eigen::MatrixXd A(12, n);
    Eigen::VectorXd y(12);
    for (int i = 0; i < 12; ++i) {
      y(i) = g(rng);
      for (int j = 0; j < n; ++j) A(i, j) = g(rng);
    }
    const Eigen::MatrixXd K = A.transpose() * A;
    const Eigen::VectorXd b = A.transpose() * y;
    double best = 1e300;
    Eigen::VectorXd bestX = Eigen::VectorXd::Zero(n);
    for (int mask = 0; mask < (1 << n); ++mask) {
      std::vector<int> idx;
      for (int j = 0; j < n; ++j)
        if (mask & (1 << j)) idx.push_back(j);
      Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
      if (!idx.empty()) {
        Eigen::MatrixXd Ks(idx.size(), idx.size());
        Eigen::VectorXd bs(idx.size());
        for (size_t a = 0; a < idx.size(); ++a) {
          bs(Eigen::Index(a)) = b(idx[a]);
          for (size_t c = 0; c < idx.size(); ++c) Ks(Eigen::Index(a), Eigen::Index(c)) = K(idx[a], idx[c]);
        }
        const Eigen::VectorXd xs = Ks.ldlt().solve(bs);
        if ((xs.array() < 0).any()) continue;
        for (size_t a = 0; a < idx.size(); ++a) x(idx[a]) = xs(Eigen::Index(a));
      }
      const double f = (A * x - y).squaredNorm();
      if (f < best) best = f, bestX = x;
    }
    std::vector<double> kv(size_t(n * n)), bv(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      bv[size_t(i)] = b(i);
      for (int j = 0; j < n; ++j) kv[size_t(i * n + j)] = K(i, j);
    }
    const std::vector<double> x = solveNnlsNormal(kv, bv, n);
    for (int j = 0; j < n; ++j) EXPECT_NEAR(x[size_t(j)], bestX(j), 1e-9) << "trial " << trial << " j " << j;
  }
}

ImageRgbaF constantMap(int w, int h, glm::vec3 c) {
  ImageRgbaF img(w, h);
  for (size_t i = 0; i < img.pixelCount(); ++i) {
    img.pixels[4 * i] = c.x, img.pixels[4 * i + 1] = c.y, img.pixels[4 * i + 2] = c.z, img.pixels[4 * i + 3] = 1;
  }
  return img;
}

// Notes A9 C2: with the DC term (fibertwin's choice) a constant map is exact;
// the plain 16-lobe fit of 001 leaves a residual below the documented bound.
TEST(SrbfFit, ConstantEnvironment) {
  const ImageRgbaF env = constantMap(128, 64, glm::vec3(1.7f, 0.9f, 0.4f));
  const SrbfFit dc = fitSrbfCpu(env);
  EXPECT_NEAR(dc.environment.constant.x, 1.7, 1.7e-6);
  EXPECT_NEAR(dc.environment.constant.z, 0.4, 0.4e-6);
  for (int j = 0; j < FT_SRBF_LOBES; ++j) EXPECT_LT(glm::length(glm::vec3(dc.environment.lobes[j].weight)), 1e-6f);
  EXPECT_LT(srbfRelativeL2(env, dc.environment), 1e-6);
  SrbfFitOptions plain;
  plain.constantTerm = false;
  const double residual = srbfRelativeL2(env, fitSrbfCpu(env, plain).environment);
  std::printf("plain 16-lobe fit of a constant map: relative L2 %.5f\n", residual);
  EXPECT_LT(residual, 0.005);  // docs/srbf.md: measured 0.0029 at 128 × 64
  EXPECT_GT(residual, 1e-4);   // and not representable: a fit that claims otherwise is wrong
}

// The condition numbers the harness tolerances quote: 2.8e3 for the 16 lobes,
// 4.7e5 with the DC term (a constant is nearly spanned by 16 broad lobes).
TEST(SrbfFit, GramCondition) {
  const ImageRgbaF env = constantMap(128, 64, glm::vec3(1.0f));
  for (bool dc : {false, true}) {
    SrbfFitOptions o;
    o.constantTerm = dc;
    const SrbfNormalEquations eq = srbfNormalEquationsCpu(env, srbfFibonacciBasis(o));
    Eigen::MatrixXd K(eq.count, eq.count);
    for (int i = 0; i < eq.count; ++i)
      for (int j = 0; j < eq.count; ++j) K(i, j) = eq.gram[size_t(i * eq.count + j)];
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
    const double cond = ev.maxCoeff() / ev.minCoeff();
    std::printf("Gram condition number, %s DC term: %.3g\n", dc ? "with" : "without", cond);
    EXPECT_GT(ev.minCoeff(), 0.0);
    EXPECT_LT(cond, dc ? 1e6 : 1e4);  // measured 2.8e3 and 4.7e5
  }
}

// data/env/sky.exr is what `fibertwin env-sky` writes, and its fit errors are
// the ones docs/srbf.md states.
TEST(SrbfFit, ShippedSkyMap) {
  const ImageRgbaF file = readExr(test::repoDataFile("env/sky.exr"));
  const ImageRgbaF made = makeProceduralSky(256, 128);
  ASSERT_EQ(file.width, 256);
  ASSERT_EQ(file.height, 128);
  for (size_t i = 0; i < made.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(file.pixels[4 * i + c], made.pixels[4 * i + c]) << "pixel " << i;
  const double full = srbfRelativeL2(file, fitSrbfCpu(file).environment);
  const ImageRgbaF noSun = makeProceduralSky(256, 128, false);
  const double sky = srbfRelativeL2(noSun, fitSrbfCpu(noSun).environment);
  std::printf("sky.exr fit: relative L2 %.4f (the sun dominates); without the sun %.4f\n", full, sky);
  EXPECT_NEAR(full, 0.991, 0.002);
  EXPECT_NEAR(sky, 0.334, 0.003);
}

// λ → 0: every channel of I equals the ambient table's A(θ_o) (notes A10 C1);
// at λ = 0 exactly the SG is ≡ 1 and only float vs double cos θ_i differs.
TEST(SrbfTable, LambdaZeroIsAmbientTable) {
  const FabricParams p = findFabricPreset("gabardine").params();
  const std::vector<glm::dvec3> A = bakeAmbientTableCpuParts(p, 16).total();
  for (int k = 0; k < 16; ++k)
    for (double tj : {-1.0, 0.2})
      for (double dphi : {0.0, 2.5}) {
        const LobeValues v = srbfConvolutionCpu(p, ftAmbientTexelAngle(k, 16), tj, dphi, 0.0);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(v.r[c] + v.tt[c], A[size_t(k)][c], 1e-6 * A[size_t(k)][c]) << k;
      }
}

TEST(SrbfTable, AxesAndLookupAtTexels) {
  const glm::ivec4 d(5, 6, 4, 7);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(ftSrbfTableTheta(k, 6), std::asin(-1.0 + 2.0 * k / 5), 1e-6);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(ftSrbfTableDeltaPhi(k, 4), kPi * k / 3, 1e-6);
  for (int k = 0; k < 7; ++k) EXPECT_NEAR(ftSrbfTableLambda(k, 7), 0.5 * std::pow(1024.0, k / 6.0), 2e-6 * 512);
  std::vector<glm::vec3> table(size_t(ftSrbfTableSize(d)));
  for (size_t i = 0; i < table.size(); ++i) table[i] = glm::vec3(float(i), float(2 * i), 1.0f);
  for (int i = 0; i < ftSrbfTableSize(d); i += 7) {
    const ivec4 k = ftSrbfTableTexel(d, i);
    EXPECT_EQ(ftSrbfTableIndex(d, k), i);
    const glm::vec3 v = lookupSrbfTableCpu(table, d, ftSrbfTableTheta(k.x, d.x), ftSrbfTableTheta(k.y, d.y),
                                           ftSrbfTableDeltaPhi(k.z, d.z), ftSrbfTableLambda(k.w, d.w));
    EXPECT_NEAR(v.x, float(i), 2e-3f * float(d.w * d.z * d.y)) << i;  // float coordinates: a few 1e-6 of a texel step
    EXPECT_NEAR(v.z, 1.0f, 1e-5f);  // the weights sum to 1
  }
}

}  // namespace
}  // namespace ft
