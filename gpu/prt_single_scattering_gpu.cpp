#include "gpu/prt_single_scattering_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {

PrtSingleScatteringGpu::PrtSingleScatteringGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &maxUboBindings_);
  if (maxUboBindings_ <= FT_UBO_PRT_SS)
    throw std::runtime_error(fmt::format("PrtSingleScatteringGpu: UBO slot {} but the driver has {} bindings",
                                         FT_UBO_PRT_SS, maxUboBindings_));
  program_ = Program(buildProgram({"shaders/prt_single_scattering.comp.glsl"}, defines));
}

Buffer PrtSingleScatteringGpu::params(std::span<const FabricParams> fabrics, uint32_t mode, uint32_t count, int axes,
                                      float lambdaSvf) {
  if (fabrics.empty() || fabrics.size() > FT_PRT_SS_MAX_FABRICS)
    throw std::invalid_argument(fmt::format("PrtSingleScatteringGpu: {} fabrics", fabrics.size()));
  PrtSsParams p{};
  std::copy(fabrics.begin(), fabrics.end(), p.fabrics);
  p.count = count;
  p.mode = mode;
  p.fabricCount = uint32_t(fabrics.size());
  p.axes = uint32_t(axes);
  p.lambdaSvf = lambdaSvf;
  p.tableSize = FT_PRT_SS_TABLE_SIZE;
  Buffer u = Buffer::create(sizeof(PrtSsParams), &p);
  u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_SS);
  return u;
}

std::vector<float> PrtSingleScatteringGpu::bakeTable(std::span<const FabricParams> fabrics) {
  const size_t n = 2 * fabrics.size() * FT_PRT_SS_TABLE_SIZE;
  const Buffer u = params(fabrics, 0, uint32_t(n), 1, FT_SVF_LAMBDA);
  const Buffer table = Buffer::create(n * 4);
  table.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_SS_TABLE);
  const Buffer unused = bindUnusedStorageBlocks({FT_SSBO_PRT_REQUESTS, FT_SSBO_PRT_RESULTS, FT_SSBO_SVF_WEIGHTS});
  dispatchFlat(program_.id(), n, FT_WG_PRT_SS, maxGroupsY_, "prt_single_scattering (table)");
  return readBuffer<float>(table.id(), n);
}

std::vector<glm::vec4> PrtSingleScatteringGpu::evaluate(std::span<const FabricParams> fabrics,
                                                        std::span<const float> table,
                                                        std::span<const PrtSsRequest> requests,
                                                        std::span<const float> weights, int axes, float lambdaSvf) {
  if (table.size() != 2 * fabrics.size() * FT_PRT_SS_TABLE_SIZE || axes < 1 || axes > FT_SVF_MAX_AXES ||
      weights.size() % size_t(axes) != 0)
    throw std::invalid_argument(fmt::format("PrtSingleScatteringGpu::evaluate: table {} for {} fabrics, {} weights, "
                                            "{} axes",
                                            table.size(), fabrics.size(), weights.size(), axes));
  const Buffer u = params(fabrics, 1, uint32_t(requests.size()), axes, lambdaSvf);
  const Buffer t = Buffer::create(table.size() * 4, table.data());
  const Buffer q = Buffer::create(std::max<size_t>(1, requests.size()) * sizeof(PrtSsRequest), requests.data());
  const Buffer w = Buffer::create(std::max<size_t>(1, weights.size()) * 4, weights.data());
  const Buffer out = Buffer::create(std::max<size_t>(1, requests.size()) * sizeof(glm::vec4));
  t.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_SS_TABLE);
  q.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_REQUESTS);
  w.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_WEIGHTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
  dispatchFlat(program_.id(), requests.size(), FT_WG_PRT_SS, maxGroupsY_, "prt_single_scattering (evaluate)");
  return readBuffer<glm::vec4>(out.id(), requests.size());
}

}  // namespace ft
