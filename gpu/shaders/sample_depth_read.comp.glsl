// Copies a 4× multisampled depth texture into a float buffer, sample by
// sample (FiberRenderer::readSampleDepths): GL reads no multisampled image
// back directly. For the harness's check that the occluder pass never claims
// a sample nearer than the frame draws it (validation/occlusion_cull_cases.cpp);
// with FT_SAMPLE_READ_UINT the line keys of a deferred frame, for the check
// that two-pass culling marked every line the frame saw (two_pass_cull_cases.cpp).
#include "common/constants.h"

layout(local_size_x = FT_WG_OCCLUSION, local_size_y = FT_WG_OCCLUSION) in;
#ifdef FT_SAMPLE_READ_UINT
// The deferred frame's line keys (FT_TEX_HIT_LINE) instead.
layout(std430, binding = FT_SSBO_SAMPLE_DEPTHS) writeonly buffer SampleDepths { uint sampleDepths[]; };
layout(binding = FT_TEX_OCCLUDER_DEPTH) uniform usampler2DMS depthSamples;
#else
layout(std430, binding = FT_SSBO_SAMPLE_DEPTHS) writeonly buffer SampleDepths { float sampleDepths[]; };
layout(binding = FT_TEX_OCCLUDER_DEPTH) uniform sampler2DMS depthSamples;
#endif
uniform uint width, height;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= width || p.y >= height) return;
  for (int s = 0; s < 4; ++s) sampleDepths[(p.y * width + p.x) * 4u + uint(s)] = texelFetch(depthSamples, ivec2(p), s).r;
}
