#include "gpu/ds_correction_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "common/constants.h"
#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {

DsCorrectionGpu::DsCorrectionGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]),
      program_(buildProgram({"shaders/ds_correction_eval.comp.glsl"}, defines)) {}

std::vector<glm::vec3> DsCorrectionGpu::evaluate(const DsCorrectionLayout& l, std::span<const glm::vec4> xiM,
                                                 std::span<const glm::vec4> xiN, std::span<const glm::vec4> psiM,
                                                 std::span<const glm::vec4> psiN, std::span<const glm::vec4> queries) {
  const size_t uv = size_t(l.size.x) * l.size.y, nm = uv * l.size.z, nn = uv * l.size.w;
  if (uv == 0 || l.size.z == 0 || l.size.w == 0 || xiM.size() != nm || psiM.size() != nm || xiN.size() != nn ||
      psiN.size() != nn)
    throw std::invalid_argument(fmt::format("DsCorrectionGpu::evaluate: textures of {}, {}, {}, {} texels for a "
                                            "{}x{} texture with {} and {} angles",
                                            xiM.size(), xiN.size(), psiM.size(), psiN.size(), l.size.x, l.size.y,
                                            l.size.z, l.size.w));
  const Buffer block = Buffer::create(sizeof(l), &l);
  block.bindBase(GL_UNIFORM_BUFFER, FT_UBO_XI);
  // The lookup reads logarithms (ftXiEncode, common/ds_correction.h).
  const auto encoded = [](std::span<const glm::vec4> t) {
    std::vector<glm::vec4> e(t.size());
    for (size_t k = 0; k < t.size(); ++k) e[k] = glm::vec4(ftXiEncode(glm::vec3(t[k])), 0.0f);
    return e;
  };
  const Buffer bxm = Buffer::fromVector(encoded(xiM)), bxn = Buffer::fromVector(encoded(xiN));
  const Buffer bpm = Buffer::fromVector(encoded(psiM)), bpn = Buffer::fromVector(encoded(psiN));
  bxm.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_XI_M);
  bxn.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_XI_N);
  bpm.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_XI_PSI_M);
  bpn.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_XI_PSI_N);
  const size_t n = std::max<size_t>(queries.size(), 1);
  std::vector<glm::vec4> requests(queries.begin(), queries.end());
  requests.resize(n);
  const Buffer in = Buffer::fromVector(requests);
  const Buffer out = Buffer::create(n * sizeof(glm::vec4));
  in.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_XI_REQUESTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_XI_RESULTS);
  setUniform(program_.id(), "requestCount", static_cast<uint32_t>(queries.size()));
  dispatchFlat(program_.id(), queries.size(), FT_WG_XI, maxGroupsY_, "ds_correction_eval");
  const std::vector<glm::vec4> raw = readBuffer<glm::vec4>(out.id(), queries.size());
  std::vector<glm::vec3> result(queries.size());
  for (size_t q = 0; q < queries.size(); ++q) result[q] = glm::vec3(raw[q]);
  return result;
}

}  // namespace ft
