// The GPU knit kernels against their CPU oracle (reference/knit_reference.h):
// knit_optimize.comp.glsl against solveKnitCpu, knit_upsample.comp.glsl against
// knitYarnModel. Tolerance: a thousandth of the yarn radius (0.05 cm), far
// below anything visible, and 100× above the float rounding the ft::knit32
// instance shows on the CPU (tests/knit_solver_test.cpp).
#include <gtest/gtest.h>

#include "gpu/gl_context.h"
#include "gpu/knit_gpu.h"
#include "knit/knit_problem.h"
#include "reference/knit_reference.h"

namespace ft {
namespace {

class KnitGpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = GlContext::create(glBackendFromEnv()).release(); }
  static void TearDownTestSuite() {
    delete context_;
    context_ = nullptr;
  }
  static GlContext* context_;
};
GlContext* KnitGpuTest::context_ = nullptr;

constexpr double kTolerance = 0.05 * 1e-3;

TEST_F(KnitGpuTest, OptimizedPointsEnergiesAndVerticesMatchTheReference) {
  for (Deformation d : {Deformation{Deformation::StretchCourse, 1.4}, Deformation{Deformation::Shear, 30.0}}) {
    const StitchMesh rest = makeRibbing1x1(6, 7);
    const KnitSetup s = buildKnitSetup(rest, deform(rest, d), {});
    const KnitSolution cpu = solveKnitCpu(s);
    KnitGpu gpu(context_->info());
    const auto records = knitGpuRecords(s);
    const auto list = knitYarnList(s);
    gpu.setStitches(records, knitSolveParams(s));
    gpu.setYarnList(list);
    gpu.run();
    const auto points = gpu.readPoints();
    const auto energies = gpu.readEnergies();
    ASSERT_EQ(points.size(), cpu.worldPoints.size());
    double worst = 0;
    for (size_t i = 0; i < points.size(); ++i)
      worst = std::max(worst, glm::length(glm::dvec3(glm::vec3(points[i])) - cpu.worldPoints[i]));
    EXPECT_LT(worst, kTolerance) << deformationKindName(d.kind);
    for (uint32_t t = 0; t < s.tileCount(); ++t) {
      // Energies: float vs double of a sum of ~33 squares; relative 1e-3 plus
      // an absolute floor for the converged (near zero) ones.
      for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(energies[t].energy[k], cpu.energy[t][k], 1e-3 * cpu.energy[t][k] + 1e-9) << t << " " << k;
      EXPECT_EQ(energies[t].steps, cpu.steps[t]);
    }
    const YarnModel ref = knitYarnModel(s, cpu.worldPoints, true);
    const YarnModel got = knitYarnModelFromVertices(s, gpu.readVertices());
    ASSERT_EQ(ref.curves.size(), got.curves.size());
    double worstV = 0;
    for (size_t c = 0; c < ref.curves.size(); ++c) {
      ASSERT_EQ(ref.curves[c].points.size(), got.curves[c].points.size());
      for (size_t i = 0; i < ref.curves[c].points.size(); ++i)
        worstV = std::max(worstV, double(glm::length(ref.curves[c].points[i] - got.curves[c].points[i])));
    }
    EXPECT_LT(worstV, kTolerance);
    std::printf("%s: worst point %.3g, vertex %.3g (tolerance %.3g)\n", std::string(deformationKindName(d.kind)).c_str(),
                worst, worstV, kTolerance);
  }
}

TEST_F(KnitGpuTest, StitchCountMismatchIsRejected) {
  KnitGpu gpu(context_->info());
  std::vector<KnitStitchGpu> one(1);
  KnitSolveParams p{1.0f, 100.0f, 3u, 2u};
  EXPECT_THROW(gpu.setStitches(one, p), std::invalid_argument);
}

}  // namespace
}  // namespace ft
