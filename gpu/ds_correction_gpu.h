// ds_correction_gpu.h — the GPU twin of the per-frame lookup of the
// dual-scattering correction ξ and fiber-level shadowing of Huang et al. 2025
// (001) §4.3 eq. 9–11 (common/ds_correction.h): ds_correction_eval.comp.glsl
// evaluates ξ_M ξ_N Ψ_M Ψ_N at a list of (u, v, θ, φ), as a fragment would.
// The textures are baked on the CPU (reference/ds_correction.h: path tracing
// has no GPU twin here). Every call uploads, dispatches and reads back.
#pragma once
#include <epoxy/gl.h>

#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "common/ds_correction.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

class DsCorrectionGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, see validation/faults.h).
  explicit DsCorrectionGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});
  // Textures in common/ds_correction.h order (rgba per texel: ξ_M, Ψ_M of
  // N_u·N_v·N_θ texels, ξ_N, Ψ_N of N_u·N_v·N_φ), values as baked (they are
  // uploaded log-encoded, ftXiEncode); queries (u, v, θ, φ).
  std::vector<glm::vec3> evaluate(const DsCorrectionLayout& layout, std::span<const glm::vec4> xiM,
                                  std::span<const glm::vec4> xiN, std::span<const glm::vec4> psiM,
                                  std::span<const glm::vec4> psiN, std::span<const glm::vec4> queries);

 private:
  int maxGroupsY_ = 65535;
  Program program_;
};

}  // namespace ft
