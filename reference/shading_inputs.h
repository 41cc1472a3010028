// shading_inputs.h (reference) — the CPU bake of every precomputed shading
// input (scene/shading_inputs.h), in double where a table is integrated and
// by the exact line integral for the self-shadow texture. The Embree ground
// truth and `fibertwin trace` shade with these.
#pragma once
#include "scene/shading_inputs.h"

namespace ft {

ShadingInputs bakeShadingInputsCpu(const ShadingBakeRequest& request);

}  // namespace ft
