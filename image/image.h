// image.h — the linear float image every picture of fibertwin is made of:
// the GPU's shaded render, the Embree ground truth, error maps. RGBA, row 0
// at the top; rgb is linear radiance (no tone mapping, no sRGB), alpha the
// fraction of the pixel the fibers cover (0 = background only).
#pragma once
#include <cstddef>
#include <vector>

namespace ft {

struct ImageRgbaF {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  // 4 floats per pixel, row-major, row 0 at the top

  ImageRgbaF() = default;
  ImageRgbaF(int w, int h) : width(w), height(h), pixels(static_cast<size_t>(w) * h * 4, 0.0f) {}
  size_t pixelCount() const { return static_cast<size_t>(width) * height; }
  float* at(int x, int y) { return pixels.data() + (static_cast<size_t>(y) * width + x) * 4; }
  const float* at(int x, int y) const { return pixels.data() + (static_cast<size_t>(y) * width + x) * 4; }
};

}  // namespace ft
