// The CPU reference's output contract: canonical order, counts that match
// its decisions, and determinism under TBB.
#include <gtest/gtest.h>

#include "common/fiber_generation.h"
#include "reference/fiber_reference.h"
#include "scene/camera.h"
#include "scene/default_scene.h"
#include "scene/yarn_fibers.h"

namespace ft {
namespace {

TEST(FiberReference, CanonicalOrderAndDeterminism) {
  const YarnModel model = makeDefaultScene();
  const YarnBuffers buffers = buildYarnBuffers(model);
  const YarnPreset& preset = findYarnPreset("polyester1");
  FiberOptions options;
  options.seed = 3;
  const FiberSetup fibers = makeFiberSetup(preset, options);
  const std::vector<FiberCoord>& table = fibers.table;
  const YarnParams& params = fibers.params;
  const Camera cam = lodCamera(model, params, LodDistance::Near, 1.0f, 640, 480);
  FiberInput input{&buffers, &table, params, makeViewParams(cam, 1.0f, true, true)};
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(buffers);
  const FiberGeometry a = generateFibersCpu(input, frames), b = generateFibersCpu(input, frames);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (size_t i = 0; i < a.vertices.size(); ++i) {
    ASSERT_EQ(a.vertices[i].position, b.vertices[i].position) << i;
    ASSERT_EQ(a.vertices[i].id, b.vertices[i].id) << i;
  }
  size_t at = 0, culled = 0;
  for (size_t i = 0; i < a.segments.size(); ++i) {
    const SegmentDecision& d = a.decisions[i];
    culled += d.culled;
    for (uint32_t ply = 0; d.culled == 0 && ply < params.plyCount; ++ply)
      for (uint32_t slot = 0; slot < ftSlotsPerPly(d); ++slot)
        for (uint32_t v = 0; v < ftStripVertexCount(d, slot); ++v, ++at) {
          const FiberVertex& fv = a.vertices.at(at);
          ASSERT_EQ(fv.id.y, a.segments[i]);
          ASSERT_EQ(fv.id.z >> 16, ply);
          ASSERT_EQ(fv.id.z & 0xFFFFu, slot == 0 ? FT_CORE_FIBER_ID : ftSlotFiber(params, slot));
          ASSERT_EQ((fv.id.w >> 8) & 0xFFu, v);
        }
  }
  EXPECT_EQ(at, a.vertices.size());
  EXPECT_GT(culled, 0u);
  EXPECT_LT(culled, a.segments.size());
}

// A segment subset generates exactly those segments' fibers, in list order.
TEST(FiberReference, SegmentSubsetMatchesTheFullRun) {
  const YarnModel model = makeDefaultScene();
  const YarnBuffers buffers = buildYarnBuffers(model);
  const YarnPreset& preset = findYarnPreset("silk1");
  const FiberSetup fibers = makeFiberSetup(preset, FiberOptions{});
  const std::vector<FiberCoord>& table = fibers.table;
  const YarnParams& params = fibers.params;
  FiberInput input{&buffers, &table, params, makeViewParams(frameModel(model, {0, 1, 1}, 320, 240), 1.0f, false, false)};
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(buffers);
  const FiberGeometry all = generateFibersCpu(input, frames);
  const std::vector<uint32_t> subset = {7, 3, 100};
  const FiberGeometry part = generateFibersCpu(input, frames, subset);
  // Counts differ per segment (the subdivisions follow the screen): find
  // each segment's range from the decisions.
  std::vector<size_t> firstOf(all.decisions.size() + 1, 0);
  for (size_t i = 0; i < all.decisions.size(); ++i) firstOf[i + 1] = firstOf[i] + all.decisions[i].vertexCount;
  ASSERT_EQ(firstOf.back(), all.vertices.size());
  size_t at = 0;
  for (size_t k = 0; k < subset.size(); ++k) {
    ASSERT_EQ(part.decisions[k].vertexCount, all.decisions[subset[k]].vertexCount);
    for (size_t v = 0; v < part.decisions[k].vertexCount; ++v, ++at) {
      const FiberVertex& p = part.vertices[at];
      const FiberVertex& f = all.vertices[firstOf[subset[k]] + v];
      ASSERT_EQ(p.position, f.position);
      ASSERT_EQ(p.id, f.id);
    }
  }
  EXPECT_EQ(at, part.vertices.size());
}

}  // namespace
}  // namespace ft
