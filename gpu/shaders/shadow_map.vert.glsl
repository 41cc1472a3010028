// Yarn shadow map depth pass (000 §4.1, common/shadow_map.h): no vertex
// input; vertex k is sub-segment k % FT_SHADOW_MAP_SUBSEGMENTS of yarn
// segment k / FT_SHADOW_MAP_SUBSEGMENTS, evaluated from the FiberGpu's yarn
// buffers (the Bézier form of the Catmull-Rom segment). Fibers are ignored.
#include "shaders/fiber_resources.glsl"
#include "common/shadow_map.h"

layout(location = 0) out vec3 tubeA;  // sub-segment end points (world)
layout(location = 1) out vec3 tubeB;
layout(location = 2) flat out uint tubeCaps;  // bit 0: the yarn starts at tubeA, bit 1: it ends at tubeB

void main() {
  uint segment = uint(gl_VertexID) / FT_SHADOW_MAP_SUBSEGMENTS;
  uint sub = uint(gl_VertexID) % FT_SHADOW_MAP_SUBSEGMENTS;
  SegmentRef ref = segmentRefs[segment];
  CurveInfo c = curves[ref.curve];
  YarnSegment s = fetchSegment(c, ref.local);
  bool open = c.closed == 0u;
  tubeCaps = (open && ref.local == 0u && sub == 0u ? 1u : 0u) |
             (open && ref.local + 1u == ftCurveSegmentCount(c) && sub + 1u == FT_SHADOW_MAP_SUBSEGMENTS ? 2u : 0u);
  tubeA = ftBezierPoint(s, float(sub) / float(FT_SHADOW_MAP_SUBSEGMENTS));
  tubeB = ftBezierPoint(s, float(sub + 1u) / float(FT_SHADOW_MAP_SUBSEGMENTS));
  gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
