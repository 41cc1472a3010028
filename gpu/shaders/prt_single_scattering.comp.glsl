// The GPU twin of single scattering of the fabric PRT, 004 §5.2, eq. 1–2,
// App. A (common/prt_single_scattering.h, gpu/prt_single_scattering_gpu.h).
// One program, two modes (prtSs.mode):
//   0 bake: one invocation per texel of the 𝒢 tables (2 rows per fabric):
//     𝒢(−θ_k; β⁻²/2) = bcsdf.h's Z(θ_k), float;
//   1 evaluate: one invocation per PrtSsRequest: ftPrtSsDirectional (λ ≤ 0)
//     or ftPrtSsSgLight, the segment's weights from the SVF group's buffer
//     (shaders/prt_ss_shade.glsl, shared with the PRT frame).
// Loops: Q ≤ 64 terms per request (llvmpipe's loop limit is not near).
#include "common/constants.h"
#include "common/prelude.h"
#include "common/bcsdf.h"
#include "common/segment_visibility.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_SS) in;
// The tables first: the shared body reads prtSsTable[] by name.
layout(std430, binding = FT_SSBO_PRT_SS_TABLE) buffer PrtSsTable { float prtSsTable[]; };
#include "common/prt_single_scattering.h"

layout(std140, binding = FT_UBO_PRT_SS) uniform PrtSsBlock { PrtSsParams prtSs; };
layout(std430, binding = FT_SSBO_PRT_REQUESTS) readonly buffer PrtSsRequests { PrtSsRequest requests[]; };
layout(std430, binding = FT_SSBO_PRT_RESULTS) writeonly buffer PrtSsResults { vec4 results[]; };
// w_k,q per weights row (the SVF group's layout, float[rows][Q]).
layout(std430, binding = FT_SSBO_SVF_WEIGHTS) readonly buffer PrtSsWeights { float svfWeights[]; };
#include "shaders/prt_ss_shade.glsl"
uniform uint groupsX;
uniform uint itemCount;

void main() {
  uint i = flatInvocationIndex(groupsX, FT_WG_PRT_SS);
  if (i >= prtSs.count) return;
  if (prtSs.mode == 0u) {
    int n = int(prtSs.tableSize);
    int row = int(i) / n, k = int(i) % n;
    FabricParams p = prtSs.fabrics[row / 2];
    prtSsTable[i] = ftPrtSsTexelGpu(k, n, (row % 2) == 0 ? p.colorR.w : p.colorTT.w);
    return;
  }
  PrtSsRequest q = requests[i];
  int fabric = int(q.tangent.w);
  vec3 L = prtSsShadeGpu(prtSs.fabrics[fabric], fabric, q.tangent.xyz, q.outgoing.xyz, q.light, q.segment.x,
                         q.segment.y, uint(q.segment.z), prtSs.axes, prtSs.lambdaSvf, q.outgoing.w);
  results[i] = vec4(L, 0.0f);
}
