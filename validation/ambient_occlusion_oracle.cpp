// ambient_occlusion_oracle.cpp — see ambient_occlusion_oracle.h. Includes nothing from common/.
#include "validation/ambient_occlusion_oracle.h"
#include "validation/case_support.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ft::oracle {

namespace {
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

double linearFieldAo(const double c[3], double halfWidth, int m, double kappa, int directions, double x, double y) {
  const double edge = halfWidth - halfWidth / m;  // outermost cell centre
  // ∫_0^L clamp(a + s b, −e, e) ds, split where the clamp engages.
  const auto clampedIntegral = [&](double a, double b, double len) {
    std::vector<double> cuts = {0.0, len};
    if (b != 0.0)
      for (double bound : {-edge, edge}) {
        const double s = (bound - a) / b;
        if (s > 0.0 && s < len) cuts.push_back(s);
      }
    std::sort(cuts.begin(), cuts.end());
    double sum = 0.0;
    for (size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double mid = 0.5 * (cuts[i] + cuts[i + 1]);  // the integrand is linear on the piece
      sum += std::clamp(a + mid * b, -edge, edge) * (cuts[i + 1] - cuts[i]);
    }
    return sum;
  };
  double ao = 0.0;
  for (int k = 0; k < directions; ++k) {
    const double phi = 2.0 * kPi * (k + 0.5) / directions;
    const double dx = std::cos(phi), dy = std::sin(phi);
    const double tx = dx > 0.0 ? (halfWidth - x) / dx : dx < 0.0 ? (-halfWidth - x) / dx : 1e300;
    const double ty = dy > 0.0 ? (halfWidth - y) / dy : dy < 0.0 ? (-halfWidth - y) / dy : 1e300;
    const double len = std::min(tx, ty);
    const double tau = c[0] * len + c[1] * clampedIntegral(x, dx, len) + c[2] * clampedIntegral(y, dy, len);
    ao += std::exp(-kappa * tau);
  }
  return ao / directions;
}

}  // namespace ft::oracle
