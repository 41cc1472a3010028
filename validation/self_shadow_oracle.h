// self_shadow_oracle.h — expected values for the self-shadow cases
// (self_shadow_cases.cpp), written in double from the definitions of
// reference-data §2 and notes-rendering §0.3 / A2 alone. Deliberately
// independent of common/: neither this header nor self_shadow_oracle.cpp
// includes common/yarn_density.h or common/self_shadow.h (or anything that
// does), so a wrong convention there cannot reach the expectation.
#pragma once

namespace ft::oracle {

// A yarn's ply cross-sections (a preset's numbers, copied by the caller):
// ply j's centre at plyRadius·(cos ϑ_j, sin ϑ_j), ϑ_j = plyAngle + 2πj/plies,
// its semi-axes ellipseN·rMax along the centre direction and ellipseB·rMax
// across it, fibers drawn with Zhao et al. 2016's acceptance p(R).
struct PlyShape {
  int plies = 1;
  double fibers = 1.0;  // per ply
  double plyRadius = 0.0, ellipseN = 1.0, ellipseB = 1.0;
  double epsilon = 0.0, beta = 0.0, rMax = 1.0;
};

// p(R) = (1 − 2ε)((e − e^{R/R_max})/(e − 1))^β + ε on [0, R_max], else 0.
double placement(const PlyShape& s, double r);
// Z = ∫_0^{R_max} p(r) 2πr dr (graded Gauss–Legendre toward R_max).
double placementMass(const PlyShape& s);
// Fibers per unit area at (x, y) of the cross-section (yarn frame), ply 0 at plyAngle.
double density(const PlyShape& s, double plyAngle, double x, double y);
// ∫_0^∞ ρ(x + t d) dt for the unit direction d = (dx, dy): per ply, the chord
// of the R_max ellipse solved in double, cut at the closest approach to the
// ply centre, each piece by Gauss–Legendre panels graded geometrically toward
// both ends (p has an unbounded slope at R_max when β < 1).
double lineIntegral(const PlyShape& s, double plyAngle, double x, double y, double dx, double dy);

// The closed form of notes A2 C3: one ply of uniform density ρ0 = fibers/(π a b)
// centred at the origin, semi-axis a along (cos ψ, sin ψ) and b across, light
// travelling +u: the density accumulated up to (u, v) is ρ0 times the length of
// the chord at height v left of u.
double uniformEllipseAccumulated(double fibers, double a, double b, double psi, double u, double v);

// The texture of notes A2 looked up as its text describes it, on values of
// lineIntegral: texel centres u_i = −W + (i + ½)Δ (likewise v_j), Δ = 2W/N,
// slice k at ψ_k = k (2π/plies)/N_s, light travelling +u; a fragment at x with
// ℓ⊥ = (lx, ly) reads at u = x·d, v = x·rot90(d), d = −ℓ⊥/|ℓ⊥|,
// ψ = (θ_ply,0 − atan2(d)) mod 2π/plies, trilinear (clamped in u, v, periodic
// in ψ) between the 8 surrounding texels, each the exact integral in double.
struct TextureLayout {
  int width = 0, height = 0, slices = 0;
  double halfWidth = 0.0;
};
double textureLookup(const PlyShape& s, const TextureLayout& t, double x, double y, double lx, double ly,
                     double plyAngle);

}  // namespace ft::oracle
