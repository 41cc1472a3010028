// shading_inputs.h — everything a shaded fiber frame reads besides the
// fibers: the shading parameters (lights, fabric, ambient) and every table
// baked from them or from the yarn (000 §4). One struct, so that a new
// precomputed input is added in one place: here, in the two bake functions
// (reference/shading_inputs.h on the CPU, gpu/shading_inputs_gpu.h on the
// GPU) and in the renderer's binding (gpu/fiber_renderer.cpp, at the
// "shading inputs" slots of common/constants.h); every caller — render,
// trace, the harness, the benches — goes through those.
#pragma once
#include <glm/glm.hpp>
#include <vector>

#include "common/fiber_shading.h"

namespace ft {

struct ShadingInputs {
  ShadingParams params{};
  // A(θ_k) of 000 eq. 7–10 at the FT_AMBIENT_TABLE_SIZE texel centres
  // (common/bcsdf.h ftAmbientTexelAngle), rgb.
  std::vector<glm::vec3> ambientTable;
};

// Throws std::invalid_argument naming the input when a table has the wrong
// size or a non-finite value (a bake that went wrong must not be drawn).
void checkShadingInputs(const ShadingInputs& inputs);

}  // namespace ft
