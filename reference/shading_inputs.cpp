#include "reference/shading_inputs.h"

#include <stdexcept>

#include "reference/bcsdf_tables.h"
#include "reference/self_shadow.h"
#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {

ShadingInputs bakeShadingInputsCpu(const ShadingBakeRequest& request) {
  ShadingInputs in;
  in.params = request.params;
  in.params.flags.w = 0u;
  in.ambientTable = bakeAmbientTableCpu(request.params.fabric);
  if (request.appearance.selfShadow) {
    if (!request.fittedPreset) throw std::invalid_argument("bakeShadingInputsCpu: self-shadow needs the yarn preset");
    in.density = makeYarnDensity(*request.fittedPreset);
    in.selfShadow = frameSelfShadowParams(in.density, request.appearance);
    in.selfShadowTexels = bakeSelfShadowCpu(in.density, in.selfShadow).texels;
    in.params.flags.w |= FT_APPEARANCE_SELF_SHADOW;
  }
  if (request.appearance.shadowMap) {  // yarn shadow map (000 §4.1): drawn per frame, nothing to bake
    if (!request.fittedPreset) throw std::invalid_argument("bakeShadingInputsCpu: the shadow map needs the yarn preset");
    frameShadowMap(in, makeYarnDensity(*request.fittedPreset), request.appearance);
  }
  checkShadingInputs(in);
  return in;
}

}  // namespace ft
