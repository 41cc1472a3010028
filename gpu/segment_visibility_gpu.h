// segment_visibility_gpu.h — the GPU twin of the segment visibility function
// of 004 §4.1 (common/segment_visibility.h, segment_visibility.comp.glsl;
// notes-appearance §5.5 steps 2–4): from given binary visibility images (the
// CPU's rays), the SSDF, the nearest-axis cells and Voronoi weights of the sum
// of SGs, and the per-pixel decode of both representations. The visibility
// rays themselves stay on the CPU (Embree) [F: docs/segment-visibility.md].
// Every call uploads, dispatches and reads back.
#pragma once
#include <epoxy/gl.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/segment_visibility.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

struct SvfGpuBatch {
  int width = 0, height = 0, axes = 48;
  float lambda = FT_SVF_LAMBDA;
  uint32_t seed = 1;
  uint32_t firstSegment = 0;         // segment id of image 0 (keys R_k)
  std::vector<uint8_t> images;       // images × W·H, 1 = visible
};

struct SvfGpuResult {
  std::vector<float> ssdf;           // images × W·H
  std::vector<int32_t> nearest;      // images × W·H/2
  std::vector<float> weights;        // images × Q
};

class SegmentVisibilityGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, validation/faults.h).
  explicit SegmentVisibilityGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});

  // Passes 0–2: SSDF, nearest axes, weights.
  SvfGpuResult run(const SvfGpuBatch& batch);
  // Pass 3: per pixel (PCA reconstruction, V^ssg) from the given mean (W·H),
  // basis (C × W·H), coefficients (images × C) and weights (images × Q).
  std::vector<glm::vec2> decode(const SvfGpuBatch& batch, std::span<const float> mean, std::span<const float> basis,
                                std::span<const float> coefficients, int components, std::span<const float> weights);

 private:
  Buffer params(const SvfGpuBatch& b, uint32_t mode, uint32_t components);
  int maxGroupsY_ = 65535;
  Program program_;
};

}  // namespace ft
