// The normal equations of the SRBF fit (001 §4.5 eq. 14; SrbfFitGpu::normalEquations):
// one invocation per sum, reduced over every pixel of the equirect map:
//   q < count:            b_q = Σ_p dΩ_p L_p G_q(ω_p)        (rgb)
//   q = count + a·count + b: K_ab = Σ_p dΩ_p G_a(ω_p) G_b(ω_p)  (x)
// with the shared kernel, directions and solid angles of common/srbf.h, over
// the rows [rowBegin, rowEnd) of one dispatch (the host splits the map so
// that no invocation loops past gallivm's 65,535 iterations: docs/llvmpipe-notes.md,
// and adds the chunks in double). The terms of one row are summed in order,
// the rows pairwise (a binary counter of partial sums, as
// bcsdf_ambient.comp.glsl), so rounding grows with log2(rows), not with the
// pixel count.
#include "common/constants.h"
#include "common/srbf.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_SRBF) in;
layout(std140, binding = FT_UBO_SRBF) uniform SrbfBlock { SrbfEnvironment basis; };  // μ, λ; weights unused
layout(std430, binding = FT_SSBO_SRBF_ENV_PIXELS) readonly buffer EnvPixels { vec4 pixels[]; };
layout(std430, binding = FT_SSBO_SRBF_SUMS) writeonly buffer Sums { vec4 sums[]; };
uniform uint groupsX;
uniform uint width;
uniform uint height;
uniform uint rowBegin;
uniform uint rowEnd;
uniform uint count;          // basis functions: 16 lobes, then the DC term if present

float basisValue(uint j, vec3 w) {
  if (j >= uint(FT_SRBF_LOBES)) return 1.0;
  return ftSrbfKernel(vec3(basis.lobes[j].axisLambda), basis.lobes[j].axisLambda.w, w);
}

void main() {
  uint q = flatInvocationIndex(groupsX, FT_WG_SRBF);
  if (q >= count + count * count) return;
  bool isRhs = q < count;
  uint a = isRhs ? q : (q - count) / count;
  uint b = isRhs ? 0u : (q - count) % count;
  vec4 partial[32];
  uint rows = rowEnd - rowBegin;
  for (uint r = 0u; r < rows; ++r) {
    uint y = rowBegin + r;
    float dOmega = ftEquirectSolidAngle(int(y), int(width), int(height));
    vec4 row = vec4(0.0);
    for (uint x = 0u; x < width; ++x) {
      vec3 w = ftEquirectDirection(int(x), int(y), int(width), int(height));
      float ga = basisValue(a, w);
      if (isRhs) row.xyz += ga * pixels[y * width + x].xyz;
      else row.x += ga * basisValue(b, w);
    }
    vec4 v = row * dOmega;
    uint level = 0u;
    for (uint n = r; (n & 1u) != 0u; n >>= 1u) v += partial[level++];
    partial[level] = v;
  }
  vec4 sum = vec4(0.0);
  for (uint level = 0u; level < 32u; ++level)
    if ((rows & (1u << level)) != 0u) sum += partial[level];
  sums[q] = sum;
}
