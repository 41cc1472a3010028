// fidelity_xi.h — the CI-size ξ bake (001 §4.3; docs/ds-correction.md) that
// the fidelity rows with dual scattering read (`shading/fidelity/*` and
// `knit/appearance/fidelity/*`): the xi/bake settings (N_v = 8, 4 × 4
// directions, 2 × 2 pixels per texel at 16 spp, 3 periods; ~2–3 s), baked
// once per run, preset and fabric, and written to a temporary file as
// `render --ds-correction` reads one.
#pragma once
#include <filesystem>
#include <string>

#include "scene/yarn_preset.h"
#include "validation/harness.h"

namespace ft {

std::filesystem::path fidelityXiFile(ValidationContext& ctx, const YarnPreset& preset, const std::string& fabric);

}  // namespace ft
