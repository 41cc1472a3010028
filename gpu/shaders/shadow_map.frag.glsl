// Yarn shadow map depth pass: the capsule's far side along the light plus
// the slope bias (ftShadowCapsuleDepth, common/shadow_map.h) as the depth;
// rays that miss the capsule write nothing. The depth test (LESS) keeps the
// nearest far side among the capsules over a texel.
#include "common/constants.h"
#include "common/shadow_map.h"

layout(std140, binding = FT_UBO_SHADOW_MAP) uniform ShadowBlock { ShadowMapParams shadowMap; };
layout(location = 0) flat in vec3 capsuleA;
layout(location = 1) flat in vec3 capsuleB;
layout(location = 2) in vec2 rayXY;
layout(location = 3) flat in uint capsuleCaps;

float tubeRadius() {
#ifdef FT_FAULT_SHADOW_MAP_PLY_RADIUS
  return shadowMap.tube.y;  // the ply's radius (the vertex stage's rectangle shrinks with it)
#else
  return shadowMap.tube.x;
#endif
}

void main() {
  float z = ftShadowCapsuleDepth(capsuleA, capsuleB, tubeRadius(), rayXY, shadowMap.tube.z * shadowMap.extent.z,
                                 (capsuleCaps & 1u) != 0u, (capsuleCaps & 2u) != 0u);
  if (z == FT_SHADOW_MAP_MISS) discard;
  gl_FragDepth = clamp(ftShadowDepth(shadowMap, z), 0.0, 1.0);
}
