// yarn_density.h (scene) — the ply-density model of a preset
// (common/yarn_density.h) as both sides' bakes take it.
#pragma once
#include "common/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {

// The density field of `preset` (already fitted to the model's yarn radius:
// scene/yarn_radius.h), with its normalisation so that ∫ρ dA = n_ply·n_f.
// Throws InputError naming the preset for a field that has no mass
// (R_max ≤ 0, a zero ellipse axis, p ≡ 0).
YarnDensityParams makeYarnDensity(const YarnPreset& preset);

}  // namespace ft
