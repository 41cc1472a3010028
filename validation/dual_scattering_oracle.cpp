// dual_scattering_oracle.cpp — see dual_scattering_oracle.h. Includes nothing from common/.
#include "validation/case_support.h"
#include "validation/dual_scattering_oracle.h"

#include <algorithm>
#include <cmath>

namespace ft::oracle {

namespace {

glm::dvec3 cTT(const Fabric& f) { return {f.colorTT[0], f.colorTT[1], f.colorTT[2]}; }
glm::dvec3 safe(glm::dvec3 v) { return glm::max(v, glm::dvec3(1e-300)); }

double gaussianVar(double x, double v) { return std::exp(-0.5 * x * x / v) / std::sqrt(2.0 * kPi * v); }
}  // namespace

double vonMisesBackFraction(double kappa) {
  const Nodes q = panelNodes(-0.5 * kPi, 0.5 * kPi, {}, kPi, 64);
  double s = 0.0;
  for (size_t k = 0; k < q.x.size(); ++k) s += q.w[k] * std::exp(-kappa * std::cos(q.x[k]));
  return s / (2.0 * kPi * std::cyl_bessel_i(0.0, kappa));
}

DsLobes dsLobes(const Fabric& f, double theta) {
  const glm::dvec3 F = fresnel(f, theta);
  const double q = vonMisesBackFraction(f.kappa());
  const glm::dvec3 tt = (glm::dvec3(1.0) - F) * cTT(f);
  return {0.5 * F, tt * (1.0 - q), 0.5 * F, tt * q};
}

DsRows dsRows(const Fabric& f, const DsLobes& l) {
  DsRows r;
  r.aF = l.aFR + l.aFTT;
  r.aB = l.aBR + l.aBTT;
  const double bR = 0.5 * f.betaR(), bT = 0.5 * f.betaTT();  // Zinke's θ_h units
  r.alphaF = glm::dvec3(0.0);
  r.alphaB = glm::dvec3(0.0);
  r.betaF2 = (l.aFR * bR * bR + l.aFTT * bT * bT) / safe(r.aF);
  r.betaB2 = (l.aBR * bR * bR + l.aBTT * bT * bT) / safe(r.aB);
  for (int c = 0; c < 3; ++c) {
    const double af = r.aF[c], ab = r.aB[c];
    const double d = std::max(1.0 - af * af, 1e-4);
    r.ab[c] = ab * af * af / d + ab * ab * ab * af * af / (d * d * d);  // eq. 14
    r.deltaB[c] = r.alphaB[c] * (1.0 - 2.0 * ab * ab / (d * d)) +
                  r.alphaF[c] * (2.0 * d * d + 4.0 * af * af * ab * ab) / (d * d * d);  // eq. 16
    const double bf2 = r.betaF2[c], bb2 = r.betaB2[c];
    const double sigma = (1.0 + kDsDensity * af * af) *
                         (ab * std::sqrt(2.0 * bf2 + bb2) + ab * ab * ab * std::sqrt(2.0 * bf2 + 3.0 * bb2)) /
                         (ab + ab * ab * ab * (2.0 * std::sqrt(bf2) + 3.0 * std::sqrt(bb2)));  // eq. 17
    r.sigmaB2[c] = sigma * sigma;
  }
  return r;
}

DsRows lerpRows(std::span<const DsRows> table, double theta) {
  const int n = int(table.size());
  const double u = std::clamp((theta + 0.5 * kPi) / kPi * n - 0.5, 0.0, double(n - 1));
  const int k0 = std::min(int(std::floor(u)), n - 2);
  const double w = u - k0;
  const DsRows& a = table[size_t(k0)];
  const DsRows& b = table[size_t(k0 + 1)];
  const auto l = [w](glm::dvec3 x, glm::dvec3 y) { return x * (1.0 - w) + y * w; };
  return {l(a.aF, b.aF),         l(a.aB, b.aB),         l(a.alphaF, b.alphaF),
          l(a.alphaB, b.alphaB), l(a.betaF2, b.betaF2), l(a.betaB2, b.betaB2),
          l(a.ab, b.ab),         l(a.deltaB, b.deltaB), l(a.sigmaB2, b.sigmaB2)};
}

DsFrameValue dsFrame(const Fabric& f, const DsRows& t, double thetaI, double thetaO, double phi, double visibility,
                     double fibers) {
  DsFrameValue r;
  const double thetaH = 0.5 * (thetaI + thetaO), thetaD = 0.5 * (thetaO - thetaI);
  const double c2 = std::max(std::cos(thetaD) * std::cos(thetaD), 1e-4);
  const glm::dvec3 F = fresnel(f, thetaI), aTT = (glm::dvec3(1.0) - F) * cTT(f);
  const double betaZ[2] = {0.5 * f.betaR(), 0.5 * f.betaTT()};
  for (int c = 0; c < 3; ++c) {
    r.transmittance[c] = kDsDensity * std::pow(t.aF[c], fibers);
    r.forwardVariance[c] = fibers * t.betaF2[c];
    r.backDirect[c] = 2.0 * t.ab[c] * gaussianVar(thetaH - t.deltaB[c], t.sigmaB2[c]) / (kPi * c2);
    r.backScattered[c] =
        2.0 * t.ab[c] * gaussianVar(thetaH - t.deltaB[c], t.sigmaB2[c] + r.forwardVariance[c]) / (kPi * c2);
    double m[2];
    for (int p = 0; p < 2; ++p) {
      const double b = std::sqrt(betaZ[p] * betaZ[p] + r.forwardVariance[c]);  // θ_h units
      m[p] = gaussianVar(thetaH, b * b) / (2.0 * lobeNorm(2.0 * b, thetaI));
    }
    r.forwardScattered[c] = (F[c] * m[0] + aTT[c] * m[1]) / (2.0 * kPi);
  }
  const glm::dvec3 f0 = bcsdf(f, thetaI, thetaO, phi);
  r.value = visibility * (f0 + kDsDensity * r.backDirect) +
            (1.0 - visibility) * r.transmittance * (r.forwardScattered + kPi * kDsDensity * r.backScattered);
  return r;
}

DsLobes dsLobesByQuadrature(const Fabric& f, double theta) {
  const double bR = f.betaR(), bT = f.betaTT();
  const Nodes qo = panelNodes(-0.5 * kPi, 0.5 * kPi,
                              {-theta - 8.0 * bR, -theta, -theta + 8.0 * bR, -theta - 8.0 * bT, -theta + 8.0 * bT},
                              std::min(bR, bT) / 2.0, 8);
  const Nodes qf = panelNodes(0.5 * kPi, kPi, {}, kPi, 32), qb = panelNodes(0.0, 0.5 * kPi, {}, kPi, 32);
  // Eq. 6 lobe by lobe, Z once per lobe (θ is fixed).
  const glm::dvec3 F = fresnel(f, theta), aTT = (glm::dvec3(1.0) - F) * cTT(f);
  const double zR = lobeNorm(bR, theta), zT = lobeNorm(bT, theta), k = f.kappa();
  const double i0 = std::cyl_bessel_i(0.0, k);
  DsLobes out{glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  for (size_t i = 0; i < qo.x.size(); ++i) {
    const double c2 = std::cos(qo.x[i]) * std::cos(qo.x[i]);
    const double mR = gaussianVar(theta + qo.x[i], bR * bR) / zR, mT = gaussianVar(theta + qo.x[i], bT * bT) / zT;
    for (int h = 0; h < 2; ++h) {
      const Nodes& qp = h == 0 ? qf : qb;
      for (size_t j = 0; j < qp.x.size(); ++j) {
        const double w = 2.0 * qo.w[i] * qp.w[j] * c2;  // 2: the mirror half φ → −φ
        const double nTT = std::exp(k * std::cos(qp.x[j] - kPi)) / (2.0 * kPi * i0);
        (h == 0 ? out.aFR : out.aBR) += w * F * (mR / (2.0 * kPi));
        (h == 0 ? out.aFTT : out.aBTT) += w * aTT * (mT * nTT);
      }
    }
  }
  return out;
}

}  // namespace ft::oracle
