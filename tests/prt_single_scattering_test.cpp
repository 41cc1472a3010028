// prt_single_scattering_test.cpp — single scattering of the fabric PRT (004
// §5.2, common/prt_single_scattering.h, reference/prt_single_scattering.h):
// the closed forms and limits that need no GL, with expectations written here
// (std::erf, the Gaussian lobe normaliser's closed form, the SG product
// identity, the BCSDF at the delta limit). The quadrature, Monte Carlo and
// CPU-vs-GPU checks live in the harness (validation/prt_single_scattering_cases.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "common/prt_single_scattering.h"
#include "reference/prt_single_scattering.h"
#include "scene/fabric.h"
#include "scene/input_error.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<FabricParams> allFabrics() {
  std::vector<FabricParams> f;
  for (const FabricPreset& p : builtinFabricPresets()) f.push_back(p.params());
  return f;
}

TEST(PrtSingleScattering, ErfMatchesStd) {
  double worst = 0.0;
  for (int i = -8000; i <= 8000; ++i) {
    const double x = i * 1e-3;
    worst = std::max(worst, std::abs(double(ftErf(float(x))) - std::erf(x)));
    EXPECT_EQ(ftErf(float(x)), -ftErf(float(-x)));  // odd by construction
  }
  EXPECT_LE(worst, 3.5e-7);  // A&S 7.1.26: 1.5e-7, plus float rounding of 1 − poly·e^{−x²} (measured 2.9e-7)
}

TEST(PrtSingleScattering, SmoothVisibilityLimits) {
  EXPECT_DOUBLE_EQ(prtss64::ftPrtSsSmoothVisibility(0.0, 300.0), 0.5);
  EXPECT_NEAR(prtss64::ftPrtSsSmoothVisibility(kPi, 200.0), 1.0, 1e-15);
  EXPECT_NEAR(prtss64::ftPrtSsSmoothVisibility(-kPi, 200.0), 0.0, 1e-15);
  // σ = 1/√λ (the formula's, notes §6.1): one σ on the visible side is ½(1 + erf(1/√2)).
  const double lambda = 400.0;
  EXPECT_NEAR(prtss64::ftPrtSsSmoothVisibility(1.0 / std::sqrt(lambda), lambda), 0.5 * (1.0 + std::erf(1.0 / std::sqrt(2.0))),
              1e-14);
  EXPECT_NEAR(prtss32::ftPrtSsSmoothVisibility(0.0f, 300.0f), 0.5f, 2e-7f);
}

TEST(PrtSingleScattering, TableIsTheLobeNormaliser) {
  // Away from ±π/2 by 10β, 𝒢(−θ; β⁻²/2) = ½(1 + e^{−2β²} cos 2θ) (untruncated Gaussian).
  const std::vector<FabricParams> f = allFabrics();
  const std::vector<double> table = bakePrtSsTableCpu(f);
  ASSERT_EQ(table.size(), 2 * f.size() * FT_PRT_SS_TABLE_SIZE);
  for (size_t row = 0; row < 2 * f.size(); ++row) {
    const double beta = row % 2 == 0 ? f[row / 2].colorR.w : f[row / 2].colorTT.w;
    for (int k = 0; k < FT_PRT_SS_TABLE_SIZE; ++k) {
      const double theta = -0.5 * kPi + k * kPi / (FT_PRT_SS_TABLE_SIZE - 1);
      const double v = table[row * FT_PRT_SS_TABLE_SIZE + size_t(k)];
      ASSERT_TRUE(std::isfinite(v) && v > 0.0) << row << " " << k;
      if (std::abs(theta) + 10.0 * beta < 0.5 * kPi) {
        EXPECT_NEAR(v, 0.5 * (1.0 + std::exp(-2.0 * beta * beta) * std::cos(2.0 * theta)), 1e-12) << row << " " << k;
      }
    }
  }
}

TEST(PrtSingleScattering, SgProductIdentity) {
  // G(ω; ξ_q, λ_svf) G(ω; ξ, λ) = G(ω; ξ̂ˢᵘᵐ, ‖ξˢᵘᵐ‖) e^{‖ξˢᵘᵐ‖ − λ_svf − λ} pointwise (004 §5.2.2).
  const glm::dvec3 a = glm::normalize(glm::dvec3(0.3, 0.1, 0.9)), b = glm::normalize(glm::dvec3(-0.5, 0.4, 0.6));
  for (double lambda : {10.0, 100.0}) {
    const glm::dvec3 s = 128.0 * a + lambda * b;
    const double n = glm::length(s);
    for (int i = 0; i < 50; ++i) {
      const glm::dvec3 w = glm::normalize(glm::dvec3(std::sin(i * 1.3), std::cos(i * 0.7), std::sin(i * 0.31 + 1.0)));
      const double lhs = std::exp(128.0 * (glm::dot(w, a) - 1.0) + lambda * (glm::dot(w, b) - 1.0));
      const double rhs = std::exp(n * (glm::dot(w, s / n) - 1.0) + n - 128.0 - lambda);
      EXPECT_NEAR(lhs, rhs, 1e-12 * std::max(1.0, lhs));
    }
  }
}

TEST(PrtSingleScattering, DeltaLimitIsTheBcsdf) {
  // Γ/M(λ) → S(ξ, ω_o) cos θ_ξ: fleece (β_R = 7.2°) at λ = 10⁶, S written here.
  const FabricPreset& p = findFabricPreset("fleece");
  const std::vector<FabricParams> f = {p.params()};
  const std::vector<double> table = bakePrtSsTableCpu(f);
  const double bR = p.betaRDegrees * kPi / 180, bT = p.betaTTDegrees * kPi / 180, g = p.gammaTTDegrees * kPi / 180;
  const double kappa = 1.0 / (g * g), lambda = 1e6, m = 2.0 * kPi / lambda;
  for (double to : {-0.6, 0.1})
    for (double tx : {-0.5, 0.2, 0.7})
      for (double phi : {0.0, 1.5, kPi}) {
        const glm::dvec3 gamma = prtss64::ftPrtSsGamma(table.data(), f[0], 0, to, tx, phi, lambda, 0.0) / m;
        for (int c = 0; c < 3; ++c) {
          const double F = p.colorR[c] + (1 - p.colorR[c]) * std::pow(1 - std::cos(tx), 5);
          const auto lobe = [&](double beta) {
            const double z = 0.5 * (1.0 + std::exp(-2 * beta * beta) * std::cos(2 * tx));
            return std::exp(-0.5 * std::pow((tx + to) / beta, 2)) / (std::sqrt(2 * kPi) * beta * z);
          };
          const double s = F * lobe(bR) / (2 * kPi) + (1 - F) * p.colorTT[c] * lobe(bT) * std::exp(-kappa * (1 + std::cos(phi))) /
                                                           (2 * kPi * std::cyl_bessel_i(0.0, kappa) * std::exp(-kappa));
          EXPECT_NEAR(gamma[c], s * std::cos(tx), 2e-3 * std::max(s, 1e-3)) << to << " " << tx << " " << phi << " " << c;
        }
      }
}

TEST(PrtSingleScattering, FloatMatchesDoubleAndStaysFinite) {
  // Log space: λ = 10⁴ and grazing/forward angles stay finite in float, and
  // the float instance (the GPU's arithmetic) follows the double one.
  const std::vector<FabricParams> f = allFabrics();
  const std::vector<double> table = bakePrtSsTableCpu(f);
  const std::vector<float> tableF(table.begin(), table.end());
  for (size_t k = 0; k < f.size(); ++k)
    for (double lambda : {100.0, 1e3, 1e4})
      for (double tx : {-1.5, -0.3, 0.0, 0.9})
        for (double phi : {0.0, 2.0, kPi}) {
          const glm::dvec3 d = prtss64::ftPrtSsGamma(table.data(), f[k], int(k), 0.2, tx, phi, lambda, 0.0);
          const glm::vec3 s = prtss32::ftPrtSsGamma(tableF.data(), f[k], int(k), 0.2f, float(tx), float(phi), float(lambda), 0.0f);
          for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(d[c]) && std::isfinite(s[c]));
            EXPECT_NEAR(s[c], d[c], 2e-4 * std::abs(d[c]) + 1e-30) << k << " " << lambda << " " << tx << " " << phi;
          }
        }
}

TEST(PrtSingleScattering, BlendWeights) {
  EXPECT_EQ(prtss64::ftPrtSsBlendWeight(10.0), 0.0);
  EXPECT_EQ(prtss64::ftPrtSsBlendWeight(100.0), 0.0);
  EXPECT_DOUBLE_EQ(prtss64::ftPrtSsBlendWeight(150.0), 0.5);
  EXPECT_EQ(prtss64::ftPrtSsBlendWeight(200.0), 1.0);
  EXPECT_EQ(prtss64::ftPrtSsBlendWeight(1e4), 1.0);
}

TEST(PrtSingleScattering, BadInputNamesTheRequest) {
  const std::vector<FabricParams> f = allFabrics();
  const std::vector<double> table(2 * f.size() * FT_PRT_SS_TABLE_SIZE, 0.5);
  PrtSsSegments segs;
  segs.weights.assign(FT_SVF_DEFAULT_AXES, 0.1f);
  PrtSsRequest q{};
  q.tangent = glm::vec4(1, 0, 0, 0);
  q.outgoing = glm::vec4(0, 0, 1, 1);
  q.light = glm::vec4(0, 1, 0, 50);
  const auto message = [&](PrtSsRequest r) {
    try {
      std::vector<PrtSsRequest> v = {q, r};
      evaluatePrtSsCpu(f, table, v, segs);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  PrtSsRequest r = q;
  r.tangent.w = 9;
  EXPECT_NE(message(r).find("request 1: fabric index = 9"), std::string::npos) << message(r);
  r = q;
  r.light.w = std::nanf("");
  EXPECT_NE(message(r).find("lambda"), std::string::npos);
  r = q;
  r.segment.z = 3;
  EXPECT_NE(message(r).find("weights row = 3"), std::string::npos);
  r = q;
  r.outgoing = glm::vec4(0, 0, 2, 1);
  EXPECT_NE(message(r).find("|outgoing|"), std::string::npos);
  EXPECT_THROW(bakePrtSsTableCpu(std::vector<FabricParams>{}), InputError);
  EXPECT_EQ(message(q), "");
}

}  // namespace
}  // namespace ft
