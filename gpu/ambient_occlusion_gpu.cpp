#include "gpu/ambient_occlusion_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {
namespace {


void checkParams(const AmbientOcclusionParams& p) {
  if (p.resolution < 2 || p.directions < 1 || p.densityResolution < 2 || !(p.halfWidth > 0.0f) ||
      !(p.marchStep > 0.0f))
    throw std::invalid_argument(fmt::format("AmbientOcclusionGpu: resolution {}, directions {}, density grid {}, "
                                            "half-width {}, march step {}",
                                            p.resolution, p.directions, p.densityResolution, p.halfWidth,
                                            p.marchStep));
}

}  // namespace

AmbientOcclusionGpu::AmbientOcclusionGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  exactProgram_ = Program(buildProgram({"shaders/ambient_occlusion_exact.comp.glsl"}, defines));
  densityProgram_ = Program(buildProgram({"shaders/ambient_occlusion_density.comp.glsl"}, defines));
  marchProgram_ = Program(buildProgram({"shaders/ambient_occlusion_march.comp.glsl"}, defines));
  evalProgram_ = Program(buildProgram({"shaders/ambient_occlusion_eval.comp.glsl"}, defines));
}

Buffer AmbientOcclusionGpu::params(const AmbientOcclusionParams& p) {
  checkParams(p);
  Buffer b = Buffer::create(sizeof(AmbientOcclusionParams), &p);
  b.bindBase(GL_UNIFORM_BUFFER, FT_UBO_AMBIENT_OCCLUSION);
  return b;
}

void AmbientOcclusionGpu::dispatch(GLuint program, size_t items, const char* what) {
  dispatchFlat(program, items, FT_WG_AO, maxGroupsY_, what);
}

std::vector<float> AmbientOcclusionGpu::bakeExact(const AmbientOcclusionParams& p) {
  const Buffer u = params(p);
  const size_t count = size_t(p.resolution) * p.resolution;
  const Buffer points = Buffer::create(16);
  const Buffer out = Buffer::create(count * sizeof(float));
  points.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_POINTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_OUTPUT);
  setUniform(exactProgram_.id(), "pointMode", 0u);
  dispatch(exactProgram_.id(), count, "ambient_occlusion_exact");
  return readBuffer<float>(out.id(), count);
}

std::vector<float> AmbientOcclusionGpu::exactAt(const AmbientOcclusionParams& p, std::span<const glm::vec3> pointsPsi) {
  const Buffer u = params(p);
  std::vector<glm::vec4> req(pointsPsi.size());
  for (size_t k = 0; k < req.size(); ++k) req[k] = glm::vec4(pointsPsi[k], 0.0f);
  const Buffer points = Buffer::create(req.size() * sizeof(glm::vec4), req.data());
  const Buffer out = Buffer::create(std::max<size_t>(req.size(), 1) * sizeof(float));
  points.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_POINTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_OUTPUT);
  setUniform(exactProgram_.id(), "pointMode", 1u);
  dispatch(exactProgram_.id(), req.size(), "ambient_occlusion_exact");
  return readBuffer<float>(out.id(), req.size());
}

std::vector<float> AmbientOcclusionGpu::densityGrid(const AmbientOcclusionParams& p) {
  const Buffer u = params(p);
  const size_t count = size_t(p.densityResolution) * p.densityResolution;
  const Buffer grid = Buffer::create(count * sizeof(float));
  grid.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_DENSITY);
  dispatch(densityProgram_.id(), count, "ambient_occlusion_density");
  return readBuffer<float>(grid.id(), count);
}

std::vector<float> AmbientOcclusionGpu::bakeMarched(const AmbientOcclusionParams& p) {
  const Buffer u = params(p);
  const size_t cells = size_t(p.densityResolution) * p.densityResolution;
  const size_t count = size_t(p.resolution) * p.resolution;
  const Buffer grid = Buffer::create(cells * sizeof(float));
  const Buffer out = Buffer::create(count * sizeof(float));
  grid.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_DENSITY);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_OUTPUT);
  dispatch(densityProgram_.id(), cells, "ambient_occlusion_density");
  dispatch(marchProgram_.id(), count, "ambient_occlusion_march");
  return readBuffer<float>(out.id(), count);
}

std::vector<float> AmbientOcclusionGpu::marchGrid(const AmbientOcclusionParams& p, std::span<const float> grid) {
  const Buffer u = params(p);
  if (grid.size() != size_t(p.densityResolution) * p.densityResolution)
    throw std::invalid_argument(fmt::format("AmbientOcclusionGpu::marchGrid: {} cells for a {}² grid", grid.size(),
                                            p.densityResolution));
  const size_t count = size_t(p.resolution) * p.resolution;
  const Buffer g = Buffer::create(grid.size() * sizeof(float), grid.data());
  const Buffer out = Buffer::create(count * sizeof(float));
  g.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_DENSITY);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_OUTPUT);
  dispatch(marchProgram_.id(), count, "ambient_occlusion_march");
  return readBuffer<float>(out.id(), count);
}

std::vector<glm::vec2> AmbientOcclusionGpu::evaluate(const AmbientOcclusionParams& p, std::span<const float> texture,
                                                     std::span<const AoEvalRequest> requests) {
  if (texture.size() != size_t(p.resolution) * p.resolution)
    throw std::invalid_argument(fmt::format("AmbientOcclusionGpu::evaluate: {} texels for a {}² texture",
                                            texture.size(), p.resolution));
  const Buffer u = params(p);
  std::vector<glm::vec4> req(2 * requests.size());
  for (size_t k = 0; k < requests.size(); ++k) {
    req[2 * k] = glm::vec4(requests[k].plyOffset, requests[k].fiberOffset);
    req[2 * k + 1] = glm::vec4(requests[k].plyAngle, 0.0f, 0.0f, 0.0f);
  }
  const Buffer points = Buffer::create(req.size() * sizeof(glm::vec4), req.data());
  const Buffer tex = Buffer::create(texture.size() * sizeof(float), texture.data());
  const Buffer out = Buffer::create(std::max<size_t>(requests.size(), 1) * sizeof(glm::vec2));
  points.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_POINTS);
  tex.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_TEXTURE);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_OUTPUT);
  dispatch(evalProgram_.id(), requests.size(), "ambient_occlusion_eval");
  return readBuffer<glm::vec2>(out.id(), requests.size());
}

}  // namespace ft
