// srbf_oracle.h — expected values for the SRBF cases (srbf_cases.cpp) and
// tests/srbf_test.cpp, written from 001 §4.5, reference-data §7 and
// docs/srbf.md's conventions in double. Independent of common/: neither this
// header nor srbf_oracle.cpp includes common/srbf.h, common/srbf_bcsdf.h or
// common/bcsdf.h (the BCSDF comes from bcsdf_oracle.h, which is independent too).
#pragma once
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "validation/bcsdf_oracle.h"

namespace ft::oracle {

// The documented equirect convention: pixel (x, y) of W × H, row 0 at the top,
// θ = π(y + ½)/H from +y, φ = 2π(x + ½)/W − π, ω = (sin θ cos φ, cos θ, sin θ sin φ).
glm::dvec3 equirectDirection(int x, int y, int width, int height);
// The pixel's exact solid angle (2π/W)(cos θ_top − cos θ_bottom).
double equirectSolidAngle(int y, int width, int height);
// Spherical Fibonacci point j of n about +y (reference-data §7).
glm::dvec3 fibonacciPoint(int j, int n);
// e^{λ(μ·ω − 1)}.
double sphericalGaussian(glm::dvec3 mu, double lambda, glm::dvec3 w);
// ∫ G dω = 2π(1 − e^{−2λ})/λ (4π at λ = 0).
double sgIntegral(double lambda);
// ∫ G_a G_b dω = e^{d − λa − λb} 2π(1 − e^{−2d})/d, d = |λa μa + λb μb| (reference-data §7).
double sgProductIntegral(glm::dvec3 muA, double lambdaA, glm::dvec3 muB, double lambdaB);

// The I_M table's axes as docs/srbf.md states them.
double srbfTableTheta(int k, int n);     // asin(−1 + 2k/(n − 1))
double srbfTableDeltaPhi(int k, int n);  // πk/(n − 1)
double srbfTableLambda(int k, int n);    // 0.5 · 1024^{k/(n − 1)}
// Continuous texel coordinate along each axis of (θ_o, θ_j, Δφ, λ), clamped.
glm::dvec4 srbfTableCoords(glm::ivec4 dims, double thetaO, double thetaJ, double deltaPhi, double lambda);
// Quadrilinear interpolation of `table` (index ((o·N_j + j)·N_Δφ + p)·N_λ + l) at those coordinates.
glm::dvec3 srbfTableInterpolate(std::span<const glm::vec3> table, glm::ivec4 dims, glm::dvec4 coords);

// I(θ_o, θ_j, Δφ, λ) = ∫ G(ω_i; ω_j, λ) f(ω_i, ω_o) cos θ_i dω_i by brute-force
// 2D quadrature over (θ_i, φ_i), the SG from 3D dot products, f = bcsdf() of
// bcsdf_oracle.h. Double; piecewise Gauss–Legendre resolving every lobe.
glm::dvec3 srbfConvolution(const Fabric& f, double thetaO, double thetaJ, double deltaPhi, double lambda);

}  // namespace ft::oracle
