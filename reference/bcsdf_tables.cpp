// bcsdf_tables.cpp — CPU evaluation of the shared BCSDF and the ambient table
// of 000 §4.3 eq. 7–10 (see bcsdf_tables.h).
#include "reference/bcsdf_tables.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "reference/quadrature.h"

namespace ft {

std::vector<glm::vec3> evaluateBcsdfCpu(const FabricParams& fabric, std::span<const FiberAngles> angles,
                                        BcsdfLobes lobes) {
  std::vector<glm::vec3> out(angles.size());
  for (size_t i = 0; i < angles.size(); ++i)
    out[i] = lobes == BcsdfLobes::R    ? ftBcsdfR(fabric, angles[i])
             : lobes == BcsdfLobes::TT ? ftBcsdfTT(fabric, angles[i])
                                       : ftBcsdf(fabric, angles[i]);
  return out;
}

std::vector<float> evaluateSimpleSpecularCpu(float ks, float beta, std::span<const FiberAngles> angles) {
  std::vector<float> out(angles.size());
  for (size_t i = 0; i < angles.size(); ++i) out[i] = ftSimpleSpecular(ks, beta, angles[i]);
  return out;
}

std::vector<FiberAngles> fiberAnglesCpu(std::span<const glm::vec3> tangents, std::span<const glm::vec3> wi,
                                        std::span<const glm::vec3> wo) {
  if (wi.size() != tangents.size() || wo.size() != tangents.size())
    throw std::invalid_argument("fiberAnglesCpu: tangents, wi and wo differ in size");
  std::vector<FiberAngles> out(tangents.size());
  for (size_t i = 0; i < tangents.size(); ++i) out[i] = ftFiberAngles(tangents[i], wi[i], wo[i]);
  return out;
}

std::vector<glm::dvec3> AmbientTableCpu::total() const {
  std::vector<glm::dvec3> out(r.size());
  for (size_t k = 0; k < r.size(); ++k) out[k] = r[k] + tt[k];
  return out;
}

namespace {

// The Gauss–Kronrod 7/15 rule (kXk, kWk, kWg) and where to stop bisecting: reference/quadrature.h.

// Requested relative accuracy of each texel's integral.
constexpr double kRelativeTolerance = 1e-9;
// A piece is resolved when its Gauss–Kronrod difference is below
// kIntegrandRounding of ∫|f|, or when it is narrower than kMinPieceLobes of
// the narrowest lobe (reference/quadrature.h says why).
constexpr size_t kMaxPieces = 4000;  // per texel, a safeguard
using Lobe = LobeValues;

struct Piece {
  Lobe value, error, absValue;
};

// The integrand of eq. 8 (R and TT parts) at θ_i, from the shared functions.
Lobe integrand(const FabricParams& p, float thetaO, double thetaI) {
  const float ti = float(thetaI);
  const vec3 f = ftFiberFresnel(vec3(p.colorR), ti);
  const double c = std::cos(double(ti));
  const double c2 = c * c;
  const double mR = ftLongitudinal(ti, thetaO, p.colorR.w), mTT = ftLongitudinal(ti, thetaO, p.colorTT.w);
  Lobe out;
  out.r = glm::dvec3(f) * (mR * c2);
  out.tt = glm::dvec3((vec3(1.0f) - f) * vec3(p.colorTT)) * (mTT * c2);
  return out;
}

using Integrand = std::function<Lobe(double)>;

Piece gaussKronrod(const Integrand& fn, double a, double b) {
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  const Lobe fc = fn(c);
  Lobe k{fc.r * kWk[7], fc.tt * kWk[7]}, g{fc.r * kWg[3], fc.tt * kWg[3]};
  Lobe abs{glm::abs(fc.r) * kWk[7], glm::abs(fc.tt) * kWk[7]};
  for (int j = 0; j < 7; ++j) {
    const double d = h * kXk[j];
    const Lobe f1 = fn(c - d), f2 = fn(c + d);
    k.r += kWk[j] * (f1.r + f2.r);
    k.tt += kWk[j] * (f1.tt + f2.tt);
    abs.r += kWk[j] * (glm::abs(f1.r) + glm::abs(f2.r));
    abs.tt += kWk[j] * (glm::abs(f1.tt) + glm::abs(f2.tt));
    if (j % 2 == 1) {
      g.r += kWg[j / 2] * (f1.r + f2.r);
      g.tt += kWg[j / 2] * (f1.tt + f2.tt);
    }
  }
  return {{k.r * h, k.tt * h}, {glm::abs(k.r - g.r) * h, glm::abs(k.tt - g.tt) * h}, {abs.r * h, abs.tt * h}};
}

struct Interval {
  double a, b;
  Piece piece;
  bool resolved;  // at the integrand's rounding: not bisected again
};

bool resolved(const Piece& p, double a, double b, double minWidth) {
  if (b - a <= minWidth) return true;
  for (int c = 0; c < 3; ++c)
    if (p.error.r[c] > kIntegrandRounding * p.absValue.r[c] || p.error.tt[c] > kIntegrandRounding * p.absValue.tt[c])
      return false;
  return true;
}

// Global adaptive quadrature (QUADPACK QAG's strategy): bisect the piece with
// the largest error, relative to the tolerance of its channel, until the
// summed Gauss–Kronrod estimates of the unresolved pieces are below
// kRelativeTolerance of the integral in every channel.
using Integration = LobeIntegral;

Integration integratePieces(const Integrand& fn, const std::vector<double>& cuts, double minWidth) {
  std::vector<Interval> pieces;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const Piece piece = gaussKronrod(fn, cuts[i], cuts[i + 1]);
    pieces.push_back({cuts[i], cuts[i + 1], piece, resolved(piece, cuts[i], cuts[i + 1], minWidth)});
  }
  const auto sum = [&](bool onlyUnresolved, bool errors) {
    Lobe s{glm::dvec3(0.0), glm::dvec3(0.0)};
    for (const Interval& v : pieces) {
      if (onlyUnresolved && v.resolved) continue;
      s.r += errors ? v.piece.error.r : v.piece.value.r;
      s.tt += errors ? v.piece.error.tt : v.piece.value.tt;
    }
    return s;
  };
  while (pieces.size() < kMaxPieces) {
    const Lobe total = sum(false, false), open = sum(true, true);
    Lobe tol;
    tol.r = kRelativeTolerance * glm::max(glm::abs(total.r), glm::dvec3(1e-300));
    tol.tt = kRelativeTolerance * glm::max(glm::abs(total.tt), glm::dvec3(1e-300));
    const auto score = [&](const Lobe& e) {
      double s = 0.0;
      for (int c = 0; c < 3; ++c) s = std::max({s, e.r[c] / tol.r[c], e.tt[c] / tol.tt[c]});
      return s;
    };
    if (score(open) <= 1.0) break;
    size_t worst = pieces.size();
    double worstScore = -1.0;
    for (size_t i = 0; i < pieces.size(); ++i)
      if (!pieces[i].resolved && score(pieces[i].piece.error) > worstScore) {
        worst = i;
        worstScore = score(pieces[i].piece.error);
      }
    const double a = pieces[worst].a, b = pieces[worst].b, m = 0.5 * (a + b);
    const Piece left = gaussKronrod(fn, a, m), right = gaussKronrod(fn, m, b);
    pieces[worst] = {a, m, left, resolved(left, a, m, minWidth)};
    pieces.push_back({m, b, right, resolved(right, m, b, minWidth)});
  }
  Integration out;
  out.value = sum(false, false);
  out.error = sum(false, true);
  out.evaluations = 15 * (pieces.size() + (pieces.size() - (cuts.size() - 1)));
  return out;
}

Integration integrateTexel(const FabricParams& p, float thetaO, const std::vector<double>& cuts) {
  const double minWidth = kMinPieceLobes * std::min(double(p.colorR.w), double(p.colorTT.w));
  return integratePieces([&](double x) { return integrand(p, thetaO, x); }, cuts, minWidth);
}

}  // namespace

LobeIntegral integrateLobesAdaptive(const std::function<LobeValues(double)>& f, std::vector<double> cuts,
                                    double minWidth) {
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end(), [](double a, double b) { return b - a < 1e-12; }), cuts.end());
  if (cuts.size() < 2) throw std::invalid_argument("integrateLobesAdaptive: need an interval");
  return integratePieces(f, cuts, minWidth);
}

AmbientTableCpu bakeAmbientTableCpuParts(const FabricParams& fabric, int texels) {
  if (texels < 2) throw std::invalid_argument("bakeAmbientTableCpu: need at least 2 texels");
  const double halfPi = 0.5 * M_PI, window = double(kFtLobeWindow);
  const double betas[2] = {double(fabric.colorR.w), double(fabric.colorTT.w)};
  AmbientTableCpu out;
  out.r.resize(size_t(texels));
  out.tt.resize(size_t(texels));
  for (int k = 0; k < texels; ++k) {
    const float thetaO = ftAmbientTexelAngle(k, texels);
    std::vector<double> cuts = {-halfPi, halfPi, -double(thetaO)};
    for (double beta : betas) {
      cuts.push_back(-double(thetaO) - window * beta);
      cuts.push_back(-double(thetaO) + window * beta);
      cuts.push_back(halfPi - window * beta);  // Z: closed form inside, quadrature outside
      cuts.push_back(-(halfPi - window * beta));
    }
    std::erase_if(cuts, [&](double x) { return !(x >= -halfPi && x <= halfPi); });
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end(), [](double a, double b) { return b - a < 1e-12; }), cuts.end());

    const Integration acc = integrateTexel(fabric, thetaO, cuts);
    out.r[size_t(k)] = acc.value.r;
    out.tt[size_t(k)] = acc.value.tt;
    out.evaluations += acc.evaluations;
    for (int c = 0; c < 3; ++c) {
      const double total = acc.value.r[c] + acc.value.tt[c];
      if (total > 0.0) out.errorEstimate = std::max(out.errorEstimate, (acc.error.r[c] + acc.error.tt[c]) / total);
    }
  }
  return out;
}

std::vector<glm::vec3> bakeAmbientTableCpu(const FabricParams& fabric, int texels) {
  const std::vector<glm::dvec3> total = bakeAmbientTableCpuParts(fabric, texels).total();
  return std::vector<glm::vec3>(total.begin(), total.end());
}

std::vector<glm::vec2> bakeLobeNormTableCpu(const FabricParams& fabric, int texels) {
  if (texels < 2) throw std::invalid_argument("bakeLobeNormTableCpu: a table needs at least 2 texels");
  std::vector<glm::vec2> out(static_cast<size_t>(texels));
  const float betaR = fabric.colorR.w, betaTT = fabric.colorTT.w;
  for (int k = 0; k < texels; ++k)
    out[size_t(k)] = glm::vec2(ftLongitudinalNorm(ftLobeNormTexelAngle(k, texels, betaR), betaR),
                               ftLongitudinalNorm(ftLobeNormTexelAngle(k, texels, betaTT), betaTT));
  return out;
}

glm::vec2 lookupLobeNormCpu(const FabricParams& fabric, std::span<const glm::vec2> table, float thetaI) {
  if (table.size() < 2) throw std::invalid_argument("lookupLobeNormCpu: a table needs at least 2 texels");
  const int n = int(table.size());
  const float betaR = fabric.colorR.w, betaTT = fabric.colorTT.w;
  const glm::vec4 r = ftLobeNormLookup(thetaI, betaR, n), t = ftLobeNormLookup(thetaI, betaTT, n);
  return glm::vec2(ftLobeNormFromTable(r, thetaI, betaR, table[size_t(r.x)].x, table[size_t(r.y)].x),
                   ftLobeNormFromTable(t, thetaI, betaTT, table[size_t(t.x)].y, table[size_t(t.y)].y));
}

}  // namespace ft
