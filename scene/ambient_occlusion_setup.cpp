// ambient_occlusion_setup.cpp — see ambient_occlusion_setup.h (moved from
// reference/ambient_occlusion.cpp so that the GPU bake can fit its own texture).
#include "scene/ambient_occlusion_setup.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace ft {

float defaultAoKappa(const YarnDensityParams& d) {
  const double rf = 0.25 * std::sqrt(3.14159265358979323846 * double(d.ellipseN) * double(d.ellipseB) /
                                     double(std::max(d.fiberCount, 1u)));
  return float(2.0 * rf);
}

AmbientOcclusionParams makeAoParams(const YarnDensityParams& density, const AoSettings& s) {
  if (s.resolution < 2 || s.resolution > 4096)
    throw std::invalid_argument(fmt::format("ambient occlusion: resolution {} (2..4096)", s.resolution));
  if (s.directions < 1 || s.directions > 65536)
    throw std::invalid_argument(fmt::format("ambient occlusion: directions {} (1..65536)", s.directions));
  if (s.densityResolution < 2 || s.densityResolution > 8192)
    throw std::invalid_argument(
        fmt::format("ambient occlusion: density resolution {} (2..8192)", s.densityResolution));
  if (!(s.marchStep > 0.0f) || !std::isfinite(s.marchStep))
    throw std::invalid_argument(fmt::format("ambient occlusion: march step {} (> 0 texels)", s.marchStep));
  if (!(s.kappa >= 0.0f) || !std::isfinite(s.kappa))
    throw std::invalid_argument(fmt::format("ambient occlusion: kappa {} (≥ 0; 0 = 2 r_f)", s.kappa));
  if (s.directionMode != FT_AO_DIRECTIONS_STRATIFIED && s.directionMode != FT_AO_DIRECTIONS_EQUAL)
    throw std::invalid_argument(fmt::format("ambient occlusion: direction mode {}", s.directionMode));
  if (!(density.supportRadius > 0.0f) || !std::isfinite(density.supportRadius))
    throw std::invalid_argument(
        fmt::format("ambient occlusion: density support radius {}", density.supportRadius));
  AmbientOcclusionParams p{};
  p.density = density;
  p.resolution = uint32_t(s.resolution);
  p.directions = uint32_t(s.directions);
  p.directionMode = s.directionMode;
  p.seed = s.seed;
  // One texel of margin: W − W_s = 2W/n, so the outermost texel centres see no fibers.
  p.halfWidth = float(double(density.supportRadius) / (1.0 - 2.0 / s.resolution));
  p.kappa = s.kappa > 0.0f ? s.kappa : defaultAoKappa(density);
  p.densityResolution = uint32_t(s.densityResolution);
  p.marchStep = s.marchStep;
  return p;
}

AmbientOcclusionParams convergedAoParams(AmbientOcclusionParams p, int directions) {
  p.directions = uint32_t(directions);
  p.directionMode = FT_AO_DIRECTIONS_EQUAL;
  return p;
}

AoCubicFit fitAoCubic(std::span<const double> texture, int n) {
  if (n < 2 || texture.size() != size_t(n) * size_t(n))
    throw std::invalid_argument(fmt::format("fitAoCubic: {} texels for a {}×{} texture", texture.size(), n, n));
  const int bins = n / 2;  // one texel (2/n in r̂) per bin over r̂ ∈ [0, 1)
  std::vector<double> count(bins, 0.0), meanAo(bins, 0.0);
  std::vector<Eigen::Vector4d> meanPow(bins, Eigen::Vector4d::Zero());
  const auto rHat = [&](int i, int j) {
    const double x = -1.0 + (i + 0.5) * 2.0 / n, y = -1.0 + (j + 0.5) * 2.0 / n;  // in units of W
    return std::hypot(x, y);
  };
  AoCubicFit fit;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r = rHat(i, j);
      if (!(r < 1.0)) continue;
      const int b = std::min(int(r * bins), bins - 1);
      count[b] += 1.0;
      meanAo[b] += texture[size_t(j) * n + i];
      meanPow[b] += Eigen::Vector4d(1.0, r, r * r, r * r * r);
      ++fit.texels;
    }
  int used = 0;
  for (int b = 0; b < bins; ++b) used += count[b] > 0.0;
  if (used < 4) throw std::invalid_argument(fmt::format("fitAoCubic: {} radial bins, a cubic needs 4", used));
  Eigen::MatrixXd a(used, 4);
  Eigen::VectorXd rhs(used);
  for (int b = 0, row = 0; b < bins; ++b) {
    if (count[b] == 0.0) continue;
    const double w = std::sqrt(count[b]);  // least squares weighted by the bin counts
    a.row(row) = (w / count[b]) * meanPow[b].transpose();
    rhs(row) = (w / count[b]) * meanAo[b];
    ++row;
  }
  const Eigen::Vector4d c = a.colPivHouseholderQr().solve(rhs);
  fit.coefficients = glm::dvec4(c(0), c(1), c(2), c(3));
  fit.bins = used;
  double sq = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r = rHat(i, j);
      if (!(r < 1.0)) continue;
      const double poly = std::clamp(c(0) + r * (c(1) + r * (c(2) + r * c(3))), 0.0, 1.0);
      const double e = texture[size_t(j) * n + i] - poly;
      sq += e * e;
      fit.maxResidual = std::max(fit.maxResidual, std::abs(e));
    }
  fit.rmsResidual = std::sqrt(sq / fit.texels);
  return fit;
}

AoCubicFit fitAoCubic(std::span<const float> texture, int n) {
  const std::vector<double> d(texture.begin(), texture.end());
  return fitAoCubic(std::span<const double>(d), n);
}

}  // namespace ft
