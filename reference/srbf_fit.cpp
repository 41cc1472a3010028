// srbf_fit.cpp — the SRBF environment fit (see srbf_fit.h).
#include "reference/srbf_fit.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ft {

SrbfBasis srbfFibonacciBasis(const SrbfFitOptions& options) {
  SrbfBasis b;
  b.constantTerm = options.constantTerm;
  const float lambda = options.lambda > 0.0f ? options.lambda : ftSrbfInitialLambda(FT_SRBF_LOBES);
  for (int j = 0; j < FT_SRBF_LOBES; ++j) b.axisLambda[j] = glm::vec4(ftSrbfFibonacci(j, FT_SRBF_LOBES), lambda);
  return b;
}

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

// Lawson & Hanson 1974, NNLS, written on the normal equations: the gradient
// of ½xᵀKx − bᵀx is −w with w = b − Kx; the passive set P holds the free
// variables, whose unconstrained optimum solves K_PP z_P = b_P (Eigen LDLT).
std::vector<double> solveNnlsNormal(const std::vector<double>& gram, const std::vector<double>& rhs, int n,
                                    int* iterations) {
  if (n <= 0 || gram.size() != size_t(n * n) || rhs.size() != size_t(n))
    throw std::invalid_argument("solveNnlsNormal: sizes do not match");
  Eigen::MatrixXd K(n, n);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    b(i) = rhs[size_t(i)];
    for (int j = 0; j < n; ++j) K(i, j) = gram[size_t(i * n + j)];
  }
  double scale = 0.0;
  for (int i = 0; i < n; ++i) scale = std::max(scale, std::abs(b(i)));
  const double tol = 1e-12 * std::max(scale, 1e-300);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> passive(size_t(n), false);
  const auto solvePassive = [&]() {
    std::vector<int> idx;
    for (int i = 0; i < n; ++i)
      if (passive[size_t(i)]) idx.push_back(i);
    Eigen::MatrixXd Kp(idx.size(), idx.size());
    Eigen::VectorXd bp(idx.size());
    for (size_t i = 0; i < idx.size(); ++i) {
      bp(Eigen::Index(i)) = b(idx[i]);
      for (size_t j = 0; j < idx.size(); ++j) Kp(Eigen::Index(i), Eigen::Index(j)) = K(idx[i], idx[j]);
    }
    const Eigen::VectorXd zp = Kp.ldlt().solve(bp);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    for (size_t i = 0; i < idx.size(); ++i) z(idx[i]) = zp(Eigen::Index(i));
    return z;
  };
  int iter = 0;
  const int maxIter = 10 * n;
  for (; iter < maxIter; ++iter) {
    const Eigen::VectorXd w = b - K * x;
    int best = -1;
    double bestW = tol;
    for (int i = 0; i < n; ++i)
      if (!passive[size_t(i)] && w(i) > bestW) {
        bestW = w(i);
        best = i;
      }
    if (best < 0) break;  // Kuhn–Tucker conditions hold
    passive[size_t(best)] = true;
    Eigen::VectorXd z = solvePassive();
    for (int inner = 0; inner < n + 1; ++inner) {
      bool feasible = true;
      double alpha = 1.0;
      for (int i = 0; i < n; ++i)
        if (passive[size_t(i)] && z(i) <= 0.0) {
          feasible = false;
          const double d = x(i) - z(i);
          if (d > 0.0) alpha = std::min(alpha, x(i) / d);
        }
      if (feasible) break;
      x += alpha * (z - x);
      for (int i = 0; i < n; ++i)
        if (passive[size_t(i)] && x(i) <= 1e-15 * std::max(1.0, x.cwiseAbs().maxCoeff())) {
          passive[size_t(i)] = false;
          x(i) = 0.0;
        }
      z = solvePassive();
    }
    x = z;
    for (int i = 0; i < n; ++i)
      if (!passive[size_t(i)]) x(i) = 0.0;
  }
  if (iterations) *iterations = iter;
  std::vector<double> out(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) out[size_t(i)] = std::max(0.0, x(i));
  return out;
}

SrbfFit fitSrbfFromSums(const SrbfBasis& basis, const SrbfNormalEquations& eq) {
  const int n = basis.count();
  if (eq.count != n || eq.gram.size() != size_t(n * n) || eq.rhs.size() != size_t(n))
    throw std::invalid_argument("fitSrbfFromSums: the normal equations do not match the basis");
  SrbfFit fit;
  fit.basis = basis;
  fit.equations = eq;
  for (int j = 0; j < FT_SRBF_LOBES; ++j) {
    fit.environment.lobes[j].axisLambda = basis.axisLambda[j];
    fit.environment.lobes[j].weight = glm::vec4(0.0f);
  }
  fit.environment.constant = glm::vec4(0.0f);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> rhs(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) rhs[size_t(i)] = eq.rhs[size_t(i)][c];
    int it = 0;
    const std::vector<double> w = solveNnlsNormal(eq.gram, rhs, n, &it);
    fit.nnlsIterations += it;
    for (int j = 0; j < FT_SRBF_LOBES; ++j) fit.environment.lobes[j].weight[c] = float(w[size_t(j)]);
    if (basis.constantTerm) fit.environment.constant[c] = float(w[FT_SRBF_LOBES]);
  }
  for (int j = 0; j < FT_SRBF_LOBES; ++j)
    fit.activeLobes += glm::any(glm::greaterThan(glm::vec3(fit.environment.lobes[j].weight), glm::vec3(0.0f)));
  return fit;
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
