#include "scene/shading_inputs.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace ft {

void checkShadingInputs(const ShadingInputs& inputs) {
  if (inputs.ambientTable.size() != FT_AMBIENT_TABLE_SIZE)
    throw std::invalid_argument(fmt::format("shading inputs: ambient table has {} texels, expected {}",
                                            inputs.ambientTable.size(), FT_AMBIENT_TABLE_SIZE));
  for (size_t k = 0; k < inputs.ambientTable.size(); ++k) {
    const glm::vec3 a = inputs.ambientTable[k];
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(a.z))
      throw std::invalid_argument(fmt::format("shading inputs: ambient table texel {} is ({}, {}, {})", k, a.x, a.y, a.z));
  }
}

}  // namespace ft
