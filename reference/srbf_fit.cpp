// srbf_fit.cpp — the SRBF environment fit (see srbf_fit.h).
#include "reference/srbf_fit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ft {

namespace {

// Basis function values at ω: lobes, then the DC term.
void basisValues(const SrbfBasis& basis, glm::vec3 w, double* out) {
  for (int j = 0; j < FT_SRBF_LOBES; ++j)
    out[j] = ftSrbfKernel(glm::vec3(basis.axisLambda[j]), basis.axisLambda[j].w, w);
  if (basis.constantTerm) out[FT_SRBF_LOBES] = 1.0;
}

void checkMap(const ImageRgbaF& env) {
  if (env.width < 2 || env.height < 2 || env.pixels.size() != env.pixelCount() * 4)
    throw std::invalid_argument("SRBF fit: the environment map is empty or malformed");
}

}  // namespace

SrbfNormalEquations srbfNormalEquationsCpu(const ImageRgbaF& env, const SrbfBasis& basis) {
  checkMap(env);
  const int n = basis.count();
  struct Sums {
    std::vector<double> gram;
    std::vector<glm::dvec3> rhs;
  };
  const Sums zero{std::vector<double>(size_t(n * n), 0.0), std::vector<glm::dvec3>(size_t(n), glm::dvec3(0.0))};
  // Rows in parallel; each row's sums are formed in order, then rows are added
  // (deterministic for a given partition; double keeps rounding at 1e-16).
  const Sums total = tbb::parallel_reduce(
      tbb::blocked_range<int>(0, env.height), zero,
      [&](const tbb::blocked_range<int>& rows, Sums s) {
        double g[FT_SRBF_LOBES + 1];
        for (int y = rows.begin(); y < rows.end(); ++y) {
          const double dOmega = ftEquirectSolidAngle(y, env.width, env.height);
          for (int x = 0; x < env.width; ++x) {
            basisValues(basis, ftEquirectDirection(x, y, env.width, env.height), g);
            const float* p = env.at(x, y);
            const glm::dvec3 L(p[0], p[1], p[2]);
            for (int a = 0; a < n; ++a) {
              s.rhs[size_t(a)] += dOmega * g[a] * L;
              for (int b = a; b < n; ++b) s.gram[size_t(a * n + b)] += dOmega * g[a] * g[b];
            }
          }
        }
        return s;
      },
      [&](Sums a, const Sums& b) {
        for (size_t i = 0; i < a.gram.size(); ++i) a.gram[i] += b.gram[i];
        for (size_t i = 0; i < a.rhs.size(); ++i) a.rhs[i] += b.rhs[i];
        return a;
      });
  SrbfNormalEquations eq;
  eq.count = n;
  eq.gram = total.gram;
  eq.rhs = total.rhs;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < a; ++b) eq.gram[size_t(a * n + b)] = eq.gram[size_t(b * n + a)];
  return eq;
}

SrbfFit fitSrbfCpu(const ImageRgbaF& env, const SrbfFitOptions& options) {
  const SrbfBasis basis = srbfFibonacciBasis(options);
  return fitSrbfFromSums(basis, srbfNormalEquationsCpu(env, basis));
}

double srbfRelativeL2(const ImageRgbaF& env, const SrbfEnvironment& fit) {
  checkMap(env);
  double err = 0.0, ref = 0.0;
  for (int y = 0; y < env.height; ++y) {
    const double dOmega = ftEquirectSolidAngle(y, env.width, env.height);
    for (int x = 0; x < env.width; ++x) {
      const glm::dvec3 L(env.at(x, y)[0], env.at(x, y)[1], env.at(x, y)[2]);
      const glm::dvec3 f(ftSrbfRadiance(fit, ftEquirectDirection(x, y, env.width, env.height)));
      err += dOmega * glm::dot(L - f, L - f);
      ref += dOmega * glm::dot(L, L);
    }
  }
  return ref > 0.0 ? std::sqrt(err / ref) : std::sqrt(err);
}

ImageRgbaF makeProceduralSky(int width, int height, bool withSun) {
  if (width < 2 || height < 2) throw std::invalid_argument("makeProceduralSky: the map needs 2 × 2 pixels at least");
  ImageRgbaF img(width, height);
  // Written with its own direction formula (the common/srbf.h convention):
  // a map made here does not move if that header's convention is broken.
  const double pi = 3.14159265358979323846;
  const glm::dvec3 sun = glm::normalize(glm::dvec3(0.45, 0.55, -0.70));
  const glm::dvec3 zenith(0.18, 0.36, 0.95), horizon(0.85, 0.90, 1.05), ground(0.22, 0.17, 0.12);
  const double sunLambda = 800.0, sunPeak = 800.0;  // ∫ sun dω ≈ 2π·sunPeak/sunLambda = 2π
  const glm::dvec3 sunColour(1.0, 0.92, 0.80);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double theta = pi * (y + 0.5) / height, phi = 2.0 * pi * (x + 0.5) / width - pi;
      const glm::dvec3 w(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      glm::dvec3 L;
      if (w.y >= 0.0) {
        const double t = std::pow(w.y, 0.4);
        L = 1.5 * glm::mix(horizon, zenith, t);
      } else {
        const double t = std::min(1.0, -w.y * 8.0);  // a soft horizon band into the ground
        L = glm::mix(1.5 * horizon * 0.6, ground, t);
      }
      if (withSun) L += sunPeak * std::exp(sunLambda * (glm::dot(sun, w) - 1.0)) * sunColour;
      float* p = img.at(x, y);
      p[0] = float(L.x);
      p[1] = float(L.y);
      p[2] = float(L.z);
      p[3] = 1.0f;
    }
  return img;
}

}  // namespace ft
