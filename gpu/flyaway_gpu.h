// flyaway_gpu.h — the GPU twin of the flyaway curves and textures (001 §4.4,
// eq. 12–13; reference/flyaway.h is the CPU side, common/flyaway.h the shared
// model): flyaway_curves.comp.glsl (one invocation per slot) and
// flyaway_bake.comp.glsl (one per texel of each layer). Each call uploads,
// dispatches and reads back.
#pragma once
#include <string>
#include <vector>

#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"
#include "scene/flyaway_input.h"

namespace ft {

class FlyawayGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, see validation/faults.h).
  explicit FlyawayGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});
  FlyawayCurves generate(const FlyawayParams& params);
  // The curves of pattern 0 must be those generate() returned (or the CPU's).
  FlyawayTextures bake(const FlyawayCurves& curves);

 private:
  int maxGroupsY_ = 65535;
  Program curves_, bake_;
};

}  // namespace ft
