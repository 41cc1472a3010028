// The paper-faithful AO texture (000 §4.2, Fig. 8b): from each texel centre,
// the stratified directions of ftAoDirectionAngle, each ray marched through
// the density grid (ambient_occlusion_density.comp.glsl) with the midpoint
// rule and a manual bilinear fetch, until it leaves the square [−W, W]²
// (ρ = 0 beyond the support radius < W). Visibility ftAoVisibility.
#include "common/constants.h"
#include "common/ambient_occlusion.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_AO) in;
layout(std140, binding = FT_UBO_AMBIENT_OCCLUSION) uniform AoBlock { AmbientOcclusionParams ao; };
layout(std430, binding = FT_SSBO_AO_DENSITY) readonly buffer AoDensity { float grid[]; };
layout(std430, binding = FT_SSBO_AO_OUTPUT) writeonly buffer AoOutput { float results[]; };
uniform uint groupsX;
uniform uint itemCount;

// Bilinear density at x: texel centres as in the bake, clamped at the edges.
float gridDensity(vec2 x) {
  uint m = ao.densityResolution;
  float fm = float(m);
  vec2 u = (x + vec2(ao.halfWidth)) / (2.0 * ao.halfWidth) * fm - vec2(0.5);
  u = clamp(u, vec2(0.0), vec2(fm - 1.0));
  vec2 lo = min(floor(u), vec2(fm - 1.0));
  uvec2 a = uvec2(lo), b = uvec2(min(lo + vec2(1.0), vec2(fm - 1.0)));
  vec2 w = u - lo;
  return mix(mix(grid[a.y * m + a.x], grid[a.y * m + b.x], w.x), mix(grid[b.y * m + a.x], grid[b.y * m + b.x], w.x),
             w.y);
}

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_AO);
  if (k >= itemCount) return;
  uint n = ao.resolution;
  vec2 p = vec2(ftAoTexelCentre(ao.halfWidth, n, k % n), ftAoTexelCentre(ao.halfWidth, n, k / n));
  float step0 = ao.marchStep * 2.0 * ao.halfWidth / float(ao.densityResolution);
  float sum = 0.0;
  for (uint j = 0u; j < ao.directions; ++j) {
    float phi = ftAoDirectionAngle(ao, k, j);
    vec2 d = vec2(cos(phi), sin(phi));
    // Distance to the square's edge along d (p is inside).
    float tx = d.x > 0.0 ? (ao.halfWidth - p.x) / d.x : (d.x < 0.0 ? (-ao.halfWidth - p.x) / d.x : 3.0e38);
    float ty = d.y > 0.0 ? (ao.halfWidth - p.y) / d.y : (d.y < 0.0 ? (-ao.halfWidth - p.y) / d.y : 3.0e38);
    float len = min(tx, ty);
    uint steps = uint(ceil(len / step0));
    float h = len / float(max(steps, 1u));
    float tau = 0.0;
    for (uint s = 0u; s < steps; ++s) tau += gridDensity(p + (float(s) + 0.5) * h * d);
    sum += ftAoVisibility(ao.kappa, tau * h);
  }
  results[k] = sum / float(ao.directions);
}
