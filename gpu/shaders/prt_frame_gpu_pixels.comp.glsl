// The GPU frame of the fabric PRT, 004 §5 (common/prt_frame.h,
// gpu/prt_frame_gpu.h PrtFrameRendererGpu; docs/prt-frame.md): its per-pixel
// program, two passes (frame.sizes.z) around the shading program's
// (prt_frame_gpu.comp.glsl), over the exemplar volume's G-buffer left on the GPU:
//   FT_PRT_FRAME_GPU_MARK    one invocation per G-buffer texel: mark its segment (the
//                            shading program shades marked segments only);
//   FT_PRT_FRAME_GPU_PIXELS  one per texel: L = L^single + V̄_glo L̃^multi of its segment.
// A program of its own: inside the shading program llvmpipe took 0.9–1.2 s for
// each of these passes at 1024² (about 1 µs per texel), alone 30–50 ms (measured).
#include "common/constants.h"
#include "common/prelude.h"
#include "common/exemplar_volume.h"
#include "common/prt_frame.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_FRAME) in;
layout(std140, binding = FT_UBO_PRT_FRAME_GPU) uniform PrtFrameGpuBlock { PrtFrameGpuParams frame; };
layout(std430, binding = FT_SSBO_PRT_RESULTS) readonly buffer PrtFrameGBuffer { VolHit gbuffer[]; };
layout(std430, binding = FT_SSBO_PRT_FRAME) buffer PrtFrameGpuData { float frameData[]; };
uniform uint groupsX;
uniform uint itemCount;

void markPass(uint i) {
  uint id = gbuffer[i].id;
  if (id != 0u && id <= frame.sizes.w) frameData[frame.offsets.w + id - 1u] = 1.0f;  // the same value from every texel
}

void pixelPass(uint i) {
  uint id = gbuffer[i].id;
  vec3 single = vec3(0.0f), multi = vec3(0.0f), total = vec3(0.0f);
  float covered = 0.0f;
  if (id != 0u && id <= frame.sizes.w) {
#ifdef FT_FAULT_PRT_FRAME_GPU_ID_OFFSET
    uint base = frame.offsets.y + id * FT_PRT_FRAME_GPU_SEGMENT_FLOATS;  // planted: the G-buffer's 1 + k read as k
#else
    uint base = frame.offsets.y + (id - 1u) * FT_PRT_FRAME_GPU_SEGMENT_FLOATS;
#endif
    single = vec3(frameData[base], frameData[base + 1u], frameData[base + 2u]);
    multi = vec3(frameData[base + 4u], frameData[base + 5u], frameData[base + 6u]);
    total = ftPrtFrameCompose(single, multi, 1.0f);
    covered = 1.0f;
  }
  uint n = frame.sizes.x;
  for (int ch = 0; ch < 3; ++ch) frameData[i * 4u + uint(ch)] = total[ch];
  frameData[i * 4u + 3u] = covered;
  if (frame.flags.x == 1u) {
    for (int ch = 0; ch < 3; ++ch) {
      frameData[(n + i) * 4u + uint(ch)] = single[ch];
      frameData[(2u * n + i) * 4u + uint(ch)] = multi[ch];
    }
    frameData[(n + i) * 4u + 3u] = covered;
    frameData[(2u * n + i) * 4u + 3u] = covered;
  }
}

void main() {
  uint item = flatInvocationIndex(groupsX, FT_WG_PRT_FRAME);
  if (item >= itemCount) return;
  if (frame.sizes.z == FT_PRT_FRAME_GPU_MARK) markPass(item);
  else pixelPass(item);
}
