// The CPU self-shadow texture (reference/self_shadow.h, common/self_shadow.h;
// 000 §4.1, notes-rendering A2) against closed forms and sums written here in
// double: the uniform circular and elliptical ply (C3), the invariants C1, C2,
// C4, C5, and the lookup's angle convention tied to ftPlyFrame.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "common/fiber_geometry.h"
#include "reference/self_shadow.h"
#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"
#include "validation/draw_order.h"

namespace ft {
namespace {

// One uniform ply (ε = 0, β = 0: p ≡ 1) of n_f fibers at the centre.
YarnDensityParams uniformPly(float eN, float eB, uint32_t fibers = 50) {
  YarnDensityParams d{};
  d.plyCount = 1;
  d.fiberCount = fibers;
  d.ellipseN = eN;
  d.ellipseB = eB;
  d.rMax = 1.0f;
  d.plyTwistSign = 1.0f;
  d.normalization = ftDensityNormalization(d);
  d.supportRadius = std::max(eN, eB);
  return d;
}

// ρ0 × the chord of the ellipse (a along (cos ψ, sin ψ), b across) at height v left of u.
double ellipseAccumulated(double fibers, double a, double b, double psi, double u, double v) {
  const double c = std::cos(psi), s = std::sin(psi);
  const double qa = c * c / (a * a) + s * s / (b * b), qb = v * c * s * (1 / (a * a) - 1 / (b * b));
  const double qc = v * v * (s * s / (a * a) + c * c / (b * b)) - 1.0, disc = qb * qb - qa * qc;
  if (disc <= 0.0) return 0.0;
  const double lo = (-qb - std::sqrt(disc)) / qa, hi = (-qb + std::sqrt(disc)) / qa;
  return fibers / (M_PI * a * b) * (std::clamp(u, lo, hi) - lo);
}

void expectAnalytic(float eN, float eB) {
  const YarnDensityParams d = uniformPly(eN, eB);
  const SelfShadowTexture t = bakeSelfShadowCpu(d, makeSelfShadowParams(d, 64, 64, 8));
  const SelfShadowParams& p = t.params;
  const double w = p.halfWidth, h = 2.0 * w / p.width, scale = 50.0 / (M_PI * eN * eB) * 2.0 * std::min(eN, eB);
  double worst = 0.0;
  for (uint32_t k = 0; k < p.slices; ++k)
    for (uint32_t j = 0; j < p.height; ++j)
      for (uint32_t i = 0; i < p.width; ++i) {
        const double e = ellipseAccumulated(50.0, eN, eB, 2.0 * M_PI * k / p.slices, -w + (i + 0.5) * h,
                                            -w + (j + 0.5) * h);
        worst = std::max(worst, std::abs(t.at(i, j, k) - e) / scale);
      }
  // Uniform density: the 16-point rule is exact; float rounding only (notes A2 C3: 1e-4).
  EXPECT_LT(worst, 1e-4) << eN << " × " << eB;
}

TEST(SelfShadow, UniformCircularPlyIsTheChord) { expectAnalytic(0.02f, 0.02f); }
TEST(SelfShadow, UniformEllipticalPlyIsTheChord) { expectAnalytic(0.012f, 0.025f); }

TEST(SelfShadow, MonotoneMassPeriodicAndMirrored) {
  for (const char* name : {"cotton1", "polyester1"}) {
    const YarnPreset& preset = findYarnPreset(name);
    const YarnDensityParams d = makeYarnDensity(preset);
    const SelfShadowTexture t = bakeSelfShadowCpu(d, makeSelfShadowParams(d, 64, 64, 8));
    const SelfShadowParams& p = t.params;
    double dMax = 0.0;
    for (float x : t.texels) dMax = std::max(dMax, double(x));
    const double dv = 2.0 * p.halfWidth / p.height, period = 2.0 * M_PI / preset.plyNum;
    for (uint32_t k = 0; k < p.slices; ++k) {
      double mass = 0.0;
      for (uint32_t j = 0; j < p.height; ++j) {
        for (uint32_t i = 0; i + 1 < p.width; ++i)  // C1
          ASSERT_GE(t.at(i + 1, j, k), t.at(i, j, k) - 1e-5 * dMax) << name << " " << i << "," << j << "," << k;
        mass += t.at(p.width - 1, j, k) * dv;
        // C5: D_ψ(u, v) = D_−ψ(u, −v).
        for (uint32_t i = 0; i < p.width; ++i)
          ASSERT_NEAR(t.at(i, j, k), t.at(i, p.height - 1 - j, (p.slices - k) % p.slices), 1e-5 * dMax);
      }
      // C2: a 64-point midpoint rule over v: 1e-3 for the smooth part, plus
      // 0.21 c Δ^1.5 at each of the 2 n_ply rows grazing a ply, where the row
      // integral is c√δ, c = 2 ε ρ_0 √(2 R_c) (p jumps to ε at R_max).
      const double a = std::max(preset.ellipseShort, preset.ellipseLong) * preset.rMax;
      const double b = std::min(preset.ellipseShort, preset.ellipseLong) * preset.rMax;
      const double c = 2.0 * preset.epsilon * d.normalization * std::sqrt(2.0 * a * a / b);
      const double tol = 1e-3 + 2.0 * preset.plyNum * 0.21 * c * std::pow(dv, 1.5) / (preset.plyNum * preset.fiberNum);
      EXPECT_NEAR(mass / (preset.plyNum * preset.fiberNum), 1.0, tol) << name << " slice " << k;
    }
    for (uint32_t j = 0; j < p.height; ++j)  // C4
      for (uint32_t i = 0; i < p.width; ++i)
        ASSERT_NEAR(ftSelfShadowExactAt(p, d, i, j, float(period)), t.at(i, j, 0), 1e-5 * dMax);
  }
}

// The lookup's ψ = θ_ply,0 − atan2(d) with θ_ply,0 the angle of ftPlyFrame's
// ply-0 N̂: looked up at random fragments, the texture must agree with a
// brute-force sum along ℓ⊥ through ellipses placed by ftPlyFrame itself.
TEST(SelfShadow, LookupFollowsThePlyFrame) {
  const YarnPreset& preset = findYarnPreset("cotton1");
  const YarnDensityParams d = makeYarnDensity(preset);
  const SelfShadowTexture t = bakeSelfShadowCpu(d, makeSelfShadowParams(d, 128, 128, 16));
  YarnParams yp{};
  yp.plyCount = d.plyCount;
  yp.plyRadius = d.plyRadius;
  TwistRates rates{};
  rates.ply = 7.3f;
  YarnFrame frame{vec3(0.0f), vec3(0, 0, 1), vec3(1, 0, 0), vec3(0, 1, 0)};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double dMax = 0.0;
  for (float x : t.texels) dMax = std::max(dMax, double(x));
  double worst = 0.0;
  for (float sign : {1.0f, -1.0f}) {
    yp.plyTwistSign = sign;
    for (int q = 0; q < 200; ++q) {
      const float s = float(0.5 * (unit(rng) + 1.0));
      const double a = M_PI * unit(rng);
      const vec2 x = vec2(0.8 * d.supportRadius * drawVec2<glm::dvec2>(unit, rng));
      const vec2 toLight(float(std::cos(a)), float(std::sin(a)));
      const float theta = float(2.0 * M_PI * sign * (s * rates.ply - std::floor(s * rates.ply)));
      // θ_ply,0 is ply 0's direction in (N̂, B̂).
      const PlyFrame pf0 = ftPlyFrame(yp, rates, frame, s, 0);
      ASSERT_NEAR(std::cos(theta), pf0.N.x, 1e-4);
      ASSERT_NEAR(std::sin(theta), pf0.N.y, 1e-4);
      // Brute force: ρ of reference-data §2 around each ftPlyFrame centre, e_N along N̂_j.
      double tau = 0.0;
      const int n = 10000;
      const double len = 2.5 * d.supportRadius, h = len / n;  // |x| ≤ 1.14 W: the ray leaves the support
      for (int i = 0; i < n; ++i) {
        const double px = x.x + (i + 0.5) * h * toLight.x, py = x.y + (i + 0.5) * h * toLight.y;
        for (uint32_t j = 0; j < d.plyCount; ++j) {
          const PlyFrame pf = ftPlyFrame(yp, rates, frame, s, j);
          const double qx = px - pf.offset.x, qy = py - pf.offset.y;
          const double r = std::hypot((qx * pf.N.x + qy * pf.N.y) / d.ellipseN,
                                      (qx * pf.B.x + qy * pf.B.y) / d.ellipseB);
          if (r > d.rMax) continue;
          const double tt = (M_E - std::exp(r / d.rMax)) / (M_E - 1.0);
          tau += ((1.0 - 2.0 * d.epsilon) * std::pow(std::max(tt, 0.0), double(d.beta)) + d.epsilon) *
                 d.normalization * h;
        }
      }
      // The lookup's own (u, v, ψ), integrated exactly without the texture:
      // the conventions alone, tight.
      const SelfShadowSample ss = ftSelfShadowSample(t.params, x, toLight, theta);
      const double exact = ftDensityLineIntegral(d, ss.w.w, vec2(ss.uvd.x, ss.uvd.y), vec2(-1.0f, 0.0f));
      // Brute force: ρ jumps by up to ρ_max at 2 n_ply boundary crossings, each
      // off by ≤ h: 6 ρ_max h ≈ 1.2e-3 of D_max; plus float: 2e-3.
      ASSERT_NEAR(exact, tau, 2e-3 * dMax) << "s " << s << " sign " << sign << " q " << q;
      worst = std::max(worst, std::abs(lookupSelfShadowCpu(t, x, toLight, theta) - tau) / dMax);
    }
  }
  // The texture's trilinear interpolation at 128² × 16: ψ dominates (a slice
  // step moves a ply edge by ~5 texels); measured 3.7%, notes A2 expect ≈ 2%.
  // 5% keeps it a check on the default size; conventions are checked above.
  EXPECT_LT(worst, 0.05);
  RecordProperty("worst_relative", std::to_string(worst));
}

TEST(SelfShadow, RefusesBadSizes) {
  const YarnDensityParams d = makeYarnDensity(findYarnPreset("cotton1"));
  EXPECT_THROW(makeSelfShadowParams(d, 2, 64, 8), std::invalid_argument);
  EXPECT_THROW(makeSelfShadowParams(d, 64, 64, 0), std::invalid_argument);
  EXPECT_THROW(makeSelfShadowParams(d, 64, 64, 8, NAN), std::invalid_argument);
  EXPECT_THROW(makeSelfShadowParams(d, 64, 64, 8, -1.0f), std::invalid_argument);
  EXPECT_EQ(makeSelfShadowParams(d, 64, 64, 8, 0.0f).kappa, 0.0f);  // no shadow: allowed
  const SelfShadowParams p = makeSelfShadowParams(d, 64, 64, 8);
  EXPECT_NEAR(p.kappa, 2.0f * 1.16e-3f, 1e-5f);  // notes §0.3: r_f = 1.16e-3 for cotton1
  EXPECT_GT(p.halfWidth, d.supportRadius);
}

}  // namespace
}  // namespace ft
