// ds_correction_oracle.h — the per-frame lookup of the ξ bake (001 §4.3
// eq. 10–11) as docs/ds-correction.md states it, in double: written from the
// page, not from common/ds_correction.h (its only use of that header is the
// layout struct the textures carry). Used by xi/lookup (ds_correction_cases.cpp)
// and eq. 17's per-lobe check (srbf_lighting_cases.cpp).
#pragma once
#include <glm/glm.hpp>

#include "scene/ds_correction_file.h"

namespace ft::oracle {

// At q = (u, v, θ, φ): u repeats with texel centres (i + ½)/N_u, v clamps,
// θ clamps at the samples −π/2 + (a + ½)π/N_θ, φ repeats at 2πb/N_φ; the
// logarithms of the texels are interpolated trilinearly and exponentiated.
// ξ_M ξ_N Ψ_M Ψ_N, or Ψ_M Ψ_N alone with psiOnly.
glm::dvec3 xiLookup(const DsCorrectionTextures& t, glm::dvec4 q, bool psiOnly = false);

// θ = θ_d − θ_o and φ ∈ [0, 2π) of light ω_d and view ω_o about the unit
// yarn tangent T, φ from ω_o's part across T towards T × that part.
glm::dvec2 xiAngles(glm::dvec3 T, glm::dvec3 wd, glm::dvec3 wo);

}  // namespace ft::oracle
