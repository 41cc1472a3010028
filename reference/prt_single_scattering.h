// prt_single_scattering.h — the CPU reference of single scattering of the
// fabric PRT, Khungurn et al. 2017 (004) §5.2, eq. 1–2, App. A
// (common/prt_single_scattering.h; docs/prt-single-scattering.md):
//   * the C++ instances of the shared body: ft::prtss64 (double, the
//     reference: std::erf, besselI0eDouble, std::atan2) and ft::prtss32
//     (float, the GPU's arithmetic and polynomials on the CPU);
//   * bakePrtSsTableCpu: the 𝒢(μ; β⁻²/2) tables in double by composite
//     Gauss–Legendre (independent of bcsdf.h's Z, which the GPU bake uses);
//   * evaluatePrtSsCpu: a list of PrtSsRequest in double;
//   * prtSsMonteCarlo: the truth of eq. 1 — Monte Carlo with the caller's
//     exact local visibility and BCSDF (so that a check can use an oracle
//     free of common/), SG importance sampling and BCSDF sampling combined
//     by the balance heuristic.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "common/prt_single_scattering.h"
#include "reference/srbf_table.h"  // besselI0eDouble

namespace ft::prtss64 {
typedef double kreal;
typedef glm::dvec2 kvec2;
typedef glm::dvec3 kvec3;
typedef glm::dvec4 kvec4;
#define KR(x) kreal(x)
#define FT_PRT_SS_INSTANTIATE
#define FT_PRT_SS_ERF(x) std::erf(x)
#define FT_PRT_SS_I0E(x) ::ft::besselI0eDouble(x)
#define FT_PRT_SS_ATAN2(y, x) std::atan2(y, x)
#define FT_PRT_SS_TABLE_DECL const kreal *prtSsTable,
#define FT_PRT_SS_TABLE_PASS prtSsTable,
#include "common/prt_single_scattering.h"  // NOLINT(bugprone-suspicious-include): precision-generic body
#undef FT_PRT_SS_ERF
#undef FT_PRT_SS_I0E
#undef FT_PRT_SS_ATAN2
#undef KR
}  // namespace ft::prtss64

namespace ft::prtss32 {
typedef float kreal;
typedef glm::vec2 kvec2;
typedef glm::vec3 kvec3;
typedef glm::vec4 kvec4;
#define KR(x) kreal(x)
#define FT_PRT_SS_ERF(x) ::ft::ftErf(x)
#define FT_PRT_SS_I0E(x) ::ft::ftBesselI0e(x)
#define FT_PRT_SS_ATAN2(y, x) ::ft::ftAtan2(y, x)
#include "common/prt_single_scattering.h"  // NOLINT(bugprone-suspicious-include)
#undef FT_PRT_SS_ERF
#undef FT_PRT_SS_I0E
#undef FT_PRT_SS_ATAN2
#undef KR
#undef FT_PRT_SS_TABLE_DECL
#undef FT_PRT_SS_TABLE_PASS
#undef FT_PRT_SS_INSTANTIATE
}  // namespace ft::prtss32

namespace ft {

// Rows 2f (R) and 2f + 1 (TT) of N texels per fabric: 𝒢(−θ_k; β⁻²/2) = Z(θ_k)
// at ftPrtSsTexelAngle, by Gauss–Legendre (8 points) on panels of β/4 over
// the lobe's ±10β window clipped to (−π/2, π/2). TBB over texels.
// InputError for no fabrics, more than FT_PRT_SS_MAX_FABRICS or β ≤ 0.
std::vector<double> bakePrtSsTableCpu(std::span<const FabricParams> fabrics, int texels = FT_PRT_SS_TABLE_SIZE);

// The shared segment data of a request list: per weights row, Q weights.
struct PrtSsSegments {
  int axes = FT_SVF_DEFAULT_AXES;
  float lambdaSvf = FT_SVF_LAMBDA;
  std::vector<float> weights;  // rows × Q
};

// Radiance (rgb) of every request in double (ft::prtss64): ftPrtSsDirectional
// for λ ≤ 0, else ftPrtSsSgLight. InputError naming the request and field for
// a fabric index or weights row out of range, a non-unit or non-finite
// direction, a non-finite λ, SSDF or V_glo. TBB over requests.
std::vector<glm::dvec3> evaluatePrtSsCpu(std::span<const FabricParams> fabrics, std::span<const double> table,
                                         std::span<const PrtSsRequest> requests, const PrtSsSegments& segments);

// ---- Monte Carlo truth of eq. 1 --------------------------------------------
// BCSDF at fiber-local angles (θ_i, θ_o, φ relative azimuth), rgb.
using PrtSsBcsdf = std::function<glm::dvec3(double thetaI, double thetaO, double phi)>;
// Local visibility of a unit direction (fabric frame): 0 or 1.
using PrtSsVisibility = std::function<double(glm::dvec3)>;
struct PrtSsMcSettings {
  int samples = 16384;
  uint32_t seed = 1;
  double betaR = 0.0, betaTT = 0.0;  // the BCSDF's lobe widths (radians), for its sampling
};
struct PrtSsMcResult {
  glm::dvec3 mean{0.0};
  glm::dvec3 stdError{0.0};  // of the mean
};
// ∫ V G(ω; ξ, λ)/M(λ) S(ω, ω_o) cos θ_i dω over S², t the unit tangent.
PrtSsMcResult prtSsMonteCarlo(const PrtSsBcsdf& bcsdf, const PrtSsVisibility& visibility, glm::dvec3 t,
                              glm::dvec3 wo, glm::dvec3 xi, double lambda, const PrtSsMcSettings& s);

}  // namespace ft
