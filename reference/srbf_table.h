// srbf_table.h — the CPU reference of the I_M table (001 §4.5 eq. 15–16;
// common/srbf_bcsdf.h): the BCSDF of common/bcsdf.h convolved with one SRBF,
//   I(θ_o, θ_j, Δφ, λ) = ∫ G(ω_i; ω_j, λ) f(ω_i, ω_o) cos θ_i dω_i,
// by the analytic reduction of notes-rendering A10 (the φ_i integral of the
// SG times each azimuthal lobe is a Bessel function): with c = cos θ_i cos θ_j,
// s = sin θ_i sin θ_j, I0e(x) = e^{−x} I0(x),
//   I_R  = ∫ F M_R · I0e(λc) e^{λ(c + s − 1)} · cos θ_i · cos θ_i dθ_i,
//   I_TT = ∫ (1 − F) C_TT M_TT · [I0e(λ_m)/I0e(κ)] e^{λ_m − κ + λ(s − 1)} · cos θ_i · cos θ_i dθ_i,
//   λ_m = √(κ² + (λc)² − 2κλc cos Δφ),
// the first cos θ_i that of eq. 15 (ftSrbfCosine), the second the measure's.
// The 1D integrals over θ_i use the ambient table's adaptive Gauss–Kronrod in
// double (integrateLobesAdaptive), with the header's float F and M as there,
// so that λ → 0 gives bakeAmbientTableCpu's A(θ_o) exactly (up to O(λ)).
#pragma once
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "common/srbf_bcsdf.h"
#include "reference/bcsdf_tables.h"

namespace ft {

// e^{−x} I0(x) in double, x ≥ 0: the power series below 20, the asymptotic
// series above (relative error ~1e-15 against std::cyl_bessel_i, tests/srbf_test.cpp).
double besselI0eDouble(double x);

// I at one point, R and TT parts; errorEstimate (if given) the Gauss–Kronrod
// estimate relative to the total (max over channels).
LobeValues srbfConvolutionCpu(const FabricParams& fabric, double thetaO, double thetaJ, double deltaPhi,
                              double lambda, double* errorEstimate = nullptr);

// The CI size of notes A10: 8 × 8 × 4 × 4.
inline constexpr glm::ivec4 kSrbfTableCiDims{8, 8, 4, 4};

struct SrbfTableCpu {
  glm::ivec4 dims{0};
  std::vector<glm::dvec3> values;  // at ftSrbfTableIndex
  std::vector<double> errors;      // per texel: its Gauss–Kronrod error estimate relative to its value
  double errorEstimate = 0.0;      // the largest of them (large only where I underflows float: < 1e-38)
  std::vector<glm::vec3> asFloat() const;
};
// Every texel at (ftSrbfTableTheta, ftSrbfTableTheta, ftSrbfTableDeltaPhi,
// ftSrbfTableLambda); TBB over texels.
SrbfTableCpu bakeSrbfTableCpu(const FabricParams& fabric, glm::ivec4 dims = kSrbfTableCiDims);

// The renderer's lookup on the CPU: ftSrbfTableLookup, its 16 taps summed.
glm::vec3 lookupSrbfTableCpu(std::span<const glm::vec3> table, glm::ivec4 dims, float thetaO, float thetaJ,
                             float deltaPhi, float lambda);

}  // namespace ft
