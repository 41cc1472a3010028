// occlusion_cull.h — exact occlusion culling of the shaded frame's fiber lines
// (FiberRenderer::draw, docs/shaded-frame.md "Occlusion culling").
//
// Why: each fragment of a capsule impostor writes its own depth (the ray-cast
// hit), so llvmpipe cannot test depth before the fragment stage, and every
// fragment of every fiber was shaded: at the whole glove, ~40 capsule layers
// per covered pixel (thick cores of short lines over each other, both sides of
// the glove). Measured before this: 12 M shaded fragments for 0.3 M covered
// pixels.
//
// How: an occluder pass rasterises, for each line, a rectangle every eye ray
// through which surely hits the capsule (FT_OCCLUDER_WIDTH of the thinner
// end's radius on either side of the axis, between the ends), pushed back
// along the eye rays (by twice the radius and the depth's change over a pixel,
// fiber_strip.geom.glsl): the depth written is never nearer than the depth
// the visibility pass writes at that sample. A max-depth
// pyramid of it (level 0: the max over a pixel's samples; level k: the max of
// 2×2 texels of level k−1) then bounds what is visible. A line whose nearest
// possible depth (its nearest end moved towards the eye by its radius) lies
// behind the pyramid's max over its screen rectangle would fail the depth
// test at every sample it covers, so the geometry stage drops it; the
// fragment stage drops fragments the same way against level 0. Nothing that
// could be seen is dropped, so the frame is the same with and without it
// (checked bit for bit: tests/occlusion_cull_test.cpp, the harness's
// shading/occlusion-cull cases).
//
// Depths are window depths in [0, 1] (GL's default depth range), the values
// the depth buffer holds.
#ifndef FT_OCCLUSION_CULL_H
#define FT_OCCLUSION_CULL_H
#include "prelude.h"
#include "rng.h"
#include "view_params.h"

#define FT_OCCLUSION_MAX_LEVELS 16
// The occluder's half-width as a fraction of the line's thinner radius. It was
// ½ until the two ways an occluder sample could claim more than the frame
// draws were found (a grazing shading ray that misses, one depth per
// fragment; docs/shaded-frame.md "Wider occluders"); at 0.9 the close-up culls
// more (−13 % of its CPU). The rest of the radius is the margin for float
// rounding of the sample rays (0.01 px, shading/strip-rays/*).
#define FT_OCCLUDER_WIDTH 0.9
// ... for the core strips with the core-fiber texture, whose occluder keeps a
// pixel by one ray's hole test through a 5 % thinner capsule (and its 3 × 3
// texels): farther from the axis that ray's hit and the shaded pass's part
// by more texels, so these stay at ½ (at 0.9, 7 samples of the whole glove
// were claimed over holes).
#define FT_CORE_OCCLUDER_WIDTH 0.5

FT_NAMESPACE_BEGIN

struct OcclusionPyramid {
  uvec4 size;                                 // (width, height, levels, enabled: 0 or 1)
  uvec4 level[FT_OCCLUSION_MAX_LEVELS];       // (first texel, width, height, 0) of each level
};
FT_ASSERT_OFFSET(OcclusionPyramid, level, 16)
FT_ASSERT_SIZE(OcclusionPyramid, 16 + 16 * FT_OCCLUSION_MAX_LEVELS)

// The pyramid's levels for a width × height target: level k has
// ⌈width/2^k⌉ × ⌈height/2^k⌉ texels, down to 1 × 1 or the level cap.
FT_FUNC OcclusionPyramid ftOcclusionPyramidLayout(uint width, uint height) {
  OcclusionPyramid p;
  p.size = uvec4(width, height, 0u, 1u);
  uint first = 0u, w = max(width, 1u), h = max(height, 1u);
  for (uint k = 0u; k < uint(FT_OCCLUSION_MAX_LEVELS); ++k) {
    p.level[k] = p.size.z == 0u ? uvec4(first, w, h, 0u) : uvec4(0u);
    if (p.size.z != 0u) continue;
    first += w * h;
    if ((w == 1u && h == 1u) || k + 1u == uint(FT_OCCLUSION_MAX_LEVELS)) p.size.z = k + 1u;
    w = (w + 1u) / 2u;
    h = (h + 1u) / 2u;
  }
  return p;
}
FT_FUNC uint ftOcclusionTexelCount(OcclusionPyramid p) {
  uvec4 last = p.level[p.size.z - 1u];
  return last.x + last.y * last.z;
}
FT_FUNC uint ftOcclusionIndex(OcclusionPyramid p, uint level, uint x, uint y) {
  uvec4 l = p.level[level];
  return l.x + min(y, l.z - 1u) * l.y + min(x, l.y - 1u);
}

// The unit view axis: clip w is the view depth along it for the perspective
// cameras of scene/camera.h (a rigid view times a perspective projection);
// zero for any other projection (then nothing is culled).
FT_FUNC vec3 ftViewForward(ViewParams v) {
  vec3 forward = vec3(v.viewProj[0][3], v.viewProj[1][3], v.viewProj[2][3]);
  float f = length(forward);
  return f > 0.5f ? forward / f : vec3(0.0f);
}

// The window depth no point within `reach` of p can be nearer than: p moved
// towards the eye by `reach` along the view axis. 0 (nothing culled) when that
// point is not in front of the eye or the projection is not perspective.
FT_FUNC float ftNearestWindowDepth(ViewParams v, vec3 p, float reach) {
  vec3 forward = ftViewForward(v);
  if (dot(forward, forward) == 0.0f) return 0.0f;
#ifdef FT_FAULT_OCCLUSION_NEAREST_FAR
  vec4 c = v.viewProj * vec4(p + reach * forward, 1.0f);  // the capsule's far side taken for its near one
#else
  vec4 c = v.viewProj * vec4(p - reach * forward, 1.0f);
#endif
  if (!(c.w > 0.0f)) return 0.0f;
  return clamp(0.5f * (c.z / c.w) + 0.5f, 0.0f, 1.0f);
}

// The pyramid level at which the pixel rectangle [lo, hi] (inclusive pixel
// indices) spans at most FT_OCCLUSION_SPAN × FT_OCCLUSION_SPAN texels: the
// finer the level, the more lines a partly covered neighbourhood still hides
// (4 × 4 at level k against 2 × 2 at level k + 1).
#define FT_OCCLUSION_SPAN 4u

FT_FUNC uint ftOcclusionLevelFor(OcclusionPyramid p, uvec2 lo, uvec2 hi) {
  uint k = 0u;
  while (k + 1u < p.size.z && (((hi.x >> k) - (lo.x >> k)) >= FT_OCCLUSION_SPAN ||
                               ((hi.y >> k) - (lo.y >> k)) >= FT_OCCLUSION_SPAN))
    ++k;
  return k;
}

// Two-pass culling (docs/shaded-frame.md "Two-pass culling"; Haar and
// Aaltonen 2015, "GPU-Driven Rendering Pipelines", the last frame's visible
// set): a frame first draws the lines that won a sample of the previous
// frame, builds the pyramid from the depth they leave, and then draws the
// other lines against it, the test above. The depth buffer holds, at every
// sample, the nearest of what was drawn, so a line of the second draw that
// the pyramid drops could not have won a sample: the frame's depth is the
// same as with one draw of everything, whatever the previous frame saw, and
// its colour too where no two lines tie at a sample's depth (a tie goes to
// the line drawn first, and the first draw reorders lines). What the
// previous frame saw only decides how much the second draw saves.
//
// A line is named by its first vertex's FiberVertex.id (y global segment,
// z ply << 16 | fiber, w's bits 8..15 the vertex along the segment), the same
// on both paths and from frame to frame whatever the LoD draws elsewhere,
// hashed (ftPcg4d) to one of 2^bits marks. Two lines that share a mark are
// both drawn first when either was seen: a matter of time only.
FT_FUNC uint ftLineKey(uvec4 id, uint bits) {
  uvec4 h = ftPcg4d(uvec4(id.y, id.z, (id.w >> 8u) & 0xFFu, 0x9E3779B9u));
  return bits >= 32u ? h.x : h.x & ((1u << bits) - 1u);
}

// The draws of a two-pass frame and the lines each takes.
#define FT_TWO_PASS_ALL 0u     // one pass: every line
#define FT_TWO_PASS_SEEN 1u    // the first draw: the lines the last frame saw
#define FT_TWO_PASS_UNSEEN 2u  // the second draw: the others (those not behind the pyramid)

FT_NAMESPACE_END
#endif  // FT_OCCLUSION_CULL_H
