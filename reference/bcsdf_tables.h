// bcsdf_tables.h — the CPU side of the fiber BCSDF (common/bcsdf.h, Wu &
// Yuksel 2019 (000) §4.3): the header's functions evaluated in C++ float on
// lists of angles or directions, and the ambient table A(θ_o) of eq. 7–10
// integrated by adaptive Gauss–Kronrod quadrature accumulated in double.
#pragma once
#include <glm/glm.hpp>
#include <functional>
#include <span>
#include <vector>

#include "common/fiber_shading.h"

namespace ft {

// Which lobes of eq. 6 to evaluate or integrate.
enum class BcsdfLobes { Both, R, TT };

// f of eq. 6 (or one of its lobes) at each angle triple, per RGB channel.
std::vector<glm::vec3> evaluateBcsdfCpu(const FabricParams& fabric, std::span<const FiberAngles> angles,
                                        BcsdfLobes lobes = BcsdfLobes::Both);
// f_spec of eq. 5 at each angle triple.
std::vector<float> evaluateSimpleSpecularCpu(float ks, float beta, std::span<const FiberAngles> angles);
// ftFiberAngles of each (t, ω_i, ω_o); the three spans have one size.
std::vector<FiberAngles> fiberAnglesCpu(std::span<const glm::vec3> tangents, std::span<const glm::vec3> wi,
                                        std::span<const glm::vec3> wo);

// The ambient integral of eq. 8 with the azimuthal integrals of eq. 9–10 equal
// to 1 (notes-rendering A4):
//   A(θ_o) = ∫_{−π/2}^{π/2} [F M_R + (1 − F) C_TT M_TT](θ_i, θ_o) cos²θ_i dθ_i,
// its R and TT parts kept apart. Texel k holds θ_k = ftAmbientTexelAngle(k, n).
struct AmbientTableCpu {
  std::vector<glm::dvec3> r, tt;
  // The largest Gauss–Kronrod error estimate of any texel and channel, relative
  // to that texel's value (≤ ~1e-9, or the float rounding of the integrand).
  double errorEstimate = 0.0;
  size_t evaluations = 0;  // integrand evaluations, all texels
  std::vector<glm::dvec3> total() const;
};

// The adaptive quadrature of the ambient table, for other integrals over θ_i
// of an R and a TT part (reference/srbf_table.cpp): global adaptive G7–K15
// (QUADPACK QAG's strategy) in double over [cuts.front(), cuts.back()], split
// at every cut, until the summed error estimates are below 1e-9 of each
// channel's integral, or a piece is narrower than minWidth or resolved to the
// float rounding of the integrand (8 ε_float of its ∫|f|).
struct LobeValues {
  glm::dvec3 r, tt;
};
struct LobeIntegral {
  LobeValues value, error;
  size_t evaluations = 0;
};
LobeIntegral integrateLobesAdaptive(const std::function<LobeValues(double)>& f, std::vector<double> cuts,
                                    double minWidth);

// The integrand (float, the header's ftFiberFresnel and ftLongitudinal) is
// integrated over θ_i by adaptive G7–K15 in double, with breakpoints at
// −θ_o, −θ_o ± 6β_R and −θ_o ± 6β_TT (the lobe windows, bcsdf.h) and at
// ±(π/2 − 6β), where Z switches from its closed form to quadrature.
AmbientTableCpu bakeAmbientTableCpuParts(const FabricParams& fabric, int texels = FT_AMBIENT_TABLE_SIZE);
// A(θ_k) as the renderer stores it (float rgb).
std::vector<glm::vec3> bakeAmbientTableCpu(const FabricParams& fabric, int texels = FT_AMBIENT_TABLE_SIZE);

// (Z_R, Z_TT) at ftLobeNormTexelAngle(k, texels, β_p): the lobe-normalisation
// table of common/bcsdf.h, from the header's exact Z (float, as the GPU).
std::vector<glm::vec2> bakeLobeNormTableCpu(const FabricParams& fabric, int texels = FT_LOBE_NORM_TABLE_SIZE);
// (Z_R, Z_TT) at θ_i looked up in such a table as the frame does.
glm::vec2 lookupLobeNormCpu(const FabricParams& fabric, std::span<const glm::vec2> table, float thetaI);

}  // namespace ft
