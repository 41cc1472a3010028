// dual_scattering.h — the CPU side of dual scattering (common/dual_scattering.h;
// Zinke et al. 2008 as 001 §4.1 eq. 8 uses it): the tables of a_{f,p}, a_{b,p}
// and the quantities derived from them, integrated in double, and the
// per-frame function evaluated in C++ float on lists of inputs.
#pragma once
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "common/dual_scattering.h"

namespace ft {

struct DsTableCpu {
  int texels = 0;
  // The four lobe integrals per texel, a_{H,p}(θ_k), in double.
  std::vector<glm::dvec3> aFR, aFTT, aBR, aBTT;
  // The table as the GPU stores it: FT_DS_ROWS vec4 per texel (texel-major),
  // derived from the lobes by ftDsTexelFromLobes (float).
  std::vector<glm::vec4> rows;
  // The largest Gauss–Kronrod error estimate of any lobe integral, relative to
  // the texel's ā_f + ā_b (channel by channel).
  double errorEstimate = 0.0;
  size_t evaluations = 0;
};

// Integrates a_{H,p}(θ_k) = 2 ∫_{φ-range of H} ∫ f_p cos²θ_o dθ_o dφ
// (ftDsIntegrandR/TT, float) for every texel: θ_o by adaptive G7–K15 in double
// with breakpoints at −θ and −θ ± 6β_p (the lobe windows), to 1e-9 relative or
// the integrand's float rounding; φ by 32-point Gauss–Legendre on each quarter
// (the von Mises of κ ≤ 8.4 is entire: the rule is exact to double rounding).
DsTableCpu bakeDualScatteringCpu(const FabricParams& fabric, int texels = FT_DS_TABLE_SIZE);

// Texel k of a table of rows, and the table read at θ as the frame reads it
// (ftDsLookup, both texels, ftDsMix).
DsTexel dsTexelOf(std::span<const glm::vec4> rows, int k);
DsTexel lookupDsCpu(std::span<const glm::vec4> rows, float theta);
// FT_DS_ROWS vec4 of one texel, in the table's order.
void dsTexelRows(const DsTexel& t, glm::vec4* out);

// One per-frame evaluation: angles, the visibility V and the fiber count n.
struct DsRequest {
  FiberAngles angles;
  float visibility = 1.0f;
  float fibers = 0.0f;
};
// ftDsEvaluate at each request with the table read at θ_d (ftDsThetaD).
std::vector<DsFrame> evaluateDsCpu(const FabricParams& fabric, std::span<const glm::vec4> rows,
                                   std::span<const DsRequest> requests);

}  // namespace ft
