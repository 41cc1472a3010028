#include "gpu/shading_inputs_gpu.h"

#include <stdexcept>

#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {

ShadingBakeGpu::ShadingBakeGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : bcsdf_(gl, defines), selfShadow_(gl, defines) {}

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
  if (request.appearance.shadowMap) {  // yarn shadow map (000 §4.1): drawn per frame, nothing to bake
    if (!request.fittedPreset) throw std::invalid_argument("ShadingBakeGpu: the shadow map needs the yarn preset");
    frameShadowMap(in, makeYarnDensity(*request.fittedPreset), request.appearance);
  }
  checkShadingInputs(in);
  return in;
}

}  // namespace ft
