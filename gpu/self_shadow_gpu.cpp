#include "gpu/self_shadow_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "common/constants.h"
#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {
namespace {

// The std140 block of every self-shadow shader.
struct ParamsBlock {
  SelfShadowParams shadow;
  YarnDensityParams density;
};
static_assert(sizeof(ParamsBlock) == 80, "SelfShadowBlock: std140 structs of 32 and 48 bytes");


}  // namespace

SelfShadowGpu::SelfShadowGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  exactProgram_ = Program(buildProgram({"shaders/self_shadow_exact.comp.glsl"}, defines));
  densityProgram_ = Program(buildProgram({"shaders/self_shadow_density.comp.glsl"}, defines));
  prefixProgram_ = Program(buildProgram({"shaders/self_shadow_prefix.comp.glsl"}, defines));
  lookupProgram_ = Program(buildProgram({"shaders/self_shadow_lookup.comp.glsl"}, defines));
}

size_t SelfShadowGpu::texelCount(const SelfShadowParams& p) {
  if (p.width < 3 || p.height < 3 || p.slices < 1 || p.width > 4096 || p.height > 4096 || p.slices > 4096)
    throw std::invalid_argument(
        fmt::format("SelfShadowGpu: texture size {}×{}×{} (each axis in [3, 4096], slices in [1, 4096])", p.width,
                    p.height, p.slices));
  return size_t(p.width) * p.height * p.slices;
}

void SelfShadowGpu::bindParams(const YarnDensityParams& density, const SelfShadowParams& params) {
  const ParamsBlock block{params, density};
  params_ = Buffer::create(sizeof(block), &block);
  params_.bindBase(GL_UNIFORM_BUFFER, FT_UBO_SELF_SHADOW);
}

void SelfShadowGpu::dispatch(GLuint program, size_t items, const char* what) {
  dispatchFlat(program, items, FT_WG_SELF_SHADOW, maxGroupsY_, what);
}

std::vector<float> SelfShadowGpu::bakeExact(const YarnDensityParams& density, const SelfShadowParams& params) {
  const size_t n = texelCount(params);
  bindParams(density, params);
  const Buffer out = Buffer::create(n * sizeof(float));
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SELF_SHADOW_TEXTURE);
  dispatch(exactProgram_.id(), n, "self_shadow_exact");
  return readBuffer<float>(out.id(), n);
}

std::vector<float> SelfShadowGpu::bakeGrid(const YarnDensityParams& density, const SelfShadowParams& params) {
  const size_t n = texelCount(params);
  bindParams(density, params);
  const Buffer rho = Buffer::create(n * sizeof(float)), out = Buffer::create(n * sizeof(float));
  rho.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SELF_SHADOW_DENSITY);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SELF_SHADOW_TEXTURE);
  dispatch(densityProgram_.id(), n, "self_shadow_density");
  dispatch(prefixProgram_.id(), size_t(params.height) * params.slices, "self_shadow_prefix");
  return readBuffer<float>(out.id(), n);
}

std::vector<SelfShadowAnswer> SelfShadowGpu::lookup(const YarnDensityParams& density, const SelfShadowParams& params,
                                                    std::span<const float> texels,
                                                    std::span<const SelfShadowQuery> queries) {
  const size_t n = texelCount(params);
  if (texels.size() != n)
    throw std::invalid_argument(fmt::format("SelfShadowGpu::lookup: {} texels for a {}×{}×{} texture", texels.size(),
                                            params.width, params.height, params.slices));
  bindParams(density, params);
  std::vector<glm::vec4> requests(2 * std::max<size_t>(queries.size(), 1));
  for (size_t q = 0; q < queries.size(); ++q) {
    requests[2 * q] = glm::vec4(queries[q].x, queries[q].toLight);
    requests[2 * q + 1] = glm::vec4(queries[q].plyAngle, 0.0f, 0.0f, 0.0f);
  }
  const Buffer tex = Buffer::create(n * sizeof(float), texels.data());
  const Buffer in = Buffer::fromVector(requests);
  const Buffer out = Buffer::create(std::max<size_t>(queries.size(), 1) * sizeof(glm::vec4));
  tex.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SELF_SHADOW_TEXTURE);
  in.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SELF_SHADOW_REQUESTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SELF_SHADOW_RESULTS);
  setUniform(lookupProgram_.id(), "requestCount", static_cast<uint32_t>(queries.size()));
  dispatch(lookupProgram_.id(), queries.size(), "self_shadow_lookup");
  const std::vector<glm::vec4> raw = readBuffer<glm::vec4>(out.id(), queries.size());
  std::vector<SelfShadowAnswer> answers(queries.size());
  for (size_t q = 0; q < queries.size(); ++q) answers[q] = {raw[q].x, raw[q].y, raw[q].z};
  return answers;
}

}  // namespace ft
