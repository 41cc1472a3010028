// Compute path, pass 1: LoD and culling decision per listed segment (eq. 4, §3.3).
#include "shaders/fiber_resources.glsl"

layout(local_size_x = FT_WG_DECIDE) in;
layout(std430, binding = FT_SSBO_DECISIONS) writeonly buffer DecisionBuffer { SegmentDecision decisions[]; };
uniform uint listCount;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= listCount) return;
  decisions[i] = ftDecideSegment(yarn, view, loadSegment(segmentList[i]));
}
