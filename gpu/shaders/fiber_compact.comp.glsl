// Deferred shading, the compaction (docs/shaded-frame.md "Deferred shading";
// FiberRenderer::drawDeferred): lists each pixel's distinct hits. The
// visibility pass wrote, at every sample a fiber won, that fragment's hit
// record (fiber_strip.frag.glsl ftPackHit: everything the shading reads), so
// samples with bit-identical records get the same colour from the shading:
// one entry per distinct record, with the mask of the samples that hold it.
// The forward pass shades once per fragment and writes that colour to the
// fragment's covered samples, so a fragment's samples share one record and
// the deferred frame shades each visible fragment once, as the forward did.
// One work group per tile that fiber_compact_tiles.comp.glsl listed: the other
// tiles have no covered sample, hence no entry.
#include "common/constants.h"
#include "shaders/deferred_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_DEFERRED_COMPACT) in;

uniform uvec2 size;
uniform uint tileBase;  // deferred_resources.glsl
uniform uint groupsX;
uniform uint itemCount;
// Two-pass culling (common/occlusion_cull.h ftLineKey): the line of each
// hit, and the bit set of the lines this frame saw, for the next frame.
layout(binding = FT_TEX_HIT_LINE) uniform usampler2DMS hitLine;
layout(std430, binding = FT_SSBO_VISIBLE_LINES) buffer VisibleNow { uint visibleNow[]; };

// The record's 20 words at sample s, as bits (so that equality is exact).
void recordBits(ivec2 p, int s, out uvec4 r[FT_VISIBILITY_TARGETS]) {
  vec4 f[FT_VISIBILITY_TARGETS];
  hitRecordAt(p, s, f);
  for (int k = 0; k < FT_VISIBILITY_TARGETS; ++k) r[k] = floatBitsToUint(f[k]);
}

bool sameRecord(uvec4 a[FT_VISIBILITY_TARGETS], uvec4 b[FT_VISIBILITY_TARGETS]) {
  bool same = true;
  for (int k = 0; k < FT_VISIBILITY_TARGETS; ++k) same = same && all(equal(a[k], b[k]));
  return same;
}

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_DEFERRED_COMPACT);
  if (k >= itemCount) return;
  uint i = k % FT_WG_DEFERRED_COMPACT;
  uvec2 q = entries[tileBase + k / FT_WG_DEFERRED_COMPACT].xy * FT_DEFERRED_TILE +
            uvec2(i % FT_DEFERRED_TILE, i / FT_DEFERRED_TILE);
  if (q.x >= size.x || q.y >= size.y) return;
  ivec2 p = ivec2(q);
  uvec4 r[FT_DEFERRED_SAMPLES][FT_VISIBILITY_TARGETS];
  for (int s = 0; s < FT_DEFERRED_SAMPLES; ++s) recordBits(p, s, r[s]);
  // Group the covered samples (record 0's w ≠ 0) by record: each group's
  // first sample stands for it.
  uint left = 0u;
  for (int s = 0; s < FT_DEFERRED_SAMPLES; ++s)
    if (r[s][0].w != 0u) left |= 1u << s;
  uint masks[FT_DEFERRED_SAMPLES];
  uint firsts[FT_DEFERRED_SAMPLES];
  uint n = 0u;
  for (int s = 0; s < FT_DEFERRED_SAMPLES; ++s) {
    if ((left & (1u << s)) == 0u) continue;
    uint mask = 0u;
    for (int t = s; t < FT_DEFERRED_SAMPLES; ++t)
      if ((left & (1u << t)) != 0u && sameRecord(r[s], r[t])) mask |= 1u << t;
    left &= ~mask;
    masks[n] = mask;
    firsts[n] = uint(s);
    ++n;
  }
#ifdef FT_FAULT_DEFERRED_DROP_LAST_SAMPLE
  // The last covered sample of the pixel left out of its entry's mask.
  if (n > 0u && bitCount(masks[n - 1u]) > 1) masks[n - 1u] &= ~(1u << uint(findMSB(masks[n - 1u])));
#endif
  if (n == 0u) return;
  uint base = atomicAdd(header.x, n);
  for (uint i = 0u; i < n; ++i) entries[base + i] = uvec4(q, firsts[i], masks[i]);
  // Every covered sample's line, not each entry's first: two lines can leave
  // bit-identical records (a ray through the joint ball two neighbours of a
  // fiber share, the same pixel-centre ray for both), and the next frame's
  // first draw must hold both (on the glove, 5 of 56,542 samples).
  uint keys[FT_DEFERRED_SAMPLES];
  for (int s = 0; s < FT_DEFERRED_SAMPLES; ++s) {
    uint key = r[s][0].w != 0u ? texelFetch(hitLine, p, s).x : 0u;
    keys[s] = key;
    bool repeated = false;
    for (int t = 0; t < s; ++t) repeated = repeated || keys[t] == key;
#ifdef FT_FAULT_TWO_PASS_MARK_FIRST
    repeated = repeated || (s > 0 && keys[0] != 0u);  // planted: the pixel's first line only
#endif
    if (key != 0u && !repeated && (key - 1u) / 32u < uint(visibleNow.length()))
      atomicOr(visibleNow[(key - 1u) / 32u], 1u << ((key - 1u) % 32u));
  }
}
