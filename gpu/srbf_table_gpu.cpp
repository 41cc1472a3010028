#include "gpu/srbf_table_gpu.h"

#include <stdexcept>

#include "common/constants.h"
#include "gpu/compute_dispatch.h"
#include "gpu/shader_library.h"

namespace ft {
namespace {

void setDims(GLuint program, glm::ivec4 dims) {
  glUseProgram(program);
  const GLint loc = glGetUniformLocation(program, "dims");
  if (loc >= 0) glUniform4i(loc, dims.x, dims.y, dims.z, dims.w);
}

std::vector<glm::vec3> rgb(const std::vector<glm::vec4>& raw) {
  std::vector<glm::vec3> out(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) out[i] = glm::vec3(raw[i]);
  return out;
}

}  // namespace

SrbfTableGpu::SrbfTableGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  bakeProgram_ = Program(buildProgram({"shaders/srbf_table_bake.comp.glsl"}, defines));
  lookupProgram_ = Program(buildProgram({"shaders/srbf_table_lookup.comp.glsl"}, defines));
}

std::vector<glm::vec3> SrbfTableGpu::bake(const FabricParams& fabric, glm::ivec4 dims) {
  if (glm::any(glm::lessThan(dims, glm::ivec4(2)))) throw std::invalid_argument("SrbfTableGpu: every axis needs 2 values");
  const size_t n = size_t(ftSrbfTableSize(dims));
  const Buffer input = Buffer::create(sizeof(FabricParams), &fabric);
  const Buffer table = Buffer::create(n * sizeof(glm::vec4));
  const GLuint p = bakeProgram_.id();
  setDims(p, dims);
  input.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SRBF_INPUT);
  table.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SRBF_TABLE);
  dispatchFlat(p, n, FT_WG_SRBF, maxGroupsY_, "srbf_table_bake");
  return rgb(readBuffer<glm::vec4>(table.id(), n));
}

std::vector<glm::vec3> SrbfTableGpu::lookup(std::span<const glm::vec3> table, glm::ivec4 dims,
                                            std::span<const glm::vec4> requests) {
  if (table.size() != size_t(ftSrbfTableSize(dims))) throw std::invalid_argument("SrbfTableGpu::lookup: table size");
  std::vector<glm::vec4> texels(table.size());
  for (size_t i = 0; i < table.size(); ++i) texels[i] = glm::vec4(table[i], 0.0f);
  const Buffer tableBuffer = Buffer::fromVector(texels);
  const Buffer input = Buffer::create(std::max<size_t>(requests.size(), 1) * sizeof(glm::vec4), requests.data());
  const Buffer out = Buffer::create(std::max<size_t>(requests.size(), 1) * sizeof(glm::vec4));
  const GLuint p = lookupProgram_.id();
  setDims(p, dims);
  setUniform(p, "requestCount", uint32_t(requests.size()));
  input.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SRBF_INPUT);
  tableBuffer.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SRBF_TABLE);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SRBF_OUTPUT);
  dispatchFlat(p, requests.size(), FT_WG_SRBF, maxGroupsY_, "srbf_table_lookup");
  return rgb(readBuffer<glm::vec4>(out.id(), requests.size()));
}

}  // namespace ft
