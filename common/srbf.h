// srbf.h — spherical-radial-basis-function (spherical Gaussian) environment
// lighting of Huang et al. 2025 (001) §4.5, shared by the CPU fit
// (reference/srbf_fit.h), its GPU reductions (gpu/srbf_fit_gpu.h) and the
// renderer:
//   * eq. 14: L(ω) ≈ Σ_j W_j G(ω; μ_j, λ_j), G = e^{λ_j(μ_j·ω − 1)}, 16 lobes
//     (001 §6), plus a constant (DC) term W_0 (docs/srbf.md: [F] a constant
//     environment is then represented exactly; its BCSDF convolution is the
//     ambient table A(θ_o) of 000 eq. 8, the λ → 0 limit of the I_M table);
//   * the equirectangular convention of the environment map (below);
//   * ∫ G dω = 2π(1 − e^{−2λ})/λ and the spherical Fibonacci centres
//     (reference-data §7).
// Equirect convention (y up): pixel (x, y) of a W × H map, row 0 at the TOP,
// u = (x + ½)/W, v = (y + ½)/H; polar angle from +y θ = πv (row 0 looks up),
// azimuth φ = 2πu − π ∈ [−π, π) with φ = atan2(z, x):
//   ω = (sin θ cos φ, cos θ, sin θ sin φ).
// So the left edge of the map looks along −x, the centre column along +x, the
// column at u = ¾ along +z. A pixel's solid angle is its exact band area
// (2π/W)(cos θ_top − cos θ_bottom) (the rows sum to 4π exactly).
#ifndef FT_SRBF_H
#define FT_SRBF_H
#include "prelude.h"

// Planted faults (validation/faults.def). Shared ones: C++ run-time switch and
// GLSL define, on both sides; FT_FAULT_SRBF_NO_MINUS_ONE is GLSL only.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultSrbfSolidAngleFlat = false;
inline bool ftFaultSrbfPhiMirror = false;
}
#define FT_FAULT_SRBF_SOLID_ANGLE_FLAT_ON ::ft::ftFaultSrbfSolidAngleFlat
#define FT_FAULT_SRBF_PHI_MIRROR_ON ::ft::ftFaultSrbfPhiMirror
#else
#if defined(FT_FAULT_SRBF_SOLID_ANGLE_FLAT)
#define FT_FAULT_SRBF_SOLID_ANGLE_FLAT_ON true
#else
#define FT_FAULT_SRBF_SOLID_ANGLE_FLAT_ON false
#endif
#if defined(FT_FAULT_SRBF_PHI_MIRROR)
#define FT_FAULT_SRBF_PHI_MIRROR_ON true
#else
#define FT_FAULT_SRBF_PHI_MIRROR_ON false
#endif
#endif

#define FT_SRBF_LOBES 16

FT_NAMESPACE_BEGIN

// One lobe: xyz μ (unit axis), w λ (sharpness); rgb W (radiance weight).
struct SrbfLobe {
  vec4 axisLambda;
  vec4 weight;
};
FT_ASSERT_OFFSET(SrbfLobe, weight, 16)
FT_ASSERT_SIZE(SrbfLobe, 32)

// The fitted environment (std140 UBO FT_UBO_SRBF): 16 lobes and the DC term
// (rgb W_0, a ≡ 1 basis function; w unused). 528 bytes.
struct SrbfEnvironment {
  SrbfLobe lobes[FT_SRBF_LOBES];
  vec4 constant;
};
FT_ASSERT_OFFSET(SrbfEnvironment, constant, 512)
FT_ASSERT_SIZE(SrbfEnvironment, 528)

// G(ω; μ, λ) = e^{λ(μ·ω − 1)} (eq. 14), ω and μ unit.
FT_FUNC float ftSrbfKernel(vec3 mu, float lambda, vec3 w) {
#ifdef FT_FAULT_SRBF_NO_MINUS_ONE
  return exp(lambda * dot(mu, w));  // without the −1: W scaled by e^{−λ} (GPU side only)
#else
  return exp(lambda * (dot(mu, w) - 1.0f));
#endif
}

// ∫_{S²} G dω = 2π(1 − e^{−2λ})/λ. Below λ = 0.1 its series
// 4π Σ_k (−2λ)^k/(k + 1)! to λ⁶ (truncation < 3e-10): the cancellation of
// 1 − e^{−2λ} in float costs ε/(2λ) (3e-6 at λ = 1e-2), 3e-7 above 0.1.
FT_FUNC float ftSrbfIntegral(float lambda) {
  if (lambda < 0.1f) {
    float l = lambda;
    return 2.0f * FT_TWO_PI *
           (1.0f + l * (-1.0f + l * (0.66666667f + l * (-0.33333333f + l * (0.13333333f + l * (-0.04444444f + l * 0.01269841f))))));
  }
  return FT_TWO_PI * (1.0f - exp(-2.0f * lambda)) / lambda;
}

// Σ_j W_j G_j(ω) + W_0 (eq. 14 with the DC term), rgb.
FT_FUNC vec3 ftSrbfRadiance(SrbfEnvironment env, vec3 w) {
  vec3 sum = vec3(env.constant);
  for (int j = 0; j < FT_SRBF_LOBES; ++j)
    sum += vec3(env.lobes[j].weight) * ftSrbfKernel(vec3(env.lobes[j].axisLambda), env.lobes[j].axisLambda.w, w);
  return sum;
}

// Spherical Fibonacci point j of n (reference-data §7) about the y axis (up):
// y_j = 1 − (2j + 1)/n, φ_j = 2π frac(j(Φ − 1)), in the equirect convention.
FT_FUNC vec3 ftSrbfFibonacci(int j, int n) {
  float y = 1.0f - (2.0f * float(j) + 1.0f) / float(n);
  float phi = FT_TWO_PI * fract(float(j) * 0.61803398874989485f);
  float r = sqrt(max(0.0f, 1.0f - y * y));
  return vec3(r * cos(phi), y, r * sin(phi));
}

// λ0 = ln 2/(1 − cos δ), δ = √(4π/n): neighbouring lobes overlap at half
// height (notes A9 [F]; n = 16: 1.885).
FT_FUNC float ftSrbfInitialLambda(int n) {
  float delta = sqrt(2.0f * FT_TWO_PI / float(n));
  return 0.69314718f / (1.0f - cos(delta));
}

// Direction of pixel (x, y) of a W × H equirect map (convention above).
FT_FUNC vec3 ftEquirectDirection(int x, int y, int width, int height) {
  float theta = FT_PI * (float(y) + 0.5f) / float(height);
  float phi = FT_TWO_PI * (float(x) + 0.5f) / float(width) - FT_PI;
  if (FT_FAULT_SRBF_PHI_MIRROR_ON) phi = -phi;  // planted: φ = atan2(−z, x), a mirrored map
  float s = sin(theta);
  return vec3(s * cos(phi), cos(theta), s * sin(phi));
}

// (u, v) ∈ [0, 1)² of a direction (the inverse; ftAtan2-free: atan is only
// used for lookups, never for a narrow lobe).
FT_FUNC vec2 ftEquirectUv(vec3 w) {
  float phi = atan(w.z, w.x);
  float theta = acos(clamp(w.y, -1.0f, 1.0f));
  return vec2((phi + FT_PI) / FT_TWO_PI, theta / FT_PI);
}

// Solid angle of a pixel in row y: (2π/W)(cos θ_top − cos θ_bottom).
FT_FUNC float ftEquirectSolidAngle(int y, int width, int height) {
  if (FT_FAULT_SRBF_SOLID_ANGLE_FLAT_ON) return FT_TWO_PI * FT_PI / (float(width) * float(height));  // planted: no sin θ
  float t0 = FT_PI * float(y) / float(height), t1 = FT_PI * float(y + 1) / float(height);
  // cos t0 − cos t1 = 2 sin((t0 + t1)/2) sin((t1 − t0)/2): no cancellation near the poles.
  return FT_TWO_PI / float(width) * 2.0f * sin(0.5f * (t0 + t1)) * sin(0.5f * (t1 - t0));
}

FT_NAMESPACE_END
#endif  // FT_SRBF_H
