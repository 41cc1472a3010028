// prt_frame_gpu.h — the GPU twin of the PRT frame's per-pixel composition of
// 004 §5 (common/prt_frame.h, prt_frame.comp.glsl; docs/prt-frame.md): from
// the exemplar volume's GPU G-buffer, the per-pixel requests (mode 0), then —
// after the single- and multiple-scattering evaluators of
// gpu/prt_single_scattering_gpu.h and gpu/prt_multiple_scattering_gpu.h have
// filled `single` and `multi` — the composition (mode 1). Every call uploads,
// dispatches and reads back (PrtFrameGpu, the twin of the arithmetic).
// PrtFrameRendererGpu is the frame renderer: data uploaded once, then per
// frame the volume's G-buffer and four passes (prt_frame_gpu_pixels.comp.glsl,
// prt_frame_gpu.comp.glsl) on the GPU, one read-back of the image.
#pragma once
#include <epoxy/gl.h>

#include <span>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/exemplar_volume.h"
#include "common/prt_frame.h"
#include "gpu/gl_context.h"
#include "gpu/exemplar_volume_gpu.h"
#include "gpu/gl_objects.h"
#include "gpu/prt_multiple_scattering_gpu.h"
#include "gpu/prt_single_scattering_gpu.h"

namespace ft {

// Everything a frame reads besides the G-buffer (spans must outlive the call).
struct PrtFrameGpuInputs {
  VolParams rays{};                       // the G-buffer's camera
  std::span<const VolSegment> segments;   // the block's
  std::span<const float> ssdf;            // [segment][n²]
  int svfSize = 0;
  std::span<const glm::vec4> segmentData; // (R_k angle, cell, 0, 0)
  std::span<const float> weights;         // [segment][axes]
  int axes = 0;
  float lambdaSvf = 0.0f;
  FabricParams fabric{};
  std::span<const float> ssTable;         // PrtSingleScatteringGpu::bakeTable
  std::span<const float> transfer;        // [cell][3 · 36 · 36]
  int bands = 0;
  const PrtMsGpuTables* msTables = nullptr;  // PrtMultipleScatteringGpu::tables
  glm::vec4 light{0.0f};                  // xyz, λ
};

// The inputs from a scene's data (reference/prt_frame.h PrtFrameData: gpu/ does not include reference/).
template <class Data>
PrtFrameGpuInputs prtFrameGpuInputs(const Data& d, const VolParams& rays, std::span<const float> ssTable,
                                    const PrtMsGpuTables& msTables, int bands, glm::vec4 light) {
  PrtFrameGpuInputs in;
  in.rays = rays;
  in.segments = d.segments;
  in.ssdf = d.ssdf;
  in.svfSize = d.svfSize;
  in.segmentData = d.segmentData;
  in.weights = d.weights;
  in.axes = d.axes;
  in.lambdaSvf = d.lambdaSvf;
  in.fabric = d.fabric;
  in.ssTable = ssTable;
  in.transfer = d.transfer;
  in.bands = bands;
  in.msTables = &msTables;
  in.light = light;
  return in;
}

class PrtFrameGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, validation/faults.h).
  // std::runtime_error when the driver lacks FT_UBO_PRT_FRAME or FT_SSBO_PRT_FRAME bindings.
  explicit PrtFrameGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});
  // Mode 0: one record per G-buffer texel (rays: the VolParams of the G-buffer's camera);
  // ssdf = [segment][n²], segmentData = per segment (R_k angle, cell, 0, 0).
  // std::invalid_argument for inconsistent sizes.
  std::vector<PrtFramePixel> requests(const VolParams& rays, std::span<const VolHit> gbuffer,
                                      std::span<const VolSegment> segments, std::span<const float> ssdf, int svfSize,
                                      std::span<const glm::vec4> segmentData, glm::vec4 light);
  // Mode 1: total = the composition of each record's single and multi.
  std::vector<PrtFramePixel> compose(std::span<const PrtFramePixel> pixels);
  // The frame: requests, the evaluators on the covered pixels, the composition.
  std::vector<PrtFramePixel> render(const PrtFrameGpuInputs& in, std::span<const VolHit> gbuffer,
                                    PrtSingleScatteringGpu& single, PrtMultipleScatteringGpu& multi);

 private:
  int maxGroupsY_ = 65535;
  Program program_;
};

// A frame of PrtFrameRendererGpu, row-major, row 0 at the top: rgb, w = 1 where
// the G-buffer has a segment (0: a miss). single and multi only when asked.
struct PrtFrameGpuImage {
  int width = 0, height = 0;
  std::vector<glm::vec4> total, single, multi;
};

// The single-pass GPU frame (docs/prt-frame.md "The GPU frame"): upload() puts
// the scene's segments, SSDFs, SG weights, 𝒢 table, A_C matrices and C_S/C_G
// tables in GPU buffers once; render() then runs, with no read-back before the
// image: the volume's G-buffer (ExemplarVolumeGpu::sampleNoReadback), the
// segments it hits marked, c_T per cell, L^single and L̃^multi per marked
// segment (the orthographic camera's one ω_o), the composition per pixel
// (prt_frame_gpu_pixels.comp.glsl, prt_frame_gpu.comp.glsl). Slots: UBO 24
// FT_UBO_PRT_FRAME_GPU (new), the frame buffer at FT_SSBO_PRT_FRAME, the
// others as the evaluators and the twin bind them.
class PrtFrameRendererGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, validation/faults.h).
  // std::runtime_error when the driver lacks the bindings or storage blocks.
  explicit PrtFrameRendererGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});
  // The scene's data and tables (in.rays and in.light are per frame: render's).
  // Again after bakes change the data. std::invalid_argument for inconsistent sizes.
  void upload(const PrtFrameGpuInputs& in);
  // One frame of the built `volume` seen by `rays` (orthographic: std::invalid_argument
  // for a pinhole, whose ω_o varies per pixel) under `light` (xyz, λ; 0 directional).
  // parts: also the single- and multiple-scattering images. std::logic_error before upload().
  PrtFrameGpuImage render(ExemplarVolumeGpu& volume, const VolParams& rays, glm::vec4 light, bool parts = false);

 private:
  int maxGroupsY_ = 65535;
  Program pixels_, shading_;
  Buffer segments_, ssdf_, segmentData_, weights_, ssTable_, transfer_, msTables_, frame_;
  size_t segmentCount_ = 0, cells_ = 0;
  int svfSize_ = 0, axes_ = 0, bands_ = 0, thetaO_ = 0, lambdaNodes_ = 0;
  float lambdaSvf_ = 0.0f;
  FabricParams fabric_{};
};

}  // namespace ft
