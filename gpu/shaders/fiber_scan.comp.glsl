// Compute path, pass 2: exclusive prefix sums of the vertex and index counts
// of the listed segments, in list order (so the output order is canonical),
// and the indirect draw command. One work group: each invocation sums a
// contiguous chunk serially, then the chunk totals are scanned in shared
// memory (Hillis–Steele), then each chunk is written out.
#include "common/constants.h"
#include "common/fiber_vertex.h"
#include "common/yarn_params.h"

layout(local_size_x = FT_WG_SCAN) in;
layout(std430, binding = FT_SSBO_DECISIONS) readonly buffer DecisionBuffer { SegmentDecision decisions[]; };
layout(std430, binding = FT_SSBO_OFFSETS) writeonly buffer OffsetBuffer { uvec4 offsets[]; };  // (vertex, index, strip, sample)
layout(std430, binding = FT_SSBO_DRAW_COMMAND) writeonly buffer DrawBuffer { DrawElementsCommand draw; };
layout(std140, binding = FT_UBO_YARN_PARAMS) uniform YarnBlock { YarnParams yarn; };
uniform uint listCount;

shared uvec4 partial[FT_WG_SCAN];

uvec4 counts(uint i) {
  SegmentDecision d = decisions[i];
  // Indices: the vertices and one restart index after each fiber strip.
  uint strips = d.culled != 0u ? 0u : yarn.plyCount * (1u + d.regularCount);
  uint samples = d.culled != 0u ? 0u : ftSampleCount(d);
  return uvec4(d.vertexCount, d.vertexCount + strips, strips, samples);
}

void main() {
  uint lane = gl_LocalInvocationID.x;
  uint chunk = (listCount + FT_WG_SCAN - 1u) / FT_WG_SCAN;
  uint begin = min(lane * chunk, listCount);
  uint end = min(begin + chunk, listCount);
  uvec4 sum = uvec4(0u);
  for (uint i = begin; i < end; ++i) sum += counts(i);
  partial[lane] = sum;
  barrier();
  for (uint stride = 1u; stride < FT_WG_SCAN; stride <<= 1u) {
    uvec4 add = lane >= stride ? partial[lane - stride] : uvec4(0u);
    barrier();
    partial[lane] += add;
    barrier();
  }
  uvec4 running = partial[lane] - sum;  // exclusive
  for (uint i = begin; i < end; ++i) {
    offsets[i] = running;
    running += counts(i);
  }
  if (lane == FT_WG_SCAN - 1u) {
    draw.count = partial[lane].y;
    draw.instanceCount = 1u;
    draw.firstIndex = 0u;
    draw.baseVertex = 0u;
    draw.baseInstance = 0u;
    draw.vertexTotal = partial[lane].x;
    draw.stripTotal = partial[lane].z;
    draw.sampleTotal = partial[lane].w;
  }
}
