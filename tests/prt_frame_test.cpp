// prt_frame_test.cpp — the PRT frame of 004 §5 (reference/prt_frame.h,
// common/prt_frame.h): the SG light sampler against its closed-form mean
// cosine, the SSDF pixel lookup against the pixel directions, bad input
// named, and a tiny frame that is finite on both renderers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/prt_frame.h"
#include "common/segment_visibility.h"
#include "reference/prt_frame.h"
#include "scene/input_error.h"
#include "validation/draw_order.h"

namespace ft {
namespace {

// E[ω·ξ] under G(ω; ξ, λ)/M(λ) is the Langevin function coth λ − 1/λ (closed form, no common/).
TEST(PrtFrame, SgSamplerMeanCosineIsLangevin) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const glm::dvec3 xi = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  for (double lambda : {0.5, 5.0, 30.0, 150.0}) {
    const int n = 200000;
    double sum = 0.0, sq = 0.0;
    for (int i = 0; i < n; ++i) {
      const double u2 = u(rng), u1 = u(rng);  // last first (validation/draw_order.h)
      const glm::dvec3 w = sampleSgDirection(xi, lambda, u1, u2);
      ASSERT_NEAR(glm::length(w), 1.0, 1e-9);
      const double c = glm::dot(w, xi);
      sum += c, sq += c * c;
    }
    const double mean = sum / n, sigma = std::sqrt((sq / n - mean * mean) / n);
    const double langevin = 1.0 / std::tanh(lambda) - 1.0 / lambda;
    EXPECT_NEAR(mean, langevin, 5.0 * sigma + 1e-12) << "lambda " << lambda;
  }
}

// Every pixel centre direction of the visibility image maps back to its own pixel.
TEST(PrtFrame, SvfPixelLookupInvertsPixelDirections) {
  for (int n : {16, 32, 64})
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) EXPECT_EQ(ftPrtFrameSvfPixel(ftSvfPixelDirection(x, y, n, n), n, n), y * n + x);
}

TEST(PrtFrame, BadInputIsNamed) {
  PrtFrameView v;
  v.wo = glm::vec3(0.0f, 0.0f, -1.0f);
  try {
    checkPrtFrameView(v);
    FAIL() << "an eye below the fabric was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("view direction"), std::string::npos) << e.what();
  }
  v = PrtFrameView{};
  v.lambda = -1.0f;
  EXPECT_THROW(checkPrtFrameView(v), InputError);
  PrtFrameSettings s;
  s.svfSize = 7;
  try {
    checkPrtFrameSettings(s);
    FAIL() << "an odd visibility image size was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--svf-size"), std::string::npos) << e.what();
  }
}

TEST(PrtFrame, TinyFrameIsFiniteAndCovered) {
  PrtFrameSettings s;
  s.exemplar.fibersPerPly = 4;
  s.exemplar.subdivisions = 1;
  s.tiles = 3;
  s.width = s.height = 8;
  s.svfSize = 8;
  s.pathsPerCell = 50;
  s.ellPaths = 50;
  s.msThetaINodes = 64;
  s.msPhiNodes = 32;
  PrtFrameScene scene(s);
  PrtFrameView v;
  v.wo = glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f));
  v.light = glm::normalize(glm::vec3(-0.3f, 0.4f, 0.9f));
  v.lambda = 50.0f;
  const PrtFrameParts prt = scene.renderPrt(v);
  const PrtFrameImage pt = scene.renderPathTraced(v, 4, 8);
  EXPECT_GT(prt.total.covered, 0u);
  EXPECT_GT(pt.covered, 0u);
  EXPECT_EQ(comparePrtFrame(prt.total, pt, false).nonFinite, 0u);
  for (size_t i = 0; i < prt.total.rgb.size(); ++i)  // the composition is the sum of the parts (V̄_glo = 1)
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(prt.total.rgb[i][c], prt.single.rgb[i][c] + prt.multi.rgb[i][c]);
}

}  // namespace
}  // namespace ft
