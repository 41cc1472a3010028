// shadow_scene.h — what the cases that judge shadow maps against Embree rays
// through the yarn tubes share (shadowmap/embree, pcss/embree): the built-in
// scene with cotton1 fitted, the map size that resolves the tubes, and
// points spread through the tubes.
#pragma once
#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "reference/shadow_map_reference.h"
#include "scene/default_scene.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_preset.h"
#include "validation/draw_order.h"
#include "validation/harness.h"

namespace ft {

// The built-in scene whatever --model says (notes A5 C5: on whole models of
// tightly packed yarns the map's bias shows, which these cases do not gate).
struct ShadowCaseScene {
  YarnBuffers buffers;
  FittedFibers fitted;
};
inline const ShadowCaseScene& shadowCaseScene(ValidationContext& ctx) {
  return ctx.cached(CacheKey<ShadowCaseScene>{"shadow-cases/default-scene"}, [&] {
    ShadowCaseScene sc;
    const YarnModel model = makeDefaultScene();
    sc.buffers = buildYarnBuffers(model);
    sc.fitted = fitFibers(findYarnPreset("cotton1"), model, ctx.options().fiber);
    return sc;
  });
}

// The map must resolve the tubes for a comparison to mean anything: the
// smallest power of two from `ciSize` up whose texel is ≤ W/4, at most 4096²
// (`texelAtCi`: the texel of the map drawn at ciSize).
inline uint32_t tubeResolvingMapSize(uint32_t ciSize, double texelAtCi, double w) {
  const double side = texelAtCi * ciSize;
  uint32_t size = ciSize;
  while (size < 4096u && side / size > w / 4.0) size *= 2u;
  return size;
}

// n points uniform in balls of radius 0.95 W around random points of the
// tubes' centre lines (where fibers lie), from `seed`.
inline std::vector<glm::vec3> pointsInTubes(const ShadowTubes& tubes, float w, size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::vector<glm::vec3> points;
  while (points.size() < n && !tubes.lines.empty()) {
    const auto& line = tubes.lines[std::min(size_t(u01(rng) * tubes.lines.size()), tubes.lines.size() - 1)];
    const size_t k = std::min(size_t(u01(rng) * (line.size() - 1)), line.size() - 2);
    const glm::vec3 centre = glm::mix(line[k], line[k + 1], u01(rng));
    glm::vec3 o;
    do o = drawVec3<glm::vec3>(u01, rng) * 2.0f - 1.0f;
    while (glm::dot(o, o) > 1.0f);
    points.push_back(centre + 0.95f * w * o);
  }
  return points;
}

}  // namespace ft
