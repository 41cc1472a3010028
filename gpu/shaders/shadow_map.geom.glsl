// Yarn shadow map depth pass: one light-facing rectangle per tube capsule
// (radius R_tube, common/shadow_map.h) into layer `lightIndex` of the map; it
// covers the capsule's light-space footprint (the segment's projection ± R,
// widened by a texel so every covered texel centre gets a fragment); the
// fragment stage ray-casts the capsule along the light and writes its far
// side.
#include "common/constants.h"
#include "common/shadow_map.h"

layout(points) in;
layout(triangle_strip, max_vertices = 4) out;
layout(std140, binding = FT_UBO_SHADOW_MAP) uniform ShadowBlock { ShadowMapParams shadowMap; };
layout(location = 0) in vec3 tubeA[];
layout(location = 1) in vec3 tubeB[];
layout(location = 2) flat in uint tubeCaps[];
layout(location = 0) flat out vec3 capsuleA;  // light space
layout(location = 1) flat out vec3 capsuleB;
layout(location = 2) out vec2 rayXY;          // light-space x, y of this fragment's ray
layout(location = 3) flat out uint capsuleCaps;

uniform int lightIndex;

float tubeRadius() {
#ifdef FT_FAULT_SHADOW_MAP_PLY_RADIUS
  return shadowMap.tube.y;  // the ply's radius: the tube misses the plies' own extent
#else
  return shadowMap.tube.x;
#endif
}

void main() {
  vec3 a = ftShadowLightSpace(shadowMap, lightIndex, tubeA[0]);
  vec3 b = ftShadowLightSpace(shadowMap, lightIndex, tubeB[0]);
  float r = tubeRadius();
  float grow = r + shadowMap.extent.z;
  vec2 d = b.xy - a.xy;
  float len = length(d);
  vec2 along = len > 1e-12 * shadowMap.extent.x ? d / len : vec2(1.0, 0.0);
  vec2 across = vec2(-along.y, along.x);
  vec2 corners[4] = vec2[4](a.xy - grow * along - grow * across, a.xy - grow * along + grow * across,
                             b.xy + grow * along - grow * across, b.xy + grow * along + grow * across);
  for (int k = 0; k < 4; ++k) {
    capsuleA = a;
    capsuleB = b;
    capsuleCaps = tubeCaps[0];
    rayXY = corners[k];
    // Depth is written per fragment; z here only has to lie inside the clip volume.
    gl_Position = vec4(corners[k] / shadowMap.extent.x, 0.0, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
