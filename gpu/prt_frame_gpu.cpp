// prt_frame_gpu.cpp — gpu/prt_frame_gpu.h.
#include "gpu/prt_frame_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {

PrtFrameGpu::PrtFrameGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  GLint ubos = 0, ssbos = 0;
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &ubos);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &ssbos);
  if (ubos <= FT_UBO_PRT_FRAME || ssbos <= FT_SSBO_SVF_SSDF)
    throw std::runtime_error(fmt::format("PrtFrameGpu: UBO slot {} and SSBO slot {} but the driver has {} and {} bindings",
                                         FT_UBO_PRT_FRAME, FT_SSBO_SVF_SSDF, ubos, ssbos));
  program_ = Program(buildProgram({"shaders/prt_frame.comp.glsl"}, defines));
}

std::vector<PrtFramePixel> PrtFrameGpu::requests(const VolParams& rays, std::span<const VolHit> gbuffer,
                                                 std::span<const VolSegment> segments, std::span<const float> ssdf,
                                                 int svfSize, std::span<const glm::vec4> segmentData, glm::vec4 light) {
  const size_t n2 = size_t(std::max(0, svfSize)) * size_t(std::max(0, svfSize));
  if (gbuffer.size() != size_t(rays.ray.x) * size_t(rays.ray.y) || segments.empty() || svfSize < 1 ||
      ssdf.size() != segments.size() * n2 || segmentData.size() != segments.size())
    throw std::invalid_argument(fmt::format("PrtFrameGpu::requests: {} texels for {}x{}, {} segments, {} SSDF values "
                                            "({}²), {} segment records",
                                            gbuffer.size(), rays.ray.x, rays.ray.y, segments.size(), ssdf.size(),
                                            svfSize, segmentData.size()));
  PrtFrameParams p{};
  p.light = light;
  p.sizes = uvec4(uint32_t(gbuffer.size()), uint32_t(svfSize), 0u, uint32_t(segments.size()));
  const Buffer u = Buffer::create(sizeof(PrtFrameParams), &p);
  const Buffer v = Buffer::create(sizeof(VolParams), &rays);
  const Buffer g = Buffer::create(std::max<size_t>(1, gbuffer.size()) * sizeof(VolHit), gbuffer.data());
  const Buffer s = Buffer::create(segments.size() * sizeof(VolSegment), segments.data());
  const Buffer d = Buffer::create(ssdf.size() * 4, ssdf.data());
  const Buffer sd = Buffer::create(segmentData.size() * sizeof(glm::vec4), segmentData.data());
  const Buffer out = Buffer::create(std::max<size_t>(1, gbuffer.size()) * sizeof(PrtFramePixel));
  u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_FRAME);
  v.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_VOL);
  g.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
  s.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_VOL_SEGMENTS);
  d.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_SSDF);
  sd.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_REQUESTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_FRAME);
  dispatchFlat(program_.id(), gbuffer.size(), FT_WG_PRT_FRAME, maxGroupsY_, "prt_frame (requests)");
  return readBuffer<PrtFramePixel>(out.id(), gbuffer.size());
}

std::vector<PrtFramePixel> PrtFrameGpu::compose(std::span<const PrtFramePixel> pixels) {
  PrtFrameParams p{};
  p.sizes = uvec4(uint32_t(pixels.size()), 1u, 1u, 1u);
  const Buffer u = Buffer::create(sizeof(PrtFrameParams), &p);
  const Buffer unusedUbo = Buffer::create(64);  // the volume's parameter block, declared but not read here
  const Buffer io = Buffer::create(std::max<size_t>(1, pixels.size()) * sizeof(PrtFramePixel), pixels.data());
  u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_FRAME);
  unusedUbo.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_VOL);
  const Buffer unused = bindUnusedStorageBlocks(
      {FT_SSBO_PRT_RESULTS, FT_SSBO_PRT_VOL_SEGMENTS, FT_SSBO_SVF_SSDF, FT_SSBO_PRT_REQUESTS});
  io.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_FRAME);
  dispatchFlat(program_.id(), pixels.size(), FT_WG_PRT_FRAME, maxGroupsY_, "prt_frame (compose)");
  return readBuffer<PrtFramePixel>(io.id(), pixels.size());
}

std::vector<PrtFramePixel> PrtFrameGpu::render(const PrtFrameGpuInputs& in, std::span<const VolHit> gbuffer,
                                               PrtSingleScatteringGpu& single, PrtMultipleScatteringGpu& multi) {
  if (in.msTables == nullptr) throw std::invalid_argument("PrtFrameGpu::render: no C_S / C_G tables");
  std::vector<PrtFramePixel> px = requests(in.rays, gbuffer, in.segments, in.ssdf, in.svfSize, in.segmentData, in.light);
  std::vector<size_t> covered;
  std::vector<PrtSsRequest> ss;
  std::vector<PrtMsQuery> ms;
  for (size_t i = 0; i < px.size(); ++i)
    if (px[i].total.w > 0.5f) {
      covered.push_back(i);
      ss.push_back(PrtSsRequest{px[i].ssTangent, px[i].ssOutgoing, px[i].ssLight, px[i].ssSegment});
      ms.push_back(PrtMsQuery{px[i].msWo, px[i].msTangent, px[i].msLight, px[i].msCell});
    }
  const std::vector<glm::vec4> ls =
      single.evaluate(std::span<const FabricParams>(&in.fabric, 1), in.ssTable, ss, in.weights, in.axes, in.lambdaSvf);
  const PrtMsGpuTables& t = *in.msTables;
  const std::vector<glm::vec3> lm = multi.evaluate(ms, in.transfer, in.bands, t.cs, t.thetaO, t.cg, t.lambdaNodes);
  for (size_t j = 0; j < covered.size(); ++j) {
    px[covered[j]].single = ls[j];
    px[covered[j]].multi = glm::vec4(lm[j], 0.0f);
  }
  return compose(px);
}

}  // namespace ft
