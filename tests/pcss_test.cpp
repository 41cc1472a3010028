// PCSS soft yarn shadows (common/pcss.h, docs/soft-shadows.md) on synthetic
// maps made here; expectations written out without common/ (disc-segment
// areas, a quadrature of the SG, the hard comparison).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/pcss.h"
#include "scene/input_error.h"
#include "scene/shading_inputs.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The share of ∫ e^{λ(cos θ − 1)} dω within θ ≤ α: closed form of the cap integral.
double capShare(double lambda, double alpha) {
  return -std::expm1(lambda * (std::cos(alpha) - 1.0)) / -std::expm1(-2.0 * lambda);
}

TEST(pcss, LobeConeHoldsTheStatedEnergyShare) {
  for (double lambda : {2.5, 3.0, 10.0, 50.0, 400.0, 5000.0}) {
    const double a = ftPcssLobeAngle(float(lambda));
    EXPECT_NEAR(capShare(lambda, a), 0.8244, 2e-4) << "λ " << lambda;
  }
  // Large λ: α √λ → the small-angle constant √(−2 ln(1 − f)) = 1.8653.
  EXPECT_NEAR(ftPcssLobeAngle(1e5f) * std::sqrt(1e5), 1.8653, 2e-3);
  // Monotone: sharper lobes, narrower cones; broad ones clamped at 80°.
  float prev = 10.0f;
  for (float l = 0.5f; l < 2000.0f; l *= 1.5f) {
    const float a = ftPcssLobeAngle(l);
    EXPECT_LE(a, prev);
    EXPECT_LE(a, float(80.0 * kPi / 180.0) + 1e-6f);
    prev = a;
  }
}

// An N × N map over world [−1, 1]², depth [−1, 1] (stored depth = z/2 + ½),
// light along +z; one layer.
struct Map {
  int n = 256;
  ShadowMapParams sm{};
  PcssParams pc{};
  std::vector<float> texels;
  explicit Map(int size) : n(size), texels(size_t(size) * size, 1.0f) {
    sm.lightX[0] = vec4(1, 0, 0, 0);
    sm.lightY[0] = vec4(0, 1, 0, 0);
    sm.lightZ[0] = vec4(0, 0, 1, 0);
    sm.extent = vec4(1.0f, 1.0f, 2.0f / float(n), float(n));
    sm.count = uvec4(1u, uint(n), 0u, 0u);
  }
  // Stored depth of world depth z over the texels whose centre has world x < x0.
  void halfPlane(float x0, float z) {
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        if (-1.0f + (x + 0.5f) * 2.0f / n < x0) texels[size_t(y * n + x)] = z * 0.5f + 0.5f;
  }
  float visibility(vec3 p, float tanAlpha) {
    pc.lightTanAlpha = vec4(tanAlpha);
    return ftPcssLightVisibility(sm, pc, 0, p, texels.data());
  }
};

TEST(pcss, UnoccludedIsOne) {
  Map m(128);
  for (float x = -0.9f; x < 0.9f; x += 0.013f)
    for (float t : {0.0f, 0.05f, 0.5f, 3.0f}) EXPECT_EQ(m.visibility(vec3(x, 0.1f, 0.5f), t), 1.0f);
  // Yarns behind the receiver (deeper) block nothing.
  m.halfPlane(0.5f, 0.8f);
  for (float x = -0.9f; x < 0.9f; x += 0.013f) EXPECT_EQ(m.visibility(vec3(x, 0.1f, 0.5f), 0.2f), 1.0f);
}

TEST(pcss, DeepUnderAWideBlockerIsZero) {
  Map m(128);
  m.halfPlane(0.5f, -0.2f);
  // Receivers 0.3 behind the blocker, tan α = 0.2: the PCF disc (radius 0.06)
  // lies inside the blocker while x < 0.5 − 0.06.
  for (float x = -0.6f; x < 0.4f; x += 0.01f) EXPECT_EQ(m.visibility(vec3(x, 0.0f, 0.1f), 0.2f), 0.0f);
}

TEST(pcss, ZeroRadiusIsTheHardLookup) {
  Map m(64);
  m.halfPlane(0.0f, -0.5f);
  for (float x = -0.9f; x < 0.9f; x += 0.007f) {
    const vec3 p(x, 0.3f, 0.2f);
    const int tx = std::min(int((x * 0.5f + 0.5f) * 64.0f), 63), ty = int((0.3f * 0.5f + 0.5f) * 64.0f);
    const float stored = m.texels[size_t(ty * 64 + tx)];
    EXPECT_EQ(m.visibility(p, 0.0f), (0.2f * 0.5f + 0.5f) <= stored ? 1.0f : 0.0f) << x;
  }
}

// Half-plane blocker at depth distance d: the PCF disc has radius d tan α, and
// the lit share is the disc's part beyond the edge: for signed distance s of
// the receiver past the edge (in units of the radius), ½ + (s√(1−s²) + asin s)/π.
TEST(pcss, HalfPlanePenumbraMatchesTheDiscSegment) {
  Map m(512);
  const float zb = -0.3f, zr = 0.2f, tanAlpha = 0.1f;  // d = 0.5, radius 0.05 = 12.8 texels
  m.halfPlane(0.0f, zb);
  const double radius = (zr - zb) * tanAlpha;
  double sumAbs = 0.0;
  int count = 0;
  for (double s = -1.2; s <= 1.2; s += 0.05) {
    // Mean over 64 receivers along y (each its own pattern rotation).
    double mean = 0.0;
    for (int k = 0; k < 64; ++k) mean += m.visibility(vec3(float(s * radius), -0.5f + k * 0.0157f, zr), tanAlpha) / 64.0;
    const double c = std::clamp(s, -1.0, 1.0);
    const double expect = 0.5 + (c * std::sqrt(1.0 - c * c) + std::asin(c)) / kPi;
    sumAbs += std::abs(mean - expect);
    ++count;
    EXPECT_NEAR(mean, expect, 0.08) << "s " << s;
  }
  EXPECT_LT(sumAbs / count, 0.03);
}

// Lobe maps: lobe 5 reads layer 1 (a blocker), lobe 2 layer 0 (none), lobe 7 none.
TEST(pcss, LobeVisibilityReadsItsOwnLayer) {
  const int n = 64;
  PcssParams pc{};
  for (int j = 0; j < FT_PCSS_MAX_LOBES; ++j) pc.lobeCone[j] = vec4(0.0f, -1.0f, 0.0f, 0.0f);
  for (int j : {2, 5}) {
    pc.lobeX[j] = vec4(1, 0, 0, 0);
    pc.lobeY[j] = vec4(0, 1, 0, 0);
    pc.lobeZ[j] = vec4(0, 0, 1, 0);
  }
  pc.lobeCone[2] = vec4(0.1f, 0.0f, 0.0997f, 0.5f);
  pc.lobeCone[5] = vec4(0.1f, 1.0f, 0.0997f, 0.5f);
  pc.extent = vec4(1.0f, 1.0f, 2.0f / n, float(n));
  pc.count = uvec4(2u, uint(n), 0u, 0u);
  std::vector<float> texels(size_t(2 * n * n), 1.0f);
  for (size_t k = size_t(n * n); k < texels.size(); ++k) texels[k] = 0.25f;  // layer 1: a blocker at z = −0.5
  const vec3 p(0.1f, -0.2f, 0.3f);
  EXPECT_EQ(ftPcssLobeVisibility(pc, 2, p, texels.data()), 1.0f);
  EXPECT_EQ(ftPcssLobeVisibility(pc, 5, p, texels.data()), 0.0f);
  EXPECT_EQ(ftPcssLobeVisibility(pc, 7, p, texels.data()), 1.0f);
}

// Bad options: an error naming the option, never a silent default.
TEST(pcss, BadOptionsAreInputErrors) {
  ShadingInputs in;
  AppearanceOptions o;
  o.softShadows = true;
  for (float bad : {-0.1f, 1.2f, std::nanf("")}) {
    o.lightAngularRadius = bad;
    try {
      frameSoftShadows(in, o);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--light-angular-radius"), std::string::npos) << e.what();
    }
  }
  o.lightAngularRadius = 0.1f;
  o.shadowMap = false;
  EXPECT_THROW(frameSoftShadows(in, o), InputError);
  o.shadowMap = true;
  frameSoftShadows(in, o);
  EXPECT_NE(in.params.flags.w & FT_APPEARANCE_SOFT_SHADOWS, 0u);
  EXPECT_FLOAT_EQ(in.lightTanAlpha.x, std::tan(0.1f));
}

}  // namespace
}  // namespace ft
