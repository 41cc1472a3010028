// GPU frames for curves of any length (issue 8): Mesa's gallivm ends a loop
// after 65,535 iterations, so the frame kernel runs in chunks of
// FT_FRAME_CHUNK knots. A 200,000-point closed curve (25 chunks, holonomy
// spread over all of them) must validate against the CPU reference, and its
// corrected frame must close: no jump between consecutive knots, at the chunk
// boundaries and at the seam, beyond what the curve's own turning explains.
#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <unistd.h>

#include "common/constants.h"
#include "gpu/gl_context.h"
#include "reference/fiber_reference.h"
#include "scene/bcc_reader.h"
#include "scene/yarn_radius.h"
#include "validation/harness.h"

namespace ft {
namespace {

namespace fs = std::filesystem;

// A (2,3) torus knot: non-planar, so the holonomy is not zero.
YarnModel torusKnot(int points) {
  YarnModel m;
  m.name = "torus-knot";
  YarnCurve c;
  c.closed = true;
  for (int i = 0; i < points; ++i) {
    const double a = 2.0 * M_PI * i / points;
    const double r = 2.0 + std::cos(3.0 * a);
    c.points.push_back(glm::vec3(float(r * std::cos(2.0 * a)), float(std::sin(3.0 * a)), float(r * std::sin(2.0 * a))));
  }
  m.curves.push_back(c);
  return m;
}

TEST(LongCurve, ClosedCurveOf200kPointsFramesCloseAcrossChunksAndSeam) {
  const YarnModel m = torusKnot(200000);
  const YarnBuffers y = buildYarnBuffers(m);
  ASSERT_GT(ftCurveSegmentCount(y.curves[0]), 3 * FT_FRAME_CHUNK);
  const std::vector<FrameNormal> f = computeKnotFramesCpu(y);
  const CurveInfo& c = y.curves[0];
  const uint32_t n = ftCurveKnotCount(c);
  double worst = 0.0, worstTurn = 0.0;
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t j = (k + 1) % n;  // the seam: knot n-1 to knot 0
    const Knot ka = knotCpu(y, c, k), kb = knotCpu(y, c, j);
    // atan2 of |a×b| and a·b in double: acos of a dot near 1 is rounding noise at these tiny angles.
    auto angle = [](vec3 u, vec3 v) {
      const glm::dvec3 a(u), b(v);
      return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
    };
    const double normalTurn = angle(vec3(f[k].normal), vec3(f[j].normal));
    const double tangentTurn = angle(ka.tangent, kb.tangent);
    worst = std::max(worst, normalTurn);
    worstTurn = std::max(worstTurn, tangentTurn);
    // A rotation-minimizing normal turns about as much as the tangent, plus
    // this knot's share of the holonomy (at most π over 200,000 knots).
    ASSERT_LE(normalTurn, 1.1 * tangentTurn + M_PI / n + 1e-4) << "knot " << k;
  }
  EXPECT_GT(worst, 0.0);
}

TEST(LongCurve, ClosedCurveOf200kPointsValidatesOnTheGpu) {
  const fs::path dir = fs::temp_directory_path() / ("fibertwin-long-curve-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path model = dir / "torus-knot-200k.bcc";
  writeBcc(torusKnot(200000), model);
  HarnessOptions o;
  o.model = model;
  o.yarns = {"cotton1"};
  // The knot's strands are ~2 apart: fitted to that, the yarn would be 22×
  // the preset and the near view a wall of fibers. The frames are what this
  // test is about; the preset keeps its own scale.
  o.fiber.yarnRadius = static_cast<float>(presetEnvelopeRadius(findYarnPreset("cotton1")));
  o.filter = "^(frames|fiber)/";  // the knit cases do not read the model
  o.images = false;
  o.reportDir = dir / "report";
  o.backend = glBackendFromEnv();
  std::ostringstream log;
  const RunSummary run = runValidation(o, log);
  ASSERT_GT(run.results.size(), 1u) << log.str();
  if (std::getenv("FT_VERBOSE")) std::cout << log.str();
  bool framesSeen = false;
  for (const CaseResult& r : run.results) {
    framesSeen = framesSeen || r.group == "frames";
    EXPECT_TRUE(r.pass) << r.name << " " << r.error << "\n" << log.str();
  }
  EXPECT_TRUE(framesSeen);
  if (!::testing::Test::HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace ft
