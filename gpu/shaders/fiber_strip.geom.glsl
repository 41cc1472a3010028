// Both paths: turns each fiber line into a screen-facing rectangle (one
// triangle around it when it is short and thin, below) that
// covers the line's capsule — the tube of the fiber's half-width around the
// line, closed by a ball at each end, the shape Embree's round linear curves
// have (reference/fiber_trace.cpp). The fragment stage ray-casts the capsule
// and discards what misses it, so the rectangle only has to be conservative:
// it spans the line's screen direction ± the larger radius and ± that radius
// across. A fiber seen end-on
// becomes a square around its end ball, not a degenerate sliver; consecutive
// lines share their end balls, so a fiber has no cracks at its vertices.
// Indifferent to fiber type: only the width differs.
//
// Under FT_OCCLUDER_PASS it emits instead the occluder of the line for
// occlusion culling (common/occlusion_cull.h): the part of the rectangle
// whose eye rays surely hit the capsule, pushed back by the radius. In the
// shaded pass it drops a line that lies wholly behind the occluders' depth
// pyramid.
#include "common/constants.h"
#include "common/occlusion_cull.h"
#include "common/view_params.h"

layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(std140, binding = FT_UBO_OCCLUSION) uniform OcclusionBlock { OcclusionPyramid pyramid; };
layout(std430, binding = FT_SSBO_OCCLUSION) readonly buffer OcclusionTexels { float occlusionTexels[]; };
uniform uint occluderTexturedCores;  // occluder pass: 1 when core strips carry the core-fiber texture (holes)

layout(location = 0) in vec4 fiberPosition[];
layout(location = 1) flat in uvec4 fiberId[];
layout(location = 2) in vec3 fiberTangent[];
layout(location = 3) in float fiberStripEnd[];  // 1 at the first or last vertex of a strip
layout(location = 4) in vec4 yarnCenterLength[];
layout(location = 5) in vec3 yarnNormal[];
layout(location = 6) in vec3 yarnBinormal[];
layout(location = 2) flat out uint stripType;
// A point of the fragment's eye ray: the world position on the rectangle,
// less the line's first end. Interpolated as world positions (units from the origin,
// rectangles ≈ 1e-3 wide) the attribute planes lost so much to float
// rounding that the rays through the multisample positions missed them by a
// median 0.06 px and up to 0.33 px at the glove close-up (measured by
// projecting them back, shading/strip-rays/*); as offsets within 0.01 px.
layout(location = 3) out vec3 stripOffset;
// The line, for the fragment stage's ray cast: end points, their unit
// tangents (fiber_strip_tangent.glsl) and half-widths.
layout(location = 5) flat out vec3 lineP0;
layout(location = 6) flat out vec3 lineP1;
layout(location = 7) flat out vec3 lineT0;
layout(location = 8) flat out vec3 lineT1;
layout(location = 9) flat out vec2 lineHalfWidth;
// The yarn frame at both ends (the fragment blends it at its hit) and the curve.
layout(location = 10) flat out vec4 lineYarnC0;
layout(location = 11) flat out vec4 lineYarnC1;
layout(location = 12) flat out vec3 lineYarnN0;
layout(location = 13) flat out vec3 lineYarnN1;
layout(location = 14) flat out vec3 lineYarnB0;
layout(location = 15) flat out vec3 lineYarnB1;
layout(location = 16) flat out uint lineCurve;
#ifdef FT_OCCLUSION_TEST
layout(location = 17) flat out float lineNearestDepth;  // no point of the line's capsule is nearer (window depth)
#endif
#ifdef FT_VISIBILITY_PASS
// Two-pass culling (common/occlusion_cull.h ftLineKey): the first draw takes
// the lines the previous frame saw, the second the others.
uniform uint twoPassDraw;  // FT_TWO_PASS_*: which lines
uniform uint lineKeyBits;  // log2 of the marks' count
layout(std430, binding = FT_SSBO_VISIBLE_LINES) readonly buffer VisibleLines { uint visibleLines[]; };
layout(location = 18) flat out uint lineKey;  // its key, which the fragment stage writes beside the hit
bool visibleLineBit(uint bit) {
  uint word = bit >> 5u;
  return word < uint(visibleLines.length()) && ((visibleLines[word] >> (bit & 31u)) & 1u) != 0u;
}
#endif

// Any unit vector ⟂ e.
vec3 anyPerpendicular(vec3 e) {
  vec3 c = abs(e.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
  return normalize(cross(e, c));
}

void main() {
  // A hair's free end: the next period restarts at the ply, so a line
  // crossing from a hair period into another period is not drawn.
  uint type0 = fiberId[0].w & 0xFFu;
  uint type1 = fiberId[1].w & 0xFFu;
  bool periodChange = (fiberId[0].w >> 16u) != (fiberId[1].w >> 16u);
  if (periodChange && (type0 == FT_FIBER_HAIR || type1 == FT_FIBER_HAIR)) return;
#ifdef FT_VISIBILITY_PASS
  uint key = ftLineKey(fiberId[0], lineKeyBits);
  if (twoPassDraw != FT_TWO_PASS_ALL && visibleLineBit(key) != (twoPassDraw == FT_TWO_PASS_SEEN)) return;
#endif

  vec3 p0 = fiberPosition[0].xyz, p1 = fiberPosition[1].xyz;
  vec3 chord = p1 - p0;
  if (dot(chord, chord) <= 0.0) return;
  vec3 a = normalize(chord);
#ifdef FT_FAULT_STRIP_HALF_WIDTH
  vec2 w = 0.5 * vec2(fiberPosition[0].w, fiberPosition[1].w);
#else
  vec2 w = vec2(fiberPosition[0].w, fiberPosition[1].w);
#endif
  vec3 t0 = dot(fiberTangent[0], fiberTangent[0]) > 0.0 ? normalize(fiberTangent[0]) : a;
  vec3 t1 = dot(fiberTangent[1], fiberTangent[1]) > 0.0 ? normalize(fiberTangent[1]) : a;

  // The rectangle lies in the plane through the line's midpoint facing the
  // eye; `along` is the line's direction in it, `across` ⟂ both. Each end
  // is carried onto the plane along its eye ray, its radius with it.
  vec3 eye = view.cameraPos.xyz;
  vec3 e = eye - 0.5 * (p0 + p1);
  float planeDepth = length(e);
  if (planeDepth <= 0.0) return;
  e /= planeDepth;
  vec3 q[2];
  float r[2], ext[2];
  vec3 tEnd[2] = vec3[2](t0, t1);
  for (int i = 0; i < 2; ++i) {
    vec3 p = i == 0 ? p0 : p1;
    float depth = dot(eye - p, e);
    // The end's margin: the larger radius and 2 % for the ball's perspective
    // silhouette (asin against atan of radius/depth). Every multisample
    // position inside the capsule's silhouette is then inside the rectangle;
    // the fragment stage decides coverage per sample. An end behind the eye
    // keeps its place.
    float scale = depth > 1e-6 * planeDepth ? planeDepth / depth : 1.0;
    q[i] = eye - (eye - p) * scale;
    r[i] = 1.02 * max(w.x, w.y) * scale;
    // Along the line, a strip's own end needs the whole ball. A joint inside
    // a strip needs the tube's end disc, which reaches w·|a·e| past the end
    // on screen, and the wedge of the joint's ball between this tube and the
    // next on the outside of the bend, w·sin φ with φ ≈ twice the angle
    // between the chord and the vertex tangent. (All of the ball would double
    // the fragments of thick, finely divided cores.)
    float sinHalfBend = length(cross(a, tEnd[i]));
    ext[i] = fiberStripEnd[i] > 0.5 ? r[i] : r[i] * min(1.0, abs(dot(a, e)) + 2.0 * sinHalfBend + 0.01);
  }
  vec3 along = q[1] - q[0];
  along -= dot(along, e) * e;
  along = dot(along, along) > 1e-12 * dot(chord, chord) ? normalize(along) : anyPerpendicular(e);
  vec3 across = cross(e, along);
  float R = max(r[0], r[1]);
  vec3 corners[4] = vec3[4](q[0] - ext[0] * along - R * across, q[0] - ext[0] * along + R * across,
                            q[1] + ext[1] * along - R * across, q[1] + ext[1] * along + R * across);
#ifdef FT_OCCLUDER_PASS
  // Every eye ray through the part of the rectangle between the ends and
  // within k of the thinner end's radius of the axis (k: FT_OCCLUDER_WIDTH,
  // 0.9, for plain lines; FT_CORE_OCCLUDER_WIDTH, ½, for textured cores)
  // passes the axis within k radii, so it hits the capsule (the fragment
  // stage never shades such a pixel through a grazing ray, which could miss). Its corners go back along
  // their eye rays to the view depth of their end plus twice its radius (no
  // point of the capsule, nor the core-fiber texture's surface, is deeper at
  // that end) plus how far the axis's depth moves over a pixel along the line:
  // the visibility pass writes one depth per fragment, its shading ray's, which
  // may lie up to 0.8 px from the sample (the farthest two of the pixel centre
  // and the four sample positions). 1/z is affine along the line's projection,
  // so over 1 px of its L px the depth moves at most |z1 − z0| · (z_max / z_min) / L,
  // and never more than |z1 − z0|. The fragment stage removes the core
  // texture's holes.
  vec3 forward = ftViewForward(view);
  if (dot(forward, forward) == 0.0) return;  // not a perspective view: no occluders
  // Two draws (FiberRenderer::drawOccluders): the plain lines, with core
  // strips among them when they have no holes, and the textured core strips.
#ifdef FT_OCCLUDER_PLAIN
  if (type0 == FT_FIBER_CORE && occluderTexturedCores != 0u) return;
#else
  if (type0 != FT_FIBER_CORE) return;
#endif
#ifdef FT_OCCLUDER_PLAIN
  const float widthFraction = FT_OCCLUDER_WIDTH;
#else
  const float widthFraction = FT_CORE_OCCLUDER_WIDTH;
#endif
  float inner = widthFraction * min(w.x, w.y) * planeDepth / max(dot(eye - p0, e), dot(eye - p1, e));
  float z0 = dot(p0 - eye, forward), z1 = dot(p1 - eye, forward);
  float lengthPx = length(q[1] - q[0]) * view.cameraPos.w / planeDepth;
  float slopePush = abs(z1 - z0) * min(1.0, max(z0, z1) / max(min(z0, z1), 1e-30) / max(lengthPx, 1e-30));
  for (int i = 0; i < 4; ++i) {
    int end = i / 2;
    corners[i] = q[end] + ((i & 1) == 0 ? -inner : inner) * across;
    float cornerDepth = dot(corners[i] - eye, forward);
    if (!(cornerDepth > 0.0)) return;  // a corner at or behind the eye: no occluder
#ifdef FT_FAULT_OCCLUDER_NOT_PUSHED
    float push = 0.0;  // the occluder left at its end's axis depth: nearer than the capsule's side
#elif defined(FT_FAULT_OCCLUDER_NO_SLOPE_PUSH)
    float push = 2.0 * w[end];  // the depth's change over the fragment's pixel forgotten
#else
    float push = 2.0 * w[end] + slopePush;
#endif
    corners[i] = eye + (corners[i] - eye) * ((dot((end == 0 ? p0 : p1) - eye, forward) + push) / cornerDepth);
  }
  float nearest = 0.0;
#else
  // The core-fiber texture moves a core's hit up to √2 of its half-width off
  // the axis (fiber_strip.frag.glsl): 1.5 covers every type.
  float nearest = min(ftNearestWindowDepth(view, p0, 1.5 * w.x), ftNearestWindowDepth(view, p1, 1.5 * w.y));
#endif
  vec4 clip[4];
  for (int i = 0; i < 4; ++i) clip[i] = view.viewProj * vec4(corners[i], 1.0);
#ifdef FT_OCCLUDER_PASS
  const int vertices = 4;
#else
  // A short, thin rectangle as one triangle: its two triangles' shared
  // diagonal crosses nearly every 4 x 4 block it touches, and llvmpipe runs
  // the fragment shader on each block once per triangle and sets up every
  // varying per triangle, so one triangle of twice the area (base 4R across
  // the start, apex 2A along: it contains the A x 2R rectangle) costs less.
  // At the whole glove, where the cores are ~2 px wide and ~1.5 px long, the
  // visibility pass took 7-12 % less CPU; long or wide rectangles stay (the
  // triangle's extra area costs more there). The casts and coverage tests are
  // the same; only the rounding of the interpolated ray origin differs
  // (docs/shaded-frame.md, "One triangle for a short, thin line").
  int vertices = 4;
  vec3 start = q[0] - ext[0] * along;
  float rectLength = dot(q[1] - q[0], along) + ext[0] + ext[1];
#ifdef FT_STRIP_RECTANGLES
  // Every line as its rectangle (validation/strip_impostor_cases.cpp).
  if (false) {
#else
  if (2.0 * R * view.cameraPos.w < 8.0 * planeDepth && rectLength < 3.0 * R) {
#endif
#ifdef FT_FAULT_STRIP_TRIANGLE_NARROW
    // Planted fault: a base of 2R, the rectangle's own width; the rectangle's
    // sides stick out of the triangle's.
    corners[0] = start - R * across;
    corners[1] = start + R * across;
#else
    corners[0] = start - 2.0 * R * across;
    corners[1] = start + 2.0 * R * across;
#endif
    corners[2] = start + 2.0 * rectLength * along;
    for (int i = 0; i < 3; ++i) clip[i] = view.viewProj * vec4(corners[i], 1.0);
    vertices = 3;
  }
#endif
#ifdef FT_OCCLUSION_TEST
  // The pixels where a sample of the line can be covered: inside what is
  // rasterised, and inside the capsule's silhouette, which the rectangle
  // holds when it takes the whole end ball at both ends. The triangle of a
  // short line holds samples outside the drawn rectangle, near a joint, that
  // the end ball covers (on the glove's close-up one sample of a visible line
  // was lost to the drawn rectangle's box). The triangle's own box, four
  // times the rectangle's, let 422 k triangles of the whole glove through
  // where this lets 390 k (docs/shaded-frame.md, two-pass culling).
#ifdef FT_FAULT_OCCLUSION_BOX_RECTANGLE
  vec2 reach = vec2(ext[0], ext[1]);  // planted: the drawn rectangle's ends, whatever is drawn
#else
  vec2 reach = vec2(r[0], r[1]);
#endif
  vec4 boxClip[8];
  for (int i = 0; i < 4; ++i) {
    boxClip[i] = clip[min(i, vertices - 1)];
    vec3 c = q[i / 2] + (i < 2 ? -reach.x : reach.y) * along + ((i & 1) == 0 ? -R : R) * across;
    boxClip[4 + i] = view.viewProj * vec4(c, 1.0);
  }
  bool boxInFront = true;
  for (int i = 0; i < 8; ++i) boxInFront = boxInFront && boxClip[i].w > 0.0;
  if (pyramid.size.w != 0u && boxInFront) {
    vec2 drawnLo = vec2(3.0e38), drawnHi = vec2(-3.0e38), ballLo = vec2(3.0e38), ballHi = vec2(-3.0e38);
    for (int i = 0; i < 4; ++i) {
      vec2 drawn = (0.5 * boxClip[i].xy / boxClip[i].w + 0.5) * vec2(pyramid.size.xy);
      vec2 ball = (0.5 * boxClip[4 + i].xy / boxClip[4 + i].w + 0.5) * vec2(pyramid.size.xy);
      drawnLo = min(drawnLo, drawn);
      drawnHi = max(drawnHi, drawn);
      ballLo = min(ballLo, ball);
      ballHi = max(ballHi, ball);
    }
    vec2 lo = max(drawnLo, ballLo), hi = min(drawnHi, ballHi);
    vec2 size = vec2(pyramid.size.xy);
    if (hi.x >= 0.0 && hi.y >= 0.0 && lo.x < size.x && lo.y < size.y) {
      uvec2 a = uvec2(clamp(floor(lo), vec2(0.0), size - 1.0)), b = uvec2(clamp(floor(hi), vec2(0.0), size - 1.0));
      uint k = ftOcclusionLevelFor(pyramid, a, b);
      float deepest = 0.0;
      for (uint y = a.y >> k; y <= (b.y >> k); ++y)
        for (uint x = a.x >> k; x <= (b.x >> k); ++x) deepest = max(deepest, occlusionTexels[ftOcclusionIndex(pyramid, k, x, y)]);
      if (nearest > deepest) return;  // behind the occluders at every pixel it could cover
    }
  }
#endif
  for (int i = 0; i < vertices; ++i) {
    stripType = i < 2 ? type0 : type1;
#ifdef FT_FAULT_STRIP_WORLD_ABSOLUTE
    stripOffset = corners[i];
#else
    stripOffset = corners[i] - p0;
#endif
    lineP0 = p0;
    lineP1 = p1;
    lineT0 = t0;
    lineT1 = t1;
    lineHalfWidth = w;
    lineYarnC0 = yarnCenterLength[0];
    lineYarnC1 = yarnCenterLength[1];
    lineYarnN0 = yarnNormal[0];
    lineYarnN1 = yarnNormal[1];
    lineYarnB0 = yarnBinormal[0];
    lineYarnB1 = yarnBinormal[1];
    lineCurve = fiberId[0].x;
#ifdef FT_OCCLUSION_TEST
    lineNearestDepth = nearest;
#endif
#ifdef FT_VISIBILITY_PASS
    lineKey = key;
#endif
    gl_Position = clip[i];
    EmitVertex();
  }
  EndPrimitive();
}
