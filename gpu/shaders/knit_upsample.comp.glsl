// Up-sampling of the optimized control points (§5.2): one invocation per
// yarn control point writes FT_KNIT_UPSAMPLE Catmull–Rom vertices of the
// segment it starts (the last point of an open yarn writes only itself).
#include "shaders/knit_precision.glsl"
#include "common/constants.h"
#include "common/knit_solver.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_KNIT_UPSAMPLE) in;
layout(std430, binding = FT_SSBO_KNIT_POINTS) readonly buffer PointBuffer { vec4 points[]; };
// Per listed point: (tile point index, first list entry of its yarn, yarn length, closed).
layout(std430, binding = FT_SSBO_KNIT_YARN_LIST) readonly buffer YarnList { uvec4 list[]; };
layout(std430, binding = FT_SSBO_KNIT_VERTICES) writeonly buffer VertexBuffer { vec4 vertices[]; };
uniform uint listCount;
uniform uint groupsX;

// Point i of the yarn (i may run one past either end): wrapped round a closed
// yarn, reflected at the ends of an open one (as scene/ treats BCC curves).
vec3 yarnPoint(uint first, int n, bool closed, int i) {
  if (closed) return points[list[first + uint((i % n + n) % n)].x].xyz;
  if (i < 0) return 2.0 * points[list[first].x].xyz - points[list[first + 1u].x].xyz;
  if (i >= n) return 2.0 * points[list[first + uint(n - 1)].x].xyz - points[list[first + uint(n - 2)].x].xyz;
  return points[list[first + uint(i)].x].xyz;
}

void main() {
  uint j = flatInvocationIndex(groupsX, FT_WG_KNIT_UPSAMPLE);
  if (j >= listCount) return;
  uvec4 e = list[j];
  int n = int(e.z);
  bool closed = e.w != 0u;
  int i = int(j - e.y);
  if (!closed && i == n - 1) {
    vertices[j * uint(FT_KNIT_UPSAMPLE)] = vec4(yarnPoint(e.y, n, closed, i), 1.0);
    return;
  }
  vec3 p0 = yarnPoint(e.y, n, closed, i - 1);
  vec3 p1 = yarnPoint(e.y, n, closed, i);
  vec3 p2 = yarnPoint(e.y, n, closed, i + 1);
  vec3 p3 = yarnPoint(e.y, n, closed, i + 2);
  for (int k = 0; k < FT_KNIT_UPSAMPLE; ++k)
    vertices[j * uint(FT_KNIT_UPSAMPLE) + uint(k)] =
        vec4(knitCatmullRom(p0, p1, p2, p3, float(k) / float(FT_KNIT_UPSAMPLE)), 1.0);
}
