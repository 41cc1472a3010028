#include "reference/prt_single_scattering.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <random>

#include "scene/input_error.h"

#include "reference/numbers.h"

namespace ft {
namespace {


// 8-point Gauss–Legendre on [−1, 1].
constexpr double kGl8X[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
constexpr double kGl8W[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

// Z(θ) = ∫_{−π/2}^{π/2} g(x + θ; β) cos²x dx, g the normalised Gaussian.
double lobeNormDouble(double theta, double beta) {
  const double a = std::max(-0.5 * kPi, -theta - 10.0 * beta), b = std::min(0.5 * kPi, -theta + 10.0 * beta);
  if (b <= a) return 0.0;
  const int panels = std::max(1, int(std::ceil((b - a) / (0.25 * beta))));
  const double h = (b - a) / panels, norm = 1.0 / (std::sqrt(2.0 * kPi) * beta);
  double z = 0.0;
  for (int p = 0; p < panels; ++p) {
    const double c = a + (p + 0.5) * h;
    for (int k = 0; k < 4; ++k)
      for (double sgn : {-1.0, 1.0}) {
        const double x = c + sgn * 0.5 * h * kGl8X[k], r = (x + theta) / beta, cx = std::cos(x);
        z += 0.5 * h * kGl8W[k] * norm * std::exp(-0.5 * r * r) * cx * cx;
      }
  }
  return z;
}

bool unitFinite(glm::vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::abs(glm::length(v) - 1.0f) < 1e-3f;
}

}  // namespace

std::vector<double> bakePrtSsTableCpu(std::span<const FabricParams> fabrics, int texels) {
  if (fabrics.empty() || fabrics.size() > FT_PRT_SS_MAX_FABRICS)
    throw InputError(fmt::format("prt single scattering: {} fabrics (1 to {})", fabrics.size(), FT_PRT_SS_MAX_FABRICS));
  if (texels < 2) throw InputError(fmt::format("prt single scattering: table of {} texels (at least 2)", texels));
  for (size_t f = 0; f < fabrics.size(); ++f)
    if (!(fabrics[f].colorR.w > 0.0f) || !(fabrics[f].colorTT.w > 0.0f))
      throw InputError(fmt::format("prt single scattering: fabric {}: beta_R {} beta_TT {} (must be > 0)", f,
                                   fabrics[f].colorR.w, fabrics[f].colorTT.w));
  const size_t rows = 2 * fabrics.size();
  std::vector<double> table(rows * size_t(texels));
  tbb::parallel_for(size_t(0), table.size(), [&](size_t i) {
    const size_t row = i / size_t(texels), k = i % size_t(texels);
    const FabricParams& p = fabrics[row / 2];
    const double beta = row % 2 == 0 ? p.colorR.w : p.colorTT.w;
    const double theta = -0.5 * kPi + double(k) * kPi / double(texels - 1);
    table[i] = lobeNormDouble(theta, beta);
  });
  return table;
}

std::vector<glm::dvec3> evaluatePrtSsCpu(std::span<const FabricParams> fabrics, std::span<const double> table,
                                         std::span<const PrtSsRequest> requests, const PrtSsSegments& segs) {
  if (table.size() != 2 * fabrics.size() * size_t(FT_PRT_SS_TABLE_SIZE))
    throw InputError(fmt::format("prt single scattering: table of {} values for {} fabrics (expected {})",
                                 table.size(), fabrics.size(), 2 * fabrics.size() * FT_PRT_SS_TABLE_SIZE));
  if (segs.axes < 1 || segs.axes > FT_SVF_MAX_AXES || segs.weights.size() % size_t(segs.axes) != 0 ||
      !(segs.lambdaSvf > 0.0f))
    throw InputError(fmt::format("prt single scattering: {} weights for Q = {} axes, lambda_svf {}",
                                 segs.weights.size(), segs.axes, segs.lambdaSvf));
  const size_t rows = segs.weights.size() / size_t(segs.axes);
  for (size_t i = 0; i < requests.size(); ++i) {
    const PrtSsRequest& q = requests[i];
    const auto bad = [&](const char* field, double v) {
      throw InputError(fmt::format("prt single scattering: request {}: {} = {}", i, field, v));
    };
    if (!(q.tangent.w >= 0.0f) || size_t(q.tangent.w) >= fabrics.size() || q.tangent.w != std::floor(q.tangent.w))
      bad("fabric index", q.tangent.w);
    if (!unitFinite(glm::vec3(q.tangent))) bad("|tangent|", glm::length(glm::vec3(q.tangent)));
    if (!unitFinite(glm::vec3(q.outgoing))) bad("|outgoing|", glm::length(glm::vec3(q.outgoing)));
    if (!unitFinite(glm::vec3(q.light))) bad("|light axis|", glm::length(glm::vec3(q.light)));
    if (!std::isfinite(q.light.w)) bad("lambda", q.light.w);
    if (!std::isfinite(q.outgoing.w)) bad("V_glo", q.outgoing.w);
    if (!std::isfinite(q.segment.x)) bad("SSDF", q.segment.x);
    if (!std::isfinite(q.segment.y)) bad("R_k angle", q.segment.y);
    if (q.light.w > 0.0f && (!(q.segment.z >= 0.0f) || size_t(q.segment.z) >= rows)) bad("weights row", q.segment.z);
  }
  std::vector<glm::dvec3> out(requests.size());
  tbb::parallel_for(size_t(0), requests.size(), [&](size_t i) {
    const PrtSsRequest& q = requests[i];
    const glm::dvec3 t(glm::vec3(q.tangent)), wo(glm::vec3(q.outgoing)), l(glm::vec3(q.light));
    const int fabric = int(q.tangent.w);
    if (q.light.w <= 0.0f) {
      out[i] = prtss64::ftPrtSsDirectional(fabrics[size_t(fabric)], t, wo, l, q.segment.x, q.outgoing.w);
      return;
    }
    double w[FT_SVF_MAX_AXES] = {};
    const size_t row = size_t(q.segment.z);
    for (int k = 0; k < segs.axes; ++k) w[k] = segs.weights[row * size_t(segs.axes) + size_t(k)];
    out[i] = prtss64::ftPrtSsSgLight(table.data(), fabrics[size_t(fabric)], fabric, t, wo, l, q.light.w, q.segment.x, w,
                                     segs.axes, q.segment.y, segs.lambdaSvf, q.outgoing.w);
  });
  return out;
}

PrtSsMcResult prtSsMonteCarlo(const PrtSsBcsdf& bcsdf, const PrtSsVisibility& visibility, glm::dvec3 t,
                              glm::dvec3 wo, glm::dvec3 xi, double lambda, const PrtSsMcSettings& s) {
  // Fiber frame: x = t, y = ω_o's part perpendicular to t (any if none), z = x × y.
  glm::dvec3 y = wo - glm::dot(wo, t) * t;
  if (glm::length(y) < 1e-9) y = std::abs(t.x) < 0.9 ? glm::cross(t, glm::dvec3(1, 0, 0)) : glm::cross(t, glm::dvec3(0, 1, 0));
  y = glm::normalize(y);
  const glm::dvec3 z = glm::cross(t, y);
  const double thetaO = std::asin(std::clamp(glm::dot(wo, t), -1.0, 1.0));
  // SG frame about ξ.
  const glm::dvec3 a = std::abs(xi.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u1 = glm::normalize(glm::cross(xi, a)), u2 = glm::cross(xi, u1);
  const double oneMinusE = -std::expm1(-2.0 * lambda);           // 1 − e^{−2λ}
  const double pdfScale = lambda / (2.0 * kPi * oneMinusE);      // 1/M(λ)
  const double betas[2] = {s.betaR, s.betaTT};
  double truncMass[2];
  for (int p = 0; p < 2; ++p)
    truncMass[p] = 0.5 * (std::erf((0.5 * kPi + thetaO) / (std::sqrt(2.0) * betas[p])) -
                          std::erf((-0.5 * kPi + thetaO) / (std::sqrt(2.0) * betas[p])));
  const auto pdfSg = [&](glm::dvec3 w) { return pdfScale * std::exp(lambda * (glm::dot(w, xi) - 1.0)); };
  const auto pdfBcsdf = [&](double theta) {
    const double c = std::cos(theta);
    if (c <= 1e-12) return 0.0;
    double sum = 0.0;
    for (int p = 0; p < 2; ++p) {
      const double r = (theta + thetaO) / betas[p];
      sum += std::exp(-0.5 * r * r) / (std::sqrt(2.0 * kPi) * betas[p] * truncMass[p]);
    }
    return 0.5 * sum / (2.0 * kPi * c);
  };
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  glm::dvec3 sum(0.0), sum2(0.0);
  for (int i = 0; i < s.samples; ++i) {
    glm::dvec3 w;
    if (i % 2 == 0) {  // the SG: cos Δ = 1 + ln(1 − u(1 − e^{−2λ}))/λ
      const double cd = std::clamp(1.0 + std::log1p(-uni(rng) * oneMinusE) / lambda, -1.0, 1.0);
      const double sd = std::sqrt(std::max(0.0, 1.0 - cd * cd)), ph = 2.0 * kPi * uni(rng);
      w = cd * xi + sd * (std::cos(ph) * u1 + std::sin(ph) * u2);
    } else {  // the BCSDF: a lobe, θ from its Gaussian about −θ_o (truncated), φ uniform
      const double beta = betas[uni(rng) < 0.5 ? 0 : 1];
      std::normal_distribution<double> g(-thetaO, beta);
      double th;
      do th = g(rng);
      while (!(th > -0.5 * kPi && th < 0.5 * kPi));
      const double ph = 2.0 * kPi * uni(rng) - kPi;
      w = std::sin(th) * t + std::cos(th) * (std::cos(ph) * y + std::sin(ph) * z);
    }
    w = glm::normalize(w);
    glm::dvec3 f(0.0);
    const double vis = visibility(w);
    if (vis > 0.0) {
      const double thetaI = std::asin(std::clamp(glm::dot(w, t), -1.0, 1.0));
      const double phi = std::abs(std::atan2(glm::dot(w, z), glm::dot(w, y)));
      const double pSg = pdfSg(w), mix = 0.5 * pSg + 0.5 * pdfBcsdf(thetaI);
      if (mix > 0.0) f = vis * bcsdf(thetaI, thetaO, phi) * (std::cos(thetaI) * pSg / mix);
    }
    sum += f;
    sum2 += f * f;
  }
  PrtSsMcResult r;
  const double n = double(s.samples);
  r.mean = sum / n;
  r.stdError = glm::sqrt(glm::max(sum2 / n - r.mean * r.mean, glm::dvec3(0.0)) / n);
  return r;
}

}  // namespace ft
