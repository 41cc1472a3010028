// core_texture_gpu.h — the GPU twin of the core-fiber texture bake
// (000 §3.2; reference/core_texture.h is the CPU side, common/core_texture.h
// the shared conventions): core_texture_bake.comp.glsl, one invocation per
// texel, FT_WG_CORE_TEXTURE per group. Each call uploads, dispatches and
// reads back (waits for the GPU).
#pragma once
#include <string>
#include <vector>

#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"
#include "scene/core_texture_input.h"

namespace ft {

class CoreTextureGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, see validation/faults.h).
  explicit CoreTextureGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});
  CoreTexture bake(const CoreTextureInput& input);

 private:
  int maxGroupsY_ = 65535;
  Program program_;
};

}  // namespace ft
