// Tessellation path, control stage: LoD and culling for the segment (eq. 4,
// §3.3) and how many isolines this instance draws. One isoline per fiber
// slot; a patch draws at most `linesPerPatch` (GL_MAX_TESS_GEN_LEVEL) of them,
// so instance k covers slots [k·linesPerPatch, (k+1)·linesPerPatch).
#include "shaders/fiber_resources.glsl"

layout(vertices = 1) out;
layout(location = 0) in flat uvec2 vListInstance[];

layout(location = 0) patch out vec4 pB[4];
layout(location = 4) patch out vec4 pN[2];
layout(location = 6) patch out vec4 pLength;       // s0, s1
layout(location = 7) patch out uvec4 pIds;         // curve, segment, first slot, slots per ply
layout(location = 8) patch out vec4 pDecision;     // λ, core half-width at t = 0 and t = 1, core lines
layout(location = 9) patch out uvec4 pDecisionU;   // regular count, subdivisions, culled, vertex count

uniform uint linesPerPatch;

void main() {
  uint listIndex = vListInstance[0].x;
  uint instance = vListInstance[0].y;
  uint segment = segmentList[listIndex];
  YarnSegment seg = loadSegment(segment);
  SegmentDecision d = ftDecideSegment(yarn, view, seg);
  uint slots = yarn.plyCount * ftSlotsPerPly(d);
  uint first = instance * linesPerPatch;
  uint lines = (d.culled != 0u || first >= slots) ? 0u : min(slots - first, linesPerPatch);

  pB[0] = seg.b0; pB[1] = seg.b1; pB[2] = seg.b2; pB[3] = seg.b3;
  pN[0] = seg.n0; pN[1] = seg.n1;
  pLength = vec4(seg.s0, seg.s1, 0.0, 0.0);
  pIds = uvec4(segmentRefs[segment].curve, segment, first, ftSlotsPerPly(d));
  pDecision = vec4(d.lambda, d.coreHalfWidth, d.coreHalfWidthEnd, float(d.coreLines));  // ≤ 64: exact
  pDecisionU = uvec4(d.regularCount, d.subdivisions, d.culled, d.vertexCount);

  // A zero outer level discards the patch.
  gl_TessLevelOuter[0] = float(lines);
  gl_TessLevelOuter[1] = float(d.subdivisions);
}
