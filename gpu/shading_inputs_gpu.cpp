#include "gpu/shading_inputs_gpu.h"

#include <stdexcept>
#include <utility>

#include "scene/srbf_solve.h"
#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {

ShadingBakeGpu::ShadingBakeGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : bcsdf_(gl, defines), selfShadow_(gl, defines), coreTexture_(gl, defines), ao_(gl, defines), gl_(gl), defines_(defines) {}

ShadingInputs ShadingBakeGpu::bake(const ShadingBakeRequest& request) {
  ShadingInputs in;
  in.params = request.params;
  in.params.flags.w = 0u;
  in.ambientTable = bcsdf_.bakeAmbientTable(request.params.fabric);
  in.lobeNormTable = bcsdf_.bakeLobeNormTable(request.params.fabric);
  if (request.appearance.selfShadow) {
    if (!request.fittedPreset) throw std::invalid_argument("ShadingBakeGpu: self-shadow needs the yarn preset");
    in.density = makeYarnDensity(*request.fittedPreset);
    in.selfShadow = frameSelfShadowParams(in.density, request.appearance);
    in.selfShadowTexels = selfShadow_.bakeGrid(in.density, in.selfShadow);  // 000 Fig. 6: grid + prefix sum
    in.params.flags.w |= FT_APPEARANCE_SELF_SHADOW;
  }
  if (request.appearance.coreTexture) {  // 000 §3.2 (common/core_texture.h)
    const CoreTextureInput core = frameCoreTextureInput(request, "ShadingBakeGpu");
    if (core.params.coreFibers > 0) {
      CoreTexture tex = coreTexture_.bake(core);
      in.coreTexture = core.params;
      in.coreTex0 = std::move(tex.tex0);
      in.coreTex1 = std::move(tex.tex1);
      in.params.flags.w |= FT_APPEARANCE_CORE_TEXTURE;
    }
  }
  // Ambient occlusion (000 §4.2): the paper-faithful GPU texture (density
  // grid, rays marched through it, Fig. 8a–b), then the same host-side cubic
  // fit as the CPU bake (scene/ambient_occlusion_setup.h) of this texture.
  if (request.appearance.ao != AoMode::None) {
    if (!request.fittedPreset) throw std::invalid_argument("ShadingBakeGpu: ambient occlusion needs the yarn preset");
    in.density = makeYarnDensity(*request.fittedPreset);
    in.aoParams = makeAoParams(in.density, request.appearance.aoSettings);
    in.aoTexels = ao_.bakeMarched(in.aoParams);
    in.aoParams.cubic = glm::vec4(fitAoCubic(std::span<const float>(in.aoTexels), int(in.aoParams.resolution)).coefficients);
    in.params.flags.w |= request.appearance.ao == AoMode::Fit ? FT_APPEARANCE_AO_FIT : FT_APPEARANCE_AO_TEXTURE;
  }
  if (request.appearance.shadowMap) {  // yarn shadow map (000 §4.1): drawn per frame, nothing to bake
    if (!request.fittedPreset) throw std::invalid_argument("ShadingBakeGpu: the shadow map needs the yarn preset");
    frameShadowMap(in, makeYarnDensity(*request.fittedPreset), request.appearance);
  }
  frameSoftShadows(in, request.appearance);  // soft yarn shadows (001 §4.5, PCSS): drawn per frame, nothing to bake
  // Dual scattering (001 §4.1, §4.3): the GPU's own table (float quadrature),
  // the ξ textures of the bake file scaled to the model, or identity.
  frameDsCorrection(in, request.fittedPreset, request.appearance);
  if ((in.params.flags.w & FT_APPEARANCE_DUAL_SCATTERING) != 0u) {
    if (!ds_) ds_ = std::make_unique<DualScatteringGpu>(gl_, defines_);
    in.dsTable = ds_->bakeTable(request.params.fabric).rows;
  }
  // SRBF environment lighting (001 §4.5): the fit's sums by compute shader
  // (the 17 × 17 solve on the host, as notes A9 says), the I_M table by the
  // GPU's brute-force quadrature (gpu/srbf_table_gpu.h).
  if (const std::optional<ImageRgbaF> env = frameEnvironmentMap(request.appearance)) {
    if (!srbfFit_) srbfFit_ = std::make_unique<SrbfFitGpu>(gl_, defines_);
    if (!srbfTable_) srbfTable_ = std::make_unique<SrbfTableGpu>(gl_, defines_);
    const SrbfBasis basis = srbfFibonacciBasis();
    const SrbfFitGpu::Sums sums = srbfFit_->normalEquations(*env, basis.axisLambda, basis.constantTerm);
    SrbfNormalEquations eq;
    eq.count = sums.count;
    eq.gram.assign(sums.gram.begin(), sums.gram.end());
    for (const glm::vec3& b : sums.rhs) eq.rhs.push_back(glm::dvec3(b));
    in.environment = fitSrbfFromSums(basis, eq).environment;
    in.srbfTableDims = request.appearance.environmentTableDims;
    in.srbfTable = srbfTable_->bake(request.params.fabric, in.srbfTableDims);
    in.params.flags.w |= FT_APPEARANCE_ENVIRONMENT;
    // 001 eq. 17's T̃^Yarn_j: with soft shadows, a PCSS shadow map per lobe.
    if (request.appearance.softShadows) in.lobeShadowEnvironment = in.environment;
  }
  if (request.appearance.flyaways) {  // 001 §4.4 (common/flyaway.h)
    if (!flyaway_) flyaway_ = std::make_unique<FlyawayGpu>(gl_, defines_);
    in.flyaway = frameFlyawayParams(request, "ShadingBakeGpu");
    in.flyawayTexels = flyaway_->bake(flyaway_->generate(in.flyaway)).texels;
    in.params.flags.w |= FT_APPEARANCE_FLYAWAYS;
  }
  checkShadingInputs(in);
  return in;
}

}  // namespace ft
