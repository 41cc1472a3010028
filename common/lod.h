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

// Planted fault (validation/faults.def), shared: run-time switch in C++, define in GLSL.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultCoreLinesOne = false;
inline bool ftFaultLodCountCeil = false;
}
#define FT_FAULT_CORE_LINES_ONE_ON ::ft::ftFaultCoreLinesOne
#define FT_FAULT_LOD_COUNT_CEIL_ON ::ft::ftFaultLodCountCeil
#else
#ifdef FT_FAULT_CORE_LINES_ONE
#define FT_FAULT_CORE_LINES_ONE_ON true
#else
#define FT_FAULT_CORE_LINES_ONE_ON false
#endif
#ifdef FT_FAULT_LOD_COUNT_CEIL
#define FT_FAULT_LOD_COUNT_CEIL_ON true
#else
#define FT_FAULT_LOD_COUNT_CEIL_ON false
#endif
#endif

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

// Pixel widths of a fiber and of a ply placed at `point`.
FT_FUNC vec2 ftScreenWidthsAt(YarnParams p, ViewParams v, vec3 point) {
  vec4 clip = v.viewProj * vec4(point, 1.0f);
  float pixelsPerUnit = v.cameraPos.w / max(clip.w, 1e-6f);
  return vec2(2.0f * p.fiberRadius * pixelsPerUnit, 2.0f * p.ellipseB * p.rhoMax * pixelsPerUnit);
}

// ... at the segment midpoint: the widths that decide the segment's λ.
FT_FUNC vec2 ftScreenWidths(YarnParams p, ViewParams v, YarnSegment seg) {
  return ftScreenWidthsAt(p, v, ftBezierPoint(seg, 0.5f));
}

// Core half-width at a knot: λ² moves it from the core's own radius towards
// the whole ply (§3.3). Taken at the knot rather than per segment, so the
// two segments meeting there agree and the core strip has no step.
FT_FUNC float ftCoreHalfWidthAt(YarnParams p, ViewParams v, vec3 knot) {
  vec2 w = ftScreenWidthsAt(p, v, knot);
  float lambda = v.lodEnabled != 0u ? ftLodLambda(w.x, w.y, v.lodThresholdPx) : 1.0f;
  return p.ellipseB * mix(p.rhoMax, p.coreRadius, lambda * lambda);
}

FT_FUNC uint ftVertexCount(YarnParams p, SegmentDecision d) {
  if (d.culled != 0u) return 0u;
  return p.plyCount * ftPlyVertexCount(d);
}

// Pixels per world unit at the segment: the largest over its Bézier points
// (the nearest one decides what a person sees).
FT_FUNC float ftSegmentPixelsPerUnit(ViewParams v, YarnSegment seg) {
  float w = min(min((v.viewProj * vec4(vec3(seg.b0), 1.0f)).w, (v.viewProj * vec4(vec3(seg.b1), 1.0f)).w),
                min((v.viewProj * vec4(vec3(seg.b2), 1.0f)).w, (v.viewProj * vec4(vec3(seg.b3), 1.0f)).w));
  return v.cameraPos.w / max(w, 1e-6f);
}

// Angle between two control-polygon legs; 0 where a leg has no length.
FT_FUNC float ftLegAngle(vec3 a, vec3 b) {
  float len2 = dot(a, a) * dot(b, b);
  if (!(len2 > 0.0f)) return 0.0f;
  return acos(clamp(dot(a, b) / sqrt(len2), -1.0f, 1.0f));
}

// Line segments a fiber needs along this yarn segment so that its polyline
// stays within v.chordErrorPx of the curve on screen, before rounding up.
//
// A polyline through n uniform samples of x(t), t ∈ [0, 1], deviates from
// the curve by at most max|x''| / (8 n²) (the chord sagitta). A fiber point
// is the yarn centre plus the ply offset (radius R_ply) plus the fiber offset
// (radius ≤ R_fib = max(e_N, e_B)·ρ_max), each turning with the frame:
//   |x''| ≤ |c''| + R_ply (ω_ply + Θ)² + R_fib (ω_ply + ω_fib + Θ)² + A_mig ω_mig²,
// with ω the twist and migration angles per unit t (2π · rate · Δs, §3.1,
// eq. 1–2), Θ the turning of the yarn's frame, bounded by the turning of the
// Bézier control polygon (a Bézier curve turns no more than its polygon),
// and |c''| ≤ 6 max|b_i − 2 b_{i+1} + b_{i+2}|. The bound is evaluated at the
// nearest control point's depth. It depends on what the segment covers on
// screen only — not on λ of eq. 4, which decides how many fibers are drawn.
// Twist rates are the preset's; closed curves round them by < ½ turn per
// loop (fiber_geometry.h), which changes the bound by a fraction of a percent.
// `fibers` = 0 bounds the ply centre alone: the path of the core strip.
FT_FUNC float ftSubdivisionBound(YarnParams p, ViewParams v, YarnSegment seg, bool fibers) {
  if (!(v.chordErrorPx > 0.0f)) return float(p.maxSubdivisions);  // 0: always the cap (full detail)
  vec3 b0 = vec3(seg.b0);
  vec3 b1 = vec3(seg.b1);
  vec3 b2 = vec3(seg.b2);
  vec3 b3 = vec3(seg.b3);
  float centre = 6.0f * max(length(b0 - 2.0f * b1 + b2), length(b1 - 2.0f * b2 + b3));
  float turning = ftLegAngle(b1 - b0, b2 - b1) + ftLegAngle(b2 - b1, b3 - b2);
  float ds = abs(seg.s1 - seg.s0);
  float wPly = FT_TWO_PI * p.plyTurnsPerLength * ds;
  float wFib = FT_TWO_PI * p.fiberTurnsPerLength * ds;
  float wMig = wFib * p.migrationS;
  float rFib = fibers ? max(p.ellipseN, p.ellipseB) * p.rhoMax : 0.0f;
  float aMig = 0.5f * (p.rhoMax - p.rhoMin) * rFib;
  FT_PRECISE float accel = centre + p.plyRadius * (wPly + turning) * (wPly + turning) +
                rFib * (wPly + wFib + turning) * (wPly + wFib + turning) + aMig * wMig * wMig;
  FT_PRECISE float n = sqrt(accel * ftSegmentPixelsPerUnit(v, seg) / (8.0f * v.chordErrorPx));
  return n;
}
FT_FUNC float ftSubdivisionEstimate(YarnParams p, ViewParams v, YarnSegment seg) {
  return ftSubdivisionBound(p, v, seg, true);
}
// The same bound for the core strip, which runs along the ply centre: no
// fiber twist or migration term. Far away, where λ of eq. 4 leaves one or
// two thin regular fibers per ply, those set the subdivisions, and the thick
// cores drew lines shorter than a pixel, each of which the fragment stage
// paid for several times (docs/shaded-frame.md).
FT_FUNC float ftCoreSubdivisionEstimate(YarnParams p, ViewParams v, YarnSegment seg) {
  return ftSubdivisionBound(p, v, seg, false);
}

// λ² scales the regular-fiber count and the core thickness (between the
// core's own and the whole ply's, ftCoreHalfWidthAt), §3.3; the subdivisions
// follow the screen (ftSubdivisionEstimate).
//
// The count is λ² n_max (eq. 4) to the nearest whole fiber. Rounding up kept
// one regular fiber per ply wherever λ > 0: at the whole glove λ² n_max is
// ~0.01, so every ply drew a sub-pixel fiber 100 times more often than eq. 4
// asks, for about a sixth of the frame's time and no gain in fidelity
// against the all-fiber reference (docs/shaded-frame.md, "Eq. 4's count").
FT_FUNC SegmentDecision ftDecideSegment(YarnParams p, ViewParams v, YarnSegment seg) {
  SegmentDecision d;
  vec2 widths = ftScreenWidths(p, v, seg);
  d.lambda = v.lodEnabled != 0u ? ftLodLambda(widths.x, widths.y, v.lodThresholdPx) : 1.0f;
  FT_PRECISE float scale = d.lambda * d.lambda;
  FT_PRECISE float fibers = floor(scale * float(p.regularFibers) + 0.5f);
  if (FT_FAULT_LOD_COUNT_CEIL_ON) fibers = ceil(scale * float(p.regularFibers));  // at least one fiber while λ > 0
#ifdef FT_FAULT_SUBDIVISIONS_LAMBDA
  FT_PRECISE float subdiv = ceil(scale * ftSubdivisionEstimate(p, v, seg));
#else
  FT_PRECISE float subdiv = ceil(ftSubdivisionEstimate(p, v, seg));
#endif
  d.regularCount = min(p.regularFibers, uint(fibers));
  d.subdivisions = uint(clamp(subdiv, 1.0f, float(p.maxSubdivisions)));
  // The core strip: its own bound, never more lines than the fibers'.
#ifdef FT_FAULT_SUBDIVISIONS_LAMBDA
  FT_PRECISE float coreSubdiv = ceil(scale * ftCoreSubdivisionEstimate(p, v, seg));
#else
  FT_PRECISE float coreSubdiv = ceil(ftCoreSubdivisionEstimate(p, v, seg));
#endif
  if (FT_FAULT_CORE_LINES_ONE_ON) coreSubdiv = 1.0f;  // one line per core: its chord far off the ply's helix
  d.coreLines = uint(clamp(coreSubdiv, 1.0f, float(d.subdivisions)));
  d.coreHalfWidth = ftCoreHalfWidthAt(p, v, vec3(seg.b0));
  d.coreHalfWidthEnd = ftCoreHalfWidthAt(p, v, vec3(seg.b3));
  d.culled = (v.cullEnabled != 0u && ftSegmentOutsideFrustum(v, seg, p.boundRadius)) ? 1u : 0u;
  d.vertexCount = 0u;
  d.vertexCount = ftVertexCount(p, d);
  return d;
}

FT_NAMESPACE_END
#endif  // FT_LOD_H
