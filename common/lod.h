// lod.h — per-segment level of detail (eq. 4 of 000_cc9bd0fbd0e08a03.txt)
// and frustum culling (§3.3). One decision per yarn segment, shared by the
// CPU reference, the compute path and the tessellation control shader.
#ifndef FT_LOD_H
#define FT_LOD_H
#include "prelude.h"
#include "fiber_vertex.h"
#include "view_params.h"
#include "yarn_curve.h"
#include "yarn_params.h"

FT_NAMESPACE_BEGIN

// Eq. 4: λ from the screen widths of a fiber and of a ply at the yarn centre.
FT_FUNC float ftLodLambda(float omegaFiber, float omegaPly, float omegaLod) {
#ifdef FT_FAULT_LOD_INVERTED
  if (omegaLod >= omegaFiber) return 1.0f;
#else
  if (omegaLod <= omegaFiber) return 1.0f;
#endif
  if (omegaPly <= omegaLod) return 0.0f;
  return (omegaFiber / omegaLod) * ((omegaPly - omegaLod) / (omegaPly - omegaFiber));
}

// The segment lies in the convex hull of its Bézier points; it is outside
// the frustum when all four, grown by the yarn's bound radius, are behind one
// plane.
FT_FUNC bool ftSegmentOutsideFrustum(ViewParams v, YarnSegment seg, float margin) {
#ifdef FT_FAULT_CULL_MARGIN
  margin = 0.0f;  // forgets that fibers reach boundRadius beyond the yarn axis
#endif
  for (int i = 0; i < 6; ++i) {
    vec4 pl = v.frustumPlanes[i];
    vec3 n = vec3(pl);
    if (dot(n, vec3(seg.b0)) + pl.w < -margin && dot(n, vec3(seg.b1)) + pl.w < -margin &&
        dot(n, vec3(seg.b2)) + pl.w < -margin && dot(n, vec3(seg.b3)) + pl.w < -margin)
      return true;
  }
  return false;
}

// Pixel widths of a fiber and of a ply placed at the segment midpoint.
FT_FUNC vec2 ftScreenWidths(YarnParams p, ViewParams v, YarnSegment seg) {
  vec4 clip = v.viewProj * vec4(ftBezierPoint(seg, 0.5f), 1.0f);
  float pixelsPerUnit = v.cameraPos.w / max(clip.w, 1e-6f);
  return vec2(2.0f * p.fiberRadius * pixelsPerUnit, 2.0f * p.ellipseB * p.rhoMax * pixelsPerUnit);
}

FT_FUNC uint ftVertexCount(YarnParams p, SegmentDecision d) {
  if (d.culled != 0u) return 0u;
  return p.plyCount * (1u + d.regularCount) * (d.subdivisions + 1u);
}

// λ² scales the regular-fiber count, the subdivisions along the segment and
// the core thickness (between the core's own and the whole ply's), §3.3.
FT_FUNC SegmentDecision ftDecideSegment(YarnParams p, ViewParams v, YarnSegment seg) {
  SegmentDecision d;
  vec2 widths = ftScreenWidths(p, v, seg);
  d.lambda = v.lodEnabled != 0u ? ftLodLambda(widths.x, widths.y, v.lodThresholdPx) : 1.0f;
  FT_PRECISE float scale = d.lambda * d.lambda;
  FT_PRECISE float fibers = ceil(scale * float(p.regularFibers));
  FT_PRECISE float subdiv = ceil(scale * float(p.maxSubdivisions));
  d.regularCount = min(p.regularFibers, uint(fibers));
  d.subdivisions = clamp(uint(subdiv), 1u, p.maxSubdivisions);
  d.coreHalfWidth = p.ellipseB * mix(p.rhoMax, p.coreRadius, scale);
  d.culled = (v.cullEnabled != 0u && ftSegmentOutsideFrustum(v, seg, p.boundRadius)) ? 1u : 0u;
  d.vertexCount = 0u;
  d.vertexCount = ftVertexCount(p, d);
  d.pad0 = 0u;
  d.pad1 = 0u;
  return d;
}

FT_NAMESPACE_END
#endif  // FT_LOD_H
