// V̄_glo of Khungurn et al. 2017 (004) §5.3.2 on the GPU: one axis of the
// separable, normalised Gaussian filter of a V_glo grid per dispatch, one
// invocation per texel (common/prt_multiple_scattering.h; the CPU twin is
// prtMsVgloFilterCpu in reference/prt_multiple_scattering.cpp). 004's GPU
// path filters the shadow map's visibility the same way before it settles on
// 40 Monte Carlo samples per fragment; the filter is the deterministic form.
#include "common/constants.h"
#include "common/prt_multiple_scattering.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_MS) in;
layout(std140, binding = FT_UBO_PRT_MS) uniform PrtMsVgloBlock { PrtMsVgloParams vg; };
layout(std430, binding = FT_SSBO_PRT_MS_TABLES) readonly buffer PrtMsVgloIn { float vIn[]; };
layout(std430, binding = FT_SSBO_PRT_RESULTS) writeonly buffer PrtMsVgloOut { float vOut[]; };
uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint item = flatInvocationIndex(groupsX, FT_WG_PRT_MS);
  if (item >= itemCount) return;
  int w = int(vg.grid.x), h = int(vg.grid.y);
  bool alongX = vg.grid.z == 0u;
  int x = int(item) % w, y = int(item) / w;
  float s = prtMsVgloSigmaTexels(vg.sigma.x, vg.sigma.y);
  int r = prtMsVgloRadius(s);
  int c = alongX ? x : y, n = alongX ? w : h;
  int lo = max(-r, -c), hi = min(r, n - 1 - c);  // A = the grid: taps outside it are dropped
  float num = 0.0f, den = 0.0f;
  for (int d = lo; d <= hi; ++d) {
    float k = prtMsVgloWeight(d, s);
    int at = alongX ? y * w + x + d : (y + d) * w + x;
    num += k * vIn[at];
    den += k;
  }
  vOut[item] = num / den;
}
