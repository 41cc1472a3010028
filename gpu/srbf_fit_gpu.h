// srbf_fit_gpu.h — the GPU side of the SRBF environment fit (001 §4.5 eq. 14;
// common/srbf.h, reference/srbf_fit.h): srbf_fit_sums.comp.glsl reduces the
// normal equations K (discrete Gram) and b over the pixels of an equirect map
// in float, one invocation per sum (the O(pixels · 17²) part), in chunks of
// rows (no invocation past gallivm's loop limit; the chunks added in double,
// 1 chunk for maps up to 256 × 128); the 17 × 17
// non-negative solve stays on the CPU (fitSrbfFromSums), as notes A9 says.
#pragma once
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "common/srbf.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"
#include "image/image.h"

namespace ft {

class SrbfFitGpu {
 public:
  explicit SrbfFitGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});
  // b (rgb, `count` entries) and K (count × count, row-major) for the lobes
  // (μ, λ) of `axisLambda` (16) and, if constantTerm, the DC term last.
  struct Sums {
    int count = 0;
    std::vector<glm::vec3> rhs;
    std::vector<float> gram;
  };
  Sums normalEquations(const ImageRgbaF& env, const glm::vec4 (&axisLambda)[FT_SRBF_LOBES], bool constantTerm);

 private:
  int maxGroupsY_ = 65535;
  Program program_;
};

}  // namespace ft
