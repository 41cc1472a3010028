// The ID volume of the exemplar of 004 §5.1 (common/exemplar_volume.h,
// gpu/exemplar_volume_gpu.h): one invocation per voxel, brute force over the
// candidate list of the voxel's cell (FT_SSBO_PRT_REQUESTS: the cells + 1
// offsets, then the entries segment · 9 + copy): among the capsules that
// touch the voxel (the conservative box test), the nearest midpoint; 0 empty.
// The ties rule (the lower segment index on equal keys) makes the result
// independent of the list's order, as on the CPU.
#include "common/constants.h"
#include "common/exemplar_volume.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_VOL) in;
layout(std140, binding = FT_UBO_PRT_VOL) uniform VolBlock { VolParams vol; };
layout(std430, binding = FT_SSBO_PRT_VOL_SEGMENTS) readonly buffer VolSegments { VolSegment segs[]; };
layout(std430, binding = FT_SSBO_PRT_REQUESTS) readonly buffer VolCandidates { uint cand[]; };
layout(std430, binding = FT_SSBO_PRT_VOL_IDS) writeonly buffer VolIds { uint ids[]; };
uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint item = flatInvocationIndex(groupsX, FT_WG_PRT_VOL);
  if (item >= itemCount) return;
  ivec3 v = ftVolVoxelOfIndex(item, vol.dims);
  vec3 centre = ftVolVoxelCentre(v, vol.origin);
  float h = vol.origin.w, P = ftVolPeriod(vol);
  vec3 lo = centre - 0.5f * h, hi = centre + 0.5f * h;
  uint B = vol.grid.w;
  uint cell = (uint(v.z) / B * vol.grid.y + uint(v.y) / B) * vol.grid.x + uint(v.x) / B;
  uint cells = vol.grid.x * vol.grid.y * vol.grid.z;
  uint first = cand[cell], last = cand[cell + 1u];
  uint best = 0u;
  float bestKey = 3.0e38f;
  for (uint e = first; e < last; ++e) {
    uint entry = cand[cells + 1u + e];
    uint k = entry / FT_VOL_COPIES, c = entry % FT_VOL_COPIES;
    vec3 off = ftVolCopyOffset(c, P);
    vec3 a = segs[k].a.xyz + off, b = segs[k].b.xyz + off;
    if (!ftVolSegmentTouchesBox(a, b, segs[k].a.w, lo, hi)) continue;
    float key = ftVolMidpointKey(centre, a, b);
    if (best == k + 1u) {
      bestKey = min(bestKey, key);
    } else if (key < bestKey || (key == bestKey && k + 1u < best)) {
      best = k + 1u;
      bestKey = key;
    }
  }
  ids[item] = best;
}
