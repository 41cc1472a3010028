// Compute path, pass 1: LoD and culling decision per listed segment (eq. 4, §3.3).
#include "shaders/fiber_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_DECIDE) in;
layout(std430, binding = FT_SSBO_DECISIONS) writeonly buffer DecisionBuffer { SegmentDecision decisions[]; };
uniform uint listCount;
uniform uint groupsX;  // work groups along x per y row

void main() {
  uint i = flatInvocationIndex(groupsX, FT_WG_DECIDE);
  if (i >= listCount) return;
  decisions[i] = ftDecideSegment(yarn, view, loadSegment(segmentList[i]));
}
