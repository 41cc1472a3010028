// srbf_table_gpu.h — the GPU side of the I_M table (001 §4.5 eq. 15–16;
// common/srbf_bcsdf.h): srbf_table_bake.comp.glsl bakes it in float by
// brute-force 2D quadrature over the incident direction (an independent twin
// of the CPU's analytic reduction, reference/srbf_table.h);
// srbf_table_lookup.comp.glsl looks it up as the renderer will.
#pragma once
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "common/fiber_shading.h"
#include "common/srbf_bcsdf.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

class SrbfTableGpu {
 public:
  explicit SrbfTableGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});
  // rgb I at every texel (index ftSrbfTableIndex).
  std::vector<glm::vec3> bake(const FabricParams& fabric, glm::ivec4 dims);
  // Each request (θ_o, θ_j, Δφ, λ) looked up in `table`.
  std::vector<glm::vec3> lookup(std::span<const glm::vec3> table, glm::ivec4 dims, std::span<const glm::vec4> requests);

 private:
  int maxGroupsY_ = 65535;
  Program bakeProgram_, lookupProgram_;
};

}  // namespace ft
