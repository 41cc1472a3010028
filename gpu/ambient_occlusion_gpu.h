// ambient_occlusion_gpu.h — the GPU side of the yarn ambient occlusion of Wu
// & Yuksel 2019 (000) §4.2 (common/ambient_occlusion.h, notes-rendering A3):
//   bakeExact / exactAt:  ftAoExact per texel or point, the same exact line
//     integral and directions as the CPU reference (ambient_occlusion_exact.comp.glsl);
//   bakeMarched:          the paper's way (Fig. 8a–b): a density grid
//     (ambient_occlusion_density.comp.glsl), then per texel rays marched
//     through it with a manual bilinear fetch (ambient_occlusion_march.comp.glsl);
//   evaluate:             the distance-based cubic and the rotated texture
//     lookup at given cross-section points (ambient_occlusion_eval.comp.glsl).
// One invocation per texel or request, FT_WG_AO per group; every call uploads,
// dispatches and reads back.
#pragma once
#include <epoxy/gl.h>

#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "common/ambient_occlusion.h"
#include "common/constants.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

// One evaluation request: the fiber point is plyOffset + fiberOffset in the
// yarn cross-section; θ_ply,0 turns the texture.
struct AoEvalRequest {
  glm::vec2 plyOffset{0.0f}, fiberOffset{0.0f};
  float plyAngle = 0.0f;
};

class AmbientOcclusionGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, validation/faults.h).
  explicit AmbientOcclusionGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});

  // AO at every texel centre (n × n, texel j·n + i), exact line integral.
  std::vector<float> bakeExact(const AmbientOcclusionParams& p);
  // AO at points (x, y, ψ), point k's jitter keyed by k.
  std::vector<float> exactAt(const AmbientOcclusionParams& p, std::span<const glm::vec3> pointsPsi);
  // The density grid (m × m over [−W, W]², m = p.densityResolution, ψ = 0).
  std::vector<float> densityGrid(const AmbientOcclusionParams& p);
  // The paper-faithful texture: density grid, then rays marched through it.
  std::vector<float> bakeMarched(const AmbientOcclusionParams& p);
  // The march alone through a given m × m grid (texel j·m + i, centres as the
  // density grid's): how the harness checks the march on a field it knows.
  std::vector<float> marchGrid(const AmbientOcclusionParams& p, std::span<const float> grid);
  // (ftAoCubic, the texture lookup) at each request; `texture` is n × n.
  std::vector<glm::vec2> evaluate(const AmbientOcclusionParams& p, std::span<const float> texture,
                                  std::span<const AoEvalRequest> requests);

 private:
  void dispatch(GLuint program, size_t items, const char* what);
  Buffer params(const AmbientOcclusionParams& p);

  int maxGroupsY_ = 65535;
  Program exactProgram_, densityProgram_, marchProgram_, evalProgram_;
};

}  // namespace ft
