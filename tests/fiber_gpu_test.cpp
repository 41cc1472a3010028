// Each fiber kernel paired with its CPU oracle, on the built-in scene: knot
// frames, LoD/culling decisions, the prefix-sum scan, compute generation and
// tessellation capture. (The harness runs the same comparisons at scale; these
// pin each kernel down on its own.)
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>

#include "common/fiber_generation.h"
#include "gpu/fiber_gpu.h"
#include "gpu/gl_context.h"
#include "reference/fiber_reference.h"
#include "scene/camera.h"
#include "scene/default_scene.h"
#include "scene/yarn_fibers.h"
#include "validation/vertex_compare.h"

namespace ft {
namespace {

class FiberGpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    context_ = GlContext::create(glBackendFromEnv()).release();
    const GlInfo& g = context_->info();
    gpu_ = new FiberGpu(g);
  }
  static void TearDownTestSuite() {
    delete gpu_;
    delete context_;
  }
  void SetUp() override {
    model_ = makeDefaultScene();
    buffers_ = buildYarnBuffers(model_);
    const YarnPreset& preset = findYarnPreset("cotton2");
    FiberOptions o;
    o.seed = 5;
    FiberSetup fibers = makeFiberSetup(preset, o);
    table_ = std::move(fibers.table);
    params_ = fibers.params;
    view_ = makeViewParams(lodCamera(model_, params_, LodDistance::Near, 1.0f, 640, 480), 1.0f, true, true);
    frames_ = computeKnotFramesCpu(buffers_);
    gpu_->setModel(buffers_, table_);
    gpu_->setParams(params_, view_);
    gpu_->setSegmentList({});
  }
  FiberGeometry cpu(std::span<const uint32_t> list = {}) {
    FiberInput in{&buffers_, &table_, params_, view_};
    return generateFibersCpu(in, frames_, list);
  }
  static GlContext* context_;
  static FiberGpu* gpu_;
  YarnModel model_;
  YarnBuffers buffers_;
  std::vector<FiberCoord> table_;
  YarnParams params_{};
  ViewParams view_{};
  std::vector<FrameNormal> frames_;
};
GlContext* FiberGpuTest::context_ = nullptr;
FiberGpu* FiberGpuTest::gpu_ = nullptr;

// Tolerance: the propagation runs the same float operations on both sides;
// only sqrt/atan/sin/cos may differ by ulps: 1e-5 per component.
TEST_F(FiberGpuTest, KnotFramesMatchTheCpu) {
  const std::vector<FrameNormal> g = gpu_->readFrames();
  ASSERT_EQ(g.size(), frames_.size());
  for (size_t i = 0; i < g.size(); ++i)
    EXPECT_LT(glm::length(vec3(g[i].normal) - vec3(frames_[i].normal)), 1e-5f) << "knot " << i;
}

// Flat dispatches past one row of work groups: a device that allowed only 3
// groups along x would run every compute pass (decide, scan, owners,
// samples, generate) in rows along y. No real model needs the 65,535 × 64
// invocations that take llvmpipe there, so the limit is lowered instead; the
// output must not change by a bit.
TEST_F(FiberGpuTest, DispatchesSpreadOverRowsGiveTheSameVertices) {
  gpu_->generateCompute();
  const std::vector<FiberVertex> wide = gpu_->readComputeVertices();
  GlInfo narrowInfo = context_->info();
  narrowInfo.maxComputeWorkGroupCount[0] = 3;
  FiberGpu narrow(narrowInfo);
  narrow.setModel(buffers_, table_);
  narrow.setParams(params_, view_);
  narrow.setSegmentList({});
  narrow.generateCompute();
  const std::vector<FiberVertex> rows = narrow.readComputeVertices();
  ASSERT_GT(wide.size(), 3u * 64u * 4u);  // several rows in every pass
  ASSERT_EQ(rows.size(), wide.size());
  for (size_t i = 0; i < wide.size(); ++i) {
    ASSERT_EQ(rows[i].position, wide[i].position) << "vertex " << i;
    ASSERT_EQ(rows[i].id, wide[i].id) << "vertex " << i;
  }
  const std::vector<FrameNormal> fw = gpu_->readFrames(), fr = narrow.readFrames();
  ASSERT_EQ(fr.size(), fw.size());
  for (size_t i = 0; i < fw.size(); ++i) ASSERT_EQ(fr[i].normal, fw[i].normal) << "knot " << i;
}

// Decisions are discrete: equal, except λ itself (ulps).
TEST_F(FiberGpuTest, DecisionsMatchTheCpu) {
  gpu_->generateCompute();
  const std::vector<SegmentDecision> g = gpu_->readDecisions();
  const FiberGeometry c = cpu();
  ASSERT_EQ(g.size(), c.decisions.size());
  size_t culled = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(g[i].culled, c.decisions[i].culled) << i;
    EXPECT_EQ(g[i].regularCount, c.decisions[i].regularCount) << i;
    EXPECT_EQ(g[i].subdivisions, c.decisions[i].subdivisions) << i;
    EXPECT_NEAR(g[i].lambda, c.decisions[i].lambda, 1e-6f) << i;
    culled += c.decisions[i].culled;
  }
  EXPECT_GT(culled, 0u) << "the near view should cull part of the scene";
}

// The scan kernel against std::exclusive_scan, on lists longer than one
// work group (1024) and not a multiple of it, with repeated segments.
TEST_F(FiberGpuTest, ScanMatchesExclusiveScan) {
  for (size_t n : {size_t(1), size_t(1023), size_t(1025), size_t(5000)}) {
    std::vector<uint32_t> list(n);
    for (size_t i = 0; i < n; ++i) list[i] = static_cast<uint32_t>((i * 7) % buffers_.segments.size());
    gpu_->setSegmentList(list);
    gpu_->generateCompute();
    const FiberGeometry c = cpu(list);
    size_t vertices = 0, strips = 0;
    for (const SegmentDecision& d : c.decisions) {
      vertices += d.vertexCount;
      strips += d.culled ? 0 : params_.plyCount * (1u + d.regularCount);
    }
    const DrawElementsCommand cmd = gpu_->readDrawCommand();
    EXPECT_EQ(cmd.vertexTotal, vertices) << n;
    EXPECT_EQ(cmd.stripTotal, strips) << n;
    EXPECT_EQ(cmd.count, vertices + strips) << n;  // one restart index per strip
    EXPECT_EQ(cmd.instanceCount, 1u);
    // Canonical order makes the compute stream equal to the CPU's element by element.
    const std::vector<FiberVertex> g = gpu_->readComputeVertices();
    ASSERT_EQ(g.size(), c.vertices.size());
    for (size_t i = 0; i < g.size(); ++i) ASSERT_EQ(g[i].id, c.vertices[i].id) << "list " << n << " vertex " << i;
  }
}

// Generated positions: 5% of a fiber radius (see validation/fiber_cases.cpp).
TEST_F(FiberGpuTest, ComputeVerticesMatchTheCpu) {
  gpu_->generateCompute();
  const FiberGeometry c = cpu();
  const std::vector<FiberVertex> g = gpu_->readComputeVertices();
  const StreamComparison r = compareStreams(c.vertices, g, params_.boundRadius);
  EXPECT_EQ(r.missing + r.extra + r.idMismatch, 0u) << r.firstMismatches;
  EXPECT_LT(r.maxAbs, 0.05 * params_.fiberRadius);
  EXPECT_GT(r.cpuVertices, 1000u);
}

TEST_F(FiberGpuTest, TessellationCaptureMatchesTheCpu) {
  const size_t lines = gpu_->captureTessellation();
  const FiberGeometry c = cpu();
  size_t expectedLines = 0;
  for (const SegmentDecision& d : c.decisions)
    if (!d.culled) expectedLines += size_t(params_.plyCount) * (1u + d.regularCount) * d.subdivisions;
  EXPECT_EQ(lines, expectedLines);
  const std::vector<FiberVertex> g = gpu_->readTessellationLines();
  const StreamComparison r = compareStreams(c.vertices, g, params_.boundRadius);
  EXPECT_EQ(r.missing + r.extra + r.idMismatch + r.duplicateDisagree, 0u) << r.firstMismatches;
  EXPECT_LT(r.maxAbs, 0.05 * params_.fiberRadius);
}

// More fiber slots than one patch's isolines: instanced patches cover them.
TEST_F(FiberGpuTest, InstancedPatchesCoverMoreFibersThanOnePatch) {
  FiberOptions o;
  o.regularFibersPerPly = 30;  // 3 plies × 31 slots = 93 > 64 isolines: two instances
  params_ = makeYarnParams(findYarnPreset("cotton2"), table_, o);
  ASSERT_GT(params_.plyCount * (1 + params_.regularFibers), 64u);
  gpu_->setParams(params_, view_);
  gpu_->captureTessellation();
  const StreamComparison r = compareStreams(cpu().vertices, gpu_->readTessellationLines(), params_.boundRadius);
  EXPECT_EQ(r.missing + r.extra + r.idMismatch, 0u) << r.firstMismatches;
  EXPECT_EQ(r.cpuFibers, r.gpuFibers);
}

}  // namespace
}  // namespace ft
