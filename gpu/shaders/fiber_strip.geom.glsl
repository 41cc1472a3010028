// Both paths: expands each fiber line into a camera-facing strip of the
// fiber's width (§5). Indifferent to fiber type: only the width differs.
// Each end takes its side vector from the vertex's own tangent
// (fiber_strip_tangent.glsl), so neighbouring quads share their edge. The
// fragment stage gives the flat strip the depth of a round fiber.
#include "common/constants.h"
#include "common/view_params.h"

layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };

layout(location = 0) in vec4 fiberPosition[];
layout(location = 1) flat in uvec4 fiberId[];
layout(location = 2) in vec3 fiberTangent[];
layout(location = 3) in float fiberStripEnd[];
layout(location = 0) out vec3 stripTangent;
layout(location = 1) out float stripAcross;   // -1 .. 1 across the strip
layout(location = 2) flat out uint stripType;
layout(location = 3) out vec3 stripWorld;      // world position on the strip's plane
layout(location = 4) out float stripHalfWidth; // world units
// The line itself, for the fragment stage's ray–tube intersection: end
// points, their unit tangents and half-widths (flat: one line per strip quad).
layout(location = 5) flat out vec3 lineP0;
layout(location = 6) flat out vec3 lineP1;
layout(location = 7) flat out vec3 lineT0;
layout(location = 8) flat out vec3 lineT1;
layout(location = 9) flat out vec2 lineHalfWidth;

void main() {
  // A hair's free end: the next period restarts at the ply, so a line
  // crossing from a hair period into another period is not drawn.
  uint type0 = fiberId[0].w & 0xFFu;
  uint type1 = fiberId[1].w & 0xFFu;
  bool periodChange = (fiberId[0].w >> 16u) != (fiberId[1].w >> 16u);
  if (periodChange && (type0 == FT_FIBER_HAIR || type1 == FT_FIBER_HAIR)) return;

  vec3 p[2] = vec3[2](fiberPosition[0].xyz, fiberPosition[1].xyz);
  vec3 chord = p[1] - p[0];
  if (dot(chord, chord) <= 0.0) return;
  chord = normalize(chord);
  vec3 eye = view.cameraPos.xyz;
  vec3 t[2];
  vec3 side[2];
  for (int i = 0; i < 2; ++i) {
    vec3 ti = fiberTangent[i];
    t[i] = dot(ti, ti) > 0.0 ? normalize(ti) : chord;
    vec3 s = cross(t[i], normalize(eye - p[i]));
#ifdef FT_FAULT_STRIP_HALF_WIDTH
    float halfWidth = 0.5 * fiberPosition[i].w;
#else
    float halfWidth = fiberPosition[i].w;
#endif
    if (dot(s, s) <= 1e-12) return;  // looking down the fiber
    side[i] = normalize(s) * halfWidth;
  }
  // Where two segments' strips meet at a knot their end vertices agree only
  // to rounding and their tangents to second order: a quarter of a width
  // of overlap closes the hairline crack without a visible cap.
  if (fiberStripEnd[0] > 0.5) p[0] -= t[0] * (0.25 * length(side[0]));
  if (fiberStripEnd[1] > 0.5) p[1] += t[1] * (0.25 * length(side[1]));
  vec3 ends[2] = vec3[2](fiberPosition[0].xyz, fiberPosition[1].xyz);  // before the overlap
  vec3 corners[4] = vec3[4](p[0] - side[0], p[0] + side[0], p[1] - side[1], p[1] + side[1]);
  for (int i = 0; i < 4; ++i) {
    stripTangent = t[i / 2];
    stripAcross = (i % 2 == 0) ? -1.0 : 1.0;
    stripType = i < 2 ? type0 : type1;
    stripWorld = corners[i];
    stripHalfWidth = length(side[i / 2]);
    lineP0 = ends[0];
    lineP1 = ends[1];
    lineT0 = t[0];
    lineT1 = t[1];
    lineHalfWidth = vec2(length(side[0]), length(side[1]));
    gl_Position = view.viewProj * vec4(corners[i], 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
