// environment_sampling.h — importance sampling of an environment map for the
// path-traced ground truth (`fibertwin trace --env`; docs/srbf-lighting.md):
// the map itself, not its SRBF fit, so that comparing the frame with the
// trace shows what the fit costs. A lat-long map in the convention of
// common/srbf.h (y up, row 0 at the top looking along +y, φ = atan2(z, x) =
// 2πu − π), read as piecewise constant over its pixels. Sampling in the
// style of pbrt-v4's PiecewiseConstant2D: a marginal over rows and a
// conditional over the columns of a row, each pixel weighted by its
// luminance times its solid angle (the exact band area, i.e. luminance ×
// sin θ up to the band's width); inside the pixel uniform in φ and cos θ, so
// the density is constant over the pixel:
//   p(ω) = lum_k / Σ_k' lum_k' dΩ_k'   (per steradian, k the pixel of ω).
// Written in double from the convention, sharing no code with common/srbf.h.
#pragma once
#include <glm/glm.hpp>
#include <vector>

#include "image/image.h"

namespace ft {

class EnvironmentSampler {
 public:
  // `map`: width = 2 height (checked by scene/environment_map.h), rgb ≥ 0.
  explicit EnvironmentSampler(const ImageRgbaF& map);

  int width() const { return width_; }
  int height() const { return height_; }
  // The pixel holding ω (unit) and its radiance.
  glm::ivec2 pixelOf(glm::dvec3 w) const;
  glm::vec3 radiance(glm::dvec3 w) const;
  // Solid-angle density of sample(); 0 where the map's luminance is 0.
  double pdf(glm::dvec3 w) const;
  // Whether any pixel has luminance > 0 (else sample() must not be called).
  bool samplable() const { return total_ > 0.0; }
  struct Sample {
    glm::dvec3 w;
    double pdf = 0.0;
    glm::vec3 radiance{0.0f};
  };
  // From three uniform numbers in [0, 1).
  Sample sample(double u0, double u1, double u2) const;
  // Solid angle of row y's pixels: (2π/W)(cos θ_top − cos θ_bottom).
  double pixelSolidAngle(int y) const;

 private:
  int width_ = 0, height_ = 0;
  std::vector<glm::vec3> rgb_;
  std::vector<double> lum_;       // per pixel
  std::vector<double> rowCdf_;    // height + 1
  std::vector<double> colCdf_;    // height × (width + 1), per row
  double total_ = 0.0;            // Σ lum dΩ
};

}  // namespace ft
