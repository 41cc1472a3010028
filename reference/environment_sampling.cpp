#include "reference/environment_sampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "reference/numbers.h"

namespace ft {
namespace {
// The last index i with cdf[i] <= u (cdf ascending, cdf.front() = 0, u in [0, cdf.back())).
int findInterval(const double* cdf, int n, double u) {
  const double* it = std::upper_bound(cdf, cdf + n + 1, u);
  return std::clamp(int(it - cdf) - 1, 0, n - 1);
}
}  // namespace

EnvironmentSampler::EnvironmentSampler(const ImageRgbaF& map) : width_(map.width), height_(map.height) {
  if (width_ < 2 || height_ < 1 || map.pixels.size() != size_t(width_) * height_ * 4)
    throw std::invalid_argument("EnvironmentSampler: empty or malformed map");
  const size_t n = size_t(width_) * height_;
  rgb_.resize(n);
  lum_.resize(n);
  for (size_t p = 0; p < n; ++p) {
    rgb_[p] = glm::vec3(map.pixels[4 * p], map.pixels[4 * p + 1], map.pixels[4 * p + 2]);
    lum_[p] = std::max(0.0, 0.2126 * rgb_[p].x + 0.7152 * rgb_[p].y + 0.0722 * rgb_[p].z);
  }
  rowCdf_.assign(size_t(height_) + 1, 0.0);
  colCdf_.assign(size_t(height_) * (width_ + 1), 0.0);
  for (int y = 0; y < height_; ++y) {
    double* c = &colCdf_[size_t(y) * (width_ + 1)];
    for (int x = 0; x < width_; ++x) c[x + 1] = c[x] + lum_[size_t(y) * width_ + x];
    rowCdf_[y + 1] = rowCdf_[y] + c[width_] * pixelSolidAngle(y);
  }
  total_ = rowCdf_[height_];
}

double EnvironmentSampler::pixelSolidAngle(int y) const {
  const double t0 = kPi * y / height_, t1 = kPi * (y + 1) / height_;
  return 2.0 * kPi / width_ * 2.0 * std::sin(0.5 * (t0 + t1)) * std::sin(0.5 * (t1 - t0));
}

glm::ivec2 EnvironmentSampler::pixelOf(glm::dvec3 w) const {
  const double phi = std::atan2(w.z, w.x), theta = std::acos(std::clamp(w.y, -1.0, 1.0));
  const int x = std::clamp(int(std::floor((phi + kPi) / (2.0 * kPi) * width_)), 0, width_ - 1);
  const int y = std::clamp(int(std::floor(theta / kPi * height_)), 0, height_ - 1);
  return {x, y};
}

glm::vec3 EnvironmentSampler::radiance(glm::dvec3 w) const {
  const glm::ivec2 p = pixelOf(w);
  return rgb_[size_t(p.y) * width_ + p.x];
}

double EnvironmentSampler::pdf(glm::dvec3 w) const {
  if (total_ <= 0.0) return 0.0;
  const glm::ivec2 p = pixelOf(w);
  return lum_[size_t(p.y) * width_ + p.x] / total_;
}

EnvironmentSampler::Sample EnvironmentSampler::sample(double u0, double u1, double u2) const {
  Sample s;
  if (total_ <= 0.0) return s;
  // Row from the marginal; column from the row's conditional.
  const double r = std::clamp(u0, 0.0, 1.0 - 1e-16) * total_;
  const int y = findInterval(rowCdf_.data(), height_, r);
  const double* c = &colCdf_[size_t(y) * (width_ + 1)];
  const double q = std::clamp(u1, 0.0, 1.0 - 1e-16) * c[width_];
  const int x = findInterval(c, width_, q);
  // Inside the pixel: φ uniform (the column's remainder), cos θ uniform (u2).
  const double fx = c[x + 1] > c[x] ? std::clamp((q - c[x]) / (c[x + 1] - c[x]), 0.0, 1.0) : 0.5;
  const double phi = 2.0 * kPi * (x + fx) / width_ - kPi;
  const double ct = std::cos(kPi * y / height_), cb = std::cos(kPi * (y + 1) / height_);
  const double cosTheta = ct + std::clamp(u2, 0.0, 1.0) * (cb - ct);
  const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
  s.w = glm::dvec3(sinTheta * std::cos(phi), cosTheta, sinTheta * std::sin(phi));
  const size_t k = size_t(y) * width_ + x;
  s.pdf = lum_[k] / total_;
  s.radiance = rgb_[k];
  return s;
}

}  // namespace ft
