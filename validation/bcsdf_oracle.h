// bcsdf_oracle.h — expected values for the BCSDF cases (bcsdf_cases.cpp),
// written from the formulas of 000 §4.3 and notes-rendering §0.2 in double,
// from a fabric's numbers. Deliberately independent of common/: neither this
// header nor bcsdf_oracle.cpp includes common/bcsdf.h (or anything that does),
// so a wrong formula there cannot reach the expectation.
#pragma once
#include <glm/glm.hpp>
#include <span>
#include <vector>

namespace ft::oracle {

// A fabric preset's numbers (scene/fabric.h's FabricPreset, copied by the caller).
struct Fabric {
  double colorR[3] = {0, 0, 0};
  double colorTT[3] = {0, 0, 0};
  double betaRDegrees = 0, betaTTDegrees = 0, gammaTTDegrees = 0;
  double betaR() const;   // radians
  double betaTT() const;  // radians
  double kappa() const;   // γ_TT^−2, γ in radians
};

// Schlick's Fresnel F = C + (1 − C)(1 − |cos θ_i|)^5, per channel.
glm::dvec3 fresnel(const Fabric& f, double thetaI);
// B1: the albedo ∫∫ f cos²θ_o dθ_o dφ of eq. 6 = F + (1 − F) C_TT.
glm::dvec3 albedo(const Fabric& f, double thetaI);
// The TT lobe's azimuthal profile relative to its peak at φ = π:
// N_TT(φ)/N_TT(π) = exp(−κ(1 + cos φ)) for a von Mises centred at π.
double vonMisesRelative(double kappa, double phi);
// A longitudinal lobe relative to its peak on the specular cone θ_o = −θ_i:
// M(θ_i, θ_o)/M(θ_i, −θ_i) = exp(−(θ_i + θ_o)²/2β²) (Z depends on θ_i only).
double gaussianRelative(double beta, double thetaI, double thetaO);
// Eq. 5: k_s cos(φ/2) exp(−θ_h²/2β²), θ_h = (θ_i + θ_o)/2.
double simpleSpecular(double ks, double beta, double thetaI, double thetaO, double phi);

// Linear interpolation of a table with texel k at θ_k = −π/2 + (k + ½)π/n,
// clamped to the end texels outside [θ_0, θ_{n−1}].
glm::dvec3 lerpTable(std::span<const glm::vec3> table, double thetaO);

// n-point Gauss–Legendre on [−1, 1] (Newton on P_n): nodes and weights.
struct Rule {
  std::vector<double> x, w;
};
Rule gaussLegendre(int n);

// Quadrature nodes and weights for ∫_a^b: n-point Gauss–Legendre on panels
// no wider than maxPanel, split at every cut inside (a, b).
struct Nodes {
  std::vector<double> x, w;
};
Nodes panelNodes(double a, double b, std::vector<double> cuts, double maxPanel, int n);

// Z(θ_i) = ∫_{−π/2}^{π/2} g(θ + θ_i; β) cos²θ dθ, Gauss–Legendre on panels of β/2.
double lobeNorm(double beta, double thetaI);

// Eq. 6 in full, per channel, at fiber-local angles: the Gaussian lobes
// normalised by Z(θ_i) = ∫ g(θ + θ_i; β) cos²θ dθ over (−π/2, π/2) (by
// quadrature here), N_R = 1/2π, N_TT the von Mises centred at π with
// std::cyl_bessel_i.
glm::dvec3 bcsdf(const Fabric& f, double thetaI, double thetaO, double phi);
// The ambient integral A(θ_o) = ∫ [F M_R + (1 − F) C_TT M_TT] cos²θ_i dθ_i.
glm::dvec3 ambientIntegral(const Fabric& f, double thetaO);
// The radiance of eq. 7 (with eq. 8's cos θ_i; the BCSDF weighted 1 − k_d and
// the k_d/π diffuse term, an energy-conserving mix: docs/shading.md) at
// a fiber point with unit tangent t and normal n, seen along ω_o (towards the
// eye), under one directional light (unit ω_i, irradiance E) and a uniform
// ambient L_amb.
struct Lighting {
  glm::dvec3 toLight{0, 1, 0}, irradiance{1}, ambient{0}, diffuse{0};
};
glm::dvec3 fiberRadiance(const Fabric& f, const Lighting& l, glm::dvec3 t, glm::dvec3 n, glm::dvec3 wo);

}  // namespace ft::oracle
