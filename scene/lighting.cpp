#include "scene/lighting.h"

#include <cmath>
#include <fmt/format.h>

#include "scene/fabric.h"
#include "scene/input_error.h"

namespace ft {

namespace {

void checkColor(glm::vec3 c, const char* what) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(c[i]) || c[i] < 0.0f)
      throw InputError(fmt::format("{}: {},{},{} is not a finite non-negative colour", what, c.x, c.y, c.z));
}

}  // namespace

ShadingParams makeShadingParams(const Lighting& l) {
  ShadingParams s{};
  s.fabric = findFabricPreset(l.fabric).params();
  if (l.model == "khungurn") s.flags.y = FT_SHADING_KHUNGURN;
  else if (l.model == "simple") s.flags.y = FT_SHADING_SIMPLE;
  else throw InputError(fmt::format("--shading: '{}' is neither khungurn nor simple", l.model));
  if (l.lights.size() > FT_MAX_LIGHTS)
    throw InputError(fmt::format("{} lights given, at most {}", l.lights.size(), FT_MAX_LIGHTS));
  for (size_t i = 0; i < l.lights.size(); ++i) {
    const glm::vec3 d = l.lights[i].direction;
    const float len = glm::length(d);
    if (!std::isfinite(len) || len == 0.0f)
      throw InputError(fmt::format("light {}: direction {},{},{} is not a non-zero vector", i, d.x, d.y, d.z));
    checkColor(l.lights[i].irradiance, "light irradiance");
    s.lightDirection[i] = glm::vec4(d / len, 0.0f);
    s.lightIrradiance[i] = glm::vec4(l.lights[i].irradiance, 0.0f);
  }
  s.flags.x = static_cast<uint32_t>(l.lights.size());
  checkColor(l.ambient, "--ambient");
  checkColor(l.diffuse, "--diffuse");
  // k_d is the diffuse share of the scattered energy (fiber_shading.h): above
  // 1 the BCSDF's weight 1 − k_d would turn negative.
  if (l.diffuse.x > 1.0f || l.diffuse.y > 1.0f || l.diffuse.z > 1.0f)
    throw InputError(fmt::format("--diffuse: {},{},{} is above 1 (k_d is the diffuse share of the scattered energy, "
                                 "in [0, 1])",
                                 l.diffuse.x, l.diffuse.y, l.diffuse.z));
  checkColor(l.background, "background");
  if (!std::isfinite(l.simpleSpecular) || l.simpleSpecular < 0.0f)
    throw InputError(fmt::format("k_s: {} is not a finite non-negative number", l.simpleSpecular));
  if (!(l.simpleBetaDegrees > 0.0f && l.simpleBetaDegrees <= 90.0f))
    throw InputError(fmt::format("simple-model β: {} degrees is outside (0, 90]", l.simpleBetaDegrees));
  s.ambient = glm::vec4(l.ambient, 0.0f);
  s.diffuse = glm::vec4(l.diffuse, 0.0f);
  s.simple = glm::vec4(l.simpleSpecular, glm::radians(l.simpleBetaDegrees), 0.0f, 0.0f);
  s.background = glm::vec4(l.background, 0.0f);
  return s;
}

}  // namespace ft
