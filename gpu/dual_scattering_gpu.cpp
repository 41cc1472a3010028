#include "gpu/dual_scattering_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "gpu/compute_dispatch.h"
#include "gpu/fabric_request_buffer.h"
#include "gpu/shader_library.h"

namespace ft {

DualScatteringGpu::DualScatteringGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  bakeProgram_ = Program(buildProgram({"shaders/dual_scattering_bake.comp.glsl"}, defines));
  evalProgram_ = Program(buildProgram({"shaders/dual_scattering_eval.comp.glsl"}, defines));
}

DsTableGpu DualScatteringGpu::bakeTable(const FabricParams& fabric, int texels, int steps) {
  if (texels < 2 || steps < 1 || steps >= 65536)
    throw std::invalid_argument(fmt::format("DualScatteringGpu: {} texels, {} steps", texels, steps));
  const Buffer input = fabricRequestBuffer(fabric, {});
  const size_t per = FT_DS_ROWS + 4;
  const Buffer output = Buffer::create(size_t(texels) * per * sizeof(glm::vec4));
  const GLuint p = bakeProgram_.id();
  setUniform(p, "texels", static_cast<uint32_t>(texels));
  setUniform(p, "steps", static_cast<uint32_t>(steps));
  input.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_DS_INPUT);
  output.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_DS_OUTPUT);
  dispatchFlat(p, size_t(texels), FT_WG_DS, maxGroupsY_, "dual_scattering_bake");
  const std::vector<glm::vec4> raw = readBuffer<glm::vec4>(output.id(), size_t(texels) * per);
  DsTableGpu out;
  for (size_t k = 0; k < size_t(texels); ++k) {
    const glm::vec4* v = raw.data() + k * per;
    out.rows.insert(out.rows.end(), v, v + FT_DS_ROWS);
    out.aFR.push_back(glm::vec3(v[FT_DS_ROWS]));
    out.aFTT.push_back(glm::vec3(v[FT_DS_ROWS + 1]));
    out.aBR.push_back(glm::vec3(v[FT_DS_ROWS + 2]));
    out.aBTT.push_back(glm::vec3(v[FT_DS_ROWS + 3]));
  }
  return out;
}

std::vector<DsFrame> DualScatteringGpu::evaluate(const FabricParams& fabric, std::span<const glm::vec4> rows,
                                                 std::span<const DsEvalRequest> requests) {
  if (rows.size() < 2 * FT_DS_ROWS || rows.size() % FT_DS_ROWS != 0)
    throw std::invalid_argument("DualScatteringGpu::evaluate: not a table of >= 2 texels");
  std::vector<glm::vec4> packed(2 * requests.size());
  for (size_t i = 0; i < requests.size(); ++i) {
    const DsEvalRequest& q = requests[i];
    packed[2 * i] = glm::vec4(q.thetaI, q.thetaO, q.phi, 0.0f);
    packed[2 * i + 1] = glm::vec4(q.visibility, q.fibers, 0.0f, 0.0f);
  }
  const Buffer input = fabricRequestBuffer(fabric, packed);
  const Buffer table = Buffer::fromVector(std::vector<glm::vec4>(rows.begin(), rows.end()));
  const Buffer output = Buffer::create(std::max<size_t>(requests.size(), 1) * 6 * sizeof(glm::vec4));
  const GLuint p = evalProgram_.id();
  setUniform(p, "requestCount", static_cast<uint32_t>(requests.size()));
  setUniform(p, "texels", static_cast<uint32_t>(rows.size() / FT_DS_ROWS));
  input.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_DS_INPUT);
  table.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_DS_TABLE);
  output.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_DS_OUTPUT);
  dispatchFlat(p, requests.size(), FT_WG_DS, maxGroupsY_, "dual_scattering_eval");
  const std::vector<glm::vec4> raw = readBuffer<glm::vec4>(output.id(), requests.size() * 6);
  std::vector<DsFrame> out(requests.size());
  for (size_t i = 0; i < requests.size(); ++i) {
    const glm::vec4* v = raw.data() + 6 * i;
    out[i].value = glm::vec3(v[0]);
    out[i].backDirect = glm::vec3(v[1]);
    out[i].backScattered = glm::vec3(v[2]);
    out[i].forwardScattered = glm::vec3(v[3]);
    out[i].transmittance = glm::vec3(v[4]);
    out[i].forwardVariance = glm::vec3(v[5]);
  }
  return out;
}

}  // namespace ft
