// Deferred shading, the shading (docs/shaded-frame.md "Deferred shading";
// FiberRenderer::drawDeferred): shadeFiber of the forward pass
// (fiber_strip.frag.glsl, included without its fragment stage) once per
// entry of the compaction's list (fiber_compact.comp.glsl), on the hit record
// the visibility pass wrote at the entry's sample; the colour goes to the
// entry's samples of the shaded target, every other sample keeps the clear
// colour, as in the forward frame. (Stored here, not by a draw of one point per
// entry with gl_SampleMask: on llvmpipe that draw cost 83-93 ms at the whole
// glove, docs/shaded-frame.md.)
#include "common/constants.h"
#define FT_DEFERRED_SHADE
#include "fiber_strip.frag.glsl"
#include "shaders/deferred_resources.glsl"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_DEFERRED_SHADE) in;
layout(binding = FT_IMAGE_SHADED, rgba32f) writeonly uniform image2DMS shadedImage;

uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_DEFERRED_SHADE);
  if (k >= itemCount) return;
  uvec4 w = entries[k];
  ivec2 p = ivec2(w.xy);
  int s = int(w.z);
#ifdef FT_FAULT_DEFERRED_WRONG_SAMPLE
  s = (s + 1) % FT_DEFERRED_SAMPLES;  // the record of the pixel's next sample shaded instead
#endif
  vec4 r[FT_VISIBILITY_TARGETS];
  hitRecordAt(p, s, r);
  FiberHit h;
  uint type;
  ftUnpackHit(r, h, type);
  // A textured core (the condition of the visibility pass's applyCoreTexture):
  // the record holds what the texture's normal and direction are computed from.
  if (type == FT_FIBER_CORE && (shading.flags.w & FT_APPEARANCE_CORE_TEXTURE) != 0u) finishCoreTexture(h);
  vec4 color = vec4(shadeFiberOfType(h, type), 1.0);
  uint mask = w.w;
#ifdef FT_FAULT_DEFERRED_RESOLVE_ALL_SAMPLES
  mask = (1u << FT_DEFERRED_SAMPLES) - 1u;  // every sample of the pixel, whoever won it
#endif
  for (int t = 0; t < FT_DEFERRED_SAMPLES; ++t)
    if ((mask & (1u << t)) != 0u) imageStore(shadedImage, p, t, color);
}
