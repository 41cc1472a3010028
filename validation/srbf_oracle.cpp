// srbf_oracle.cpp — see srbf_oracle.h. No common/ include here.
#include "validation/case_support.h"
#include "validation/srbf_oracle.h"

#include <algorithm>
#include <cmath>

namespace ft::oracle {
namespace {
}

glm::dvec3 equirectDirection(int x, int y, int width, int height) {
  const double theta = kPi * (y + 0.5) / height, phi = 2.0 * kPi * (x + 0.5) / width - kPi;
  return {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
}

double equirectSolidAngle(int y, int width, int height) {
  return 2.0 * kPi / width * (std::cos(kPi * y / height) - std::cos(kPi * (y + 1) / height));
}

glm::dvec3 fibonacciPoint(int j, int n) {
  const double golden = 0.5 * (1.0 + std::sqrt(5.0));
  const double y = 1.0 - (2.0 * j + 1.0) / n;
  double frac = j * (golden - 1.0);
  frac -= std::floor(frac);
  const double phi = 2.0 * kPi * frac, r = std::sqrt(std::max(0.0, 1.0 - y * y));
  return {r * std::cos(phi), y, r * std::sin(phi)};
}

double sphericalGaussian(glm::dvec3 mu, double lambda, glm::dvec3 w) { return std::exp(lambda * (glm::dot(mu, w) - 1.0)); }

double sgIntegral(double lambda) { return lambda <= 0.0 ? 4.0 * kPi : 2.0 * kPi * (-std::expm1(-2.0 * lambda)) / lambda; }

double sgProductIntegral(glm::dvec3 muA, double lambdaA, glm::dvec3 muB, double lambdaB) {
  const double d = glm::length(lambdaA * muA + lambdaB * muB);
  return std::exp(d - lambdaA - lambdaB) * sgIntegral(d);
}

double srbfTableTheta(int k, int n) { return std::asin(-1.0 + 2.0 * k / (n - 1)); }
double srbfTableDeltaPhi(int k, int n) { return kPi * k / (n - 1); }
double srbfTableLambda(int k, int n) { return 0.5 * std::pow(1024.0, double(k) / (n - 1)); }

glm::dvec4 srbfTableCoords(glm::ivec4 dims, double thetaO, double thetaJ, double deltaPhi, double lambda) {
  double p = std::fmod(std::abs(deltaPhi), 2.0 * kPi);
  if (p > kPi) p = 2.0 * kPi - p;
  const double l = std::log(std::clamp(lambda, 0.5, 512.0) / 0.5) / std::log(1024.0);
  const glm::dvec4 u((std::sin(thetaO) + 1.0) / 2.0 * (dims.x - 1), (std::sin(thetaJ) + 1.0) / 2.0 * (dims.y - 1),
                     p / kPi * (dims.z - 1), l * (dims.w - 1));
  return glm::clamp(u, glm::dvec4(0.0), glm::dvec4(dims) - 1.0);
}

glm::dvec3 srbfTableInterpolate(std::span<const glm::vec3> table, glm::ivec4 dims, glm::dvec4 u) {
  int lo[4];
  double frac[4];
  for (int a = 0; a < 4; ++a) {
    lo[a] = std::min(int(std::floor(u[a])), dims[a] - 2);
    frac[a] = u[a] - lo[a];
  }
  glm::dvec3 sum(0.0);
  for (int o = 0; o < 2; ++o)
    for (int j = 0; j < 2; ++j)
      for (int p = 0; p < 2; ++p)
        for (int l = 0; l < 2; ++l) {
          const double w = (o ? frac[0] : 1 - frac[0]) * (j ? frac[1] : 1 - frac[1]) * (p ? frac[2] : 1 - frac[2]) *
                           (l ? frac[3] : 1 - frac[3]);
          const size_t idx =
              size_t(((lo[0] + o) * dims.y + (lo[1] + j)) * dims.z + (lo[2] + p)) * size_t(dims.w) + size_t(lo[3] + l);
          sum += w * glm::dvec3(table[idx]);
        }
  return sum;
}

namespace {

// Gauss–Legendre nodes over [a, b] split at the cuts, each piece in panels no
// wider than width(midpoint).
template <class Width>
Nodes pieceNodes(double a, double b, std::vector<double> cuts, Width width, int n) {
  cuts.push_back(a);
  cuts.push_back(b);
  std::erase_if(cuts, [&](double x) { return !(x >= a && x <= b); });
  std::sort(cuts.begin(), cuts.end());
  Nodes out;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    if (!(cuts[i + 1] > cuts[i])) continue;
    const Nodes q = panelNodes(cuts[i], cuts[i + 1], {}, width(0.5 * (cuts[i] + cuts[i + 1])), n);
    out.x.insert(out.x.end(), q.x.begin(), q.x.end());
    out.w.insert(out.w.end(), q.w.begin(), q.w.end());
  }
  return out;
}

}  // namespace

glm::dvec3 srbfConvolution(const Fabric& f, double thetaO, double thetaJ, double deltaPhi, double lambda) {
  const double bR = f.betaR(), bT = f.betaTT(), k = f.kappa();
  const double sg = lambda > 0.0 ? 1.0 / std::sqrt(lambda) : 100.0;
  const Nodes qt = pieceNodes(
      -0.5 * kPi, 0.5 * kPi,
      {-thetaO, -thetaO - 8 * bR, -thetaO + 8 * bR, -thetaO - 8 * bT, -thetaO + 8 * bT, thetaJ, thetaJ - 8 * sg,
       thetaJ + 8 * sg},
      [&](double m) {
        double h = 0.2;
        if (std::abs(m + thetaO) < 8 * bR) h = std::min(h, bR / 2);
        if (std::abs(m + thetaO) < 8 * bT) h = std::min(h, bT / 2);
        if (std::abs(m - thetaJ) < 8 * sg) h = std::min(h, sg / 2);
        return h;
      },
      8);
  // The SG's axis at azimuth 0, ω_o at azimuth Δφ, about the fiber axis z.
  const glm::dvec3 mu(std::cos(thetaJ), 0.0, std::sin(thetaJ));
  glm::dvec3 total(0.0);
  const double ttPeak = 1.0 - std::exp(-2.0 * k);  // v(π) − v(0), v = exp(−κ(1 + cos φ))
  for (size_t a = 0; a < qt.x.size(); ++a) {
    const double ti = qt.x[a];
    // f(φ) = R + T·v(φ): the R lobe is flat in φ, TT a von Mises at π; R and
    // T from the oracle's eq. 6 at φ = π and φ = 0.
    const glm::dvec3 fPi = bcsdf(f, ti, thetaO, kPi), f0 = bcsdf(f, ti, thetaO, 0.0);
    const glm::dvec3 T = (fPi - f0) / ttPeak, R = fPi - T;
    const double c = std::cos(ti) * std::cos(thetaJ);
    const double w = c > 0.0 && lambda > 0.0 ? 1.0 / std::sqrt(lambda * c) : 100.0;
    double ttCentre = deltaPhi - kPi;  // where φ = Δφ − ψ = ±π
    if (ttCentre < -kPi) ttCentre += 2 * kPi;
    const Nodes qp = pieceNodes(
        -kPi, kPi, {0.0, -w, w, -4 * w, 4 * w, -8 * w, 8 * w, ttCentre},
        [&](double m) { return std::abs(m) < 8 * w ? std::min(kPi / 8, w / 2) : kPi / 8; }, 8);
    double sR = 0.0, sT = 0.0;
    for (size_t b = 0; b < qp.x.size(); ++b) {
      const double psi = qp.x[b];
      const glm::dvec3 wi(std::cos(ti) * std::cos(psi), std::cos(ti) * std::sin(psi), std::sin(ti));
      const double g = sphericalGaussian(mu, lambda, wi) * qp.w[b];
      sR += g;
      sT += g * vonMisesRelative(k, deltaPhi - psi);
    }
    total += qt.w[a] * std::cos(ti) * std::cos(ti) * (R * sR + T * sT);
  }
  return total;
}

}  // namespace ft::oracle
