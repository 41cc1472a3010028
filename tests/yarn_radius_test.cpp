// The yarn radius a model was built for (scene/yarn_radius.h), against
// models whose spacing is known by construction, and the preset scaling.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "knit/knit_problem.h"
#include "knit/stitch_mesh.h"
#include "scene/bcc_reader.h"
#include "scene/default_scene.h"
#include "scene/input_error.h"
#include "scene/yarn_radius.h"
#include "tests/test_data.h"

namespace ft {
namespace {

YarnCurve line(glm::vec3 from, glm::vec3 to, int points) {
  YarnCurve c;
  for (int i = 0; i < points; ++i) c.points.push_back(glm::mix(from, to, float(i) / float(points - 1)));
  return c;
}

// Parallel yarns `pitch` apart touch when the radius is pitch / 2.
TEST(YarnRadius, ParallelYarns) {
  YarnModel m;
  m.name = "parallel";
  for (int k = 0; k < 6; ++k) m.curves.push_back(line({0.0f, 0.0f, 0.3f * k}, {4.0f, 0.0f, 0.3f * k}, 41));
  const YarnRadiusEstimate e = estimateYarnRadius(m);
  EXPECT_NEAR(e.radius, 0.15, 0.15 * 1e-3);
  EXPECT_EQ(e.withNeighbour, e.samples);
}

// One yarn coiled into a spring: its neighbour is itself one turn later (the
// arc between the two points is far longer than their distance).
TEST(YarnRadius, CoilTouchesItself) {
  YarnModel m;
  m.name = "coil";
  YarnCurve c;
  const double radius = 1.0, pitch = 0.25;
  for (int i = 0; i <= 8 * 64; ++i) {
    const double a = 2.0 * M_PI * i / 64.0;
    c.points.push_back(glm::vec3(radius * std::cos(a), pitch * a / (2.0 * M_PI), radius * std::sin(a)));
  }
  m.curves.push_back(c);
  const YarnRadiusEstimate e = estimateYarnRadius(m);
  // The turns are 0.25 apart along the axis; the chord between samples cuts
  // inside the circle by 1 - cos(π/64) ≈ 1.2e-3 at most.
  EXPECT_NEAR(e.radius, 0.125, 0.125 * 0.01);
}

// The built-in scene: yarns cross 2 × 0.04 apart (default_scene.cpp).
TEST(YarnRadius, DefaultScene) {
  EXPECT_NEAR(estimateYarnRadius(makeDefaultScene()).radius, 0.04, 0.04 * 0.02);
}

// A knitted stockinette from the knot model of 001 §3: contacts are eq. 4's
// 2r apart, so the estimate must land near the knot yarn radius r.
TEST(YarnRadius, KnitStockinetteNearKnotRadius) {
  KnitOptions o;
  const StitchMesh rest = makeStockinette(12, 12);
  const KnitSetup setup = buildKnitSetup(rest, rest, o);
  const YarnModel m = knitYarnModel(setup, liftKnitPoints(setup, initialKnitPoints(setup)), false);
  const YarnRadiusEstimate e = estimateYarnRadius(m);
  EXPECT_NEAR(e.radius, o.yarnRadius, 0.15 * o.yarnRadius) << "estimated " << e.radius;
}

// The shipped models, as docs/pictures.md quotes them.
TEST(YarnRadius, ShippedModels) {
  EXPECT_NEAR(estimateYarnRadius(readBcc(test::yarnModel("glove.bcc"))).radius, 0.0913, 0.0005);
  EXPECT_NEAR(estimateYarnRadius(readBcc(test::yarnModel("fiber.bcc"))).radius, 0.0890, 0.0005);
}

TEST(YarnRadius, LoneStraightYarnHasNoThickness) {
  YarnModel m;
  m.name = "lonely.bcc";
  m.curves.push_back(line({0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, 11));
  EXPECT_FALSE(estimateYarnRadius(m).found);
  // Fitting then keeps the preset's own scale, and says so.
  const FittedPreset f = fitYarnPreset(findYarnPreset("cotton1"), m, std::nullopt);
  EXPECT_DOUBLE_EQ(f.scale, 1.0);
  EXPECT_NE(f.source.find("lonely.bcc"), std::string::npos) << f.source;
  EXPECT_NE(f.source.find("own scale"), std::string::npos) << f.source;
}

// Neighbours far apart compared with the point spacing (a densely sampled
// knot whose strands are 50 spacings apart) are still found, quickly.
TEST(YarnRadius, SparseNeighboursOfADenseCurve) {
  YarnModel m;
  m.name = "dense pair";
  m.curves.push_back(line({0.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, 40001));
  m.curves.push_back(line({0.0f, 0.0025f, 0.0f}, {2.0f, 0.0025f, 0.0f}, 2));  // spacing 5e-5 vs distance 2.5e-3
  m.curves.push_back(line({0.0f, 0.0f, 1.0f}, {2.0f, 0.0f, 1.0f}, 40001));
  m.curves.push_back(line({0.0f, 0.0025f, 1.0f}, {2.0f, 0.0025f, 1.0f}, 40001));
  const YarnRadiusEstimate e = estimateYarnRadius(m);
  ASSERT_TRUE(e.found);
  EXPECT_NEAR(e.radius, 0.00125, 0.00125 * 0.01);
  EXPECT_LE(e.samples, 20001u);
}

// Every length of reference-data §2 scales, every ratio and angle stays.
TEST(YarnRadius, ScaleEveryLength) {
  const YarnPreset& p = findYarnPreset("rayon3");
  const double k = 2.5;
  const YarnPreset s = scaleYarnPreset(p, k);
  EXPECT_DOUBLE_EQ(s.yarnRadius, k * p.yarnRadius);
  EXPECT_DOUBLE_EQ(s.yarnAlpha, k * p.yarnAlpha);
  EXPECT_DOUBLE_EQ(s.alpha, k * p.alpha);
  EXPECT_DOUBLE_EQ(s.ellipseLong, k * p.ellipseLong);
  EXPECT_DOUBLE_EQ(s.ellipseShort, k * p.ellipseShort);
  EXPECT_DOUBLE_EQ(s.hairZe.mu, k * p.hairZe.mu);
  EXPECT_DOUBLE_EQ(s.hairZe.sigma, k * p.hairZe.sigma);
  EXPECT_DOUBLE_EQ(s.hairR0.mu, k * p.hairR0.mu);
  EXPECT_DOUBLE_EQ(s.hairRe.sigma, k * p.hairRe.sigma);
  EXPECT_DOUBLE_EQ(s.loopR1.mu, k * p.loopR1.mu);
  EXPECT_DOUBLE_EQ(s.hairDensity, p.hairDensity / k);
  EXPECT_DOUBLE_EQ(s.loopDensity, p.loopDensity / k);
  EXPECT_DOUBLE_EQ(s.hairPe.mu, p.hairPe.mu);  // an angle
  EXPECT_DOUBLE_EQ(s.sI, p.sI);
  EXPECT_DOUBLE_EQ(s.rhoMin, p.rhoMin);
  EXPECT_DOUBLE_EQ(s.rMax, p.rMax);
  EXPECT_DOUBLE_EQ(s.beta, p.beta);
  EXPECT_THROW(scaleYarnPreset(p, 0.0), InputError);
  EXPECT_THROW(scaleYarnPreset(p, std::nan("")), InputError);
}

// Fitted to a radius R, the yarn's envelope (ply offset + ply semi-axis)
// is R, and the drawn fiber radius scales with it.
TEST(YarnRadius, FitToRadius) {
  const YarnPreset& p = findYarnPreset("cotton1");
  FiberOptions o;
  o.yarnRadius = 0.1f;
  const FittedFibers f = fitFibers(p, makeDefaultScene(), o);
  EXPECT_EQ(f.fit.source, "--yarn-radius");
  EXPECT_NEAR(f.params.plyRadius + f.params.ellipseB * f.params.rhoMax, 0.1, 1e-6);
  EXPECT_NEAR(f.params.fiberRadius, o.fiberRadius * f.fit.scale, 1e-9);
  EXPECT_NEAR(f.fit.scale, double(o.yarnRadius) / (p.yarnRadius / 2 + p.ellipseLong * p.rhoMax), 1e-12);
  o.yarnRadius = -1.0f;
  EXPECT_THROW(fitFibers(p, makeDefaultScene(), o), InputError);
}

}  // namespace
}  // namespace ft
