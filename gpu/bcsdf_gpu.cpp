#include "gpu/bcsdf_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "common/constants.h"
#include "gpu/compute_dispatch.h"
#include "gpu/fabric_request_buffer.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {

BcsdfGpu::BcsdfGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  evalProgram_ = Program(buildProgram({"shaders/bcsdf_eval.comp.glsl"}, defines));
  bakeProgram_ = Program(buildProgram({"shaders/bcsdf_ambient.comp.glsl"}, defines));
  lobeNormProgram_ = Program(buildProgram({"shaders/bcsdf_lobe_norm.comp.glsl"}, defines));
}

void BcsdfGpu::dispatch(GLuint program, size_t items, const char* what) {
  dispatchFlat(program, items, FT_WG_BCSDF, maxGroupsY_, what);
}

std::vector<glm::vec3> BcsdfGpu::readResults(size_t count) {
  const std::vector<glm::vec4> raw = readBuffer<glm::vec4>(output_.id(), count);
  std::vector<glm::vec3> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = glm::vec3(raw[i]);
  return out;
}

std::vector<glm::vec3> BcsdfGpu::evaluate(const FabricParams& fabric, const std::vector<glm::vec4>& requests,
                                          size_t count, Kind kind, const BcsdfEvalMode& mode) {
  if (mode.model != FT_SHADING_KHUNGURN && mode.model != FT_SHADING_SIMPLE)
    throw std::invalid_argument(fmt::format("BcsdfGpu: unknown model {}", mode.model));
  const Buffer input = fabricRequestBuffer(fabric, requests);
  output_ = Buffer::create(std::max<size_t>(count, 1) * sizeof(glm::vec4));
  const GLuint p = evalProgram_.id();
  setUniform(p, "requestCount", static_cast<uint32_t>(count));
  setUniform(p, "model", mode.model);
  setUniform(p, "lobes", mode.lobes);
  setUniform(p, "kind", static_cast<uint32_t>(kind));
  setUniform(p, "simple", glm::vec2(mode.ks, mode.beta));
  input.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_BCSDF_INPUT);
  output_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_BCSDF_OUTPUT);
  dispatch(p, count, "bcsdf_eval");
  return readResults(count);
}

std::vector<glm::vec3> BcsdfGpu::evaluateAngles(const FabricParams& fabric, std::span<const FiberAngles> angles,
                                                const BcsdfEvalMode& mode) {
  std::vector<glm::vec4> requests(angles.size());
  for (size_t i = 0; i < angles.size(); ++i)
    requests[i] = glm::vec4(angles[i].thetaI, angles[i].thetaO, angles[i].phi, 0.0f);
  return evaluate(fabric, requests, angles.size(), kAngles, mode);
}

std::vector<glm::vec4> BcsdfGpu::directionRequests(std::span<const glm::vec3> tangents, std::span<const glm::vec3> wi,
                                                   std::span<const glm::vec3> wo) {
  if (wi.size() != tangents.size() || wo.size() != tangents.size())
    throw std::invalid_argument("BcsdfGpu: tangents, wi and wo differ in size");
  std::vector<glm::vec4> requests(3 * tangents.size());
  for (size_t i = 0; i < tangents.size(); ++i) {
    requests[3 * i] = glm::vec4(tangents[i], 0.0f);
    requests[3 * i + 1] = glm::vec4(wi[i], 0.0f);
    requests[3 * i + 2] = glm::vec4(wo[i], 0.0f);
  }
  return requests;
}

std::vector<glm::vec3> BcsdfGpu::evaluateDirections(const FabricParams& fabric, std::span<const glm::vec3> tangents,
                                                    std::span<const glm::vec3> wi, std::span<const glm::vec3> wo,
                                                    const BcsdfEvalMode& mode) {
  return evaluate(fabric, directionRequests(tangents, wi, wo), tangents.size(), kDirections, mode);
}

std::vector<FiberAngles> BcsdfGpu::fiberAngles(std::span<const glm::vec3> tangents, std::span<const glm::vec3> wi,
                                               std::span<const glm::vec3> wo) {
  const std::vector<glm::vec3> raw =
      evaluate(FabricParams{}, directionRequests(tangents, wi, wo), tangents.size(), kDirectionAngles, {});
  std::vector<FiberAngles> out(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) out[i] = {raw[i].x, raw[i].y, raw[i].z};
  return out;
}

std::vector<glm::vec3> BcsdfGpu::bakeAmbientTable(const FabricParams& fabric, int texels, int steps) {
  if (texels < 2 || steps < 1) throw std::invalid_argument(fmt::format("BcsdfGpu: {} texels, {} steps", texels, steps));
  const Buffer input = fabricRequestBuffer(fabric, {});
  output_ = Buffer::create(size_t(texels) * sizeof(glm::vec4));
  const GLuint p = bakeProgram_.id();
  setUniform(p, "texels", static_cast<uint32_t>(texels));
  setUniform(p, "steps", static_cast<uint32_t>(steps));
  input.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_BCSDF_INPUT);
  output_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_BCSDF_OUTPUT);
  dispatch(p, size_t(texels), "bcsdf_ambient");
  return readResults(size_t(texels));
}

std::vector<glm::vec3> BcsdfGpu::lookupAmbient(std::span<const glm::vec3> table, std::span<const float> thetas) {
  if (table.size() < 2) throw std::invalid_argument("BcsdfGpu::lookupAmbient: a table needs at least 2 texels");
  std::vector<glm::vec4> texels(table.size()), requests(thetas.size());
  for (size_t k = 0; k < table.size(); ++k) texels[k] = glm::vec4(table[k], 0.0f);
  for (size_t i = 0; i < thetas.size(); ++i) requests[i] = glm::vec4(thetas[i], 0.0f, 0.0f, 0.0f);
  const Buffer tableBuffer = Buffer::fromVector(texels);
  tableBuffer.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AMBIENT_TABLE);
  setUniform(evalProgram_.id(), "texels", static_cast<uint32_t>(table.size()));
  return evaluate(FabricParams{}, requests, thetas.size(), kLookup, {});
}

std::vector<glm::vec2> BcsdfGpu::runLobeNorm(const FabricParams& fabric, std::span<const glm::vec2> table,
                                             std::span<const float> thetas, int texels, bool lookup) {
  if (texels < 2) throw std::invalid_argument(fmt::format("BcsdfGpu: a lobe-normalisation table of {} texels", texels));
  std::vector<glm::vec4> requests(thetas.size());
  for (size_t i = 0; i < thetas.size(); ++i) requests[i] = glm::vec4(thetas[i], 0.0f, 0.0f, 0.0f);
  const Buffer input = fabricRequestBuffer(fabric, requests);
  const std::vector<glm::vec2> tableOrDummy = table.empty() ? std::vector<glm::vec2>(2) : std::vector(table.begin(), table.end());
  const Buffer tableBuffer = Buffer::fromVector(tableOrDummy);
  const size_t count = lookup ? thetas.size() : size_t(texels);
  output_ = Buffer::create(std::max<size_t>(count, 1) * sizeof(glm::vec4));
  const GLuint p = lobeNormProgram_.id();
  setUniform(p, "texels", static_cast<uint32_t>(texels));
  setUniform(p, "count", static_cast<uint32_t>(thetas.size()));
  setUniform(p, "lookup", lookup ? 1u : 0u);
  input.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_BCSDF_INPUT);
  tableBuffer.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_LOBE_NORM_TABLE);
  output_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_BCSDF_OUTPUT);
  dispatch(p, count, "bcsdf_lobe_norm");
  const std::vector<glm::vec3> raw = readResults(count);
  std::vector<glm::vec2> out(count);
  for (size_t i = 0; i < count; ++i) out[i] = glm::vec2(raw[i]);
  return out;
}

std::vector<glm::vec2> BcsdfGpu::bakeLobeNormTable(const FabricParams& fabric, int texels) {
  return runLobeNorm(fabric, {}, {}, texels, false);
}

std::vector<glm::vec2> BcsdfGpu::lookupLobeNorm(const FabricParams& fabric, std::span<const glm::vec2> table,
                                                std::span<const float> thetas) {
  return runLobeNorm(fabric, table, thetas, int(table.size()), true);
}

}  // namespace ft
