// srbf_solve.h — the host-side half of the SRBF environment fit (001 §4.5
// eq. 14; docs/srbf.md), shared by the CPU fit (reference/srbf_fit.h: its
// sums in double) and the GPU bake of the shaded frame (gpu/srbf_fit_gpu.h:
// its sums by compute shader): the basis, the normal equations and their
// non-negative solve. In scene/ (moved from reference/srbf_fit.h unchanged)
// because gpu/ may not include reference/ and both bakes of the frame's
// inputs (scene/shading_inputs.h) solve the 17 × 17 system on the CPU.
#pragma once
#include <glm/glm.hpp>
#include <vector>

#include "common/srbf.h"

namespace ft {

struct SrbfFitOptions {
  bool constantTerm = true;  // the DC basis function (docs/srbf.md: C2 option (a))
  float lambda = 0.0f;       // every lobe's λ; 0: λ0 = ftSrbfInitialLambda(16)
};

// The basis of a fit: the 16 lobes' (μ, λ) and whether the DC term is in.
struct SrbfBasis {
  glm::vec4 axisLambda[FT_SRBF_LOBES];
  bool constantTerm = true;
  int count() const { return FT_SRBF_LOBES + (constantTerm ? 1 : 0); }  // lobes first, then the DC term
};
SrbfBasis srbfFibonacciBasis(const SrbfFitOptions& options = {});

// Normal equations of the fit: K (count × count, row-major) and b (rgb per
// basis function), basis functions ordered lobes first, then the DC term.
struct SrbfNormalEquations {
  int count = 0;
  std::vector<double> gram;
  std::vector<glm::dvec3> rhs;
};
// Lawson–Hanson NNLS on normal equations: min ½xᵀKx − bᵀx subject to x ≥ 0
// (K symmetric positive semi-definite, n × n row-major). Iterations out.
std::vector<double> solveNnlsNormal(const std::vector<double>& gram, const std::vector<double>& rhs, int n,
                                    int* iterations = nullptr);

struct SrbfFit {
  SrbfBasis basis;
  SrbfEnvironment environment{};  // the UBO block: μ, λ, W per lobe; W_0 in `constant`
  SrbfNormalEquations equations;
  int nnlsIterations = 0;         // summed over the three channels
  int activeLobes = 0;            // lobes with a non-zero weight in some channel
};
SrbfFit fitSrbfFromSums(const SrbfBasis& basis, const SrbfNormalEquations& equations);

}  // namespace ft
