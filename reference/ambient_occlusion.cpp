// ambient_occlusion.cpp — see ambient_occlusion.h.
#include "reference/ambient_occlusion.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace ft {

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

}  // namespace ft
