// knit_gpu.h — the GPU twin of the knit optimization: knit_optimize.comp.glsl
// (one invocation per stitch, float) and knit_upsample.comp.glsl (Catmull–Rom
// rendering vertices per yarn point). Inputs are plain common/ records, so
// gpu/ stays independent of knit/ and reference/.
#pragma once
#include <epoxy/gl.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <string>
#include <vector>

#include "common/knit_stitch.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

class KnitGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, see validation/faults.h).
  explicit KnitGpu(const GlInfo& gl, std::vector<std::string> defines = {});

  // Uploads the stitches (one invocation each) and solver settings.
  void setStitches(std::span<const KnitStitchGpu> stitches, const KnitSolveParams& params);
  // Uploads the up-sampling list (knitYarnList).
  void setYarnList(std::span<const glm::uvec4> list);

  // Runs the optimizer, then (when a list is set) the up-sampling; does not wait.
  void run();
  void optimize();
  void upsample();

  uint32_t stitchCount() const { return stitchCount_; }
  // Read-backs (wait for the GPU): world points (stitch * 14 + i), per-stitch
  // energies (KnitEnergyGpu per stitch, common/knit_stitch.h), vertices.
  std::vector<glm::vec4> readPoints() const;
  std::vector<KnitEnergyGpu> readEnergies() const;
  std::vector<glm::vec4> readVertices() const;

 private:
  void dispatch(GLuint program, size_t items, size_t groupSize, const char* what);

  std::vector<std::string> defines_;
  int maxGroupsY_ = 65535;
  Program optimizeProgram_, upsampleProgram_;
  Buffer params_, stitches_, points_, energies_, list_, vertices_;
  uint32_t stitchCount_ = 0;
  size_t listCount_ = 0;
};

}  // namespace ft
