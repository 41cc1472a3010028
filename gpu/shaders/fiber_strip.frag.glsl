// Both paths' fragment stage. The camera-facing strip stands for a round
// fiber: each fragment casts the eye ray through itself against the tube
// around its line (radius = the strip's half-width) and takes the hit as the
// fiber's surface there — its depth, its position along the line (which
// mixes the two vertex tangents) and its normal. This is what the Embree
// ground truth computes (reference/fiber_trace.cpp). Interpolating tangent
// and "across" over the strip quad instead is wrong by degrees wherever the
// quad is not a parallelogram (its two triangles interpolate differently),
// which moved the 1°-wide highlights of silk and cotton by pixels.
// Crossing tubes (plies, a core inside its ply) intersect where tubes do.
//
// Two outputs, chosen by `shaded`:
//  * 0: the preview of the harness thumbnails — a Kajiya–Kay style highlight
//    from a headlight and a round-fiber falloff across the strip (RGBA8);
//  * 1: the fiber shading of Wu & Yuksel 2019 §4.3 (common/fiber_shading.h):
//    the shared BCSDF per directional light plus the ambient table, in linear
//    HDR radiance (a float target), alpha 1 for coverage.
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
layout(location = 5) flat in vec3 lineP0;
layout(location = 6) flat in vec3 lineP1;
layout(location = 7) flat in vec3 lineT0;
layout(location = 8) flat in vec3 lineT1;
layout(location = 9) flat in vec2 lineHalfWidth;
layout(location = 0) out vec4 color;

uniform uint shaded;
uniform vec3 lightDir;
uniform vec3 baseColor;

struct TubeHit {
  vec3 position;
  vec3 tangent;
  vec3 normal;
};

// The eye ray through this fragment against the cylinder around the line
// with the half-width at the fragment's place along it. A ray that grazes
// past the cylinder (the strip's edge pixels: the strip is as wide as the
// tube's silhouette, up to rasterisation) takes its closest approach.
TubeHit castTube() {
  vec3 eye = view.cameraPos.xyz;
  vec3 d = normalize(stripWorld - eye);
  vec3 axis = lineP1 - lineP0;
  float len2 = max(dot(axis, axis), 1e-30);
  vec3 a = axis * inversesqrt(len2);
  float u = clamp(dot(stripWorld - lineP0, axis) / len2, 0.0, 1.0);
  float r = mix(lineHalfWidth.x, lineHalfWidth.y, u);
  vec3 m = eye - lineP0;
  vec3 dp = d - dot(d, a) * a, mp = m - dot(m, a) * a;
  float qa = max(dot(dp, dp), 1e-30), qb = dot(dp, mp), qc = dot(mp, mp) - r * r;
  float s = (-qb - sqrt(max(qb * qb - qa * qc, 0.0))) / qa;
  TubeHit h;
  h.position = eye + s * d;
  u = clamp(dot(h.position - lineP0, axis) / len2, 0.0, 1.0);
  vec3 t = mix(lineT0, lineT1, u);
  h.tangent = dot(t, t) > 0.0 ? normalize(t) : a;
  vec3 radial = h.position - (lineP0 + u * axis);
  radial -= dot(radial, h.tangent) * h.tangent;
  h.normal = dot(radial, radial) > 0.0 ? normalize(radial) : -d;
#ifdef FT_FAULT_SHADE_FLAT_NORMAL
  vec3 toEye = -d - dot(-d, h.tangent) * h.tangent;
  h.normal = normalize(toEye);  // the flat strip's normal: the fiber loses its roundness
#endif
  return h;
}

vec3 shadeFiber(TubeHit h) {
  vec3 v = normalize(view.cameraPos.xyz - h.position);
  vec3 radiance = vec3(0.0);
  for (int i = 0; i < int(shading.flags.x) && i < FT_MAX_LIGHTS; ++i)
    radiance += ftFiberDirect(shading, i, h.tangent, h.normal, v);
  FiberAngles o = ftFiberAngles(h.tangent, v, v);
  vec3 k = ftAmbientLookup(o.thetaO, FT_AMBIENT_TABLE_SIZE);
  vec3 table = mix(ambientTable[int(k.x)].xyz, ambientTable[int(k.y)].xyz, k.z);
  return radiance + ftFiberAmbient(shading, table);
}

void main() {
  TubeHit h = castTube();
  if (shaded != 0u) {
    color = vec4(shadeFiber(h), 1.0);
  } else {
    float ct = dot(h.tangent, normalize(lightDir));
    float diffuse = sqrt(max(1.0 - ct * ct, 0.0));
    float round_ = sqrt(max(1.0 - stripAcross * stripAcross, 0.0));
    vec3 tint = stripType == FT_FIBER_CORE ? baseColor * 0.7 : baseColor;
    color = vec4(tint * (0.25 + 0.75 * diffuse) * (0.5 + 0.5 * round_), 1.0);
  }
  vec4 clip = view.viewProj * vec4(h.position, 1.0);
  gl_FragDepth = clamp(0.5 * (clip.z / clip.w) + 0.5, 0.0, 1.0);
}
