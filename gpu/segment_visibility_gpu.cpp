#include "gpu/segment_visibility_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <initializer_list>
#include <stdexcept>

#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {
namespace {

size_t imageCount(const SvfGpuBatch& b) {
  const size_t P = size_t(b.width) * size_t(b.height);
  // W·H ≤ 16,384: pass 0 scans every pixel of an image (llvmpipe's loop limit, docs/llvmpipe-notes.md).
  if (b.width < 4 || b.height < 4 || b.width % 2 || b.height % 2 || P > 16384 || b.axes < 1 ||
      b.axes > FT_SVF_MAX_AXES || b.images.size() % P != 0)
    throw std::invalid_argument(fmt::format("SegmentVisibilityGpu: {} × {} images ({} bytes), {} axes", b.width,
                                            b.height, b.images.size(), b.axes));
  return b.images.size() / P;
}

}  // namespace

SegmentVisibilityGpu::SegmentVisibilityGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  program_ = Program(buildProgram({"shaders/segment_visibility.comp.glsl"}, defines));
}

Buffer SegmentVisibilityGpu::params(const SvfGpuBatch& b, uint32_t mode, uint32_t components) {
  SvfParams p{};
  p.width = uint32_t(b.width);
  p.height = uint32_t(b.height);
  p.axes = uint32_t(b.axes);
  p.segments = uint32_t(imageCount(b));
  p.seed = b.seed;
  p.components = components;
  p.firstSegment = b.firstSegment;
  p.mode = mode;
  p.lambda = b.lambda;
  Buffer u = Buffer::create(sizeof(SvfParams), &p);
  u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_SVF);
  return u;
}

SvfGpuResult SegmentVisibilityGpu::run(const SvfGpuBatch& b) {
  const size_t n = imageCount(b), P = size_t(b.width) * size_t(b.height);
  std::vector<uint32_t> img(b.images.begin(), b.images.end());
  const Buffer images = Buffer::create(std::max<size_t>(1, img.size()) * 4, img.data());
  const Buffer ssdf = Buffer::create(std::max<size_t>(1, n * P) * 4);
  const Buffer nearest = Buffer::create(std::max<size_t>(1, n * P / 2) * 4);
  const Buffer weights = Buffer::create(std::max<size_t>(1, n * size_t(b.axes)) * 4);
  images.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_IMAGES);
  ssdf.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_SSDF);
  nearest.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_NEAREST);
  weights.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_WEIGHTS);
  const Buffer unused = bindUnusedStorageBlocks(
      {FT_SSBO_SVF_PCA, FT_SSBO_SVF_DECODE});
  SvfGpuResult r;
  {
    const Buffer u = params(b, 0, 0);
    dispatchFlat(program_.id(), n * P, FT_WG_SVF, maxGroupsY_, "segment_visibility (SSDF)");
  }
  {
    const Buffer u = params(b, 1, 0);
    dispatchFlat(program_.id(), n * P / 2, FT_WG_SVF, maxGroupsY_, "segment_visibility (nearest axis)");
  }
  {
    const Buffer u = params(b, 2, 0);
    dispatchFlat(program_.id(), n * size_t(b.axes), FT_WG_SVF, maxGroupsY_, "segment_visibility (weights)");
  }
  r.ssdf = readBuffer<float>(ssdf.id(), n * P);
  r.nearest = readBuffer<int32_t>(nearest.id(), n * P / 2);
  r.weights = readBuffer<float>(weights.id(), n * size_t(b.axes));
  return r;
}

std::vector<glm::vec2> SegmentVisibilityGpu::decode(const SvfGpuBatch& b, std::span<const float> mean,
                                                    std::span<const float> basis, std::span<const float> coefficients,
                                                    int components, std::span<const float> weights) {
  const size_t n = imageCount(b), P = size_t(b.width) * size_t(b.height);
  if (components < 0 || components > FT_SVF_MAX_AXES || mean.size() != P || basis.size() != size_t(components) * P ||
      coefficients.size() != n * size_t(components) || weights.size() != n * size_t(b.axes))
    throw std::invalid_argument(fmt::format("SegmentVisibilityGpu::decode: mean {}, basis {}, coefficients {}, "
                                            "weights {} for {} images of {} pixels, {} components",
                                            mean.size(), basis.size(), coefficients.size(), weights.size(), n, P,
                                            components));
  const Buffer u = params(b, 3, uint32_t(components));
  const Buffer unused = bindUnusedStorageBlocks({FT_SSBO_SVF_IMAGES, FT_SSBO_SVF_SSDF, FT_SSBO_SVF_NEAREST});
  std::vector<float> packed(mean.begin(), mean.end());
  packed.insert(packed.end(), basis.begin(), basis.end());
  packed.insert(packed.end(), coefficients.begin(), coefficients.end());
  const Buffer pcaBuffer = Buffer::create(packed.size() * 4, packed.data());
  const Buffer w = Buffer::create(std::max<size_t>(1, weights.size()) * 4, weights.data());
  const Buffer out = Buffer::create(std::max<size_t>(1, n * P) * sizeof(glm::vec2));
  pcaBuffer.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_PCA);
  w.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_WEIGHTS);
  out.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SVF_DECODE);
  dispatchFlat(program_.id(), n * P, FT_WG_SVF, maxGroupsY_, "segment_visibility (decode)");
  return readBuffer<glm::vec2>(out.id(), n * P);
}

}  // namespace ft
