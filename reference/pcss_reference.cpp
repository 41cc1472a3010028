#include "reference/pcss_reference.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ft {
namespace {

constexpr double kGolden = 2.39996322972865332;  // π(3 − √5)

// Directions at polar angles cos θ_k around `axis`, azimuths k·golden angle.
std::vector<glm::vec3> spiral(glm::vec3 axis, int n, double (*cosTheta)(double u, double p), double param) {
  if (n <= 0) throw std::invalid_argument(fmt::format("cone directions: {} rays", n));
  const glm::dvec3 z = glm::normalize(glm::dvec3(axis));
  const glm::dvec3 helper = std::abs(z.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 x = glm::normalize(glm::cross(helper, z)), y = glm::cross(z, x);
  std::vector<glm::vec3> out;
  out.reserve(size_t(n));
  for (int k = 0; k < n; ++k) {
    const double c = std::clamp(cosTheta((k + 0.5) / n, param), -1.0, 1.0), s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double phi = k * kGolden;
    out.push_back(glm::vec3(s * std::cos(phi) * x + s * std::sin(phi) * y + c * z));
  }
  return out;
}

}  // namespace

std::vector<glm::vec3> coneDirections(glm::vec3 axis, double alpha, int n) {
  return spiral(axis, n, [](double u, double a) { return 1.0 - u * (1.0 - std::cos(a)); }, alpha);
}

std::vector<glm::vec3> sgDirections(glm::vec3 mu, double lambda, int n) {
  return spiral(mu, n, [](double u, double l) { return 1.0 + std::log1p(-u * -std::expm1(-2.0 * l)) / l; }, lambda);
}

std::vector<float> directionsVisibility(const ShadowMapReference& tubes, std::span<const glm::vec3> points,
                                        std::span<const glm::vec3> directions) {
  std::vector<float> out(points.size());
  tbb::parallel_for(size_t(0), points.size(), [&](size_t i) {
    size_t lit = 0;
    for (const glm::vec3& d : directions) lit += tubes.visibility(points[i], d) > 0.5f ? 1 : 0;
    out[i] = float(double(lit) / double(directions.size()));
  });
  return out;
}

std::vector<float> pcssLightLookup(const ShadowMapParams& sm, const PcssParams& pc, std::span<const float> texels, int light,
                                   std::span<const glm::vec3> points) {
  const size_t n = size_t(sm.count.y);
  if (light < 0 || light >= int(sm.count.x) || texels.size() < n * n * size_t(light + 1))
    throw std::out_of_range(fmt::format("pcssLightLookup: light {} of {} in {} texels", light, sm.count.x, texels.size()));
  std::vector<float> out(points.size());
  for (size_t k = 0; k < points.size(); ++k) out[k] = ftPcssLightVisibility(sm, pc, light, points[k], texels.data());
  return out;
}

std::vector<float> pcssLobeLookup(const PcssParams& pc, std::span<const float> texels, int lobe,
                                  std::span<const glm::vec3> points) {
  const size_t n = size_t(pc.count.y);
  if (lobe < 0 || lobe >= FT_PCSS_MAX_LOBES || texels.size() < n * n * std::max<size_t>(pc.count.x, 1))
    throw std::out_of_range(fmt::format("pcssLobeLookup: lobe {} in {} texels", lobe, texels.size()));
  std::vector<float> out(points.size());
  for (size_t k = 0; k < points.size(); ++k) out[k] = ftPcssLobeVisibility(pc, lobe, points[k], texels.data());
  return out;
}

}  // namespace ft
