// quadrature.h — the Gauss–Kronrod 7/15 rule (QUADPACK qk15) the CPU
// reference's adaptive integrals use (reference/bcsdf_tables.cpp,
// reference/dual_scattering.cpp): Kronrod nodes on [0, 1] of the half rule
// (odd indices and the centre are the Gauss nodes), Kronrod weights, Gauss
// weights. The oracles in validation/ and tests/ keep their own rules on
// purpose: they must not share the reference's code.
#pragma once
#include <cfloat>

namespace ft {

inline constexpr double kGk15Nodes[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851, 0.864864423359769072789712788640926,
    0.741531185599394439863864773280788, 0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.0};
inline constexpr double kGk15KronrodWeights[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204, 0.104790010322250183839876322541518,
    0.140653259715525918745189590510238, 0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
inline constexpr double kGk15GaussWeights[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                                                0.381830050505118944950369775488975, 0.417959183673469387755102040816327};
// The short names both integrators use.
inline constexpr const double* kXk = kGk15Nodes;
inline constexpr const double* kWk = kGk15KronrodWeights;
inline constexpr const double* kWg = kGk15GaussWeights;

// Where both stop bisecting a piece of a lobe integral. The integrands are
// float functions of a float angle: rounding θ_i ≈ 1.5 to float moves a 1°
// lobe by up to 6e-8 rad, up to ~3e-6 of its value on the flanks, so a
// Gauss–Kronrod difference below 8 ε of ∫|f| is that rounding; and a piece
// narrower than 1/16 of the narrowest lobe is integrated exactly to double
// precision by K15 (exact for degree 22; the Gaussian's Taylor series over
// ±β/32 has converged long before), so bisecting it further would only
// integrate the rounding.
inline constexpr double kIntegrandRounding = 8.0 * FLT_EPSILON;
inline constexpr double kMinPieceLobes = 1.0 / 16.0;

}  // namespace ft
