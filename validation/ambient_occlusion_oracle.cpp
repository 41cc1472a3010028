// ambient_occlusion_oracle.cpp — see ambient_occlusion_oracle.h. Includes nothing from common/.
#include "validation/ambient_occlusion_oracle.h"

#include <algorithm>
#include <cmath>

namespace ft::oracle {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

double uniformDiskAo(double kappa, double rho0, double a, double x, double y, int nodes) {
  double sum = 0.0;
  const double r2 = x * x + y * y;
  for (int k = 0; k < nodes; ++k) {
    const double phi = 2.0 * kPi * k / nodes;
    const double pd = x * std::cos(phi) + y * std::sin(phi);
    const double chord = -pd + std::sqrt(std::max(pd * pd - r2 + a * a, 0.0));  // exit distance along d
    sum += std::exp(-kappa * rho0 * chord);
  }
  return sum / nodes;
}

double uniformDiskAoCentre(double kappa, double rho0, double a) { return std::exp(-kappa * rho0 * a); }

double aoCubic(const double a[4], double r) {
  return std::clamp(a[0] + a[1] * r + a[2] * r * r + a[3] * r * r * r, 0.0, 1.0);
}

void plyCentre(double radius, int j, int n, double theta, double& x, double& y) {
  const double angle = 2.0 * kPi * j / n + theta;
  x = radius * std::cos(angle);
  y = radius * std::sin(angle);
}

}  // namespace ft::oracle
