// dual_scattering.cpp — the CPU dual-scattering tables and per-frame function
// (see dual_scattering.h).
#include "reference/dual_scattering.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <stdexcept>

#include "reference/quadrature.h"

namespace ft {
namespace {

// The Gauss–Kronrod 7/15 rule (kXk, kWk, kWg) and where to stop bisecting: reference/quadrature.h.
// A piece is resolved when |K15 − G7| is below 1e-10 (absolute: the lobe
// integrals are fractions of an albedo ≤ 1, so this is ≤ 1e-9 of any ā above
// 0.1) or below the float rounding of the integrand (8 ε of ∫|f|), or when it
// is narrower than 1/16 of the narrowest lobe (K15 is then exact for the
// smooth Gaussian to double precision; what is left is rounding).
constexpr double kPieceTolerance = 1e-10;
constexpr int kPhiNodes = 32;

using Values = std::array<double, 12>;  // a_{f,R}, a_{f,TT}, a_{b,R}, a_{b,TT} × rgb

struct Rule {
  std::array<double, kPhiNodes> x, w;
};
// n-point Gauss–Legendre on [−1, 1] (Newton on P_n).
Rule gaussLegendre() {
  Rule r;
  const int n = kPhiNodes;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    r.x[size_t(i)] = x;
    r.w[size_t(i)] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
  return r;
}

struct Texel {
  const FabricParams& p;
  float theta;
  vec2 z;  // (Z_R, Z_TT) at θ
  const Rule& rule;
  size_t evaluations = 0;

  // ∫ over φ of the integrands at θ_o, on both halves.
  Values at(double thetaO) {
    Values v{};
    const vec2 ranges[2] = {ftDsForwardPhiRange(), ftDsBackwardPhiRange()};
    for (int h = 0; h < 2; ++h) {
      const double c = 0.5 * (double(ranges[h].x) + ranges[h].y), half = 0.5 * (double(ranges[h].y) - ranges[h].x);
      for (int j = 0; j < kPhiNodes; ++j) {
        const float phi = float(c + half * rule.x[size_t(j)]);
        const glm::dvec3 r(ftDsIntegrandR(p, theta, float(thetaO), phi, z.x));
        const glm::dvec3 t(ftDsIntegrandTT(p, theta, float(thetaO), phi, z.y));
        for (int ch = 0; ch < 3; ++ch) {
          v[size_t(6 * h + ch)] += half * rule.w[size_t(j)] * r[ch];
          v[size_t(6 * h + 3 + ch)] += half * rule.w[size_t(j)] * t[ch];
        }
      }
    }
    evaluations += 2 * 2 * kPhiNodes;
    return v;
  }

  // Recursive adaptive G7–K15 over [a, b]; adds the value and |K − G| to out.
  void integrate(double a, double b, double minWidth, Values& value, Values& error) {
    const double c = 0.5 * (a + b), h = 0.5 * (b - a);
    Values k{}, g{}, absK{};
    const Values fc = at(c);
    for (size_t i = 0; i < 12; ++i) {
      k[i] = kWk[7] * fc[i];
      g[i] = kWg[3] * fc[i];
      absK[i] = kWk[7] * std::abs(fc[i]);
    }
    for (int j = 0; j < 7; ++j) {
      const Values f1 = at(c - h * kXk[j]), f2 = at(c + h * kXk[j]);
      for (size_t i = 0; i < 12; ++i) {
        k[i] += kWk[j] * (f1[i] + f2[i]);
        absK[i] += kWk[j] * (std::abs(f1[i]) + std::abs(f2[i]));
        if (j % 2 == 1) g[i] += kWg[j / 2] * (f1[i] + f2[i]);
      }
    }
    bool done = b - a <= minWidth;
    for (size_t i = 0; i < 12 && !done; ++i) {
      const double e = std::abs(k[i] - g[i]) * h;
      if (e > kPieceTolerance && e > kIntegrandRounding * absK[i] * h) break;
      if (i == 11) done = true;
    }
    if (!done) {
      integrate(a, c, minWidth, value, error);
      integrate(c, b, minWidth, value, error);
      return;
    }
    for (size_t i = 0; i < 12; ++i) {
      value[i] += k[i] * h;
      error[i] += std::abs(k[i] - g[i]) * h;
    }
  }
};

}  // namespace

void dsTexelRows(const DsTexel& t, glm::vec4* out) {
  const vec3 rows[FT_DS_ROWS] = {t.aF, t.aB, t.alphaF, t.alphaB, t.betaF2, t.betaB2, t.ab, t.deltaB, t.sigmaB2};
  for (int r = 0; r < FT_DS_ROWS; ++r) out[r] = glm::vec4(rows[r], 0.0f);
}

DsTexel dsTexelOf(std::span<const glm::vec4> rows, int k) {
  const glm::vec4* v = rows.data() + size_t(k) * FT_DS_ROWS;
  DsTexel t;
  t.aF = vec3(v[FT_DS_ROW_A_F]);
  t.aB = vec3(v[FT_DS_ROW_A_B]);
  t.alphaF = vec3(v[FT_DS_ROW_ALPHA_F]);
  t.alphaB = vec3(v[FT_DS_ROW_ALPHA_B]);
  t.betaF2 = vec3(v[FT_DS_ROW_BETA_F2]);
  t.betaB2 = vec3(v[FT_DS_ROW_BETA_B2]);
  t.ab = vec3(v[FT_DS_ROW_AB]);
  t.deltaB = vec3(v[FT_DS_ROW_DELTA_B]);
  t.sigmaB2 = vec3(v[FT_DS_ROW_SIGMA_B2]);
  return t;
}

DsTexel lookupDsCpu(std::span<const glm::vec4> rows, float theta) {
  const int n = int(rows.size() / FT_DS_ROWS);
  if (n < 2 || rows.size() % FT_DS_ROWS != 0) throw std::invalid_argument("lookupDsCpu: not a table of >= 2 texels");
  const vec3 l = ftDsLookup(theta, n);
  return ftDsMix(dsTexelOf(rows, int(l.x)), dsTexelOf(rows, int(l.y)), l.z);
}

DsTableCpu bakeDualScatteringCpu(const FabricParams& fabric, int texels) {
  if (texels < 2) throw std::invalid_argument("bakeDualScatteringCpu: need at least 2 texels");
  const Rule rule = gaussLegendre();
  const double halfPi = 0.5 * M_PI, window = double(kFtLobeWindow);
  const double betas[2] = {double(fabric.colorR.w), double(fabric.colorTT.w)};
  const double minWidth = kMinPieceLobes * std::min(betas[0], betas[1]);
  DsTableCpu out;
  out.texels = texels;
  out.aFR.resize(size_t(texels));
  out.aFTT.resize(size_t(texels));
  out.aBR.resize(size_t(texels));
  out.aBTT.resize(size_t(texels));
  out.rows.resize(size_t(texels) * FT_DS_ROWS);
  std::vector<double> errors(size_t(texels), 0.0);
  std::vector<size_t> evaluations(size_t(texels), 0);
  tbb::parallel_for(0, texels, [&](int k) {
    const float theta = ftDsTexelAngle(k, texels);
    Texel t{fabric, theta, ftLobeNorms(fabric, theta), rule};
    std::vector<double> cuts = {-halfPi, halfPi, -double(theta)};
    for (double beta : betas) {
      cuts.push_back(-double(theta) - window * beta);
      cuts.push_back(-double(theta) + window * beta);
    }
    std::erase_if(cuts, [&](double x) { return !(x >= -halfPi && x <= halfPi); });
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end(), [](double a, double b) { return b - a < 1e-12; }), cuts.end());
    Values value{}, error{};
    for (size_t i = 0; i + 1 < cuts.size(); ++i) t.integrate(cuts[i], cuts[i + 1], minWidth, value, error);
    const size_t kk = size_t(k);
    for (int c = 0; c < 3; ++c) {
      out.aFR[kk][c] = value[size_t(c)];
      out.aFTT[kk][c] = value[size_t(3 + c)];
      out.aBR[kk][c] = value[size_t(6 + c)];
      out.aBTT[kk][c] = value[size_t(9 + c)];
      const double total = value[size_t(c)] + value[size_t(3 + c)] + value[size_t(6 + c)] + value[size_t(9 + c)];
      const double e = error[size_t(c)] + error[size_t(3 + c)] + error[size_t(6 + c)] + error[size_t(9 + c)];
      if (total > 0.0) errors[kk] = std::max(errors[kk], e / total);
    }
    const DsTexel texel = ftDsTexelFromLobes(fabric, vec3(out.aFR[kk]), vec3(out.aFTT[kk]), vec3(out.aBR[kk]),
                                             vec3(out.aBTT[kk]));
    dsTexelRows(texel, out.rows.data() + kk * FT_DS_ROWS);
    evaluations[kk] = t.evaluations;
  });
  for (int k = 0; k < texels; ++k) {
    out.errorEstimate = std::max(out.errorEstimate, errors[size_t(k)]);
    out.evaluations += evaluations[size_t(k)];
  }
  return out;
}

std::vector<DsFrame> evaluateDsCpu(const FabricParams& fabric, std::span<const glm::vec4> rows,
                                   std::span<const DsRequest> requests) {
  std::vector<DsFrame> out(requests.size());
  for (size_t i = 0; i < requests.size(); ++i) {
    const DsRequest& q = requests[i];
    out[i] = ftDsEvaluate(fabric, lookupDsCpu(rows, ftDsThetaD(q.angles)), q.angles, q.visibility, q.fibers);
  }
  return out;
}

}  // namespace ft
