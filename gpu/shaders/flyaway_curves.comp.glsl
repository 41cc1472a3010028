// Flyaway curves of 001 §4.4 eq. 12–13 (FlyawayGpu::generate): one invocation
// per slot (pattern, set, slot) runs the shared generator of common/flyaway.h,
// as reference/flyaway.cpp does on the CPU.
#include "common/constants.h"
#include "common/flyaway.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_FLYAWAY) in;
layout(std140, binding = FT_UBO_FLYAWAY) uniform FlyawayBlock { FlyawayParams fly; };
layout(std430, binding = FT_SSBO_FLYAWAY_POINTS) writeonly buffer FlyawayPoints { vec4 points[]; };
layout(std430, binding = FT_SSBO_FLYAWAY_HEADERS) writeonly buffer FlyawayHeaders { vec4 headers[]; };
uniform uint groupsX;

void main() {
  uint index = flatInvocationIndex(groupsX, FT_WG_FLYAWAY);
  if (index >= fly.patterns * FT_FLYAWAY_SETS * fly.maxPerSet) return;
  uint slot = index % fly.maxPerSet;
  uint set = (index / fly.maxPerSet) % FT_FLYAWAY_SETS;
  uint pattern = index / (fly.maxPerSet * FT_FLYAWAY_SETS);
  uint count = ftFlyawayCount(fly, pattern, set);
  FlyawayShape s = ftFlyawayShape(fly, pattern, set, slot, count);
  if (s.present == 0u) {
    for (uint k = 0u; k < FT_FLYAWAY_POINTS; ++k) points[index * FT_FLYAWAY_POINTS + k] = vec4(0.0);
    headers[index] = vec4(0.0);
    return;
  }
  FlyawayWalk w = ftFlyawayWalkStart(s, fly.alpha);
  vec3 p = ftFlyawayWalkPoint(fly, w);
  float zMin = p.z, zMax = p.z;
  points[index * FT_FLYAWAY_POINTS] = vec4(p, 0.0);
  for (uint k = 1u; k <= FT_FLYAWAY_STEPS; ++k) {
    w = ftFlyawayWalkStep(fly, s, pattern, set, slot, k, w);
    p = ftFlyawayWalkPoint(fly, w);
    zMin = min(zMin, p.z);
    zMax = max(zMax, p.z);
    points[index * FT_FLYAWAY_POINTS + k] = vec4(p, float(k) / float(FT_FLYAWAY_STEPS));
  }
  headers[index] = vec4(1.0, float(ftFlyawayKept(fly, set, zMin, zMax)), zMin, zMax);
}
