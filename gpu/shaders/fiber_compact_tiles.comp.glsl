// Deferred shading, before the compaction (docs/shaded-frame.md "Deferred
// shading"; FiberRenderer::drawDeferred): lists the 8 × 8-pixel tiles that
// hold a covered sample, so that the compaction reads the records of those
// tiles only. On llvmpipe a compute invocation runs all of its code, so the
// compaction's 20 record reads per sample cost as much on the background as
// on the fibres (about 0.2 s of the whole glove's frame at 1280 × 960, where
// fibres cover a quarter of the pixels); this kernel reads one word per sample.
#include "common/constants.h"
#include "shaders/deferred_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_DEFERRED_TILES) in;

uniform uvec2 size;
uniform uint tileBase;  // deferred_resources.glsl
uniform uint groupsX;
uniform uint itemCount;
layout(binding = FT_TEX_HIT_LINE) uniform usampler2DMS hitLine;

void main() {
  uint t = flatInvocationIndex(groupsX, FT_WG_DEFERRED_TILES);
  if (t >= itemCount) return;
  uint tilesX = (size.x + FT_DEFERRED_TILE - 1u) / FT_DEFERRED_TILE;
  uvec2 tile = uvec2(t % tilesX, t / tilesX);
  bool covered = false;
  // A loop, not unrolled code: llvmpipe leaves it once every lane has found a covered sample.
  for (uint i = 0u; i < FT_DEFERRED_TILE * FT_DEFERRED_TILE && !covered; ++i) {
    uvec2 q = tile * FT_DEFERRED_TILE + uvec2(i % FT_DEFERRED_TILE, i / FT_DEFERRED_TILE);
    if (q.x >= size.x || q.y >= size.y) continue;
    for (int s = 0; s < FT_DEFERRED_SAMPLES; ++s) covered = covered || texelFetch(hitLine, ivec2(q), s).x != 0u;
  }
#ifdef FT_FAULT_DEFERRED_TILE_FIRST_ROW
  covered = false;  // planted: only the tile's first row looked at
  for (uint i = 0u; i < FT_DEFERRED_TILE; ++i) {
    uvec2 q = tile * FT_DEFERRED_TILE + uvec2(i, 0u);
    if (q.x >= size.x || q.y >= size.y) continue;
    for (int s = 0; s < FT_DEFERRED_SAMPLES; ++s) covered = covered || texelFetch(hitLine, ivec2(q), s).x != 0u;
  }
#endif
  if (covered) entries[tileBase + atomicAdd(header.y, 1u)] = uvec4(tile, 0u, 0u);
}
