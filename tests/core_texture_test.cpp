// The core-fiber texture (common/core_texture.h, reference/core_texture.h;
// Wu & Yuksel 2019 (000) §3.2) without a GPU: the helix, its derivatives and
// the ray–capsule test against expectations written here in double, the two
// CPU geometric paths (Embree round curves, the shared capsule chain) against
// each other, the lookup's wrap and clamp, and bad sizes.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "reference/core_texture.h"
#include "scene/core_texture_input.h"
#include "scene/input_error.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_preset.h"
#include "validation/draw_order.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;

FiberSetup cotton1() {
  FiberOptions o;
  return makeFiberSetup(findYarnPreset("cotton1"), o);
}

CoreTextureInput ciInput(const FiberSetup& s) {
  return makeCoreTextureInput(s.params, s.table, FT_CORE_TEXTURE_CI_WIDTH, FT_CORE_TEXTURE_CI_HEIGHT);
}

TEST(core_texture, CoreSetIsEveryFiberButTheRegularOnesAndRCoreEnclosesThem) {
  const FiberSetup s = cotton1();
  const CoreTextureInput in = ciInput(s);
  ASSERT_EQ(in.fibers.size(), size_t(s.params.fiberCount - s.params.regularFibers));
  const double e = std::max(s.params.ellipseN, s.params.ellipseB);
  double farthest = 0.0;
  for (const glm::vec4& f : in.fibers) farthest = std::max(farthest, double(f.x));
  EXPECT_NEAR(in.params.coreHalfWidth, e * farthest * s.params.rhoMax + s.params.fiberRadius, 1e-7);
  EXPECT_FLOAT_EQ(in.params.migrationS, 1.0f) << "§3.2: the core's fibers use s = 1";
  EXPECT_NEAR(in.params.alpha, 0.366114, 1e-6);
}

TEST(core_texture, HelixIsPeriodicOverOneTwistAndMatchesEq2) {
  const CoreTextureInput in = ciInput(cotton1());
  const CoreTextureParams& c = in.params;
  for (const glm::vec4& f : in.fibers)
    for (double th : {0.0, 0.7, 2.0, 4.1}) {
      const glm::vec3 a = ftCoreHelixPoint(c, f, float(th)), b = ftCoreHelixPoint(c, f, float(th + 2.0 * kPi));
      EXPECT_NEAR(a.x, b.x, 2e-6);
      EXPECT_NEAR(a.y, b.y, 2e-6);
      EXPECT_NEAR(b.z - a.z, c.alpha, 2e-6);
      // Eq. 2 (period starting at R_min) and eq. 1's polar angle, written here.
      const double frac = f.z + th / (2.0 * kPi) + 0.5;
      const double r = c.plyScale * f.x * (c.rhoMin + (c.rhoMax - c.rhoMin) * 0.5 * (1.0 - std::cos(2.0 * kPi * frac)));
      const double phi = c.twistSign * (2.0 * kPi * f.y + th);
      EXPECT_NEAR(a.x, r * std::cos(phi), 1e-6);
      EXPECT_NEAR(a.y, r * std::sin(phi), 1e-6);
    }
}

TEST(core_texture, DerivativesMatchCentralDifferences) {
  const CoreTextureInput in = ciInput(cotton1());
  const CoreTextureParams& c = in.params;
  const glm::vec4 f = in.fibers.back();
  for (double th : {0.1, 1.3, 3.3, 5.9}) {
    const double h = 1e-3;
    const glm::dvec3 d1 = (glm::dvec3(ftCoreHelixPoint(c, f, float(th + h))) - glm::dvec3(ftCoreHelixPoint(c, f, float(th - h)))) / (2 * h);
    const glm::dvec3 d2 = (glm::dvec3(ftCoreHelixDerivative(c, f, float(th + h), c.twistSign)) -
                           glm::dvec3(ftCoreHelixDerivative(c, f, float(th - h), c.twistSign))) / (2 * h);
    const glm::dvec3 g1(ftCoreHelixDerivative(c, f, float(th), c.twistSign)), g2(ftCoreHelixSecond(c, f, float(th)));
    EXPECT_LT(glm::length(g1 - d1), 2e-4 * glm::length(d1)) << th;
    EXPECT_LT(glm::length(g2 - d2), 2e-3 * glm::length(d2)) << th;
  }
}

// Distance from a point to a segment, and the first ray point within r of it, by marching (double).
double segDist(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
  const glm::dvec3 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

TEST(core_texture, RayCapsuleMatchesMarching) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, caps = 0;
  for (int n = 0; n < 400; ++n) {
    const double r = 0.3;
    const glm::dvec3 a = glm::dvec3(0.3, 0.3, 0.2) * drawVec3<glm::dvec3>(u, rng);
    const glm::dvec3 b = a + glm::dvec3(0.4, 0.4, 0.6) * drawVec3<glm::dvec3>(u, rng);
    const glm::dvec2 oyz = glm::dvec2(0.6, 0.5) * drawVec2<glm::dvec2>(u, rng);
    const glm::dvec3 o(2.0, oyz);
    // March along −x in steps of 1e-3 to the first point within r, then
    // bisect (a chord shorter than a step, ~1e-6 r from the rim, is missed).
    double want = -1.0;
    for (double t = 0.0; t < 4.0; t += 1e-3)
      if (segDist(o - glm::dvec3(t, 0, 0), a, b) <= r) {
        double lo = std::max(0.0, t - 1e-3), hi = t;
        for (int it = 0; it < 60; ++it) {
          const double m = 0.5 * (lo + hi);
          (segDist(o - glm::dvec3(m, 0, 0), a, b) <= r ? hi : lo) = m;
        }
        want = hi;
        break;
      }
    const glm::vec3 got = ftRayCapsule(glm::vec3(o), glm::vec3(a), glm::vec3(b), float(r));
    if (want < 0.0) {
      EXPECT_EQ(got.z, 0.0f) << n;
      continue;
    }
    ++hits;
    ASSERT_EQ(got.z, 1.0f) << n << " marching hit at " << want;
    EXPECT_NEAR(got.x, want, 2e-5) << n;
    // w: the axis parameter of the hit's nearest axis point.
    const glm::dvec3 p = o - glm::dvec3(got.x, 0, 0), ab = b - a;
    const double w = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    caps += (w == 0.0 || w == 1.0);
    EXPECT_NEAR(got.y, w, 1e-3) << n;
  }
  EXPECT_GT(hits, 100);
  EXPECT_GT(caps, 10) << "the cap branch was not exercised";
}

// Embree round curves vs the shared capsule chain: same geometry, different intersectors.
TEST(core_texture, EmbreeAndCapsuleChainAgree) {
  const CoreTextureInput in = ciInput(cotton1());
  const CoreTexture a = bakeCoreTextureEmbree(in), b = bakeCoreTextureCapsules(in);
  size_t ha = 0, hb = 0, both = 0;
  double dh = 0.0;
  for (size_t k = 0; k < a.tex0.size(); ++k) {
    const bool x = a.tex0[k].x > 0.0f, y = b.tex0[k].x > 0.0f;
    ha += x, hb += y;
    if (x && y) ++both, dh = std::max(dh, double(std::abs(a.tex0[k].x - b.tex0[k].x)));
  }
  const double n = double(a.tex0.size());
  EXPECT_GT(ha / n, 0.3) << "the core covers a good part of its strip";
  EXPECT_LT(std::abs(double(ha) - double(hb)) / n, 0.005);
  EXPECT_GT(double(both) / double(std::max(ha, hb)), 0.98);
  EXPECT_LT(dh, 1e-3);  // the harness checks interior texels tightly; here every shared hit
}

TEST(core_texture, HeightIsZeroExactlyForHolesAndNormalIsUnit) {
  const CoreTextureInput in = ciInput(cotton1());
  const CoreTexture t = bakeCoreTextureEmbree(in);
  size_t holes = 0;
  for (size_t k = 0; k < t.tex0.size(); ++k) {
    const glm::vec4 t0 = t.tex0[k], t1 = t.tex1[k];
    if (t0.x == 0.0f) {
      ++holes;
      EXPECT_EQ(t1, glm::vec4(0.0f));
      continue;
    }
    EXPECT_GT(t0.x, 0.0f);
    EXPECT_LE(t0.x, 1.0f);
    EXPECT_LE(std::hypot(t0.y, t0.z), 1.0f + 1e-5f);
    EXPECT_NEAR(glm::length(glm::vec3(t1)), 1.0f, 1e-5f);
    EXPECT_GT(t1.x, 0.0f) << "t points toward growing u";
  }
  EXPECT_GT(holes, 0u) << "a core of a few dozen fibers leaves holes (§3.2)";
}

TEST(core_texture, LookupWrapsInUAndClampsInV) {
  // u = 0: between the last and the first column, half way.
  CoreLookup l = ftCoreTextureLookup(8, 4, 0.0f, 0.5f);
  EXPECT_EQ(l.i.x, 7u);
  EXPECT_EQ(l.i.y, 0u);
  EXPECT_NEAR(l.w.x, 0.5f, 1e-6f);
  EXPECT_EQ(l.j.x, 1u);
  EXPECT_EQ(l.j.y, 2u);
  EXPECT_NEAR(l.w.y, 0.5f, 1e-6f);
  // A texel centre returns that texel; u = 1.25 is u = 0.25.
  l = ftCoreTextureLookup(8, 4, 1.0f + 2.5f / 8.0f, 0.0f);
  EXPECT_EQ(l.i.x, 2u);
  EXPECT_NEAR(l.w.x, 0.0f, 1e-5f);
  EXPECT_EQ(l.j.x, 0u);
  EXPECT_EQ(l.j.y, 1u);
  EXPECT_EQ(l.w.y, 0.0f);
  l = ftCoreTextureLookup(8, 4, 0.3f, 1.0f);
  EXPECT_EQ(l.j.x, 3u);
  EXPECT_EQ(l.j.y, 3u);
}

// The lookup wraps u with one select (no integer remainder: llvmpipe divides
// lane by lane); the columns must be those of the remainder's definition,
// written here, for every u, at widths that are and are not powers of two.
TEST(core_texture, LookupColumnsAreTheRemainderWrap) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-3.0f, 3.0f);
  for (uint32_t width : {1u, 2u, 7u, 8u, 61u, 64u, 1000u}) {
    std::vector<float> us = {0.0f, -0.0f, 1.0f, -1e-9f, 1e-9f, std::nextafter(1.0f, 0.0f), -std::nextafter(1.0f, 0.0f),
                             0.5f / float(width), 1.0f - 0.5f / float(width)};
    for (int k = 0; k < 2000; ++k) us.push_back(unit(rng));
    for (float u : us) {
      const float x = (u - std::floor(u)) * float(width) - 0.5f;
      const int i0 = int(std::floor(x));
      const uint32_t expected0 = uint32_t((i0 % int(width) + int(width)) % int(width));
      const CoreLookup l = ftCoreTextureLookup(width, 4, u, 0.5f);
      EXPECT_EQ(l.i.x, expected0) << "width " << width << ", u " << u;
      EXPECT_EQ(l.i.y, (expected0 + 1u) % width) << "width " << width << ", u " << u;
    }
  }
}

TEST(core_texture, SamplingReturnsTexelsAtCentresAndWrapsInU) {
  const CoreTextureInput in = ciInput(cotton1());
  const CoreTexture t = bakeCoreTextureEmbree(in);
  const uint32_t w = t.columns, h = t.height;
  for (uint32_t j = 0; j < h; j += 5)
    for (uint32_t i = 0; i < w; i += 7) {
      const CoreTexel s = sampleCoreTexture(t, (i + 0.5f) / w, (j + 0.5f) / h);
      for (int c = 0; c < 4; ++c) {
        EXPECT_NEAR(s.tex0[c], t.at0(i, j)[c], 1e-5f) << i << " " << j;
        EXPECT_NEAR(s.tex1[c], t.at1(i, j)[c], 1e-5f) << i << " " << j;
      }
    }
  // u = 0 is half way between the last and the first column; u and u + 1 agree.
  const CoreTexel a = sampleCoreTexture(t, 0.0f, 0.5f), b = sampleCoreTexture(t, 1.0f, 0.5f);
  const glm::vec4 want = 0.5f * (t.at0(w - 1, h / 2 - 1) + t.at0(0, h / 2 - 1)) * 0.5f +
                         0.5f * (t.at0(w - 1, h / 2) + t.at0(0, h / 2)) * 0.5f;
  for (int c = 0; c < 4; ++c) {
    EXPECT_NEAR(a.tex0[c], want[c], 1e-5f);
    EXPECT_NEAR(b.tex0[c], a.tex0[c], 1e-6f);
  }
  EXPECT_THROW(sampleCoreTexture(CoreTexture{}, 0.5f, 0.5f), InputError);
}

TEST(core_texture, RuntimeUIsTheSemanticReadingOfEq3) {
  // u = frac(Φ/2π − k_ψ ψ/2π): Φ in turns.
  EXPECT_NEAR(ftCoreTextureU(2.25f, 0.0f, 0.5f), 0.25f, 1e-6f);
  EXPECT_NEAR(ftCoreTextureU(0.25f, float(kPi), 0.5f), 0.0f, 1e-6f);
  EXPECT_NEAR(ftCoreTextureU(0.25f, float(kPi) / 2.0f, -1.0f), 0.5f, 1e-6f);
  YarnParams p{};
  p.fiberTurnsPerLength = 2.0f;
  p.plyTurnsPerLength = 3.0f;
  EXPECT_NEAR(ftCoreBundlePhaseTurns(p, 0.5f, 0.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(ftCoreBundlePhaseTurns(p, 0.5f, -1.0f), -0.5f, 1e-6f);
}

TEST(core_texture, BadSizesAndPresetsWithoutCoreAreInputErrors) {
  const FiberSetup s = cotton1();
  try {
    makeCoreTextureInput(s.params, s.table, 1, 16);
    FAIL() << "width 1 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("width 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(makeCoreTextureInput(s.params, s.table, 128, 100000), InputError);
  YarnParams all = s.params;
  all.regularFibers = all.fiberCount;
  EXPECT_THROW(makeCoreTextureInput(all, s.table, 128, 16), InputError);
}

}  // namespace
}  // namespace ft
