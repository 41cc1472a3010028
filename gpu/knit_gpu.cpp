#include "gpu/knit_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "common/constants.h"
#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {

KnitGpu::KnitGpu(const GlInfo& gl, std::vector<std::string> defines)
    : defines_(std::move(defines)), maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  optimizeProgram_ = Program(buildProgram({"shaders/knit_optimize.comp.glsl"}, defines_));
  upsampleProgram_ = Program(buildProgram({"shaders/knit_upsample.comp.glsl"}, defines_));
  params_ = Buffer::create(sizeof(KnitSolveParams));
}

void KnitGpu::setStitches(std::span<const KnitStitchGpu> stitches, const KnitSolveParams& params) {
  if (params.stitchCount != stitches.size())
    throw std::invalid_argument(fmt::format("KnitGpu: params.stitchCount {} but {} stitches", params.stitchCount,
                                            stitches.size()));
  stitchCount_ = static_cast<uint32_t>(stitches.size());
  params_.update(&params, sizeof(params));
  stitches_ = Buffer::create(stitches.size_bytes(), stitches.data());
  points_ = Buffer::create(size_t(stitchCount_) * FT_KNIT_TILE_POINTS * sizeof(glm::vec4));
  energies_ = Buffer::create(size_t(stitchCount_) * sizeof(KnitEnergyGpu));
}

void KnitGpu::setYarnList(std::span<const glm::uvec4> list) {
  listCount_ = list.size();
  list_ = Buffer::create(list.size_bytes(), list.data());
  vertices_ = Buffer::create(listCount_ * FT_KNIT_UPSAMPLE * sizeof(glm::vec4));
  vertices_.clear();
}

void KnitGpu::dispatch(GLuint program, size_t items, size_t groupSize, const char* what) {
  if (items == 0) return;
  const size_t groups = (items + groupSize - 1) / groupSize;
  const uint32_t groupsX = static_cast<uint32_t>(std::min<size_t>(groups, 65535));
  const size_t groupsY = (groups + groupsX - 1) / groupsX;
  if (groupsY > static_cast<size_t>(maxGroupsY_))
    throw std::runtime_error(fmt::format("{}: {} work groups exceed the GL limit", what, groups));
  setUniform(program, "groupsX", groupsX);
  glDispatchCompute(groupsX, static_cast<GLuint>(groupsY), 1);
  glCheck(what);
}

void KnitGpu::optimize() {
  glUseProgram(optimizeProgram_.id());
  params_.bindBase(GL_UNIFORM_BUFFER, FT_UBO_KNIT_PARAMS);
  stitches_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_KNIT_STITCHES);
  points_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_KNIT_POINTS);
  energies_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_KNIT_ENERGY);
  dispatch(optimizeProgram_.id(), stitchCount_, FT_WG_KNIT, "knit_optimize");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void KnitGpu::upsample() {
  if (listCount_ == 0) return;
  glUseProgram(upsampleProgram_.id());
  points_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_KNIT_POINTS);
  list_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_KNIT_YARN_LIST);
  vertices_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_KNIT_VERTICES);
  setUniform(upsampleProgram_.id(), "listCount", static_cast<uint32_t>(listCount_));
  dispatch(upsampleProgram_.id(), listCount_, FT_WG_KNIT_UPSAMPLE, "knit_upsample");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void KnitGpu::run() {
  optimize();
  upsample();
}

std::vector<glm::vec4> KnitGpu::readPoints() const {
  return readBuffer<glm::vec4>(points_.id(), size_t(stitchCount_) * FT_KNIT_TILE_POINTS);
}
std::vector<KnitEnergyGpu> KnitGpu::readEnergies() const {
  return readBuffer<KnitEnergyGpu>(energies_.id(), size_t(stitchCount_));
}
std::vector<glm::vec4> KnitGpu::readVertices() const {
  return readBuffer<glm::vec4>(vertices_.id(), listCount_ * FT_KNIT_UPSAMPLE);
}

}  // namespace ft
