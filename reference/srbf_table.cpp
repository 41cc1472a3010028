// srbf_table.cpp — the I_M table by the analytic reduction (see srbf_table.h).
#include "reference/srbf_table.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ft {

double besselI0eDouble(double x) {
  x = std::abs(x);
  if (x < 20.0) {
    // I0(x) = Σ_k ((x/2)^{2k} / (k!)²): all terms positive, no cancellation;
    // the terms fall below 1e-17 of the sum by k ≈ 2x + 20.
    const double q = 0.25 * x * x;
    double term = 1.0, sum = 1.0;
    for (int k = 1; k < 200; ++k) {
      term *= q / (double(k) * double(k));
      sum += term;
      if (term < 1e-17 * sum) break;
    }
    return sum * std::exp(-x);
  }
  // I0(x) e^{−x} ~ (2πx)^{−½} Σ_k ((2k − 1)!!)² / (k! 8^k x^k): at x ≥ 20 the
  // terms shrink below 1e-16 before the series starts to diverge (k ≈ 2x).
  const double u = 1.0 / (8.0 * x);
  double term = 1.0, sum = 1.0;
  for (int k = 1; k < 30; ++k) {
    term *= double((2 * k - 1) * (2 * k - 1)) * u / k;
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return sum / std::sqrt(2.0 * M_PI * x);
}

LobeValues srbfConvolutionCpu(const FabricParams& p, double thetaO, double thetaJ, double deltaPhi, double lambda,
                              double* errorEstimate) {
  if (!(lambda >= 0.0) || !std::isfinite(lambda)) throw std::invalid_argument("srbfConvolutionCpu: λ must be ≥ 0");
  const float to = float(thetaO);
  const double kappa = p.lobes.y, i0eKappa = besselI0eDouble(kappa);
  const double cj = std::cos(thetaJ), sj = std::sin(thetaJ), cosDphi = std::cos(deltaPhi);
  const vec3 colorR(p.colorR), colorTT(p.colorTT);
  const auto integrand = [&](double x) {
    const float ti = float(x);
    const vec3 F = ftFiberFresnel(colorR, ti);
    const double mR = ftLongitudinal(ti, to, p.colorR.w), mTT = ftLongitudinal(ti, to, p.colorTT.w);
    const double ci = std::cos(double(ti)), si = std::sin(double(ti));
    const double measure = double(ftSrbfCosine(ti)) * ci;  // eq. 15's cos θ_i × dω's cos θ_i
    const double c = ci * cj, s = si * sj, lc = lambda * c;
    const double azR = besselI0eDouble(lc) * std::exp(lambda * (c + s - 1.0));
    const double lm = std::sqrt(std::max(0.0, kappa * kappa + lc * lc - 2.0 * kappa * lc * cosDphi));
    const double azTT = besselI0eDouble(lm) / i0eKappa * std::exp(lm - kappa + lambda * (s - 1.0));
    LobeValues v;
    v.r = glm::dvec3(F) * (mR * azR * measure);
    v.tt = glm::dvec3((vec3(1.0f) - F) * colorTT) * (mTT * azTT * measure);
    return v;
  };
  const double halfPi = 0.5 * M_PI, window = double(kFtLobeWindow);
  std::vector<double> cuts = {-halfPi, halfPi, -thetaO, thetaJ};
  for (double beta : {double(p.colorR.w), double(p.colorTT.w)}) {
    cuts.push_back(-thetaO - window * beta);
    cuts.push_back(-thetaO + window * beta);
    cuts.push_back(halfPi - window * beta);  // Z: closed form inside, quadrature outside
    cuts.push_back(-(halfPi - window * beta));
  }
  // The SG's factor e^{λ(cos(θ_i − θ_j) − 1)} ≈ e^{−λ(θ_i − θ_j)²/2}: width 1/√λ about θ_j.
  const double sgWidth = lambda > 0.0 ? 1.0 / std::sqrt(lambda) : 10.0;
  for (double k : {2.0, 4.0, 8.0}) {
    cuts.push_back(thetaJ - k * sgWidth);
    cuts.push_back(thetaJ + k * sgWidth);
  }
  std::erase_if(cuts, [&](double x) { return !(x >= -halfPi && x <= halfPi); });
  const double minWidth =
      (1.0 / 16.0) * std::min({double(p.colorR.w), double(p.colorTT.w), sgWidth});
  const LobeIntegral acc = integrateLobesAdaptive(integrand, cuts, minWidth);
  if (errorEstimate) {
    double e = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double total = acc.value.r[c] + acc.value.tt[c];
      if (total > 0.0) e = std::max(e, (acc.error.r[c] + acc.error.tt[c]) / total);
    }
    *errorEstimate = e;
  }
  return acc.value;
}

std::vector<glm::vec3> SrbfTableCpu::asFloat() const { return std::vector<glm::vec3>(values.begin(), values.end()); }

SrbfTableCpu bakeSrbfTableCpu(const FabricParams& fabric, glm::ivec4 dims) {
  if (glm::any(glm::lessThan(dims, glm::ivec4(2)))) throw std::invalid_argument("bakeSrbfTableCpu: every axis needs 2 values");
  SrbfTableCpu out;
  out.dims = dims;
  const int n = ftSrbfTableSize(dims);
  out.values.resize(static_cast<size_t>(n));
  std::vector<double> errors(size_t(n), 0.0);
  tbb::parallel_for(0, n, [&](int i) {
    const ivec4 k = ftSrbfTableTexel(dims, i);
    const LobeValues v = srbfConvolutionCpu(fabric, ftSrbfTableTheta(k.x, dims.x), ftSrbfTableTheta(k.y, dims.y),
                                            ftSrbfTableDeltaPhi(k.z, dims.z), ftSrbfTableLambda(k.w, dims.w),
                                            &errors[size_t(i)]);
    out.values[size_t(i)] = v.r + v.tt;
  });
  out.errorEstimate = *std::max_element(errors.begin(), errors.end());
  out.errors = std::move(errors);
  return out;
}

glm::vec3 lookupSrbfTableCpu(std::span<const glm::vec3> table, glm::ivec4 dims, float thetaO, float thetaJ,
                             float deltaPhi, float lambda) {
  if (table.size() != size_t(ftSrbfTableSize(dims))) throw std::invalid_argument("lookupSrbfTableCpu: table size");
  const vec4 u = ftSrbfTableLookup(dims, thetaO, thetaJ, deltaPhi, lambda);
  glm::vec3 sum(0.0f);
  for (int c = 0; c < 16; ++c) {
    const vec2 tap = ftSrbfTableTap(dims, u, c);
    sum += tap.y * table[size_t(tap.x)];
  }
  return sum;
}

}  // namespace ft
