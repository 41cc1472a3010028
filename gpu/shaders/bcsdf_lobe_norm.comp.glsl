// The lobe-normalisation table Z_p(|θ_i|) of common/bcsdf.h
// (BcsdfGpu::bakeLobeNormTable), and lookups in it (BcsdfGpu::lookupLobeNorm):
// one invocation per texel or request.
#include "common/constants.h"
#include "common/fiber_shading.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_BCSDF) in;
layout(std430, binding = FT_SSBO_BCSDF_INPUT) readonly buffer BcsdfInput {
  FabricParams fabric;
  vec4 requests[];  // lookup: x θ
};
layout(std430, binding = FT_SSBO_LOBE_NORM_TABLE) readonly buffer LobeNormTable { vec2 lobeNorm[]; };
layout(std430, binding = FT_SSBO_BCSDF_OUTPUT) writeonly buffer BcsdfOutput { vec4 results[]; };  // xy (Z_R, Z_TT)
uniform uint groupsX;
uniform uint texels;  // n of the table
uniform uint count;   // lookup: requests
uniform uint lookup;  // 0: bake texel k; 1: look request k up in lobeNorm

void main() {
  uint k = flatInvocationIndex(groupsX, FT_WG_BCSDF);
  if (lookup == 0u) {
    if (k >= texels) return;
    int n = int(texels);
    results[k] = vec4(ftLongitudinalNorm(ftLobeNormTexelAngle(int(k), n, fabric.colorR.w), fabric.colorR.w),
                      ftLongitudinalNorm(ftLobeNormTexelAngle(int(k), n, fabric.colorTT.w), fabric.colorTT.w), 0.0, 0.0);
    return;
  }
  if (k >= count) return;
  float theta = requests[k].x;
  vec4 r = ftLobeNormLookup(theta, fabric.colorR.w, int(texels));
  vec4 t = ftLobeNormLookup(theta, fabric.colorTT.w, int(texels));
  results[k] = vec4(ftLobeNormFromTable(r, theta, fabric.colorR.w, lobeNorm[int(r.x)].x, lobeNorm[int(r.y)].x),
                    ftLobeNormFromTable(t, theta, fabric.colorTT.w, lobeNorm[int(t.x)].y, lobeNorm[int(t.y)].y), 0.0,
                    0.0);
}
