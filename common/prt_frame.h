// prt_frame.h — the per-pixel composition of the fabric PRT frame of
// Khungurn et al. 2017 (004) §5, shared by the CPU reference
// (reference/prt_frame.h) and a GPU twin (docs/prt-frame.md):
//   G-buffer texel (004 §5.1: segment id k of the exemplar volume's first
//   non-empty sample) → ω_o = −(eye ray direction), t_k = the segment's unit
//   direction, d_k(ω) = the SSDF image's pixel containing ω (nearest pixel of
//   the 2D (θ, φ) image of common/segment_visibility.h) →
//   L = L^single (004 §5.2, common/prt_single_scattering.h)
//     + V̄_glo · L̃^multi (004 §5.3, common/prt_multiple_scattering.h).
// The flat tiled fabric has no macro-scale occluder: V_glo = V̄_glo = 1
// (004 §5.3.2's filter of a constant is the constant).
#ifndef FT_PRT_FRAME_H
#define FT_PRT_FRAME_H
#include "prelude.h"
#include "bcsdf.h"
#include "srbf.h"

// Planted faults (validation/faults.def). Shared: C++ run-time switch and GLSL
// define, on both sides.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultPrtFrameOutgoingFlipped = false;
inline bool ftFaultPrtFrameSvfNoSwizzle = false;
inline bool ftFaultPrtFrameMsDropped = false;
}
#define FT_FAULT_PRT_FRAME_OUTGOING_FLIPPED_ON ::ft::ftFaultPrtFrameOutgoingFlipped
#define FT_FAULT_PRT_FRAME_SVF_NO_SWIZZLE_ON ::ft::ftFaultPrtFrameSvfNoSwizzle
#define FT_FAULT_PRT_FRAME_MS_DROPPED_ON ::ft::ftFaultPrtFrameMsDropped
#else
#if defined(FT_FAULT_PRT_FRAME_OUTGOING_FLIPPED)
#define FT_FAULT_PRT_FRAME_OUTGOING_FLIPPED_ON true
#else
#define FT_FAULT_PRT_FRAME_OUTGOING_FLIPPED_ON false
#endif
#if defined(FT_FAULT_PRT_FRAME_SVF_NO_SWIZZLE)
#define FT_FAULT_PRT_FRAME_SVF_NO_SWIZZLE_ON true
#else
#define FT_FAULT_PRT_FRAME_SVF_NO_SWIZZLE_ON false
#endif
#if defined(FT_FAULT_PRT_FRAME_MS_DROPPED)
#define FT_FAULT_PRT_FRAME_MS_DROPPED_ON true
#else
#define FT_FAULT_PRT_FRAME_MS_DROPPED_ON false
#endif
#endif

FT_NAMESPACE_BEGIN

// ω_o of a pixel: towards the eye, the eye ray reversed.
FT_FUNC vec3 ftPrtFrameOutgoing(vec3 rayDirection) {
  if (FT_FAULT_PRT_FRAME_OUTGOING_FLIPPED_ON) return rayDirection;  // planted: along the eye ray
  return -rayDirection;
}

// t_k: the unit direction of segment (a, b) (the BCSDF's θ = asin(ω·t) needs |t| = 1).
FT_FUNC vec3 ftPrtFrameTangent(vec3 a, vec3 b) {
  return ftNormalize(b - a);
}

// Row-major index of the SSDF/visibility image pixel (W × H, θ from +z by
// rows, φ = atan2(y, x) by columns: ftSvfPixelDirection) that contains ω.
FT_FUNC int ftPrtFrameSvfPixel(vec3 w, int width, int height) {
  // ftSvfPixelDirection swaps y and z of the equirect map (y up) into the fabric frame (z up).
  vec2 uv = FT_FAULT_PRT_FRAME_SVF_NO_SWIZZLE_ON ? ftEquirectUv(w) : ftEquirectUv(vec3(w.x, w.z, w.y));  // planted: y up
  int x = clamp(int(uv.x * float(width)), 0, width - 1);
  int y = clamp(int(uv.y * float(height)), 0, height - 1);
  return y * width + x;
}

// The GPU twin's parameters (std140 UBO FT_UBO_PRT_FRAME).
struct PrtFrameParams {
  vec4 light;   // xyz ω_d or ξ (unit, towards the light), w λ (0: directional)
  uvec4 sizes;  // x pixels, y visibility image side n, z mode (0 requests, 1 compose), w segments of the block
};
FT_ASSERT_SIZE(PrtFrameParams, 32)

// One pixel (std430, FT_SSBO_PRT_FRAME): the single-scattering request (the
// four vec4 of PrtSsRequest, common/prt_single_scattering.h), the
// multiple-scattering query (PrtMsQuery, common/prt_multiple_scattering.h),
// their results and the composed radiance (total.w: 1 covered, 0 a miss).
struct PrtFramePixel {
  vec4 ssTangent, ssOutgoing, ssLight, ssSegment;
  vec4 msWo, msTangent, msLight;
  uvec4 msCell;
  vec4 single, multi, total;
};
FT_ASSERT_SIZE(PrtFramePixel, 176)

FT_FUNC PrtFramePixel ftPrtFrameMiss() {
  PrtFramePixel p;
  p.ssTangent = vec4(0.0f);
  p.ssOutgoing = vec4(0.0f);
  p.ssLight = vec4(0.0f);
  p.ssSegment = vec4(0.0f);
  p.msWo = vec4(0.0f);
  p.msTangent = vec4(0.0f);
  p.msLight = vec4(0.0f);
  p.msCell = uvec4(0u);
  p.single = vec4(0.0f);
  p.multi = vec4(0.0f);
  p.total = vec4(0.0f);
  return p;
}

// The requests of a covered pixel: segment k (a, b) of the G-buffer, the eye
// ray's direction, d_k at the light (ssdfAtLight), R_k (angle), k's IIRTF
// cell, the light (xyz, λ). Fabric 0; V_glo = 1 (the flat fabric).
FT_FUNC PrtFramePixel ftPrtFrameRequests(uint k, vec3 rayDirection, vec3 a, vec3 b, float ssdfAtLight, float angle,
                                         uint cell, vec4 light) {
  vec3 wo = ftPrtFrameOutgoing(rayDirection);
  vec3 t = ftPrtFrameTangent(a, b);
  PrtFramePixel p = ftPrtFrameMiss();
  p.ssTangent = vec4(t.x, t.y, t.z, 0.0f);
  p.ssOutgoing = vec4(wo.x, wo.y, wo.z, 1.0f);
  p.ssLight = light;
  p.ssSegment = vec4(ssdfAtLight, angle, float(k), 0.0f);
  p.msWo = vec4(wo.x, wo.y, wo.z, 0.0f);
  p.msTangent = vec4(t.x, t.y, t.z, 0.0f);
  p.msLight = light;
  p.msCell = uvec4(cell, 0u, 0u, 0u);
  p.total = vec4(0.0f, 0.0f, 0.0f, 1.0f);
  return p;
}

// The GPU frame (gpu/prt_frame_gpu.h PrtFrameRendererGpu): per frame, four
// passes of two programs over data that stays on the GPU
// (prt_frame_gpu_pixels.comp.glsl: mark, pixels; prt_frame_gpu.comp.glsl:
// cells, segments). With the orthographic camera of the frame ω_o is the same
// for every pixel and V_glo = 1, so a pixel's radiance depends on its segment
// alone: the light's c_d and c_T = A_C c_d are done once per cell, the SH
// rotation R_ωo, the C_S dot and single scattering once per segment the
// G-buffer hits, and a pixel only composes its segment's two terms.
#define FT_PRT_FRAME_GPU_MARK 0u      // one invocation per G-buffer texel: mark its segment
#define FT_PRT_FRAME_GPU_CELLS 1u     // one per IIRTF cell: c_T = A_C c_d
#define FT_PRT_FRAME_GPU_SEGMENTS 2u  // one per block segment: L^single, L̃^multi (zeros if no texel marked it)
#define FT_PRT_FRAME_GPU_PIXELS 3u    // one per G-buffer texel: L = L^single + V̄_glo L̃^multi
#define FT_PRT_FRAME_GPU_CT_FLOATS 144u  // c_T of a cell in the frame buffer: vec4 (rgb, 0) per coefficient
#define FT_PRT_FRAME_GPU_SEGMENT_FLOATS 8u  // a segment's shading: (L^single, 0), (L̃^multi, 0)

// std140 UBO FT_UBO_PRT_FRAME_GPU. The frame buffer (FT_SSBO_PRT_FRAME, float):
// the image, vec4 (L rgb, covered) per pixel, [then L^single and L̃^multi
// images when flags.x = 1], c_T per cell at offsets.x, the shading per segment
// at offsets.y, 286 floats of SH rotation per segment at offsets.z, one mark
// per segment at offsets.w (cleared to 0 before each frame).
struct PrtFrameGpuParams {
  vec4 light;     // xyz ω_d or ξ (unit, towards the light), w λ (0: directional)
  uvec4 sizes;    // x pixels, y visibility image side n, z pass (FT_PRT_FRAME_GPU_*), w segments of the block
  uvec4 ms;       // x IIRTF cells, y SH bands L + 1, z C_S rows (θ_o), w C_G rows (λ)
  uvec4 offsets;  // floats: x c_T, y segment shading, z rotation scratch, w segment marks
  uvec4 flags;    // x 1: also the single- and multiple-scattering images
  vec4 svf;       // x λ_svf, y SG axes Q
  FabricParams fabric;
};
FT_ASSERT_OFFSET(PrtFrameGpuParams, fabric, 96)
FT_ASSERT_SIZE(PrtFrameGpuParams, 144)

// L = L^single + V̄_glo L̃^multi (004 §5, §5.3).
FT_FUNC vec3 ftPrtFrameCompose(vec3 single, vec3 multi, float vGloBar) {
  if (FT_FAULT_PRT_FRAME_MS_DROPPED_ON) return single;  // planted: single scattering only
  return single + vGloBar * multi;
}

FT_NAMESPACE_END
#endif  // FT_PRT_FRAME_H
