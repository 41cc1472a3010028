// Independent checks of the dual-scattering header (common/dual_scattering.h;
// Zinke et al. 2008 as 001 §4.1 eq. 8 uses it, notes-rendering A6) and its CPU
// bake (reference/dual_scattering.h), without GL. Every expected value is
// written here in double from the formulas and the preset rows; none of the
// header's helpers computes an expectation.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "reference/dual_scattering.h"
#include "scene/fabric.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;

// q(κ) = ∫_{−π/2}^{π/2} e^{−κ cos φ} dφ / (2π I0(κ)), by composite Simpson (4096 intervals).
double backFraction(double kappa) {
  const int n = 4096;
  const double h = kPi / n;
  double s = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    s += w * std::exp(-kappa * std::cos(-0.5 * kPi + i * h));
  }
  return s * h / 3.0 / (2.0 * kPi * std::cyl_bessel_i(0.0, kappa));
}

double schlick(double c, double theta) {
  const double m = 1.0 - std::abs(std::cos(theta));
  return c + (1.0 - c) * m * m * m * m * m;
}

// Eq. 14 written out.
double zinkeAb(double af, double ab) {
  const double d = 1.0 - af * af;
  return ab * af * af / d + ab * ab * ab * af * af / (d * d * d);
}

TEST(DualScattering, BackFractionMatchesTheNotes) {
  // notes A6 C1: fleece 0.0029, cotton 0.057 (γ_TT 25.989°, 38.269°).
  const auto kappa = [](double deg) { return 1.0 / std::pow(deg * kPi / 180.0, 2.0); };
  EXPECT_NEAR(backFraction(kappa(25.989)), 0.0029, 1e-4);
  EXPECT_NEAR(backFraction(kappa(38.269)), 0.057, 1e-3);
}

// C1 on the CPU bake: the lobe integrals against F/2 and (1 − F) C_TT q, 1 − q.
TEST(DualScattering, CpuBakeMatchesClosedForms) {
  for (const char* name : {"fleece", "cotton", "silk"}) {
    const FabricPreset& f = findFabricPreset(name);
    const DsTableCpu t = bakeDualScatteringCpu(f.params(), 16);
    const double q = backFraction(double(f.params().lobes.y));
    EXPECT_LT(t.errorEstimate, 1e-6) << name;
    for (int k = 0; k < t.texels; ++k) {
      const double theta = double(ftDsTexelAngle(k, t.texels));
      for (int c = 0; c < 3; ++c) {
        const double F = schlick(f.colorR[c], theta), tt = (1.0 - F) * f.colorTT[c];
        const double albedo = F + tt;
        EXPECT_NEAR(t.aFR[size_t(k)][c], 0.5 * F, 1e-5 * albedo) << name << " texel " << k;
        EXPECT_NEAR(t.aBR[size_t(k)][c], 0.5 * F, 1e-5 * albedo) << name << " texel " << k;
        EXPECT_NEAR(t.aFTT[size_t(k)][c], tt * (1.0 - q), 1e-5 * albedo) << name << " texel " << k;
        EXPECT_NEAR(t.aBTT[size_t(k)][c], tt * q, 1e-5 * albedo) << name << " texel " << k;
        // Δ_b ≡ 0 (C2): eq. 16 is linear in ᾱ = 0.
        EXPECT_EQ(t.rows[size_t(k) * FT_DS_ROWS + FT_DS_ROW_DELTA_B][c], 0.0f);
      }
    }
  }
}

// Eq. 14 and 17 at given ā, β̄² against the formulas written here; the guard.
TEST(DualScattering, DerivedQuantities) {
  // Fleece blue at θ = 0 (notes A6: ā_f = 0.907 → A_b = 0.23).
  const vec3 ab = ftDsAb(vec3(0.907f), vec3(0.046f));
  EXPECT_NEAR(ab.z, zinkeAb(0.907, 0.046), 1e-5 * zinkeAb(0.907, 0.046));
  EXPECT_NEAR(ab.z, 0.23, 0.005);
  // Cotton (ā_f ≈ ā_b ≈ 0.5 → A_b ≈ 0.25).
  EXPECT_NEAR(ftDsAb(vec3(0.505f), vec3(0.495f)).x, 0.244, 0.005);
  // The guard 1 − ā_f² ≥ 1e-4 keeps ā_f = 1 finite.
  EXPECT_TRUE(std::isfinite(ftDsAb(vec3(1.0f), vec3(0.5f)).x));
  EXPECT_NEAR(ftDsAb(vec3(1.0f), vec3(0.5f)).x, 0.5 / 1e-4 + 0.125 / 1e-12, 1e-3 * (0.125 / 1e-12));
  // Eq. 17 as published (the unsquared β̄ in the denominator), squared.
  const double af = 0.6, abk = 0.3, bf2 = 0.01, bb2 = 0.02;
  const double s = (1.0 + 0.7 * af * af) * (abk * std::sqrt(2 * bf2 + bb2) + abk * abk * abk * std::sqrt(2 * bf2 + 3 * bb2)) /
                   (abk + abk * abk * abk * (2 * std::sqrt(bf2) + 3 * std::sqrt(bb2)));
  EXPECT_NEAR(ftDsSigmaB2(vec3(af), vec3(abk), vec3(bf2), vec3(bb2)).x, s * s, 1e-6 * s * s);
}

DsTexel someTexel() {
  DsTexel t{};
  t.aF = vec3(0.9f, 0.6f, 0.3f);
  t.aB = vec3(0.05f, 0.3f, 0.2f);
  t.betaF2 = vec3(0.0076f, 0.004f, 0.001f);
  t.betaB2 = vec3(0.002f);
  t.ab = ftDsAb(t.aF, t.aB);
  t.sigmaB2 = ftDsSigmaB2(t.aF, t.aB, t.betaF2, t.betaB2);
  return t;
}

// σ̄_f²(n) = n β̄_f²: linear growth (variances of independent spreads add).
TEST(DualScattering, ForwardVarianceGrowsLinearly) {
  const DsTexel t = someTexel();
  for (int n = 0; n <= 20; ++n)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(ftDsForwardVariance(t, float(n))[c], n * double(t.betaF2[c]), 1e-6 * (n + 1) * t.betaF2[c]);
  // f_back^sc broadens with n: its value on the cone (θ_h = 0) falls.
  const FiberAngles a{0.2f, -0.2f, 0.3f};
  float last = 1e30f;
  for (int n = 0; n <= 10; ++n) {
    const float v = ftDsBackscatter(t, a, ftDsForwardVariance(t, float(n))).x;
    EXPECT_LT(v, last);
    last = v;
  }
}

// C3: T_f(0) = d_f, non-increasing in n, → 0.
TEST(DualScattering, TransmittanceLimits) {
  const DsTexel t = someTexel();
  EXPECT_FLOAT_EQ(ftDsForwardTransmittance(t, 0.0f).x, 0.7f);
  for (int n = 1; n <= 60; ++n)
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(ftDsForwardTransmittance(t, float(n))[c], ftDsForwardTransmittance(t, float(n - 1))[c]);
  EXPECT_NEAR(ftDsForwardTransmittance(t, 5.0f).y, 0.7 * std::pow(0.6, 5.0), 1e-6);
  EXPECT_LT(ftDsForwardTransmittance(t, 400.0f).x, 1e-12f);
}

// C6 on the CPU: at σ = 0 the broadened lobe is the BCSDF's own,
// g(θ_i + θ_o; β)/Z(θ_i), with Z's closed form ½(1 + e^{−2β²} cos 2θ_i)
// (valid while |θ_i| + 6β ≤ π/2).
TEST(DualScattering, BroadenedLobeAtZeroSpreadIsTheLobe) {
  for (double beta : {1.0 * kPi / 180, 10.0 * kPi / 180}) {
    for (double ti : {-0.6, 0.0, 0.4})
      for (double to : {-0.5, -0.4, -0.3, 0.0, 0.2}) {
        const double x = (ti + to) / beta;
        const double z = 0.5 * (1.0 + std::exp(-2.0 * beta * beta) * std::cos(2.0 * ti));
        const double want = std::exp(-0.5 * x * x) / (std::sqrt(2.0 * kPi) * beta) / z;
        const double got = ftDsBroadenedLobe(float(ti), float(to), ftDsBetaZ(float(beta)), 0.0f, 0.0f);
        EXPECT_NEAR(got, want, 1e-4 * std::max(want, 1e-3 / beta)) << beta << " " << ti << " " << to;
      }
  }
}

// f_s^sc keeps f's albedo for every n: ∫∫ f_s^sc cos²θ_o dθ_o dφ = F + (1 − F) C_TT
// (unit-energy M^G, N^G = 1/2π), by Simpson over θ_o here.
TEST(DualScattering, ScatteredForwardLobeKeepsTheAlbedo) {
  const FabricPreset& f = findFabricPreset("fleece");
  const FabricParams p = f.params();
  for (float n : {0.0f, 5.0f}) {
    const vec3 var = vec3(n * 0.005f);
    const float ti = 0.3f;
    const int m = 8192;
    const double h = kPi / m;
    double s = 0.0;
    for (int i = 0; i <= m; ++i) {
      const double to = -0.5 * kPi + i * h, c = std::cos(to);
      const double w = (i == 0 || i == m) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      s += w * ftDsForwardScattered(p, FiberAngles{ti, float(to), 1.0f}, var).y * c * c;
    }
    s *= h / 3.0 * 2.0 * kPi;
    const double F = schlick(f.colorR[1], ti);
    EXPECT_NEAR(s, F + (1.0 - F) * f.colorTT[1], 2e-5) << n;
  }
}

// C3: V = 1 gives f + d_b f_back^dir whatever n; V = 0 decays.
TEST(DualScattering, FrameLimits) {
  const FabricParams p = findFabricPreset("cotton").params();
  const DsTexel t = someTexel();
  const FiberAngles a{0.3f, -0.25f, 2.5f};
  const DsFrame f0 = ftDsEvaluate(p, t, a, 1.0f, 0.0f), f5 = ftDsEvaluate(p, t, a, 1.0f, 5.0f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(f0.value[c], ftBcsdf(p, a)[c] + 0.7f * f0.backDirect[c]);
    EXPECT_FLOAT_EQ(f5.value[c], f0.value[c]);
    EXPECT_FLOAT_EQ(ftDsRuntime(ftBcsdf(p, a), f0.backDirect, 1.0f)[c], f0.value[c]);
  }
  const DsFrame far = ftDsEvaluate(p, t, a, 0.0f, 300.0f), near = ftDsEvaluate(p, t, a, 0.0f, 0.0f);
  for (int c = 0; c < 3; ++c) EXPECT_LT(far.value[c], 1e-9f * near.value[c]);
}

// f_back^dir's energy over the backward half, ∫_{H_b} ∫ f_back cos²θ_o dθ_o dφ
// (H_b of measure π in the full circle), as published: 2 A_b g/(π cos²θ_d)
// integrates to ≈ 4 A_b for a narrow σ̄_b (2 from g in θ_h over dθ_o = 2 dθ_h,
// 2 from 2/π × π), not A_b. Pinned here so that the constant stays as
// published (docs/dual-scattering.md discusses it); midpoint rule, 20,000 steps.
TEST(DualScattering, BackscatterEnergyAsPublished) {
  DsTexel t{};
  t.ab = vec3(0.25f);
  t.sigmaB2 = vec3(0.0005f);
  for (float ti : {0.0f, 0.5f}) {
    const int m = 20000;
    const double h = kPi / m;
    double e = 0.0;
    for (int i = 0; i < m; ++i) {
      const double to = -0.5 * kPi + (i + 0.5) * h, c = std::cos(to);
      e += kPi * ftDsBackscatter(t, FiberAngles{ti, float(to), 0.0f}, vec3(0.0f)).x * c * c * h;
    }
    EXPECT_NEAR(e / 0.25, 3.994, 0.002) << ti;
  }
}

// The lookup: texel centres return the texel, midpoints mix half and half.
TEST(DualScattering, Lookup) {
  const int n = FT_DS_TABLE_SIZE;
  for (int k = 0; k < n; ++k) {
    const vec3 l = ftDsLookup(float(-0.5 * kPi + (k + 0.5) * kPi / n), n);
    EXPECT_EQ(int(l.x) + (l.z > 0.5f ? 1 : 0), k);
    EXPECT_NEAR(std::min(l.z, 1.0f - l.z), 0.0f, 1e-4f);
    if (k + 1 < n) {
      const vec3 m = ftDsLookup(float(-0.5 * kPi + (k + 1.0) * kPi / n), n);
      EXPECT_EQ(int(m.x), k);
      EXPECT_NEAR(m.z, 0.5f, 1e-4f);
    }
  }
  EXPECT_EQ(ftDsLookup(float(-0.5 * kPi), n).z, 0.0f);
  EXPECT_EQ(int(ftDsLookup(float(0.5 * kPi), n).x), n - 1);
}

}  // namespace
}  // namespace ft
