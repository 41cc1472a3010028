// segment_visibility.h — the CPU reference of the segment visibility function
// of Khungurn et al. 2017 (004) §4.1 (common/segment_visibility.h for the
// conventions; docs/segment-visibility.md):
//   * SvfScene: the tiled exemplar's segments as Embree round linear curves;
//     visibilityImage casts one ray per pixel centre from μ_k that ignores
//     every segment of k's own fiber (004 §4.1: "does not hit any fiber other
//     than the one segment k is a part of" — read as: the fiber that segment
//     k is a part of [F]);
//   * svfSsdfCpu: the SSDF from a binary image (boundary list);
//   * svfWeightsCpu: the Voronoi weights of the sum of SGs;
//   * svfPcaCpu: PCA of all SSDFs (Eigen, double), 48 components by default.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "reference/exemplar.h"

namespace ft {

// Planted fault svf-own-fiber-occludes (validation/faults.def): the ray is
// excused only from its own segment, not from the rest of its fiber.
inline bool ftFaultSvfOwnFiberOccludes = false;
#define FT_FAULT_SVF_OWN_FIBER_OCCLUDES_ON ::ft::ftFaultSvfOwnFiberOccludes

class SvfScene {
 public:
  // Throws std::runtime_error when Embree fails, InputError for a segment of
  // zero length, non-finite coordinates or radius ≤ 0 (naming its index).
  explicit SvfScene(std::span<const ExemplarSegment> segments);
  ~SvfScene();
  SvfScene(SvfScene&&) noexcept;
  SvfScene& operator=(SvfScene&&) noexcept;
  size_t segmentCount() const;

  // The binary W × H image (1 = visible, pixel y·W + x) of rays from
  // `origin` that ignore fiber `ownFiber` (and, whatever the fiber, segment
  // `ownSegment`). Serial: callers parallelise over segments.
  std::vector<uint8_t> visibilityImage(glm::vec3 origin, uint32_t ownFiber, uint32_t ownSegment, int width,
                                       int height) const;

  // The nearest hit of o + t d, t ∈ [0, tFar], on any segment (no fiber
  // excused): (segment index, t), or (−1, tFar) on a miss. Thread-safe: the
  // exemplar volume's truth (reference/exemplar_volume.h) calls it per pixel.
  std::pair<int64_t, float> firstHit(glm::vec3 origin, glm::vec3 direction, float tFar) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

struct SvfSettings {
  int width = 64, height = 64;  // the image (004: 128 × 128); W, H even
  int axes = 48;                // Q (004 §4.1)
  float lambda = 128.0f;        // λ_svf
  uint32_t seed = 1;            // key of R_k
};
// Throws InputError naming the option (--width/--height/--axes/--lambda).
void checkSvfSettings(const SvfSettings& s);

// Everything of one segment k of the block: its image (from the centre
// copy of the tiling), SSDF, R_k angle and weights.
struct SvfSegment {
  std::vector<uint8_t> image;
  std::vector<float> ssdf;
  float angle = 0.0f;
  std::vector<float> weights;
};
// `scene` built from tileExemplar(block, tiles); k indexes block.segments.
SvfSegment svfSegmentCpu(const SvfScene& scene, const Exemplar& block, int tiles, uint32_t k, const SvfSettings& s);

// SSDF per pixel (radians, + visible; ±π when the image has one value).
std::vector<float> svfSsdfCpu(std::span<const uint8_t> image, int width, int height);

// Index of the nearest axis of every z > 0 pixel (rows < H/2), R_k = `angle`.
std::vector<int32_t> svfNearestAxesCpu(int width, int height, int axes, float angle);
// w_q = Σ solid angle of the visible z > 0 pixels nearest to ξ_q, summed in
// pixel order in float (as the GPU does).
std::vector<float> svfWeightsCpu(std::span<const uint8_t> image, int width, int height, int axes, float angle);
// V^ssg at every pixel centre.
std::vector<float> svfSgDecodeCpu(std::span<const float> weights, float angle, float lambda, int width, int height);

// PCA of `rows` SSDFs of `pixels` values each (row-major), centred on the
// mean: the top `components` principal directions (unit, sign: largest |entry|
// positive), the coefficients of every row, and the spectrum. Deterministic
// for a given input. components is clamped to min(rows, pixels).
struct SvfPca {
  int pixels = 0, components = 0;
  std::vector<double> mean;          // pixels
  std::vector<double> basis;         // components × pixels
  std::vector<double> coefficients;  // rows × components
  std::vector<double> eigenvalues;   // components, descending (variance × rows)
  double totalVariance = 0.0;        // Σ of all eigenvalues (the trace)
};
SvfPca svfPcaCpu(std::span<const float> ssdf, size_t rows, int pixels, int components);
// Row k reconstructed from its first `use` components (≤ pca.components).
std::vector<double> svfPcaReconstruct(const SvfPca& pca, size_t row, int use);

}  // namespace ft
