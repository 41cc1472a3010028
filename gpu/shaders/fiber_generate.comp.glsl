// Compute path, pass 5: one invocation per fiber strip (listed segment, ply,
// fiber slot) of the visible segments — the strips are numbered by the scan,
// so no invocation idles on culled segments or dropped LoD fibers. Each
// writes its fiber's vertices in canonical order and its line-strip indices.
#include "shaders/fiber_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_GENERATE) in;
layout(std430, binding = FT_SSBO_DECISIONS) readonly buffer DecisionBuffer { SegmentDecision decisions[]; };
layout(std430, binding = FT_SSBO_STRIP_OWNERS) readonly buffer StripOwnerBuffer { uint stripOwner[]; };
layout(std430, binding = FT_SSBO_OFFSETS) readonly buffer OffsetBuffer { uvec4 offsets[]; };  // (vertex, index, strip, sample)
layout(std430, binding = FT_SSBO_SAMPLES) readonly buffer SampleBuffer { YarnSample samples[]; };
layout(std430, binding = FT_SSBO_VERTICES) writeonly buffer VertexBuffer { FiberVertex vertices[]; };
layout(std430, binding = FT_SSBO_INDICES) writeonly buffer IndexBuffer { uint indices[]; };
uniform uint listCount;
uniform uint stripTotal;
uniform uint groupsX;  // work groups along x per y row

void main() {
  uint global = flatInvocationIndex(groupsX, FT_WG_GENERATE);
  if (global >= stripTotal) return;
  uint i = stripOwner[global];
  SegmentDecision d = decisions[i];
  uint slotsPerPly = ftSlotsPerPly(d);
  uint strip = global - offsets[i].z;
  uint ply = strip / slotsPerPly;
  uint slot = strip % slotsPerPly;
  uint segment = segmentList[i];
  SegmentRef ref = segmentRefs[segment];
  uint sampleBase = offsets[i].w;
  TwistRates rates = ftTwistRates(yarn, curves[ref.curve]);
  FiberCoord fc = slotFiberCoord(slot);
  uint vertexBase = offsets[i].x + ftVertexOffset(d, ply, slot, 0u);
  uint indexBase = offsets[i].y + ftStripIndexOffset(d, ply, slot);
  uint last = ftStripVertexCount(d, slot) - 1u;
  PeriodCache cache = ftEmptyPeriodCache();
  for (uint v = 0u; v <= last; ++v) {
    CachedFiberVertex cv = ftFiberVertexAt(yarn, rates, samples[sampleBase + ftStripSample(d, slot, v)], d, ref.curve,
                                           segment, ply, slot, fc, v, cache);
    cache = cv.cache;
    vertices[vertexBase + v] = cv.vertex;
    indices[indexBase + v] = vertexBase + v;
  }
#ifdef FT_FAULT_RESTART_DROPPED
  indices[indexBase + last + 1u] = vertexBase + last;  // the next strip joins on
#else
  indices[indexBase + last + 1u] = FT_RESTART_INDEX;
#endif
}
