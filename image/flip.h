// flip.h — FLIP, the perceptual error map of NVIDIA's reference tool:
// LDR-FLIP (Andersson et al. 2020, "FLIP: A Difference Evaluator for
// Alternating Images", PACMCGIT 3(2)) and HDR-FLIP (Andersson et al. 2021,
// "Visualizing Errors in Rendered High Dynamic Range Images", Eurographics
// short papers). Written from a restatement of the tool's algorithm (NVlabs/flip
// v1.6; docs/flip.md), in float32 as the tool computes, so the pooled numbers
// agree with the tool's six printed decimals (docs/flip.md: measured agreement).
//
// Input checks throw std::invalid_argument naming "reference" or "test", the
// pixel, the channel and the value: sizes must match and be non-empty, ppd in
// (0, 1000]. Non-finite rgb values are never clamped or mapped into a result:
// the call throws with their count and the first one (the harness counts
// non-finite pixels as failures; compareImages() of image_metrics.h counts
// them without throwing). Alpha is ignored (the tool drops it, it does not
// composite).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "image/image.h"

namespace ft {

// Tone curves HDR-FLIP maps each exposure with.
enum class FlipToneMapper { Aces, Hable, Reinhard };

struct FlipOptions {
  // Pixels per degree of visual angle: 0.7 m from a 0.7 m wide 3840-pixel
  // display, 3840·π/180. Every kernel depends on it: 67 and 67.0206 differ in
  // the sixth decimal of the mean.
  double ppd = 67.0206433;
  // HDR-FLIP only. An exposure left unset is derived from the reference
  // (start: its brightest luminance maps to 0.85 after tone mapping; stop:
  // its median does); the count defaults to max(2, ceil(stop - start)).
  FlipToneMapper toneMapper = FlipToneMapper::Aces;
  std::optional<float> startExposure, stopExposure;  // stops, start <= stop
  std::optional<int> exposureCount;                  // 2 to 300
  // Pixels pooled into the statistics: empty = all; otherwise one value per
  // pixel (row-major, row 0 at the top), 1 = pooled, 0 = left out. The error
  // map itself is always computed on the whole image (the filters see every
  // pixel); only the pooling is restricted. The span must outlive the call.
  std::span<const uint8_t> mask;
};

// The pooled numbers of an error map, with the tool's definitions.
// count == 0 (a mask of zeros) gives every field 0: a defined, NaN-free
// result that callers recognise by count.
struct FlipPooled {
  size_t count = 0;  // pixels pooled
  // float32 running sum in row-major order / count: the tool's printed mean.
  // It drifts from the exact mean as the sum grows (9e-6 on a 640x480 pair):
  // meanDouble, summed in double, is the one to hold to a threshold.
  float mean = 0.0f;
  double meanDouble = 0.0;
  // Weighted percentiles: the first value, in ascending order, at which the
  // running sum exceeds p × the total (each pixel weighs its own error).
  float weightedQuartile1 = 0.0f, weightedMedian = 0.0f, weightedQuartile3 = 0.0f;
  float min = 0.0f, max = 0.0f;
  // 100 buckets of width 0.01 over [0, 1] (1.0 in the last one).
  std::array<size_t, 100> histogram{};
  // The same percentiles from the histogram with each bucket weighted by its
  // centre, interpolated linearly inside the bucket (not printed by the tool).
  float histogramWeighted25 = 0.0f, histogramWeighted50 = 0.0f, histogramWeighted75 = 0.0f;
};

struct FlipResult {
  int width = 0, height = 0;
  std::vector<float> errorMap;  // one value in [0, 1] per pixel, row-major, row 0 at the top
  FlipPooled pooled;            // over FlipOptions::mask
  // HDR-FLIP only (0 for LDR): the exposures evaluated, in stops.
  float startExposure = 0.0f, stopExposure = 0.0f;
  int exposureCount = 0;
};

// LDR-FLIP on linear rgb; each channel is clamped to [0, 1] first.
FlipResult flipLdr(const ImageRgbaF& reference, const ImageRgbaF& test, const FlipOptions& options = {});
// LDR-FLIP on sRGB-encoded values in [0, 1] (what readPng returns): decoded
// to linear per channel as the tool does for PNG input, then flipLdr.
FlipResult flipLdrSrgb(const ImageRgbaF& reference, const ImageRgbaF& test, const FlipOptions& options = {});
// HDR-FLIP on linear rgb: the per-pixel maximum of LDR-FLIP over the
// tone-mapped exposures (each tone-mapped image clamped to [0, 1] and used as
// linear rgb). The exposure range comes from the reference only, so swapping
// the images can change the result. Deviations from the tool, for inputs it
// does not handle: negative values count as 0; exposed values are capped at
// 1e18 (every curve is saturated far below); a median luminance of 0 (mostly
// black background) takes the median of the positive luminances instead (the
// tool v1.6 makes the stop exposure infinite); a reference without positive
// luminance needs both exposures given.
FlipResult flipHdr(const ImageRgbaF& reference, const ImageRgbaF& test, const FlipOptions& options = {});

// Pools an error map (width × height values) over `mask` (rules of FlipOptions::mask).
FlipPooled poolFlipErrors(std::span<const float> errors, std::span<const uint8_t> mask = {});

// The 1-D filters (weights for offsets -radius ... radius), exposed for the
// check values of docs/flip.md.
struct FlipCsfKernels {
  int radius = 0;  // common to the three channels, from the widest Gaussian
  std::vector<float> achromatic, redGreen;  // Y', Cx: each sums to 1
  // Cz is a sum of two Gaussians: h1(x)h1(y) + h2(x)h2(y) sums to 1.
  std::vector<float> blueYellow1, blueYellow2;
};
FlipCsfKernels flipCsfKernels(double ppd);
struct FlipFeatureKernels {
  int radius = 0;
  std::vector<float> gaussian;      // sums to 1
  std::vector<float> derivative1;   // positive weights sum to +1, negative to -1
  std::vector<float> derivative2;   // likewise
};
FlipFeatureKernels flipFeatureKernels(double ppd);
// cmax: (HyAB distance of Hunt-adjusted pure green and pure blue)^0.7.
float flipColorMax();

// The 256-entry magma colour map (matplotlib's, the tool's error-map
// colours): value e in [0, 1] → entry floor(255e + 0.5), each channel as the
// byte floor(255c + 0.5); values outside [0, 1] are clamped first, NaN throws
// std::invalid_argument. Returns RGBA8 (alpha 255), 4 bytes per value.
std::vector<uint8_t> magmaRgba8(std::span<const float> values);
// The table itself, entries in [0, 1].
const std::array<std::array<float, 3>, 256>& magmaTable();

}  // namespace ft
