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

PrtFrameRendererGpu::PrtFrameRendererGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  GLint ubos = 0, blocks = 0;
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &ubos);
  glGetIntegerv(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, &blocks);
  constexpr int kHighestSsbo = FT_SSBO_SVF_WEIGHTS, kBlocks = 8;
  if (ubos <= FT_UBO_PRT_FRAME_GPU || gl.maxShaderStorageBufferBindings <= kHighestSsbo || blocks < kBlocks)
    throw std::runtime_error(fmt::format("PrtFrameRendererGpu: UBO slot {}, SSBO slots up to {} and {} storage blocks "
                                         "per compute shader, but the driver has {} UBO and {} SSBO bindings and {} blocks",
                                         FT_UBO_PRT_FRAME_GPU, kHighestSsbo, kBlocks, ubos,
                                         gl.maxShaderStorageBufferBindings, blocks));
  pixels_ = Program(buildProgram({"shaders/prt_frame_gpu_pixels.comp.glsl"}, defines));
  shading_ = Program(buildProgram({"shaders/prt_frame_gpu.comp.glsl"}, defines));
}

void PrtFrameRendererGpu::upload(const PrtFrameGpuInputs& in) {
  constexpr size_t kMatrix = size_t(3) * FT_SH_COEFFS * FT_SH_COEFFS;
  const size_t n2 = size_t(std::max(0, in.svfSize)) * size_t(std::max(0, in.svfSize));
  const PrtMsGpuTables* t = in.msTables;
  const size_t segs = in.segments.size();
  if (t == nullptr || segs == 0 || in.svfSize < 1 || in.ssdf.size() != segs * n2 || in.segmentData.size() != segs ||
      in.axes < 1 || in.axes > FT_SVF_MAX_AXES || in.weights.size() != segs * size_t(in.axes) ||
      in.ssTable.size() != 2 * FT_PRT_SS_TABLE_SIZE || in.transfer.empty() || in.transfer.size() % kMatrix != 0 ||
      in.bands < 1 || in.bands > FT_SH_BANDS || t->thetaO < 2 || t->cs.size() != size_t(t->thetaO) * FT_SH_COEFFS * 3 ||
      t->lambdaNodes < 2 || t->cg.size() != size_t(t->lambdaNodes) * FT_SH_BANDS)
    throw std::invalid_argument(fmt::format(
        "PrtFrameRendererGpu::upload: {} segments, {} SSDF values ({}²), {} segment records, {} weights ({} axes), "
        "𝒢 table {}, {} transfer values, {} bands, C_S {} ({} rows), C_G {}",
        segs, in.ssdf.size(), in.svfSize, in.segmentData.size(), in.weights.size(), in.axes, in.ssTable.size(),
        in.transfer.size(), in.bands, t ? t->cs.size() : 0, t ? t->thetaO : 0, t ? t->cg.size() : 0));
  const size_t cells = in.transfer.size() / kMatrix;
  for (size_t k = 0; k < segs; ++k)
    if (!(in.segmentData[k].y >= 0.0f) || size_t(in.segmentData[k].y) >= cells)
      throw std::invalid_argument(fmt::format("PrtFrameRendererGpu::upload: segment {}: cell {} of {}", k,
                                              in.segmentData[k].y, cells));
  cells_ = cells;  // nothing changes before the checks have passed
  segmentCount_ = segs;
  svfSize_ = in.svfSize;
  axes_ = in.axes;
  bands_ = in.bands;
  thetaO_ = t->thetaO;
  lambdaNodes_ = t->lambdaNodes;
  lambdaSvf_ = in.lambdaSvf;
  fabric_ = in.fabric;
  segments_ = Buffer::create(segs * sizeof(VolSegment), in.segments.data());
  ssdf_ = Buffer::create(in.ssdf.size() * 4, in.ssdf.data());
  segmentData_ = Buffer::create(segs * sizeof(glm::vec4), in.segmentData.data());
  weights_ = Buffer::create(in.weights.size() * 4, in.weights.data());
  ssTable_ = Buffer::create(in.ssTable.size() * 4, in.ssTable.data());
  transfer_ = Buffer::create(in.transfer.size() * 4, in.transfer.data());
  // C_S as [θ_o][36][4] then C_G (prt_ms_frame.glsl's layout, as PrtMultipleScatteringGpu::evaluate packs it).
  const std::vector<float> packed = PrtMultipleScatteringGpu::packFrameTables(*t);
  msTables_ = Buffer::create(packed.size() * 4, packed.data());
}

PrtFrameGpuImage PrtFrameRendererGpu::render(ExemplarVolumeGpu& volume, const VolParams& rays, glm::vec4 light,
                                             bool parts) {
  if (segmentCount_ == 0) throw std::logic_error("PrtFrameRendererGpu::render before upload");
  if (uint32_t(rays.camPos.w) == FT_VOL_CAMERA_PINHOLE)
    throw std::invalid_argument("PrtFrameRendererGpu::render: a pinhole camera (ω_o per pixel); the frame's camera is "
                                "orthographic");
  if (rays.dims.w != segmentCount_)
    throw std::invalid_argument(fmt::format("PrtFrameRendererGpu::render: the rays' volume has {} segments, the "
                                            "uploaded block {}",
                                            rays.dims.w, segmentCount_));
  const size_t pixels = size_t(rays.ray.x) * size_t(rays.ray.y);
  const Buffer& gbuffer = volume.sampleNoReadback(rays);
  if (gbuffer.size() != pixels * sizeof(VolHit))
    throw std::logic_error(fmt::format("PrtFrameRendererGpu::render: a G-buffer of {} bytes for {} pixels",
                                       gbuffer.size(), pixels));
  gbuffer.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
  const size_t images = parts ? 3 : 1;
  PrtFrameGpuParams p{};
  p.light = light;
  p.sizes = glm::uvec4(uint32_t(pixels), uint32_t(svfSize_), 0u, uint32_t(segmentCount_));
  p.ms = glm::uvec4(uint32_t(cells_), uint32_t(bands_), uint32_t(thetaO_), uint32_t(lambdaNodes_));
  const size_t ct = images * pixels * 4, seg = ct + cells_ * FT_PRT_FRAME_GPU_CT_FLOATS,
               scratch = seg + segmentCount_ * FT_PRT_FRAME_GPU_SEGMENT_FLOATS,
               marks = scratch + segmentCount_ * FT_SH_ROTATION_SIZE, floats = marks + segmentCount_;
  if (floats > size_t(UINT32_MAX))
    throw std::invalid_argument(fmt::format("PrtFrameRendererGpu::render: {} floats of frame buffer", floats));
  p.offsets = glm::uvec4(uint32_t(ct), uint32_t(seg), uint32_t(scratch), uint32_t(marks));
  p.flags = glm::uvec4(parts ? 1u : 0u, 0u, 0u, 0u);
  p.svf = glm::vec4(lambdaSvf_, float(axes_), 0.0f, 0.0f);
  p.fabric = fabric_;
  if (frame_.id() == 0 || frame_.size() != floats * 4) frame_ = Buffer::create(floats * 4);
  const float zero = 0.0f;
  glClearNamedBufferSubData(frame_.id(), GL_R32F, GLintptr(marks * 4), GLsizeiptr(segmentCount_ * 4), GL_RED, GL_FLOAT,
                            &zero);
  const Buffer vol = Buffer::create(sizeof(VolParams), &rays);
  vol.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_VOL);
  segments_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_VOL_SEGMENTS);
  ssdf_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_SSDF);
  segmentData_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_REQUESTS);
  weights_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_WEIGHTS);
  ssTable_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_SS_TABLE);
  transfer_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_MS_TRANSFER);
  msTables_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_MS_TABLES);
  frame_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_FRAME);
  const struct {
    GLuint program;
    uint32_t pass;
    size_t items;
    const char* what;
  } passes[] = {{pixels_.id(), FT_PRT_FRAME_GPU_MARK, pixels, "prt_frame_gpu_pixels (segment marks)"},
                {shading_.id(), FT_PRT_FRAME_GPU_CELLS, cells_, "prt_frame_gpu (c_T per cell)"},
                {shading_.id(), FT_PRT_FRAME_GPU_SEGMENTS, segmentCount_, "prt_frame_gpu (shading per segment)"},
                {pixels_.id(), FT_PRT_FRAME_GPU_PIXELS, pixels, "prt_frame_gpu_pixels (composition per pixel)"}};
  for (const auto& pass : passes) {
    p.sizes.z = pass.pass;
    const Buffer u = Buffer::create(sizeof(PrtFrameGpuParams), &p);
    u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_FRAME_GPU);
    dispatchFlat(pass.program, pass.items, FT_WG_PRT_FRAME, maxGroupsY_, pass.what);
  }
  const std::vector<glm::vec4> all = readBuffer<glm::vec4>(frame_.id(), images * pixels);
  PrtFrameGpuImage im;
  im.width = int(rays.ray.x);
  im.height = int(rays.ray.y);
  im.total.assign(all.begin(), all.begin() + long(pixels));
  if (parts) {
    im.single.assign(all.begin() + long(pixels), all.begin() + long(2 * pixels));
    im.multi.assign(all.begin() + long(2 * pixels), all.end());
  }
  return im;
}

}  // namespace ft
