#include "gpu/flyaway_gpu.h"

#include <fmt/format.h>

#include <stdexcept>

#include "common/constants.h"
#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {

FlyawayGpu::FlyawayGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  curves_ = Program(buildProgram({"shaders/flyaway_curves.comp.glsl"}, defines));
  bake_ = Program(buildProgram({"shaders/flyaway_bake.comp.glsl"}, defines));
}

FlyawayCurves FlyawayGpu::generate(const FlyawayParams& f) {
  const size_t slots = size_t(f.patterns) * FT_FLYAWAY_SETS * f.maxPerSet;
  if (slots == 0) throw std::invalid_argument("FlyawayGpu::generate: no slots");
  const Buffer block = Buffer::create(sizeof(FlyawayParams), &f);
  const Buffer points = Buffer::create(slots * FT_FLYAWAY_POINTS * sizeof(glm::vec4));
  const Buffer headers = Buffer::create(slots * sizeof(glm::vec4));
  block.bindBase(GL_UNIFORM_BUFFER, FT_UBO_FLYAWAY);
  points.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FLYAWAY_POINTS);
  headers.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FLYAWAY_HEADERS);
  dispatchFlat(curves_.id(), slots, FT_WG_FLYAWAY, maxGroupsY_, "flyaway_curves");
  FlyawayCurves out;
  out.params = f;
  out.points = readBuffer<glm::vec4>(points.id(), slots * FT_FLYAWAY_POINTS);
  out.headers = readBuffer<glm::vec4>(headers.id(), slots);
  return out;
}

FlyawayTextures FlyawayGpu::bake(const FlyawayCurves& c) {
  const FlyawayParams& f = c.params;
  if (c.headers.size() < size_t(FT_FLYAWAY_SETS) * f.maxPerSet || c.points.size() != c.headers.size() * FT_FLYAWAY_POINTS)
    throw std::invalid_argument("FlyawayGpu::bake: curve buffers do not match the block");
  const size_t texels = size_t(FT_FLYAWAY_LAYERS) * f.width * f.height;
  const Buffer block = Buffer::create(sizeof(FlyawayParams), &f);
  const Buffer points = Buffer::fromVector(c.points);
  const Buffer headers = Buffer::fromVector(c.headers);
  const Buffer out = Buffer::create(texels * sizeof(uint32_t));
  block.bindBase(GL_UNIFORM_BUFFER, FT_UBO_FLYAWAY);
  points.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FLYAWAY_POINTS);
  headers.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FLYAWAY_HEADERS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FLYAWAY_TEXELS);
  dispatchFlat(bake_.id(), texels, FT_WG_FLYAWAY, maxGroupsY_, "flyaway_bake");
  FlyawayTextures t;
  t.width = f.width;
  t.height = f.height;
  t.texels = readBuffer<uint32_t>(out.id(), texels);
  return t;
}

}  // namespace ft
