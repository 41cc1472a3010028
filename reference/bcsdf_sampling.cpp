#include "reference/bcsdf_sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/rng.h"

#include "reference/numbers.h"

namespace ft {

namespace {

constexpr double kHalfPi = 0.5 * std::numbers::pi;

double gaussian(double x, double beta) {
  const double r = x / beta;
  return std::exp(-0.5 * r * r) / (std::sqrt(2.0 * kPi) * beta);
}

// Mass of the Gaussian g(· ; β) on [lo, hi].
double gaussianMass(double lo, double hi, double beta) {
  const double s = 1.0 / (std::sqrt(2.0) * beta);
  return 0.5 * (std::erf(hi * s) - std::erf(lo * s));
}

// N(0, β) restricted to [lo, hi] (lo < 0 < hi here: the window always holds
// the lobe's centre, so at least half the draws are kept).
double sampleTruncatedGaussian(double beta, double lo, double hi, RandomStream& rng) {
  for (;;) {
    const double u1 = 1.0 - rng.next();  // (0, 1]
    const double u2 = rng.next();
    const double x = beta * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
    if (x >= lo && x <= hi) return x;
  }
}

double meanOf(vec3 c) { return (double(c.x) + double(c.y) + double(c.z)) / 3.0; }

}  // namespace

float RandomStream::next() {
  if (left_ == 0) {
    bits_ = ftPcg4d(uvec4(pixel_, sample_, seed_, counter_++));
    left_ = 4;
  }
  return ftUnitFloat(bits_[--left_]);
}

double sampleVonMises(double kappa, RandomStream& rng) {
  // Best & Fisher, "Efficient simulation of the von Mises distribution",
  // Applied Statistics 28 (1979): wrapped-Cauchy envelope.
  const double tau = 1.0 + std::sqrt(1.0 + 4.0 * kappa * kappa);
  const double rho = (tau - std::sqrt(2.0 * tau)) / (2.0 * kappa);
  const double r = (1.0 + rho * rho) / (2.0 * rho);
  for (;;) {
    const double z = std::cos(kPi * rng.next());
    const double f = (1.0 + r * z) / (r + z);
    const double c = kappa * (r - f);
    const double u2 = 1.0 - rng.next();  // (0, 1]
    if (c * (2.0 - c) > u2 || std::log(c / u2) + 1.0 - c >= 0.0) {
      const double phi = std::acos(std::clamp(f, -1.0, 1.0));
      return rng.next() < 0.5 ? -phi : phi;
    }
  }
}

FiberScatter::FiberScatter(const ShadingParams& s, vec3 t, vec3 n, vec3 wo) : unitLight_(s), t_(t), n_(n), wo_(wo) {
  unitLight_.lightIrradiance[0] = vec4(1.0f, 1.0f, 1.0f, 0.0f);
  thetaO_ = std::asin(std::clamp(dot(wo, t), -1.0f, 1.0f));  // ftFiberAngles' θ_o
  // Azimuth frame: φ = 0 along ω_o's part normal to t (any normal of t when
  // ω_o runs along the fiber: f does not depend on φ there).
  vec3 perp = wo - dot(wo, t) * t;
  if (dot(perp, perp) < 1e-12f) perp = std::abs(t.x) < 0.9f ? cross(t, vec3(1, 0, 0)) : cross(t, vec3(0, 1, 0));
  u_ = normalize(perp);
  w_ = cross(t, u_);

  const double thetaO = thetaO_;
  auto longitudinal = [&](double albedo, double beta, double kappa) {
    if (albedo <= 0.0) return;
    // θ_i = x − θ_o with x ~ g(x; β) on the x for which θ_i ∈ [−π/2, π/2].
    lobes_[lobeCount_++] = {albedo, false, beta, kappa, gaussianMass(thetaO - kHalfPi, thetaO + kHalfPi, beta)};
  };
  if (s.flags.y == FT_SHADING_SIMPLE) {
    // ∫∫ k_s cos(φ/2) exp(−θ_h²/2β²) cos²θ_i dθ_i dφ ≈ k_s · 4 · 2β√(2π) cos²θ_o.
    const double beta = s.simple.y;
    const double c = std::cos(thetaO);
    longitudinal(meanOf(vec3(1.0f) - vec3(s.diffuse)) * s.simple.x * 8.0 * std::sqrt(2.0 * kPi) * beta * c * c,
                 2.0 * beta, 0.0);
  } else {
    // Albedos of eq. 6 (notes-rendering B1) with F taken at θ_o: the lobes
    // send θ_i to about −θ_o, and F is even.
    const FabricParams& p = s.fabric;
    // The BCSDF carries 1 − k_d of the energy (fiber_shading.h).
    const vec3 share = vec3(1.0f) - vec3(s.diffuse);
    const vec3 fresnel = ftFiberFresnel(vec3(p.colorR), thetaO_);
    longitudinal(meanOf(share * fresnel), p.colorR.w, 0.0);
    longitudinal(meanOf(share * (vec3(1.0f) - fresnel) * vec3(p.colorTT)), p.colorTT.w, p.lobes.y);
  }
  if (const double kd = meanOf(vec3(s.diffuse)); kd > 0.0) lobes_[lobeCount_++] = {kd, true};
  for (int i = 0; i < lobeCount_; ++i) total_ += lobes_[i].probability;
  for (int i = 0; i < lobeCount_; ++i) lobes_[i].probability /= total_;
}

vec3 FiberScatter::sample(RandomStream& rng) const {
  const double pick = rng.next();
  int k = 0;
  double below = lobes_[0].probability;  // probability of lobes 0..k
  while (k + 1 < lobeCount_ && pick >= below) below += lobes_[++k].probability;
  const Lobe& lobe = lobes_[k];
  if (lobe.diffuse) {
    // Cosine-weighted about n (Malley: a uniform disk lifted to the hemisphere).
    const double r = std::sqrt(rng.next()), a = 2.0 * kPi * rng.next();
    const vec3 b1 = normalize(std::abs(n_.x) < 0.9f ? cross(n_, vec3(1, 0, 0)) : cross(n_, vec3(0, 1, 0)));
    const vec3 b2 = cross(n_, b1);
    const double z = std::sqrt(std::max(0.0, 1.0 - r * r));
    return normalize(float(r * std::cos(a)) * b1 + float(r * std::sin(a)) * b2 + float(z) * n_);
  }
  const double thetaO = thetaO_;
  const double x = sampleTruncatedGaussian(lobe.beta, thetaO - kHalfPi, thetaO + kHalfPi, rng);
  const double thetaI = std::clamp(x - thetaO, -kHalfPi, kHalfPi);
  const double phi = lobe.kappa > 0.0 ? kPi + sampleVonMises(lobe.kappa, rng) : 2.0 * kPi * rng.next();
  const double c = std::cos(thetaI);
  return normalize(float(std::sin(thetaI)) * t_ + float(c * std::cos(phi)) * u_ + float(c * std::sin(phi)) * w_);
}

double FiberScatter::angularDensity(const FiberAngles& a, vec3 wi) const {
  double p = 0.0;
  for (int i = 0; i < lobeCount_; ++i) {
    const Lobe& lobe = lobes_[i];
    double density;
    if (lobe.diffuse) {
      density = std::max(0.0f, dot(n_, wi)) / kPi * std::cos(double(a.thetaI));
    } else {
      density = gaussian(double(a.thetaI) + double(a.thetaO), lobe.beta) / lobe.norm;
      // N_TT of bcsdf.h, exp(κ cos(φ − π)) / (2π I0(κ)), with I0 scaled by e^−κ.
      density *= lobe.kappa > 0.0 ? std::exp(-lobe.kappa * (1.0 + std::cos(double(a.phi)))) /
                                        (2.0 * kPi * double(ftBesselI0e(float(lobe.kappa))))
                                  : 1.0 / (2.0 * kPi);
    }
    p += lobe.probability * density;
  }
  return p;
}

double FiberScatter::angularDensity(vec3 wi) const { return angularDensity(ftFiberAngles(t_, wi, wo_), wi); }

vec3 FiberScatter::weight(vec3 wi) const {
  const FiberAngles a = ftFiberAngles(t_, wi, wo_);
  const double density = angularDensity(a, wi);
  if (!(density > 0.0)) return vec3(0.0f);
  ShadingParams s = unitLight_;
  s.lightDirection[0] = vec4(wi, 0.0f);
  // h dω / (p dω) with dω = cos θ_i dθ_i dφ: h cos θ_i over the angular density.
  return ftFiberDirect(s, 0, t_, n_, wo_) * float(std::cos(double(a.thetaI)) / density);
}

}  // namespace ft
