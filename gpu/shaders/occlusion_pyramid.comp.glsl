// The max-depth pyramid of the occluder pass (common/occlusion_cull.h,
// FiberRenderer::draw): one dispatch per level. Level 0 takes the max over
// each pixel's samples of the occluder depth; level k the max over the (up
// to) 2 × 2 texels of level k − 1 that it covers, so a texel bounds every
// sample of its pixels exactly (no odd-size rounding).
#include "common/constants.h"
#include "common/occlusion_cull.h"

layout(local_size_x = FT_WG_OCCLUSION, local_size_y = FT_WG_OCCLUSION) in;
layout(std140, binding = FT_UBO_OCCLUSION) uniform OcclusionBlock { OcclusionPyramid pyramid; };
layout(std430, binding = FT_SSBO_OCCLUSION) buffer OcclusionTexels { float texels[]; };
layout(binding = FT_TEX_OCCLUDER_DEPTH) uniform sampler2DMS occluderDepth;
uniform uint level;
uniform uint samples;

void main() {
  uvec4 l = pyramid.level[level];
  uvec2 t = gl_GlobalInvocationID.xy;
  if (t.x >= l.y || t.y >= l.z) return;
  float deepest = 0.0;
  if (level == 0u) {
    for (uint s = 0u; s < samples; ++s) deepest = max(deepest, texelFetch(occluderDepth, ivec2(t), int(s)).r);
  } else {
    uvec4 below = pyramid.level[level - 1u];
    for (uint dy = 0u; dy < 2u; ++dy)
      for (uint dx = 0u; dx < 2u; ++dx) {
        uvec2 c = 2u * t + uvec2(dx, dy);
        if (c.x < below.y && c.y < below.z) deepest = max(deepest, texels[below.x + c.y * below.y + c.x]);
      }
  }
  texels[l.x + t.y * l.y + t.x] = deepest;
}
