// self_shadow_oracle.cpp — see self_shadow_oracle.h. Includes nothing from common/.
#include "validation/case_support.h"
#include "validation/self_shadow_oracle.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "validation/bcsdf_oracle.h"  // gaussLegendre: independent of common/ too

namespace ft::oracle {
namespace {


// Nodes and weights on [0, 1], graded toward both ends: the halves are cut
// into panels [r^{l+1}, r^l]·½ (l < 10, r = 0.3) plus the innermost piece,
// 8-point Gauss–Legendre each. An endpoint behaviour x^0.2 (β = 0.2 of
// cotton1) is then integrated to ~1e-7 (the innermost piece, 3e-6 wide, holds ~2e-7 of it).
struct Graded {
  std::vector<double> x, w;
  Graded() {
    const Rule g = gaussLegendre(8);
    const double r = 0.3;
    const int levels = 10;
    std::vector<double> edges{0.0};
    for (int l = levels; l >= 0; --l) edges.push_back(0.5 * std::pow(r, l));
    for (int side = 0; side < 2; ++side)
      for (size_t e = 0; e + 1 < edges.size(); ++e) {
        const double a = edges[e], b = edges[e + 1], h = 0.5 * (b - a), c = 0.5 * (a + b);
        for (size_t k = 0; k < g.x.size(); ++k) {
          const double t = c + h * g.x[k];
          x.push_back(side == 0 ? t : 1.0 - t);
          w.push_back(h * g.w[k]);
        }
      }
  }
};
const Graded& graded() {
  static const Graded g;
  return g;
}

template <class F>
double integrate(F f, double a, double b) {
  if (!(b > a)) return 0.0;
  const Graded& g = graded();
  double sum = 0.0;
  for (size_t k = 0; k < g.x.size(); ++k) sum += g.w[k] * f(a + (b - a) * g.x[k]);
  return sum * (b - a);
}

}  // namespace

double placement(const PlyShape& s, double r) {
  if (r > s.rMax) return 0.0;
  const double t = std::max((std::exp(1.0) - std::exp(r / s.rMax)) / (std::exp(1.0) - 1.0), 0.0);
  return (1.0 - 2.0 * s.epsilon) * std::pow(t, s.beta) + s.epsilon;
}

double placementMass(const PlyShape& s) {
  return integrate([&](double r) { return placement(s, r) * 2.0 * kPi * r; }, 0.0, s.rMax);
}

double density(const PlyShape& s, double plyAngle, double x, double y) {
  const double scale = s.fibers / (s.ellipseN * s.ellipseB * placementMass(s));
  double rho = 0.0;
  for (int j = 0; j < s.plies; ++j) {
    const double a = plyAngle + 2.0 * kPi * j / s.plies, c = std::cos(a), sn = std::sin(a);
    const double qx = x - s.plyRadius * c, qy = y - s.plyRadius * sn;
    rho += placement(s, std::hypot((qx * c + qy * sn) / s.ellipseN, (-qx * sn + qy * c) / s.ellipseB));
  }
  return rho * scale;
}

double lineIntegral(const PlyShape& s, double plyAngle, double x, double y, double dx, double dy) {
  const double scale = s.fibers / (s.ellipseN * s.ellipseB * placementMass(s));
  double tau = 0.0;
  for (int j = 0; j < s.plies; ++j) {
    const double a = plyAngle + 2.0 * kPi * j / s.plies, c = std::cos(a), sn = std::sin(a);
    const double qx = x - s.plyRadius * c, qy = y - s.plyRadius * sn;
    // Ellipse-local unit-disk coordinates along the line: q(t) = q0 + t q1.
    const double q0x = (qx * c + qy * sn) / s.ellipseN, q0y = (-qx * sn + qy * c) / s.ellipseB;
    const double q1x = (dx * c + dy * sn) / s.ellipseN, q1y = (-dx * sn + dy * c) / s.ellipseB;
    const double A = q1x * q1x + q1y * q1y, B = q0x * q1x + q0y * q1y, C = q0x * q0x + q0y * q0y - s.rMax * s.rMax;
    const double disc = B * B - A * C;
    if (!(disc > 0.0)) continue;
    const double t0 = std::max((-B - std::sqrt(disc)) / A, 0.0), t1 = (-B + std::sqrt(disc)) / A;
    if (!(t1 > t0)) continue;
    const double tm = std::clamp(-B / A, t0, t1);
    const auto p = [&](double t) {
      const double r = std::min(std::hypot(q0x + t * q1x, q0y + t * q1y), s.rMax);
      return placement(s, r);
    };
    tau += integrate(p, t0, tm) + integrate(p, tm, t1);
  }
  return tau * scale;
}

double uniformEllipseAccumulated(double fibers, double a, double b, double psi, double u, double v) {
  // Points (u, v) with ((u c + v s)/a)² + ((−u s + v c)/b)² ≤ 1: a quadratic in u.
  const double c = std::cos(psi), s = std::sin(psi);
  const double qa = c * c / (a * a) + s * s / (b * b);
  const double qb = v * c * s * (1.0 / (a * a) - 1.0 / (b * b));
  const double qc = v * v * (s * s / (a * a) + c * c / (b * b)) - 1.0;
  const double disc = qb * qb - qa * qc;
  if (!(disc > 0.0)) return 0.0;
  const double lo = (-qb - std::sqrt(disc)) / qa, hi = (-qb + std::sqrt(disc)) / qa;
  return fibers / (kPi * a * b) * (std::clamp(u, lo, hi) - lo);
}

double textureLookup(const PlyShape& s, const TextureLayout& t, double x, double y, double lx, double ly,
                     double plyAngle) {
  const double len = std::hypot(lx, ly), dx = -lx / len, dy = -ly / len;
  const double u = x * dx + y * dy, v = -x * dy + y * dx;
  const double period = 2.0 * kPi / s.plies;
  double psi = std::fmod(plyAngle - std::atan2(dy, dx), period);
  if (psi < 0.0) psi += period;
  const double du = 2.0 * t.halfWidth / t.width, dv = 2.0 * t.halfWidth / t.height;
  const double fu = std::clamp((u + t.halfWidth) / du - 0.5, 0.0, t.width - 1.0);
  const double fv = std::clamp((v + t.halfWidth) / dv - 0.5, 0.0, t.height - 1.0);
  const double fr = psi / period * t.slices;
  const int i0 = std::min(int(fu), t.width - 2), j0 = std::min(int(fv), t.height - 2), k0 = int(fr);
  const double wu = fu - i0, wv = fv - j0, wr = fr - k0;
  double sum = 0.0;
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        const double w = (di ? wu : 1.0 - wu) * (dj ? wv : 1.0 - wv) * (dk ? wr : 1.0 - wr);
        if (w == 0.0) continue;
        const int k = (k0 + dk) % t.slices;  // ψ_{N_s} = one period: slice 0 again
        const double uc = -t.halfWidth + (i0 + di + 0.5) * du, vc = -t.halfWidth + (j0 + dj + 0.5) * dv;
        sum += w * lineIntegral(s, period * k / t.slices, uc, vc, -1.0, 0.0);
      }
  return sum;
}

}  // namespace ft::oracle
