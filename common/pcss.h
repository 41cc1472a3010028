// pcss.h — soft yarn shadows by Percentage-Closer Soft Shadows (Fernando
// 2005) on the yarn shadow maps (common/shadow_map.h), as Huang et al. 2025
// (001) §4.5 uses them for the environment's SRBF lobes (eq. 17, T̃^Yarn):
// "we directly use the yarn-level shadow map generated from the SRBF center
// direction ω_j, as the light direction. The attenuation T̃ at the shading
// point is then approximated using PCSS". notes-rendering A11, docs/soft-shadows.md.
//
// A light here is a cone of directions of angular radius α around the light
// direction, uniform in solid angle (a disc light at infinity). The maps are
// orthographic (world-unit depths), so Fernando's perspective ratio
// w_light·(d_r − d_b)/d_b becomes (z_r − z_b)·tan α: a blocker at depth
// distance d in front of the receiver shadows it from the directions whose
// rays pass through it, a disc of radius d·tan α on the blocker's plane.
//  1. blocker search over a disc of radius w_s = (z_r − z_near)·tan α (the
//     cone's cross-section at the map's near plane, the farthest a blocker can
//     be), capped at FT_PCSS_MAX_RADIUS_TEXELS: z_b = mean of the stored depths
//     in front of the receiver; none: T̃ = 1;
//  2. penumbra: the PCF radius w_p = (z_r − z_b)·tan α (capped the same);
//  3. PCF: T̃ = the share of FT_PCSS_SAMPLES Vogel-disk samples within w_p whose
//     stored depth is not in front of the receiver.
// The stored depth is the tube's far side plus the slope bias (shadow_map.h),
// so the comparison is plain: a sample blocks when z_map < z_r, as V_map.
//
// SRBF lobes (eq. 14, G = e^{λ(μ·ω − 1)}) are not cones: a lobe is mapped to
// the cone that holds FT_PCSS_SG_ENERGY_FRACTION of its energy,
//   cos α = 1 + ln(1 − f(1 − e^{−2λ}))/λ,     (∫_cap G dω / ∫_S² G dω = f)
// f chosen so that the cone's straight-edge shadow has the SG's 10–90 % width
// for large λ (derivation in docs/soft-shadows.md): α ≈ 1.865/√λ.
//
// The map texels are read through FT_PCSS_FETCH: in C++ from the pointer the
// functions take, in GLSL from ftPcssFetch(source, index), which the
// includer defines (source 0: the light maps, 1: the lobe maps).
#ifndef FT_PCSS_H
#define FT_PCSS_H
#include "prelude.h"
#include "rng.h"
#include "shadow_map.h"

// Planted faults (validation/faults.def). Shared ones: run-time switch in C++,
// define in GLSL. FT_FAULT_PCSS_SEARCH_UNSCALED and FT_FAULT_PCSS_LOBE_LAYER_SHIFT
// are GPU-only (GLSL defines; the C++ side never sees them).
#ifdef __cplusplus
namespace ft {
inline bool ftFaultPcssReceiverDepth = false;
inline bool ftFaultPcssAlphaInverseLambda = false;
}
#define FT_FAULT_PCSS_RECEIVER_DEPTH_ON ::ft::ftFaultPcssReceiverDepth
#define FT_FAULT_PCSS_ALPHA_INVERSE_LAMBDA_ON ::ft::ftFaultPcssAlphaInverseLambda
#define FT_FAULT_PCSS_SEARCH_UNSCALED_ON false
#define FT_PCSS_TEXELS , const float* texels
#define FT_PCSS_TEXELS_ARG , texels
#define FT_PCSS_FETCH(source, i) (static_cast<void>(source), texels[i])
#else
#ifdef FT_FAULT_PCSS_RECEIVER_DEPTH
#define FT_FAULT_PCSS_RECEIVER_DEPTH_ON true
#else
#define FT_FAULT_PCSS_RECEIVER_DEPTH_ON false
#endif
#ifdef FT_FAULT_PCSS_ALPHA_INVERSE_LAMBDA
#define FT_FAULT_PCSS_ALPHA_INVERSE_LAMBDA_ON true
#else
#define FT_FAULT_PCSS_ALPHA_INVERSE_LAMBDA_ON false
#endif
#ifdef FT_FAULT_PCSS_SEARCH_UNSCALED
#define FT_FAULT_PCSS_SEARCH_UNSCALED_ON true
#else
#define FT_FAULT_PCSS_SEARCH_UNSCALED_ON false
#endif
float ftPcssFetch(int source, uint i);  // defined by the includer
#define FT_PCSS_TEXELS
#define FT_PCSS_TEXELS_ARG
#define FT_PCSS_FETCH(source, i) ftPcssFetch(source, i)
#endif

#define FT_PCSS_SAMPLES 16                 // Vogel-disk samples of the blocker search and of the PCF (notes A11 [F])
#define FT_PCSS_MAX_RADIUS_TEXELS 32.0f    // cap of the search and PCF radii (notes A11 [F])
#define FT_PCSS_SG_ENERGY_FRACTION 0.8244f // lobe → cone: the cap holding this share of G's energy ([F], header)
#define FT_PCSS_MAX_ANGLE 1.3962634f       // 80°: α is clamped below π/2 (tan α finite; broad lobes)
#define FT_PCSS_MAX_LOBES 16               // = FT_SRBF_LOBES
#define FT_PCSS_LOBE_MIN_SHARE 0.01f       // lobes with less of the environment's energy get no map (T̃ = 1)
#define FT_PCSS_LOBE_DEFAULT_SIZE 1024u    // lobe map texels per side (notes A11 [F])
#define FT_PCSS_GOLDEN_ANGLE 2.39996323f   // π(3 − √5)
#define FT_PCSS_SOURCE_LIGHTS 0
#define FT_PCSS_SOURCE_LOBES 1

FT_NAMESPACE_BEGIN

// Uniform block of the soft shadows (std140, FT_UBO_PCSS): the directional
// lights' cone radii (their maps are ShadowMapParams') and the SRBF lobes'
// maps: one layer per lobe with a map, in the light space of lobe j's axis.
struct PcssParams {
  vec4 lightTanAlpha;                   // tan α of directional light i = 0..3
  vec4 lobeX[FT_PCSS_MAX_LOBES];        // as ShadowMapParams.lightX, of lobe j's map
  vec4 lobeY[FT_PCSS_MAX_LOBES];
  vec4 lobeZ[FT_PCSS_MAX_LOBES];        // −μ_j: the lobe's propagation
  vec4 lobeCone[FT_PCSS_MAX_LOBES];     // x tan α_j, y layer of lobe j's map (−1: none, T̃ = 1), z α_j, w energy share
  vec4 extent;                          // lobe maps: x h, y h_z, z texel (world), w N
  uvec4 count;                          // x lobe-map layers, y N, zw unused
};
FT_ASSERT_OFFSET(PcssParams, lobeX, 16)
FT_ASSERT_OFFSET(PcssParams, lobeCone, 784)
FT_ASSERT_OFFSET(PcssParams, extent, 1040)
FT_ASSERT_OFFSET(PcssParams, count, 1056)
FT_ASSERT_SIZE(PcssParams, 1072)

// The cone radius α of an SRBF lobe of sharpness λ (eq. 14): the cap around μ
// that holds FT_PCSS_SG_ENERGY_FRACTION of ∫G dω, clamped to FT_PCSS_MAX_ANGLE.
FT_FUNC float ftPcssLobeAngle(float lambda) {
  if (FT_FAULT_PCSS_ALPHA_INVERSE_LAMBDA_ON) return min(1.0f / lambda, FT_PCSS_MAX_ANGLE);  // α = 1/λ
  float l = max(lambda, 1e-6f);
  // 1 − e^{−2λ} without cancellation at small λ (−expm1(−2λ)).
  float twoL = 2.0f * l;
  float oneMinus = twoL < 1e-3f ? twoL * (1.0f - 0.5f * twoL) : 1.0f - exp(-twoL);
  // 1 − cos α = −ln(1 − f(1 − e^{−2λ}))/λ = 2 sin²(α/2): the half-angle form
  // keeps small α accurate where 1 − cos α cancels in float.
  float s2 = -log(1.0f - FT_PCSS_SG_ENERGY_FRACTION * oneMinus) / (2.0f * l);
  float alpha = s2 >= 1.0f ? FT_PI : 2.0f * asin(sqrt(max(s2, 0.0f)));
  return min(alpha, FT_PCSS_MAX_ANGLE);
}

// Sample k of n on the unit Vogel disk, rotated by `rotation` radians.
FT_FUNC vec2 ftPcssDisk(int k, int n, float rotation) {
  float r = sqrt((float(k) + 0.5f) / float(n));
  float a = float(k) * FT_PCSS_GOLDEN_ANGLE + rotation;
  return vec2(r * cos(a), r * sin(a));
}

// The pattern's rotation at a receiver texel: a hash of its integer
// coordinates (the same on both sides), so neighbouring texels see different
// samples (noise instead of banding).
FT_FUNC float ftPcssRotation(int x, int y, uint layer) {
  uvec4 h = ftPcg4d(uvec4(uint(x), uint(y), layer, 0x50C55u));
  return FT_TWO_PI * ftUnitFloat(h.x);
}

// T̃ of a receiver at map coordinates m = (u, v, stored depth) of one N × N
// layer that starts at texel index `base`, for a cone of half-angle α
// (tanAlpha); `depthScale`: world units per unit of stored depth (2 h_z),
// `texel`: world size of a texel. tan α = 0: the hard lookup (V_map) with
// the map's own filter (FT_SHADOW_FILTER_*, common/shadow_map.h), as the
// frame without soft shadows looks it up.
FT_FUNC float ftPcssFiltered(vec3 m, int n, uint base, uint layer, float depthScale, float texel, float tanAlpha,
                             uint mapFilter, int source FT_PCSS_TEXELS) {
  if (m.x < 0.0f || m.x >= 1.0f || m.y < 0.0f || m.y >= 1.0f) return 1.0f;  // outside the map: no yarn there
  vec2 pc = vec2(m.x, m.y) * float(n);
  int cx = min(int(pc.x), n - 1), cy = min(int(pc.y), n - 1);
  float zr = m.z;
  if (tanAlpha <= 0.0f && mapFilter == FT_SHADOW_FILTER_PCF) {
    vec4 f = ftShadowPcfFootprint(m, n);
    int x0 = ftShadowPcfTexel(f.x, 0, n), x1 = ftShadowPcfTexel(f.x, 1, n);
    int y0 = ftShadowPcfTexel(f.y, 0, n), y1 = ftShadowPcfTexel(f.y, 1, n);
    return ftShadowPcfCombine(f, ftShadowVisibility(zr, FT_PCSS_FETCH(source, base + uint(y0 * n + x0))),
                              ftShadowVisibility(zr, FT_PCSS_FETCH(source, base + uint(y0 * n + x1))),
                              ftShadowVisibility(zr, FT_PCSS_FETCH(source, base + uint(y1 * n + x0))),
                              ftShadowVisibility(zr, FT_PCSS_FETCH(source, base + uint(y1 * n + x1))));
  }
  if (tanAlpha <= 0.0f) return ftShadowVisibility(zr, FT_PCSS_FETCH(source, base + uint(cy * n + cx)));
  float rotation = ftPcssRotation(cx, cy, layer);
  // 1. Blocker search: the cone's cross-section at the near plane (depth 0).
  float ws = min(zr * depthScale * tanAlpha / texel, FT_PCSS_MAX_RADIUS_TEXELS);
  if (FT_FAULT_PCSS_SEARCH_UNSCALED_ON) ws = 1.0f;  // a fixed one-texel search
  float sum = 0.0f;
  int found = 0;
  for (int k = 0; k < FT_PCSS_SAMPLES; ++k) {
    vec2 q = pc + ws * ftPcssDisk(k, FT_PCSS_SAMPLES, rotation);
    int x = int(floor(q.x)), y = int(floor(q.y));
    if (x < 0 || y < 0 || x >= n || y >= n) continue;
    float z = FT_PCSS_FETCH(source, base + uint(y * n + x));
    if (z < zr && z < 1.0f) {  // a cleared texel (1) holds no yarn
      sum += z;
      found += 1;
    }
  }
  if (found == 0) return 1.0f;
  float zb = sum / float(found);
  // 2. Penumbra: the blocker's depth distance times tan α (orthographic).
  float d = (zr - zb) * depthScale;
  if (FT_FAULT_PCSS_RECEIVER_DEPTH_ON) d = zr * depthScale;  // the receiver's depth, not its distance to the blocker
  float wp = min(d * tanAlpha / texel, FT_PCSS_MAX_RADIUS_TEXELS);
  // 3. PCF over the penumbra disc (Fernando's test: in front of the receiver).
  // Not a cone test against the stored surface ((z_r − z)·tan α ≥ offset):
  // the map holds a tube's far side only, the tube reaches 2W nearer the
  // light, and such a test lost contact shadows (pcss/embree: mean error
  // 0.07–0.16 instead of 0.02–0.10, all too bright; docs/soft-shadows.md).
  int lit = 0;
  for (int k = 0; k < FT_PCSS_SAMPLES; ++k) {
    vec2 q = pc + wp * ftPcssDisk(k, FT_PCSS_SAMPLES, rotation);
    int x = clamp(int(floor(q.x)), 0, n - 1), y = clamp(int(floor(q.y)), 0, n - 1);
    float z = FT_PCSS_FETCH(source, base + uint(y * n + x));
    lit += z < zr && z < 1.0f ? 0 : 1;
  }
  return float(lit) / float(FT_PCSS_SAMPLES);
}

// T̃ of directional light i (its yarn shadow map, ShadowMapParams) at world point p.
FT_FUNC float ftPcssLightVisibility(ShadowMapParams sm, PcssParams pc, int i, vec3 p FT_PCSS_TEXELS) {
  vec3 m = ftShadowNdcToMap(ftShadowNdc(sm, ftShadowLightSpace(sm, i, p)));
  int n = int(sm.count.y);
  uint base = ftShadowMapIndex(sm, i, 0, 0);
  return ftPcssFiltered(m, n, base, uint(i), 2.0f * sm.extent.y, sm.extent.z, pc.lightTanAlpha[i], sm.count.z,
                        FT_PCSS_SOURCE_LIGHTS FT_PCSS_TEXELS_ARG);
}

// T̃^Yarn_j of eq. 17: the yarn-level soft shadow of SRBF lobe j at world
// point p, from lobe j's map; 1 for a lobe without a map (too little energy).
FT_FUNC float ftPcssLobeVisibility(PcssParams pc, int j, vec3 p FT_PCSS_TEXELS) {
  int layer = int(pc.lobeCone[j].y);
#ifdef FT_FAULT_PCSS_LOBE_LAYER_SHIFT
  if (j + 1 < FT_PCSS_MAX_LOBES) layer = int(pc.lobeCone[j + 1].y);  // lobe j reads the next lobe's map
#endif
  if (layer < 0) return 1.0f;
  vec4 q = vec4(p, 1.0f);
  vec3 l = vec3(dot(pc.lobeX[j], q), dot(pc.lobeY[j], q), dot(pc.lobeZ[j], q));
  vec3 m = ftShadowNdcToMap(vec3(l.x / pc.extent.x, l.y / pc.extent.x, l.z / pc.extent.y));
  int n = int(pc.count.y);
  uint base = uint(layer) * pc.count.y * pc.count.y;
  // A lobe always has a cone (tan α > 0); at zero it would read its one texel.
  return ftPcssFiltered(m, n, base, uint(layer), 2.0f * pc.extent.y, pc.extent.z, pc.lobeCone[j].x,
                        FT_SHADOW_FILTER_NEAREST, FT_PCSS_SOURCE_LOBES FT_PCSS_TEXELS_ARG);
}

FT_NAMESPACE_END
#endif  // FT_PCSS_H
