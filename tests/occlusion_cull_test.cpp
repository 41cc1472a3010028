// The occlusion pyramid's layout and level choice (common/occlusion_cull.h)
// against brute force: every level halves with rounding up down to 1 × 1, the
// levels lie back to back, a texel of level k covers exactly the pixels
// [x·2^k, (x+1)·2^k), and the level chosen for a pixel rectangle is the
// lowest at which it spans at most 4 × 4 texels. That the culling changes no
// pixel is the harness's shading/occlusion-cull cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "common/constants.h"
#include "common/occlusion_cull.h"

namespace ft {
namespace {

TEST(OcclusionPyramid, LevelsHalveRoundingUpToOneTexel) {
  for (const auto& [w, h] : {std::pair{1280u, 960u}, {320u, 240u}, {1u, 1u}, {7u, 3u}, {1u, 1000u}, {8192u, 8192u}}) {
    const OcclusionPyramid p = ftOcclusionPyramidLayout(w, h);
    ASSERT_GE(p.size.z, 1u);
    uint32_t first = 0, lw = w, lh = h;
    for (uint32_t k = 0; k < p.size.z; ++k) {
      EXPECT_EQ(p.level[k].x, first) << w << "x" << h << " level " << k;
      EXPECT_EQ(p.level[k].y, lw);
      EXPECT_EQ(p.level[k].z, lh);
      first += lw * lh;
      lw = (lw + 1) / 2;
      lh = (lh + 1) / 2;
    }
    const glm::uvec4 last = p.level[p.size.z - 1];
    EXPECT_EQ(last.y * last.z, 1u) << w << "x" << h;
    EXPECT_EQ(ftOcclusionTexelCount(p), first);
  }
}

TEST(OcclusionPyramid, LevelForSpansAtMostFourByFourAndIsTheLowest) {
  const OcclusionPyramid p = ftOcclusionPyramidLayout(1280, 960);
  for (uint32_t x0 = 0; x0 < 1280; x0 += 37)
    for (uint32_t ex : {0u, 1u, 2u, 5u, 63u, 64u, 300u, 1279u})
      for (uint32_t ey : {0u, 3u, 100u}) {
        const uint32_t x1 = std::min(x0 + ex, 1279u), y0 = (x0 * 7) % 960, y1 = std::min(y0 + ey, 959u);
        const uint32_t k = ftOcclusionLevelFor(p, glm::uvec2(x0, y0), glm::uvec2(x1, y1));
        EXPECT_LE((x1 >> k) - (x0 >> k), 3u);
        EXPECT_LE((y1 >> k) - (y0 >> k), 3u);
        if (k > 0) {
          const uint32_t j = k - 1;
          EXPECT_TRUE((x1 >> j) - (x0 >> j) > 3u || (y1 >> j) - (y0 >> j) > 3u) << "level " << k << " is not the lowest";
        }
      }
}

// The nearest window depth of a ball: no point of the ball projects nearer.
TEST(OcclusionPyramid, NearestWindowDepthBoundsTheBall) {
  ViewParams v{};
  const glm::mat4 view = glm::lookAt(glm::vec3(0.3f, 0.5f, 4.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0));
  v.viewProj = glm::perspective(glm::radians(40.0f), 4.0f / 3.0f, 0.1f, 100.0f) * view;
  const glm::vec3 centre(0.2f, -0.1f, 0.5f);
  const float reach = 0.3f;
  const float bound = ftNearestWindowDepth(v, centre, reach);
  float nearest = 1.0f;
  for (int i = 0; i < 20000; ++i) {  // points of the sphere, by a golden-angle spiral
    const float z = 1.0f - 2.0f * (i + 0.5f) / 20000.0f, r = std::sqrt(1.0f - z * z), phi = 2.39996323f * i;
    const glm::vec4 c = v.viewProj * glm::vec4(centre + reach * glm::vec3(r * std::cos(phi), r * std::sin(phi), z), 1.0f);
    nearest = std::min(nearest, 0.5f * c.z / c.w + 0.5f);
  }
  EXPECT_LE(bound, nearest);
  EXPECT_GT(bound, nearest - 1e-4f) << "the bound is the ball's own nearest depth, not a loose one";
  // An orthographic view has no view axis in clip w: nothing is culled.
  v.viewProj = glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 0.1f, 10.0f) * view;
  EXPECT_EQ(ftNearestWindowDepth(v, centre, reach), 0.0f);
}

// Two-pass culling's line keys: inside the 2^bits marks, the same for the
// same line whatever else its vertex id holds (the curve, the type and
// period bits), and spread: over 200 k lines of a glove-like model (segments
// × plies × fibers × lines) into 2^22 marks, the lines that share a mark
// with an earlier one are near the n / 2m ≈ 2.4 % of a uniform hash. A
// shared mark only costs time (both lines drawn first when either was seen).
TEST(OcclusionPyramid, LineKeysStayInRangeAndSpread) {
  const uint32_t bits = 22;
  std::vector<bool> taken(size_t(1) << bits, false);
  size_t lines = 0, shared = 0;
  for (uint32_t segment = 0; segment < 800; ++segment)
    for (uint32_t ply = 0; ply < 3; ++ply)
      for (uint32_t fiber : {0u, 1u, 5u, 19u, 74u, uint32_t(FT_CORE_FIBER_ID)})
        for (uint32_t vertex = 0; vertex < 14; ++vertex) {
          const glm::uvec4 id(segment / 40, segment, (ply << 16u) | fiber, (vertex << 8u) | FT_FIBER_MIGRATION);
          const uint32_t key = ftLineKey(id, bits);
          ASSERT_LT(key, 1u << bits);
          const glm::uvec4 other(id.x + 3, id.y, id.z, (7u << 16u) | (vertex << 8u) | FT_FIBER_HAIR);
          EXPECT_EQ(ftLineKey(other, bits), key) << "the key depends only on segment, ply, fiber and vertex";
          shared += taken[key];
          taken[key] = true;
          ++lines;
        }
  const double expected = double(lines) / double(2u << bits);
  EXPECT_LT(double(shared) / double(lines), 1.5 * expected) << shared << " of " << lines << " lines share a mark";
  EXPECT_EQ(ftLineKey(glm::uvec4(0, 5, 7, 3u << 8u), 32u), ftLineKey(glm::uvec4(0, 5, 7, 3u << 8u), 32u));
}

}  // namespace
}  // namespace ft
