// dual_scattering_oracle.h — expected values for the dual-scattering cases
// (dual_scattering_cases.cpp, tests/dual_scattering_test.cpp), written in
// double from Zinke et al. 2008 (equation numbers as notes-rendering A6 cites
// them) and the closed forms of the lobe integrals of the Khungurn BCSDF.
// Deliberately independent of common/: neither this file nor its .cpp
// includes common/ (or anything that does); the BCSDF itself comes from
// bcsdf_oracle.h, which is independent too.
#pragma once
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "validation/bcsdf_oracle.h"

namespace ft::oracle {

// Zinke's density factors d_f = d_b.
constexpr double kDsDensity = 0.7;

// q(κ) = ∫_{−π/2}^{π/2} e^{−κ cos φ} dφ / (2π I0(κ)): the share of the TT von
// Mises (centred at π) that falls in the backward half |φ| < π/2. By
// 64-point Gauss–Legendre and std::cyl_bessel_i.
double vonMisesBackFraction(double kappa);

// The lobe integrals a_{H,p}(θ) in closed form: the longitudinal lobes carry
// unit energy over θ_o (Z normalises over θ_o), N_R = 1/2π puts half of R in
// each half, N_TT puts q(κ) in the backward half:
//   a_{f,R} = a_{b,R} = F/2,  a_{b,TT} = (1 − F) C_TT q,  a_{f,TT} = (1 − F) C_TT (1 − q).
struct DsLobes {
  glm::dvec3 aFR, aFTT, aBR, aBTT;
};
DsLobes dsLobes(const Fabric& f, double theta);

// A texel's values from its lobes: ā, ᾱ (0: no shifts), β̄² with β^Z = β/2,
// A_b (eq. 14), Δ_b (eq. 16), σ̄_b² (eq. 17 as published, squared).
struct DsRows {
  glm::dvec3 aF, aB, alphaF, alphaB, betaF2, betaB2, ab, deltaB, sigmaB2;
};
DsRows dsRows(const Fabric& f, const DsLobes& lobes);
// Each row linearly interpolated at θ in a table of texels at −π/2 + (k + ½)π/n
// (clamped ends), as a frame reads it.
DsRows lerpRows(std::span<const DsRows> table, double theta);

// The per-frame function of notes A6, written out:
//   T_f = d_f ā_f^n, σ̄_f² = n β̄_f², f_back = 2 A_b g(θ_h − Δ_b; var)/(π max(cos²θ_d, 1e-4)),
//   f_s^sc = Σ_p A_p [g(θ_h; √(β_p²/4 + σ̄_f²)) / (2 Z(θ_i; 2√(…)))] / (2π),
//   F = V (f + d_b f_back^dir) + (1 − V) T_f (f_s^sc + π d_b f_back^sc).
struct DsFrameValue {
  glm::dvec3 value, backDirect, backScattered, forwardScattered, transmittance, forwardVariance;
};
DsFrameValue dsFrame(const Fabric& f, const DsRows& atThetaD, double thetaI, double thetaO, double phi,
                     double visibility, double fibers);

// a_{H,p}(θ) by brute force: f of eq. 6 (bcsdf_oracle.h) integrated over θ_o
// (Gauss–Legendre panels of β_R/2 around the lobes) and φ (32 nodes per
// quarter); forward: cos φ < 0. Checks the closed forms themselves.
DsLobes dsLobesByQuadrature(const Fabric& f, double theta);

}  // namespace ft::oracle
