// Deferred shading, the resolve (docs/shaded-frame.md "Deferred shading";
// FiberRenderer::drawDeferred): one point per entry of the shaded list, at its
// pixel's centre; the fragment stage writes the entry's colour to the entry's
// samples (gl_SampleMask), so that every sample gets what the forward pass
// wrote there.
#include "common/constants.h"
#include "shaders/deferred_resources.glsl"
uniform uvec2 size;

layout(location = 0) flat out vec4 entryColor;
layout(location = 1) flat out uint entryMask;

void main() {
  DeferredEntry e = entries[gl_VertexID];
  entryColor = e.color;
  entryMask = e.where.w;
  gl_Position = vec4((vec2(e.where.xy) + 0.5) / vec2(size) * 2.0 - 1.0, 0.0, 1.0);
  gl_PointSize = 1.0;
}
