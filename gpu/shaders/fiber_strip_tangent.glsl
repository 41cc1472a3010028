// fiber_strip_tangent.glsl — GLSL-only include: the tangent of a fiber
// polyline at one of its vertices, from the vertices around it. Both GPU
// paths draw strips with it (the compute path's vertex shader reads the
// neighbours from the vertex buffer, the tessellation path's evaluation
// shader evaluates them), so a strip is the same on both.
//
// The camera-facing strip is built from per-vertex side vectors: the two
// quads that share a vertex share its edge, so a strip has no gaps or
// overlaps at its vertices and shades smoothly along the fiber. Interior
// vertices take the central difference; the first and last vertex of a
// segment's strip the second-order one-sided difference (−3p₀ + 4p₁ − p₂),
// which matches the neighbouring segment's strip at the shared knot to
// second order in the subdivision length, so segments join without a wedge.
#include "common/constants.h"
#include "common/fiber_vertex.h"

// Whether two vertices of one fiber are consecutive samples of one piece of
// curve: the same segment and fiber, vertex indices `step` apart, and no hair
// free end between them (fiber_strip.geom.glsl drops that line too).
bool ftStripNeighbour(uvec4 a, uvec4 b, int step) {
  if (a.y != b.y || a.z != b.z) return false;
  int va = int((a.w >> 8u) & 0xFFu), vb = int((b.w >> 8u) & 0xFFu);
  if (vb - va != step) return false;
  bool periodChange = (a.w >> 16u) != (b.w >> 16u);
  return !(periodChange && ((a.w & 0xFFu) == FT_FIBER_HAIR || (b.w & 0xFFu) == FT_FIBER_HAIR));
}

// Neighbours at -2, -1, +1, +2 with their availability (has.x .. has.w);
// a missing -2/+2 is only read when the far side is missing too.
vec3 ftStripTangent(vec3 pm2, vec3 pm1, vec3 p0, vec3 pp1, vec3 pp2, bvec4 has) {
  if (has.y && has.z) return pp1 - pm1;
  if (has.z) return has.w ? 4.0 * pp1 - 3.0 * p0 - pp2 : pp1 - p0;
  if (has.y) return has.x ? 3.0 * p0 - 4.0 * pm1 + pm2 : p0 - pm1;
  return vec3(0.0);
}
