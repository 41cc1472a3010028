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
#include "scene/srbf_solve.h"

namespace ft {

// In double over the pixels (rgb of `env`; alpha ignored), the shared float
// kernel ftSrbfKernel, directions ftEquirectDirection, weights ftEquirectSolidAngle.
SrbfNormalEquations srbfNormalEquationsCpu(const ImageRgbaF& env, const SrbfBasis& basis);

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
