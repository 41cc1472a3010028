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
inline bool ftFaultVolCapsuleExit = false;
using glm::ivec3;
}
#define FT_FAULT_VOL_WRAP_NEGATIVE_ON ::ft::ftFaultVolWrapNegative
#define FT_FAULT_VOL_VOXEL_CORNER_ON ::ft::ftFaultVolVoxelCorner
#define FT_FAULT_VOL_CAPSULE_EXIT_ON ::ft::ftFaultVolCapsuleExit
#else
#if defined(FT_FAULT_VOL_CAPSULE_EXIT)
#define FT_FAULT_VOL_CAPSULE_EXIT_ON true
#else
#define FT_FAULT_VOL_CAPSULE_EXIT_ON false
#endif
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
// The G-buffer's id (VolParams.camDir.w): 004 §5.1's nearest midpoint at the
// first non-empty sample, or the first exact ray–capsule hit among the
// candidates of the cells the ray crosses (docs/exemplar-volume.md).
#define FT_VOL_IDS_MIDPOINT 0u
#define FT_VOL_IDS_CAPSULE 1u
#define FT_VOL_MAX_STEPS 8192u  // cells per ray of the capsule walk (then a miss)

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
  vec4 camDir;    // xyz: viewing direction (unit); w: the id (FT_VOL_IDS_*)
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

// ---- capsule ids: the first exact hit along the ray ------------------------
// (docs/exemplar-volume.md "Ids"). The ray walks the candidate cells it
// crosses (Amanatides & Woo 1987's traversal on the cells, unwrapped
// coordinates); in each, the candidates (every capsule that can touch the
// cell's voxels) are tested exactly, in the block frame shifted by the cell's
// whole periods; the nearest hit wins once the walk passes it. The loop over
// candidates is written out by the two callers (reference/
// exemplar_volume.cpp, exemplar_volume_sample.comp.glsl), like the sampler's.

FT_FUNC uint ftVolIdMode(VolParams p) { return uint(p.camDir.w + 0.5f); }

// Entry parameter t ≥ 0 of the ray o + t d into the capsule of axis a–b and
// radius r (the union of the lateral cylinder between the end planes and the
// two end spheres: its first point is the earliest entry of the three); −1:
// no entry ahead. The origin is taken to be outside the capsule.
FT_FUNC float ftVolRayCapsule(vec3 o, vec3 d, vec3 a, vec3 b, float r) {
  // Start from the ray's point nearest the capsule's midpoint: with the eye
  // ~100 radii away, the quadratics below would otherwise cancel away the r².
  float dd = dot(d, d);
  float tc = dot(0.5f * (a + b) - o, d) / dd;
  o = o + tc * d;
  vec3 ba = b - a, oa = o - a;
  float baba = dot(ba, ba), bard = dot(ba, d), baoa = dot(ba, oa), rdoa = dot(d, oa), oaoa = dot(oa, oa);
  // The entry root of each part (planted fault: the exit root, the far side of the fiber).
  float sgn = FT_FAULT_VOL_CAPSULE_EXIT_ON ? 1.0f : -1.0f;
  float best = -1.0f;
  // Lateral surface: |(oa + t d) ⊥ ba|² = r², multiplied through by |ba|².
  float qa = baba * dd - bard * bard, qb = baba * rdoa - baoa * bard, qc = baba * oaoa - baoa * baoa - r * r * baba;
  float disc = qb * qb - qa * qc;
  if (qa > 1e-12f * baba * dd && disc >= 0.0f) {
    float t = (-qb + sgn * sqrt(disc)) / qa;
    float y = baoa + t * bard;  // axial coordinate × |ba|²
    if (tc + t >= 0.0f && y >= 0.0f && y <= baba) best = tc + t;
  }
  // End spheres (centre a, then b).
  for (int e = 0; e < 2; ++e) {
    vec3 oc = e == 0 ? oa : o - b;
    float sb = dot(oc, d), sc = dot(oc, oc) - r * r;
    float sdisc = sb * sb - dd * sc;
    if (sdisc < 0.0f) continue;
    float t = tc + (-sb + sgn * sqrt(sdisc)) / dd;
    if (t >= 0.0f && (best < 0.0f || t < best)) best = t;
  }
  return best;
}

// The cell walk: a voxel v (unwrapped) of the current candidate cell, the
// cell's entry parameter t, and per axis the parameter where the ray leaves
// the cell through its face in the step direction. Cells are grid.w voxels a
// side from each period's start, the last of a period (and of the slab in z)
// partial when the count is not a multiple; each face's parameter is computed
// from the ray afresh (no accumulated increments).
struct VolWalk {
  ivec3 v;
  float t;
  vec3 tMax;
  ivec3 step;
};

// The face coordinate (in voxels, unwrapped) of the cell of voxel v on one
// axis, in the step direction dir: periodic (x, y: cells restart every n
// voxels) or not (z).
FT_FUNC int ftVolCellFace(int v, int dir, int n, int B, bool periodic) {
  int w = periodic ? ftVolWrap(v, n) : v;
  int lo = (w / B) * B;
  int hi = min(lo + B, n);
  return v - w + (dir > 0 ? hi : lo);
}

// Parameter at which the ray reaches voxel coordinate f on axis a.
FT_FUNC float ftVolFaceT(vec3 o, vec3 d, int a, int f, VolParams p) {
  float oa = a == 0 ? o.x : (a == 1 ? o.y : o.z);
  float da = a == 0 ? d.x : (a == 1 ? d.y : d.z);
  float ga = a == 0 ? p.origin.x : (a == 1 ? p.origin.y : p.origin.z);
  return (ga + float(f) * p.origin.w - oa) / da;
}

FT_FUNC float ftVolWalkFaceT(vec3 o, vec3 d, int a, ivec3 v, ivec3 step, VolParams p) {
  int st = a == 0 ? step.x : (a == 1 ? step.y : step.z);
  if (st == 0) return 3.0e38f;
  int va = a == 0 ? v.x : (a == 1 ? v.y : v.z);
  int n = int(a == 0 ? p.dims.x : (a == 1 ? p.dims.y : p.dims.z));
  return ftVolFaceT(o, d, a, ftVolCellFace(va, st, n, int(p.grid.w), a < 2), p);
}

// The walk from the slab entry t0 (the start voxel's k clamped into the slab:
// a point on a face may round to just outside it).
FT_FUNC VolWalk ftVolWalkBegin(vec3 o, vec3 d, float t0, VolParams p) {
  VolWalk w;
  vec3 c = (o + t0 * d - vec3(p.origin.x, p.origin.y, p.origin.z)) / p.origin.w;
  w.v = ivec3(int(floor(c.x)), int(floor(c.y)), int(floor(c.z)));
  w.v.z = min(max(w.v.z, 0), int(p.dims.z) - 1);
  w.t = t0;
  w.step = ivec3(d.x > 0.0f ? 1 : (d.x < 0.0f ? -1 : 0), d.y > 0.0f ? 1 : (d.y < 0.0f ? -1 : 0),
                 d.z > 0.0f ? 1 : (d.z < 0.0f ? -1 : 0));
  w.tMax = vec3(ftVolWalkFaceT(o, d, 0, w.v, w.step, p), ftVolWalkFaceT(o, d, 1, w.v, w.step, p),
                ftVolWalkFaceT(o, d, 2, w.v, w.step, p));
  return w;
}

// The next cell: across the nearest face (v moves to the first voxel beyond it).
FT_FUNC VolWalk ftVolWalkNext(vec3 o, vec3 d, VolWalk w, VolParams p) {
  int a = (w.tMax.x <= w.tMax.y && w.tMax.x <= w.tMax.z) ? 0 : (w.tMax.y <= w.tMax.z ? 1 : 2);
  int B = int(p.grid.w);
  if (a == 0) {
    w.t = w.tMax.x;
    int f = ftVolCellFace(w.v.x, w.step.x, int(p.dims.x), B, true);
    w.v.x = w.step.x > 0 ? f : f - 1;
    w.tMax.x = ftVolWalkFaceT(o, d, 0, w.v, w.step, p);
  } else if (a == 1) {
    w.t = w.tMax.y;
    int f = ftVolCellFace(w.v.y, w.step.y, int(p.dims.y), B, true);
    w.v.y = w.step.y > 0 ? f : f - 1;
    w.tMax.y = ftVolWalkFaceT(o, d, 1, w.v, w.step, p);
  } else {
    w.t = w.tMax.z;
    int f = ftVolCellFace(w.v.z, w.step.z, int(p.dims.z), B, false);
    w.v.z = w.step.z > 0 ? f : f - 1;
    w.tMax.z = ftVolWalkFaceT(o, d, 2, w.v, w.step, p);
  }
  return w;
}

// Whole periods between an unwrapped voxel index and its wrapped one
// ((i − wrap(i)) / n, exact; non-negative divisions only).
FT_FUNC int ftVolPeriodsOf(int i, int n) {
  int m = i - ftVolWrap(i, n);
  return m >= 0 ? m / n : -((-m) / n);
}

// The GPU volume buffer (gpu/exemplar_volume_gpu.h): nx·ny·nz ids, then the
// candidate lists (cells + 1 offsets, then the entries), then the segment
// table as 8 words per segment (VolSegment's a, b as float bits). The
// offsets' base and the segment table's:
FT_FUNC uint ftVolCandidateBase(VolParams p) { return p.dims.x * p.dims.y * p.dims.z; }
FT_FUNC uint ftVolCellCount(VolParams p) { return p.grid.x * p.grid.y * p.grid.z; }

// The candidate cell of a wrapped voxel (cells of grid.w³ voxels).
FT_FUNC uint ftVolCellOf(ivec3 wrapped, VolParams p) {
  uint B = p.grid.w;
  return (uint(wrapped.z) / B * p.grid.y + uint(wrapped.y) / B) * p.grid.x + uint(wrapped.x) / B;
}

FT_NAMESPACE_END
#endif  // FT_EXEMPLAR_VOLUME_H
