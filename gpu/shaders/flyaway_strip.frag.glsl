// The flyaway pass's fragment stage (flyaway_strip.vert.glsl): the layer of
// this period of the yarn (ftFlyawayLayer, constant over a period), the
// coverage interpolated bilinearly; below ¼ no flyaway (discarded); otherwise the stored
// tangent, taken from the strip frame (u along the yarn, v across, w toward
// the eye) to world space, shaded with the frame's BCSDF and ambient table
// (common/fiber_shading.h) like a regular fiber, without self-shadow, AO or
// the shadow map [F] (docs/flyaways.md).
#include "common/constants.h"
#include "common/bcsdf.h"
#include "common/fiber_shading.h"
#include "common/flyaway.h"
#include "common/view_params.h"

layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(std140, binding = FT_UBO_SHADING) uniform ShadingBlock { ShadingParams shading; };
layout(std430, binding = FT_SSBO_AMBIENT_TABLE) readonly buffer AmbientTable { vec4 ambientTable[]; };
layout(std430, binding = FT_SSBO_LOBE_NORM_TABLE) readonly buffer LobeNormTable { vec2 lobeNorm[]; };
layout(std140, binding = FT_UBO_FLYAWAY) uniform FlyawayBlock { FlyawayParams fly; };
layout(std430, binding = FT_SSBO_FLYAWAY_FRAME) readonly buffer FlyawayTexels { uint flyTexels[]; };
layout(location = 0) in vec3 flyWorld;
layout(location = 1) in vec2 flySV;
layout(location = 2) flat in vec3 flyAxis;
layout(location = 3) flat in uint flyCurve;
layout(location = 0) out vec4 color;

vec2 lobeNormsAt(FiberAngles a) {
  float theta = ftLobeNormAngle(a), betaR = shading.fabric.colorR.w, betaTT = shading.fabric.colorTT.w;
  vec4 r = ftLobeNormLookup(theta, betaR, FT_LOBE_NORM_TABLE_SIZE);
  vec4 t = ftLobeNormLookup(theta, betaTT, FT_LOBE_NORM_TABLE_SIZE);
  return vec2(ftLobeNormFromTable(r, theta, betaR, lobeNorm[int(r.x)].x, lobeNorm[int(r.y)].x),
              ftLobeNormFromTable(t, theta, betaTT, lobeNorm[int(t.x)].y, lobeNorm[int(t.y)].y));
}

void main() {
  float u = flySV.x / fly.period;
  float n = floor(u);
  uint layer = ftFlyawayLayer(flyCurve, int(n), fly.seed);
  // Coverage interpolated bilinearly and cut at ¼ (a line's outline instead
  // of whole texels: no staircase when a texel spans pixels; ¼, not ½, because
  // a line the bake drew half a texel wide may sit on alternate rows of
  // adjacent columns, where the interpolated coverage falls to ½), the tangent of
  // the covered texel with the largest weight. Along u the texel past the last
  // column is column 0 of the same layer: the first and last columns are the
  // boundary set's in every layer (common/flyaway.h), so this is the next
  // period's texel whichever layer that period draws.
  float x = max(u - n, 0.0) * float(fly.width) - 0.5, y = (0.5 * flySV.y + 0.5) * float(fly.height) - 0.5;
  float fx = x - floor(x), fy = y - floor(y);
  int i0 = int(floor(x)), j0 = int(floor(y));
  float coverage = 0.0, bestWeight = -1.0;
  vec4 texel = vec4(0.0);
  for (int k = 0; k < 4; ++k) {
    int i = i0 + (k & 1), j = j0 + (k >> 1);
    i = (i + int(fly.width)) % int(fly.width);
    j = clamp(j, 0, int(fly.height) - 1);
    vec4 t = unpackUnorm4x8(flyTexels[(layer * fly.height + uint(j)) * fly.width + uint(i)]);
    float w = ((k & 1) != 0 ? fx : 1.0 - fx) * ((k >> 1) != 0 ? fy : 1.0 - fy);
    coverage += w * t.w;
    if (t.w >= 0.5 && w > bestWeight) {
      bestWeight = w;
      texel = t;
    }
  }
  if (coverage < 0.25 || texel.w < 0.5) discard;
  vec3 toEye = normalize(view.cameraPos.xyz - flyWorld);
  vec3 w = toEye - flyAxis * dot(toEye, flyAxis);
  w = dot(w, w) > 1e-12 ? normalize(w) : toEye;
  vec3 side = cross(flyAxis, w);  // v = u × w, as the bake's frame (x, y, z) = (w, v, u)
  vec3 s = 2.0 * texel.xyz - vec3(1.0);
  vec3 t = ftNormalize(s.x * flyAxis + s.y * side + s.z * w);
  vec3 normal = w - t * dot(w, t);
  normal = dot(normal, normal) > 1e-12 ? normalize(normal) : w;
  vec3 radiance = vec3(0.0);
  for (int k = 0; k < int(shading.flags.x) && k < FT_MAX_LIGHTS; ++k) {
    FiberAngles a = ftFiberAngles(t, vec3(shading.lightDirection[k]), toEye);
    radiance += ftFiberDirectNormed(shading, k, a, normal, lobeNormsAt(a));
  }
  FiberAngles o = ftFiberAngles(t, toEye, toEye);
  vec3 kk = ftAmbientLookup(o.thetaO, FT_AMBIENT_TABLE_SIZE);
  radiance += ftFiberAmbient(shading, mix(ambientTable[int(kk.x)].xyz, ambientTable[int(kk.y)].xyz, kk.z));
  color = vec4(radiance, 1.0);
}
