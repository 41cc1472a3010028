// ambient_occlusion_setup.h — host-side setup of the yarn ambient occlusion
// (Wu & Yuksel 2019 (000) §4.2, common/ambient_occlusion.h): the bake
// parameters and the distance-based cubic fit. In scene/ because both bake
// functions of the shaded frame use them: the CPU one on the CPU texture
// (reference/shading_inputs.cpp), the GPU one on the GPU texture
// (gpu/shading_inputs_gpu.cpp), and gpu/ does not link reference/.
#pragma once
#include <glm/glm.hpp>
#include <span>

#include "common/ambient_occlusion.h"

namespace ft {

// Sizes and constants of a bake; 0 = default. Defaults (notes A3 [F]; the
// paper gives none): AO 128², 64 stratified directions, density grid 256²,
// march step ½ density texel; CI: 64², 32 directions, grid 128².
struct AoSettings {
  int resolution = 128;
  int directions = 64;
  int densityResolution = 256;
  float marchStep = 0.5f;
  float kappa = 0.0f;  // 0: defaultAoKappa
  uint32_t seed = 0x000A0C1Du;
  uint32_t directionMode = FT_AO_DIRECTIONS_STRATIFIED;
  static AoSettings ci() { return AoSettings{64, 32, 128}; }
};

// κ = 2 r_f with r_f = ¼ √(π e_N e_B / n_f) (notes §0.3 [F]: about 5 fibers
// crossed per ply diameter; cotton1: r_f = 1.16e-3, κ = 2.32e-3).
float defaultAoKappa(const YarnDensityParams& density);

// The bake parameters of a density field; W = the field's support radius plus
// one AO texel (W − W_s = 2W/n). Throws std::invalid_argument naming the
// setting for sizes < 2 (texture, grid) or < 1 (directions), a step ≤ 0,
// κ < 0 or not finite, or a field without support.
AmbientOcclusionParams makeAoParams(const YarnDensityParams& density, const AoSettings& settings = {});

// The converged variant of `p`: `directions` equally spaced directions.
AmbientOcclusionParams convergedAoParams(AmbientOcclusionParams p, int directions = 4096);

// 000 §4.2: "the radial average of the precomputed ambient occlusion texture"
// fitted by a cubic. Bins of one texel in r = |p| over r̂ = r/W < 1; each bin
// holds the mean of AO and the means of r̂^0..3 of its texels, so a texture
// that is exactly a cubic in r̂ is recovered exactly; least squares weighted
// by the bin counts (area weighting), with Eigen's column-pivoting QR.
struct AoCubicFit {
  glm::dvec4 coefficients{0.0};  // a0..a3
  double rmsResidual = 0.0;      // per texel with r̂ < 1: texture − clamp(cubic)
  double maxResidual = 0.0;
  int bins = 0, texels = 0;
};
AoCubicFit fitAoCubic(std::span<const double> texture, int n);
AoCubicFit fitAoCubic(std::span<const float> texture, int n);

}  // namespace ft
