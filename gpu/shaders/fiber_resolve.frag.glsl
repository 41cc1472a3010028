// Deferred shading, the resolve: fiber_resolve.vert.glsl.
layout(location = 0) flat in vec4 entryColor;
layout(location = 1) flat in uint entryMask;
layout(location = 0) out vec4 color;

void main() {
#ifdef FT_FAULT_DEFERRED_RESOLVE_ALL_SAMPLES
  gl_SampleMask[0] = -1;  // every sample of the pixel, whoever won it
#else
  gl_SampleMask[0] = int(entryMask);
#endif
  color = entryColor;
}
