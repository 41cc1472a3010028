// dual_scattering_gpu.h — the GPU side of dual scattering
// (common/dual_scattering.h; Zinke et al. 2008 as 001 §4.1 eq. 8 uses it):
// dual_scattering_bake.comp.glsl bakes the table in float, one invocation per
// texel; dual_scattering_eval.comp.glsl evaluates the per-frame function on a
// list of requests. Every call uploads, dispatches and reads back.
#pragma once
#include <epoxy/gl.h>

#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/dual_scattering.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

struct DsTableGpu {
  std::vector<glm::vec4> rows;                  // FT_DS_ROWS per texel, texel-major
  std::vector<glm::vec3> aFR, aFTT, aBR, aBTT;  // the lobe integrals per texel
};

// One evaluation request: angles, visibility V, fibers crossed n.
struct DsEvalRequest {
  float thetaI = 0.0f, thetaO = 0.0f, phi = 0.0f;
  float visibility = 1.0f, fibers = 0.0f;
};

class DualScatteringGpu {
 public:
  // Midpoint steps over θ_o ∈ [−π/2, π/2]: π/2048 is 1/11 of the narrowest
  // lobe (β_R = 1°); the midpoint rule on a Gaussian is then exact to far
  // below float rounding (its error falls as exp(−2π²β²/h²)).
  static constexpr int kSteps = 2048;

  // defines: extra preprocessor symbols (fault injection, see validation/faults.h).
  explicit DualScatteringGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});

  DsTableGpu bakeTable(const FabricParams& fabric, int texels = FT_DS_TABLE_SIZE, int steps = kSteps);
  // ftDsEvaluate at each request with `rows` (a table of FT_DS_ROWS per texel) read at θ_d.
  std::vector<DsFrame> evaluate(const FabricParams& fabric, std::span<const glm::vec4> rows,
                                std::span<const DsEvalRequest> requests);

 private:
  int maxGroupsY_ = 65535;
  Program bakeProgram_, evalProgram_;
};

}  // namespace ft
