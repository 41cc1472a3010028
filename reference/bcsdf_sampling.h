// bcsdf_sampling.h — importance sampling of the fiber scattering of
// common/fiber_shading.h for the path-traced ground truth (CPU only; the GPU
// never samples). The integrand at a fiber point is the bracket of
// fiber_shading.h per unit incident radiance,
//   h(ω_i) = (1 − k_d) f(ω_i, ω_o) cos θ_i + (k_d/π) max(0, n·ω_i),
// with f the BCSDF of 000 §4.3 eq. 6 (or the simple model, eq. 5). A
// continuation direction is drawn from a one-sample mixture of its lobes
// (notes-rendering §0.2):
//   R:       θ_i from the Gaussian g(θ_i + θ_o; β_R) truncated to [−π/2, π/2], φ uniform;
//   TT:      θ_i likewise with β_TT, φ from the von Mises N_TT centred at π (κ = γ_TT^−2);
//   simple:  θ_i likewise with 2β (eq. 5's exp(−θ_h²/2β²), θ_h = (θ_i + θ_o)/2), φ uniform;
//   diffuse: cosine about the surface normal n.
// Each lobe is picked with the probability of its albedo at θ_o (R: F(θ_o),
// TT: (1 − F(θ_o)) C_TT, both times 1 − k_d, diffuse: k_d, averaged over RGB), and the weight
// divides h by the mixture's density in solid angle, dω = cos θ dθ dφ, so
// the estimate is unbiased whatever the pick probabilities are.
#pragma once
#include <cstdint>

#include "common/fiber_shading.h"

namespace ft {

// The uniform numbers of one (pixel, sample, seed): the shared hash of
// common/rng.h over (pixel, sample, seed, draw counter), four numbers per
// hash. A value depends on nothing else (thread count, tile order).
class RandomStream {
 public:
  RandomStream(uint32_t pixel, uint32_t sample, uint32_t seed) : pixel_(pixel), sample_(sample), seed_(seed) {}
  float next();  // [0, 1), 24 bits

 private:
  uint32_t pixel_, sample_, seed_;
  uint32_t counter_ = 0;
  uvec4 bits_{0u};
  int left_ = 0;
};

// The continuation lobes of one fiber point (tangent t, normal n, towards
// the eye ω_o, all unit vectors).
class FiberScatter {
 public:
  FiberScatter(const ShadingParams& s, vec3 t, vec3 n, vec3 wo);

  // Whether anything scatters (some lobe has a non-zero albedo).
  bool scatters() const { return total_ > 0.0; }
  // A direction ω_i drawn from the mixture. Requires scatters().
  vec3 sample(RandomStream& rng) const;
  // h(ω_i) / p(ω_i) per channel, p the mixture's solid-angle density; 0
  // where p vanishes.
  vec3 weight(vec3 wi) const;
  // The mixture's density at ω_i per unit dθ_i dφ, i.e. p(ω_i) cos θ_i
  // (finite at θ_i = ±π/2, where the solid-angle density is not).
  double angularDensity(vec3 wi) const;

 private:
  struct Lobe {
    double probability = 0.0;
    bool diffuse = false;  // cosine about n; otherwise Gaussian in θ_i + θ_o:
    double beta = 0.0;     //   its width,
    double kappa = 0.0;    //   the von Mises concentration of φ about π (0: φ uniform),
    double norm = 1.0;     //   its mass inside θ_i ∈ [−π/2, π/2]
  };
  double angularDensity(const FiberAngles& a, vec3 wi) const;

  ShadingParams unitLight_;  // s with light 0 of irradiance 1: ftFiberDirect(unitLight_, 0, ...) is h
  vec3 t_, n_, wo_;
  vec3 u_, w_;               // azimuth frame: u_ along ω_o's part normal to t (φ = 0), w_ = t × u_
  float thetaO_ = 0.0f;
  Lobe lobes_[3];
  int lobeCount_ = 0;
  double total_ = 0.0;       // sum of the lobes' albedos (pick weights)
};

// A von Mises deviate on (−π, π] about 0 (Best & Fisher 1979), κ > 0.
double sampleVonMises(double kappa, RandomStream& rng);

}  // namespace ft
