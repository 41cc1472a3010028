// ambient_occlusion.h — the ambient occlusion of a yarn cross-section (Wu &
// Yuksel 2019 (000) §4.2, Figs. 7–8; notes-rendering A3): the precomputed 2D
// texture, its distance-based cubic fit, and both lookups.
//
// Bake (000 §4.2: "trace rays starting from the texel location through the 2D
// density" with "stratified sampling of all possible 2D directions"; the yarn
// untwisted, plies parallel, so everything is 2D): at slice angle ψ = 0 (ply 0
// along +N̂, common/yarn_density.h),
//   AO(p) = (1/N) Σ_k exp(−κ τ(p, d_k)),  d_k = (cos φ_k, sin φ_k),
//   φ_k = 2π (k + ξ_k) / N,
// τ the exact line integral of the ply density (ftDensityLineIntegral), ξ_k a
// jitter from the shared hash (common/rng.h) or ½ (equally spaced). The paper
// only says the accumulated density "indicates the visibility"; exp(−κτ)
// with κ = 2 r_f is the fill of notes §0.3/A3 [F]. Texel (i, j) of an n × n
// texture is centred at p = (−W + (i + ½) 2W/n, −W + (j + ½) 2W/n), texel
// index j·n + i; W = the density's support radius plus one texel.
//
// Use (per fragment), p in the yarn cross-section (x along N̂, y along B̂):
//   (a) distance-based (000's default): AO = clamp(a0 + a1 r̂ + a2 r̂² + a3 r̂³, 0, 1),
//       r̂ = |p|/W measured from the *yarn* centre (000: the ply centre "would
//       not account for the occlusion of separate plies");
//   (b) texture: rotate p by −θ_ply,0 (the ply-0 phase of ftPlyFrame,
//       common/fiber_geometry.h) back to the baked orientation, then a manual
//       bilinear fetch (no sampler: its weight precision is implementation-
//       defined, notes §0.4).
#ifndef FT_AMBIENT_OCCLUSION_H
#define FT_AMBIENT_OCCLUSION_H
#include "prelude.h"
#include "rng.h"
#include "yarn_density.h"

// Planted faults (validation/faults.def). The shared ones live here and so run
// on both sides: C++ reads a run-time switch (the harness turns it on), GLSL
// the define. FT_FAULT_AO_PLY_DISTANCE and FT_FAULT_AO_LOOKUP_PLUS are GPU-only
// defines.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultAoHalfCircle = false;
inline bool ftFaultAoLinearVisibility = false;
}  // namespace ft
#define FT_FAULT_AO_HALF_CIRCLE_ON ::ft::ftFaultAoHalfCircle
#define FT_FAULT_AO_LINEAR_VISIBILITY_ON ::ft::ftFaultAoLinearVisibility
#else
#ifdef FT_FAULT_AO_HALF_CIRCLE
#define FT_FAULT_AO_HALF_CIRCLE_ON true
#else
#define FT_FAULT_AO_HALF_CIRCLE_ON false
#endif
#ifdef FT_FAULT_AO_LINEAR_VISIBILITY
#define FT_FAULT_AO_LINEAR_VISIBILITY_ON true
#else
#define FT_FAULT_AO_LINEAR_VISIBILITY_ON false
#endif
#endif

// AmbientOcclusionParams.directionMode
#define FT_AO_DIRECTIONS_STRATIFIED 0u  // φ_k = 2π(k + ξ_k)/N, ξ_k from the shared hash
#define FT_AO_DIRECTIONS_EQUAL 1u       // φ_k = 2π(k + ½)/N

// Stream of the shared hash the direction jitter is drawn from.
#define FT_AO_RNG_STREAM 0xA0u

FT_NAMESPACE_BEGIN

// Everything a bake or a lookup needs (std140; also the UBO FT_UBO_AMBIENT_OCCLUSION).
struct AmbientOcclusionParams {
  YarnDensityParams density;  // the ply-density field (common/yarn_density.h)
  vec4 cubic;                 // a0..a3 of the distance-based fit, in r̂ = |p|/W
  uint resolution;            // n: texels per side of the AO texture
  uint directions;            // N directions per texel
  uint directionMode;         // FT_AO_DIRECTIONS_*
  uint seed;                  // of the jitter
  float halfWidth;            // W: the texture covers [−W, W]²
  float kappa;                // κ: optical depth per fiber per unit length (notes §0.3: 2 r_f)
  uint densityResolution;     // texels per side of the density grid (paper-faithful bake)
  float marchStep;            // ray-march step, in density texels (notes A3: ½)
};
FT_ASSERT_OFFSET(AmbientOcclusionParams, cubic, 48)
FT_ASSERT_OFFSET(AmbientOcclusionParams, resolution, 64)
FT_ASSERT_OFFSET(AmbientOcclusionParams, halfWidth, 80)
FT_ASSERT_OFFSET(AmbientOcclusionParams, marchStep, 92)
FT_ASSERT_SIZE(AmbientOcclusionParams, 96)

// Centre of texel i (0..n−1) along one axis of an n-texel grid over [−W, W].
FT_FUNC float ftAoTexelCentre(float halfWidth, uint n, uint i) {
  return -halfWidth + (float(i) + 0.5f) * (2.0f * halfWidth / float(n));
}

// Angle of direction k of texel (or point) `sampleId`.
FT_FUNC float ftAoDirectionAngle(AmbientOcclusionParams ao, uint sampleId, uint k) {
  float xi = 0.5f;
  if (ao.directionMode == FT_AO_DIRECTIONS_STRATIFIED) {
    FiberRandomKey key;
    key.yarn = sampleId;
    key.plyFiber = 0u;
    key.period = k;
    key.seed = ao.seed;
    xi = ftUnitFloat(ftRandomBits(key, FT_AO_RNG_STREAM).x);
  }
  // All 2D directions: [0, 2π). Fault: half of them, [0, π).
  float range = FT_FAULT_AO_HALF_CIRCLE_ON ? FT_PI : FT_TWO_PI;
  return range * (float(k) + xi) / float(ao.directions);
}

// Visibility along a ray that crosses τ fibers per unit of κ [F: exp(−κτ)].
FT_FUNC float ftAoVisibility(float kappa, float tau) {
  if (FT_FAULT_AO_LINEAR_VISIBILITY_ON) return max(0.0f, 1.0f - kappa * tau);
  return exp(-kappa * tau);
}

// AO at cross-section point x of the field turned by ψ (ψ = 0 for the
// texture), with the exact line integral. `sampleId` keys the jitter (the texel
// index j·n + i in a bake).
FT_FUNC float ftAoExact(AmbientOcclusionParams ao, float psi, vec2 x, uint sampleId) {
  float sum = 0.0f;
  for (uint k = 0u; k < ao.directions; ++k) {
    float phi = ftAoDirectionAngle(ao, sampleId, k);
    float tau = ftDensityLineIntegral(ao.density, psi, x, vec2(cos(phi), sin(phi)));
    sum += ftAoVisibility(ao.kappa, tau);
  }
  return sum / float(ao.directions);
}

// ---- Distance-based AO (000 §4.2 "method 1", fitted to the texture's radial average) ----

FT_FUNC float ftAoCubicAt(AmbientOcclusionParams ao, float rHat) {
  vec4 a = ao.cubic;
  return clamp(a.x + rHat * (a.y + rHat * (a.z + rHat * a.w)), 0.0f, 1.0f);
}

// The fiber point in the cross-section is plyOffset + fiberOffset (ply centre
// Δc^ply of ftPlyFrame, then the fiber's displacement around it, both
// projected on (N̂, B̂)); its distance is taken from the yarn centre.
FT_FUNC float ftAoCubic(AmbientOcclusionParams ao, vec2 plyOffset, vec2 fiberOffset) {
#ifdef FT_FAULT_AO_PLY_DISTANCE
  float r = length(fiberOffset);  // from the ply centre: misses the other plies' occlusion
#else
  float r = length(plyOffset + fiberOffset);
#endif
  return ftAoCubicAt(ao, r / ao.halfWidth);
}

// ---- Texture lookup ------------------------------------------------------------------

// (cos θ_ply,0, sin θ_ply,0) in the yarn frame from ply 0's frame: pass
// ftPlyFrame(p, r, f, s, 0u).N and the yarn frame's N̂, B̂, so the texture
// turns with the plies exactly as the fibers do.
FT_FUNC vec2 ftAoPlyDirection(vec3 plyN, vec3 yarnN, vec3 yarnB) {
  return vec2(dot(plyN, yarnN), dot(plyN, yarnB));
}

// Texels and weights of a bilinear lookup: index (i0, j0) .. (i1, j1), weights (wx, wy).
struct AoTexelLookup {
  uvec2 lo;
  uvec2 hi;
  vec2 weight;
};

// p in the yarn cross-section, plyDir = (cos θ_ply,0, sin θ_ply,0): p turned
// by −θ_ply,0 (ρ_θ(R_θ x) = ρ_0(x), so AO_θ(p) = AO_0(R_−θ p)), then texel
// coordinates with the half-texel shift, clamped to the texture.
FT_FUNC AoTexelLookup ftAoTextureLookup(AmbientOcclusionParams ao, vec2 p, vec2 plyDir) {
#ifdef FT_FAULT_AO_LOOKUP_PLUS
  vec2 q = vec2(plyDir.x * p.x - plyDir.y * p.y, plyDir.y * p.x + plyDir.x * p.y);  // turned by +θ: wrong
#else
  vec2 q = vec2(plyDir.x * p.x + plyDir.y * p.y, -plyDir.y * p.x + plyDir.x * p.y);
#endif
  float n = float(ao.resolution);
  vec2 u = (q + vec2(ao.halfWidth)) / (2.0f * ao.halfWidth) * n - vec2(0.5f);
  u = clamp(u, vec2(0.0f), vec2(n - 1.0f));
  vec2 lo = min(floor(u), vec2(n - 1.0f));
  AoTexelLookup t;
  t.lo = uvec2(lo);
  t.hi = uvec2(min(lo + vec2(1.0f), vec2(n - 1.0f)));
  t.weight = u - lo;
  return t;
}

// The bilinear mix of the four texels (lo.x, lo.y), (hi.x, lo.y), (lo.x, hi.y), (hi.x, hi.y).
FT_FUNC float ftAoBilinear(float t00, float t10, float t01, float t11, vec2 w) {
  return mix(mix(t00, t10, w.x), mix(t01, t11, w.x), w.y);
}

FT_NAMESPACE_END
#endif  // FT_AMBIENT_OCCLUSION_H
