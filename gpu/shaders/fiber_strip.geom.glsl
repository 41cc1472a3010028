// Both paths: expands each fiber line into a camera-facing strip of the
// fiber's width (§5). Indifferent to fiber type: only the width differs.
#include "common/constants.h"
#include "common/view_params.h"

layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };

layout(location = 0) in vec4 fiberPosition[];
layout(location = 1) flat in uvec4 fiberId[];
layout(location = 0) out vec3 stripTangent;
layout(location = 1) out float stripAcross;   // -1 .. 1 across the strip
layout(location = 2) flat out uint stripType;

void main() {
  // A hair's free end: the next period restarts at the ply, so a line
  // crossing from a hair period into another period is not drawn.
  uint type0 = fiberId[0].w & 0xFFu;
  uint type1 = fiberId[1].w & 0xFFu;
  bool periodChange = (fiberId[0].w >> 16u) != (fiberId[1].w >> 16u);
  if (periodChange && (type0 == FT_FIBER_HAIR || type1 == FT_FIBER_HAIR)) return;

  vec3 p0 = fiberPosition[0].xyz;
  vec3 p1 = fiberPosition[1].xyz;
  vec3 t = p1 - p0;
  if (dot(t, t) <= 0.0) return;
  t = normalize(t);
  vec3 eye = view.cameraPos.xyz;
  vec3 side0 = cross(t, normalize(eye - p0));
  vec3 side1 = cross(t, normalize(eye - p1));
  if (dot(side0, side0) <= 1e-12 || dot(side1, side1) <= 1e-12) return;  // looking down the fiber
  side0 = normalize(side0) * fiberPosition[0].w;
  side1 = normalize(side1) * fiberPosition[1].w;
  // Overlap neighbouring quads by half a width so a curving strip shows no
  // wedge-shaped gaps at the joints (the depth test hides the overlap).
  p0 -= t * (0.5 * fiberPosition[0].w);
  p1 += t * (0.5 * fiberPosition[1].w);
  vec3 corners[4] = vec3[4](p0 - side0, p0 + side0, p1 - side1, p1 + side1);
  for (int i = 0; i < 4; ++i) {
    stripTangent = t;
    stripAcross = (i % 2 == 0) ? -1.0 : 1.0;
    stripType = i < 2 ? type0 : type1;
    gl_Position = view.viewProj * vec4(corners[i], 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
