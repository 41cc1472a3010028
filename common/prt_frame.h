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

// L = L^single + V̄_glo L̃^multi (004 §5, §5.3).
FT_FUNC vec3 ftPrtFrameCompose(vec3 single, vec3 multi, float vGloBar) {
  if (FT_FAULT_PRT_FRAME_MS_DROPPED_ON) return single;  // planted: single scattering only
  return single + vGloBar * multi;
}

FT_NAMESPACE_END
#endif  // FT_PRT_FRAME_H
