#include "gpu/srbf_fit_gpu.h"

#include <algorithm>
#include <stdexcept>

#include "common/constants.h"
#include "gpu/compute_dispatch.h"
#include "gpu/shader_library.h"

namespace ft {

SrbfFitGpu::SrbfFitGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  program_ = Program(buildProgram({"shaders/srbf_fit_sums.comp.glsl"}, defines));
}

SrbfFitGpu::Sums SrbfFitGpu::normalEquations(const ImageRgbaF& env, const glm::vec4 (&axisLambda)[FT_SRBF_LOBES],
                                             bool constantTerm) {
  if (env.width < 2 || env.height < 2 || env.pixels.size() != env.pixelCount() * 4)
    throw std::invalid_argument("SrbfFitGpu: the environment map is empty or malformed");
  SrbfEnvironment block{};
  for (int j = 0; j < FT_SRBF_LOBES; ++j) block.lobes[j].axisLambda = axisLambda[j];
  const Buffer ubo = Buffer::create(sizeof(block), &block);
  const Buffer pixels = Buffer::create(env.pixels.size() * sizeof(float), env.pixels.data());
  const int count = FT_SRBF_LOBES + (constantTerm ? 1 : 0);
  const size_t items = size_t(count + count * count);
  const Buffer out = Buffer::create(items * sizeof(glm::vec4));
  const GLuint p = program_.id();
  setUniform(p, "width", uint32_t(env.width));
  setUniform(p, "height", uint32_t(env.height));
  setUniform(p, "count", uint32_t(count));
  ubo.bindBase(GL_UNIFORM_BUFFER, FT_UBO_SRBF);
  pixels.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SRBF_ENV_PIXELS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SRBF_SUMS);
  // gallivm ends a loop after 65,535 iterations counted over the whole
  // invocation (docs/llvmpipe-notes.md): at most kIterations pixels per
  // invocation, the chunks added here in double.
  constexpr int kIterations = 32768;
  if (env.width > kIterations) throw std::invalid_argument("SrbfFitGpu: the map is wider than 32,768 pixels");
  const int rowsPerChunk = std::max(1, kIterations / env.width);
  std::vector<glm::dvec4> total(items, glm::dvec4(0.0));
  for (int y0 = 0; y0 < env.height; y0 += rowsPerChunk) {
    setUniform(p, "rowBegin", uint32_t(y0));
    setUniform(p, "rowEnd", uint32_t(std::min(env.height, y0 + rowsPerChunk)));
    dispatchFlat(p, items, FT_WG_SRBF, maxGroupsY_, "srbf_fit_sums");
    const std::vector<glm::vec4> raw = readBuffer<glm::vec4>(out.id(), items);
    for (size_t i = 0; i < items; ++i) total[i] += glm::dvec4(raw[i]);
  }
  Sums s;
  s.count = count;
  for (int i = 0; i < count; ++i) s.rhs.push_back(glm::vec3(total[size_t(i)]));
  for (size_t i = size_t(count); i < items; ++i) s.gram.push_back(float(total[i].x));
  return s;
}

}  // namespace ft
