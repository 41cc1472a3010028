// The third pass of the shaded frame (001 §5.2: "shadow, regular shading, and
// flyaway shading"): the flyaway textures (common/flyaway.h) on camera-facing
// strips of half-width W_fly along each yarn. No vertex input and no geometry
// stage (llvmpipe runs geometry shaders slowly; shadow_map.vert.glsl does the
// same): six vertices per piece, piece k the sub-segment k % FT_FLYAWAY_PIECES
// of yarn segment k / FT_FLYAWAY_PIECES. The strip is moved toward the eye by
// the regular fibers' reach W, to the front of its own yarn (the bake already
// dropped flyaways hidden by it, 001 §4.4), so the depth test keeps what lies
// behind other yarns' nearer fibers hidden (docs/flyaways.md).
#include "shaders/fiber_resources.glsl"
#include "common/flyaway.h"

layout(std140, binding = FT_UBO_FLYAWAY) uniform FlyawayBlock { FlyawayParams fly; };
layout(location = 0) out vec3 flyWorld;      // the strip point before the push toward the eye
layout(location = 1) out vec2 flySV;         // s (yarn length coordinate), v ∈ [−1, 1] across
layout(location = 2) flat out vec3 flyAxis;  // the piece's unit direction
layout(location = 3) flat out uint flyCurve;

void main() {
  uint piece = uint(gl_VertexID) / 6u;
  uint corner = uint(gl_VertexID) % 6u;
  uint segment = piece / FT_FLYAWAY_PIECES;
  uint sub = piece % FT_FLYAWAY_PIECES;
  SegmentRef ref = segmentRefs[segment];
  CurveInfo c = curves[ref.curve];
  YarnSegment s = fetchSegment(c, ref.local);
  float t0 = float(sub) / float(FT_FLYAWAY_PIECES), t1 = float(sub + 1u) / float(FT_FLYAWAY_PIECES);
  vec3 a = ftBezierPoint(s, t0), b = ftBezierPoint(s, t1);
  vec3 d = b - a;
  vec3 axis = dot(d, d) > 0.0 ? d / length(d) : vec3(1.0, 0.0, 0.0);
  const uvec2 kCorner[6] = uvec2[6](uvec2(0u, 0u), uvec2(1u, 0u), uvec2(0u, 1u), uvec2(0u, 1u), uvec2(1u, 0u),
                                    uvec2(1u, 1u));
  uvec2 k = kCorner[corner];
  vec3 p = k.x == 0u ? a : b;
  vec3 toEye = normalize(view.cameraPos.xyz - p);
  vec3 side = cross(axis, toEye);
  side = dot(side, side) > 1e-12 ? normalize(side) : vec3(0.0, 1.0, 0.0);
  float v = k.y == 0u ? -1.0 : 1.0;
  vec3 q = p + v * fly.halfWidth * side;
  flyWorld = q;
  flySV = vec2(mix(s.s0, s.s1, k.x == 0u ? t0 : t1), v);
  flyAxis = axis;
  flyCurve = ref.curve;
  vec3 pushed = q + normalize(view.cameraPos.xyz - q) * fly.bodyRadius;
  gl_Position = view.viewProj * vec4(pushed, 1.0);
}
