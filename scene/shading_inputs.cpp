#include "scene/shading_inputs.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "common/srbf_bcsdf.h"
#include "scene/ds_correction_file.h"
#include "scene/environment_map.h"
#include "scene/input_error.h"
#include "scene/lighting.h"
#include "scene/yarn_preset.h"

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
  if (o.shadowMapFilter != FT_SHADOW_FILTER_PCF && o.shadowMapFilter != FT_SHADOW_FILTER_NEAREST)
    throw InputError(fmt::format("--shadow-map-filter: {} is neither pcf ({}) nor nearest ({})", o.shadowMapFilter,
                                 FT_SHADOW_FILTER_PCF, FT_SHADOW_FILTER_NEAREST));
  in.shadowMapSize = o.shadowMapSize;
  in.shadowMapFilter = o.shadowMapFilter;
  in.params.flags.w |= FT_APPEARANCE_SHADOW_MAP;
}

void frameSoftShadows(ShadingInputs& in, const AppearanceOptions& o) {
  if (!o.softShadows) return;
  const float a = o.lightAngularRadius;
  if (!std::isfinite(a) || a < 0.0f || a > 60.0f * 3.14159265f / 180.0f)
    throw InputError(fmt::format("--light-angular-radius: {} degrees must be in [0, 60]", a * 180.0f / 3.14159265f));
  if (!o.shadowMap) throw InputError("--soft-shadows filters the yarn shadow map: it cannot go with --no-shadow-map");
  in.params.flags.w |= FT_APPEARANCE_SOFT_SHADOWS;
  in.lightTanAlpha = glm::vec4(std::tan(a));
}

// Below this coverage a texel of a ξ bake is not applied (frameDsCorrection).
constexpr float kFrameXiMinCoverage = 0.5f;

void frameDsCorrection(ShadingInputs& in, const YarnPreset* preset, const AppearanceOptions& o) {
  if (!o.dualScattering && !o.dsCorrectionFile) return;
  in.params.flags.w |= FT_APPEARANCE_DUAL_SCATTERING;
  if (!o.dsCorrectionFile) {  // plain dual scattering: ξ = 1, Ψ_G^Fiber = the self-shadow T (or 1)
    in.dsCorrection.size = glm::uvec4(1u);
    in.dsCorrection.yarn = glm::vec4(1.0f, 1.0f, 0.0f, 0.0f);
    in.xiM = in.xiN = in.psiM = in.psiN = {glm::vec4(1.0f, 1.0f, 1.0f, 0.0f)};
    return;
  }
  const std::string file = o.dsCorrectionFile->string();
  DsCorrectionTextures t;
  try {
    t = readDsCorrection(*o.dsCorrectionFile);
  } catch (const InputError& e) {
    throw InputError(fmt::format("--ds-correction: {}", e.what()));
  }
  if (!preset) throw std::invalid_argument("frameDsCorrection: the ξ bake needs the frame's yarn preset");
  // A bake for another yarn or fabric is refused: ξ is a ratio of the path
  // tracer's radiance over dual scattering's for that yarn's fibers and that
  // BCSDF, and its u axis is that preset's ply period.
  if (!t.yarn.empty() && t.yarn != preset->name)
    throw InputError(fmt::format("--ds-correction: {} was baked for yarn preset '{}', the frame's is '{}'", file,
                                 t.yarn, preset->name));
  if (!t.fabric.empty()) {
    Lighting l;
    l.fabric = t.fabric;
    const FabricParams baked = makeShadingParams(l).fabric;  // InputError for an unknown fabric
    if (std::memcmp(&baked, &in.params.fabric, sizeof(FabricParams)) != 0)
      throw InputError(fmt::format("--ds-correction: {} was baked for fabric '{}', which is not the frame's fabric",
                                   file, t.fabric));
  }
  if (!(t.layout.yarn.x > 0.0f) || !(t.layout.yarn.y > 0.0f))
    throw InputError(fmt::format("--ds-correction: {}: period {} and half-width {} must be positive", file,
                                 t.layout.yarn.x, t.layout.yarn.y));
  // The bake is at the preset's own scale; the frame's preset is fitted to the
  // model (scene/yarn_radius.h): P and W scale with it.
  const float scale = ftFaultFrameDsUnscaled ? 1.0f : float(preset->yarnAlpha) / t.layout.yarn.x;
  // Rim texels that under half of their camera samples hit are taken as
  // uncovered (ξ = Ψ = 1, as the bake leaves texels no sample hits): their
  // rank-1 fits rest on a few samples and ran to factors of 1e7–1e12 in the
  // CI-size bake, which the trilinear lookup then mixes into covered pixels.
  const size_t texels = size_t(t.layout.size.x) * t.layout.size.y;
  for (size_t k = 0; k < texels && k < t.coverage.size(); ++k) {
    if (t.coverage[k] >= kFrameXiMinCoverage) continue;
    for (uint32_t a = 0; a < t.layout.size.z; ++a) t.xiM[a * texels + k] = t.psiM[a * texels + k] = glm::vec4(1, 1, 1, 0);
    for (uint32_t b = 0; b < t.layout.size.w; ++b) t.xiN[b * texels + k] = t.psiN[b * texels + k] = glm::vec4(1, 1, 1, 0);
  }
  in.dsCorrection = t.layout;
  in.dsCorrection.yarn.x *= scale;
  in.dsCorrection.yarn.y *= scale;
  in.xiM = std::move(t.xiM);
  in.xiN = std::move(t.xiN);
  in.psiM = std::move(t.psiM);
  in.psiN = std::move(t.psiN);
  in.params.flags.w |= FT_APPEARANCE_DS_CORRECTION;
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
  if ((inputs.params.flags.w & FT_APPEARANCE_FLYAWAYS) != 0u) {
    const FlyawayParams& f = inputs.flyaway;
    const size_t want = size_t(f.width) * f.height * FT_FLYAWAY_LAYERS;
    if (f.width == 0 || f.height == 0 || inputs.flyawayTexels.size() != want || !(f.period > 0.0f) ||
        !(f.halfWidth > 0.0f) || !std::isfinite(f.period) || !std::isfinite(f.halfWidth) || !std::isfinite(f.bodyRadius))
      throw std::invalid_argument(fmt::format("shading inputs: flyaway textures hold {} texels, their layout {}×{}×3, "
                                              "P {}, W_fly {}",
                                              inputs.flyawayTexels.size(), f.width, f.height, f.period, f.halfWidth));
  }
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
  if ((inputs.params.flags.w & FT_APPEARANCE_SOFT_SHADOWS) != 0u) {
    if ((inputs.params.flags.w & FT_APPEARANCE_SHADOW_MAP) == 0u)
      throw std::invalid_argument("shading inputs: soft shadows without the shadow map");
    for (int i = 0; i < 4; ++i)
      if (!std::isfinite(inputs.lightTanAlpha[i]) || inputs.lightTanAlpha[i] < 0.0f)
        throw std::invalid_argument(fmt::format("shading inputs: tan α of light {} is {}", i, inputs.lightTanAlpha[i]));
  }
  if (inputs.lobeShadowEnvironment &&
      (inputs.lobeShadowMapSize < 16 || inputs.lobeShadowMapSize > 8192))
    throw std::invalid_argument(fmt::format("shading inputs: lobe shadow map size {}", inputs.lobeShadowMapSize));
  if ((inputs.params.flags.w & FT_APPEARANCE_SHADOW_MAP) != 0u) {
    if (inputs.shadowMapSize < 16 || inputs.shadowMapSize > 8192)
      throw std::invalid_argument(fmt::format("shading inputs: shadow map size {}", inputs.shadowMapSize));
    const float w = inputs.density.supportRadius;
    if (!std::isfinite(w) || w <= 0.0f || !std::isfinite(inputs.density.plyRadius))
      throw std::invalid_argument(fmt::format("shading inputs: shadow-map tube radius W = {}", w));
  }
  // Dual scattering (001 §4.1, §4.3): the table and the ξ textures.
  if ((inputs.params.flags.w & FT_APPEARANCE_DUAL_SCATTERING) != 0u) {
    if (inputs.dsTable.size() != size_t(FT_DS_ROWS) * FT_DS_TABLE_SIZE)
      throw std::invalid_argument(fmt::format("shading inputs: DS table has {} rows, expected {}", inputs.dsTable.size(),
                                              FT_DS_ROWS * FT_DS_TABLE_SIZE));
    const auto finite = [](const std::vector<glm::vec4>& v, const char* name) {
      for (size_t k = 0; k < v.size(); ++k)
        if (!std::isfinite(v[k].x) || !std::isfinite(v[k].y) || !std::isfinite(v[k].z))
          throw std::invalid_argument(fmt::format("shading inputs: {} value {} is not finite", name, k));
    };
    finite(inputs.dsTable, "DS table");
    const DsCorrectionLayout& l = inputs.dsCorrection;
    const size_t uv = size_t(l.size.x) * l.size.y;
    if (uv == 0 || l.size.z == 0 || l.size.w == 0 || inputs.xiM.size() != uv * l.size.z ||
        inputs.psiM.size() != uv * l.size.z || inputs.xiN.size() != uv * l.size.w || inputs.psiN.size() != uv * l.size.w)
      throw std::invalid_argument(fmt::format("shading inputs: ξ textures have {} / {} / {} / {} texels, layout {}×{}×({}, {})",
                                              inputs.xiM.size(), inputs.xiN.size(), inputs.psiM.size(),
                                              inputs.psiN.size(), l.size.x, l.size.y, l.size.z, l.size.w));
    if (!(std::isfinite(l.yarn.x) && l.yarn.x > 0.0f && std::isfinite(l.yarn.y) && l.yarn.y > 0.0f))
      throw std::invalid_argument(fmt::format("shading inputs: ξ period {} / half-width {}", l.yarn.x, l.yarn.y));
    finite(inputs.xiM, "ξ_M");
    finite(inputs.xiN, "ξ_N");
    finite(inputs.psiM, "Ψ_M");
    finite(inputs.psiN, "Ψ_N");
  }
  // SRBF environment lighting (001 §4.5): the fit and the I_M table.
  if ((inputs.params.flags.w & FT_APPEARANCE_ENVIRONMENT) != 0u) {
    const glm::ivec4 d = inputs.srbfTableDims;
    if (d.x < 2 || d.y < 2 || d.z < 2 || d.w < 2 || inputs.srbfTable.size() != size_t(d.x) * d.y * d.z * d.w)
      throw std::invalid_argument(fmt::format("shading inputs: I_M table has {} texels, its dimensions {}×{}×{}×{}",
                                              inputs.srbfTable.size(), d.x, d.y, d.z, d.w));
    for (size_t k = 0; k < inputs.srbfTable.size(); ++k) {
      const glm::vec3 v = inputs.srbfTable[k];
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw std::invalid_argument(fmt::format("shading inputs: I_M texel {} is not finite", k));
    }
    for (int j = 0; j <= FT_SRBF_LOBES; ++j) {
      const glm::vec4 a = j < FT_SRBF_LOBES ? inputs.environment.lobes[j].weight : inputs.environment.constant;
      const float l = j < FT_SRBF_LOBES ? inputs.environment.lobes[j].axisLambda.w : 1.0f;
      if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(a.z) || !std::isfinite(l) || l <= 0.0f)
        throw std::invalid_argument(fmt::format("shading inputs: SRBF lobe {} is not finite", j));
    }
  }
}

std::optional<ImageRgbaF> frameEnvironmentMap(const AppearanceOptions& o) {
  if (!o.environmentImage && !o.environmentMap) return std::nullopt;
  const glm::ivec4 d = o.environmentTableDims;
  for (int a = 0; a < 4; ++a)
    if (d[a] < 2 || d[a] > 64)
      throw InputError(fmt::format("--env-table: {},{},{},{}: each size must be in [2, 64]", d.x, d.y, d.z, d.w));
  if (o.environmentImage) {
    checkEnvironmentMap(*o.environmentImage, "--env (in memory)");
    return *o.environmentImage;
  }
  return readEnvironmentMap(*o.environmentMap);
}

CoreTextureInput frameCoreTextureInput(const ShadingBakeRequest& r, const char* who) {
  if (!r.yarnParams || !r.fiberTable)
    throw std::invalid_argument(fmt::format("{}: the core texture needs the frame's yarn parameters and fiber table", who));
  if (ftCoreFiberCount(*r.yarnParams) == 0) return {};  // every fiber explicit: nothing to texture
  return makeCoreTextureInput(*r.yarnParams, *r.fiberTable, r.appearance.coreTextureWidth,
                              r.appearance.coreTextureHeight);
}

FlyawayParams frameFlyawayParams(const ShadingBakeRequest& r, const char* who) {
  if (!r.fittedPreset || !r.yarnParams)
    throw std::invalid_argument(fmt::format("{}: flyaways need the fitted yarn preset and its yarn parameters", who));
  return makeFlyawayParams(*r.fittedPreset, *r.yarnParams, r.appearance.flyawaySettings);
}

}  // namespace ft
