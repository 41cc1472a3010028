// Two-pass culling on the compute path (common/occlusion_cull.h ftLineKey,
// FiberRenderer::drawDeferred): the line strips' index buffer for one of the
// two draws, the indices of the lines that draw cannot take replaced by
// restarts, so that their vertex and geometry stages never run (llvmpipe runs
// those on the calling thread: the close-up's first draw took 0.93 s with
// this and 1.2-1.35 s without). One invocation per index. A vertex stays
// when a line it ends may be drawn: in the first draw a line the previous
// frame saw; in the second a line it did not see whose box is not behind
// the pyramid of the first draw's depth. The geometry stage still makes its
// own choice (fiber_strip.geom.glsl); this only drops lines it would drop
// too or that cannot win a sample, and keeps the others in their order, so
// the frame is the same.
#include "common/constants.h"
#include "common/fiber_vertex.h"
#include "common/occlusion_cull.h"
#include "common/view_params.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_TWO_PASS) in;
layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(std140, binding = FT_UBO_OCCLUSION) uniform OcclusionBlock { OcclusionPyramid pyramid; };
layout(std430, binding = FT_SSBO_OCCLUSION) readonly buffer OcclusionTexels { float occlusionTexels[]; };
layout(std430, binding = FT_SSBO_VERTICES) readonly buffer VertexBuffer { FiberVertex vertices[]; };
layout(std430, binding = FT_SSBO_INDICES) readonly buffer IndexBuffer { uint indices[]; };
layout(std430, binding = FT_SSBO_VISIBLE_LINES) readonly buffer VisibleLines { uint visibleLines[]; };
layout(std430, binding = FT_SSBO_TWO_PASS_INDICES) writeonly buffer DrawIndices { uint drawIndices[]; };
uniform uint itemCount;  // the indices (dispatchFlat)
uniform uint twoPassDraw;  // FT_TWO_PASS_SEEN or FT_TWO_PASS_UNSEEN (then not behind the pyramid either)
uniform uint lineKeyBits;
uniform uint groupsX;

// Every sample the line (a, b) can cover lies in the projection of the box
// around both end balls of 1.5 times the larger half-width (the capsule, and
// the core-fiber texture's hit within √2 of it), and every depth it can write
// is at or behind its nearer end moved that far towards the eye (the
// geometry stage's bound): hidden when that depth is behind the pyramid's
// deepest texel over the projection's bounds.
bool hidden(FiberVertex a, FiberVertex b) {
  float reach = 1.5 * max(a.position.w, b.position.w);
  vec3 lo = min(a.position.xyz, b.position.xyz) - vec3(reach), hi = max(a.position.xyz, b.position.xyz) + vec3(reach);
  vec2 pxLo = vec2(3.0e38), pxHi = vec2(-3.0e38);
  for (int k = 0; k < 8; ++k) {
    vec3 corner = vec3((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y, (k & 4) != 0 ? hi.z : lo.z);
    vec4 c = view.viewProj * vec4(corner, 1.0);
    if (!(c.w > 0.0)) return false;  // a corner at or behind the eye
    vec2 px = (0.5 * c.xy / c.w + 0.5) * vec2(pyramid.size.xy);
    pxLo = min(pxLo, px);
    pxHi = max(pxHi, px);
  }
#ifdef FT_FAULT_TWO_PASS_BOX_FAR
  // Planted fault: the bound taken on the line's far side.
  float nearest = max(ftNearestWindowDepth(view, a.position.xyz, -1.5 * a.position.w),
                      ftNearestWindowDepth(view, b.position.xyz, -1.5 * b.position.w));
#else
  float nearest = min(ftNearestWindowDepth(view, a.position.xyz, 1.5 * a.position.w),
                      ftNearestWindowDepth(view, b.position.xyz, 1.5 * b.position.w));
#endif
  vec2 size = vec2(pyramid.size.xy);
  if (!(pxHi.x >= 0.0 && pxHi.y >= 0.0 && pxLo.x < size.x && pxLo.y < size.y)) return false;
  uvec2 p0 = uvec2(clamp(floor(pxLo), vec2(0.0), size - 1.0)), p1 = uvec2(clamp(floor(pxHi), vec2(0.0), size - 1.0));
  uint level = ftOcclusionLevelFor(pyramid, p0, p1);
  float deepest = 0.0;
  for (uint y = p0.y >> level; y <= (p1.y >> level); ++y)
    for (uint x = p0.x >> level; x <= (p1.x >> level); ++x)
      deepest = max(deepest, occlusionTexels[ftOcclusionIndex(pyramid, level, x, y)]);
  return nearest > deepest;
}

bool visibleLineBit(uint bit) {
  uint word = bit >> 5u;
  return word < uint(visibleLines.length()) && ((visibleLines[word] >> (bit & 31u)) & 1u) != 0u;
}

bool drawsLine(uint first, uint second) {
  FiberVertex a = vertices[first];
  bool seen = visibleLineBit(ftLineKey(a.id, lineKeyBits));
  return twoPassDraw == FT_TWO_PASS_SEEN ? seen : !seen && !hidden(a, vertices[second]);
}

void main() {
  uint i = flatInvocationIndex(groupsX, FT_WG_TWO_PASS);
  if (i >= itemCount) return;
  uint v = indices[i];
  bool keep = false;
  if (v != FT_RESTART_INDEX) {
    if (i > 0u && indices[i - 1u] != FT_RESTART_INDEX) keep = drawsLine(indices[i - 1u], v);
    if (!keep && i + 1u < itemCount && indices[i + 1u] != FT_RESTART_INDEX) keep = drawsLine(v, indices[i + 1u]);
  }
  drawIndices[i] = keep ? v : FT_RESTART_INDEX;
}
