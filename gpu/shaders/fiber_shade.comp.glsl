// Deferred shading, the shading (docs/shaded-frame.md "Deferred shading";
// FiberRenderer::drawDeferred): shadeFiber of the forward pass
// (fiber_strip.frag.glsl, included without its fragment stage) once per
// entry of the compaction's list (fiber_compact.comp.glsl), on the hit record
// the visibility pass wrote at the entry's sample. fiber_resolve.*.glsl then
// writes the colour to the entry's samples.
#include "common/constants.h"
#define FT_DEFERRED_SHADE
#include "fiber_strip.frag.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_DEFERRED_SHADE) in;

layout(binding = FT_TEX_HIT_RECORD0 + 0) uniform sampler2DMS hitRecord0;
layout(binding = FT_TEX_HIT_RECORD0 + 1) uniform sampler2DMS hitRecord1;
layout(binding = FT_TEX_HIT_RECORD0 + 2) uniform sampler2DMS hitRecord2;
layout(binding = FT_TEX_HIT_RECORD0 + 3) uniform sampler2DMS hitRecord3;
layout(binding = FT_TEX_HIT_RECORD0 + 4) uniform sampler2DMS hitRecord4;
struct DeferredEntry {
  uvec4 where;  // (x, y, sample, mask)
  vec4 color;
};
layout(std430, binding = FT_SSBO_DEFERRED_LIST) buffer DeferredList {
  uvec4 header;
  DeferredEntry entries[];
};

uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_DEFERRED_SHADE);
  if (k >= itemCount) return;
  uvec4 w = entries[k].where;
  ivec2 p = ivec2(w.xy);
  int s = int(w.z);
#ifdef FT_FAULT_DEFERRED_WRONG_SAMPLE
  s = (s + 1) % FT_DEFERRED_SAMPLES;  // the record of the pixel's next sample shaded instead
#endif
  vec4 r[FT_VISIBILITY_TARGETS];
  r[0] = texelFetch(hitRecord0, p, s);
  r[1] = texelFetch(hitRecord1, p, s);
  r[2] = texelFetch(hitRecord2, p, s);
  r[3] = texelFetch(hitRecord3, p, s);
  r[4] = texelFetch(hitRecord4, p, s);
  FiberHit h;
  uint type;
  ftUnpackHit(r, h, type);
  entries[k].color = vec4(shadeFiberOfType(h, type), 1.0);
}
