// The GPU twin of local multiple scattering of 004 §4.3 and §5.3.1
// (common/prt_multiple_scattering.h, common/sh.h, gpu/prt_multiple_scattering_gpu.h).
// One program, five passes (ms.mode):
//   FT_PRT_MS_PHI      one invocation per (lobe, θ_i): Φ_p,j(θ_i) = Σ_φ Y_j N_p Δφ, j < 36;
//   FT_PRT_MS_CS       one per (θ_o row, chunk of 256 θ_i): partial sums of C_S[θ_o, j] rgb =
//                      Σ_θi cos²θ_i (lobe_R Φ_R + lobe_TT Φ_TT) Δθ, Φ read from the tables buffer;
//   FT_PRT_MS_CS_SUM   one per (θ_o, j): the partial sums added in chunk order;
//   FT_PRT_MS_CG       one per λ node: C_G[λ, l], l < 6;
//   FT_PRT_MS_FRAME    one per query: c_d (or rotated c_G) → c_T = A_C c_d → R_ωo → dot C_S[θ_o]
//                      (shaders/prt_ms_frame.glsl, shared with the PRT frame);
//   FT_PRT_MS_SH_PROBE one per query: Y(ω) and M(R) Y(ω) (R rows: tangent.xyz, light.xyz, their cross).
// Sums in float. llvmpipe ends an invocation's loops after 65,535 iterations in all
// (docs/llvmpipe-notes.md): Φ's 512 φ × ~63 inner iterations, C_S in chunks of 256 θ_i.
#include "common/constants.h"
// Results first, then (FRAME, SH_PROBE) each invocation's SH rotation matrices
// at itemCount·72 + item·286: common/sh.h's storage redirected here, so that
// llvmpipe indexes memory instead of a 286-way ladder over a private array.
layout(std430, binding = FT_SSBO_PRT_RESULTS) buffer PrtMsResults { float results[]; };
uint ftShScratchBase = 0u;
#define SH_ROT_LOAD(R_, I_) results[ftShScratchBase + uint(I_)]
#define SH_ROT_STORE(R_, I_, V_) results[ftShScratchBase + uint(I_)] = (V_)
#include "common/prt_multiple_scattering.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_PRT_MS) in;
layout(std140, binding = FT_UBO_PRT_MS) uniform PrtMsBlock { PrtMsParams ms; };
layout(std430, binding = FT_SSBO_PRT_REQUESTS) readonly buffer PrtMsRequests { PrtMsQuery queries[]; };
// A_C per cell: float[cells][3][36][36], row j1, column j0.
layout(std430, binding = FT_SSBO_PRT_MS_TRANSFER) readonly buffer PrtMsTransfer { float transfer[]; };
// FRAME: C_S as float[θ_o][36][4] (rgb, 0), then C_G as float[λ][6]. CS: Φ as float[2][θ_i][36].
layout(std430, binding = FT_SSBO_PRT_MS_TABLES) readonly buffer PrtMsTables { float tables[]; };
#include "shaders/prt_ms_frame.glsl"
uniform uint groupsX;
uniform uint itemCount;

void phiPass(uint item) {
  int n = int(ms.thetaINodes), np = int(ms.phiNodes);
  int lobe = int(item) / n, i = int(item) % n;
  float th = prtMsThetaINode(i, n);
  float dphi = 6.283185307179586f / float(np);
  float acc[FT_SH_COEFFS];
  for (int j = 0; j < FT_SH_COEFFS; ++j) acc[j] = 0.0f;
  for (int k = 0; k < np; ++k) {
    float ph = prtMsPhiNode(k, np);
    ShCoeffs y = shEval(prtMsOmegaOSpaceDirection(th, ph));
    float w = (lobe == 0 ? 1.0f : prtMsAzimuthTT(ms.fabric, ph)) * dphi;
    for (int j = 0; j < FT_SH_COEFFS; ++j) acc[j] += y.c[j] * w;
  }
  for (int j = 0; j < FT_SH_COEFFS; ++j) results[item * uint(FT_SH_COEFFS) + uint(j)] = acc[j];
}

uint csChunks() { return (ms.thetaINodes + uint(FT_MS_CS_CHUNK) - 1u) / uint(FT_MS_CS_CHUNK); }

// Partial sums of chunk `item % chunks` of row `item / chunks`: float[θ_o][chunk][36][4].
void csPass(uint item) {
  int n = int(ms.thetaINodes);
  uint chunks = csChunks();
  uint row = item / chunks, chunk = item % chunks;
  float thetaO = prtMsThetaONode(int(row), int(ms.thetaONodes));
  float dtheta = 3.14159265358979f / float(n);
  vec3 acc[FT_SH_COEFFS];
  for (int j = 0; j < FT_SH_COEFFS; ++j) acc[j] = vec3(0.0f);
  int i0 = int(chunk) * FT_MS_CS_CHUNK, i1 = min(n, i0 + FT_MS_CS_CHUNK);
  for (int i = i0; i < i1; ++i) {
    float th = prtMsThetaINode(i, n);
    float c2 = cos(th) * cos(th) * dtheta;
    vec3 r = prtMsLobeR(ms.fabric, th, thetaO), tt = prtMsLobeTT(ms.fabric, th, thetaO);
    uint pr = uint(i) * uint(FT_SH_COEFFS), pt = (uint(n) + uint(i)) * uint(FT_SH_COEFFS);
    for (int j = 0; j < FT_SH_COEFFS; ++j) acc[j] += c2 * (r * tables[pr + uint(j)] + tt * tables[pt + uint(j)]);
  }
  for (int j = 0; j < FT_SH_COEFFS; ++j)
    for (int ch = 0; ch < 3; ++ch) results[(item * uint(FT_SH_COEFFS) + uint(j)) * 4u + uint(ch)] = acc[j][ch];
}

// C_S[θ_o, j]: the chunks' partial sums (bound as the tables) added in chunk order.
void csSumPass(uint item) {
  uint chunks = csChunks();
  uint row = item / uint(FT_SH_COEFFS), j = item % uint(FT_SH_COEFFS);
  vec3 s = vec3(0.0f);
  for (uint c = 0u; c < chunks; ++c)
    for (int ch = 0; ch < 3; ++ch) s[ch] += tables[((row * chunks + c) * uint(FT_SH_COEFFS) + j) * 4u + uint(ch)];
  for (int ch = 0; ch < 3; ++ch) results[item * 4u + uint(ch)] = s[ch];
}

void cgPass(uint item) {
  PrtMsZonal z = prtMsZonalSg(float(item) / float(ms.lambdaNodes - 1u));
  for (int l = 0; l < FT_SH_BANDS; ++l) results[item * uint(FT_SH_BANDS) + uint(l)] = z.c[l];
}

void framePass(uint item) {
  ftShScratchBase = itemCount * 72u + item * uint(FT_SH_ROTATION_SIZE);
  PrtMsQuery q = queries[item];
  int bands = int(ms.bands);
  ShCoeffs cd = prtMsGpuLightCoeffs(q.light, ms.thetaONodes, ms.lambdaNodes, bands);
  ShCoeffs3 cT = prtMsGpuTransfer(q.cell.x, cd, bands);
  vec3 L = prtMsGpuRadiance(cT, q.tangent.xyz, q.wo.xyz, ms.thetaONodes, bands);
  for (int ch = 0; ch < 3; ++ch) results[item * 4u + uint(ch)] = L[ch];
  results[item * 4u + 3u] = 0.0f;
}

void probePass(uint item) {
  ftShScratchBase = itemCount * 72u + item * uint(FT_SH_ROTATION_SIZE);
  PrtMsQuery q = queries[item];
  vec3 rx = q.tangent.xyz, ry = q.light.xyz, rz = cross(rx, ry);
  ShCoeffs y = shEval(q.wo.xyz);
  ShCoeffs r = shRotate(shRotation(rx, ry, rz, FT_SH_BANDS), y, FT_SH_BANDS);
  for (int j = 0; j < FT_SH_COEFFS; ++j) {
    results[item * 72u + uint(j)] = y.c[j];
    results[item * 72u + 36u + uint(j)] = r.c[j];
  }
}

void main() {
  uint item = flatInvocationIndex(groupsX, FT_WG_PRT_MS);
  if (item >= itemCount) return;
  if (ms.mode == FT_PRT_MS_PHI) phiPass(item);
  else if (ms.mode == FT_PRT_MS_CS) csPass(item);
  else if (ms.mode == FT_PRT_MS_CG) cgPass(item);
  else if (ms.mode == FT_PRT_MS_CS_SUM) csSumPass(item);
  else if (ms.mode == FT_PRT_MS_FRAME) framePass(item);
  else probePass(item);
}
