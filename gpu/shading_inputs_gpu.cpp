#include "gpu/shading_inputs_gpu.h"

#include <stdexcept>
#include <utility>

#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {

ShadingBakeGpu::ShadingBakeGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : bcsdf_(gl, defines), selfShadow_(gl, defines), coreTexture_(gl, defines) {}

ShadingInputs ShadingBakeGpu::bake(const ShadingBakeRequest& request) {
  ShadingInputs in;
  in.params = request.params;
  in.params.flags.w = 0u;
  in.ambientTable = bcsdf_.bakeAmbientTable(request.params.fabric);
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
  checkShadingInputs(in);
  return in;
}

}  // namespace ft
