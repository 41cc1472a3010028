// The shared ply-density field (common/yarn_density.h, notes-rendering §0.3)
// against sums written here in double from reference-data §2 alone: the
// field's mass, its line integral, and the ellipse orientation.
#include <gtest/gtest.h>

#include <cmath>

#include "common/yarn_density.h"
#include "scene/input_error.h"
#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {
namespace {

// p(R) of reference-data §2, in double.
double placement(const YarnPreset& p, double r) {
  if (r > p.rMax) return 0.0;
  const double t = (M_E - std::exp(r / p.rMax)) / (M_E - 1.0);
  return (1.0 - 2.0 * p.epsilon) * std::pow(std::max(t, 0.0), p.beta) + p.epsilon;
}

// ρ at (x, y) with ψ = 0, written out from the definition: ply j's centre at
// yarn_radius/2 in direction 2πj/n, short axis e_N along it.
double density(const YarnPreset& p, double z, double x, double y) {
  double rho = 0.0;
  for (int j = 0; j < p.plyNum; ++j) {
    const double a = 2.0 * M_PI * j / p.plyNum;
    const double cx = std::cos(a), cy = std::sin(a);
    const double qx = x - 0.5 * p.yarnRadius * cx, qy = y - 0.5 * p.yarnRadius * cy;
    const double u = (qx * cx + qy * cy) / p.ellipseShort, v = (-qx * cy + qy * cx) / p.ellipseLong;
    rho += placement(p, std::hypot(u, v));
  }
  return rho / z;
}

// Z·e_N·e_B/n_f: the normaliser, by a fine midpoint rule over r.
double normaliser(const YarnPreset& p) {
  const int n = 200000;
  double z = 0.0;
  for (int i = 0; i < n; ++i) {
    const double r = (i + 0.5) * p.rMax / n;
    z += placement(p, r) * 2.0 * M_PI * r * p.rMax / n;
  }
  return z * p.ellipseShort * p.ellipseLong / p.fiberNum;
}

TEST(YarnDensity, MassIsPliesTimesFibers) {
  for (const char* name : {"cotton1", "polyester1", "rayon2", "silk1"}) {
    const YarnPreset& preset = findYarnPreset(name);
    const YarnDensityParams d = makeYarnDensity(preset);
    // Integrate the shared field over a grid covering its support.
    const int n = 600;
    const double w = d.supportRadius * 1.02, h = 2.0 * w / n;
    double mass = 0.0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        mass += ftYarnDensity(d, 0.0f, vec2(float(-w + (i + 0.5) * h), float(-w + (j + 0.5) * h))) * h * h;
    // Midpoint rule on a field with a jump of ε·ρ0 at the ply boundary: 0.5%.
    EXPECT_NEAR(mass / (preset.plyNum * preset.fiberNum), 1.0, 5e-3) << name;
  }
}

TEST(YarnDensity, PointValuesMatchTheDefinition) {
  const YarnPreset& preset = findYarnPreset("cotton1");
  const YarnDensityParams d = makeYarnDensity(preset);
  const double z = normaliser(preset);
  const double w = d.supportRadius;
  for (int i = 0; i < 41; ++i)
    for (int j = 0; j < 41; ++j) {
      const double x = -w + 2.0 * w * i / 40.0, y = -w + 2.0 * w * j / 40.0;
      const double expected = density(preset, z, x, y);
      const double got = ftYarnDensity(d, 0.0f, vec2(float(x), float(y)));
      EXPECT_NEAR(got, expected, 1e-4 * (expected + 1e-3 * d.normalization)) << x << "," << y;
    }
}

TEST(YarnDensity, LineIntegralMatchesBruteForce) {
  const YarnPreset& preset = findYarnPreset("cotton1");
  const YarnDensityParams d = makeYarnDensity(preset);
  const double z = normaliser(preset);
  const double w = d.supportRadius;
  uint32_t state = 12345u;
  auto next = [&] { state = state * 1664525u + 1013904223u; return (state >> 8) * (1.0 / 16777216.0); };
  double worst = 0.0;
  for (int k = 0; k < 40; ++k) {
    const double x = (2.0 * next() - 1.0) * w, y = (2.0 * next() - 1.0) * w;
    const double a = 2.0 * M_PI * next();
    const double dx = std::cos(a), dy = std::sin(a);
    // Brute force: 200,000 midpoint steps over the support (the line leaves it by 2W).
    const int n = 200000;
    const double len = 2.0 * w, h = len / n;
    double tau = 0.0;
    for (int i = 0; i < n; ++i) tau += density(preset, z, x + (i + 0.5) * h * dx, y + (i + 0.5) * h * dy) * h;
    const double got = ftDensityLineIntegral(d, 0.0f, vec2(float(x), float(y)), vec2(float(dx), float(dy)));
    // Tolerance: the brute force's own error at the ply boundaries (jump ε·ρ0 over ≤ h
    // per crossing, 2 crossings per ply) plus float rounding of the shared one.
    const double bound = 2.0 * preset.plyNum * d.normalization * h + 2e-4 * tau;
    EXPECT_NEAR(got, tau, bound) << "start " << x << "," << y << " angle " << a;
    worst = std::max(worst, std::abs(got - tau) / std::max(tau, 1.0));
  }
  RecordProperty("worst_relative", std::to_string(worst));
}

TEST(YarnDensity, PlyTwistRotatesTheField) {
  // ψ turns every ply about the yarn centre: ρ_ψ(R_ψ x) = ρ_0(x).
  const YarnDensityParams d = makeYarnDensity(findYarnPreset("rayon2"));
  const float psi = 0.7f;
  for (int k = 0; k < 50; ++k) {
    const vec2 x(d.supportRadius * (0.02f * k - 0.5f), d.supportRadius * 0.3f);
    const vec2 rx(std::cos(psi) * x.x - std::sin(psi) * x.y, std::sin(psi) * x.x + std::cos(psi) * x.y);
    EXPECT_NEAR(ftYarnDensity(d, psi, rx), ftYarnDensity(d, 0.0f, x), 1e-4f * d.normalization);
  }
}

TEST(YarnDensity, RefusesAFieldWithoutMass) {
  YarnPreset preset = findYarnPreset("cotton1");
  preset.rMax = 0.0;
  EXPECT_THROW(makeYarnDensity(preset), InputError);
}

}  // namespace
}  // namespace ft
