// fiber_vertex.h — what fiber generation produces, on every path: the
// per-segment LoD/culling decision and the tagged fiber vertices (std430).
#ifndef FT_FIBER_VERTEX_H
#define FT_FIBER_VERTEX_H
#include "prelude.h"

FT_NAMESPACE_BEGIN

struct FiberVertex {
  vec4 position;  // xyz world position, w = half-width of the camera-facing strip
  uvec4 id;       // x yarn (curve), y global segment, z ply << 16 | fiber (FT_CORE_FIBER_ID for core),
                  // w type (bits 0..7) | vertex index along the segment (bits 8..15) | period (bits 16..31)
};
FT_ASSERT_OFFSET(FiberVertex, id, 16)
FT_ASSERT_SIZE(FiberVertex, 32)

struct SegmentDecision {
  float lambda;          // λ of eq. 4
  float coreHalfWidth;   // core fiber half-width after LoD scaling at t = 0 (lod.h)
  uint regularCount;     // regular fibers per ply generated (outermost first)
  uint subdivisions;     // line segments per fiber; 0 when culled
  uint culled;           // 1: outside the view frustum, nothing generated
  uint vertexCount;      // vertices this segment emits
  float coreHalfWidthEnd;  // the same at t = 1; linear in between
  uint coreLines;        // line segments of the core strips (≤ subdivisions; lod.h)
};
FT_ASSERT_OFFSET(SegmentDecision, regularCount, 8)
FT_ASSERT_OFFSET(SegmentDecision, vertexCount, 20)
FT_ASSERT_OFFSET(SegmentDecision, coreHalfWidthEnd, 24)
FT_ASSERT_OFFSET(SegmentDecision, coreLines, 28)
FT_ASSERT_SIZE(SegmentDecision, 32)

// Vertices of one strip of a segment: a regular fiber (slot > 0) has one per
// line end t = v / subdivisions; the core (slot 0), which follows only the
// ply centre, one per t = v / coreLines (lod.h ftDecideSegment).
FT_FUNC uint ftStripVertexCount(SegmentDecision d, uint slot) {
  return (slot == 0u ? d.coreLines : d.subdivisions) + 1u;
}
// The yarn samples of a segment (its frame and length coordinate, shared by
// the strips): subdivisions + 1 for the regular fibers, then coreLines + 1
// for the cores.
FT_FUNC uint ftSampleCount(SegmentDecision d) { return d.subdivisions + d.coreLines + 2u; }
// The sample of a strip's vertex.
FT_FUNC uint ftStripSample(SegmentDecision d, uint slot, uint vertex) {
  return slot == 0u ? d.subdivisions + 1u + vertex : vertex;
}
// The curve parameter of a sample.
FT_FUNC float ftSampleT(SegmentDecision d, uint sampleIndex) {
  FT_PRECISE float t;
  if (sampleIndex <= d.subdivisions) t = float(sampleIndex) / float(d.subdivisions);
  else t = float(sampleIndex - d.subdivisions - 1u) / float(d.coreLines);
  return t;
}
// Vertices of one ply: its core strip, then regularCount regular strips.
FT_FUNC uint ftPlyVertexCount(SegmentDecision d) {
  return ftStripVertexCount(d, 0u) + d.regularCount * (d.subdivisions + 1u);
}

// glDrawElementsIndirect command, filled by the compute path.
struct DrawElementsCommand {
  uint count;
  uint instanceCount;
  uint firstIndex;
  uint baseVertex;
  uint baseInstance;
  uint vertexTotal;   // not read by GL: total vertices written, for read-back
  uint stripTotal;    // not read by GL: fiber strips (one generate invocation each)
  uint sampleTotal;   // not read by GL: yarn samples (one per visible segment and vertex index)
};
FT_ASSERT_SIZE(DrawElementsCommand, 32)

// The yarn frame and length coordinate at one vertex parameter t of one
// segment: shared by every fiber of every ply there. The compute path
// evaluates it once (a pass of its own); the tessellation path per vertex.
struct YarnSample {
  vec4 centerLength;  // xyz yarn centre, w length coordinate s
  vec4 tangent;       // xyz T (w unused)
  vec4 normal;        // xyz N
  vec4 binormal;      // xyz B
};
FT_ASSERT_SIZE(YarnSample, 64)

FT_FUNC uint ftPackFiberId(uint ply, uint fiber) { return (ply << 16u) | (fiber & 0xFFFFu); }
FT_FUNC uint ftPackTypeVertex(uint type, uint vertex, uint period) {
  return (type & 0xFFu) | ((vertex & 0xFFu) << 8u) | ((period & 0xFFFFu) << 16u);
}

FT_NAMESPACE_END
#endif  // FT_FIBER_VERTEX_H
