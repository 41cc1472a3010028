// prt_multiple_scattering_test.cpp — local multiple scattering of 004 §4.2,
// §4.3, §5.3.1 on the CPU (common/prt_multiple_scattering.h, reference/
// prt_multiple_scattering.h, bake/iirtf_bake.h) against what this file
// computes without common/'s SH: std::sph_legendre (Condon–Shortley phase
// removed), closed forms of C_G (Langevin function and limits), brute-force 2D
// quadratures of ∫ Y S cos and ∫ f S cos, the estimator of 004 §4.2c on an
// analytic T with its own sample variance.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include "bake/bake.h"
#include "bake/bake_runner.h"
#include "bake/iirtf_bake.h"
#include "reference/prt_multiple_scattering.h"
#include "scene/fabric.h"
#include "scene/input_error.h"
#include "validation/draw_order.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;

double oracleY(int l, int m, glm::dvec3 w) {
  const double theta = std::acos(std::clamp(w.z, -1.0, 1.0));
  const double phi = std::atan2(w.y, w.x);
  const int am = std::abs(m);
  const double p = std::sph_legendre(unsigned(l), unsigned(am), theta) * ((am % 2) ? -1.0 : 1.0);
  if (m == 0) return p;
  return std::sqrt(2.0) * p * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}
std::vector<double> oracleAll(glm::dvec3 w, int bands = FT_SH_BANDS) {
  std::vector<double> y;
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) y.push_back(oracleY(l, m, w));
  return y;
}

// ---- C_G ----------------------------------------------------------------------
double langevin(double x) {
  if (x < 1e-3) return x / 3.0 - x * x * x / 45.0 + 2.0 * std::pow(x, 5) / 945.0;
  return 1.0 / std::tanh(x) - 1.0 / x;
}

TEST(PrtMsTables, ZonalSgClosedForms) {
  const int n = FT_MS_LAMBDA_NODES;
  const double y00 = 1.0 / std::sqrt(4.0 * kPi), k1 = std::sqrt(3.0 / (4.0 * kPi));
  double l0 = 0.0, l1 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double u = double(k) / (n - 1);
    const PrtMsZonal z = prtMsZonalSg(u);
    l0 = std::max(l0, std::abs(z.c[0] - y00));
    const double lambda = u / (1.0 - u);
    const double expect = k == n - 1 ? k1 : k1 * langevin(lambda);
    l1 = std::max(l1, std::abs(z.c[1] - expect));
  }
  EXPECT_LT(l0, 1e-12);  // ∫ G/M Y_00 = Y_00 for every λ
  EXPECT_LT(l1, 1e-10);  // Langevin: √(3/4π)(coth λ − 1/λ)
  // λ → ∞: √((2l + 1)/4π); λ → 0: only l = 0 (C_l ~ λ^l).
  const PrtMsZonal big = prtMsZonalSg(1.0 - 1e-7), small = prtMsZonalSg(1e-6);
  for (int l = 0; l < FT_SH_BANDS; ++l) {
    EXPECT_NEAR(big.c[l], std::sqrt((2 * l + 1) / (4.0 * kPi)), 2e-5 * l * (l + 1) + 1e-12) << l;
    if (l > 0) {
      EXPECT_LT(std::abs(small.c[l]), 1e-6) << l;
    }
  }
  // Lerp in u between nodes: worst l = 1 error at node midpoints vs the closed form (documented figure).
  double interp = 0.0;
  const PrtMsTables t = prtMsTablesCpu(findFabricPreset("fleece").params(), 64, 64);
  for (double lambda : {0.05, 0.3, 1.0, 3.7, 10.0, 42.0, 150.0, 700.0, 5000.0}) {
    const glm::dvec3 lk = prtMsCgLookup(lambda, t.lambdaNodes);
    const double v = glm::mix(t.cg[size_t(lk.x) * FT_SH_BANDS + 1], t.cg[size_t(lk.y) * FT_SH_BANDS + 1], lk.z);
    interp = std::max(interp, std::abs(v - k1 * langevin(lambda)));
  }
  // Measured 2.7e-6 (256 nodes in u, lerp: h²/8 · |∂²C_1/∂u²| with h = 1/255); C_1 ≤ 0.49.
  EXPECT_LT(interp, 5e-6);
}

// ---- C_S ----------------------------------------------------------------------
// ∫ Y_j S cos θ_i dω_i by brute force for several θ_o rows: θ_i on n midpoints, φ on m
// midpoints, the full BCSDF (bcsdf.h) and the oracle's Y, in ω_o-space as the header defines it.
// Returns [row][j][rgb].
std::vector<double> bruteCs(const FabricParams& p, const std::vector<int>& rows, int n, int m) {
  std::vector<double> out(rows.size() * FT_SH_COEFFS * 3, 0.0);
  for (int i = 0; i < n; ++i) {
    const double th = -kPi / 2 + (i + 0.5) * kPi / n;
    for (int k = 0; k < m; ++k) {
      const double ph = 2.0 * kPi * (k + 0.5) / m;
      const glm::dvec3 w(std::sin(th), std::cos(th) * std::cos(ph), std::cos(th) * std::sin(ph));
      const double wt = std::cos(th) * std::cos(th) * (kPi / n) * (2.0 * kPi / m);
      const std::vector<double> y = oracleAll(w);
      for (size_t r = 0; r < rows.size(); ++r) {
        FiberAngles a;
        a.thetaI = float(th);
        a.thetaO = float(-kPi / 2 + rows[r] * kPi / (FT_MS_THETA_O - 1));
        a.phi = float(std::abs(std::remainder(ph, 2.0 * kPi)));
        const glm::vec3 s = ftBcsdf(p, a);
        for (int j = 0; j < FT_SH_COEFFS; ++j)
          for (int ch = 0; ch < 3; ++ch) out[(r * FT_SH_COEFFS + size_t(j)) * 3 + size_t(ch)] += wt * y[size_t(j)] * double(s[ch]);
      }
    }
  }
  return out;
}

TEST(PrtMsTables, CsMatchesBruteForceQuadrature) {
  const std::vector<int> rows = {40, 200, 255, 256, 400, 500};
  for (const char* name : {"fleece", "silk"}) {
    const FabricParams p = findFabricPreset(name).params();
    const PrtMsTables t = prtMsTablesCpu(p);
    // 3,000 θ_i nodes (not the table's 2,048) and 180 φ nodes (not its 512).
    const std::vector<double> b = bruteCs(p, rows, 3000, 180);
    double scale = 0.0, err = 0.0, odd = 0.0;
    for (size_t r = 0; r < rows.size(); ++r) {
      for (int j = 0; j < FT_SH_COEFFS; ++j)
        for (int ch = 0; ch < 3; ++ch) {
          const double v = t.cs[(size_t(rows[r]) * FT_SH_COEFFS + size_t(j)) * 3 + size_t(ch)];
          const double bv = b[(r * FT_SH_COEFFS + size_t(j)) * 3 + size_t(ch)];
          scale = std::max(scale, std::abs(bv));
          err = std::max(err, std::abs(v - bv));
        }
      // In ω_o-space S depends on |φ|: every Y odd under z → −z integrates to 0.
      for (int j = 0; j < FT_SH_COEFFS; ++j) {
        const glm::dvec3 w(0.3, 0.4, std::sqrt(0.75));
        const double a = oracleAll(w)[size_t(j)], bm = oracleAll(glm::dvec3(w.x, w.y, -w.z))[size_t(j)];
        if (std::abs(a + bm) < 1e-12 && std::abs(a) > 1e-6)
          for (int ch = 0; ch < 3; ++ch)
            odd = std::max(odd, std::abs(t.cs[(size_t(rows[r]) * FT_SH_COEFFS + size_t(j)) * 3 + size_t(ch)]));
      }
    }
    std::printf("C_S %s: max |table − brute force| = %.3g of max |C_S| %.4g; odd-in-z entries ≤ %.3g\n", name, err,
                scale, odd);
    // Both rules resolve the lobes (≥ 11 and ≥ 16 nodes per σ of the 1° R lobe): they agree to the
    // float BCSDF evaluations' rounding (6e-8 relative) plus the rules' own error.
    EXPECT_LT(err, 1e-5 * scale) << name << ": " << err << " of " << scale;
    EXPECT_LT(odd, 1e-6 * scale) << name;
  }
}

TEST(PrtMsTables, CsReconstructsSmoothBcsdfAndConvergesInL) {
  // A smooth BCSDF (β_R = β_TT = 30°, γ_TT = 40°): Σ_j C_S Y_j → S cos θ_i as L grows.
  FabricParams p = findFabricPreset("fleece").params();
  p.colorR.w = float(30.0 * kPi / 180.0);
  p.colorTT.w = float(30.0 * kPi / 180.0);
  p.lobes.x = float(40.0 * kPi / 180.0);
  p.lobes.y = 1.0f / (p.lobes.x * p.lobes.x);
  const PrtMsTables t = prtMsTablesCpu(p, 1024, 256);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double prev = 1e30;
  std::vector<double> rms(FT_SH_BANDS, 0.0);
  for (int bands = 1; bands <= FT_SH_BANDS; ++bands) {
    double e2 = 0.0, f2 = 0.0;
    for (int s = 0; s < 400; ++s) {
      const int o = int(u(rng) * (FT_MS_THETA_O - 1));
      const double thetaO = -kPi / 2 + o * kPi / (FT_MS_THETA_O - 1);
      const double th = std::asin(2.0 * u(rng) - 1.0), ph = 2.0 * kPi * u(rng);
      const glm::dvec3 w(std::sin(th), std::cos(th) * std::cos(ph), std::cos(th) * std::sin(ph));
      FiberAngles a;
      a.thetaI = float(th);
      a.thetaO = float(thetaO);
      a.phi = float(std::abs(std::remainder(ph, 2.0 * kPi)));
      const double f = double(ftBcsdf(p, a).y) * std::cos(th);
      const std::vector<double> y = oracleAll(w, bands);
      double g = 0.0;
      for (size_t j = 0; j < y.size(); ++j) g += t.cs[(size_t(o) * FT_SH_COEFFS + j) * 3 + 1] * y[j];
      e2 += (g - f) * (g - f);
      f2 += f * f;
    }
    rms[size_t(bands - 1)] = std::sqrt(e2 / f2);
    std::printf("smooth BCSDF, L = %d: relative RMS of Σ C_S Y − S cos = %.4f\n", bands - 1, rms[size_t(bands - 1)]);
    EXPECT_LT(rms[size_t(bands - 1)], prev) << "L = " << bands - 1;
    prev = rms[size_t(bands - 1)];
  }
  // Measured: relative RMS 0.71 (L = 0) … 0.10 (L = 5) for 30° lobes; L = 5 keeps the shape within 15 %.
  EXPECT_LT(rms[FT_SH_BANDS - 1], 0.15);
}

// ---- the estimator (004 §4.2c) ----------------------------------------------
TEST(Iirtf, EstimatorOnAnalyticKernelWithinThreeSigma) {
  // T = (1 + ω0·ω1)/4π: a[j0, 0] = ∫_H+ Y_j0 /√(4π), a[j0, (1, m)] = ∫_H+ Y_j0 Y_1m / 3, else 0.
  std::vector<double> hemi(FT_SH_COEFFS), hemi1(FT_SH_COEFFS * 3);
  {
    const int nz = 64, np = 64;
    for (int i = 0; i < nz; ++i)
      for (int k = 0; k < np; ++k) {
        const double z = (i + 0.5) / nz, r = std::sqrt(1 - z * z), ph = 2 * kPi * (k + 0.5) / np;
        const std::vector<double> y = oracleAll({r * std::cos(ph), r * std::sin(ph), z});
        const double w = (1.0 / nz) * (2 * kPi / np);
        for (int j = 0; j < FT_SH_COEFFS; ++j) {
          hemi[size_t(j)] += w * y[size_t(j)];
          for (int m = 0; m < 3; ++m) hemi1[size_t(j) * 3 + size_t(m)] += w * y[size_t(j)] * y[size_t(1 + m)];
        }
      }
  }
  // The z midpoint rule on polynomials of degree ≤ 6 in z: error ~ (1/64)²/24 ~ 1e-5 of the integrand;
  // the check below is statistical at σ ~ 1e-3, so that is exact enough.
  const int N = 50000;
  std::vector<double> sum(kIirtfMatrixSize, 0.0), sq(FT_SH_COEFFS * FT_SH_COEFFS, 0.0);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < N; ++i) {
    glm::dvec3 w0, w1;
    const double u4 = u(rng), u3 = u(rng), u2 = u(rng), u1 = u(rng);  // last first (validation/draw_order.h)
    iirtfDirections(u1, u2, u3, u4, w0, w1);
    const double T = (1.0 + glm::dot(w0, w1)) / (4 * kPi);
    iirtfAccumulate(sum, glm::dvec3(T), w0, w1);
    const std::vector<double> y0 = oracleAll(w0), y1 = oracleAll(w1);
    for (int j1 = 0; j1 < FT_SH_COEFFS; ++j1)
      for (int j0 = 0; j0 < FT_SH_COEFFS; ++j0) {
        const double x = T * y0[size_t(j0)] * y1[size_t(j1)] * 8 * kPi * kPi;
        sq[size_t(j1 * FT_SH_COEFFS + j0)] += x * x;
      }
  }
  int beyond3 = 0;
  double worstZ = 0.0;
  for (int j1 = 0; j1 < FT_SH_COEFFS; ++j1)
    for (int j0 = 0; j0 < FT_SH_COEFFS; ++j0) {
      const double mean = sum[size_t(j1 * FT_SH_COEFFS + j0)] / N;
      const double var = sq[size_t(j1 * FT_SH_COEFFS + j0)] / N - mean * mean;
      const double sigma = std::sqrt(std::max(var, 0.0) / N);
      double exact = 0.0;
      if (j1 == 0) exact = hemi[size_t(j0)] / std::sqrt(4 * kPi);
      else if (j1 <= 3) exact = hemi1[size_t(j0) * 3 + size_t(j1 - 1)] / 3.0;
      const double z = std::abs(mean - exact) / sigma;
      worstZ = std::max(worstZ, z);
      beyond3 += z > 3.0;
      // every channel got the same T
      EXPECT_EQ(sum[size_t(j1 * FT_SH_COEFFS + j0)], sum[size_t(2 * FT_SH_COEFFS * FT_SH_COEFFS + j1 * FT_SH_COEFFS + j0)]);
    }
  std::printf("estimator on T = (1 + ω0·ω1)/4π: %d of 1,296 coefficients beyond 3σ, max |z| = %.3f\n", beyond3, worstZ);
  // 1,296 coefficients: 0.27 % of them (3.5) expected beyond 3σ by chance; max |z| of 1,296 normals rarely > 4.5.
  EXPECT_LE(beyond3, 13) << "worst z " << worstZ;
  EXPECT_LT(worstZ, 5.0);
}

// A small exemplar for the path-traced checks: 64 segments, 3 × 3 tiles.
struct Small {
  Exemplar block;
  std::unique_ptr<IirtfScene> scene;
  IirtfSettings s;
  FabricParams fabric;
  Small() {
    ExemplarSettings ex;
    ex.fibersPerPly = 2;
    ex.spansPerYarn = 4;
    ex.subdivisions = 1;
    block = makePlainWeaveExemplar(ex);
    s.tiles = 3;
    s.pathsPerCell = 512;
    scene = std::make_unique<IirtfScene>(tileExemplar(block, s.tiles));
    fabric = findFabricPreset("fleece").params();
  }
};

TEST(Iirtf, ZeroAlbedoGivesZeroExactly) {
  Small t;
  t.s.albedo = 0.0;
  const IirtfCell c = iirtfCellCpu(*t.scene, t.block, t.s.tiles, t.fabric, t.s, {0, 5, 9});
  for (double v : c.a) ASSERT_EQ(v, 0.0);
  EXPECT_GT(c.rays, 0u);
}

TEST(Iirtf, CellIsTheMeanOfItsSegments) {
  Small t;
  const std::vector<uint32_t> members = {3, 17, 40};
  const IirtfCell cell = iirtfCellCpu(*t.scene, t.block, t.s.tiles, t.fabric, t.s, members);
  const int per = int((t.s.pathsPerCell + members.size() - 1) / members.size());
  std::vector<double> mean(kIirtfMatrixSize, 0.0);
  uint64_t rays = 0;
  for (uint32_t k : members) {
    const std::vector<double> a = iirtfSegmentSum(*t.scene, t.block, t.s.tiles, t.fabric, t.s, k, per, rays);
    for (size_t i = 0; i < a.size(); ++i) mean[i] += a[i] / per / double(members.size());
  }
  double scale = 0.0, err = 0.0;
  for (size_t i = 0; i < mean.size(); ++i) scale = std::max(scale, std::abs(mean[i])), err = std::max(err, std::abs(mean[i] - cell.a[i]));
  EXPECT_GT(scale, 0.0);
  EXPECT_LT(err, 1e-12 * scale);
  EXPECT_EQ(rays, cell.rays);
}

// The noise-aware SH order (prtMsNoiseCut) and the per-band noise report (iirtfNoiseByBand) on a
// matrix written here: a ≡ 1, SE = 0.1 in bands 0–2, 0.7 in band 3, 0.2 in bands 4–5 (max(l1, l0)).
TEST(Iirtf, NoiseCutAndNoiseByBand) {
  IirtfCell c;
  c.a.assign(kIirtfMatrixSize, 1.0);
  c.stdError.resize(kIirtfMatrixSize);
  const double perBand[FT_SH_BANDS] = {0.1, 0.1, 0.1, 0.7, 0.2, 0.2};
  const auto band = [](int j) { return j < 1 ? 0 : j < 4 ? 1 : j < 9 ? 2 : j < 16 ? 3 : j < 25 ? 4 : 5; };
  for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
    const int e = int(i % (FT_SH_COEFFS * FT_SH_COEFFS));
    c.stdError[i] = perBand[std::max(band(e / FT_SH_COEFFS), band(e % FT_SH_COEFFS))];
  }
  const std::vector<float> af(c.a.begin(), c.a.end()), ef(c.stdError.begin(), c.stdError.end());
  const IirtfNoiseByBand n = iirtfNoiseByBand(af, ef);
  for (int l = 0; l < FT_SH_BANDS; ++l) EXPECT_NEAR(n.band[size_t(l)], perBand[l], 1e-6) << "band " << l;
  EXPECT_NEAR(n.pair[size_t(3 * FT_SH_BANDS + 1)], 0.7, 1e-6);  // (l1, l0) = (3, 1): max 3
  IirtfCell cut = c;
  EXPECT_EQ(prtMsNoiseCut(cut, 0.5), 3);  // band 3 is the first above 0.5: bands 0–2 kept
  for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
    const int e = int(i % (FT_SH_COEFFS * FT_SH_COEFFS));
    ASSERT_EQ(cut.a[i], std::max(band(e / FT_SH_COEFFS), band(e % FT_SH_COEFFS)) < 3 ? 1.0 : 0.0) << i;
  }
  IirtfCell all = c;
  EXPECT_EQ(prtMsNoiseCut(all, 0.8), FT_SH_BANDS);  // no band above 0.8: nothing cut
  EXPECT_EQ(all.a, c.a);
}

TEST(Iirtf, MeanFreePathAndCells) {
  Small t;
  const MeanFreePath ell = estimateMeanFreePath(*t.scene, t.block, t.s.tiles, t.fabric, t.s);
  // The CI exemplar is sparse (2 fibers per ply): most paths from above pass through; some scatter twice.
  std::printf("ℓ = %.5g from %llu distances (P = %.4g)\n", ell.ell, (unsigned long long)ell.distances, t.block.period);
  EXPECT_GT(ell.distances, 10u);
  EXPECT_GT(ell.ell, 0.0);
  EXPECT_LT(ell.ell, t.block.period);
  const IirtfCells cells = makeIirtfCells(t.block, t.block.period / 2);
  EXPECT_EQ(cells.nx, 2);
  EXPECT_EQ(cells.ny, 2);
  size_t total = 0;
  for (const auto& m : cells.members) total += m.size();
  EXPECT_EQ(total, t.block.segments.size());
  for (size_t k = 0; k < cells.cellOf.size(); ++k) EXPECT_LT(cells.cellOf[k], cells.count());
  EXPECT_THROW(makeIirtfCells(t.block, 0.0), InputError);
}

// ---- per frame (004 §5.3.1) ---------------------------------------------------
TEST(PrtMsFrame, MatchesBruteForceOfTheIncomingRadiance) {
  // A_C with a[0, j1] = √(4π) f_j1, all else 0: c_T = f whatever ω_d, so
  // L̃ = ∫ f(ω_i) S(ω_i, ω_o) cos θ_i dω_i — brute force here on a grid about t.
  const FabricParams p = findFabricPreset("fleece").params();
  const PrtMsTables t = prtMsTablesCpu(p);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> n;
  std::vector<double> f(FT_SH_COEFFS);
  for (double& v : f) v = n(rng);
  f[0] += 4.0;
  std::vector<double> a(kIirtfMatrixSize, 0.0);
  for (int ch = 0; ch < 3; ++ch)
    for (int j1 = 0; j1 < FT_SH_COEFFS; ++j1) a[(size_t(ch) * FT_SH_COEFFS + size_t(j1)) * FT_SH_COEFFS] = std::sqrt(4 * kPi) * f[size_t(j1)];
  for (int trial = 0; trial < 2; ++trial) {
    glm::dvec3 tt = drawVec3<glm::dvec3>(n, rng), wo = drawVec3<glm::dvec3>(n, rng);
    tt /= glm::length(tt);
    wo /= glm::length(wo);
    PrtMsQuery q{};
    q.wo = vec4(glm::vec3(wo), 0.0f);
    q.tangent = vec4(glm::vec3(tt), 0.0f);
    q.light = vec4(0.0f, 0.0f, 1.0f, 0.0f);
    const glm::dvec3 L = prtMsRadianceCpu(t, a, FT_SH_BANDS, q);
    // Brute force about t: ω = sin θ t + cos θ (cos φ u + sin φ v).
    const glm::dvec3 u0 = glm::normalize(std::abs(tt.x) < 0.9 ? glm::cross(tt, glm::dvec3(1, 0, 0)) : glm::cross(tt, glm::dvec3(0, 1, 0)));
    const glm::dvec3 v0 = glm::cross(tt, u0);
    const int nt = 1024, np = 192;
    glm::dvec3 B(0.0);
    for (int i = 0; i < nt; ++i) {
      const double th = -kPi / 2 + (i + 0.5) * kPi / nt;
      for (int k = 0; k < np; ++k) {
        const double ph = 2 * kPi * (k + 0.5) / np;
        const glm::dvec3 w = std::sin(th) * tt + std::cos(th) * (std::cos(ph) * u0 + std::sin(ph) * v0);
        const std::vector<double> y = oracleAll(w);
        double fv = 0.0;
        for (int j = 0; j < FT_SH_COEFFS; ++j) fv += f[size_t(j)] * y[size_t(j)];
        const FiberAngles an = ftFiberAngles(glm::vec3(tt), glm::vec3(w), glm::vec3(wo));
        const glm::vec3 s = ftBcsdf(p, an);
        B += glm::dvec3(s) * (fv * std::cos(th) * std::cos(th) * (kPi / nt) * (2 * kPi / np));
      }
    }
    // The C_S rows are 0.35° apart and lerped in θ_o: second-order error ≤ (Δθ)²/8 · |∂²C_S| ≈ 1e-4 relative for fleece.
    std::printf("per frame vs brute force: (%.6g %.6g %.6g) vs (%.6g %.6g %.6g)\n", L.x, L.y, L.z, B.x, B.y, B.z);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(L[ch], B[ch], 2e-3 * std::abs(B[ch]) + 1e-5) << "trial " << trial << " ch " << ch;
  }
}

// ---- the bake --------------------------------------------------------------------
std::unique_ptr<Bake> iirtfBake(std::vector<std::string> args) {
  std::unique_ptr<Bake> b = makeBake("iirtf");
  CLI::App app;
  b->addOptions(app);
  std::reverse(args.begin(), args.end());  // CLI11 parses a reversed vector
  app.parse(args);
  b->prepare();
  return b;
}

std::string readBytes(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(IirtfBake, SameBytesForAnyThreadCountAndTheReaderReadsIt) {
  const std::vector<std::string> args = {"--cell-size", "0.05", "--paths", "300", "--tiles", "3", "--subdivisions", "1",
                                         "--spans", "4", "--fibers-per-ply", "2", "--ell-paths", "200"};
  const auto dir = std::filesystem::temp_directory_path();
  std::ostringstream log;
  std::string first;
  for (int threads : {1, 2}) {
    const auto out = dir / fmt::format("ft_iirtf_test_{}_{}.bin", threads, ::testing::UnitTest::GetInstance()->random_seed());
    runBake(*iirtfBake(args), {out, threads, true}, log);
    const std::string bytes = readBytes(out);
    if (first.empty()) first = bytes;
    EXPECT_EQ(bytes, first) << threads << " threads";
    const IirtfFile f = readIirtfFile(out);
    EXPECT_EQ(f.segments, 64u);
    EXPECT_GE(f.cells, 2u);
    EXPECT_EQ(f.transfer.size(), f.cells * kIirtfMatrixSize);
    EXPECT_EQ(f.version, 2);
    ASSERT_EQ(f.stdError.size(), f.transfer.size());
    for (size_t i = 0; i < f.stdError.size(); ++i) {
      if (f.transfer[i] != 0.0f) {
        ASSERT_GT(f.stdError[i], 0.0f) << "entry " << i;  // a non-zero mean of ≥ 2 paths varies
      }
    }
    EXPECT_EQ(f.header["relative_noise_by_band"].size(), size_t(FT_SH_BANDS));
    EXPECT_GT(f.header.value("mean_free_path", 0.0), 0.0);
    {  // A version 1 file (no stderr section) reads with no noise estimate; an unknown version is refused by name.
      const size_t headerEnd = bytes.find('\n');
      nlohmann::json h = nlohmann::json::parse(bytes.substr(0, headerEnd));
      const auto v1 = dir / fmt::format("ft_iirtf_test_v1_{}.bin", threads);
      const auto write = [&](int version, size_t keep) {
        h["version"] = version;
        std::ofstream o(v1, std::ios::binary);
        o << h.dump() << '\n' << bytes.substr(headerEnd + 1, keep);
      };
      write(1, bytes.size() - headerEnd - 1 - f.cells * kIirtfMatrixSize * 4);
      const IirtfFile old = readIirtfFile(v1);
      EXPECT_EQ(old.version, 1);
      EXPECT_TRUE(old.stdError.empty());
      EXPECT_EQ(old.transfer, f.transfer);
      write(3, bytes.size() - headerEnd - 1);
      try {
        readIirtfFile(v1);
        ADD_FAILURE() << "a version 3 file was read";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("\"version\": 3"), std::string::npos) << e.what();
      }
      std::filesystem::remove(v1);
    }
    // A cut file names its size.
    std::filesystem::resize_file(out, std::filesystem::file_size(out) - 4);
    try {
      readIirtfFile(out);
      ADD_FAILURE() << "a cut file was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("expected exactly"), std::string::npos) << e.what();
    }
    std::filesystem::remove(out);
  }
  EXPECT_THROW(iirtfBake({"--tiles", "4"}), InputError);
  EXPECT_THROW(iirtfBake({"--fabric", "no-such-fabric"}), InputError);
  EXPECT_THROW(iirtfBake({"--albedo-is-not-an-option", "1"}), std::exception);
}

// The sparse CI block (6 fibers per ply), where L̃^multi is far from path tracing
// (docs/prt-multiple-scattering.md, "the sparse block"): the zeroth coefficient of A_C must still
// be 4π E[T] over ω0, ω1 uniform on the sphere (T = 0 for ω0 below) and k uniform in the cell,
// estimated here with directions drawn by this file's own code — so the solid-angle factors,
// the hemisphere density, the per-cell mean and the escaping (T = 0) paths are right there, and the
// gap is the transfer's shape (spiky in ω1, anisotropic), not its normalisation.
TEST(Iirtf, SparseBlockZerothCoefficientIsTheMeanTransfer) {
  const FabricParams p = findFabricPreset("fleece").params();
  ExemplarSettings ex;  // fibersPerPly 6: the sparse CI block
  const Exemplar block = makePlainWeaveExemplar(ex);
  IirtfSettings s;
  s.tiles = 3;
  s.pathsPerCell = 120000;
  const IirtfScene scene(tileExemplar(block, s.tiles));
  std::vector<uint32_t> members;
  for (uint32_t k = 0; k < block.segments.size(); k += 4) members.push_back(k);
  const IirtfCell cell = iirtfCellCpu(scene, block, s.tiles, p, s, members);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto sphere = [&] {
    const double z = 2.0 * u(rng) - 1.0, r = std::sqrt(std::max(0.0, 1.0 - z * z)), ph = 2.0 * kPi * u(rng);
    return glm::dvec3(r * std::cos(ph), r * std::sin(ph), z);
  };
  const int n = 600000;
  double sum = 0.0, sq = 0.0;
  uint64_t rays = 0, nonZero = 0;
  const size_t S = block.segments.size();
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 w0 = sphere(), w1 = sphere();
    const uint32_t k = members[size_t(u(rng) * double(members.size())) % members.size()];
    const ExemplarSegment& own = scene.segments()[centreCopy(s.tiles) * S + k];
    double t = 0.0;
    if (w0.z > 0.0) {
      const glm::dvec3 T = iirtfPathRadiance(scene, p, 1.0, s.maxDepth, own.mid(), own.fiber, glm::vec3(w0),
                                             glm::vec3(w1), 0xABCu, uint32_t(i), 77u, rays);
      t = (T.x + T.y + T.z) / 3.0;
    }
    nonZero += t != 0.0;
    sum += t;
    sq += t * t;
  }
  const double mean = sum / n, sd = std::sqrt((sq / n - mean * mean) / n);
  const size_t plane = size_t(FT_SH_COEFFS) * FT_SH_COEFFS;
  const double a00 = (cell.a[0] + cell.a[plane] + cell.a[2 * plane]) / 3.0;
  // a00 = ∫∫ T Y_00² = (1/4π) ∫∫ T = 4π E[T]. σ: this estimate's and the bake's (its own 120,000 paths
  // sample the same mean; taken equal per path, scaled by the path counts).
  const double sigma = 4.0 * kPi * sd * std::sqrt(1.0 + double(n) / double(cell.paths));
  fmt::print("sparse block: a00 {:.5g}, 4π E[T] {:.5g} ± {:.2g} ({} of {} (ω0, ω1) non-zero)\n", a00, 4.0 * kPi * mean,
             sigma, nonZero, n);
  EXPECT_GT(nonZero, 100u);
  EXPECT_LT(double(nonZero) / n, 0.5);  // sparse indeed: most (ω0, ω1) carry no transfer
  EXPECT_LT(std::abs(a00 - 4.0 * kPi * mean), 4.0 * sigma)
      << "a00 " << a00 << " vs 4π E[T] " << 4.0 * kPi * mean << " ± " << sigma << ", " << nonZero << " of " << n
      << " non-zero";
}

// V̄_glo (004 §5.3.2): the separable filter equals the 2D normalised Gaussian sum over the grid
// (written here with its own weights), and bad input is refused naming it.
TEST(PrtMsVglo, SeparableFilterIsTheNormalisedGaussianSumOverTheGrid) {
  const int w = 23, h = 17;
  const double texel = 0.01, sigma = 0.027;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> v(size_t(w) * h);
  for (double& x : v) x = u(rng) < 0.4 ? 0.0 : u(rng);
  const std::vector<double> f = prtMsVgloFilterCpu(v, w, h, texel, sigma);
  const double st = sigma / texel;
  const int r = int(std::ceil(4.0 * st));
  double worst = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double num = 0.0, den = 0.0;
      for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy)
        for (int xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx) {
          const double k = std::exp(-0.5 * (double((xx - x) * (xx - x)) + double((yy - y) * (yy - y))) / (st * st));
          num += k * v[size_t(yy) * w + size_t(xx)];
          den += k;
        }
      worst = std::max(worst, std::abs(f[size_t(y) * w + size_t(x)] - num / den));
    }
  EXPECT_LT(worst, 1e-13);
  auto message = [&](auto&& call) {
    try {
      call();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { prtMsVgloFilterCpu(v, w, h + 1, texel, sigma); }).find("23 × 18"), std::string::npos);
  EXPECT_NE(message([&] { prtMsVgloFilterCpu(v, w, h, 0.0, sigma); }).find("texel side 0"), std::string::npos);
  EXPECT_NE(message([&] { prtMsVgloFilterCpu(v, w, h, texel, -1.0); }).find("σ_glo -1"), std::string::npos);
  std::vector<double> bad = v;
  bad[size_t(5) * w + 7] = std::nan("");
  EXPECT_NE(message([&] { prtMsVgloFilterCpu(bad, w, h, texel, sigma); }).find("texel (7, 5)"), std::string::npos);
  // 004's CPU sampler: V ≡ 1 → 1 exactly; a half plane → ½ within the binomial σ.
  EXPECT_EQ(prtMsVgloSampleCpu([](glm::dvec2) { return 1.0; }, glm::dvec2(0.3, 0.2), 0.05, 100, 1u, 2u), 1.0);
  const double half = prtMsVgloSampleCpu([](glm::dvec2 x) { return x.x > 0.0 ? 1.0 : 0.0; }, glm::dvec2(0.0, 0.0), 0.05,
                                         20000, 3u, 4u);
  EXPECT_LT(std::abs(half - 0.5), 4.0 * 0.5 / std::sqrt(20000.0));
}

}  // namespace
}  // namespace ft
