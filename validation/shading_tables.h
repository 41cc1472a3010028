// shading_tables.h — the ambient table A(θ_o) (common/bcsdf.h) each side of
// a shaded picture uses: the GPU render its own float bake, the ground truth
// the CPU reference's double bake.
#pragma once
#include <string>
#include <vector>

#include "common/fiber_shading.h"
#include "gpu/gl_context.h"

namespace ft {

std::vector<glm::vec3> bakeAmbientTableGpu(const GlInfo& gl, const std::vector<std::string>& defines,
                                           const FabricParams& fabric);

}  // namespace ft
