// Compute path, pass 3: for every fiber strip and every yarn sample, which
// listed segment owns it — so passes 4 and 5 find their segment with one
// load instead of a binary search over the scan's offsets.
#include "shaders/fiber_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_DECIDE) in;
layout(std430, binding = FT_SSBO_DECISIONS) readonly buffer DecisionBuffer { SegmentDecision decisions[]; };
layout(std430, binding = FT_SSBO_OFFSETS) readonly buffer OffsetBuffer { uvec4 offsets[]; };  // (vertex, index, strip, sample)
layout(std430, binding = FT_SSBO_STRIP_OWNERS) writeonly buffer StripOwnerBuffer { uint stripOwner[]; };
layout(std430, binding = FT_SSBO_SAMPLE_OWNERS) writeonly buffer SampleOwnerBuffer { uint sampleOwner[]; };
uniform uint listCount;
uniform uint groupsX;  // work groups along x per y row

void main() {
  uint i = flatInvocationIndex(groupsX, FT_WG_DECIDE);
  if (i >= listCount) return;
  SegmentDecision d = decisions[i];
  if (d.culled != 0u) return;
  uint strips = yarn.plyCount * (1u + d.regularCount);
  for (uint k = 0u; k < strips; ++k) stripOwner[offsets[i].z + k] = i;
  for (uint k = 0u; k < ftSampleCount(d); ++k) sampleOwner[offsets[i].w + k] = i;
}
