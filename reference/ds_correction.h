// ds_correction.h (reference) — the bake of the dual-scattering correction ξ
// and the fiber-level shadowing Ψ_G^Fiber of Huang et al. 2025 (001) §4.3,
// eq. 9–11, §5.1 (notes-rendering A7; docs/ds-correction.md).
//
// One straight yarn of the all-fiber reference (every fiber of the preset
// explicit, no core, no flyaways), `periods` ply-twist periods long, seen
// from the side (θ_o = 0) by a near-orthographic camera over its middle
// period; for each light direction (θ_a, φ_b) of an N_θ × N_φ grid
// (common/ds_correction.h: ftXiThetaSample, ftXiPhiSample) the Embree path
// tracer (reference/fiber_trace.h: all bounces inside the yarn, directional
// light of irradiance 1, no ambient, no diffuse term) gives the reference
// L_* per texel, and at the same camera samples the dual-scattering
// prediction of 001 eq. 8 with the runtime's terms:
//   g   = (f(ω_d, ω_o) + d_b f_back^dir) cos θ_d                 (the local part, 1 + Ψ_L)
//   Ψ_G = V + (1 − V) T_f(n),  T_f = d_f ā_f(θ_d)^n           (n fibers crossed towards the light)
// Per texel, over the samples that hit a fiber: Ψ̄ = mean Ψ_G, ḡ = mean g and
//   ξ(a, b) = L_* / (Ψ̄ ḡ),
// so that the runtime's ξ Ψ̄ g reproduces L_* where g is the texel's mean.
// Eq. 10: ξ and Ψ̄ are each factored into a θ and a φ part by a rank-1 fit of
// their logarithms (exact for separable data). Each direction is one shard of
// the bake runner (bake/ds_correction_bake.cpp).
#pragma once
#include <filesystem>
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "common/ds_correction.h"
#include "common/fiber_shading.h"
#include "scene/ds_correction_file.h"
#include "scene/yarn_preset.h"

namespace ft {

// Planted fault (validation/faults.def "xi-bake-light-mirrored"): the bake
// lights the yarn from the mirror side of the one it files the result under
// (φ → −φ), as a sign slip in ω_d would.
inline bool ftFaultXiBakeLightMirrored = false;
#define FT_FAULT_XI_BAKE_LIGHT_MIRRORED_ON ::ft::ftFaultXiBakeLightMirrored
// The bake's ξ no longer grey: blue's ξ_M doubled (reference/ds_correction.cpp).
inline bool ftFaultXiBakeNotGrey = false;
#define FT_FAULT_XI_BAKE_NOT_GREY_ON ::ft::ftFaultXiBakeNotGrey

struct DsCorrectionSettings {
  std::string yarn = "cotton1";   // preset (data/yarn-presets.tsv); its flyaways are left out
  std::vector<std::string> presetOverrides;  // "name=value" (overrideYarnPreset), applied first
  std::string fabric = "cotton";  // BCSDF preset (data/fabric-bcsdf.tsv)
  int height = 32;                // N_v texels across the yarn (N_u follows from P / 2W)
  int thetaSamples = 8;           // N_θ
  int phiSamples = 8;             // N_φ: "eight directions in both dimensions" (§5.1) read as 8 × 8
  int pixelsPerTexel = 2;         // camera pixels per texel side
  int samplesPerPixel = 64;       // path-traced samples per camera pixel
  int maxDepth = 16;              // scattering events per path
  int periods = 5;                // ply-twist periods of yarn; the middle one is measured
  uint32_t seed = 1;
};

// ω_d of the bake's light (θ, φ) in world space: the yarn runs along
// t = +x, the eye looks from ω_o = +z, and
//   ω_d = sin θ t + cos θ (cos φ ω_o + sin φ t × ω_o),
// so that ftXiRelativeAngles(t, ω_d, ω_o) = (θ, φ) (tests/ds_correction_test.cpp).
glm::vec3 dsCorrectionLightDirection(float theta, float phi);

// Throws InputError naming the setting and value for sizes out of range
// (N_v 1–512, N_θ and N_φ 1–64, pixels per texel 1–16, spp 1–65536, depth
// 1–256, periods 3–21 odd) or unknown presets.
void checkDsCorrectionSettings(const DsCorrectionSettings& s);

// The sums of one direction, per texel (N_u · N_v, u fastest), in double:
// L_* (rgb), Ψ_G (rgb), g (rgb) over the samples that hit, and their count.
struct DsDirectionSums {
  std::vector<glm::dvec3> reference, shadowing, local;
  std::vector<double> hits;
};

// Everything each direction needs, built once (deterministic: the same on
// every rank of a distributed bake).
class DsCorrectionScene {
 public:
  explicit DsCorrectionScene(const DsCorrectionSettings& settings);
  ~DsCorrectionScene();
  DsCorrectionScene(DsCorrectionScene&&) noexcept;

  const DsCorrectionSettings& settings() const;
  DsCorrectionLayout layout() const;
  int directionCount() const;  // N_θ · N_φ; direction d = a · N_φ + b
  glm::vec3 lightDirection(int d) const;  // ω_d of direction d, world space
  size_t segmentCount() const;            // Embree fiber segments
  // Path-traces direction d (TBB inside; the result does not depend on the
  // thread count).
  DsDirectionSums trace(int d) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// Eq. 10 from the directions' sums (shard order d = a · N_φ + b), in double:
// per texel and channel ℓ(a, b) = log X(a, b), X_M(a) = exp(mean_b ℓ),
// X_N(b) = exp(mean_a ℓ − mean_ab ℓ). A texel no sample hit gets ξ = Ψ = 1
// and coverage 0. ξ = max(L_*, ε)/max(Ψ̄ ḡ, ε), ε = 1e-7 (of the light's
// irradiance 1): a texel in the dark on both sides is not corrected.
// samplesPerTexel: camera samples per texel (spp · pixelsPerTexel²), for the coverage.
DsCorrectionTextures factorDsCorrection(const DsCorrectionLayout& layout, std::span<const DsDirectionSums> directions,
                                        double samplesPerTexel);

// The rank-1 log fit alone, on X(a, b) given as values[(a · nPhi + b)] of one
// channel: (X_M(a) for a < nTheta, then X_N(b) for b < nPhi).
std::vector<double> factorLogRankOne(std::span<const double> values, int nTheta, int nPhi);

// ξ_M ξ_N Ψ_M Ψ_N at texture coordinate uv and angles (θ, φ) (ftXiLookup and
// the trilinear corners, as the GPU twin does).
// The rank-1 fit that minimises Σ_ab w(a, b) (T(a, b) − x_a y_b g(a, b))²
// (alternating least squares, `iterations` rounds from x = y = 1), T, g and w
// given as [a · nPhi + b]: (x_a for a < nTheta, then y_b), y scaled to a
// geometric mean of 1. Exact for T = x y g (any g, w > 0) once converged.
std::vector<double> factorWeightedRankOne(std::span<const double> target, std::span<const double> basis,
                                          std::span<const double> weight, int nTheta, int nPhi, int iterations);

glm::vec3 evaluateDsCorrectionCpu(const DsCorrectionTextures& t, glm::vec2 uv, glm::vec2 thetaPhi);


}  // namespace ft
