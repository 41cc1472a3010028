#include "reference/flyaway.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <glm/gtc/packing.hpp>
#include <stdexcept>

namespace ft {

FlyawayCurves generateFlyawaysCpu(const FlyawayParams& f) {
  FlyawayCurves out;
  out.params = f;
  const size_t slots = size_t(f.patterns) * FT_FLYAWAY_SETS * f.maxPerSet;
  out.points.assign(slots * FT_FLYAWAY_POINTS, glm::vec4(0.0f));
  out.headers.assign(slots, glm::vec4(0.0f));
  tbb::parallel_for(uint32_t(0), f.patterns * FT_FLYAWAY_SETS, [&](uint32_t ps) {
    const uint32_t pattern = ps / FT_FLYAWAY_SETS, set = ps % FT_FLYAWAY_SETS;
    const uint32_t count = ftFlyawayCount(f, pattern, set);
    for (uint32_t slot = 0; slot < f.maxPerSet; ++slot) {
      const uint32_t index = ftFlyawaySlot(f, pattern, set, slot);
      const FlyawayShape s = ftFlyawayShape(f, pattern, set, slot, count);
      if (!s.present) continue;
      FlyawayWalk w = ftFlyawayWalkStart(s, f.alpha);
      glm::vec3 p = ftFlyawayWalkPoint(f, w);
      float zMin = p.z, zMax = p.z;
      out.points[size_t(index) * FT_FLYAWAY_POINTS] = glm::vec4(p, 0.0f);
      for (uint32_t k = 1; k <= FT_FLYAWAY_STEPS; ++k) {
        w = ftFlyawayWalkStep(f, s, pattern, set, slot, k, w);
        p = ftFlyawayWalkPoint(f, w);
        zMin = std::min(zMin, p.z), zMax = std::max(zMax, p.z);
        out.points[size_t(index) * FT_FLYAWAY_POINTS + k] = glm::vec4(p, float(k) / float(FT_FLYAWAY_STEPS));
      }
      out.headers[index] = glm::vec4(1.0f, float(ftFlyawayKept(f, set, zMin, zMax)), zMin, zMax);
    }
  });
  return out;
}

FlyawayTextures bakeFlyawaysCpu(const FlyawayCurves& c) {
  const FlyawayParams& f = c.params;
  if (c.headers.size() < size_t(FT_FLYAWAY_SETS) * f.maxPerSet || c.points.size() != c.headers.size() * FT_FLYAWAY_POINTS)
    throw std::invalid_argument("bakeFlyawaysCpu: curve buffers do not match the block");
  FlyawayTextures t;
  t.width = f.width;
  t.height = f.height;
  t.texels.assign(size_t(FT_FLYAWAY_LAYERS) * f.width * f.height, 0u);
  tbb::parallel_for(uint32_t(0), FT_FLYAWAY_LAYERS * f.height, [&](uint32_t lj) {
    const uint32_t layer = lj / f.height, j = lj % f.height;
    for (uint32_t i = 0; i < f.width; ++i) {
      const glm::vec2 q = ftFlyawayTexelYZ(f, i, j);
      bool found = false;
      float bestX = 0.0f;
      glm::vec3 bestA(0.0f), bestB(0.0f);
      for (uint32_t set : {0u, layer + 1u}) {
        for (uint32_t slot = 0; slot < f.maxPerSet; ++slot) {
          const uint32_t index = ftFlyawaySlot(f, 0u, set, slot);
          if (c.headers[index].y == 0.0f) continue;  // absent or not kept
          for (uint32_t shift = 0; shift < ftFlyawayShiftCount(set); ++shift) {
            const glm::vec3 dz(0.0f, 0.0f, shift * f.period);
            for (uint32_t k = 0; k < FT_FLYAWAY_STEPS; ++k) {
              const glm::vec3 a = glm::vec3(c.points[size_t(index) * FT_FLYAWAY_POINTS + k]) + dz;
              const glm::vec3 b = glm::vec3(c.points[size_t(index) * FT_FLYAWAY_POINTS + k + 1]) + dz;
              const glm::vec2 h = ftFlyawaySegmentHit(a, b, q, f.lineHalfWidth);
              if (h.x != 0.0f && (!found || h.y > bestX)) found = true, bestX = h.y, bestA = a, bestB = b;
            }
          }
        }
      }
      if (!found || ftFlyawayHidden(f, q.x, bestX)) continue;
      glm::vec4 texel = ftFlyawayTexel(bestA, bestB);
      if (ftFaultFlyawayCpuVFlip) texel.y = 1.0f - texel.y;  // planted (faults.def): v mirrored on the CPU side only
      t.texels[(size_t(layer) * f.height + j) * f.width + i] = glm::packUnorm4x8(texel);
    }
  });
  return t;
}

}  // namespace ft
