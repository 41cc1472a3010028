// The GPU twin of the PRT frame's per-pixel composition (004 §5;
// common/prt_frame.h, gpu/prt_frame_gpu.h). One program, two modes
// (frame.sizes.z):
//   0 requests: one invocation per pixel of the exemplar volume's G-buffer:
//     ω_o, t_k, d_k at the light, R_k, k's cell → the single-scattering
//     request and multiple-scattering query of the pixel (evaluated by
//     prt_single_scattering.comp.glsl and prt_multiple_scattering.comp.glsl);
//   1 compose: L = L^single + V̄_glo L̃^multi (V̄_glo = 1).
#include "common/constants.h"
#include "common/prelude.h"
#include "common/exemplar_volume.h"
#include "common/prt_frame.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_FRAME) in;
layout(std140, binding = FT_UBO_PRT_FRAME) uniform PrtFrameBlock { PrtFrameParams frame; };
layout(std140, binding = FT_UBO_PRT_VOL) uniform PrtVolBlock { VolParams vol; };
layout(std430, binding = FT_SSBO_PRT_RESULTS) readonly buffer PrtFrameGBuffer { VolHit gbuffer[]; };
layout(std430, binding = FT_SSBO_PRT_VOL_SEGMENTS) readonly buffer PrtFrameSegments { VolSegment segments[]; };
layout(std430, binding = FT_SSBO_SVF_SSDF) readonly buffer PrtFrameSsdf { float ssdf[]; };
// Per segment: (R_k angle, IIRTF cell, 0, 0).
layout(std430, binding = FT_SSBO_PRT_REQUESTS) readonly buffer PrtFrameSegmentData { vec4 segmentData[]; };
layout(std430, binding = FT_SSBO_PRT_FRAME) buffer PrtFramePixels { PrtFramePixel pixels[]; };
uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint i = flatInvocationIndex(groupsX, FT_WG_PRT_FRAME);
  if (i >= frame.sizes.x) return;
  if (frame.sizes.z == 1u) {
    PrtFramePixel p = pixels[i];
    pixels[i].total = vec4(ftPrtFrameCompose(p.single.xyz, p.multi.xyz, 1.0f), p.total.w);
    return;
  }
  VolHit h = gbuffer[i];
  if (h.id == 0u || h.id > frame.sizes.w) {
    pixels[i] = ftPrtFrameMiss();
    return;
  }
  uint k = h.id - 1u;
  uint w = vol.ray.x;
  int n = int(frame.sizes.y);
#ifdef FT_FAULT_PRT_FRAME_SSDF_STRIDE
  float d = ssdf[k * uint(n) + uint(ftPrtFrameSvfPixel(frame.light.xyz, n, n))];  // planted: one row per segment
#else
  float d = ssdf[k * uint(n * n) + uint(ftPrtFrameSvfPixel(frame.light.xyz, n, n))];
#endif
  vec4 sd = segmentData[k];
  pixels[i] = ftPrtFrameRequests(k, ftVolRayDirection(vol, i % w, i / w), segments[k].a.xyz, segments[k].b.xyz, d, sd.x,
                                 uint(sd.y), frame.light);
}
