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

AoMode parseAoMode(const std::string& name) {
  if (name == "none") return AoMode::None;
  if (name == "fit") return AoMode::Fit;
  if (name == "texture") return AoMode::Texture;
  throw InputError(fmt::format("--ao: '{}' is not one of none, fit, texture", name));
}

const char* aoModeName(AoMode mode) {
  switch (mode) {
    case AoMode::None: return "none";
    case AoMode::Fit: return "fit";
    case AoMode::Texture: return "texture";
  }
  return "?";
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
  if (inputs.lobeNormTable.size() != FT_LOBE_NORM_TABLE_SIZE)
    throw std::invalid_argument(fmt::format("shading inputs: lobe-normalisation table has {} texels, expected {}",
                                            inputs.lobeNormTable.size(), FT_LOBE_NORM_TABLE_SIZE));
  for (size_t k = 0; k < inputs.lobeNormTable.size(); ++k) {
    const glm::vec2 z = inputs.lobeNormTable[k];
    if (!(std::isfinite(z.x) && z.x > 0.0f && std::isfinite(z.y) && z.y > 0.0f))  // M = g / Z
      throw std::invalid_argument(fmt::format("shading inputs: lobe-normalisation texel {} is ({}, {})", k, z.x, z.y));
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
  const bool core = (inputs.params.flags.w & FT_APPEARANCE_CORE_TEXTURE) != 0u;
  const size_t coreTexels = size_t(inputs.coreTexture.columns) * inputs.coreTexture.height;
  if (core && (coreTexels == 0 || inputs.coreTexture.columns != inputs.coreTexture.width ||
               inputs.coreTex0.size() != coreTexels || inputs.coreTex1.size() != coreTexels))
    throw std::invalid_argument(fmt::format("shading inputs: core texture has {} / {} texels, its layout {}",
                                            inputs.coreTex0.size(), inputs.coreTex1.size(), coreTexels));
  for (size_t k = 0; core && k < coreTexels; ++k) {
    const glm::vec4 a = inputs.coreTex0[k], b = inputs.coreTex1[k];
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(a[c]) || !std::isfinite(b[c]))
        throw std::invalid_argument(fmt::format("shading inputs: core texel {} is not finite", k));
  }
  // Ambient occlusion (000 §4.2).
  const bool ao = (inputs.params.flags.w & (FT_APPEARANCE_AO_FIT | FT_APPEARANCE_AO_TEXTURE)) != 0u;
  const size_t aoTexels = size_t(inputs.aoParams.resolution) * inputs.aoParams.resolution;
  if (ao && (aoTexels == 0 || inputs.aoTexels.size() != aoTexels))
    throw std::invalid_argument(fmt::format("shading inputs: AO texture has {} texels, its layout {}",
                                            inputs.aoTexels.size(), aoTexels));
  for (size_t k = 0; ao && k < aoTexels; ++k)
    if (!std::isfinite(inputs.aoTexels[k]))
      throw std::invalid_argument(fmt::format("shading inputs: AO texel {} is {}", k, inputs.aoTexels[k]));
  const glm::vec4 c = inputs.aoParams.cubic;
  if (ao && !(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) && std::isfinite(c.w) &&
              inputs.aoParams.halfWidth > 0.0f))
    throw std::invalid_argument(fmt::format("shading inputs: AO cubic ({}, {}, {}, {}) or half width {}", c.x, c.y,
                                            c.z, c.w, inputs.aoParams.halfWidth));
  if ((inputs.params.flags.w & FT_APPEARANCE_SHADOW_MAP) != 0u) {
    if (inputs.shadowMapSize < 16 || inputs.shadowMapSize > 8192)
      throw std::invalid_argument(fmt::format("shading inputs: shadow map size {}", inputs.shadowMapSize));
    const float w = inputs.density.supportRadius;
    if (!std::isfinite(w) || w <= 0.0f || !std::isfinite(inputs.density.plyRadius))
      throw std::invalid_argument(fmt::format("shading inputs: shadow-map tube radius W = {}", w));
  }
}

CoreTextureInput frameCoreTextureInput(const ShadingBakeRequest& r, const char* who) {
  if (!r.yarnParams || !r.fiberTable)
    throw std::invalid_argument(fmt::format("{}: the core texture needs the frame's yarn parameters and fiber table", who));
  if (ftCoreFiberCount(*r.yarnParams) == 0) return {};  // every fiber explicit: nothing to texture
  return makeCoreTextureInput(*r.yarnParams, *r.fiberTable, r.appearance.coreTextureWidth,
                              r.appearance.coreTextureHeight);
}

}  // namespace ft
