// ambient_occlusion_oracle.h — expected values for the ambient-occlusion
// cases (ambient_occlusion_cases.cpp), written in double from notes-rendering
// A3 and 000 §4.2 alone. Deliberately independent of common/: neither this
// header nor ambient_occlusion_oracle.cpp includes anything from common/, so a
// wrong formula there cannot reach the expectation.
#pragma once

namespace ft::oracle {

// A3 C3: a uniform disk of radius a and number density ρ0 centred at the
// origin, visibility exp(−κτ). AO at (x, y), |(x, y)| < a:
//   AO = (1/2π) ∫_0^{2π} exp(−κ ρ0 (−p·d + √((p·d)² − |p|² + a²))) dφ,
// by the trapezoid rule on `nodes` equally spaced φ (the integrand is smooth
// and periodic inside the disk, so the rule converges geometrically).
double uniformDiskAo(double kappa, double rho0, double a, double x, double y, int nodes = 8192);
// At the centre every ray crosses the radius a: exp(−κ ρ0 a), exactly.
double uniformDiskAoCentre(double kappa, double rho0, double a);

// The distance-based AO of 000 §4.2: clamp(a0 + a1 r + a2 r² + a3 r³, 0, 1).
double aoCubic(const double a[4], double r);

// Centre of ply j of n at ply phase θ, distance R from the yarn centre:
// R (cos(2πj/n + θ), sin(2πj/n + θ)) (000 §3.1; notes §0.1).
void plyCentre(double radius, int j, int n, double theta, double& x, double& y);

// The paper-faithful march on a field it must integrate exactly: ρ(x, y) =
// c0 + c1 cx(x) + c2 cy(y) on the square [−W, W]², cx/cy clamping to the
// outermost of m grid-cell centres (what bilinear interpolation of that field,
// clamped at the edges, reproduces exactly), marched from (x, y) along φ to
// the square's edge. τ integrated piecewise (exact: linear pieces), AO =
// (1/N) Σ_k exp(−κ τ_k) over φ_k = 2π(k + ½)/N.
double linearFieldAo(const double c[3], double halfWidth, int m, double kappa, int directions, double x, double y);

}  // namespace ft::oracle
