#include "image/image_metrics.h"

#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <stdexcept>

namespace ft {
namespace {

void checkSameSize(const ImageRgbaF& reference, const ImageRgbaF& test) {
  if (reference.width != test.width || reference.height != test.height)
    throw std::invalid_argument(fmt::format("image metrics: reference is {}x{} but test is {}x{}", reference.width,
                                            reference.height, test.width, test.height));
}

double relativeSquared(double r, double t) { return (t - r) * (t - r) / (r * r + kRelMseEpsilon); }

}  // namespace

ImageMetrics compareImages(const ImageRgbaF& reference, const ImageRgbaF& test, std::span<const uint8_t> mask) {
  checkSameSize(reference, test);
  const size_t n = reference.pixelCount();
  if (!mask.empty() && mask.size() != n)
    throw std::invalid_argument(fmt::format("image metrics: mask has {} values for {} pixels", mask.size(), n));
  ImageMetrics m;
  double squared = 0.0, relative = 0.0;
  for (size_t i = 0; i < n; ++i) {
    if (!mask.empty()) {
      if (mask[i] > 1)
        throw std::invalid_argument(
            fmt::format("image metrics: mask value {} at pixel {} is neither 0 nor 1", mask[i], i));
      if (!mask[i]) continue;
    }
    const float* r = reference.pixels.data() + i * 4;
    const float* t = test.pixels.data() + i * 4;
    bool finite = true;
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(r[c])) ++m.nonFiniteReference, finite = false;
      if (!std::isfinite(t[c])) ++m.nonFiniteTest, finite = false;
    }
    if (!finite) continue;
    ++m.pixels;
    for (int c = 0; c < 3; ++c) {
      const double d = double(t[c]) - double(r[c]);
      squared += d * d;
      relative += relativeSquared(r[c], t[c]);
    }
  }
  if (m.pixels) {
    const double values = 3.0 * static_cast<double>(m.pixels);
    m.rmse = std::sqrt(squared / values);
    m.relMse = relative / values;
  }
  return m;
}

ImageRgbaF relativeSquaredError(const ImageRgbaF& reference, const ImageRgbaF& test) {
  checkSameSize(reference, test);
  ImageRgbaF out(reference.width, reference.height);
  for (size_t i = 0; i < reference.pixelCount(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float r = reference.pixels[i * 4 + c], t = test.pixels[i * 4 + c];
      out.pixels[i * 4 + c] = std::isfinite(r) && std::isfinite(t) ? static_cast<float>(relativeSquared(r, t))
                                                                  : std::numeric_limits<float>::quiet_NaN();
    }
    out.pixels[i * 4 + 3] = 1.0f;
  }
  return out;
}

}  // namespace ft
