// Both paths' fragment stage. Two outputs, chosen by `shaded`:
//  * 0: the preview of the harness thumbnails — a Kajiya–Kay style highlight
//    from a headlight and a round-fiber falloff across the strip (RGBA8);
//  * 1: the fiber shading of Wu & Yuksel 2019 §4.3 (common/fiber_shading.h):
//    the shared BCSDF per directional light plus the ambient table, in linear
//    HDR radiance (a float target), alpha 1 for coverage.
// The strip stands for a round fiber: across it (a ∈ [−1, 1]) the surface
// normal turns from the side vector through the view direction, n = a·side +
// √(1 − a²)·v⊥, which is what a ray hitting the tube there sees (the Embree
// ground truth, reference/fiber_trace.cpp).
//
// Depth: a flat camera-facing strip has the depth of its centre line across
// its whole width, so where two thick strips cross (the plies of a twisted
// yarn, a core inside its ply) the nearer centre line wins over the full
// width and the crossing shows as a straight cut. Each fragment is moved
// towards the eye to the surface of the round fiber the strip stands for
// (by halfWidth·sqrt(1 − a²) at a across the strip), so crossings are the
// curved intersections of tubes.
#include "common/constants.h"
#include "common/fiber_shading.h"
#include "common/view_params.h"

layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(std140, binding = FT_UBO_SHADING) uniform ShadingBlock { ShadingParams shading; };
layout(std430, binding = FT_SSBO_AMBIENT_TABLE) readonly buffer AmbientTable { vec4 ambientTable[]; };
layout(location = 0) in vec3 stripTangent;
layout(location = 1) in float stripAcross;
layout(location = 2) flat in uint stripType;
layout(location = 3) in vec3 stripWorld;
layout(location = 4) in float stripHalfWidth;
layout(location = 0) out vec4 color;

uniform uint shaded;
uniform vec3 lightDir;
uniform vec3 baseColor;

vec3 shadeFiber(vec3 t, vec3 surface) {
  vec3 v = normalize(view.cameraPos.xyz - surface);
  vec3 vPerp = v - dot(v, t) * t;
  float lp = length(vPerp);
  vPerp = lp > 0.0 ? vPerp / lp : v;
  vec3 side = cross(t, vPerp);  // the geometry stage's side vector, unit
  float a = clamp(stripAcross, -1.0, 1.0);
#ifdef FT_FAULT_SHADE_FLAT_NORMAL
  vec3 n = vPerp;  // the flat strip's normal: the fiber loses its roundness
#else
  vec3 n = a * side + sqrt(max(1.0 - a * a, 0.0)) * vPerp;
#endif
  vec3 radiance = vec3(0.0);
  for (int i = 0; i < int(shading.flags.x) && i < FT_MAX_LIGHTS; ++i) radiance += ftFiberDirect(shading, i, t, n, v);
  FiberAngles o = ftFiberAngles(t, v, v);
  vec3 k = ftAmbientLookup(o.thetaO, FT_AMBIENT_TABLE_SIZE);
  vec3 table = mix(ambientTable[int(k.x)].xyz, ambientTable[int(k.y)].xyz, k.z);
  return radiance + ftFiberAmbient(shading, table);
}

void main() {
  vec3 t = normalize(stripTangent);
  float round_ = sqrt(max(1.0 - stripAcross * stripAcross, 0.0));
  vec3 surface = stripWorld + normalize(view.cameraPos.xyz - stripWorld) * (stripHalfWidth * round_);
  if (shaded != 0u) {
    color = vec4(shadeFiber(t, surface), 1.0);
  } else {
    float ct = dot(t, normalize(lightDir));
    float diffuse = sqrt(max(1.0 - ct * ct, 0.0));
    vec3 tint = stripType == FT_FIBER_CORE ? baseColor * 0.7 : baseColor;
    color = vec4(tint * (0.25 + 0.75 * diffuse) * (0.5 + 0.5 * round_), 1.0);
  }
  vec4 clip = view.viewProj * vec4(surface, 1.0);
  gl_FragDepth = clamp(0.5 * (clip.z / clip.w) + 0.5, 0.0, 1.0);
}
