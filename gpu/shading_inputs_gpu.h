// shading_inputs_gpu.h — the GPU bake of every precomputed shading input
// (scene/shading_inputs.h): the real-time side's own tables, in float, with
// the kernels of each algorithm (gpu/bcsdf_gpu.h, gpu/self_shadow_gpu.h: the
// paper's density grid and prefix sum). The renderer (gpu/fiber_renderer.h)
// draws with what this returns.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "gpu/ambient_occlusion_gpu.h"
#include "gpu/bcsdf_gpu.h"
#include "gpu/core_texture_gpu.h"
#include "gpu/dual_scattering_gpu.h"
#include "gpu/flyaway_gpu.h"
#include "gpu/gl_context.h"
#include "gpu/self_shadow_gpu.h"
#include "gpu/srbf_fit_gpu.h"
#include "gpu/srbf_table_gpu.h"
#include "scene/shading_inputs.h"

namespace ft {

class ShadingBakeGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, validation/faults.h).
  explicit ShadingBakeGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});
  ShadingInputs bake(const ShadingBakeRequest& request);

 private:
  BcsdfGpu bcsdf_;
  SelfShadowGpu selfShadow_;
  CoreTextureGpu coreTexture_;
  AmbientOcclusionGpu ao_;
  // The DS table's kernels, built on the first frame that asks for dual scattering.
  const GlInfo& gl_;
  std::vector<std::string> defines_;
  std::unique_ptr<DualScatteringGpu> ds_;
  std::unique_ptr<SrbfFitGpu> srbfFit_;  // SRBF environment (001 §4.5), built on first use
  std::unique_ptr<SrbfTableGpu> srbfTable_;
  std::unique_ptr<FlyawayGpu> flyaway_;  // built on the first frame with flyaways
};

}  // namespace ft
