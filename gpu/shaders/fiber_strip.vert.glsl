// Compute path drawing: vertex pulling from the generated vertex buffer
// (glDrawElementsIndirect with line strips; gl_VertexID is the index value).
// A fiber's vertices are consecutive in the buffer (common/fiber_generation.h),
// so the neighbours that give the strip its tangent are at gl_VertexID ± 1, 2.
#include "common/constants.h"
#include "common/fiber_vertex.h"
#include "common/view_params.h"
#include "shaders/fiber_strip_tangent.glsl"

layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(std430, binding = FT_SSBO_VERTICES) readonly buffer VertexBuffer { FiberVertex vertices[]; };
layout(std430, binding = FT_SSBO_OFFSETS) readonly buffer OffsetBuffer { uvec4 offsets[]; };  // (vertex, index, strip, sample)
layout(std430, binding = FT_SSBO_SAMPLES) readonly buffer SampleBuffer { YarnSample samples[]; };
layout(std430, binding = FT_SSBO_DECISIONS) readonly buffer DecisionBuffer { SegmentDecision decisions[]; };
uniform uint vertexTotal;  // vertices written; the buffer may be longer
uniform uint listCount;    // listed segments; 0: no yarn samples (a foreign vertex stream)

layout(location = 0) out vec4 fiberPosition;
layout(location = 1) flat out uvec4 fiberId;
layout(location = 2) out vec3 fiberTangent;
layout(location = 3) out float fiberStripEnd;  // 1 at the first or last vertex of a strip
// The yarn's centre, length coordinate and frame where this vertex was made
// (the self-shadow lookup of 000 §4.1 works in the yarn cross-section).
layout(location = 4) out vec4 yarnCenterLength;
layout(location = 5) out vec3 yarnNormal;
layout(location = 6) out vec3 yarnBinormal;

// The yarn sample of vertex i: its segment is the last listed one whose
// vertices start at or before i (offsets[].x ascends), its sample that
// segment's first plus ftStripSample of the vertex index along it (the
// cores have samples of their own).
YarnSample yarnSampleOf(uint i, uint vertexIndex, bool core) {
  uint lo = 0u, hi = listCount - 1u;
  while (lo < hi) {
    uint mid = (lo + hi + 1u) / 2u;
    if (offsets[mid].x <= i) lo = mid;
    else hi = mid - 1u;
  }
  return samples[offsets[lo].w + ftStripSample(decisions[lo], core ? 0u : 1u, vertexIndex)];
}

void main() {
  int i = gl_VertexID;
  FiberVertex v = vertices[i];
  vec3 p[5];
  bool has[5];
  for (int k = -2; k <= 2; ++k) {
    int j = i + k;
    has[k + 2] = k != 0 && j >= 0 && uint(j) < vertexTotal && ftStripNeighbour(v.id, vertices[j].id, k);
    p[k + 2] = has[k + 2] ? vertices[j].position.xyz : v.position.xyz;
  }
  fiberPosition = v.position;
  fiberId = v.id;
  fiberTangent = ftStripTangent(p[0], p[1], p[2], p[3], p[4], bvec4(has[0], has[1], has[3], has[4]));
  fiberStripEnd = (has[1] && has[3]) ? 0.0 : 1.0;
  if (listCount > 0u) {
    YarnSample ys = yarnSampleOf(uint(i), (v.id.w >> 8u) & 0xFFu, (v.id.w & 0xFFu) == FT_FIBER_CORE);
    yarnCenterLength = ys.centerLength;
    yarnNormal = ys.normal.xyz;
    yarnBinormal = ys.binormal.xyz;
  } else {
    yarnCenterLength = vec4(v.position.xyz, 0.0);
    yarnNormal = vec3(1.0, 0.0, 0.0);
    yarnBinormal = vec3(0.0, 1.0, 0.0);
  }
  gl_Position = view.viewProj * vec4(v.position.xyz, 1.0);
}
