// srbf_solve.cpp — see srbf_solve.h (moved from reference/srbf_fit.cpp).
#include "scene/srbf_solve.h"

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

}  // namespace ft
