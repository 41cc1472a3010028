// Eye rays by volume sampling, 004 §5.1 (common/exemplar_volume.h,
// gpu/exemplar_volume_gpu.h): one invocation per pixel; the ray is clipped to
// the slab and sampled at N linearly spaced sample centres; the first sample
// in a non-empty voxel writes (flat-space point, id) to the G-buffer
// (FT_SSBO_PRT_RESULTS), none writes a miss (id 0).
#include "common/constants.h"
#include "common/exemplar_volume.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_VOL) in;
layout(std140, binding = FT_UBO_PRT_VOL) uniform VolBlock { VolParams vol; };
layout(std430, binding = FT_SSBO_PRT_VOL_IDS) readonly buffer VolIds { uint ids[]; };
layout(std430, binding = FT_SSBO_PRT_RESULTS) writeonly buffer VolGbuffer { VolHit gbuffer[]; };
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
  if (t.x <= t.y) {
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
