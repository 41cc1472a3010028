#include "gpu/shading_inputs_gpu.h"

namespace ft {

ShadingBakeGpu::ShadingBakeGpu(const GlInfo& gl, const std::vector<std::string>& defines) : bcsdf_(gl, defines) {}

ShadingInputs ShadingBakeGpu::bake(const ShadingParams& params) {
  ShadingInputs in;
  in.params = params;
  in.ambientTable = bcsdf_.bakeAmbientTable(params.fabric);
  checkShadingInputs(in);
  return in;
}

}  // namespace ft
