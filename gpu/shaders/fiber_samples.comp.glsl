// Compute path, pass 4: the yarn frame and length coordinate at every vertex
// parameter of every visible listed segment (ftYarnSample), once — every
// fiber of every ply at that parameter reads it in pass 4 instead of
// re-evaluating the cubic and its frame. Samples are numbered by the scan.
#include "shaders/fiber_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SAMPLES) in;
layout(std430, binding = FT_SSBO_DECISIONS) readonly buffer DecisionBuffer { SegmentDecision decisions[]; };
layout(std430, binding = FT_SSBO_SAMPLE_OWNERS) readonly buffer SampleOwnerBuffer { uint sampleOwner[]; };
layout(std430, binding = FT_SSBO_OFFSETS) readonly buffer OffsetBuffer { uvec4 offsets[]; };  // (vertex, index, strip, sample)
layout(std430, binding = FT_SSBO_SAMPLES) writeonly buffer SampleBuffer { YarnSample samples[]; };
uniform uint listCount;
uniform uint sampleTotal;
uniform uint groupsX;  // work groups along x per y row

void main() {
  uint global = flatInvocationIndex(groupsX, FT_WG_SAMPLES);
  if (global >= sampleTotal) return;
  uint i = sampleOwner[global];
  samples[global] = ftYarnSample(loadSegment(segmentList[i]), decisions[i], global - offsets[i].w);
}
