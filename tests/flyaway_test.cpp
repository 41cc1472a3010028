// Flyaways of Huang et al. 2025 (001 §4.4, eq. 12–13; common/flyaway.h,
// reference/flyaway.h, docs/flyaways.md) on the CPU: eq. 13's end points and
// monotonicity (notes A8 C1), the curves against eq. 12 written here, the
// kept sets and the seam construction, bad parameters refused. No GL.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/packing.hpp>

#include "reference/flyaway.h"
#include "scene/flyaway_input.h"
#include "scene/input_error.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_preset.h"

namespace ft {
namespace {

FlyawayParams cotton(FlyawaySettings s = {}) {
  const YarnPreset& p = findYarnPreset("cotton1");
  const FiberSetup f = makeFiberSetup(p, FiberOptions{});
  s.width = FT_FLYAWAY_CI_WIDTH;
  s.height = FT_FLYAWAY_CI_HEIGHT;
  return makeFlyawayParams(p, f.params, s);
}

TEST(Flyaway, Eq13EndPointsAndMonotone) {
  for (float alpha : {0.3f, 1.0f, 2.0f, 5.0f}) {
    EXPECT_FLOAT_EQ(ftFlyawayRadius(0.02f, 0.015f, alpha, 0.0f), 0.02f) << alpha;
    EXPECT_NEAR(ftFlyawayRadius(0.02f, 0.015f, alpha, 1.0f), 0.035f, 1e-7f) << alpha;
    float last = 0.0f;
    for (int k = 0; k <= 64; ++k) {
      const float r = ftFlyawayRadius(0.02f, 0.015f, alpha, k / 64.0f);
      EXPECT_GE(r, last) << "dR/dt >= 0 for R_e >= 0, alpha " << alpha;
      last = r;
    }
  }
  // α = 1 is eq. 12's linear R(t) = R_0 + R_e t.
  for (int k = 0; k <= 8; ++k) EXPECT_NEAR(ftFlyawayRadius(0.02f, 0.015f, 1.0f, k / 8.0f), 0.02f + 0.015f * k / 8.0f, 1e-7f);
  // Clamped at 0 (notes A8 [F]).
  EXPECT_EQ(ftFlyawayRadius(0.01f, -0.05f, 1.0f, 1.0f), 0.0f);
}

TEST(Flyaway, CleanCurvesFollowEq12) {
  FlyawaySettings s;
  s.noise = 0.0f;
  s.alpha = 2.0f;
  s.patterns = 2;
  const FlyawayParams f = cotton(s);
  const FlyawayCurves c = generateFlyawaysCpu(f);
  int checked = 0;
  for (size_t i = 0; i < c.slots(); ++i) {
    if (c.headers[i].x == 0.0f) continue;
    const glm::vec4 a = c.points[i * FT_FLYAWAY_POINTS], b = c.points[i * FT_FLYAWAY_POINTS + FT_FLYAWAY_STEPS];
    const double r0 = std::hypot(a.x, a.y), r1 = std::hypot(b.x, b.y);
    for (uint32_t k = 0; k <= FT_FLYAWAY_STEPS; ++k) {
      const glm::vec4 p = c.points[i * FT_FLYAWAY_POINTS + k];
      const double t = double(k) / FT_FLYAWAY_STEPS;
      EXPECT_NEAR(p.w, t, 1e-7);
      EXPECT_NEAR(p.z, a.z + (b.z - a.z) * t, 1e-6);
      if (r0 > 1e-3 && r1 > 1e-3) {
        EXPECT_NEAR(std::hypot(p.x, p.y), r0 + (r1 - r0) * (1.0 - std::pow(1.0 - t, 2.0)), 2e-6);
      }
    }
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(Flyaway, KeptSetsAndSeamColumns) {
  const FlyawayParams f = cotton();
  const FlyawayCurves c = generateFlyawaysCpu(f);
  for (uint32_t set = 0; set < FT_FLYAWAY_SETS; ++set)
    for (uint32_t slot = 0; slot < f.maxPerSet; ++slot) {
      const glm::vec4 h = c.headers[ftFlyawaySlot(f, 0, set, slot)];
      if (h.y == 0.0f) continue;
      if (set == 0) EXPECT_TRUE(h.z < 0.0f && h.w >= 0.0f);
      else EXPECT_TRUE(h.z >= f.margin && h.w <= f.period - f.margin);
    }
  const FlyawayTextures t = bakeFlyawaysCpu(c);
  size_t covered = 0;
  for (uint32_t v : t.texels) covered += (v >> 24) != 0;
  EXPECT_GT(covered, 0u);
  // The first and last columns hold the shared boundary set only.
  for (uint32_t j = 0; j < t.height; ++j)
    for (uint32_t i : {0u, t.width - 1})
      for (uint32_t layer = 1; layer < FT_FLYAWAY_LAYERS; ++layer) EXPECT_EQ(t.at(layer, i, j), t.at(0, i, j));
  // Decoded tangents are unit vectors with t_u ≥ 0 (RGBA8).
  for (uint32_t v : t.texels) {
    if ((v >> 24) == 0) continue;
    const glm::vec3 d = 2.0f * glm::vec3(glm::unpackUnorm4x8(v)) - 1.0f;
    EXPECT_NEAR(glm::length(d), 1.0f, 0.02f);
    EXPECT_GE(d.x, -1.0f / 255.0f);
  }
}

TEST(Flyaway, Deterministic) {
  const FlyawayParams f = cotton();
  EXPECT_EQ(bakeFlyawaysCpu(generateFlyawaysCpu(f)).texels, bakeFlyawaysCpu(generateFlyawaysCpu(f)).texels);
  // The layer of a yarn period is a pure function of (yarn, period).
  EXPECT_EQ(ftFlyawayLayer(3u, 7, f.seed), ftFlyawayLayer(3u, 7, f.seed));
  int seen[3] = {0, 0, 0};
  for (int n = 0; n < 300; ++n) ++seen[ftFlyawayLayer(1u, n, f.seed)];
  for (int k : seen) EXPECT_GT(k, 60);
}

TEST(Flyaway, BadSettingsRefused) {
  const YarnPreset& p = findYarnPreset("cotton1");
  const FiberSetup f = makeFiberSetup(p, FiberOptions{});
  FlyawaySettings s;
  s.alpha = 0.0f;
  EXPECT_THROW(makeFlyawayParams(p, f.params, s), InputError);
  s = {};
  s.noise = std::nanf("");
  EXPECT_THROW(makeFlyawayParams(p, f.params, s), InputError);
  s = {};
  s.width = 1;
  EXPECT_THROW(makeFlyawayParams(p, f.params, s), InputError);
  s = {};
  s.lengthScale = 1e6f;  // a reach far beyond any texture period
  EXPECT_THROW(makeFlyawayParams(p, f.params, s), InputError);
}

}  // namespace
}  // namespace ft
