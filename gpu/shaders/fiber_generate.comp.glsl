// Compute path, pass 3: one invocation per (listed segment, ply, fiber slot)
// writes that fiber's vertices in canonical order and its line-strip indices.
// Segments run along work-group y and z (each at most 65,535 on llvmpipe).
#include "shaders/fiber_resources.glsl"

layout(local_size_x = FT_WG_GENERATE) in;
layout(std430, binding = FT_SSBO_DECISIONS) readonly buffer DecisionBuffer { SegmentDecision decisions[]; };
layout(std430, binding = FT_SSBO_OFFSETS) readonly buffer OffsetBuffer { uvec2 offsets[]; };
layout(std430, binding = FT_SSBO_VERTICES) writeonly buffer VertexBuffer { FiberVertex vertices[]; };
layout(std430, binding = FT_SSBO_INDICES) writeonly buffer IndexBuffer { uint indices[]; };
uniform uint listCount;
uniform uint groupsY;  // work groups along y per z slice

void main() {
  uint i = gl_WorkGroupID.y + gl_WorkGroupID.z * groupsY;
  if (i >= listCount) return;
  SegmentDecision d = decisions[i];
  uint slotsPerPly = ftSlotsPerPly(d);
  uint strip = gl_GlobalInvocationID.x;
  if (d.culled != 0u || strip >= yarn.plyCount * slotsPerPly) return;
  uint ply = strip / slotsPerPly;
  uint slot = strip % slotsPerPly;
  uint segment = segmentList[i];
  SegmentRef ref = segmentRefs[segment];
  YarnSegment seg = loadSegment(segment);
  TwistRates rates = ftTwistRates(yarn, curves[ref.curve]);
  FiberCoord fc = slotFiberCoord(slot);
  uint vertexBase = offsets[i].x + ftVertexOffset(d, ply, slot, 0u);
  uint indexBase = offsets[i].y + strip * (d.subdivisions + 2u);
  for (uint v = 0u; v <= d.subdivisions; ++v) {
    vertices[vertexBase + v] = ftFiberVertex(yarn, rates, seg, d, ref.curve, segment, ply, slot, fc, v);
    indices[indexBase + v] = vertexBase + v;
  }
  indices[indexBase + d.subdivisions + 1u] = FT_RESTART_INDEX;
}
