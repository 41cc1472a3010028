// deferred_resources.glsl — GLSL-only include of deferred shading's kernels
// (FiberRenderer::drawDeferred): the visibility pass's hit records and the
// list of distinct hits. Not a stage of its own.
#include "common/constants.h"

layout(binding = FT_TEX_HIT_RECORD0 + 0) uniform sampler2DMS hitRecord0;
layout(binding = FT_TEX_HIT_RECORD0 + 1) uniform sampler2DMS hitRecord1;
layout(binding = FT_TEX_HIT_RECORD0 + 2) uniform sampler2DMS hitRecord2;
layout(binding = FT_TEX_HIT_RECORD0 + 3) uniform sampler2DMS hitRecord3;
layout(binding = FT_TEX_HIT_RECORD0 + 4) uniform sampler2DMS hitRecord4;
// header.x: the entry count, header.y: the tile count; then per entry (x, y,
// the sample whose record is shaded, sample mask), with room for one entry
// per sample of the target; after that room, from entries[tileBase] on
// (W·H·FT_DEFERRED_SAMPLES, a uniform of the kernels that use it), the tiles
// that hold a covered sample (fiber_compact_tiles.comp.glsl), (x, y) in tiles.
layout(std430, binding = FT_SSBO_DEFERRED_LIST) buffer DeferredList {
  uvec4 header;
  uvec4 entries[];
};

// The hit record at sample s of pixel p (fiber_strip.frag.glsl ftPackHit).
void hitRecordAt(ivec2 p, int s, out vec4 r[FT_VISIBILITY_TARGETS]) {
  r[0] = texelFetch(hitRecord0, p, s);
  r[1] = texelFetch(hitRecord1, p, s);
  r[2] = texelFetch(hitRecord2, p, s);
  r[3] = texelFetch(hitRecord3, p, s);
  r[4] = texelFetch(hitRecord4, p, s);
}
