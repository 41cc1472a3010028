// self_shadow_gpu.h — the GPU side of the self-shadow 3D texture of Wu &
// Yuksel 2019 (000) §4.1 (common/self_shadow.h, notes-rendering A2), in two
// variants:
//   bakeExact: every texel by the shared exact line integral
//     (self_shadow_exact.comp.glsl), the same float function as the CPU
//     reference (reference/self_shadow.h);
//   bakeGrid: the paper's construction (Fig. 6): the density of each slice on
//     the texel grid (self_shadow_density.comp.glsl), then a prefix sum along
//     the light with the midpoint rule (self_shadow_prefix.comp.glsl);
// and the per-fragment lookup on a list of requests (self_shadow_lookup.comp.glsl).
// Every call uploads, dispatches and reads back (waits for the GPU).
#pragma once
#include <epoxy/gl.h>

#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "common/self_shadow.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

// One lookup: cross-section point x, ℓ⊥ of the unit ℓ towards the light, θ_ply,0.
struct SelfShadowQuery {
  glm::vec2 x{0.0f}, toLight{1.0f, 0.0f};
  float plyAngle = 0.0f;
};
// D, T = exp(−κ D) and ψ of one lookup.
struct SelfShadowAnswer {
  float density = 0.0f, transmittance = 1.0f, psi = 0.0f;
};

class SelfShadowGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, see validation/faults.h).
  explicit SelfShadowGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});

  // Texels in ftSelfShadowIndex order (u fastest, then v, then slice).
  std::vector<float> bakeExact(const YarnDensityParams& density, const SelfShadowParams& params);
  std::vector<float> bakeGrid(const YarnDensityParams& density, const SelfShadowParams& params);
  // The texture `texels` (of `params`) looked up at each query.
  std::vector<SelfShadowAnswer> lookup(const YarnDensityParams& density, const SelfShadowParams& params,
                                       std::span<const float> texels, std::span<const SelfShadowQuery> queries);

 private:
  void bindParams(const YarnDensityParams& density, const SelfShadowParams& params);
  void dispatch(GLuint program, size_t items, const char* what);
  static size_t texelCount(const SelfShadowParams& params);

  int maxGroupsY_ = 65535;
  Program exactProgram_, densityProgram_, prefixProgram_, lookupProgram_;
  Buffer params_;
};

}  // namespace ft
