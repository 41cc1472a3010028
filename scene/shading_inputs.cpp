#include "scene/shading_inputs.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "scene/input_error.h"

namespace ft {

SelfShadowParams frameSelfShadowParams(const YarnDensityParams& density, const AppearanceOptions& o) {
  if (o.selfShadowSize < 3 || o.selfShadowSize > 4096)
    throw InputError(fmt::format("--self-shadow-size: {} must be in [3, 4096]", o.selfShadowSize));
  if (o.selfShadowSlices < 1 || o.selfShadowSlices > 4096)
    throw InputError(fmt::format("--self-shadow-slices: {} must be in [1, 4096]", o.selfShadowSlices));
  if (!std::isfinite(o.selfShadowKappa))
    throw InputError(fmt::format("--self-shadow-kappa: {} must be a finite number", o.selfShadowKappa));
  const float kappa = o.selfShadowKappa >= 0.0f ? o.selfShadowKappa : 2.0f * ftSelfShadowFiberRadius(density);
  return ftSelfShadowParams(density, o.selfShadowSize, o.selfShadowSize, o.selfShadowSlices, kappa);
}

void frameShadowMap(ShadingInputs& in, const YarnDensityParams& density, const AppearanceOptions& o) {
  if (o.shadowMapSize < 16 || o.shadowMapSize > 8192)
    throw InputError(fmt::format("--shadow-map-size: {} must be in [16, 8192]", o.shadowMapSize));
  in.density = density;  // the tube radius is its reach W (notes §0.3, A5)
  in.shadowMapSize = o.shadowMapSize;
  in.params.flags.w |= FT_APPEARANCE_SHADOW_MAP;
}

void checkShadingInputs(const ShadingInputs& inputs) {
  if (inputs.ambientTable.size() != FT_AMBIENT_TABLE_SIZE)
    throw std::invalid_argument(fmt::format("shading inputs: ambient table has {} texels, expected {}",
                                            inputs.ambientTable.size(), FT_AMBIENT_TABLE_SIZE));
  for (size_t k = 0; k < inputs.ambientTable.size(); ++k) {
    const glm::vec3 a = inputs.ambientTable[k];
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(a.z))
      throw std::invalid_argument(fmt::format("shading inputs: ambient table texel {} is ({}, {}, {})", k, a.x, a.y, a.z));
  }
  const bool selfShadow = (inputs.params.flags.w & FT_APPEARANCE_SELF_SHADOW) != 0u;
  const size_t texels = size_t(inputs.selfShadow.width) * inputs.selfShadow.height * inputs.selfShadow.slices;
  if (selfShadow && (texels == 0 || inputs.selfShadowTexels.size() != texels))
    throw std::invalid_argument(fmt::format("shading inputs: self-shadow texture has {} texels, its layout {}",
                                            inputs.selfShadowTexels.size(), texels));
  for (size_t k = 0; selfShadow && k < texels; ++k)
    if (!std::isfinite(inputs.selfShadowTexels[k]))
      throw std::invalid_argument(
          fmt::format("shading inputs: self-shadow texel {} is {}", k, inputs.selfShadowTexels[k]));
  if ((inputs.params.flags.w & FT_APPEARANCE_SHADOW_MAP) != 0u) {
    if (inputs.shadowMapSize < 16 || inputs.shadowMapSize > 8192)
      throw std::invalid_argument(fmt::format("shading inputs: shadow map size {}", inputs.shadowMapSize));
    const float w = inputs.density.supportRadius;
    if (!std::isfinite(w) || w <= 0.0f || !std::isfinite(inputs.density.plyRadius))
      throw std::invalid_argument(fmt::format("shading inputs: shadow-map tube radius W = {}", w));
  }
}

}  // namespace ft
