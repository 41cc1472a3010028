// self_shadow.cpp — see self_shadow.h (reference).
#include "reference/self_shadow.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace ft {

SelfShadowParams makeSelfShadowParams(const YarnDensityParams& density, uint32_t width, uint32_t height,
                                      uint32_t slices, std::optional<float> kappa) {
  // 3 texels: one of margin on each side of the support and one inside.
  if (width < 3 || height < 3 || slices < 1 || width > 4096 || height > 4096 || slices > 4096)
    throw std::invalid_argument(fmt::format("self-shadow texture size {}×{}×{}: each axis must be in [3, 4096] "
                                            "(slices in [1, 4096])",
                                            width, height, slices));
  if (kappa && !(std::isfinite(*kappa) && *kappa >= 0.0f))
    throw std::invalid_argument(fmt::format("self-shadow kappa {}: must be a finite number ≥ 0", *kappa));
  if (!(density.supportRadius > 0.0f) || density.plyCount == 0)
    throw std::invalid_argument(fmt::format("self-shadow: density field without support (W {}, {} plies)",
                                            density.supportRadius, density.plyCount));
  const float k = kappa ? *kappa : 2.0f * ftSelfShadowFiberRadius(density);
  return ftSelfShadowParams(density, width, height, slices, k);
}

SelfShadowTexture bakeSelfShadowCpu(const YarnDensityParams& density, const SelfShadowParams& params) {
  SelfShadowTexture t;
  t.params = params;
  t.density = density;
  t.texels.resize(size_t(params.width) * params.height * params.slices);
  const uint32_t rows = params.height * params.slices;
  tbb::parallel_for(uint32_t(0), rows, [&](uint32_t row) {
    const uint32_t j = row % params.height, k = row / params.height;
    const float psi = ftSelfShadowSliceAngle(params, k);
    for (uint32_t i = 0; i < params.width; ++i)
      t.texels[ftSelfShadowIndex(params, i, j, k)] = ftSelfShadowExactAt(params, density, i, j, psi);
  });
  return t;
}

float lookupSelfShadowCpu(const SelfShadowTexture& texture, glm::vec2 x, glm::vec2 toLight, float plyAngle) {
  const SelfShadowSample s = ftSelfShadowSample(texture.params, x, toLight, plyAngle);
  const auto corners = [&](uint32_t k) {
    return glm::vec4(texture.at(s.u.x, s.u.z, k), texture.at(s.u.y, s.u.z, k), texture.at(s.u.x, s.u.w, k),
                     texture.at(s.u.y, s.u.w, k));
  };
  return ftSelfShadowBlend(s, corners(s.r.x), corners(s.r.y));
}

}  // namespace ft
