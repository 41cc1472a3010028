// Tessellation path, evaluation stage: one isoline per fiber, one vertex per
// subdivision point; the same ftFiberVertex() as the CPU and compute paths.
#include "shaders/fiber_resources.glsl"
#ifdef FT_STRIP_TANGENTS
#include "shaders/fiber_strip_tangent.glsl"
#endif

layout(isolines, equal_spacing) in;

layout(location = 0) patch in vec4 pB[4];
layout(location = 4) patch in vec4 pN[2];
layout(location = 6) patch in vec4 pLength;
layout(location = 7) patch in uvec4 pIds;
layout(location = 8) patch in vec4 pDecision;
layout(location = 9) patch in uvec4 pDecisionU;

// Captured by transform feedback for the harness; also feeds the strip GS.
layout(location = 0) out vec4 fiberPosition;     // xyz, w = half-width
layout(location = 1) flat out uvec4 fiberId;
#ifdef FT_STRIP_TANGENTS
// Drawing only (the capture program has no strips): the neighbours at
// vertex ± 1, 2 of the same fiber, evaluated here, give the strip tangent.
layout(location = 2) out vec3 fiberTangent;
layout(location = 3) out float fiberStripEnd;
layout(location = 4) out vec4 yarnCenterLength;  // the yarn frame here (fiber_strip.vert.glsl says why)
layout(location = 5) out vec3 yarnNormal;
layout(location = 6) out vec3 yarnBinormal;
#endif

void main() {
  YarnSegment seg;
  seg.b0 = pB[0]; seg.b1 = pB[1]; seg.b2 = pB[2]; seg.b3 = pB[3];
  seg.n0 = pN[0]; seg.n1 = pN[1];
  seg.s0 = pLength.x; seg.s1 = pLength.y;
  SegmentDecision d;
  d.lambda = pDecision.x;
  d.coreHalfWidth = pDecision.y;
  d.coreHalfWidthEnd = pDecision.z;
  d.regularCount = pDecisionU.x;
  d.subdivisions = pDecisionU.y;
  d.culled = pDecisionU.z;
  d.vertexCount = pDecisionU.w;
  d.coreLines = uint(pDecision.w);

  // Line k of n sits at y = k/n; vertex j of S at x = j/S. Round, then
  // recompute t from the integers so t is bit-identical to the CPU's.
  uint line = uint(round(gl_TessCoord.y * gl_TessLevelOuter[0]));
  uint vertex = uint(round(gl_TessCoord.x * float(d.subdivisions)));
  uint strip = pIds.z + line;
  uint ply = strip / pIds.w;
  uint slot = strip % pIds.w;
  // The isoline has subdivisions + 1 vertices; a core strip has fewer
  // (ftStripVertexCount): the rest repeat its last, and the geometry stage
  // drops the empty lines between them.
  uint last = ftStripVertexCount(d, slot) - 1u;
  vertex = min(vertex, last);
  uint curve = pIds.x;
  TwistRates rates = ftTwistRates(yarn, curves[curve]);
  FiberVertex fv = ftFiberVertex(yarn, rates, seg, d, curve, pIds.y, ply, slot, slotFiberCoord(slot), vertex);
  fiberPosition = fv.position;
  fiberId = fv.id;
#ifdef FT_STRIP_TANGENTS
  vec3 p[5];
  bool has[5];
  for (int k = -2; k <= 2; ++k) {
    int j = int(vertex) + k;
    has[k + 2] = false;
    p[k + 2] = fv.position.xyz;
    // ±2 only where the other side is missing (ftStripTangent reads it then).
    bool needed = k == -1 || k == 1 || (k == -2 && vertex + 1u > last) || (k == 2 && vertex == 0u);
    if (k == 0 || !needed || j < 0 || j > int(last)) continue;
    FiberVertex nv = ftFiberVertex(yarn, rates, seg, d, curve, pIds.y, ply, slot, slotFiberCoord(slot), uint(j));
    has[k + 2] = ftStripNeighbour(fv.id, nv.id, k);
    p[k + 2] = nv.position.xyz;
  }
  fiberTangent = ftStripTangent(p[0], p[1], p[2], p[3], p[4], bvec4(has[0], has[1], has[3], has[4]));
  fiberStripEnd = (has[1] && has[3]) ? 0.0 : 1.0;
  YarnSample ys = ftYarnSample(seg, d, ftStripSample(d, slot, vertex));
  yarnCenterLength = ys.centerLength;
  yarnNormal = ys.normal.xyz;
  yarnBinormal = ys.binormal.xyz;
#endif
  gl_Position = view.viewProj * vec4(fv.position.xyz, 1.0);
}
