// Eye rays by volume sampling, 004 §5.1 (common/exemplar_volume.h,
// gpu/exemplar_volume_gpu.h): one invocation per pixel; the ray is clipped to
// the slab and sampled at N linearly spaced sample centres; the first sample
// in a non-empty voxel writes (flat-space point, id) to the G-buffer
// (FT_SSBO_PRT_RESULTS), none writes a miss (id 0). Capsule ids
// (vol.camDir.w = FT_VOL_IDS_CAPSULE): the walk over the candidate cells,
// the exact test of their candidates (held after the ids in the volume
// buffer, ftVolCandidateBase), the nearest hit (the CPU's sampleCapsules).
#include "common/constants.h"
#include "common/exemplar_volume.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_VOL) in;
layout(std140, binding = FT_UBO_PRT_VOL) uniform VolBlock { VolParams vol; };
layout(std430, binding = FT_SSBO_PRT_VOL_IDS) readonly buffer VolIds { uint ids[]; };
layout(std430, binding = FT_SSBO_PRT_RESULTS) writeonly buffer VolGbuffer { VolHit gbuffer[]; };

// Segment k of the table after the candidate lists (8 words each).
vec4 volSegmentWord4(uint base, uint k, uint part) {
  uint w = base + 8u * k + 4u * part;
  return uintBitsToFloat(uvec4(ids[w], ids[w + 1u], ids[w + 2u], ids[w + 3u]));
}
uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint item = flatInvocationIndex(groupsX, FT_WG_PRT_VOL);
  if (item >= itemCount) return;
  uint x = item % vol.ray.x, y = item / vol.ray.x;
  vec3 o = ftVolRayOrigin(vol, x, y), d = ftVolRayDirection(vol, x, y);
  float zLo = vol.origin.z, zHi = vol.origin.z + float(vol.dims.z) * vol.origin.w;
  vec2 t = ftVolSlabInterval(o, d, zLo, zHi);
  VolHit hit;
  hit.point = vec3(0.0f);
  hit.id = 0u;
  uint n = vol.ray.z;
  if (t.x <= t.y && ftVolIdMode(vol) == FT_VOL_IDS_CAPSULE) {
    int nx = int(vol.dims.x), ny = int(vol.dims.y), nz = int(vol.dims.z);
    float P = ftVolPeriod(vol);
    uint cells = ftVolCellCount(vol), cbase = ftVolCandidateBase(vol);
    uint sbase = cbase + cells + 1u + ids[cbase + cells];
    float best = -1.0f;
    uint bestId = 0u;
    VolWalk w = ftVolWalkBegin(o, d, t.x, vol);
    for (uint step = 0u; step < FT_VOL_MAX_STEPS; ++step, w = ftVolWalkNext(o, d, w, vol)) {
      if (w.v.z < 0 || w.v.z >= nz || w.t > t.y || (best >= 0.0f && w.t > best)) break;
      ivec3 wv = ivec3(ftVolWrap(w.v.x, nx), ftVolWrap(w.v.y, ny), w.v.z);
      int cell = int(ftVolCellOf(wv, vol)), sx = ftVolPeriodsOf(w.v.x, nx), sy = ftVolPeriodsOf(w.v.y, ny);
#ifdef FT_FAULT_VOL_CAPSULE_NO_SHIFT
      vec3 os = o;  // planted: the candidates tested in the block's own frame, whatever tile the cell is in
#else
      vec3 os = o - vec3(float(sx) * P, float(sy) * P, 0.0f);
#endif
      for (uint e = ids[cbase + uint(cell)]; e < ids[cbase + uint(cell) + 1u]; ++e) {
        uint entry = ids[cbase + cells + 1u + e];
        uint k = entry / FT_VOL_COPIES, c = entry % FT_VOL_COPIES;
        vec3 off = ftVolCopyOffset(c, P);
        vec4 a = volSegmentWord4(sbase, k, 0u), b = volSegmentWord4(sbase, k, 1u);
        float th = ftVolRayCapsule(os, d, a.xyz + off, b.xyz + off, a.w);
        if (th < 0.0f) continue;
        if (best < 0.0f || th < best || (th == best && k + 1u < bestId)) {
          best = th;
          bestId = k + 1u;
        }
      }
#ifdef FT_FAULT_VOL_CAPSULE_FIRST_CELL
      if (bestId != 0u) break;  // planted: the first cell with a hit ends the walk, nearer hits beyond it unseen
#endif
    }
    if (bestId != 0u) {
      hit.point = o + best * d;
      hit.id = bestId;
    }
  } else if (t.x <= t.y) {
    for (uint i = 0u; i < n; ++i) {
#ifdef FT_FAULT_VOL_SAMPLE_ENDPOINTS
      float ti = t.x + (float(i) + 0.5f) * ((t.y - t.x) / float(max(n, 2u) - 1u));  // planted: step (t1 − t0)/(N − 1)
#else
      float ti = ftVolSampleT(t.x, t.y, i, n);
#endif
      int idx = ftVolSampleIndex(o, d, ti, vol);
      if (idx >= 0 && ids[uint(idx)] != 0u) {
        hit.point = o + ti * d;
        hit.id = ids[uint(idx)];
        break;
      }
    }
  }
  gbuffer[item] = hit;
}
