#include "gpu/core_texture_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "common/constants.h"
#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {

CoreTextureGpu::CoreTextureGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  program_ = Program(buildProgram({"shaders/core_texture_bake.comp.glsl"}, defines));
}

CoreTexture CoreTextureGpu::bake(const CoreTextureInput& input) {
  const CoreTextureParams& c = input.params;
  if (c.columns == 0 || c.height == 0 || input.fibers.size() != c.coreFibers || input.fibers.empty())
    throw std::invalid_argument(fmt::format("CoreTextureGpu: {}×{} texels, {} fibers for {} core fibers", c.columns,
                                            c.height, input.fibers.size(), c.coreFibers));
  const size_t texels = size_t(c.columns) * c.height;
  const Buffer block = Buffer::create(sizeof(CoreTextureParams), &c);
  const Buffer fibers = Buffer::fromVector(input.fibers);
  const Buffer tex0 = Buffer::create(texels * sizeof(glm::vec4));
  const Buffer tex1 = Buffer::create(texels * sizeof(glm::vec4));
  block.bindBase(GL_UNIFORM_BUFFER, FT_UBO_CORE_TEXTURE);
  fibers.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_CORE_FIBERS);
  tex0.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_CORE_TEX0);
  tex1.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_CORE_TEX1);

  dispatchFlat(program_.id(), texels, FT_WG_CORE_TEXTURE, maxGroupsY_, "core_texture_bake");

  CoreTexture out;
  out.columns = c.columns;
  out.height = c.height;
  out.tex0 = readBuffer<glm::vec4>(tex0.id(), texels);
  out.tex1 = readBuffer<glm::vec4>(tex1.id(), texels);
  return out;
}

}  // namespace ft
