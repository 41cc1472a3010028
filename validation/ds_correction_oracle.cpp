// ds_correction_oracle.cpp — see ds_correction_oracle.h. Includes nothing of
// common/ beyond the layout struct of the textures.
#include "validation/case_support.h"
#include "validation/ds_correction_oracle.h"

#include <algorithm>
#include <cmath>

namespace ft::oracle {
namespace {


// Axis of n texels: periodic with centres (k + c)/n, or clamped with centres (k + ½)/n.
struct AxisWeights {
  int k0, k1;
  double w1;
};
AxisWeights periodicAxis(double x, int n, double centre) {
  double c = x * n - centre;
  const double k = std::floor(c);
  const int k0 = int(((long long)k % n + n) % n);
  return {k0, (k0 + 1) % n, c - k};
}
AxisWeights clampedAxis(double x, int n) {
  const double c = std::clamp(x * n - 0.5, 0.0, double(n - 1));
  const int k0 = std::min(int(std::floor(c)), n - 1);
  return {k0, std::min(k0 + 1, n - 1), c - k0};
}
// Trilinear read of the logarithms of a texture with `angles` slices at
// (u, v, angle weights): the lookup interpolates the factors geometrically
// (docs/ds-correction.md).
glm::dvec3 readLog(const std::vector<glm::vec4>& tex, int nu, int nv, AxisWeights u, AxisWeights v, AxisWeights a) {
  glm::dvec3 sum(0.0);
  for (int c = 0; c < 8; ++c) {
    const int i = c & 1 ? u.k1 : u.k0, j = c & 2 ? v.k1 : v.k0, k = c & 4 ? a.k1 : a.k0;
    const double w = (c & 1 ? u.w1 : 1 - u.w1) * (c & 2 ? v.w1 : 1 - v.w1) * (c & 4 ? a.w1 : 1 - a.w1);
    const glm::vec4 value = tex[size_t((k * nv + j) * nu + i)];
    for (int ch = 0; ch < 3; ++ch) sum[ch] += w * std::log(std::max(double(value[ch]), 1e-30));
  }
  return sum;
}

}  // namespace

glm::dvec3 xiLookup(const DsCorrectionTextures& t, glm::dvec4 q, bool psiOnly) {
  const int nu = int(t.layout.size.x), nv = int(t.layout.size.y), nt = int(t.layout.size.z), np = int(t.layout.size.w);
  const AxisWeights u = periodicAxis(q.x, nu, 0.5), v = clampedAxis(q.y, nv);
  const AxisWeights theta = clampedAxis((q.z + kPi / 2) / kPi, nt);  // θ_a = −π/2 + (a + ½)π/N_θ
  const AxisWeights phi = periodicAxis(q.w / (2 * kPi), np, 0.0);    // φ_b = 2πb/N_φ
  const glm::dvec3 psi = readLog(t.psiM, nu, nv, u, v, theta) + readLog(t.psiN, nu, nv, u, v, phi);
  if (psiOnly) return glm::exp(psi);
  return glm::exp(readLog(t.xiM, nu, nv, u, v, theta) + readLog(t.xiN, nu, nv, u, v, phi) + psi);
}

glm::dvec2 xiAngles(glm::dvec3 T, glm::dvec3 wd, glm::dvec3 wo) {
  const double thetaD = std::asin(std::clamp(glm::dot(wd, T), -1.0, 1.0));
  const double thetaO = std::asin(std::clamp(glm::dot(wo, T), -1.0, 1.0));
  const glm::dvec3 e1 = glm::normalize(wo - glm::dot(wo, T) * T), e2 = glm::cross(T, e1);
  double phi = std::atan2(glm::dot(wd, e2), glm::dot(wd, e1));
  if (phi < 0.0) phi += 2.0 * kPi;
  return {thetaD - thetaO, phi};
}

}  // namespace ft::oracle
