// prt_single_scattering_gpu.h — the GPU twin of single scattering of the
// fabric PRT, 004 §5.2, eq. 1–2, App. A (common/prt_single_scattering.h,
// prt_single_scattering.comp.glsl): the 𝒢 table bake and the evaluation of a
// list of PrtSsRequest (what a deferred frame does per pixel, without the
// G-buffer). Every call uploads, dispatches and reads back.
#pragma once
#include <epoxy/gl.h>

#include <span>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/prt_single_scattering.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

class PrtSingleScatteringGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, validation/faults.h).
  // std::runtime_error when the driver has fewer uniform buffer bindings than
  // FT_UBO_PRT_SS + 1.
  explicit PrtSingleScatteringGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});

  // The tables (2 rows of FT_PRT_SS_TABLE_SIZE per fabric), float.
  std::vector<float> bakeTable(std::span<const FabricParams> fabrics);
  // Radiance (rgb, w = 0) per request, with the given table and weights
  // (rows × axes, the SVF group's layout).
  std::vector<glm::vec4> evaluate(std::span<const FabricParams> fabrics, std::span<const float> table,
                                  std::span<const PrtSsRequest> requests, std::span<const float> weights, int axes,
                                  float lambdaSvf);
  int maxUniformBufferBindings() const { return maxUboBindings_; }

 private:
  Buffer params(std::span<const FabricParams> fabrics, uint32_t mode, uint32_t count, int axes, float lambdaSvf);
  int maxGroupsY_ = 65535;
  int maxUboBindings_ = 0;
  Program program_;
};

}  // namespace ft
