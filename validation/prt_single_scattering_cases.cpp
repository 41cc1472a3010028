// prt_single_scattering_cases.cpp — single scattering of the fabric PRT,
// Khungurn et al. 2017 (004) §5.2, eq. 1–2, App. A (common/
// prt_single_scattering.h, reference/prt_single_scattering.h,
// gpu/prt_single_scattering_gpu.h; docs/prt-single-scattering.md). Path
// "prtss". The expectations come from code written here or in
// validation/bcsdf_oracle.h, never from common/: the BCSDF (Schlick, Gaussian
// lobes normalised by Z(θ_i), von Mises TT with std::cyl_bessel_i), the 2D
// product quadrature of the SG–BCSDF convolution, the image lookup of the
// exact visibility, the Monte Carlo integrand.
//   prt/ss/gamma     Γ of eq. 2 (double) vs a 2D product quadrature of ∫ G S cos dω, over fabric,
//                    λ ∈ {100, 200, 10³, 10⁴}, θ_o, θ′, ϕ′;
//   prt/ss/delta     Γ/M(λ) → S(ξ, ω_o) cos θ_ξ as λ → ∞ (λ = 10⁴ and 10⁶);
//   prt/ss/limits    erf against std::erf, Ṽ_loc's limits 0, ½, 1; the blend equals the pure
//                    branches at λ = 100 and 200 and is continuous there; directional = SSDF sign;
//   prt/ss/furnace   ∫ over light axes of Γ/M = ∫ S cos θ_i dω_i (the oracle's A(θ_o));
//   prt/ss/lone      a lone segment (V ≡ 1): sum of SGs and Γ vs Monte Carlo of eq. 1;
//   prt/ss/exemplar  a plain-weave segment: the full SG light (both visibility
//                    representations and the blend) vs Monte Carlo with its exact binary image;
//   prt/ss/cylinder  a segment beside a parallel cylinder: the SG light vs MC with the exact lune;
//   prt/ss/gpu       the GPU 𝒢 bake vs the CPU's; GPU vs CPU over a 64 × 32 sweep of light axes ×
//                    λ ∈ {10, 50, 100, 150, 200, 400, 10³, 10⁴} (+ directional), fleece and silk.
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

#include "common/prt_single_scattering.h"
#include "gpu/prt_single_scattering_gpu.h"
#include "reference/exemplar.h"
#include "reference/prt_single_scattering.h"
#include "reference/segment_visibility.h"
#include "scene/fabric.h"
#include "validation/bcsdf_oracle.h"
#include "validation/case_support.h"
#include "validation/harness.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kDeg = kPi / 180.0;

CaseResult startSs(const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "prt-ss";
  r.path = "prtss";
  return r;
}

bool finite3(glm::dvec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
double maxComp(glm::dvec3 v) { return std::max({v.x, v.y, v.z}); }
double maxAbsDiff(glm::dvec3 a, glm::dvec3 b) { return maxComp(glm::abs(a - b)); }

// ---- the oracle BCSDF (validation/bcsdf_oracle.h pieces, no common/) --------
struct OracleBcsdf {
  oracle::Fabric f;
  double i0Kappa = 1.0;
  // Z of each lobe where its ±8β window is clipped: oracle::lobeNorm on 4,097
  // angles over [−π/2, π/2], Catmull–Rom between them (spacing 7.7e-4 rad =
  // β/23 at β = 1°: interpolation error ~(h/β)⁴ ≈ 4e-6 relative).
  static constexpr int kZ = 4097;
  std::vector<double> zTable[2];
  explicit OracleBcsdf(const FabricPreset& p) {
    for (int c = 0; c < 3; ++c) f.colorR[c] = p.colorR[c], f.colorTT[c] = p.colorTT[c];
    f.betaRDegrees = p.betaRDegrees;
    f.betaTTDegrees = p.betaTTDegrees;
    f.gammaTTDegrees = p.gammaTTDegrees;
    i0Kappa = std::cyl_bessel_i(0.0, f.kappa());
    for (int l = 0; l < 2; ++l) {
      zTable[l].resize(kZ);
      for (int k = 0; k < kZ; ++k) zTable[l][size_t(k)] = oracle::lobeNorm(l == 0 ? f.betaR() : f.betaTT(), -0.5 * kPi + k * kPi / (kZ - 1));
    }
  }
  // Z(θ) = ∫ g(x + θ; β) cos²x dx over (−π/2, π/2): ½(1 + e^{−2β²} cos 2θ) for
  // the untruncated Gaussian while its ±8β lies inside, the table otherwise.
  double z(int lobe, double theta) const {
    const double beta = lobe == 0 ? f.betaR() : f.betaTT();
    if (std::abs(theta) + 8.0 * beta <= 0.5 * kPi) return 0.5 * (1.0 + std::exp(-2.0 * beta * beta) * std::cos(2.0 * theta));
    const double u = std::clamp((theta + 0.5 * kPi) / kPi * (kZ - 1), 0.0, double(kZ - 1));
    const int k = std::min(int(u), kZ - 2);
    const double t = u - k;
    const auto at = [&](int i) { return zTable[lobe][size_t(std::clamp(i, 0, kZ - 1))]; };
    const double p0 = at(k - 1), p1 = at(k), p2 = at(k + 1), p3 = at(k + 2);
    return p1 + 0.5 * t * (p2 - p0 + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + t * (3.0 * (p1 - p2) + p3 - p0)));
  }
  static double gauss(double x, double beta) { return std::exp(-0.5 * x * x / (beta * beta)) / (std::sqrt(2.0 * kPi) * beta); }
  // The two longitudinal factors at θ_i (for reuse along a row of φ).
  struct Row {
    glm::dvec3 r, tt;  // F M_R / 2π and (1 − F) C_TT M_TT
  };
  Row row(double thetaI, double thetaO) const {
    const glm::dvec3 F = oracle::fresnel(f, thetaI);
    const double bR = f.betaR(), bT = f.betaTT();
    const double mR = gauss(thetaI + thetaO, bR) / z(0, thetaI), mT = gauss(thetaI + thetaO, bT) / z(1, thetaI);
    return {F * (mR / (2.0 * kPi)), (glm::dvec3(1.0) - F) * glm::dvec3(f.colorTT[0], f.colorTT[1], f.colorTT[2]) * mT};
  }
  double nTT(double phi) const { return std::exp(f.kappa() * std::cos(phi - kPi)) / (2.0 * kPi * i0Kappa); }
  glm::dvec3 operator()(double thetaI, double thetaO, double phi) const {
    const Row w = row(thetaI, thetaO);
    return w.r + w.tt * nTT(phi);
  }
};

// ∫_{S²} G(ω; ξ, λ) S(ω, ω_o) cos θ_i dω by iterated Gauss–Legendre in the
// fiber frame (θ, φ relative to ω_o's azimuth), ξ at (θ′, ϕ′): θ over the
// SG's window |θ − θ′| ≤ 15/√λ (G < e^{−40} outside), panels ≤ β_R/2 on the R
// lobe's ±8β_R about −θ_o and ≤ min(β_TT, 1/√λ)/2 elsewhere; per θ, φ over
// the window where λ cos θ cos θ′ (1 − cos Δφ) ≤ 40, panels ≤ 1/√(λ cos θ cos θ′);
// 8 Gauss–Legendre points per panel (a Gaussian over half a width: ~1e-12).
glm::dvec3 convolutionQuadrature(const OracleBcsdf& b, double thetaO, double thetaX, double phiX, double lambda) {
  const double bR = b.f.betaR(), bT = b.f.betaTT(), w = 15.0 / std::sqrt(lambda);
  const double lo = std::max(-0.5 * kPi, thetaX - w), hi = std::min(0.5 * kPi, thetaX + w);
  std::vector<double> cuts = {lo, hi, thetaX, -thetaO, -thetaO - 8.0 * bR, -thetaO + 8.0 * bR};
  std::erase_if(cuts, [&](double x) { return x < lo || x > hi; });
  std::sort(cuts.begin(), cuts.end());
  glm::dvec3 total(0.0);
  const double cx = std::cos(thetaX), sx = std::sin(thetaX);
  for (size_t c = 0; c + 1 < cuts.size(); ++c) {
    const double a = cuts[c], e = cuts[c + 1];
    if (e <= a) continue;
    const double mid = 0.5 * (a + e);
    const double panel = std::abs(mid + thetaO) <= 8.0 * bR ? bR / 2.0 : std::min(bT, 1.0 / std::sqrt(lambda)) / 2.0;
    const oracle::Nodes th = oracle::panelNodes(a, e, {}, panel, 8);
    for (size_t i = 0; i < th.x.size(); ++i) {
      const double t = th.x[i], ct = std::cos(t), st = std::sin(t);
      const OracleBcsdf::Row row = b.row(t, thetaO);
      const double az = lambda * ct * cx;
      const double half = az * 2.0 <= 40.0 ? kPi : std::acos(1.0 - 40.0 / az);
      const double phiPanel = az > 1.0 ? 1.0 / std::sqrt(az) : 1.0;
      const oracle::Nodes ph = oracle::panelNodes(phiX - half, phiX + half, {phiX}, phiPanel, 8);
      glm::dvec3 inner(0.0);
      for (size_t j = 0; j < ph.x.size(); ++j) {
        const double g = std::exp(lambda * (st * sx + ct * cx * std::cos(ph.x[j] - phiX) - 1.0));
        double rel = std::fmod(std::abs(ph.x[j]), 2.0 * kPi);
        if (rel > kPi) rel = 2.0 * kPi - rel;
        inner += ph.w[j] * g * (row.r + row.tt * b.nTT(rel));
      }
      total += th.w[i] * ct * ct * inner;
    }
  }
  return total;
}

// M(λ) = 2π(1 − e^{−2λ})/λ.
double sgIntegral(double lambda) { return 2.0 * kPi * -std::expm1(-2.0 * lambda) / lambda; }

// The fabrics and their double 𝒢 tables (all five rows of data/fabric-bcsdf.tsv).
struct Fabrics {
  std::vector<FabricPreset> presets;
  std::vector<FabricParams> params;
  std::vector<double> table;
  std::vector<OracleBcsdf> oracles;
  int index(std::string_view name) const {
    for (size_t i = 0; i < presets.size(); ++i)
      if (presets[i].name == name) return int(i);
    throw std::runtime_error(fmt::format("no fabric {}", name));
  }
};
const Fabrics& fabrics(ValidationContext& ctx) {
  return ctx.cached(CacheKey<Fabrics>{"prtss-fabrics"}, [] {
    Fabrics f;
    f.presets = builtinFabricPresets();
    for (const FabricPreset& p : f.presets) f.params.push_back(p.params());
    f.table = bakePrtSsTableCpu(f.params);
    for (const FabricPreset& p : f.presets) f.oracles.emplace_back(p);
    return f;
  });
}

glm::dvec3 sphericalZ(double theta, double phi) {  // θ from +z
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// ---- Tolerances (measured; each case's metric states the reason) -----------
// Γ vs quadrature: 004's approximations (small-angle cos(θ − θ′), cos θ_i,
// F, Z frozen at the peak θ_p) err as O(1/λ) relative to the peak: measured
// 2.0e-3 at λ = 100, 1.3e-3 at 200, 3e-4 at 10³, ≤ 7e-5 at 10⁴ (notes §6.1:
// 0.13 % for R at λ = 200, β = 7°); 5e-3 leaves 2.5× at λ = 100.
constexpr double kGammaTolerance = 5e-3;

CaseResult runGammaCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = startSs(name);
  const Fabrics& fs = fabrics(ctx);
  const auto t0 = Clock::now();
  struct Point {
    int fabric;
    double lambda, thetaO, thetaX, phiX;
    glm::dvec3 gamma, quad;
  };
  std::vector<Point> pts;
  for (const char* fn : {"fleece", "gabardine", "silk"})
    for (double lambda : {100.0, 200.0, 1000.0, 10000.0})
      for (double to : {-50.0, -20.0, 40.0})
        for (double tx : {-40.0, -30.0, 20.0, 50.0})
          for (double px : {0.3, kPi}) pts.push_back({fs.index(fn), lambda, to * kDeg, tx * kDeg, px, {}, {}});
  const std::vector<OracleBcsdf>& oracles = fs.oracles;
  tbb::parallel_for(size_t(0), pts.size(), [&](size_t i) {
    Point& p = pts[i];
    p.gamma = prtss64::ftPrtSsGamma(fs.table.data(), fs.params[size_t(p.fabric)], p.fabric, p.thetaO, p.thetaX, p.phiX,
                                    p.lambda, 0.0);
    p.quad = convolutionQuadrature(oracles[size_t(p.fabric)], p.thetaO, p.thetaX, p.phiX, p.lambda);
  });
  r.cpuMilliseconds = msSince(t0);
  // Error relative to the largest value of the same (fabric, λ): off-lobe
  // points are orders of magnitude smaller and their relative error says nothing.
  double worst = 0.0;
  uint64_t bad = 0;
  std::string table;
  size_t worstIdx = 0;
  for (const char* fn : {"fleece", "gabardine", "silk"}) {
    table += fmt::format("{}:", fn);
    for (double lambda : {100.0, 200.0, 1000.0, 10000.0}) {
      double peak = 0.0, err = 0.0;
      for (const Point& p : pts)
        if (p.fabric == fs.index(fn) && p.lambda == lambda) peak = std::max(peak, maxComp(p.quad));
      for (size_t i = 0; i < pts.size(); ++i) {
        const Point& p = pts[i];
        if (p.fabric != fs.index(fn) || p.lambda != lambda) continue;
        if (!finite3(p.gamma) || !finite3(p.quad)) ++bad;
        const double e = maxAbsDiff(p.gamma, p.quad) / peak;
        r.histogram.add(e);
        if (!(e <= worst)) worstIdx = i;
        err = maxKeepNaN(err, e);
        worst = maxKeepNaN(worst, e);
      }
      table += fmt::format(" λ={:g} {:.2e};", lambda, err);
    }
    table += " ";
  }
  const Point& w = pts[worstIdx];
  r.details = fmt::format("worst: {} λ={:g} θo={:.0f}° θ′={:.0f}° ϕ′={:.2f}: Γ ({:.6g} {:.6g} {:.6g}) quadrature ({:.6g} "
                          "{:.6g} {:.6g}); per fabric/λ: {}",
                          fs.presets[size_t(w.fabric)].name, w.lambda, w.thetaO / kDeg, w.thetaX / kDeg, w.phiX,
                          w.gamma.x, w.gamma.y, w.gamma.z, w.quad.x, w.quad.y, w.quad.z, table);
  r.histogramMetric = "gamma.max_rel";
  r.metrics = {
      Metric{"gamma.max_rel", worst, kGammaTolerance, "of the peak",
             fmt::format("Γ (004 eq. 2, double) vs 2D product quadrature of ∫ G S cos dω over {} points (3 fabrics × λ "
                         "100..10⁴ × θ_o × θ′ × ϕ′), relative to the largest value per fabric and λ: 004's "
                         "approximations are O(1/λ) (per fabric/λ in the details)",
                         pts.size())},
      nonFiniteMetric("cpu", bad, "Γ and quadrature values"),
  };
  r.finish();
  return r;
}

constexpr double kDelta4Tolerance = 0.2, kDelta6Tolerance = 2e-3;

CaseResult runDeltaCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = startSs(name);
  const Fabrics& fs = fabrics(ctx);
  const auto t0 = Clock::now();
  double err4 = 0.0, err6 = 0.0;
  uint64_t bad = 0;
  std::string per;
  for (size_t f = 0; f < fs.presets.size(); ++f) {
    const OracleBcsdf& o = fs.oracles[f];
    double e4 = 0.0, e6 = 0.0;
    for (double to : {-45.0, 0.0, 30.0}) {
      // S cos over θ′ ∈ [−70°, 70°], ϕ′ ∈ {0, π/2, π}; the peak normalises.
      double peak = 0.0;
      std::vector<std::array<double, 3>> at;
      for (double tx = -70.0; tx <= 70.0; tx += 2.5)
        for (double px : {0.0, 0.5 * kPi, kPi}) at.push_back({to * kDeg, tx * kDeg, px});
      std::vector<glm::dvec3> truth(at.size());
      for (size_t i = 0; i < at.size(); ++i) {
        truth[i] = o(at[i][1], at[i][0], at[i][2]) * std::cos(at[i][1]);
        peak = std::max(peak, maxComp(truth[i]));
      }
      for (size_t i = 0; i < at.size(); ++i)
        for (double lambda : {1e4, 1e6}) {
          const glm::dvec3 g = prtss64::ftPrtSsGamma(fs.table.data(), fs.params[f], int(f), at[i][0], at[i][1], at[i][2],
                                                     lambda, 0.0) /
                               sgIntegral(lambda);
          if (!finite3(g)) ++bad;
          const double e = maxAbsDiff(g, truth[i]) / peak;
          (lambda < 1e5 ? e4 : e6) = maxKeepNaN(lambda < 1e5 ? e4 : e6, e);
        }
    }
    per += fmt::format("{} {:.2e}/{:.2e} ", fs.presets[f].name, e4, e6);
    err4 = maxKeepNaN(err4, e4);
    err6 = maxKeepNaN(err6, e6);
  }
  r.cpuMilliseconds = msSince(t0);
  r.details = "Γ/M vs S cos θ, λ = 10⁴ / 10⁶, relative to the peak: " + per;
  r.metrics = {
      Metric{"delta.lambda1e4_max_rel", err4, kDelta4Tolerance, "of the peak",
             "Γ(ξ, 10⁴, ω_o)/M vs the oracle's S(ξ, ω_o) cos θ_ξ, 5 fabrics, θ′ ∈ [−70°, 70°]: the SG of width 1/√λ = "
             "0.57° still blurs the 1° R lobes of silk and cotton by up to ~1/(λβ²) = 0.33 (measured 0.13; fleece 2e-3)"},
      Metric{"delta.lambda1e6_max_rel", err6, kDelta6Tolerance, "of the peak",
             "the same at λ = 10⁶: 1/(λβ²) ≤ 3.3e-3 for β = 1°, ≤ 6e-5 for fleece (notes §6.6: ≤ 1e-3 once λβ² ≫ 1)"},
      nonFiniteMetric("cpu", bad, "Γ/M values"),
  };
  r.finish();
  return r;
}

CaseResult runLimitsCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = startSs(name);
  const Fabrics& fs = fabrics(ctx);
  const auto t0 = Clock::now();
  // erf: the shared float polynomial vs std::erf.
  double erfErr = 0.0;
  for (int i = -6000; i <= 6000; ++i) {
    const double x = i * 1e-3;
    erfErr = maxKeepNaN(erfErr, std::abs(double(ftErf(float(x))) - std::erf(x)));
  }
  // Ṽ_loc: ½ at d = 0; → 1 / 0 far on the visible / occluded side.
  double vErr = std::abs(prtss64::ftPrtSsSmoothVisibility(0.0, 150.0) - 0.5);
  for (double lambda : {200.0, 1000.0, 1e4}) {
    vErr = std::max(vErr, std::abs(prtss64::ftPrtSsSmoothVisibility(0.5, lambda) - 1.0));
    vErr = std::max(vErr, std::abs(prtss64::ftPrtSsSmoothVisibility(-0.5, lambda)));
    vErr = std::max(vErr, std::abs(prtss64::ftPrtSsSmoothVisibility(kPi, lambda) - 1.0));
  }
  // Blend: a segment half occluded (weights on half the axes), fleece.
  const int f = fs.index("fleece");
  const FabricParams& p = fs.params[size_t(f)];
  double w[FT_SVF_MAX_AXES] = {};
  for (int q = 0; q < FT_SVF_DEFAULT_AXES; ++q) w[q] = (q % 2) ? 0.13 : 0.0;
  const glm::dvec3 t = glm::normalize(glm::dvec3(1, 0.2, 0.1)), wo = glm::normalize(glm::dvec3(0.2, -0.6, 0.7));
  const glm::dvec3 xi = glm::normalize(glm::dvec3(-0.3, 0.4, 0.8));
  const double ssdf = 0.05, angle = 0.4;
  const auto full = [&](double lambda) {
    return prtss64::ftPrtSsSgLight(fs.table.data(), p, f, t, wo, xi, lambda, ssdf, w, FT_SVF_DEFAULT_AXES, angle,
                                   FT_SVF_LAMBDA, 1.0);
  };
  const auto sosg = [&](double lambda) {
    glm::dvec3 s(0.0);
    for (int q = 0; q < FT_SVF_DEFAULT_AXES; ++q)
      s += prtss64::ftPrtSsSosgTerm(fs.table.data(), p, f, t, wo, xi, lambda, w[q],
                                    glm::dvec3(ftSvfAxis(q + 1, FT_SVF_DEFAULT_AXES, float(angle))), FT_SVF_LAMBDA);
    return s / sgIntegral(lambda);
  };
  const auto sharp = [&](double lambda) {
    return prtss64::ftPrtSsSmoothVisibility(ssdf, lambda) *
           prtss64::ftPrtSsGammaAt(fs.table.data(), p, f, t, wo, xi, lambda, 0.0) / sgIntegral(lambda);
  };
  const double scale = std::max({maxComp(full(100.0)), maxComp(full(200.0)), 1e-30});
  double pureErr = 0.0;
  pureErr = std::max(pureErr, maxAbsDiff(full(100.0), sosg(100.0)) / scale);
  pureErr = std::max(pureErr, maxAbsDiff(full(200.0), sharp(200.0)) / scale);
  pureErr = std::max(pureErr, maxAbsDiff(full(120.0), 0.8 * sosg(120.0) + 0.2 * sharp(120.0)) / scale);
  pureErr = std::max(pureErr, maxAbsDiff(full(50.0), sosg(50.0)) / scale);
  pureErr = std::max(pureErr, maxAbsDiff(full(400.0), sharp(400.0)) / scale);
  double jump = 0.0;
  for (double l : {100.0, 200.0}) jump = std::max(jump, maxAbsDiff(full(l - 1e-6), full(l + 1e-6)) / scale);
  // Directional: [d > 0] S cos against the oracle.
  const OracleBcsdf& o = fs.oracles[size_t(f)];
  const double ti = std::asin(glm::dot(xi, t)), tO = std::asin(glm::dot(wo, t));
  const glm::dvec3 py = xi - glm::dot(xi, t) * t, po = wo - glm::dot(wo, t) * t;
  const double phi = std::acos(std::clamp(glm::dot(py, po) / (glm::length(py) * glm::length(po)), -1.0, 1.0));
  const glm::dvec3 dirTruth = o(ti, tO, phi) * std::cos(ti);
  const double dirErr = maxAbsDiff(prtss64::ftPrtSsDirectional(p, t, wo, xi, 0.01, 1.0), dirTruth) / maxComp(dirTruth);
  const double dirOccluded = maxComp(glm::abs(prtss64::ftPrtSsDirectional(p, t, wo, xi, -0.01, 1.0)));
  r.cpuMilliseconds = msSince(t0);
  r.metrics = {
      Metric{"erf.max_abs", erfErr, 3.5e-7, "",
             "the shared float erf (A&S 7.1.26, |error| ≤ 1.5e-7; series below ½) vs std::erf on [−6, 6], + float rounding of 1 − "
             "poly·e^{−x²}"},
      Metric{"vloc.limits_max_abs", vErr, 1e-12, "",
             "Ṽ_loc = ½ at d = 0; 1 and 0 at d = ±0.5 rad for λ ≥ 200 (erf(5) = 1 − 1.5e-12... to double rounding)"},
      Metric{"blend.branch_max_rel", pureErr, 1e-6, "of the result",
             "SG light = pure sum of SGs at λ ≤ 100, pure SSDF+erf at λ ≥ 200, 0.8/0.2 at λ = 120 (004 §5.2.2), "
             "branches computed apart with M(λ) in double; the shared M(λ) is srbf.h's float one (6e-8 measured)"},
      Metric{"blend.jump_max_rel", jump, 1e-6, "of the result",
             "continuity at λ = 100 and 200: ±1e-6 in λ changes the result by O(1e-8) (the weight is continuous)"},
      Metric{"directional.max_rel", dirErr, 1e-5, "",
             "d > 0: S cos θ_d vs the oracle's BCSDF (float S of bcsdf.h: ~1e-6)"},
      Metric{"directional.occluded", dirOccluded, 0.0, "", "d < 0: exactly 0 (004 §5.2.1: the SSDF's sign)"},
  };
  r.finish();
  return r;
}

CaseResult runFurnaceCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = startSs(name);
  const Fabrics& fs = fabrics(ctx);
  const auto t0 = Clock::now();
  const double lambda = 200.0;
  double maxEnergy = 0.0, err = 0.0, maxTruth = 0.0;
  uint64_t bad = 0;
  std::string per;
  std::mutex m;
  struct Job {
    size_t f;
    double to;
  };
  std::vector<Job> jobs;
  for (size_t f = 0; f < fs.presets.size(); ++f)
    for (double to : {-60.0, 0.0, 35.0}) jobs.push_back({f, to * kDeg});
  tbb::parallel_for(size_t(0), jobs.size(), [&](size_t j) {
    const size_t f = jobs[j].f;
    const double to = jobs[j].to;
    const OracleBcsdf& o = fs.oracles[f];
    const glm::dvec3 truth = oracle::ambientIntegral(o.f, to);  // ∫ S cos θ_i dω_i (the φ integrals are 1)
    // ∫ over light axes ξ of Γ/M: iterated Gauss–Legendre in (θ′, ϕ′), panels
    // ≤ β_R within ±8√(β_R² + 1/λ) of −θ_o, 0.04 elsewhere, ϕ′ ∈ [0, π] (doubled) in
    // panels of π/6; 8 points each.
    const double bR = o.f.betaR(), wR = 8.0 * std::sqrt(bR * bR + 1.0 / lambda);
    std::vector<double> cuts = {-0.5 * kPi, 0.5 * kPi, -to - wR, -to, -to + wR};
    std::erase_if(cuts, [](double x) { return std::abs(x) > 0.5 * kPi; });
    std::sort(cuts.begin(), cuts.end());
    const oracle::Nodes ph = oracle::panelNodes(0.0, kPi, {}, kPi / 6.0, 8);
    glm::dvec3 e(0.0);
    for (size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double mid = 0.5 * (cuts[c] + cuts[c + 1]);
      const oracle::Nodes th =
          oracle::panelNodes(cuts[c], cuts[c + 1], {}, std::abs(mid + to) < wR ? bR : 0.04, 8);
      for (size_t i = 0; i < th.x.size(); ++i)
        for (size_t k = 0; k < ph.x.size(); ++k)
          e += 2.0 * th.w[i] * ph.w[k] * std::cos(th.x[i]) *
               prtss64::ftPrtSsGamma(fs.table.data(), fs.params[f], int(f), to, th.x[i], ph.x[k], lambda, 0.0) /
               sgIntegral(lambda);
    }
    std::lock_guard<std::mutex> lock(m);
    if (!finite3(e)) ++bad;
    maxEnergy = maxKeepNaN(maxEnergy, maxComp(e));
    maxTruth = std::max(maxTruth, maxComp(truth));
    err = maxKeepNaN(err, maxComp(glm::abs(e - truth) / truth));
    if (to == 0.0) per += fmt::format("{} ({:.4f} {:.4f} {:.4f}) ", fs.presets[f].name, e.x, e.y, e.z);
  });
  r.cpuMilliseconds = msSince(t0);
  r.details = "∫ Γ/M dξ at θ_o = 0: " + per;
  r.metrics = {
      Metric{"furnace.max_rel", err, 0.01, "",
             "∫ over all light axes of Γ/M (5 fabrics, θ_o ∈ {−60°, 0°, 35°}, λ = 200) vs the oracle's "
             "∫ S cos θ_i dω_i (bcsdf_oracle ambientIntegral; ∫ G/M dξ = 1): Γ's O(1/λ) approximation, 5.6e-3 measured"},
      Metric{"furnace.max_energy", maxEnergy, 0.0, "",
             fmt::format("the largest of those integrals, per channel; not bounded by 1: the lobes are normalised over "
                         "θ_o at θ_i (Z(θ_i)), so their integral over ω_i is not an albedo (the oracle's own reaches "
                         "{:.4f})", maxTruth),
             false},
      nonFiniteMetric("cpu", bad, "energies"),
  };
  r.finish();
  return r;
}

// ---- Monte Carlo comparisons ------------------------------------------------
struct McPoint {
  glm::dvec3 xi, wo;
  double lambda;
  glm::dvec3 ours, mc, se;
};

// ω_o on ξ's specular cone (θ_o = −θ_ξ: the R lobe's peak), turned by
// 2.5 rad about t from ξ's azimuth (near the TT lobe's φ = π).
glm::dvec3 specularView(glm::dvec3 t, glm::dvec3 xi) {
  const double s = glm::dot(xi, t);
  glm::dvec3 u = xi - s * t;
  u = glm::length(u) > 1e-9 ? glm::normalize(u) : glm::normalize(glm::cross(t, glm::dvec3(0, 0, 1)));
  const glm::dvec3 v = glm::cross(t, u);
  const double c = std::sqrt(std::max(0.0, 1.0 - s * s));
  return glm::normalize(-s * t + c * (std::cos(2.5) * u + std::sin(2.5) * v));
}

// |ours − MC| beyond 4 standard errors, relative to the largest MC value of
// the same λ (per channel max).
// sigmas = 0: the raw difference.
double mcError(const std::vector<McPoint>& pts, double lambda, double sigmas = 4.0) {
  double peak = 0.0, e = 0.0;
  for (const McPoint& p : pts)
    if (p.lambda == lambda) peak = std::max(peak, maxComp(p.mc));
  for (const McPoint& p : pts)
    if (p.lambda == lambda)
      e = maxKeepNaN(e, maxComp(glm::max(glm::abs(p.ours - p.mc) - sigmas * p.se, glm::dvec3(0.0))) / peak);
  return e;
}

// Σ |ours − MC| / Σ MC over the lights of one λ (max channel): the aggregate
// error, robust to the one light a visibility edge crosses.
double mcMeanError(const std::vector<McPoint>& pts, double lambda) {
  double num = 0.0, den = 0.0;
  for (const McPoint& p : pts)
    if (p.lambda == lambda) num += maxComp(glm::abs(p.ours - p.mc)), den += maxComp(p.mc);
  return num / den;
}

// Our SG light (double) for one segment: weights, R_k, the SSDF at ξ by `ssdfAt`.
template <class SsdfAt>
void evaluateOurs(const Fabrics& fs, int f, glm::dvec3 t, const std::vector<float>& weights,
                  float angle, SsdfAt ssdfAt, std::vector<McPoint>& pts) {
  double w[FT_SVF_MAX_AXES] = {};
  for (size_t q = 0; q < weights.size(); ++q) w[q] = weights[q];
  for (McPoint& p : pts)
    p.ours = prtss64::ftPrtSsSgLight(fs.table.data(), fs.params[size_t(f)], f, t, p.wo, p.xi, p.lambda, ssdfAt(p.xi), w,
                                     int(weights.size()), angle, FT_SVF_LAMBDA, 1.0);
}

void runMc(const Fabrics& fs, int f, glm::dvec3 t, const PrtSsVisibility& vis, int samples,
           std::vector<McPoint>& pts) {
  const OracleBcsdf& o = fs.oracles[size_t(f)];
  const PrtSsBcsdf s = [&](double a, double b, double c) { return o(a, b, c); };
  tbb::parallel_for(size_t(0), pts.size(), [&](size_t i) {
    PrtSsMcSettings ms;
    ms.samples = samples;
    ms.seed = uint32_t(1000 + i);
    ms.betaR = o.f.betaR();
    ms.betaTT = o.f.betaTT();
    const PrtSsMcResult mc = prtSsMonteCarlo(s, vis, t, pts[i].wo, pts[i].xi, pts[i].lambda, ms);
    pts[i].mc = mc.mean;
    pts[i].se = mc.stdError;
  });
}

constexpr int kMcSamples = 4096;
// Sum of SGs vs MC with V^ssg: Γ at ‖ξˢᵘᵐ‖ ≥ 128 − λ errs ~2e-3 of the peak
// (prt/ss/gamma at λ = 100); MC's 4σ is taken off first.
constexpr double kLoneSosgTolerance = 0.02;
// Exemplar vs MC (aggregate over lights): set from the measured values in
// docs/prt-single-scattering.md with ~1.5× margin; model error, not rounding.
// Measured: soft 0.19, sharp 0.35 (exact SSDF) and 0.22 (PCA-decoded).
constexpr double kExemplarSoftTolerance = 0.25, kExemplarSharpTolerance = 0.45;
// The parallel cylinder vs MC, measured: soft 0.25 (λ = 50; 48 SGs 21° apart
// against a lune 35° wide), sharp 0.10.
constexpr double kCylinderSoftTolerance = 0.35, kCylinderSharpTolerance = 0.15;

CaseResult runSsLoneCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = startSs(name);
  const Fabrics& fs = fabrics(ctx);
  const auto t0 = Clock::now();
  // A lone segment along x: the SVF code's image is all visible, SSDF = +π.
  const int W = 64, H = 64;
  const std::vector<uint8_t> img(size_t(W) * H, 1);
  const float angle = ftSvfRotationAngle(0u, 1u);
  const std::vector<float> weights = svfWeightsCpu(img, W, H, FT_SVF_DEFAULT_AXES, angle);
  const glm::dvec3 t(1, 0, 0);
  std::string details;
  std::vector<Metric> metrics;
  uint64_t bad = 0;
  double sosgErr = 0.0, gammaErr = 0.0, rippleErr = 0.0;
  // V^ssg(ω) = Σ_q w_q e^{λ_svf(ξ_q·ω − 1)}/M(λ_svf), the axes of 004 §4.1c written here.
  const PrtSsVisibility vssg = [&](glm::dvec3 w) {
    double v = 0.0;
    for (int q = 1; q <= FT_SVF_DEFAULT_AXES; ++q) {
      const double z = 1.0 - double(q - 1) / FT_SVF_DEFAULT_AXES, rr = std::sqrt(std::max(0.0, 1.0 - z * z));
      const double phi = 4.0 * kPi * q / (1.0 + std::sqrt(5.0)) + double(angle);
      const glm::dvec3 axis(rr * std::cos(phi), rr * std::sin(phi), z);
      v += weights[size_t(q - 1)] * std::exp(double(FT_SVF_LAMBDA) * (glm::dot(w, axis) - 1.0));
    }
    return v / sgIntegral(FT_SVF_LAMBDA);
  };
  for (const char* fn : {"fleece", "silk"}) {
    const int f = fs.index(fn);
    std::vector<McPoint> pts;
    for (double el : {35.0, 60.0, 90.0})
      for (double az : {0.0, 100.0, 200.0})
        for (double lambda : {10.0, 50.0, 100.0, 200.0, 400.0, 1000.0})
        {
          const glm::dvec3 xi = sphericalZ((90.0 - el) * kDeg, az * kDeg);
          pts.push_back({xi, specularView(t, xi), lambda, {}, {}, {}});
        }
    evaluateOurs(fs, f, t, weights, angle, [](glm::dvec3) { return kPi; }, pts);
    std::vector<McPoint> ssg = pts;
    runMc(fs, f, t, [](glm::dvec3) { return 1.0; }, kMcSamples, pts);
    runMc(fs, f, t, vssg, kMcSamples, ssg);
    for (const McPoint& p : pts)
      if (!finite3(p.ours) || !finite3(p.mc)) ++bad;
    details += fmt::format("{}:", fn);
    for (double lambda : {10.0, 50.0, 100.0, 200.0, 400.0, 1000.0}) {
      const double e = mcError(pts, lambda);
      details += fmt::format(" λ={:g} {:.2e}", lambda, e);
      if (lambda <= 100.0) {
        const double es = mcError(ssg, lambda);
        details += fmt::format(" (vs V^ssg {:.2e}, raw {:.2e})", es, mcError(ssg, lambda, 0.0));
        sosgErr = maxKeepNaN(sosgErr, es);
        rippleErr = maxKeepNaN(rippleErr, e);
      } else {
        gammaErr = maxKeepNaN(gammaErr, e);
      }
      details += ";";
    }
    details += " ";
  }
  r.cpuMilliseconds = msSince(t0);
  r.details = "|ours − MC| beyond 4σ, relative to the largest MC value per λ: " + details;
  r.metrics = {
      Metric{"lone.sosg_vs_mc", sosgErr, kLoneSosgTolerance, "of the peak",
             "λ ≤ 100: the sum-of-SGs product (004 §5.2.2: Γ at ‖ξˢᵘᵐ‖ with its renormalisation) vs MC of eq. 1 with "
             "the same V^ssg evaluated pointwise (axes written here): Γ's O(1/‖ξˢᵘᵐ‖) approximation, plus 4σ of MC "
             "(4,096 samples, SG + BCSDF sampling, balance heuristic); fleece and silk, lights at 35–90° elevation"},
      Metric{"lone.ripple_vs_exact", rippleErr, 0.0, "of the peak",
             "λ ≤ 100: the same against MC with the exact V ≡ 1: the representation's own error — 48 SGs of width "
             "1/√128 = 5° on axes 21° apart ripple under a light of width 1/√λ ≥ 5.7° (notes §5.7); 004's reason to "
             "blend to the SSDF above λ = 100",
             false},
      Metric{"lone.gamma_vs_mc", gammaErr, 0.05, "of the peak",
             "λ ≥ 200: Ṽ_loc(+π) Γ/M vs MC: Γ's O(1/λ) approximation"},
      nonFiniteMetric("cpu", bad, "ours and MC"),
  };
  r.finish();
  return r;
}

CaseResult runExemplarCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = startSs(name);
  const Fabrics& fs = fabrics(ctx);
  const auto t0 = Clock::now();
  ExemplarSettings es;
  es.fibersPerPly = 4;
  es.spansPerYarn = 8;
  es.subdivisions = 1;
  const Exemplar block = makePlainWeaveExemplar(es);
  const int tiles = 3;
  const SvfScene scene(tileExemplar(block, tiles));
  SvfSettings s;
  s.width = 64;
  s.height = 64;
  // The segment among the first 8 whose upper hemisphere is most occluded
  // but not closed (partly lit from above).
  // 24 segments (every ⌊S/24⌋-th) for a PCA of their SSDFs (16 components, as
  // the SVF bake compresses them: svfPcaCpu), the chosen one among them.
  const size_t rows = std::min<size_t>(24, block.segments.size()), stride = block.segments.size() / rows;
  std::vector<SvfSegment> all(rows);
  tbb::parallel_for(size_t(0), rows, [&](size_t i) { all[i] = svfSegmentCpu(scene, block, tiles, uint32_t(i * stride), s); });
  size_t row = 0;
  double best = -1.0;
  for (size_t i = 0; i < rows; ++i) {
    const size_t half = size_t(s.width) * size_t(s.height) / 2;
    const double occ = double(std::count(all[i].image.begin(), all[i].image.begin() + long(half), uint8_t(0))) / double(half);
    if (occ < 0.8 && occ > best) best = occ, row = i;
  }
  const SvfSegment& seg = all[row];
  const uint32_t pick = uint32_t(row * stride);
  std::vector<float> ssdfAll;
  for (const SvfSegment& a : all) ssdfAll.insert(ssdfAll.end(), a.ssdf.begin(), a.ssdf.end());
  const SvfPca pca = svfPcaCpu(ssdfAll, rows, s.width * s.height, 16);
  const std::vector<double> decoded = svfPcaReconstruct(pca, row, pca.components);
  const ExemplarSegment& es0 = block.segments[pick];
  const glm::dvec3 t = glm::normalize(glm::dvec3(es0.b - es0.a));
  // The image's pixel of a direction (θ = π(y + ½)/H from +z, φ = 2π(x + ½)/W − π), written here.
  const auto pixel = [&](glm::dvec3 w) {
    const double th = std::acos(std::clamp(w.z, -1.0, 1.0)), ph = std::atan2(w.y, w.x);
    const int y = std::clamp(int(th / kPi * s.height), 0, s.height - 1);
    const int x = std::clamp(int((ph + kPi) / (2.0 * kPi) * s.width), 0, s.width - 1);
    return size_t(y) * size_t(s.width) + size_t(x);
  };
  const PrtSsVisibility vis = [&](glm::dvec3 w) { return double(seg.image[pixel(w)]); };
  const int f = fs.index("fleece");
  std::vector<McPoint> pts;
  // Lights at pixel centres (rows 3, 10, 21: 80°, 60°, 30° elevation; 4
  // columns 90° apart): the SSDF is sampled there, the lookup is nearest-pixel.
  for (int y : {3, 10, 21})
    for (int x : {32, 48, 0, 16})
      for (double lambda : {10.0, 50.0, 150.0, 400.0, 1000.0})
      {
        const glm::dvec3 xi = sphericalZ(kPi * (y + 0.5) / s.height, 2.0 * kPi * (x + 0.5) / s.width - kPi);
        pts.push_back({xi, specularView(t, xi), lambda, {}, {}, {}});
      }
  evaluateOurs(fs, f, t, seg.weights, seg.angle, [&](glm::dvec3 w) { return double(seg.ssdf[pixel(w)]); }, pts);
  runMc(fs, f, t, vis, kMcSamples, pts);
  // The same with the PCA-decoded SSDF (what a frame reads), and with the SSDF
  // moved half a row (π/2H) towards 0: the distance to the pixel edge, not
  // to the opposite pixel's centre (an experiment, informational).
  std::vector<McPoint> viaPca = pts, halfPixel = pts;
  evaluateOurs(fs, f, t, seg.weights, seg.angle, [&](glm::dvec3 w) { return decoded[pixel(w)]; }, viaPca);
  evaluateOurs(fs, f, t, seg.weights, seg.angle, [&](glm::dvec3 w) {
    const double d = seg.ssdf[pixel(w)];
    return d - std::copysign(0.5 * kPi / s.height, d);
  }, halfPixel);
  r.cpuMilliseconds = msSince(t0);
  uint64_t bad = 0;
  for (const McPoint& p : pts)
    if (!finite3(p.ours) || !finite3(p.mc)) ++bad;
  std::string details = fmt::format("segment {} ({:.0f} % of the upper hemisphere occluded), fleece:", pick, 100.0 * best);
  double soft = 0.0, sharp = 0.0, sharpPca = 0.0, sharpHalf = 0.0;
  details += " mean (max beyond 4σ) per λ:";
  for (double lambda : {10.0, 50.0, 150.0, 400.0, 1000.0}) {
    const double e = mcMeanError(pts, lambda), ep = mcMeanError(viaPca, lambda);
    details += fmt::format(" λ={:g} {:.3f} ({:.3f}), PCA SSDF {:.3f} ({:.3f});", lambda, e, mcError(pts, lambda), ep,
                           mcError(viaPca, lambda));
    (lambda <= 150.0 ? soft : sharp) = maxKeepNaN(lambda <= 150.0 ? soft : sharp, e);
    if (lambda > 150.0) sharpPca = maxKeepNaN(sharpPca, ep), sharpHalf = maxKeepNaN(sharpHalf, mcMeanError(halfPixel, lambda));
  }
  r.details = details;
  r.metrics = {
      Metric{"exemplar.soft_vs_mc", soft, kExemplarSoftTolerance, "",
             "λ ∈ {10, 50, 150}: Σ|ours − MC|/Σ MC over 12 lights, sum of SGs (and the blend) vs MC with the segment's "
             "exact 64² binary image: the representation's ripple (prt/ss/lone) and softness (004 Fig. 6b: too bright "
             "in shadow); light through the fabric from below, which the upper-hemisphere SGs leave out"},
      Metric{"exemplar.sharp_vs_mc", sharp, kExemplarSharpTolerance, "",
             "λ ∈ {400, 10³}: the same for Ṽ_loc(SSDF) Γ: the SSDF is a distance between pixel centres, half a pixel "
             "(1.4°–2.8°) more than to the edge, which at λ = 400 (SG width 2.9°) turns a half-lit light into "
             "Ṽ ≈ 0.17 or 0.83 (004 Fig. 6c); the max per light is in the details"},
      Metric{"exemplar.sharp_pca_vs_mc", sharpPca, 0.3, "",
             fmt::format("the same with the SSDF decoded from a PCA of {} segments' SSDFs ({} components, svfPcaCpu)",
                         rows, pca.components)},
      Metric{"exemplar.sharp_half_pixel_vs_mc", sharpHalf, 0.0, "",
             "experiment: the exact SSDF moved half a row towards 0 (≈ the distance to the pixel edge): the sharp "
             "branch's aggregate error drops from 0.35 to 0.22 — much of it is the SSDF's centre-to-centre convention, "
             "not Γ or Ṽ_loc",
             false},
      nonFiniteMetric("cpu", bad, "ours and MC"),
  };
  r.finish();
  return r;
}

// A segment along x beside a parallel infinite cylinder (axis distance d,
// radius r, azimuth α about x): V = 0 on the lune |φ_x − α| < asin(r/d),
// φ_x = atan2(ω_z, ω_y) (notes-appearance §5.6). The SVF data come from the
// lune drawn into a 64² image here (svfSsdfCpu, svfWeightsCpu); the MC uses
// the exact, continuous lune.
CaseResult runSsCylinderCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = startSs(name);
  const Fabrics& fs = fabrics(ctx);
  const auto t0 = Clock::now();
  const double d = 0.1, rc = 0.03, alpha = 1.2, half = std::asin(rc / d);
  const auto wrap = [](double a) {
    a = std::fmod(a + kPi, 2.0 * kPi);
    return (a < 0.0 ? a + 2.0 * kPi : a) - kPi;
  };
  const auto visible = [&](glm::dvec3 w) {
    if (w.y * w.y + w.z * w.z < 1e-20) return 1.0;
    return std::abs(wrap(std::atan2(w.z, w.y) - alpha)) < half ? 0.0 : 1.0;
  };
  const int W = 64, H = 64;
  std::vector<uint8_t> img(size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double th = kPi * (y + 0.5) / H, ph = 2.0 * kPi * (x + 0.5) / W - kPi;
      img[size_t(y) * W + size_t(x)] = uint8_t(visible(sphericalZ(th, ph)));
    }
  const float angle = ftSvfRotationAngle(5u, 1u);
  const std::vector<float> ssdf = svfSsdfCpu(img, W, H);
  const std::vector<float> weights = svfWeightsCpu(img, W, H, FT_SVF_DEFAULT_AXES, angle);
  const auto pixel = [&](glm::dvec3 w) {
    const double th = std::acos(std::clamp(w.z, -1.0, 1.0)), ph = std::atan2(w.y, w.x);
    return size_t(std::clamp(int(th / kPi * H), 0, H - 1)) * W + size_t(std::clamp(int((ph + kPi) / (2.0 * kPi) * W), 0, W - 1));
  };
  const glm::dvec3 t(1, 0, 0);
  const int f = fs.index("fleece");
  std::vector<McPoint> pts;
  // Lights on a ring across the lune: x-component 0.3, azimuth about x from α − 0.6 to α + 0.6.
  for (int k = -6; k <= 6; ++k)
    for (double lambda : {50.0, 150.0, 400.0, 1000.0}) {
      const double ph = alpha + 0.1 * k, c = std::sqrt(1.0 - 0.09);
      const glm::dvec3 xi(0.3, c * std::cos(ph), c * std::sin(ph));
      pts.push_back({xi, specularView(t, xi), lambda, {}, {}, {}});
    }
  evaluateOurs(fs, f, t, weights, angle, [&](glm::dvec3 w) { return double(ssdf[pixel(w)]); }, pts);
  runMc(fs, f, t, visible, kMcSamples, pts);
  r.cpuMilliseconds = msSince(t0);
  uint64_t bad = 0;
  for (const McPoint& p : pts)
    if (!finite3(p.ours) || !finite3(p.mc)) ++bad;
  double soft = 0.0, sharp = 0.0;
  std::string details = "fleece, 13 lights across the lune, Σ|ours − MC|/Σ MC (max beyond 4σ) per λ:";
  for (double lambda : {50.0, 150.0, 400.0, 1000.0}) {
    const double e = mcMeanError(pts, lambda);
    details += fmt::format(" λ={:g} {:.3f} ({:.3f});", lambda, e, mcError(pts, lambda));
    (lambda <= 150.0 ? soft : sharp) = maxKeepNaN(lambda <= 150.0 ? soft : sharp, e);
  }
  r.details = details;
  r.metrics = {
      Metric{"cylinder.soft_vs_mc", soft, kCylinderSoftTolerance, "",
             "λ ∈ {50, 150}: the sum of SGs (and the blend) vs MC with the exact lune of a parallel cylinder "
             "(occluded half-width asin(r/d) = 17.5°, 69° up): the representation's ripple and softness"},
      Metric{"cylinder.sharp_vs_mc", sharp, kCylinderSharpTolerance, "",
             "λ ∈ {400, 10³}: Ṽ_loc(SSDF of the 64² image) Γ vs MC with the exact lune: the SSDF's pixel "
             "quantisation (2.8° × 5.6° pixels, centre-to-centre distances) against an edge the SG straddles"},
      nonFiniteMetric("cpu", bad, "ours and MC"),
  };
  r.finish();
  return r;
}

// ---- CPU vs GPU ---------------------------------------------------------------
CaseResult runSsGpuCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = startSs(name);
  const Fabrics& fs = fabrics(ctx);
  PrtSingleScatteringGpu& gpu = ctx.gpu<PrtSingleScatteringGpu>();
  // The 𝒢 tables: GPU (bcsdf.h's Z in float) vs CPU (double quadrature here).
  const auto g0 = Clock::now();
  const std::vector<float> gTable = gpu.bakeTable(fs.params);
  double tableErr = 0.0;
  uint64_t badGpu = 0;
  for (size_t i = 0; i < gTable.size(); ++i) {
    if (!std::isfinite(gTable[i])) ++badGpu;
    tableErr = maxKeepNaN(tableErr, std::abs(double(gTable[i]) - fs.table[i]) / std::max(fs.table[i], 1e-3));
  }
  // Segment data: row 0 a lone segment (all visible), row 1 a half-occluded one
  // (the lower half of the axes' weights zero), SSDF from a cap boundary.
  const int W = 64, H = 64, Q = FT_SVF_DEFAULT_AXES;
  const std::vector<uint8_t> all(size_t(W) * H, 1);
  std::vector<uint8_t> half(size_t(W) * H, 1);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W / 2; ++x) half[size_t(y) * W + size_t(x)] = 0;  // φ < 0 occluded
  const float a0 = ftSvfRotationAngle(0u, 1u), a1 = ftSvfRotationAngle(1u, 1u);
  std::vector<float> weights = svfWeightsCpu(all, W, H, Q, a0);
  const std::vector<float> w1 = svfWeightsCpu(half, W, H, Q, a1);
  weights.insert(weights.end(), w1.begin(), w1.end());
  const std::vector<float> ssdf1 = svfSsdfCpu(half, W, H);
  const auto pixel = [&](glm::vec3 w) {
    const double th = std::acos(std::clamp(double(w.z), -1.0, 1.0)), ph = std::atan2(double(w.y), double(w.x));
    return size_t(std::clamp(int(th / kPi * H), 0, H - 1)) * W + size_t(std::clamp(int((ph + kPi) / (2 * kPi) * W), 0, W - 1));
  };
  const std::vector<double> lambdas = {10, 50, 100, 150, 200, 400, 1000, 10000};
  const glm::vec3 t = glm::normalize(glm::vec3(1.0f, 0.2f, 0.1f)), wo = glm::normalize(glm::vec3(0.2f, -0.5f, 0.8f));
  std::vector<PrtSsRequest> req;
  std::vector<int> groupOf;  // (fabric slot, λ index or 8 = directional)
  int slot = 0;
  for (const char* fn : {"fleece", "silk"}) {
    const int f = fs.index(fn);
    for (int li = 0; li <= int(lambdas.size()); ++li)
      for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
          const glm::vec3 xi =
              glm::vec3(sphericalZ(kPi * (y + 0.5) / 32.0, 2.0 * kPi * (x + 0.5) / 64.0 - kPi));
          const int row = (x + y) % 2;
          PrtSsRequest q{};
          q.tangent = glm::vec4(t, float(f));
          q.outgoing = glm::vec4(wo, 0.75f);
          q.light = glm::vec4(glm::normalize(xi), li < int(lambdas.size()) ? float(lambdas[size_t(li)]) : 0.0f);
          q.segment = glm::vec4(row == 0 ? float(kPi) : ssdf1[pixel(xi)], row == 0 ? a0 : a1, float(row), 0.0f);
          req.push_back(q);
          groupOf.push_back(slot * 16 + li);
        }
    ++slot;
  }
  const std::vector<glm::vec4> g = gpu.evaluate(fs.params, gTable, req, weights, Q, FT_SVF_LAMBDA);
  r.gpuMilliseconds = msSince(g0);
  r.gpuTiming = "wall clock of the table bake + upload + evaluate + read-back";
  const auto c0 = Clock::now();
  PrtSsSegments segs;
  segs.axes = Q;
  segs.weights = weights;
  // The CPU evaluates with the GPU's float table (converted): the table bake is compared above.
  const std::vector<double> gTableD(gTable.begin(), gTable.end());
  const std::vector<glm::dvec3> c = evaluatePrtSsCpu(fs.params, gTableD, req, segs);
  r.cpuMilliseconds = msSince(c0);
  std::vector<double> groupMax(32, 0.0);
  uint64_t badCpu = 0;
  for (size_t i = 0; i < c.size(); ++i) {
    if (!finite3(c[i])) ++badCpu;
    groupMax[size_t(groupOf[i])] = std::max(groupMax[size_t(groupOf[i])], maxComp(c[i]));
  }
  double worst = 0.0;
  size_t worstIdx = 0;
  std::vector<double> perLambda(lambdas.size() + 1, 0.0);
  for (size_t i = 0; i < c.size(); ++i) {
    const glm::dvec3 gv(g[i]);
    if (!finite3(gv)) ++badGpu;
    const double e = maxAbsDiff(gv, c[i]) / (maxComp(glm::abs(c[i])) + 1e-2 * groupMax[size_t(groupOf[i])] + 1e-300);
    r.histogram.add(e);
    if (!(e <= worst)) worstIdx = i;
    worst = maxKeepNaN(worst, e);
    perLambda[size_t(groupOf[i] % 16)] = maxKeepNaN(perLambda[size_t(groupOf[i] % 16)], e);
  }
  std::string per;
  for (size_t li = 0; li < perLambda.size(); ++li)
    per += li < lambdas.size() ? fmt::format("λ={:g} {:.1e}; ", lambdas[li], perLambda[li])
                               : fmt::format("directional {:.1e}", perLambda[li]);
  r.details = fmt::format("worst request {} (λ {}): cpu ({:.8g} {:.8g} {:.8g}) gpu ({:.8g} {:.8g} {:.8g}); per λ: {}",
                          worstIdx, req[worstIdx].light.w, c[worstIdx].x, c[worstIdx].y, c[worstIdx].z, g[worstIdx].x,
                          g[worstIdx].y, g[worstIdx].z, per);
  r.histogramMetric = "sweep.max_rel";
  r.metrics = {
      Metric{"table.max_rel", tableErr, 2e-5, "",
             "GPU 𝒢 texels (bcsdf.h's Z: closed form, or 20-point Gauss–Legendre over the ±6β window clipped at ±π/2, "
             "in float) vs the CPU's double quadrature over ±10β, relative to max(Z, 1e-3): measured 8e-6 (the "
             "window's truncation and float)"},
      Metric{"sweep.max_rel", worst, 1e-4, "",
             fmt::format("GPU vs CPU radiance over {} requests (64 × 32 light axes × 8 λ + directional, fleece and silk, "
                         "2 segments), |Δ| / (|cpu| + 1e-2 · the largest of its fabric and λ): float vs double with the "
                         "same table (notes §6.6: 1e-4 rel + 1e-6 of the max)",
                         req.size())},
      Metric{"gpu.nan_count", double(badGpu), 0, "count", "non-finite GPU texels and radiances"},
      nonFiniteMetric("cpu", badCpu, "CPU radiances"),
      Metric{"gl.max_uniform_buffer_bindings", double(gpu.maxUniformBufferBindings()), 0, "count",
             fmt::format("the driver's GL_MAX_UNIFORM_BUFFER_BINDINGS (FT_UBO_PRT_SS = {} must be below)", FT_UBO_PRT_SS),
             false},
  };
  r.finish();
  return r;
}

}  // namespace

void addPrtSingleScatteringCases(ValidationContext&, std::vector<ValidationCase>& out) {
  out.push_back({"prt/ss/gamma", [](ValidationContext& c) { return runGammaCase(c, "prt/ss/gamma"); }});
  out.push_back({"prt/ss/delta", [](ValidationContext& c) { return runDeltaCase(c, "prt/ss/delta"); }});
  out.push_back({"prt/ss/limits", [](ValidationContext& c) { return runLimitsCase(c, "prt/ss/limits"); }});
  out.push_back({"prt/ss/furnace", [](ValidationContext& c) { return runFurnaceCase(c, "prt/ss/furnace"); }});
  out.push_back({"prt/ss/lone", [](ValidationContext& c) { return runSsLoneCase(c, "prt/ss/lone"); }});
  out.push_back({"prt/ss/exemplar", [](ValidationContext& c) { return runExemplarCase(c, "prt/ss/exemplar"); }});
  out.push_back({"prt/ss/cylinder", [](ValidationContext& c) { return runSsCylinderCase(c, "prt/ss/cylinder"); }});
  out.push_back({"prt/ss/gpu", [](ValidationContext& c) { return runSsGpuCase(c, "prt/ss/gpu"); }});
}

}  // namespace ft
