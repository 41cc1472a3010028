// shading_inputs.h (reference) — the CPU bake of every precomputed shading
// input (scene/shading_inputs.h), in double where a table is integrated. The
// Embree ground truth and `fibertwin trace` shade with these.
#pragma once
#include "scene/shading_inputs.h"

namespace ft {

ShadingInputs bakeShadingInputsCpu(const ShadingParams& params);

}  // namespace ft
