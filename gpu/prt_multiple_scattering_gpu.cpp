#include "gpu/prt_multiple_scattering_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <initializer_list>
#include <stdexcept>
#include <utility>

#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {
namespace {

constexpr size_t kMatrix = size_t(3) * FT_SH_COEFFS * FT_SH_COEFFS;

}  // namespace

PrtMultipleScatteringGpu::PrtMultipleScatteringGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]), defines_(defines) {
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &uboBindings_);
  glCheck("glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS)");
  if (uboBindings_ <= FT_UBO_PRT_MS || gl.maxShaderStorageBufferBindings <= FT_SSBO_PRT_MS_TABLES)
    throw std::runtime_error(fmt::format("PrtMultipleScatteringGpu: the driver has {} uniform-buffer and {} storage "
                                         "bindings; UBO {} and SSBO {} are needed",
                                         uboBindings_, gl.maxShaderStorageBufferBindings, FT_UBO_PRT_MS,
                                         FT_SSBO_PRT_MS_TABLES));
  program_ = Program(buildProgram({"shaders/prt_multiple_scattering.comp.glsl"}, defines));
}

Buffer PrtMultipleScatteringGpu::params(uint32_t mode, uint32_t count, uint32_t bands, uint32_t thetaI, uint32_t phi,
                                        uint32_t thetaO, uint32_t lambdas, uint32_t cells, const FabricParams& fabric) {
  PrtMsParams p{};
  p.mode = mode;
  p.bands = bands;
  p.count = count;
  p.thetaINodes = thetaI;
  p.phiNodes = phi;
  p.thetaONodes = thetaO;
  p.lambdaNodes = lambdas;
  p.cells = cells;
  p.fabric = fabric;
  Buffer u = Buffer::create(sizeof(PrtMsParams), &p);
  u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_MS);
  return u;
}

PrtMsGpuTables PrtMultipleScatteringGpu::tables(const FabricParams& fabric, int thetaI, int phiNodes) {
  if (thetaI < 2 || phiNodes < 2 || thetaI > 65535 || phiNodes > 65535)
    throw std::invalid_argument(fmt::format("PrtMultipleScatteringGpu::tables: {} θ_i, {} φ nodes", thetaI, phiNodes));
  PrtMsGpuTables t;
  const size_t nPhi = size_t(2) * size_t(thetaI) * FT_SH_COEFFS;
  const Buffer requests = bindUnusedStorageBlocks({FT_SSBO_PRT_REQUESTS, FT_SSBO_PRT_MS_TRANSFER});
  {
    const Buffer out = Buffer::create(nPhi * 4);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
    const Buffer unused = bindUnusedStorageBlocks({FT_SSBO_PRT_MS_TABLES});
    const Buffer u = params(FT_PRT_MS_PHI, uint32_t(2 * thetaI), 0, uint32_t(thetaI), uint32_t(phiNodes),
                            uint32_t(t.thetaO), uint32_t(t.lambdaNodes), 0, fabric);
    dispatchFlat(program_.id(), size_t(2 * thetaI), FT_WG_PRT_MS, maxGroupsY_, "prt_multiple_scattering (Φ)");
    t.phi = readBuffer<float>(out.id(), nPhi);
  }
  {
    const size_t chunks = (size_t(thetaI) + FT_MS_CS_CHUNK - 1) / FT_MS_CS_CHUNK;
    const size_t partialCount = size_t(t.thetaO) * chunks;
    const Buffer in = Buffer::create(nPhi * 4, t.phi.data());
    in.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_MS_TABLES);
    const Buffer partial = Buffer::create(partialCount * FT_SH_COEFFS * 16);
    partial.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
    {
      const Buffer u = params(FT_PRT_MS_CS, uint32_t(partialCount), 0, uint32_t(thetaI), uint32_t(phiNodes),
                              uint32_t(t.thetaO), uint32_t(t.lambdaNodes), 0, fabric);
      dispatchFlat(program_.id(), partialCount, FT_WG_PRT_MS, maxGroupsY_, "prt_multiple_scattering (C_S partial sums)");
    }
    partial.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_MS_TABLES);
    const Buffer out = Buffer::create(size_t(t.thetaO) * FT_SH_COEFFS * 16);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
    const size_t entries = size_t(t.thetaO) * FT_SH_COEFFS;
    const Buffer u = params(FT_PRT_MS_CS_SUM, uint32_t(entries), 0, uint32_t(thetaI), uint32_t(phiNodes),
                            uint32_t(t.thetaO), uint32_t(t.lambdaNodes), 0, fabric);
    dispatchFlat(program_.id(), entries, FT_WG_PRT_MS, maxGroupsY_, "prt_multiple_scattering (C_S)");
    const std::vector<float> raw = readBuffer<float>(out.id(), entries * 4);
    t.cs.resize(entries * 3);
    for (size_t i = 0; i < entries; ++i)
      for (size_t ch = 0; ch < 3; ++ch) t.cs[i * 3 + ch] = raw[i * 4 + ch];
  }
  {
    const Buffer unused = bindUnusedStorageBlocks({FT_SSBO_PRT_MS_TABLES});
    const Buffer out = Buffer::create(size_t(t.lambdaNodes) * FT_SH_BANDS * 4);
    out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
    const Buffer u = params(FT_PRT_MS_CG, uint32_t(t.lambdaNodes), 0, uint32_t(thetaI), uint32_t(phiNodes),
                            uint32_t(t.thetaO), uint32_t(t.lambdaNodes), 0, fabric);
    dispatchFlat(program_.id(), size_t(t.lambdaNodes), FT_WG_PRT_MS, maxGroupsY_, "prt_multiple_scattering (C_G)");
    t.cg = readBuffer<float>(out.id(), size_t(t.lambdaNodes) * FT_SH_BANDS);
  }
  return t;
}

std::vector<glm::vec3> PrtMultipleScatteringGpu::evaluate(std::span<const PrtMsQuery> queries,
                                                          std::span<const float> transfer, int bands,
                                                          std::span<const float> cs, int thetaO,
                                                          std::span<const float> cg, int lambdaNodes) {
  const size_t cells = transfer.size() / kMatrix;
  if (transfer.size() % kMatrix != 0 || cells == 0 || bands < 1 || bands > FT_SH_BANDS || thetaO < 2 ||
      cs.size() != size_t(thetaO) * FT_SH_COEFFS * 3 || lambdaNodes < 2 || cg.size() != size_t(lambdaNodes) * FT_SH_BANDS)
    throw std::invalid_argument(fmt::format("PrtMultipleScatteringGpu::evaluate: {} transfer values, {} bands, C_S {} "
                                            "({} rows), C_G {} ({} rows)",
                                            transfer.size(), bands, cs.size(), thetaO, cg.size(), lambdaNodes));
  for (size_t i = 0; i < queries.size(); ++i)
    if (queries[i].cell.x >= cells)
      throw std::invalid_argument(fmt::format("PrtMultipleScatteringGpu::evaluate: query {}: cell {} of {}", i,
                                              queries[i].cell.x, cells));
  const std::vector<float> packed = packFrameTables(cs, thetaO, cg);
  const Buffer tablesBuf = Buffer::create(packed.size() * 4, packed.data());
  const Buffer transferBuf = Buffer::create(transfer.size() * 4, transfer.data());
  const Buffer req = Buffer::create(std::max<size_t>(1, queries.size()) * sizeof(PrtMsQuery), queries.data());
  // Results, then 286 floats of rotation scratch per query after 72 floats per query (the shader's layout).
  const Buffer out = Buffer::create(std::max<size_t>(1, queries.size()) * (72 + FT_SH_ROTATION_SIZE) * 4);
  tablesBuf.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_MS_TABLES);
  transferBuf.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_MS_TRANSFER);
  req.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_REQUESTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
  const Buffer u = params(FT_PRT_MS_FRAME, uint32_t(queries.size()), uint32_t(bands), 0, 0, uint32_t(thetaO),
                          uint32_t(lambdaNodes), uint32_t(cells), FabricParams{});
  dispatchFlat(program_.id(), queries.size(), FT_WG_PRT_MS, maxGroupsY_, "prt_multiple_scattering (frame)");
  const std::vector<glm::vec4> raw = readBuffer<glm::vec4>(out.id(), queries.size());
  std::vector<glm::vec3> r(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) r[i] = glm::vec3(raw[i]);
  return r;
}

std::vector<float> PrtMultipleScatteringGpu::packFrameTables(std::span<const float> cs, int thetaO,
                                                             std::span<const float> cg) {
  std::vector<float> packed(size_t(thetaO) * FT_SH_COEFFS * 4, 0.0f);
  for (size_t i = 0; i < size_t(thetaO) * FT_SH_COEFFS && i * 3 + 2 < cs.size(); ++i)
    for (size_t ch = 0; ch < 3; ++ch) packed[i * 4 + ch] = cs[i * 3 + ch];
  packed.insert(packed.end(), cg.begin(), cg.end());
  return packed;
}

std::vector<double> PrtMultipleScatteringGpu::accumulateIirtf(std::span<const PrtMsSample> samples) {
  std::vector<double> a(kMatrix, 0.0);
  if (samples.empty()) return a;
  if (!accumulateProgram_.id())
    accumulateProgram_ = Program(buildProgram({"shaders/prt_ms_accumulate.comp.glsl"}, defines_));
  const size_t n = samples.size(), chunks = (n + FT_MS_ACC_CHUNK - 1) / FT_MS_ACC_CHUNK;
  const size_t entries = size_t(FT_SH_COEFFS) * FT_SH_COEFFS;
  const Buffer in = Buffer::create(n * sizeof(PrtMsSample), samples.data());
  const Buffer ys = Buffer::create(n * 72 * 4);
  in.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_REQUESTS);
  {
    const Buffer unused = bindUnusedStorageBlocks({FT_SSBO_PRT_MS_TABLES});
    PrtMsAccumParams p{};
    p.sizes = glm::uvec4(0u, uint32_t(n), uint32_t(chunks), 0u);
    const Buffer u = Buffer::create(sizeof(p), &p);
    u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_MS);
    ys.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
    dispatchFlat(accumulateProgram_.id(), n, FT_WG_PRT_MS, maxGroupsY_, "prt_ms_accumulate (Y)");
  }
  const Buffer partial = Buffer::create(chunks * entries * 16);
  ys.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_MS_TABLES);
  partial.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
  PrtMsAccumParams p{};
  p.sizes = glm::uvec4(1u, uint32_t(n), uint32_t(chunks), 0u);
  const Buffer u = Buffer::create(sizeof(p), &p);
  u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_MS);
  dispatchFlat(accumulateProgram_.id(), chunks * entries, FT_WG_PRT_MS, maxGroupsY_, "prt_ms_accumulate (sums)");
  const std::vector<float> raw = readBuffer<float>(partial.id(), chunks * entries * 4);
  // 1 / (N p(ω0) p(ω1)) = 2π · 4π / N (004 §4.2c); chunks added in order.
  const double scale = 8.0 * 3.14159265358979323846 * 3.14159265358979323846 / double(n);
  for (size_t c = 0; c < chunks; ++c)
    for (size_t e = 0; e < entries; ++e)
      for (size_t ch = 0; ch < 3; ++ch) a[ch * entries + e] += double(raw[(c * entries + e) * 4 + ch]);
  for (double& v : a) v *= scale;
  return a;
}

std::vector<float> PrtMultipleScatteringGpu::vgloFilter(std::span<const float> v, int width, int height, float texel,
                                                        float sigma) {
  if (width < 1 || height < 1 || v.size() != size_t(width) * size_t(height) || !(texel > 0.0f) || !(sigma > 0.0f))
    throw std::invalid_argument(fmt::format("PrtMultipleScatteringGpu::vgloFilter: {} values for {} × {}, texel {}, σ {}",
                                            v.size(), width, height, texel, sigma));
  if (!vgloProgram_.id()) vgloProgram_ = Program(buildProgram({"shaders/prt_ms_visibility.comp.glsl"}, defines_));
  const size_t n = v.size();
  Buffer a = Buffer::create(n * 4, v.data());
  Buffer b = Buffer::create(n * 4);
  for (uint32_t axis = 0; axis < 2; ++axis) {  // x then y, as the CPU twin
    PrtMsVgloParams p{};
    p.grid = glm::uvec4(uint32_t(width), uint32_t(height), axis, 0u);
    p.sigma = glm::vec4(sigma, texel, 0.0f, 0.0f);
    const Buffer u = Buffer::create(sizeof(p), &p);
    u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_MS);
    a.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_MS_TABLES);
    b.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
    dispatchFlat(vgloProgram_.id(), n, FT_WG_PRT_MS, maxGroupsY_, "prt_ms_visibility (V̄_glo)");
    std::swap(a, b);
  }
  return readBuffer<float>(a.id(), n);
}

std::vector<float> PrtMultipleScatteringGpu::shProbe(std::span<const glm::vec3> dirs, std::span<const glm::vec3> rx,
                                                     std::span<const glm::vec3> ry) {
  if (rx.size() != dirs.size() || ry.size() != dirs.size())
    throw std::invalid_argument("PrtMultipleScatteringGpu::shProbe: sizes");
  std::vector<PrtMsQuery> q(dirs.size());
  for (size_t i = 0; i < dirs.size(); ++i) {
    q[i].wo = glm::vec4(dirs[i], 0.0f);
    q[i].tangent = glm::vec4(rx[i], 0.0f);
    q[i].light = glm::vec4(ry[i], 0.0f);
    q[i].cell = glm::uvec4(0u);
  }
  const Buffer req = Buffer::create(std::max<size_t>(1, q.size()) * sizeof(PrtMsQuery), q.data());
  const Buffer out = Buffer::create(std::max<size_t>(1, q.size()) * (72 + FT_SH_ROTATION_SIZE) * 4);
  req.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_REQUESTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
  const Buffer unused = bindUnusedStorageBlocks({FT_SSBO_PRT_MS_TRANSFER, FT_SSBO_PRT_MS_TABLES});
  const Buffer u = params(FT_PRT_MS_SH_PROBE, uint32_t(q.size()), FT_SH_BANDS, 0, 0, 0, 0, 0, FabricParams{});
  dispatchFlat(program_.id(), q.size(), FT_WG_PRT_MS, maxGroupsY_, "prt_multiple_scattering (SH probe)");
  return readBuffer<float>(out.id(), q.size() * 72);
}

}  // namespace ft
