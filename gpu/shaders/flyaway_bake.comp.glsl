// The three flyaway textures of 001 §4.4 (FlyawayGpu::bake): one invocation
// per texel of each layer finds the nearest drawn segment of B (at z and
// z + P) and I_k over the curves FlyawayGpu::generate wrote, drops it when it
// lies behind the regular fibers (the paper's pass-1 depth stencil), and
// packs the tangent as RGBA8 (common/flyaway.h).
#include "common/constants.h"
#include "common/flyaway.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_FLYAWAY) in;
layout(std140, binding = FT_UBO_FLYAWAY) uniform FlyawayBlock { FlyawayParams fly; };
layout(std430, binding = FT_SSBO_FLYAWAY_POINTS) readonly buffer FlyawayPoints { vec4 points[]; };
layout(std430, binding = FT_SSBO_FLYAWAY_HEADERS) readonly buffer FlyawayHeaders { vec4 headers[]; };
layout(std430, binding = FT_SSBO_FLYAWAY_TEXELS) writeonly buffer FlyawayTexels { uint texels[]; };
uniform uint groupsX;

void main() {
  uint index = flatInvocationIndex(groupsX, FT_WG_FLYAWAY);
  uint perLayer = fly.width * fly.height;
  if (index >= FT_FLYAWAY_LAYERS * perLayer) return;
  uint layer = index / perLayer;
  uint i = index % fly.width;
  uint j = (index % perLayer) / fly.width;
  vec2 q = ftFlyawayTexelYZ(fly, i, j);
  bool found = false;
  float bestX = 0.0;
  vec3 bestA = vec3(0.0), bestB = vec3(0.0);
  for (uint pass = 0u; pass < 2u; ++pass) {
    uint set = pass == 0u ? 0u : layer + 1u;
    for (uint slot = 0u; slot < fly.maxPerSet; ++slot) {
      uint c = ftFlyawaySlot(fly, 0u, set, slot);
      if (headers[c].y == 0.0) continue;
      for (uint shift = 0u; shift < ftFlyawayShiftCount(set); ++shift) {
        vec3 dz = vec3(0.0, 0.0, float(shift) * fly.period);
        for (uint k = 0u; k < FT_FLYAWAY_STEPS; ++k) {
          vec3 a = points[c * FT_FLYAWAY_POINTS + k].xyz + dz;
          vec3 b = points[c * FT_FLYAWAY_POINTS + k + 1u].xyz + dz;
          vec2 h = ftFlyawaySegmentHit(a, b, q, fly.lineHalfWidth);
          if (h.x != 0.0 && (!found || h.y > bestX)) {
            found = true;
            bestX = h.y;
            bestA = a;
            bestB = b;
          }
        }
      }
    }
  }
#ifdef FT_FAULT_FLYAWAY_GPU_NO_OCCLUSION
  bool hidden = false;  // planted: the depth stencil of the regular fibers ignored
#else
  bool hidden = found && ftFlyawayHidden(fly, q.x, bestX);
#endif
  texels[index] = (found && !hidden) ? packUnorm4x8(ftFlyawayTexel(bestA, bestB)) : 0u;
}
