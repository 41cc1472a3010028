// flyaway_input.h — what both flyaway bakes (reference/flyaway.h,
// gpu/flyaway_gpu.h) take and return (001 §4.4, eq. 12–13; common/flyaway.h,
// docs/flyaways.md).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/flyaway.h"
#include "common/yarn_params.h"
#include "scene/yarn_preset.h"

namespace ft {

struct FlyawaySettings {
  uint32_t width = FT_FLYAWAY_WIDTH, height = FT_FLYAWAY_HEIGHT;
  uint32_t patterns = 1;  // independent triples (statistics draw many)
  float alpha = 1.0f;     // eq. 13's α [F]: 1 = eq. 12
  float noise = 0.1f;     // σ_n [F]: notes A8
  float lengthScale = 1.0f;  // z_e and R_e scaled (001 Fig. 15's "extended" configuration: ×3)
  uint32_t seed = 0x5EEDu;
};

// The curves of every slot: FT_FLYAWAY_POINTS points each (xyz, w = t) and a
// header (present, kept, zMin, zMax); slot index ftFlyawaySlot.
struct FlyawayCurves {
  FlyawayParams params{};
  std::vector<glm::vec4> points;
  std::vector<glm::vec4> headers;
  size_t slots() const { return headers.size(); }
};

// Three layers of width × height RGBA8 texels (glm::packUnorm4x8 order,
// r in the low byte), row-major, row j = v; 0 = no flyaway.
struct FlyawayTextures {
  uint32_t width = 0, height = 0;
  std::vector<uint32_t> texels;  // [layer][row][column]
  uint32_t at(uint32_t layer, uint32_t i, uint32_t j) const { return texels[(size_t(layer) * height + j) * width + i]; }
};

// The block for a preset already fitted to the model (YarnParams from
// makeFiberSetup; `fitted` the fitted preset: its hair density per length).
// Throws InputError naming the preset and value for sizes or parameters it
// cannot use.
FlyawayParams makeFlyawayParams(const YarnPreset& fitted, const YarnParams& p, const FlyawaySettings& s);

// λ of a set per pattern: B's candidates over [−Z, Z), I's over [0, P).
double flyawayLambda(const FlyawayParams& f, double densityPerLength, uint32_t set);

// Refuses curves or textures of the wrong size or with non-finite values.
void checkFlyawayTextures(const FlyawayTextures& t, const std::string& what);

}  // namespace ft
