#include "scene/yarn_density.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "scene/input_error.h"

namespace ft {

YarnDensityParams makeYarnDensity(const YarnPreset& preset) {
  YarnDensityParams d{};
  d.plyCount = static_cast<uint32_t>(preset.plyNum);
  d.fiberCount = static_cast<uint32_t>(preset.fiberNum);
  d.plyRadius = static_cast<float>(preset.yarnRadius / 2.0);
  d.ellipseN = static_cast<float>(preset.ellipseShort);
  d.ellipseB = static_cast<float>(preset.ellipseLong);
  d.epsilon = static_cast<float>(preset.epsilon);
  d.beta = static_cast<float>(preset.beta);
  d.rMax = static_cast<float>(preset.rMax);
  d.plyTwistSign = preset.yarnClockWise ? -1.0f : 1.0f;
  if (d.plyCount == 0 || d.fiberCount == 0 || !(d.ellipseN > 0.0f) || !(d.ellipseB > 0.0f) || !(d.rMax > 0.0f) ||
      !std::isfinite(d.plyRadius) || !(d.plyRadius >= 0.0f))
    throw InputError(fmt::format("yarn preset {}: no ply density (ply_num {}, fiber_num {}, ellipse {}×{}, R_max {}, "
                                 "yarn_radius {})",
                                 preset.name, preset.plyNum, preset.fiberNum, preset.ellipseShort,
                                 preset.ellipseLong, preset.rMax, preset.yarnRadius));
  const float mass = ftFiberPlacementMass(d);
  if (!(mass > 0.0f) || !std::isfinite(mass))
    throw InputError(fmt::format("yarn preset {}: fiber density p(R) has no mass (epsilon {}, beta {})", preset.name,
                                 preset.epsilon, preset.beta));
  d.normalization = ftDensityNormalization(d);
  d.supportRadius = d.plyRadius + std::max(d.ellipseN, d.ellipseB) * d.rMax;
  return d;
}

}  // namespace ft
