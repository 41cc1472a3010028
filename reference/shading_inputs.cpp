#include "reference/shading_inputs.h"

#include <stdexcept>
#include <utility>

#include "reference/ambient_occlusion.h"
#include "reference/bcsdf_tables.h"
#include "reference/core_texture.h"
#include "reference/dual_scattering.h"
#include "reference/flyaway.h"
#include "reference/self_shadow.h"
#include "reference/srbf_fit.h"
#include "reference/srbf_table.h"
#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {

ShadingInputs bakeShadingInputsCpu(const ShadingBakeRequest& request) {
  ShadingInputs in;
  in.params = request.params;
  in.params.flags.w = 0u;
  in.ambientTable = bakeAmbientTableCpu(request.params.fabric);
  in.lobeNormTable = bakeLobeNormTableCpu(request.params.fabric);
  if (request.appearance.selfShadow) {
    if (!request.fittedPreset) throw std::invalid_argument("bakeShadingInputsCpu: self-shadow needs the yarn preset");
    in.density = makeYarnDensity(*request.fittedPreset);
    in.selfShadow = frameSelfShadowParams(in.density, request.appearance);
    in.selfShadowTexels = bakeSelfShadowCpu(in.density, in.selfShadow).texels;
    in.params.flags.w |= FT_APPEARANCE_SELF_SHADOW;
  }
  if (request.appearance.coreTexture) {  // 000 §3.2 (common/core_texture.h)
    const CoreTextureInput core = frameCoreTextureInput(request, "bakeShadingInputsCpu");
    if (core.params.coreFibers > 0) {
      CoreTexture tex = bakeCoreTextureEmbree(core);
      in.coreTexture = core.params;
      in.coreTex0 = std::move(tex.tex0);
      in.coreTex1 = std::move(tex.tex1);
      in.params.flags.w |= FT_APPEARANCE_CORE_TEXTURE;
    }
  }
  // Ambient occlusion (000 §4.2): the CPU texture (exact line integral) and
  // the cubic fitted to its radial average; both modes carry both.
  if (request.appearance.ao != AoMode::None) {
    if (!request.fittedPreset) throw std::invalid_argument("bakeShadingInputsCpu: ambient occlusion needs the yarn preset");
    in.density = makeYarnDensity(*request.fittedPreset);
    in.aoParams = makeAoParams(in.density, request.appearance.aoSettings);
    in.aoTexels = bakeAmbientOcclusionCpu(in.aoParams).ao;
    in.aoParams.cubic = glm::vec4(fitAoCubic(std::span<const float>(in.aoTexels), int(in.aoParams.resolution)).coefficients);
    in.params.flags.w |= request.appearance.ao == AoMode::Fit ? FT_APPEARANCE_AO_FIT : FT_APPEARANCE_AO_TEXTURE;
  }
  if (request.appearance.shadowMap) {  // yarn shadow map (000 §4.1): drawn per frame, nothing to bake
    if (!request.fittedPreset) throw std::invalid_argument("bakeShadingInputsCpu: the shadow map needs the yarn preset");
    frameShadowMap(in, makeYarnDensity(*request.fittedPreset), request.appearance);
  }
  frameSoftShadows(in, request.appearance);  // soft yarn shadows (001 §4.5, PCSS): drawn per frame, nothing to bake
  // Dual scattering (001 §4.1, §4.3): the CPU's own table (double quadrature),
  // the ξ textures of the bake file scaled to the model, or identity.
  frameDsCorrection(in, request.fittedPreset, request.appearance);
  if ((in.params.flags.w & FT_APPEARANCE_DUAL_SCATTERING) != 0u) in.dsTable = bakeDualScatteringCpu(request.params.fabric).rows;
  // SRBF environment lighting (001 §4.5): the fit's sums in double, the I_M
  // table by the analytic reduction (reference/srbf_table.h).
  if (const std::optional<ImageRgbaF> env = frameEnvironmentMap(request.appearance)) {
    in.environment = fitSrbfCpu(*env).environment;
    in.srbfTableDims = request.appearance.environmentTableDims;
    in.srbfTable = bakeSrbfTableCpu(request.params.fabric, in.srbfTableDims).asFloat();
    in.params.flags.w |= FT_APPEARANCE_ENVIRONMENT;
    // 001 eq. 17's T̃^Yarn_j: with soft shadows, a PCSS shadow map per lobe.
    if (request.appearance.softShadows) in.lobeShadowEnvironment = in.environment;
  }
  if (request.appearance.flyaways) {  // 001 §4.4 (common/flyaway.h)
    in.flyaway = frameFlyawayParams(request, "bakeShadingInputsCpu");
    in.flyawayTexels = bakeFlyawaysCpu(generateFlyawaysCpu(in.flyaway)).texels;
    in.params.flags.w |= FT_APPEARANCE_FLYAWAYS;
  }
  checkShadingInputs(in);
  return in;
}

}  // namespace ft
