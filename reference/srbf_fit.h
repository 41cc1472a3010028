// srbf_fit.h — the SRBF (spherical Gaussian) fit of an equirectangular
// environment map, Huang et al. 2025 (001) §4.5 eq. 14 and §6 ("16 SRBFs"),
// with the fill-ins of notes-rendering A9 [F] (docs/srbf.md):
//   * axes μ_j: the 16 spherical Fibonacci points (common/srbf.h), fixed;
//   * λ_j = λ0 = ln 2/(1 − cos δ), δ = √(4π/16): 1.885 for all lobes;
//   * a constant (DC) basis function W_0 (≡ 1) besides the 16 lobes, so a
//     constant environment is represented exactly (switchable: constantTerm);
//   * weights: non-negative least squares of Σ_p dΩ_p ‖L_p − Σ_j W_j G_j(ω_p)‖²
//     per channel, from the normal equations K W = b (discrete Gram K_ab =
//     Σ_p dΩ_p G_a G_b, b_j = Σ_p dΩ_p L_p G_j) by Lawson–Hanson on Eigen's LDLT;
//   * no refinement of (μ, λ) (no Levenberg–Marquardt): a lone lobe off the
//     Fibonacci axes is fitted, not recovered.
// The sums are accumulated in double over the shared float kernel and pixel
// directions; gpu/srbf_fit_gpu.h computes the same sums by compute-shader
// reductions, and fitSrbfFromSums solves either.
#pragma once
#include <glm/glm.hpp>
#include <vector>

#include "common/srbf.h"
#include "image/image.h"

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
// In double over the pixels (rgb of `env`; alpha ignored), the shared float
// kernel ftSrbfKernel, directions ftEquirectDirection, weights ftEquirectSolidAngle.
SrbfNormalEquations srbfNormalEquationsCpu(const ImageRgbaF& env, const SrbfBasis& basis);

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
SrbfFit fitSrbfCpu(const ImageRgbaF& env, const SrbfFitOptions& options = {});

// Solid-angle-weighted relative L2 error of the fitted radiance over the map,
// all channels: √(Σ_p dΩ_p ‖L_p − L̂_p‖² / Σ_p dΩ_p ‖L_p‖²).
double srbfRelativeL2(const ImageRgbaF& env, const SrbfEnvironment& fit);

// The procedural environment shipped as data/env/sky.exr (`fibertwin env-sky`):
// an HDR sky gradient, a sun (a sharp SG, λ = 800, ∫ ≈ 2π per channel) and a
// darker ground, W × H float rgb, alpha 1.
// withSun = false: the same map without the sun (docs/srbf.md's second fit error).
ImageRgbaF makeProceduralSky(int width = 256, int height = 128, bool withSun = true);

}  // namespace ft
