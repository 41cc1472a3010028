// The GPU frame of the fabric PRT, 004 §5 (common/prt_frame.h,
// gpu/prt_frame_gpu.h PrtFrameRendererGpu; docs/prt-frame.md): its shading
// program, two passes (frame.sizes.z) between the per-pixel program's
// (prt_frame_gpu_pixels.comp.glsl), no read-back between them:
//   FT_PRT_FRAME_GPU_CELLS     one invocation per IIRTF cell: the light's c_d
//                              (004 §5.3.1: Y(ω_d), or C_G turned to ξ) and c_T = A_C c_d;
//   FT_PRT_FRAME_GPU_SEGMENTS  one per block segment that a pixel marked (zeros for the
//                              rest): ω_o of the orthographic camera, t_k, d_k at the
//                              light → L^single (004 §5.2: SSDF / sums of SGs / their
//                              blend) and L̃^multi = C_S[θ_o]·(R_ωo c_T) of the segment's
//                              cell (004 §5.3.1).
// The math is the shared headers'; the table reads are prt_ss_shade.glsl's and
// prt_ms_frame.glsl's, as in the evaluators.
#include "common/constants.h"
#include "common/prelude.h"
// The frame buffer first: common/sh.h's rotation storage is redirected into it
// (286 floats per segment at offsets.z; a private array becomes a 286-way branch
// ladder on llvmpipe, prt_multiple_scattering.comp.glsl).
layout(std430, binding = FT_SSBO_PRT_FRAME) buffer PrtFrameGpuData { float frameData[]; };
uint ftShScratchBase = 0u;
#define SH_ROT_LOAD(R_, I_) frameData[ftShScratchBase + uint(I_)]
#define SH_ROT_STORE(R_, I_, V_) frameData[ftShScratchBase + uint(I_)] = (V_)
#include "common/bcsdf.h"
#include "common/segment_visibility.h"
// The 𝒢 tables before the single-scattering body (it reads prtSsTable[] by name).
layout(std430, binding = FT_SSBO_PRT_SS_TABLE) readonly buffer PrtFrameSsTable { float prtSsTable[]; };
#include "common/prt_single_scattering.h"
#include "common/prt_multiple_scattering.h"
#include "common/exemplar_volume.h"
#include "common/prt_frame.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_FRAME) in;
layout(std140, binding = FT_UBO_PRT_FRAME_GPU) uniform PrtFrameGpuBlock { PrtFrameGpuParams frame; };
layout(std140, binding = FT_UBO_PRT_VOL) uniform PrtVolBlock { VolParams vol; };
layout(std430, binding = FT_SSBO_PRT_VOL_SEGMENTS) readonly buffer PrtFrameSegments { VolSegment segments[]; };
layout(std430, binding = FT_SSBO_SVF_SSDF) readonly buffer PrtFrameSsdf { float ssdf[]; };
// Per segment: (R_k angle, IIRTF cell, 0, 0).
layout(std430, binding = FT_SSBO_PRT_REQUESTS) readonly buffer PrtFrameSegmentData { vec4 segmentData[]; };
layout(std430, binding = FT_SSBO_SVF_WEIGHTS) readonly buffer PrtFrameWeights { float svfWeights[]; };
layout(std430, binding = FT_SSBO_PRT_MS_TRANSFER) readonly buffer PrtFrameTransfer { float transfer[]; };
layout(std430, binding = FT_SSBO_PRT_MS_TABLES) readonly buffer PrtFrameMsTables { float tables[]; };
#include "shaders/prt_ss_shade.glsl"
#include "shaders/prt_ms_frame.glsl"
uniform uint groupsX;
uniform uint itemCount;

void cellPass(uint c) {
  int bands = int(frame.ms.y);
  ShCoeffs cd = prtMsGpuLightCoeffs(frame.light, frame.ms.z, frame.ms.w, bands);
  ShCoeffs3 cT = prtMsGpuTransfer(c, cd, bands);
  uint base = frame.offsets.x + c * FT_PRT_FRAME_GPU_CT_FLOATS;
  for (int j = 0; j < FT_SH_COEFFS; ++j)
    for (int ch = 0; ch < 3; ++ch) frameData[base + uint(j) * 4u + uint(ch)] = cT.c[j][ch];
}

void segmentPass(uint k) {
  uint base = frame.offsets.y + k * FT_PRT_FRAME_GPU_SEGMENT_FLOATS;
  if (frameData[frame.offsets.w + k] == 0.0f) {  // no pixel shows it: skip the shading
    for (uint j = 0u; j < FT_PRT_FRAME_GPU_SEGMENT_FLOATS; ++j) frameData[base + j] = 0.0f;
    return;
  }
  // ω_o of pixel (0, 0): the orthographic camera's, every pixel's (the driver refuses a pinhole).
  vec3 wo = ftPrtFrameOutgoing(ftVolRayDirection(vol, 0u, 0u));
  vec3 t = ftPrtFrameTangent(segments[k].a.xyz, segments[k].b.xyz);
  int n = int(frame.sizes.y);
  float d = ssdf[k * uint(n * n) + uint(ftPrtFrameSvfPixel(frame.light.xyz, n, n))];
  vec4 sd = segmentData[k];
  vec3 single = prtSsShadeGpu(frame.fabric, 0, t, wo, frame.light, d, sd.x, k, uint(frame.svf.y), frame.svf.x, 1.0f);
  uint cell = uint(sd.y);
#ifdef FT_FAULT_PRT_FRAME_GPU_CT_STRIDE
  uint ct = frame.offsets.x + cell * uint(FT_SH_COEFFS);  // planted: one float per coefficient, not a vec4
#else
  uint ct = frame.offsets.x + cell * FT_PRT_FRAME_GPU_CT_FLOATS;
#endif
  ShCoeffs3 cT;
  for (int j = 0; j < FT_SH_COEFFS; ++j)
    cT.c[j] = vec3(frameData[ct + uint(j) * 4u], frameData[ct + uint(j) * 4u + 1u], frameData[ct + uint(j) * 4u + 2u]);
  ftShScratchBase = frame.offsets.z + k * uint(FT_SH_ROTATION_SIZE);
  vec3 multi = prtMsGpuRadiance(cT, t, wo, frame.ms.z, int(frame.ms.y));
  for (int ch = 0; ch < 3; ++ch) {
    frameData[base + uint(ch)] = single[ch];
    frameData[base + 4u + uint(ch)] = multi[ch];
  }
  frameData[base + 3u] = 0.0f;
  frameData[base + 7u] = 0.0f;
}

void main() {
  uint item = flatInvocationIndex(groupsX, FT_WG_PRT_FRAME);
  if (item >= itemCount) return;
  if (frame.sizes.z == FT_PRT_FRAME_GPU_CELLS) cellPass(item);
  else segmentPass(item);
}
