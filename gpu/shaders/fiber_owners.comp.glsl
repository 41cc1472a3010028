// Compute path, pass 3: for every fiber strip and every yarn sample, which
// listed segment owns it — so passes 4 and 5 find their segment with one
// load instead of a binary search over the scan's offsets.
#include "common/constants.h"
#include "common/fiber_vertex.h"
#include "common/yarn_params.h"

layout(local_size_x = FT_WG_DECIDE) in;
layout(std140, binding = FT_UBO_YARN_PARAMS) uniform YarnBlock { YarnParams yarn; };
layout(std430, binding = FT_SSBO_DECISIONS) readonly buffer DecisionBuffer { SegmentDecision decisions[]; };
layout(std430, binding = FT_SSBO_OFFSETS) readonly buffer OffsetBuffer { uvec4 offsets[]; };  // (vertex, index, strip, sample)
layout(std430, binding = FT_SSBO_STRIP_OWNERS) writeonly buffer StripOwnerBuffer { uint stripOwner[]; };
layout(std430, binding = FT_SSBO_SAMPLE_OWNERS) writeonly buffer SampleOwnerBuffer { uint sampleOwner[]; };
uniform uint listCount;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= listCount) return;
  SegmentDecision d = decisions[i];
  if (d.culled != 0u) return;
  uint strips = yarn.plyCount * (1u + d.regularCount);
  for (uint k = 0u; k < strips; ++k) stripOwner[offsets[i].z + k] = i;
  for (uint k = 0u; k <= d.subdivisions; ++k) sampleOwner[offsets[i].w + k] = i;
}
