// bcsdf_oracle.cpp — see bcsdf_oracle.h. Includes nothing from common/.
#include "validation/bcsdf_oracle.h"
#include "validation/case_support.h"

#include <algorithm>
#include <cmath>

namespace ft::oracle {

namespace {
constexpr double kDeg = kPi / 180.0;
}  // namespace

double Fabric::betaR() const { return betaRDegrees * kDeg; }
double Fabric::betaTT() const { return betaTTDegrees * kDeg; }
double Fabric::kappa() const {
  const double gamma = gammaTTDegrees * kDeg;
  return 1.0 / (gamma * gamma);
}

glm::dvec3 fresnel(const Fabric& f, double thetaI) {
  const double m = 1.0 - std::abs(std::cos(thetaI));
  const double m5 = m * m * m * m * m;
  return {f.colorR[0] + (1.0 - f.colorR[0]) * m5, f.colorR[1] + (1.0 - f.colorR[1]) * m5,
          f.colorR[2] + (1.0 - f.colorR[2]) * m5};
}

glm::dvec3 albedo(const Fabric& f, double thetaI) {
  const glm::dvec3 F = fresnel(f, thetaI);
  return F + (glm::dvec3(1.0) - F) * glm::dvec3(f.colorTT[0], f.colorTT[1], f.colorTT[2]);
}

double vonMisesRelative(double kappa, double phi) { return std::exp(-kappa * (1.0 + std::cos(phi))); }

double gaussianRelative(double beta, double thetaI, double thetaO) {
  const double r = (thetaI + thetaO) / beta;
  return std::exp(-0.5 * r * r);
}

double simpleSpecular(double ks, double beta, double thetaI, double thetaO, double phi) {
  const double h = 0.5 * (thetaI + thetaO) / beta;
  return ks * std::cos(0.5 * phi) * std::exp(-0.5 * h * h);
}

glm::dvec3 lerpTable(std::span<const glm::vec3> table, double thetaO) {
  const int n = int(table.size());
  const double u = std::clamp((thetaO + 0.5 * kPi) / kPi * n - 0.5, 0.0, double(n - 1));
  const int k0 = std::min(int(std::floor(u)), n - 2);
  const double w = u - k0;
  return glm::dvec3(table[size_t(k0)]) * (1.0 - w) + glm::dvec3(table[size_t(k0 + 1)]) * w;
}

Rule gaussLegendre(int n) {
  Rule r;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
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
    r.x.push_back(x);
    r.w.push_back(2.0 / ((1.0 - x * x) * dp * dp));
  }
  return r;
}

Nodes panelNodes(double a, double b, std::vector<double> cuts, double maxPanel, int n) {
  const Rule rule = gaussLegendre(n);
  cuts.push_back(a);
  cuts.push_back(b);
  std::erase_if(cuts, [&](double x) { return !(x >= a && x <= b); });
  std::sort(cuts.begin(), cuts.end());
  Nodes out;
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double len = cuts[i + 1] - cuts[i];
    if (len <= 0.0) continue;
    const int panels = std::max(1, int(std::ceil(len / maxPanel)));
    const double h = len / panels;
    for (int p = 0; p < panels; ++p) {
      const double c = cuts[i] + (p + 0.5) * h;
      for (size_t k = 0; k < rule.x.size(); ++k) {
        out.x.push_back(c + 0.5 * h * rule.x[k]);
        out.w.push_back(0.5 * h * rule.w[k]);
      }
    }
  }
  return out;
}

namespace {

double gaussian(double x, double beta) { return std::exp(-0.5 * x * x / (beta * beta)) / (std::sqrt(2.0 * kPi) * beta); }

}  // namespace

// Over the lobe's ±8β (the rest is below e^−32 of its peak), in panels of β/2.
double lobeNorm(double beta, double thetaI) {
  const double a = std::max(-0.5 * kPi, -thetaI - 8.0 * beta), b = std::min(0.5 * kPi, -thetaI + 8.0 * beta);
  if (b <= a) return 0.0;
  const Nodes q = panelNodes(a, b, {-thetaI}, beta / 2.0, 8);
  double z = 0.0;
  for (size_t k = 0; k < q.x.size(); ++k) z += q.w[k] * gaussian(q.x[k] + thetaI, beta) * std::cos(q.x[k]) * std::cos(q.x[k]);
  return z;
}

namespace {

// θ = asin(ω·t); φ from the parts of ω_i and ω_o perpendicular to t.
void localAngles(glm::dvec3 t, glm::dvec3 wi, glm::dvec3 wo, double& thetaI, double& thetaO, double& phi) {
  thetaI = std::asin(std::clamp(glm::dot(wi, t), -1.0, 1.0));
  thetaO = std::asin(std::clamp(glm::dot(wo, t), -1.0, 1.0));
  const glm::dvec3 pi = wi - glm::dot(wi, t) * t, po = wo - glm::dot(wo, t) * t;
  const double d = glm::length(pi) * glm::length(po);
  phi = d > 0.0 ? std::acos(std::clamp(glm::dot(pi, po) / d, -1.0, 1.0)) : 0.0;
}

}  // namespace

glm::dvec3 bcsdf(const Fabric& f, double thetaI, double thetaO, double phi) {
  const glm::dvec3 F = fresnel(f, thetaI);
  const double mR = gaussian(thetaI + thetaO, f.betaR()) / lobeNorm(f.betaR(), thetaI);
  const double mTT = gaussian(thetaI + thetaO, f.betaTT()) / lobeNorm(f.betaTT(), thetaI);
  const double k = f.kappa();
  const double nTT = std::exp(k * std::cos(phi - kPi)) / (2.0 * kPi * std::cyl_bessel_i(0.0, k));
  const glm::dvec3 cTT(f.colorTT[0], f.colorTT[1], f.colorTT[2]);
  return F * (mR / (2.0 * kPi)) + (glm::dvec3(1.0) - F) * cTT * (mTT * nTT);
}

glm::dvec3 ambientIntegral(const Fabric& f, double thetaO) {
  const double bR = f.betaR(), bT = f.betaTT();
  const Nodes q = panelNodes(-0.5 * kPi, 0.5 * kPi,
                             {-thetaO - 8.0 * bR, -thetaO, -thetaO + 8.0 * bR, -thetaO - 8.0 * bT, -thetaO + 8.0 * bT},
                             bR / 2.0, 8);
  const glm::dvec3 cTT(f.colorTT[0], f.colorTT[1], f.colorTT[2]);
  glm::dvec3 a(0.0);
  for (size_t k = 0; k < q.x.size(); ++k) {
    const double ti = q.x[k];
    const glm::dvec3 F = fresnel(f, ti);
    const double mR = gaussian(ti + thetaO, bR) / lobeNorm(bR, ti);
    const double mTT = gaussian(ti + thetaO, bT) / lobeNorm(bT, ti);
    a += q.w[k] * std::cos(ti) * std::cos(ti) * (F * mR + (glm::dvec3(1.0) - F) * cTT * mTT);
  }
  return a;
}

glm::dvec3 fiberRadiance(const Fabric& f, const Lighting& l, glm::dvec3 t, glm::dvec3 n, glm::dvec3 wo) {
  double thetaI = 0, thetaO = 0, phi = 0;
  localAngles(t, l.toLight, wo, thetaI, thetaO, phi);
  const glm::dvec3 direct =
      l.irradiance * ((glm::dvec3(1.0) - l.diffuse) * bcsdf(f, thetaI, thetaO, phi) * std::cos(thetaI) +
                      l.diffuse * (std::max(glm::dot(n, l.toLight), 0.0) / kPi));
  return direct + l.ambient * ((glm::dvec3(1.0) - l.diffuse) * ambientIntegral(f, thetaO) + l.diffuse);
}

}  // namespace ft::oracle
