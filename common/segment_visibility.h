// segment_visibility.h — the segment visibility function (SVF) of Khungurn et
// al. 2017 (004) §4.1, shared by the CPU reference (reference/
// segment_visibility.h), its GPU twin (gpu/segment_visibility_gpu.h,
// segment_visibility.comp.glsl) and the bake (docs/segment-visibility.md):
//   * the visibility image over the (θ, φ) parameterization of the sphere
//     (004 §4.1 "SSDF implementation"), fabric frame z up (the normal of the
//     flat fabric, 004 §2): pixel (x, y) of a W × H image, row 0 at the +z
//     pole, θ = π(y + ½)/H, φ = 2π(x + ½)/W − π,
//       ω = (sin θ cos φ, sin θ sin φ, cos θ)
//     — common/srbf.h's equirect direction with y and z exchanged (that map is
//     y up), so pixel centres and the exact band solid angle
//     (2π/W)(cos θ_top − cos θ_bottom) are srbf.h's (reused, not duplicated);
//   * the SSDF d_k(ω) (004 §4.1, Wang et al. 2009): per pixel the great-circle
//     distance in radians to the nearest pixel centre of the opposite value,
//     positive where visible [F: notes-appearance §5.4], ±π when the image
//     has one value only; the candidates are the opposite-valued pixels with a
//     4-neighbour of the other value (the boundary list, [F] notes §5.4);
//   * the sum of SGs (004 §4.1b–d): Q = 48 axes ξ_k,q = R_k ξ′_q on the
//     upper-hemisphere Fibonacci set, R_k a rotation about z by an angle drawn
//     from common/rng.h keyed by the segment id, weights w_k,q = solid angle
//     of the visible z > 0 pixels whose nearest axis is ξ_k,q (Voronoi),
//     V^ssg(ω) = Σ_q w_q G(ω; ξ_q, λ_svf)/M(λ_svf) with srbf.h's G and M.
#ifndef FT_SEGMENT_VISIBILITY_H
#define FT_SEGMENT_VISIBILITY_H
#include "prelude.h"
#include "rng.h"
#include "srbf.h"

// Planted faults (validation/faults.def). Shared: C++ run-time switch and GLSL
// define, on both sides.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultSvfFibAxesFullSphere = false;
inline bool ftFaultSvfSsdfPixelDistance = false;
}
#define FT_FAULT_SVF_FIB_AXES_FULL_SPHERE_ON ::ft::ftFaultSvfFibAxesFullSphere
#define FT_FAULT_SVF_SSDF_PIXEL_DISTANCE_ON ::ft::ftFaultSvfSsdfPixelDistance
#else
#if defined(FT_FAULT_SVF_FIB_AXES_FULL_SPHERE)
#define FT_FAULT_SVF_FIB_AXES_FULL_SPHERE_ON true
#else
#define FT_FAULT_SVF_FIB_AXES_FULL_SPHERE_ON false
#endif
#if defined(FT_FAULT_SVF_SSDF_PIXEL_DISTANCE)
#define FT_FAULT_SVF_SSDF_PIXEL_DISTANCE_ON true
#else
#define FT_FAULT_SVF_SSDF_PIXEL_DISTANCE_ON false
#endif
#endif

#define FT_SVF_MAX_AXES 64     // Q ≤ 64 (the paper's 48 + room)
#define FT_SVF_DEFAULT_AXES 48  // Q (004 §4.1)
#define FT_SVF_LAMBDA 128.0f    // λ_svf (004 §4.1: ≥ 100, 128 in every rendering)

FT_NAMESPACE_BEGIN

// The GPU twin's parameters (std140 UBO FT_UBO_SVF).
struct SvfParams {
  uint width;      // W (φ)
  uint height;     // H (θ), even: rows < H/2 are the z > 0 hemisphere
  uint axes;       // Q
  uint segments;   // images in this batch
  uint seed;       // key of R_k
  uint components; // PCA components (decode)
  uint firstSegment;  // segment id of image 0 (R_k is keyed by the id)
  uint mode;       // shader pass (segment_visibility.comp.glsl)
  float lambda;    // λ_svf
  float pad0, pad1, pad2;
};
FT_ASSERT_OFFSET(SvfParams, lambda, 32)
FT_ASSERT_SIZE(SvfParams, 48)

// Direction of the centre of pixel (x, y), fabric frame (z up).
FT_FUNC vec3 ftSvfPixelDirection(int x, int y, int width, int height) {
  vec3 d = ftEquirectDirection(x, y, width, height);
  return vec3(d.x, d.z, d.y);
}

// Exact solid angle of a pixel of row y (band area; the rows sum to 4π).
FT_FUNC float ftSvfPixelSolidAngle(int y, int width, int height) { return ftEquirectSolidAngle(y, width, height); }

// R_k: angle of the rotation about z of segment `segment` (004 §4.1c; uniform
// in [0, 2π) [F notes §5.9]), from the shared counter RNG.
FT_FUNC float ftSvfRotationAngle(uint segment, uint seed) {
  uvec4 b = ftPcg4d(uvec4(segment, seed, 0x53564652u, 0u));  // "SVFR"
  return FT_TWO_PI * ftUnitFloat(b.x);
}

// ξ′_q of 004 §4.1c (q = 1..Q, q = 1 at the pole): z_q = 1 − (q − 1)/Q,
// ϕ_q = 4πq/(1 + √5), r_q = √(1 − z_q²); then turned by `angle` about z.
FT_FUNC vec3 ftSvfAxis(int q, int count, float angle) {
  float z = 1.0f - float(q - 1) / float(count);
  if (FT_FAULT_SVF_FIB_AXES_FULL_SPHERE_ON) z = 1.0f - float(2 * q - 1) / float(count);  // planted: whole sphere
  // 4πq/(1 + √5) = 2π q (Φ − 1) with Φ − 1 = 0.618…: reduce q(Φ − 1) mod 1
  // first, so that float keeps the angle's bits (q ≤ 64).
  float phi = FT_TWO_PI * fract(float(q) * 0.61803398874989485f) + angle;
  float r = sqrt(max(0.0f, 1.0f - z * z));
  return vec3(r * cos(phi), r * sin(phi), z);
}

// Index (0-based) of the axis nearest to ω: the largest ω·ξ, the first on a tie.
FT_FUNC int ftSvfNearestAxis(vec3 w, int count, float angle) {
  int best = 0;
  float bestDot = -2.0f;
  for (int q = 0; q < count; ++q) {
    float c = dot(w, ftSvfAxis(q + 1, count, angle));
    if (c > bestDot) {
      bestDot = c;
      best = q;
    }
  }
  return best;
}

// 4-neighbour of pixel (x, y) in direction `dir` (0 −x, 1 +x, 2 −y, 3 +y) as
// a flat index: φ wraps; across a pole the neighbour is the same row half a
// turn round (W even).
FT_FUNC int ftSvfNeighbour(int x, int y, int dir, int width, int height) {
  if (dir == 0) return y * width + (x + width - 1) % width;
  if (dir == 1) return y * width + (x + 1) % width;
  int halfTurn = width / 2;
  if (dir == 2) return y == 0 ? (x + halfTurn) % width : (y - 1) * width + x;
  return y == height - 1 ? (height - 1) * width + (x + halfTurn) % width : (y + 1) * width + x;
}

// Squared chord |ω_p − ω_q|² between two pixel centres (their directions wp,
// wq from ftSvfPixelDirection, which callers may tabulate), or (fault) the
// squared flat (θ, φ) distance (φ wrapped).
FT_FUNC float ftSvfDistanceKey(vec3 wp, vec3 wq, int px, int py, int qx, int qy, int width, int height) {
  if (FT_FAULT_SVF_SSDF_PIXEL_DISTANCE_ON) {
    float dt = FT_PI * float(py - qy) / float(height);
    int dx = abs(px - qx);
    dx = min(dx, width - dx);
    float dp = FT_TWO_PI * float(dx) / float(width);
    return dt * dt + dp * dp;
  }
  vec3 d = wp - wq;
  return dot(d, d);
}

// The geodesic distance of a distance key: 2 asin(chord/2), written as
// 2 atan2(chord/2, √(1 − chord²/4)) — well conditioned at small angles
// (unlike acos of a dot product), and Mesa lowers GLSL asin to a polynomial
// ~4e-4 rad off at 1 rad, atan to one good to ~1e-6; the fault's key is
// already an angle.
FT_FUNC float ftSvfDistanceOfKey(float key) {
  if (FT_FAULT_SVF_SSDF_PIXEL_DISTANCE_ON) return sqrt(key);
  float k = clamp(key, 0.0f, 4.0f);
  return 2.0f * atan(0.5f * sqrt(k), sqrt(max(0.0f, 1.0f - 0.25f * k)));
}

// SSDF value of a pixel from the minimum key over the opposite boundary
// pixels (key < 0: none — the image has one value: ±π).
FT_FUNC float ftSvfSsdfFromKey(bool visible, float minKey) {
  float d = minKey < 0.0f ? FT_PI : min(FT_PI, ftSvfDistanceOfKey(minKey));
  return visible ? d : -d;
}

// V^ssg(ω) = Σ_q w_q G(ω; ξ_q, λ)/M(λ) (004 §4.1b) for one term: callers sum.
FT_FUNC float ftSvfSgTerm(float weight, vec3 axis, float lambda, vec3 w) {
  return weight * ftSrbfKernel(axis, lambda, w) / ftSrbfIntegral(lambda);
}

FT_NAMESPACE_END
#endif  // FT_SEGMENT_VISIBILITY_H
