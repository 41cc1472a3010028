// Yarn shadow map depth pass (000 §4.1, common/shadow_map.h): no vertex
// input and no geometry stage (llvmpipe runs geometry shaders slowly): six
// vertices (two triangles) per tube piece. Piece k is sub-segment
// k % FT_SHADOW_MAP_SUBSEGMENTS of yarn segment k / FT_SHADOW_MAP_SUBSEGMENTS,
// evaluated from the FiberGpu's yarn buffers (the Bézier form of the
// Catmull-Rom segment); fibers are ignored. The rectangle covers the piece's
// light-space footprint (its projection ± R, widened by a texel so every
// covered texel centre gets a fragment); the fragment stage ray-casts the
// piece along the light and writes its far side.
#include "shaders/fiber_resources.glsl"
#include "common/shadow_map.h"

layout(std140, binding = FT_UBO_SHADOW_MAP) uniform ShadowBlock { ShadowMapParams shadowMap; };
layout(location = 0) flat out vec3 capsuleA;  // light space
layout(location = 1) flat out vec3 capsuleB;
layout(location = 2) out vec2 rayXY;          // light-space x, y of this fragment's ray
layout(location = 3) flat out uint capsuleCaps;  // bit 0: the yarn starts at A, bit 1: it ends at B

uniform int lightIndex;

float tubeRadius() {
#ifdef FT_FAULT_SHADOW_MAP_PLY_RADIUS
  return shadowMap.tube.y;  // the ply's radius: the tube misses the plies' own extent
#else
  return shadowMap.tube.x;
#endif
}

void main() {
  uint piece = uint(gl_VertexID) / 6u;
  uint corner = uint(gl_VertexID) % 6u;
  uint segment = piece / FT_SHADOW_MAP_SUBSEGMENTS;
  uint sub = piece % FT_SHADOW_MAP_SUBSEGMENTS;
  SegmentRef ref = segmentRefs[segment];
  CurveInfo c = curves[ref.curve];
  YarnSegment s = fetchSegment(c, ref.local);
  bool open = c.closed == 0u;
  capsuleCaps = (open && ref.local == 0u && sub == 0u ? 1u : 0u) |
                (open && ref.local + 1u == ftCurveSegmentCount(c) && sub + 1u == FT_SHADOW_MAP_SUBSEGMENTS ? 2u : 0u);
  vec3 a = ftShadowLightSpace(shadowMap, lightIndex, ftBezierPoint(s, float(sub) / float(FT_SHADOW_MAP_SUBSEGMENTS)));
  vec3 b = ftShadowLightSpace(shadowMap, lightIndex,
                              ftBezierPoint(s, float(sub + 1u) / float(FT_SHADOW_MAP_SUBSEGMENTS)));
  capsuleA = a;
  capsuleB = b;
  float r = tubeRadius(), texel = shadowMap.extent.z;
  float grow = r + texel;
  vec2 d = b.xy - a.xy;
  float len = length(d);
  vec2 along = len > 1e-12 * shadowMap.extent.x ? d / len : vec2(1.0, 0.0);
  vec2 across = vec2(-along.y, along.x);
  // Along the axis a piece without a cap ends in the disc ⟂ the axis, whose
  // projection reaches r·|cos γ| past the end point (γ: axis to light): the
  // rectangle stops there, so consecutive pieces barely overlap; a capped end
  // needs the ball's r.
  float l3 = length(b - a);
  float endReach = (l3 > 0.0 ? r * abs(b.z - a.z) / l3 : r) + texel;
  float growA = (capsuleCaps & 1u) != 0u ? grow : endReach;
  float growB = (capsuleCaps & 2u) != 0u ? grow : endReach;
  // Corners (end, side) of the two triangles: (0,0) (1,0) (0,1) | (0,1) (1,0) (1,1).
  const uvec2 kCorner[6] = uvec2[6](uvec2(0u, 0u), uvec2(1u, 0u), uvec2(0u, 1u), uvec2(0u, 1u), uvec2(1u, 0u),
                                    uvec2(1u, 1u));
  uvec2 k = kCorner[corner];
  vec2 p = (k.x == 0u ? a.xy - growA * along : b.xy + growB * along) + (k.y == 0u ? -grow : grow) * across;
  rayXY = p;
  // Depth is written per fragment; z here only has to lie inside the clip volume.
  gl_Position = vec4(p / shadowMap.extent.x, 0.0, 1.0);
}
