// shadow_map.h — the yarn shadow map of Wu & Yuksel 2019 (000) §4.1, last
// paragraph: "we simply render each yarn curve as a thick tube, completely
// disregarding the fiber-level structure" into a light-space depth map, one
// per directional light (notes-rendering A5). Shared by the GPU depth pass
// and lookup (gpu/shaders/shadow_map.*.glsl, fiber_strip.frag.glsl) and the
// CPU side (the harness's lookups in the read-back map, the Embree reference
// reference/shadow_map_reference.h). docs/shadow-map.md.
//
// Conventions: light space is world units, origin at the centre of the
// casters' bounds, x and y across the light, z along its propagation (away
// from the light). The orthographic projection maps the square [−h, h]² and
// depth [−h_z, h_z] to NDC [−1, 1]³; texture coordinates and stored depth are
// NDC·0.5 + 0.5 ([0, 1], GL's default depth range).
//
// Each tube segment is a capsule of radius R_tube = W (the yarn's reach,
// plyRadius + max(e_N, e_B)·R_max, notes §0.3). The map stores the capsule's
// FAR side (notes A5): a yarn's own fibers lie in front of it and are never
// shadowed by their own tube (the self-shadow texture, common/self_shadow.h,
// covers that), while anything behind a tube is.
#ifndef FT_SHADOW_MAP_H
#define FT_SHADOW_MAP_H
#include "prelude.h"

// Planted faults (validation/faults.def), shared: run-time switch in C++, define in GLSL.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultShadowMapFrontDepth = false;
inline bool ftFaultShadowMapNoRemap = false;
inline bool ftFaultShadowPcfWeightsSwapped = false;
}
#define FT_FAULT_SHADOW_MAP_FRONT_DEPTH_ON ::ft::ftFaultShadowMapFrontDepth
#define FT_FAULT_SHADOW_MAP_NO_REMAP_ON ::ft::ftFaultShadowMapNoRemap
#define FT_FAULT_SHADOW_PCF_WEIGHTS_SWAPPED_ON ::ft::ftFaultShadowPcfWeightsSwapped
#else
#ifdef FT_FAULT_SHADOW_MAP_FRONT_DEPTH
#define FT_FAULT_SHADOW_MAP_FRONT_DEPTH_ON true
#else
#define FT_FAULT_SHADOW_MAP_FRONT_DEPTH_ON false
#endif
#ifdef FT_FAULT_SHADOW_MAP_NO_REMAP
#define FT_FAULT_SHADOW_MAP_NO_REMAP_ON true
#else
#define FT_FAULT_SHADOW_MAP_NO_REMAP_ON false
#endif
#ifdef FT_FAULT_SHADOW_PCF_WEIGHTS_SWAPPED
#define FT_FAULT_SHADOW_PCF_WEIGHTS_SWAPPED_ON true
#else
#define FT_FAULT_SHADOW_PCF_WEIGHTS_SWAPPED_ON false
#endif
#endif

#define FT_SHADOW_MAP_MAX_LIGHTS 4
#define FT_SHADOW_MAP_DEFAULT_SIZE 2048u  // notes A5 [F]
#define FT_SHADOW_MAP_CI_SIZE 256u
#define FT_SHADOW_MAP_SUBSEGMENTS 8u      // tube capsules per Catmull-Rom segment (notes A5 [F])
#define FT_SHADOW_MAP_BIAS_TEXELS 1.5f    // slope bias: depth change over 1.5 texels (notes A5 [F])
#define FT_SHADOW_MAP_MISS -3.0e38f
// The lookup's filter (ShadowMapParams::count.z; 000 says nothing about filtering):
#define FT_SHADOW_FILTER_NEAREST 0u  // the nearest texel's comparison: hard texel-sized steps
#define FT_SHADOW_FILTER_PCF 1u      // 2 × 2 percentage-closer filtering (notes A5 [F]), the default

FT_NAMESPACE_BEGIN

// Uniform block of the depth pass and the frame's lookup (std140).
struct ShadowMapParams {
  vec4 lightX[FT_SHADOW_MAP_MAX_LIGHTS];  // xyz: light-space x axis (world), w: −dot(axis, centre)
  vec4 lightY[FT_SHADOW_MAP_MAX_LIGHTS];
  vec4 lightZ[FT_SHADOW_MAP_MAX_LIGHTS];  // the light's propagation: −(direction towards the light)
  vec4 extent;  // x h (half side, world), y h_z (half depth), z texel size 2h/N (world), w N (texels per side)
  vec4 tube;    // x R_tube = W, y the ply radius (fault), z bias texels, w unused
  uvec4 count;  // x lights, y N, z the lookup's filter (FT_SHADOW_FILTER_*), w unused
};
FT_ASSERT_OFFSET(ShadowMapParams, lightY, 64)
FT_ASSERT_OFFSET(ShadowMapParams, extent, 192)
FT_ASSERT_OFFSET(ShadowMapParams, count, 224)
FT_ASSERT_SIZE(ShadowMapParams, 240)

// World point → light space (world units) of light i.
FT_FUNC vec3 ftShadowLightSpace(ShadowMapParams m, int i, vec3 p) {
  vec4 q = vec4(p, 1.0f);
  return vec3(dot(m.lightX[i], q), dot(m.lightY[i], q), dot(m.lightZ[i], q));
}

// Light space → NDC [−1, 1]³ (the orthographic projection).
FT_FUNC vec3 ftShadowNdc(ShadowMapParams m, vec3 l) {
  return vec3(l.x / m.extent.x, l.y / m.extent.x, l.z / m.extent.y);
}

// NDC → map coordinates: (u, v) in [0, 1]² and depth in [0, 1], as GL's
// viewport transform and depth range write them.
FT_FUNC vec3 ftShadowNdcToMap(vec3 ndc) {
  if (FT_FAULT_SHADOW_MAP_NO_REMAP_ON) return ndc;  // NDC taken for [0, 1]
  return ndc * 0.5f + vec3(0.5f);
}

// Light-space depth (world units) → stored depth in [0, 1].
FT_FUNC float ftShadowDepth(ShadowMapParams m, float lz) { return ftShadowNdcToMap(vec3(0.0f, 0.0f, lz / m.extent.y)).z; }

// The tube piece of radius r around segment [a, b] (light space) along the
// ray (q, z), z increasing away from the light: its far side's depth plus the
// slope bias, in light-space units, or FT_SHADOW_MAP_MISS. The piece is the
// cylinder clipped to the segment's span, closed by a half-ball only where
// `capA` / `capB` say the yarn ends there. Pieces of one yarn then share one
// surface, as a mesh tube does: a far side stored per full capsule would lie
// inside the neighbouring capsules (their balls reach r along the axis), and
// under a grazing light the yarn would shadow its own fibers through them.
// The bias is the depth the far surface drops within `biasWorld` across the
// map (a nearest-texel lookup reads a texel centre up to ~0.7 texel away):
// across the axis, (sqrt(r² − ρ²) − sqrt(r² − (ρ + b)²)) / sin γ (ρ the
// ray's distance from the axis, γ the axis's angle to the light), the whole
// half-chord where ρ + b leaves the tube; along the axis, b·|cot γ|. Capped
// where the stored depth would pass the piece's deepest point.
FT_FUNC float ftShadowCapsuleDepth(vec3 a, vec3 b, float r, vec2 q, float biasWorld, bool capA, bool capB) {
  float farZ = FT_SHADOW_MAP_MISS;
  float nearZ = -FT_SHADOW_MAP_MISS;
  float rho = 0.0f;        // the far hit's ray distance from the axis (ball: from the centre)
  float sinGamma = 1.0f;   // 1 on a ball
  float cotGamma = 0.0f;
  vec3 d = b - a;
  float len2 = dot(d, d);
  if (len2 > 0.0f) {
    // |(o − a) − ((o − a)·d̂)d̂|² = r² along o = (q, z).
    vec3 w = vec3(q.x - a.x, q.y - a.y, -a.z);  // o(z = 0) − a
    vec3 e = vec3(0.0f, 0.0f, 1.0f);
    float ed = d.z / len2, wd = dot(w, d) / len2;
    vec3 ep = e - d * ed, wp = w - d * wd;
    float qa = dot(ep, ep), qb = dot(ep, wp), qc = dot(wp, wp) - r * r;
    float disc = qb * qb - qa * qc;
    if (qa > 1e-12f && disc >= 0.0f) {
      float s = sqrt(disc);
      float z1 = (-qb - s) / qa, z2 = (-qb + s) / qa;
      float t1 = wd + z1 * ed, t2 = wd + z2 * ed;
      if (t2 >= 0.0f && t2 <= 1.0f) {
        farZ = z2;
        rho = sqrt(max(r * r - disc / qa, 0.0f));
        sinGamma = sqrt(qa);  // |e − (e·d̂)d̂| = sin γ
        cotGamma = abs(d.z) / max(length(vec2(d.x, d.y)), 1e-30f);
      }
      if (t1 >= 0.0f && t1 <= 1.0f) nearZ = z1;
    }
  }
  for (int k = 0; k < 2; ++k) {
    if (!(k == 0 ? capA : capB)) continue;
    vec3 c = k == 0 ? a : b;
    vec2 dq = q - vec2(c.x, c.y);
    float h2 = r * r - dot(dq, dq);
    if (h2 < 0.0f) continue;
    float h = sqrt(h2);
    // Only the half-ball beyond the end belongs to the tube's surface.
    float tFar = len2 > 0.0f ? dot(vec3(q.x, q.y, c.z + h) - a, d) / len2 : float(k);
    float tNear = len2 > 0.0f ? dot(vec3(q.x, q.y, c.z - h) - a, d) / len2 : float(k);
    bool outside = k == 0 ? tFar <= 0.0f : tFar >= 1.0f;
    if (outside && c.z + h > farZ) {
      farZ = c.z + h;
      rho = length(dq);
      sinGamma = 1.0f;
      cotGamma = 0.0f;
    }
    bool outsideNear = k == 0 ? tNear <= 0.0f : tNear >= 1.0f;
    if (outsideNear) nearZ = min(nearZ, c.z - h);
  }
  if (farZ == FT_SHADOW_MAP_MISS) return FT_SHADOW_MAP_MISS;
  if (FT_FAULT_SHADOW_MAP_FRONT_DEPTH_ON) return nearZ < farZ ? nearZ : farZ;  // the near side, no bias
  float halfChord = sqrt(max(r * r - rho * rho, 0.0f));
  float outer = rho + biasWorld;
  float across = (outer >= r ? halfChord : halfChord - sqrt(r * r - outer * outer)) / max(sinGamma, 1e-6f);
  float bias = across + biasWorld * cotGamma;
  float deepest = max(a.z, b.z) + r;
  return min(farZ + bias, max(deepest, farZ));
}

// Map texel of a point: (column, row, layer index = light) clamped; false
// (through the returned w < 0) when the point lies outside the map's square.
FT_FUNC ivec4 ftShadowTexel(ShadowMapParams m, vec3 mapCoord) {
  int n = int(m.count.y);
  if (mapCoord.x < 0.0f || mapCoord.x >= 1.0f || mapCoord.y < 0.0f || mapCoord.y >= 1.0f) return ivec4(0, 0, 0, -1);
  return ivec4(min(int(mapCoord.x * float(n)), n - 1), min(int(mapCoord.y * float(n)), n - 1), 0, 1);
}

// V_map of notes A5: 1 when the point is in front of (or at) the stored far
// side, 0 behind it. A cleared texel (1: no tube) lets every depth through,
// so receivers beyond the casters' bounds are lit.
FT_FUNC float ftShadowVisibility(float pointDepth, float mapDepth) {
  if (mapDepth >= 1.0f) return 1.0f;
  return pointDepth <= mapDepth ? 1.0f : 0.0f;
}

// Index of texel (column x, row y) of light i in the stored maps (layer-major, rows bottom-up as GL).
FT_FUNC uint ftShadowMapIndex(ShadowMapParams m, int i, int x, int y) {
  return (uint(i) * m.count.y + uint(y)) * m.count.y + uint(x);
}

// 2 × 2 percentage-closer filtering (Reeves et al. 1987, in the bilinear form
// of hardware shadow samplers) [F]: the point's depth is compared with the
// four texels whose centres surround its map position, and the four verdicts
// (ftShadowVisibility) are weighted bilinearly, so a shadow's edge becomes a
// ramp one texel wide instead of a texel-sized step (docs/shadow-map.md).
// The texel centres read lie within √2 texels of the point, inside the
// depth's bias of FT_SHADOW_MAP_BIAS_TEXELS. For map coordinates in an
// n × n map, returns the footprint's lower-left texel (column, row; −1 at the
// map's low edge) in xy and the weights towards the next column and row in zw.
FT_FUNC vec4 ftShadowPcfFootprint(vec3 mapCoord, int n) {
  vec2 f = vec2(mapCoord.x, mapCoord.y) * float(n) - vec2(0.5f);
  vec2 c = floor(f);
  vec2 w = f - c;
  if (FT_FAULT_SHADOW_PCF_WEIGHTS_SWAPPED_ON) w = vec2(1.0f) - w;  // planted: each texel weighted as the other
  return vec4(c.x, c.y, w.x, w.y);
}

// Column (or row) c + k, k = 0 or 1, of the footprint, clamped to the map's n texels.
FT_FUNC int ftShadowPcfTexel(float c, int k, int n) { return clamp(int(c) + k, 0, n - 1); }

// The filtered visibility from the verdicts at the footprint's texels
// (v10: one column on, v01: one row on, v11: both).
FT_FUNC float ftShadowPcfCombine(vec4 footprint, float v00, float v10, float v01, float v11) {
  float wx = footprint.z, wy = footprint.w;
  return (1.0f - wy) * ((1.0f - wx) * v00 + wx * v10) + wy * ((1.0f - wx) * v01 + wx * v11);
}

FT_NAMESPACE_END
#endif  // FT_SHADOW_MAP_H
