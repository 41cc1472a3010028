// lighting.h — what a shaded picture is lit and made of: the fabric preset
// (data/fabric-bcsdf.tsv), the shading model of 000 §4.3, directional lights,
// a uniform ambient and the diffuse term. One description for the GPU render,
// the Embree ground truth, the harness and the benches; ShadingParams
// (common/fiber_shading.h) is what both sides read.
#pragma once
#include <string>
#include <vector>

#include "common/fiber_shading.h"

namespace ft {

struct DirectionalLight {
  glm::vec3 direction{0.3f, 0.8f, 0.5f};  // towards the light, world space (normalised on use)
  glm::vec3 irradiance{3.0f};             // on a plane facing the light
};

struct Lighting {
  std::string fabric = "cotton";      // preset name
  std::string model = "khungurn";     // khungurn (eq. 6 + ambient table) or simple (eq. 5)
  std::vector<DirectionalLight> lights{DirectionalLight{}};
  glm::vec3 ambient{0.1f};            // uniform ambient radiance L_amb
  glm::vec3 diffuse{0.4f};            // k_d ∈ [0, 1]: the diffuse share of the energy (fiber_shading.h)
  float simpleSpecular = 0.5f;        // k_s of eq. 5
  float simpleBetaDegrees = 5.0f;     // β of eq. 5 (000 gives no value; notes-rendering A4 [F])
  glm::vec3 background{0.0f};         // radiance behind the fibers
};

// The std140 block; InputError for an unknown fabric or model, more than
// FT_MAX_LIGHTS lights, a zero light direction, or negative / non-finite
// radiometric values (named by option).
ShadingParams makeShadingParams(const Lighting& lighting);

}  // namespace ft
