// The GPU twin of the segment visibility function of 004 §4.1
// (common/segment_visibility.h, gpu/segment_visibility_gpu.h), from binary
// visibility images the CPU's rays made. One program, four passes (svf.mode):
//   0 SSDF: one invocation per (image, pixel); scans every pixel of the image
//     for opposite-valued boundary pixels (the CPU's boundary list);
//   1 nearest axis: one per (image, z > 0 pixel): argmax_q ω·ξ_k,q;
//   2 weights: one per (image, axis): Σ solid angle of the visible pixels of
//     pass 1's cell, in pixel order (no atomics: deterministic);
//   3 decode: one per (image, pixel): the PCA reconstruction of the SSDF and
//     V^ssg = Σ_q w_q G(ω; ξ_q, λ)/M(λ).
// Loops stay under llvmpipe's 65,535 iterations: W·H ≤ 16,384 in pass 0,
// W·H/2 in pass 2, Q, C ≤ 64 in passes 1 and 3.
#include "common/constants.h"
#include "common/segment_visibility.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SVF) in;
layout(std140, binding = FT_UBO_SVF) uniform SvfBlock { SvfParams svf; };
layout(std430, binding = FT_SSBO_SVF_IMAGES) readonly buffer SvfImages { uint images[]; };
layout(std430, binding = FT_SSBO_SVF_SSDF) writeonly buffer SvfSsdf { float ssdf[]; };
layout(std430, binding = FT_SSBO_SVF_NEAREST) buffer SvfNearest { int nearest[]; };
layout(std430, binding = FT_SSBO_SVF_WEIGHTS) buffer SvfWeights { float weights[]; };
// mean[P], basis[C][P], coefficients[images][C], one after the other.
layout(std430, binding = FT_SSBO_SVF_PCA) readonly buffer SvfPca { float pca[]; };
layout(std430, binding = FT_SSBO_SVF_DECODE) writeonly buffer SvfDecode { vec2 decoded[]; };
uniform uint groupsX;
uniform uint itemCount;

float rotationOf(uint image) {
#ifdef FT_FAULT_SVF_GPU_NO_ROTATION
  return 0.0f;  // planted: R_k not applied (the axes of every segment alike)
#else
  return ftSvfRotationAngle(svf.firstSegment + image, svf.seed);
#endif
}

bool isBoundary(uint base, int x, int y, int W, int H, uint value) {
  for (int dir = 0; dir < 4; ++dir)
    if (images[base + uint(ftSvfNeighbour(x, y, dir, W, H))] != value) return true;
  return false;
}

void main() {
  uint item = flatInvocationIndex(groupsX, FT_WG_SVF);
  if (item >= itemCount) return;
  int W = int(svf.width), H = int(svf.height);
  uint P = svf.width * svf.height;
  if (svf.mode == 0u) {
    uint image = item / P, p = item % P;
    uint base = image * P;
    int px = int(p % svf.width), py = int(p / svf.width);
    uint value = images[base + p];
    vec3 wp = ftSvfPixelDirection(px, py, W, H);
    float best = -1.0f;
    for (uint q = 0u; q < P; ++q) {
      if (images[base + q] == value) continue;
      int qx = int(q % svf.width), qy = int(q / svf.width);
      if (!isBoundary(base, qx, qy, W, H, 1u - value)) continue;
      float key = ftSvfDistanceKey(wp, ftSvfPixelDirection(qx, qy, W, H), px, py, qx, qy, W, H);
      if (best < 0.0f || key < best) best = key;
    }
    ssdf[item] = ftSvfSsdfFromKey(value != 0u, best);
  } else if (svf.mode == 1u) {
    uint upper = P / 2u;
    uint image = item / upper, p = item % upper;
    vec3 w = ftSvfPixelDirection(int(p % svf.width), int(p / svf.width), W, H);
    nearest[item] = ftSvfNearestAxis(w, int(svf.axes), rotationOf(image));
  } else if (svf.mode == 2u) {
    uint image = item / svf.axes;
    int q = int(item % svf.axes);
    uint upper = P / 2u;
    float sum = 0.0f;
    for (uint p = 0u; p < upper; ++p)
      if (images[image * P + p] != 0u && nearest[image * upper + p] == q)
        sum += ftSvfPixelSolidAngle(int(p / svf.width), W, H);
    weights[item] = sum;
  } else {
    uint image = item / P, p = item % P;
    uint coefs = P + svf.components * P + image * svf.components;
    float rec = pca[p];
    for (uint c = 0u; c < svf.components; ++c) rec += pca[coefs + c] * pca[P + c * P + p];
    vec3 w = ftSvfPixelDirection(int(p % svf.width), int(p / svf.width), W, H);
    float angle = rotationOf(image);
    float v = 0.0f;
    for (int q = 0; q < int(svf.axes); ++q)
      v += ftSvfSgTerm(weights[image * svf.axes + uint(q)], ftSvfAxis(q + 1, int(svf.axes), angle), svf.lambda, w);
    decoded[item] = vec2(rec, v);
  }
}
