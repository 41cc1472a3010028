// self_shadow.h (reference) — the CPU side of the self-shadow 3D texture of
// Wu & Yuksel 2019 (000) §4.1 (common/self_shadow.h): every texel is the
// exact line integral of the shared ply-density field (ftDensityLineIntegral,
// common/yarn_density.h) from the light side to its centre, in C++ float,
// TBB over rows; and the per-fragment lookup on such a texture.
#pragma once
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "common/self_shadow.h"

namespace ft {

struct SelfShadowTexture {
  SelfShadowParams params{};
  YarnDensityParams density{};
  std::vector<float> texels;  // ftSelfShadowIndex order: u fastest, then v, then slice
  float at(uint32_t i, uint32_t j, uint32_t k) const { return texels[ftSelfShadowIndex(params, i, j, k)]; }
};

// The layout of `density` at width × height × slices with κ (none: the
// default 2 r_f, ftSelfShadowFiberRadius; 0 turns the shadow off).
// std::invalid_argument naming the value for sizes below 3 × 3 × 1, above
// 4096 per axis, or a κ that is negative, NaN or infinite.
SelfShadowParams makeSelfShadowParams(const YarnDensityParams& density, uint32_t width, uint32_t height,
                                      uint32_t slices, std::optional<float> kappa = std::nullopt);

// The exact bake: D_k(i, j) = τ((u_i, v_j), (−1, 0)) at ψ_k.
SelfShadowTexture bakeSelfShadowCpu(const YarnDensityParams& density, const SelfShadowParams& params);

// The texture looked up at a cross-section point x, light ℓ⊥ (of the unit ℓ)
// and ply phase θ_ply,0: ftSelfShadowSample, the 8 texels, ftSelfShadowBlend.
float lookupSelfShadowCpu(const SelfShadowTexture& texture, glm::vec2 x, glm::vec2 toLight, float plyAngle);

}  // namespace ft
