// shadow_map_reference.h — the CPU side of the yarn shadow map (000 §4.1 last
// paragraph, common/shadow_map.h, docs/shadow-map.md):
//  * the ground truth (notes A5 (b)): Embree round linear curves of radius
//    R_tube through the yarn centre lines (each Catmull-Rom segment in
//    FT_SHADOW_MAP_SUBSEGMENTS pieces, the depth pass's capsules) and a binary
//    visibility ray from the point towards the light. The map stores the
//    tube's far side, so the tube region a point lies in does not occlude it
//    (a yarn's own fibers: the self-shadow texture covers those); the light
//    is blocked when the ray, once out of that region, enters a tube again;
//  * the lookup of a read-back map, the C++ twin of the frame's
//    (fiber_strip.frag.glsl shadowMapVisibility).
#pragma once
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <vector>

#include "common/shadow_map.h"
#include "scene/yarn_model.h"

namespace ft {

// Tube centre lines: polylines (world), one capsule of `radius` per piece.
struct ShadowTubes {
  std::vector<std::vector<glm::vec3>> lines;
  float radius = 0.0f;
};

// Every yarn segment of `yarn` split into FT_SHADOW_MAP_SUBSEGMENTS pieces
// (the Bézier form of its Catmull-Rom segment), one line per segment.
ShadowTubes shadowTubes(const YarnBuffers& yarn, float radius);

class ShadowMapReference {
 public:
  explicit ShadowMapReference(const ShadowTubes& tubes);
  ~ShadowMapReference();
  ShadowMapReference(const ShadowMapReference&) = delete;
  ShadowMapReference& operator=(const ShadowMapReference&) = delete;
  // 1 when p + τ·toLight, τ > 0, never enters the tubes after leaving the region around p; else 0.
  float visibility(glm::vec3 p, glm::vec3 toLight) const;
  // The same for many points (TBB).
  std::vector<float> visibility(std::span<const glm::vec3> points, glm::vec3 toLight) const;
  size_t capsuleCount() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// V_map of light i at p in a read-back map (FiberRenderer::readShadowMap),
// filtered as the frame looks it up (m.count.z: nearest texel or 2 × 2 PCF).
float shadowMapLookup(const ShadowMapParams& m, std::span<const float> texels, int light, glm::vec3 p);

}  // namespace ft
