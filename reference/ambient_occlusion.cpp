// ambient_occlusion.cpp — see ambient_occlusion.h.
#include "reference/ambient_occlusion.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

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

namespace {

// AO at x and its standard deviation. The sum is ftAoExact's, term by term
// in the same float order (tests/ambient_occlusion_test checks they agree
// bit for bit). σ: one jittered sample per stratum; the variance of stratum
// k's sample is estimated by (f_k − f_{k+1})²/2 from its neighbour (cyclic),
// which also counts the trend between strata, so it errs on the large side:
// σ² = Σ_k (f_k − f_{k+1})² / (2 N²).
float aoWithSigma(const AmbientOcclusionParams& p, float psi, glm::vec2 x, uint32_t sample, float& sigma) {
  float sum = 0.0f, first = 0.0f, prev = 0.0f;
  double var = 0.0;
  for (uint32_t k = 0; k < p.directions; ++k) {
    const float phi = ftAoDirectionAngle(p, sample, k);
    const float tau = ftDensityLineIntegral(p.density, psi, x, glm::vec2(std::cos(phi), std::sin(phi)));
    const float f = ftAoVisibility(p.kappa, tau);
    sum += f;
    if (k == 0) first = f;
    else var += 0.5 * double(f - prev) * double(f - prev);
    prev = f;
  }
  var += 0.5 * double(first - prev) * double(first - prev);
  sigma = float(std::sqrt(var) / p.directions);
  return sum / float(p.directions);
}

}  // namespace

AoBakeCpu bakeAmbientOcclusionCpu(const AmbientOcclusionParams& p) {
  const uint32_t n = p.resolution;
  AoBakeCpu out;
  out.ao.resize(size_t(n) * n);
  out.sigma.resize(out.ao.size());
  tbb::parallel_for(uint32_t(0), n, [&](uint32_t j) {
    const float y = ftAoTexelCentre(p.halfWidth, n, j);
    for (uint32_t i = 0; i < n; ++i) {
      const size_t t = size_t(j) * n + i;
      out.ao[t] = aoWithSigma(p, 0.0f, glm::vec2(ftAoTexelCentre(p.halfWidth, n, i), y), uint32_t(t), out.sigma[t]);
    }
  });
  return out;
}

AoBakeCpu ambientOcclusionAtCpu(const AmbientOcclusionParams& p, std::span<const glm::vec3> pointsPsi,
                                std::span<const uint32_t> sampleIds) {
  if (!sampleIds.empty() && sampleIds.size() != pointsPsi.size())
    throw std::invalid_argument("ambientOcclusionAtCpu: points and sample ids differ in size");
  AoBakeCpu out;
  out.ao.resize(pointsPsi.size());
  out.sigma.resize(pointsPsi.size());
  tbb::parallel_for(size_t(0), pointsPsi.size(), [&](size_t k) {
    const glm::vec3 q = pointsPsi[k];
    out.ao[k] = aoWithSigma(p, q.z, glm::vec2(q.x, q.y), sampleIds.empty() ? uint32_t(k) : sampleIds[k], out.sigma[k]);
  });
  return out;
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
