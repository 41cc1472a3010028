// image_metrics.h — plain per-value error measures between a reference and a
// test image: RMSE and relative MSE over the rgb channels, with an optional
// mask, counting what cannot be measured (non-finite values) instead of
// letting it poison the result. FLIP, the perceptual measure, is in flip.h.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "image/image.h"

namespace ft {

// ε of the relative squared error (t - r)² / (r² + ε): keeps black reference
// pixels from dominating (the value common in the Monte Carlo rendering and
// denoising literature).
inline constexpr double kRelMseEpsilon = 0.01;

struct ImageMetrics {
  size_t pixels = 0;              // pixels pooled (mask set, every rgb value of both images finite)
  size_t nonFiniteReference = 0;  // rgb values (not pixels) that are NaN or ±inf, over masked pixels
  size_t nonFiniteTest = 0;
  double rmse = 0.0;    // √(mean over pooled pixels and channels of (t - r)²)
  double relMse = 0.0;  // mean over pooled pixels and channels of (t - r)² / (r² + ε)
};

// Reference and test must have the same size (std::invalid_argument
// otherwise). Alpha is not compared. `mask`: empty = every pixel, else one
// value per pixel (row-major), 1 = pooled, 0 = left out (other values are
// rejected). A pixel with any non-finite rgb value in either image is left
// out of rmse/relMse and counted; pixels == 0 gives rmse = relMse = 0.
ImageMetrics compareImages(const ImageRgbaF& reference, const ImageRgbaF& test, std::span<const uint8_t> mask = {});

// Per pixel and channel (t - r)² / (r² + ε) as an image (alpha 1) for reports;
// a non-finite input value gives NaN in its channel (writePngTonemapped
// shows such pixels in magenta).
ImageRgbaF relativeSquaredError(const ImageRgbaF& reference, const ImageRgbaF& test);

}  // namespace ft
