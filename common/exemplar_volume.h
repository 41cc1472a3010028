// exemplar_volume.h — the exemplar volume and eye-ray casting of Khungurn et
// al. 2017 (004) §5.1, shared by the CPU reference (reference/
// exemplar_volume.h), its GPU twin (gpu/exemplar_volume_gpu.h,
// exemplar_volume_build.comp.glsl, exemplar_volume_sample.comp.glsl) and the
// harness (docs/exemplar-volume.md):
//   * the volume: the flat periodic exemplar block (reference/exemplar.h,
//     period P in x and y, fabric frame z up) on a grid of cubic voxels of side
//     h = P / n (n = round(P / 2r_f): h ≈ the fiber diameter, notes-appearance
//     §8.7 [F]; P an integer number of voxels so that the block tiles), nz
//     voxels in z from origin.z; voxel (i, j, k) covers origin + [i, i+1)·h …,
//     its centre is origin + (i + ½, j + ½, k + ½)·h;
//   * periodic lookup: x and y voxel indices wrap by floor-mod (negative
//     coordinates included: the tiled fabric), z outside [0, nz) is empty;
//   * fill [F notes §8.7]: a voxel is non-empty if any capsule of the block
//     (or of its 8 translates by ±P) may intersect it — conservative: the
//     capsule's axis against the voxel box grown by r on every side (a
//     superset of box ⊕ ball; exact on faces, too generous by ≤ (√3 − 1) r at
//     corners) — and stores 1 + the block index of the nearest midpoint among
//     those capsules (ties: the lower index); 0 = empty;
//   * eye rays (004 §5.1): the ray is clipped to the slab z ∈ [z_lo, z_hi] of
//     the volume, t ∈ [t0, t1], and sampled at N linearly spaced *sample
//     centres* t_i = t0 + (i + ½)(t1 − t0)/N, i = 0 … N − 1 (no sample on the
//     slab's faces, where it would read the empty padding); the first sample
//     in a non-empty voxel is the hit: its id and its flat-space position go
//     to the G-buffer; none: a miss (id 0).
#ifndef FT_EXEMPLAR_VOLUME_H
#define FT_EXEMPLAR_VOLUME_H
#include "prelude.h"

// Planted faults (validation/faults.def). Shared: C++ run-time switch and GLSL
// define, on both sides.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultVolWrapNegative = false;
inline bool ftFaultVolVoxelCorner = false;
using glm::ivec3;
}
#define FT_FAULT_VOL_WRAP_NEGATIVE_ON ::ft::ftFaultVolWrapNegative
#define FT_FAULT_VOL_VOXEL_CORNER_ON ::ft::ftFaultVolVoxelCorner
#else
#if defined(FT_FAULT_VOL_WRAP_NEGATIVE)
#define FT_FAULT_VOL_WRAP_NEGATIVE_ON true
#else
#define FT_FAULT_VOL_WRAP_NEGATIVE_ON false
#endif
#if defined(FT_FAULT_VOL_VOXEL_CORNER)
#define FT_FAULT_VOL_VOXEL_CORNER_ON true
#else
#define FT_FAULT_VOL_VOXEL_CORNER_ON false
#endif
#endif

#define FT_VOL_MAX_SAMPLES 4096u  // N per ray (llvmpipe's loop limit is 65,535)
#define FT_VOL_COPIES 9u          // the block and its 8 translates by (±P, ±P)
#define FT_VOL_CAMERA_ORTHO 0u
#define FT_VOL_CAMERA_PINHOLE 1u

FT_NAMESPACE_BEGIN

// The GPU twin's parameters (std140 UBO FT_UBO_PRT_VOL).
struct VolParams {
  vec4 origin;    // xyz: the volume's lower corner (x = y = 0: the block's), w: h
  uvec4 dims;     // nx, ny, nz, segments of the block
  uvec4 grid;     // candidate grid: cells in x, y, z; w: voxels per cell side
  uvec4 ray;      // width, height, samples N, mode (shader pass of the build program: unused by the sampler)
  vec4 camPos;    // ortho: centre of the image rectangle; pinhole: the eye; w: camera type
  vec4 camRight;  // xyz: image right axis; w: half width (ortho: length; pinhole: tan of half the fov)
  vec4 camUp;     // xyz: image up axis; w: half height (same units)
  vec4 camDir;    // xyz: viewing direction (unit); w: unused
};
FT_ASSERT_OFFSET(VolParams, dims, 16)
FT_ASSERT_OFFSET(VolParams, ray, 48)
FT_ASSERT_OFFSET(VolParams, camDir, 112)
FT_ASSERT_SIZE(VolParams, 128)

// A segment of the block (std430 SSBO FT_SSBO_PRT_VOL_SEGMENTS): endpoints,
// a.w the radius, b.w the fiber id (as a float: < 2^24).
struct VolSegment {
  vec4 a;
  vec4 b;
};
FT_ASSERT_OFFSET(VolSegment, b, 16)
FT_ASSERT_SIZE(VolSegment, 32)

// A G-buffer texel (std430 SSBO FT_SSBO_PRT_RESULTS): the flat-space hit
// point and 1 + the segment id (0: miss, point undefined = 0).
struct VolHit {
  vec3 point;
  uint id;
};
FT_ASSERT_OFFSET(VolHit, id, 12)
FT_ASSERT_SIZE(VolHit, 16)

// Floor-mod: i mod n in [0, n) for negative i too (only non-negative integer
// divisions: GLSL leaves % of negatives undefined).
FT_FUNC int ftVolWrap(int i, int n) {
  if (FT_FAULT_VOL_WRAP_NEGATIVE_ON) return (i >= 0 ? i : -i) % n;  // planted: |i| mod n (mirrors the negative tiles)
  if (i >= 0) return i % n;
  int r = (-i) % n;
  return r == 0 ? 0 : n - r;
}

// Unwrapped voxel coordinates of a point: floor((p − origin)/h).
FT_FUNC ivec3 ftVolVoxelCoord(vec3 p, vec4 origin) {
  vec3 c = (p - vec3(origin.x, origin.y, origin.z)) / origin.w;
  return ivec3(int(floor(c.x)), int(floor(c.y)), int(floor(c.z)));
}

// Linear index of voxel (i, j, k) after the periodic wrap of i, j; −1 when k
// is outside the slab.
FT_FUNC int ftVolIndex(ivec3 v, uvec4 dims) {
  int nx = int(dims.x), ny = int(dims.y), nz = int(dims.z);
  if (v.z < 0 || v.z >= nz) return -1;
  return (v.z * ny + ftVolWrap(v.y, ny)) * nx + ftVolWrap(v.x, nx);
}

// The voxel of a linear index (0 ≤ index < nx·ny·nz).
FT_FUNC ivec3 ftVolVoxelOfIndex(uint index, uvec4 dims) {
  return ivec3(int(index % dims.x), int((index / dims.x) % dims.y), int(index / (dims.x * dims.y)));
}

// Centre of voxel v: origin + (v + ½)·h.
FT_FUNC vec3 ftVolVoxelCentre(ivec3 v, vec4 origin) {
  vec3 f = vec3(float(v.x), float(v.y), float(v.z));
  if (!FT_FAULT_VOL_VOXEL_CORNER_ON) f = f + vec3(0.5f);  // planted: the corner instead of the centre
  return vec3(origin.x, origin.y, origin.z) + f * origin.w;
}

// The period P = nx·h of the volume (both sides use this value, not the
// block's own float P: they differ by ~1 ulp).
FT_FUNC float ftVolPeriod(VolParams p) { return float(p.dims.x) * p.origin.w; }

// Translation of copy c (0 … 8) of the block: ((c mod 3) − 1, (c div 3) − 1)·P.
FT_FUNC vec3 ftVolCopyOffset(uint c, float period) {
  return vec3(float(int(c % 3u) - 1) * period, float(int(c / 3u) - 1) * period, 0.0f);
}

// Does the segment a–b come within r of the box [lo, hi]? Conservative: the
// slab test of the segment against the box grown by r on every side.
FT_FUNC bool ftVolSegmentTouchesBox(vec3 a, vec3 b, float r, vec3 lo, vec3 hi) {
  vec3 d = b - a;
  float t0 = 0.0f, t1 = 1.0f;
  for (int axis = 0; axis < 3; ++axis) {
    float da = axis == 0 ? d.x : (axis == 1 ? d.y : d.z);
    float pa = axis == 0 ? a.x : (axis == 1 ? a.y : a.z);
    float l = (axis == 0 ? lo.x : (axis == 1 ? lo.y : lo.z)) - r;
    float h = (axis == 0 ? hi.x : (axis == 1 ? hi.y : hi.z)) + r;
    if (da == 0.0f) {
      if (pa < l || pa > h) return false;
    } else {
      float u = (l - pa) / da, v = (h - pa) / da;
      t0 = max(t0, min(u, v));
      t1 = min(t1, max(u, v));
    }
  }
  return t0 <= t1;
}

// Squared distance from the voxel centre to a midpoint: the id's key.
FT_FUNC float ftVolMidpointKey(vec3 centre, vec3 a, vec3 b) {
  vec3 m = 0.5f * (a + b) - centre;
  return dot(m, m);
}

// The ray's parameter interval inside the slab z ∈ [zLo, zHi]: (t0, t1), or
// t0 > t1 when the ray misses it (a horizontal ray, or one leaving it).
FT_FUNC vec2 ftVolSlabInterval(vec3 o, vec3 d, float zLo, float zHi) {
  if (d.z == 0.0f) return vec2(1.0f, 0.0f);  // no bounded segment: a miss
  float u = (zLo - o.z) / d.z, v = (zHi - o.z) / d.z;
  return vec2(max(0.0f, min(u, v)), max(u, v));
}

// Sample i of N on [t0, t1]: the centre of the i-th of N equal pieces.
FT_FUNC float ftVolSampleT(float t0, float t1, uint i, uint n) {
  return t0 + (float(i) + 0.5f) * ((t1 - t0) / float(n));
}

// The linear voxel index of sample i of N of the ray o + t d on [t0, t1]
// (−1: outside the slab). The first-non-empty lookup is the loop over i of
// `ids[index] != 0` — written out by its two callers (reference/
// exemplar_volume.cpp, exemplar_volume_sample.comp.glsl) because common/
// cannot take the volume array.
FT_FUNC int ftVolSampleIndex(vec3 o, vec3 d, float t, VolParams p) {
  return ftVolIndex(ftVolVoxelCoord(o + t * d, p.origin), p.dims);
}

// Distance from p to the nearest voxel face, in units of h (the ambiguity of
// a sample's voxel: float rounding moves p by ~1e-7 h).
FT_FUNC float ftVolFaceDistance(vec3 p, vec4 origin) {
  vec3 c = (p - vec3(origin.x, origin.y, origin.z)) / origin.w;
  vec3 f = c - floor(c);
  vec3 g = min(f, vec3(1.0f) - f);
  return min(g.x, min(g.y, g.z));
}

// The eye ray of pixel (x, y) (row 0 at the top, through pixel centres).
FT_FUNC vec3 ftVolRayOrigin(VolParams p, uint x, uint y) {
  float sx = 2.0f * (float(x) + 0.5f) / float(p.ray.x) - 1.0f;
  float sy = 1.0f - 2.0f * (float(y) + 0.5f) / float(p.ray.y);
  vec3 e = vec3(p.camPos.x, p.camPos.y, p.camPos.z);
  if (uint(p.camPos.w) == FT_VOL_CAMERA_PINHOLE) return e;
  return e + (sx * p.camRight.w) * vec3(p.camRight.x, p.camRight.y, p.camRight.z) +
         (sy * p.camUp.w) * vec3(p.camUp.x, p.camUp.y, p.camUp.z);
}
FT_FUNC vec3 ftVolRayDirection(VolParams p, uint x, uint y) {
  vec3 f = vec3(p.camDir.x, p.camDir.y, p.camDir.z);
  if (uint(p.camPos.w) != FT_VOL_CAMERA_PINHOLE) return f;
  float sx = 2.0f * (float(x) + 0.5f) / float(p.ray.x) - 1.0f;
  float sy = 1.0f - 2.0f * (float(y) + 0.5f) / float(p.ray.y);
  vec3 d = f + (sx * p.camRight.w) * vec3(p.camRight.x, p.camRight.y, p.camRight.z) +
           (sy * p.camUp.w) * vec3(p.camUp.x, p.camUp.y, p.camUp.z);
  return ftNormalize(d);
}

FT_NAMESPACE_END
#endif  // FT_EXEMPLAR_VOLUME_H
