// Both paths' fragment stage: a ray-cast impostor. The geometry stage's
// rectangle covers the line's capsule (the tube of the fiber's half-width
// around the line and a ball at each end, the shape of Embree's round linear
// curves in the ground truth, reference/fiber_trace.cpp); each fragment tests
// the capsule at its multisample positions (coverage) and casts one eye ray
// against it for shading, and is discarded when no sample is covered. The hit gives the
// fiber's depth (crossing plies and a core inside its ply intersect as tubes
// do), its place along the line (which mixes the two vertex tangents) and its
// normal. Interpolating tangent and "across" over a strip quad instead is
// wrong by degrees wherever the quad is not a parallelogram, which moved the
// 1°-wide highlights of silk and cotton by pixels; a strip seen end-on was a
// bow-tie where the fiber is a disc.
//
// Two outputs, chosen by `shaded`:
//  * 0: the preview of the harness thumbnails — a Kajiya–Kay style highlight
//    from a headlight and a round-fiber falloff (RGBA8);
//  * 1: the fiber shading of Wu & Yuksel 2019 §4.3 (common/fiber_shading.h):
//    the shared BCSDF per directional light plus the ambient table, in linear
//    HDR radiance (a float target), alpha 1 for coverage.
//
// Deferred shading (docs/shaded-frame.md, FiberRenderer::drawDeferred):
//  * FT_VISIBILITY_PASS: the same casts, coverage, core texture holes and
//    depth, but instead of shading the fragment writes its hit (FiberHit,
//    everything shadeFiber reads; at a textured core what the texture's
//    normal and direction are computed from) as FT_VISIBILITY_TARGETS float vectors;
//  * FT_DEFERRED_SHADE: this file included by fiber_shade.comp.glsl without
//    the fragment stage (varyings, casts, main), for shadeFiber on the hits.
#include "common/ambient_occlusion.h"
#include "common/constants.h"
#include "common/core_texture.h"
#include "common/ds_correction.h"
#include "common/dual_scattering.h"
#include "common/fiber_geometry.h"
#include "common/fiber_shading.h"
#include "common/occlusion_cull.h"
#include "common/self_shadow.h"
#include "common/shadow_map.h"
#include "common/srbf.h"
#include "common/view_params.h"

layout(std140, binding = FT_UBO_VIEW_PARAMS) uniform ViewBlock { ViewParams view; };
layout(std140, binding = FT_UBO_SHADING) uniform ShadingBlock { ShadingParams shading; };
layout(std430, binding = FT_SSBO_AMBIENT_TABLE) readonly buffer AmbientTable { vec4 ambientTable[]; };
layout(std430, binding = FT_SSBO_LOBE_NORM_TABLE) readonly buffer LobeNormTable { vec2 lobeNorm[]; };
layout(std140, binding = FT_UBO_YARN_PARAMS) uniform YarnBlock { YarnParams yarn; };
layout(std430, binding = FT_SSBO_CURVES) readonly buffer CurveBuffer { CurveInfo curves[]; };
layout(std140, binding = FT_UBO_SELF_SHADOW) uniform SelfShadowBlock {
  SelfShadowParams selfShadow;
  YarnDensityParams selfShadowDensity;
};
layout(std430, binding = FT_SSBO_SELF_SHADOW_TEXTURE) readonly buffer SelfShadowTexture { float selfShadowTexels[]; };
layout(std140, binding = FT_UBO_CORE_TEXTURE) uniform CoreTextureBlock { CoreTextureParams coreTexture; };
layout(std430, binding = FT_SSBO_CORE_TEX0) readonly buffer CoreTex0 { vec4 coreTex0[]; };
layout(std430, binding = FT_SSBO_CORE_TEX1) readonly buffer CoreTex1 { vec4 coreTex1[]; };
layout(std140, binding = FT_UBO_AMBIENT_OCCLUSION) uniform AoBlock { AmbientOcclusionParams ao; };
layout(std430, binding = FT_SSBO_AO_TEXTURE) readonly buffer AoTexture { float aoTexels[]; };
// Yarn shadow map (000 §4.1 last paragraph): FiberRenderer::drawShadowMap.
layout(std140, binding = FT_UBO_SHADOW_MAP) uniform ShadowMapBlock { ShadowMapParams shadowMap; };
layout(std430, binding = FT_SSBO_SHADOW_MAP) readonly buffer ShadowMapTexels { float shadowMapTexels[]; };
#ifdef FT_FRAME_PCSS
// Soft yarn shadows by PCSS (001 §4.5 eq. 17, common/pcss.h): the lights'
// cones and the SRBF lobes' maps (FiberRenderer::drawLobeShadowMaps).
#include "common/pcss.h"
layout(std140, binding = FT_UBO_PCSS) uniform PcssBlock { PcssParams pcss; };
layout(std430, binding = FT_SSBO_PCSS_LOBE_MAPS) readonly buffer PcssLobeTexels { float pcssLobeTexels[]; };
float ftPcssFetch(int source, uint i) { return source == FT_PCSS_SOURCE_LOBES ? pcssLobeTexels[i] : shadowMapTexels[i]; }
#endif
// T̃^Yarn_j of 001 eq. 17: the yarn-level soft shadow of SRBF lobe j at p, by
// PCSS on lobe j's map; 1 in a frame without lobe maps (no FT_FRAME_PCSS).
float softLobeVisibility(int j, vec3 p) {
#ifdef FT_FRAME_PCSS
  return ftPcssLobeVisibility(pcss, j, p);
#else
  return 1.0;
#endif
}
// Dual scattering (001 §4.1 eq. 8, §4.3 eq. 11): the DS table of the fabric,
// the ξ layout (scaled to the model) and the four ξ textures; identity
// textures without a ξ bake (scene/shading_inputs.h).
layout(std430, binding = FT_SSBO_FRAME_DS_TABLE) readonly buffer FrameDsTable { vec4 dsTable[]; };
layout(std140, binding = FT_UBO_XI) uniform FrameXiBlock { DsCorrectionLayout xiLayout; };
layout(std430, binding = FT_SSBO_FRAME_XI_M) readonly buffer FrameXiM { vec4 xiM[]; };
layout(std430, binding = FT_SSBO_FRAME_XI_N) readonly buffer FrameXiN { vec4 xiN[]; };
layout(std430, binding = FT_SSBO_FRAME_PSI_M) readonly buffer FramePsiM { vec4 psiM[]; };
layout(std430, binding = FT_SSBO_FRAME_PSI_N) readonly buffer FramePsiN { vec4 psiN[]; };
#ifdef FT_FRAME_ENVIRONMENT
// SRBF environment lighting (001 §4.5 eq. 16, common/srbf_lighting.h): the
// fitted map and the I_M table of the fabric; only in this variant of the
// shaded pass (FiberRenderer), so frames without it keep their SSBO count.
layout(std140, binding = FT_UBO_FRAME_SRBF) uniform FrameSrbfBlock {
  SrbfEnvironment environment;
  ivec4 srbfDims;
};
layout(std430, binding = FT_SSBO_FRAME_SRBF_TABLE) readonly buffer FrameSrbfTable { vec4 srbfTable[]; };
#include "common/srbf_lighting.h"
#endif
#ifndef FT_DEFERRED_SHADE
layout(location = 2) flat in uint stripType;
layout(location = 3) in vec3 stripOffset;  // the rectangle point less lineP0 (fiber_strip.geom.glsl says why)
layout(location = 5) flat in vec3 lineP0;
layout(location = 6) flat in vec3 lineP1;
layout(location = 7) flat in vec3 lineT0;
layout(location = 8) flat in vec3 lineT1;
layout(location = 9) flat in vec2 lineHalfWidth;
layout(location = 10) flat in vec4 lineYarnC0;
layout(location = 11) flat in vec4 lineYarnC1;
layout(location = 12) flat in vec3 lineYarnN0;
layout(location = 13) flat in vec3 lineYarnN1;
layout(location = 14) flat in vec3 lineYarnB0;
layout(location = 15) flat in vec3 lineYarnB1;
layout(location = 16) flat in uint lineCurve;
#ifdef FT_OCCLUSION_TEST
layout(location = 17) flat in float lineNearestDepth;
#endif
#ifdef FT_VISIBILITY_PASS
layout(location = 18) flat in uint lineKey;  // ftLineKey (fiber_strip.geom.glsl)
#endif

// The rectangle point on this fragment's eye ray (pixel centre), and on the
// eye ray through multisample position i.
#ifdef FT_FAULT_STRIP_WORLD_ABSOLUTE
// Planted fault: the geometry stage passes the world position itself, which
// the rasteriser's attribute planes round to a fraction of a pixel.
#define stripWorld stripOffset
#define stripWorldAtSample(i) interpolateAtSample(stripOffset, (i))
#else
#define stripWorld (lineP0 + stripOffset)
#define stripWorldAtSample(i) (lineP0 + interpolateAtSample(stripOffset, (i)))
#endif
#ifdef FT_STRIP_RAY_PROBE
// Debug output of the forward pass (validation/strip_impostor_cases.cpp): how far
// the points through which the fragment casts its rays land from where they
// belong, in pixels, by projecting them back to the window. Set by
// FiberRenderer from GL: the multisample positions in the pixel (y up) and
// the viewport size.
uniform vec2 probeSamplePositions[4];
uniform vec2 probeViewport;
vec2 probeWindow(vec3 p) {
  vec4 c = view.viewProj * vec4(p, 1.0);
  return (0.5 * c.xy / c.w + 0.5) * probeViewport;
}
#endif
// Occlusion culling (common/occlusion_cull.h): level 0 of the occluders' depth pyramid.
layout(std140, binding = FT_UBO_OCCLUSION) uniform OcclusionBlock { OcclusionPyramid pyramid; };
layout(std430, binding = FT_SSBO_OCCLUSION) readonly buffer OcclusionTexels { float occlusionTexels[]; };
#ifdef FT_VISIBILITY_PASS
layout(location = 0) out vec4 hitRecord[FT_VISIBILITY_TARGETS];  // ftPackHit
layout(location = FT_VISIBILITY_TARGETS) out uint hitLine;  // ftLineKey + 1: the compaction marks the lines seen
#else
layout(location = 0) out vec4 color;
#endif

uniform uint shaded;
uniform vec3 lightDir;
uniform vec3 baseColor;
#endif  // FT_DEFERRED_SHADE

// The occluder pass (common/occlusion_cull.h) tests a capsule 5 % thinner:
// where its centre ray hits, so does the shaded pass's, whatever the float
// rounding of the other ray origin there.
#ifdef FT_OCCLUDER_PASS
#define FT_COVERAGE_SCALE 0.95
#else
#define FT_COVERAGE_SCALE 1.0
#endif

struct FiberHit {
  vec3 position;
  vec3 tangent;
  vec3 normal;
  float along;  // place along the line, [0, 1]
  // Deferred shading only (FT_DEFERRED_SHADE): the line's yarn frame blended
  // at `along` (unnormalised) and its curve, read from the hit record.
  vec4 yarnC;
  vec3 yarnN;
  vec3 yarnB;
  uint curve;
};

// What the shading reads of the line at a hit: the varyings in the fragment
// stage, written exactly as before deferred shading so that the forward
// pass compiles as it did (Mesa lowers mix() by what else a shader
// computes, and a last-bit change can move a core-texture hole); the hit
// record's copy in the deferred shading.
#ifdef FT_DEFERRED_SHADE
#define FT_HIT_YARN_C(h) (h).yarnC
#define FT_HIT_YARN_N(h) (h).yarnN
#define FT_HIT_YARN_B(h) (h).yarnB
#define FT_HIT_CURVE(h) (h).curve
#else
#define FT_HIT_YARN_C(h) mix(lineYarnC0, lineYarnC1, (h).along)
#define FT_HIT_YARN_N(h) mix(lineYarnN0, lineYarnN1, (h).along)
#define FT_HIT_YARN_B(h) mix(lineYarnB0, lineYarnB1, (h).along)
#define FT_HIT_CURVE(h) lineCurve
#endif

#ifndef FT_DEFERRED_SHADE

// The first hit of the eye ray through o with the capsule. o is a point of
// the rectangle, within a few radii of the line, so the quadratics are solved
// relative to it (from the eye they would lose the radius², ~1e-6 of the
// distance², to float rounding); the hit may lie nearer the eye than o.
bool castCapsule(vec3 o, out FiberHit h) {
  vec3 d = normalize(o - view.cameraPos.xyz);
  vec3 axis = lineP1 - lineP0;
  float len2 = max(dot(axis, axis), 1e-30);
  vec3 a = axis * inversesqrt(len2);
  const float kMiss = 3.0e38;
  float best = kMiss;
  int part = -1;  // 0: the tube, 1: the ball at p0, 2: the ball at p1
  float tubeRadius = 0.0;
  // Tube: the cylinder with the radius at the ray's closest approach to the
  // axis (the radius changes little along one line).
  vec3 m = o - lineP0;
  vec3 dp = d - dot(d, a) * a, mp = m - dot(m, a) * a;
  float qa = dot(dp, dp);
  if (qa > 1e-12) {
    float uClosest = clamp(dot(m - dot(mp, dp) / qa * d, axis) / len2, 0.0, 1.0);
    float r = FT_COVERAGE_SCALE * mix(lineHalfWidth.x, lineHalfWidth.y, uClosest);
    tubeRadius = r;
    float qb = dot(dp, mp), qc = dot(mp, mp) - r * r;
    float disc = qb * qb - qa * qc;
    if (disc >= 0.0) {
      float s = (-qb - sqrt(disc)) / qa;
      float u = dot(m + s * d, axis) / len2;
      if (u >= 0.0 && u <= 1.0) { best = s; part = 0; }
    }
  }
  // The end balls. A tapered line: the tube's radius at the ray's closest
  // approach exceeds the thinner end's, and a ray within it there that enters
  // the cylinder past that end crosses the end's plane within the same radius
  // of the end — capsuleCovers accepts it, and the balls of the ends' own
  // radii missed it (4 pixels of the glove close-up, found by sweeping the
  // probe's rays over 0.9–1 r). So where nothing was hit, a second round takes
  // the balls with the tube's radius; every other hit is as before. (A loop,
  // not a branch: llvmpipe skips its second round when no lane needs it.)
  for (int round = 0; round < 2; ++round) {
    float floorRadius = round == 0 ? 0.0 : tubeRadius;
    for (int i = 0; i < 2; ++i) {
      vec3 oc = o - (i == 0 ? lineP0 : lineP1);
      float w = max(FT_COVERAGE_SCALE * (i == 0 ? lineHalfWidth.x : lineHalfWidth.y), floorRadius);
      float b = dot(oc, d), disc = b * b - (dot(oc, oc) - w * w);
      if (disc < 0.0) continue;
      float s = -b - sqrt(disc);
      if (s < best) { best = s; part = 1 + i; }
    }
#ifdef FT_FAULT_CAST_TAPER_MISS
    break;  // the balls of the ends' own radii only
#endif
    if (part >= 0 || !(tubeRadius > 0.0)) break;
  }
  if (part < 0) return false;
  h.position = o + best * d;
  float u = clamp(dot(h.position - lineP0, axis) / len2, 0.0, 1.0);
  if (part == 1) u = 0.0;
  if (part == 2) u = 1.0;
  h.along = u;
  vec3 t = mix(lineT0, lineT1, u);
  h.tangent = dot(t, t) > 0.0 ? normalize(t) : a;
  vec3 radial = part == 0 ? h.position - (lineP0 + u * axis) : h.position - (part == 1 ? lineP0 : lineP1);
#ifdef FT_FAULT_SHADE_CAP_TUBE_NORMAL
  radial -= dot(radial, h.tangent) * h.tangent;  // the end balls shaded as if they were tube
#else
  if (part == 0) radial -= dot(radial, h.tangent) * h.tangent;
#endif
  h.normal = dot(radial, radial) > 0.0 ? normalize(radial) : -d;
#ifdef FT_FAULT_SHADE_FLAT_NORMAL
  vec3 toEye = -d - dot(-d, h.tangent) * h.tangent;
  h.normal = normalize(toEye);  // the flat strip's normal: the fiber loses its roundness
#endif
  return true;
}

// Whether the eye ray through o passes within the capsule's radius of its
// line (the capsule is the set of points that close to it, with the radius
// at the closest point): the coverage test of a multisample position, a
// third of castCapsule, which only the shading hit needs. o lies within a few
// radii of the line, so the distances are taken relative to it.
bool capsuleCovers(vec3 o) {
  vec3 d = o - view.cameraPos.xyz;
  vec3 axis = lineP1 - lineP0;
  vec3 w = o - lineP0;
  float a = dot(d, d), b = dot(d, axis), c = dot(axis, axis), e = dot(axis, w), f = dot(d, w);
  float den = a * c - b * b;  // 0 for a line seen end-on: its nearer end decides
  float u = clamp(den > 1e-12 * a * c ? (a * e - b * f) / den : (b > 0.0 ? 0.0 : 1.0), 0.0, 1.0);
  vec3 q = w - u * axis;               // from the axis point to o
  vec3 across = q - (dot(q, d) / a) * d;  // its part across the ray
  float r = FT_COVERAGE_SCALE * mix(lineHalfWidth.x, lineHalfWidth.y, u);
  // 0.05 % inside the radius: castCapsule's quadratic rounds otherwise than
  // these distances, and a ray that grazed the capsule passed this test but
  // missed the cast, which dropped the whole fragment when it was the shading
  // ray — its solidly covered samples too (a hole in the fiber, and an
  // occluder sample claiming what the frame did not draw: docs/shaded-frame.md,
  // "Wider occluders"). The margin is ~100 times the two formulas'
  // disagreement found at such a ray (8e-6 of r²), so any ray this test
  // accepts hits.
#ifdef FT_FAULT_COVERAGE_NO_MARGIN
  return dot(across, across) <= r * r;  // to the full radius: a grazing ray can pass and miss the cast
#else
  return dot(across, across) <= 0.999 * (r * r);
#endif
}
#ifdef FT_STRIP_RAY_PROBE
// Probe (validation/strip_impostor_cases.cpp): rays swept across the two
// radii where the coverage test is weakest — its own bound √0.999 r and the
// capsule's outline r — in steps of 4e-6 r, and over 0.9–1 r, by moving o across its ray
// (first order: the ray's closest point moves by the step times its distance
// over o's). Returns how many the coverage test accepts and castCapsule
// misses: none, or some fragment loses its samples.
float probeGrazingMisses(vec3 o) {
  vec3 eye = view.cameraPos.xyz;
  vec3 d = o - eye, axis = lineP1 - lineP0, w = o - lineP0;
  float a = dot(d, d), b = dot(d, axis), c = dot(axis, axis), e = dot(axis, w), f = dot(d, w);
  float den = a * c - b * b;
  if (!(den > 1e-12 * a * c)) return 0.0;
  float u = clamp((a * e - b * f) / den, 0.0, 1.0);
  vec3 q = w - u * axis;
  vec3 across = q - (dot(q, d) / a) * d;
  float len = length(across);
  if (!(len > 0.0)) return 0.0;
  float r = FT_COVERAGE_SCALE * mix(lineHalfWidth.x, lineHalfWidth.y, u);
  float reach = dot(lineP0 + u * axis - eye, d) / a;  // the closest point's distance along the ray, over o's
  float misses = 0.0;
  for (int k = 0; k < 132; ++k) {
    // 33 rays about each of the two radii, 66 over 0.9–1 r (a tapered
    // line's end: a structural miss, not a rounding one, lies deeper)
    float target = k < 66 ? r * ((k < 33 ? sqrt(0.999) : 1.0) + float(k % 33 - 16) * 4e-6)
                          : r * (0.9 + float(k - 66) * (0.1 / 65.0));
    vec3 ok = o + ((target - len) / max(reach, 1e-6)) * (across / len);
    FiberHit hk;
    if (capsuleCovers(ok) && !castCapsule(ok, hk)) misses += 1.0;
  }
  return misses;
}
#endif
#endif  // FT_DEFERRED_SHADE

float selfShadowTexel(uint i, uint j, uint k) { return selfShadowTexels[ftSelfShadowIndex(selfShadow, i, j, k)]; }
vec4 selfShadowCorners(SelfShadowSample s, uint k) {
  return vec4(selfShadowTexel(s.u.x, s.u.z, k), selfShadowTexel(s.u.y, s.u.z, k), selfShadowTexel(s.u.x, s.u.w, k),
              selfShadowTexel(s.u.y, s.u.w, k));
}

// The hit in the yarn's cross-section (000 §4.1): its offset from the yarn
// centre in (N̂, B̂), the frame blended along the line, and the angle of
// ply 0's N̂ there (ftPlyFrame: 2π·sign·fract(s·r_ply)).
struct CrossSection {
  vec2 x;
  vec3 N, B;
  float plyAngle;
};
CrossSection crossSection(FiberHit h) {
  CrossSection c;
  vec4 cs = FT_HIT_YARN_C(h);
  c.N = normalize(FT_HIT_YARN_N(h));
  vec3 b = FT_HIT_YARN_B(h);
  c.B = normalize(b - dot(b, c.N) * c.N);
  vec3 q = h.position - cs.xyz;
  c.x = vec2(dot(q, c.N), dot(q, c.B));
  TwistRates r = ftTwistRates(yarn, curves[FT_HIT_CURVE(h)]);
  c.plyAngle = FT_TWO_PI * yarn.plyTwistSign * fract(cs.w * r.ply);
  return c;
}
// The yarn's axis T̂ = N̂ × B̂ at the cross-section.
vec3 crossSectionAxis(CrossSection c) { return normalize(cross(c.N, c.B)); }

// T_self = exp(−κD) of the light towards `wi` (000 §4.1, common/self_shadow.h).
float selfShadowTransmittance(CrossSection c, vec3 wi) {
#ifdef FT_FAULT_FRAME_SELF_SHADOW_LIGHT_SIGN
  wi = -wi;  // the light's propagation taken for its direction
#endif
  SelfShadowSample s = ftSelfShadowSample(selfShadow, c.x, vec2(dot(wi, c.N), dot(wi, c.B)), c.plyAngle);
  float density = ftSelfShadowBlend(s, selfShadowCorners(s, s.r.x), selfShadowCorners(s, s.r.y));
  return ftSelfShadowTransmittance(selfShadow, s, density);
}

// ---- the core-fiber texture (000 §3.2, eq. 3–4; common/core_texture.h) ----
// The core strip's hit, in the ply frame of the generator (ftPlyFrame,
// ftFiberPosition): z along the yarn's T̂, x along the ply's own N̂_j (from the
// yarn centre to the ply centre), y along B̂_j = T̂ × N̂_j. The bake looks along
// −x; a viewer at azimuth ψ_rel from N̂_j sees the texture at
// u = ftCoreTextureU(Φ(s), ψ_rel, k_ψ) (eq. 3 as settled: docs/core-texture.md),
// v across the strip, whose half-width is the core's at the LoD of eq. 4
// (ftCoreHalfWidthAt: λ² towards the whole ply), so the texture stretches
// with it. Returns false on a hole (h = 0 at the nearest texel: 000 "use the
// height-map to determine these holes"), else replaces the hit's normal,
// tangent (the BCSDF's fiber direction) and position (moved by h towards the
// viewer, which the self-shadow lookup then uses); the visibility pass leaves
// the normal and tangent to the shading kernel (finishCoreTexture).
vec4 coreTexel0(uint i, uint j) { return coreTex0[j * coreTexture.columns + i]; }
vec4 coreTexel1(uint i, uint j) { return coreTex1[j * coreTexture.columns + i]; }
// mix(a, b, t) written out as a + t (b − a): Mesa's NIR lowers each mix()
// by what else the shader computes — to this form in the fragment stages
// here, to a (1 − t) + b t in the deferred shading kernel — so the kernel's
// finishCoreTexture rounded the lerps differently from the forward pass (up
// to 1.6e-4 of a pixel's value through cotton's 1°-wide lobes). Written out,
// every pass computes the same, and the fragment stages exactly what mix()
// gave them (the glove's EXRs are byte-identical). Not `precise`: that
// reaches back into u and v, i.e. the hole test, and changed the frame.
vec4 coreMix(vec4 a, vec4 b, float t) { return a + t * (b - a); }
vec4 coreLerp0(CoreLookup l) {
  return coreMix(coreMix(coreTexel0(l.i.x, l.j.x), coreTexel0(l.i.y, l.j.x), l.w.x),
                 coreMix(coreTexel0(l.i.x, l.j.y), coreTexel0(l.i.y, l.j.y), l.w.x), l.w.y);
}
vec4 coreLerp1(CoreLookup l) {
  return coreMix(coreMix(coreTexel1(l.i.x, l.j.x), coreTexel1(l.i.y, l.j.x), l.w.x),
                 coreMix(coreTexel1(l.i.x, l.j.y), coreTexel1(l.i.y, l.j.y), l.w.x), l.w.y);
}
// The texture's normal and fiber direction at lookup l (t0 = coreLerp0(l)) in
// the frame (T̂, side, v̂_p): the forward pass's, and the deferred shading
// kernel's from the values the visibility pass wrote (finishCoreTexture).
void coreTextureShadingFrame(CoreLookup l, vec4 t0, vec3 T, vec3 side, vec3 vp, inout FiberHit h) {
  vec4 t1 = coreLerp1(l);
  vec3 n = ftCoreTexelNormal(t0);  // (n_x toward the viewer, n_y, n_z) in the bake frame
  h.normal = normalize(n.z * T + n.y * side + n.x * vp);
  vec3 t = t1.x * T + t1.y * side + t1.z * vp;
  if (dot(t, t) > 0.0) h.tangent = normalize(t);
}
#ifndef FT_DEFERRED_SHADE
bool applyCoreTexture(inout FiberHit h) {
  CrossSection c = crossSection(h);
  vec4 cs = FT_HIT_YARN_C(h);
  vec3 T = crossSectionAxis(c);
  vec3 axisPoint = mix(lineP0, lineP1, h.along);  // the ply centre (the core runs along it)
  vec3 q = axisPoint - cs.xyz;
  q -= dot(q, T) * T;
  vec3 plyN = dot(q, q) > 1e-6 * yarn.plyRadius * yarn.plyRadius
                  ? normalize(q)
                  : cos(c.plyAngle) * c.N + sin(c.plyAngle) * c.B;  // one ply on the axis: ply 0's frame
  vec3 plyB = cross(T, plyN);
  vec3 toEye = normalize(view.cameraPos.xyz - h.position);
  vec3 vp = toEye - dot(toEye, T) * T;
  vp = dot(vp, vp) > 1e-12 ? normalize(vp) : plyN;  // seen end-on: any azimuth
  float psiRel = atan(dot(vp, plyB), dot(vp, plyN));
  vec3 side = cross(T, vp);  // the texture's y: B̂_j when ψ_rel = 0
  // Φ(s) with the curve's own rates (whole turns on closed curves, as the generator).
  TwistRates r = ftTwistRates(yarn, curves[FT_HIT_CURVE(h)]);
  YarnParams rates = yarn;
  rates.fiberTurnsPerLength = r.fiber;
  rates.plyTurnsPerLength = r.ply;
  float u = ftCoreTextureU(ftCoreBundlePhaseTurns(rates, cs.w, FT_CORE_TEXTURE_K_PLY), psiRel, ftCoreTextureKPsi(yarn));
  float halfWidth = max(mix(lineHalfWidth.x, lineHalfWidth.y, h.along), 1e-30);
  float y = dot(h.position - axisPoint, side);
  float v = 0.5 + 0.5 * y / halfWidth;
  CoreLookup l = ftCoreTextureLookup(coreTexture.width, coreTexture.height, u, v);
  uint ni = l.w.x < 0.5 ? l.i.x : l.i.y, nj = l.w.y < 0.5 ? l.j.x : l.j.y;
#ifndef FT_FAULT_FRAME_CORE_HOLES_DRAWN
  if (coreTexel0(ni, nj).x <= 0.0) return false;  // a hole: what lies behind shows through
#ifdef FT_OCCLUDER_PASS
  // An occluder only where the texels around the nearest are solid too: the
  // shaded pass's hit, from another ray origin, may round to a neighbour.
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      // u wraps; a select, not %: llvmpipe divides lane by lane.
      uint i = di < 0 ? (ni == 0u ? coreTexture.width : ni) - 1u : (di > 0 && ni + 1u == coreTexture.width ? 0u : ni + uint(di));
      uint j = uint(clamp(int(nj) + dj, 0, int(coreTexture.height) - 1));
      if (coreTexel0(i, j).x <= 0.0) return false;
    }
#endif
#endif
  vec4 t0 = coreLerp0(l);
#ifdef FT_VISIBILITY_PASS
  // Deferred: only the hole and the moved position (the depth) decide
  // visibility here; the normal and fiber direction are the shading
  // kernel's (finishCoreTexture), from v̂_p and (u, v) as computed here,
  // which the record carries in the normal's and the tangent's place: on
  // llvmpipe this pass pays every statement for every rasterised fragment
  // (docs/shaded-frame.md).
  h.tangent = vec3(u, v, 0.0);
  h.normal = vp;
#else
  coreTextureShadingFrame(l, t0, T, side, vp, h);
#endif
  h.position = axisPoint + (2.0 * t0.x - 1.0) * halfWidth * vp + y * side;
  return true;
}
#endif  // FT_DEFERRED_SHADE

// ---- Ambient occlusion (000 §4.2, common/ambient_occlusion.h) ----
// The yarn's AO at the hit: the cubic at r̂ = |x|/W, x the hit's offset from
// the *yarn* centre (000: the ply centre would miss the other plies'
// occlusion), or the 2D texture turned back by the ply-0 angle.
float aoTexel(uint i, uint j) { return aoTexels[j * ao.resolution + i]; }
float ambientOcclusion(CrossSection c) {
  if ((shading.flags.w & FT_APPEARANCE_AO_TEXTURE) != 0u) {
    AoTexelLookup t = ftAoTextureLookup(ao, c.x, vec2(cos(c.plyAngle), sin(c.plyAngle)));
    return ftAoBilinear(aoTexel(t.lo.x, t.lo.y), aoTexel(t.hi.x, t.lo.y), aoTexel(t.lo.x, t.hi.y),
                        aoTexel(t.hi.x, t.hi.y), t.weight);
  }
  vec2 x = c.x;
#ifdef FT_FAULT_FRAME_AO_PLY_CENTRE
  // r̂ from the nearest ply centre: the other plies' occlusion is lost.
  float best = 3.0e38;
  for (uint j = 0u; j < ao.density.plyCount; ++j) {
    vec2 d = c.x - ao.density.plyRadius * ftPlyDirection(ao.density, j, c.plyAngle);
    if (dot(d, d) < best) { best = dot(d, d); x = d; }
  }
#endif
  return ftAoCubicAt(ao, length(x) / ao.halfWidth);
}

// V_map of light i at p (notes A5): nearest texel, the far side stored with its bias.
float shadowMapVisibility(int i, vec3 p) {
  vec3 m = ftShadowNdcToMap(ftShadowNdc(shadowMap, ftShadowLightSpace(shadowMap, i, p)));
  ivec4 t = ftShadowTexel(shadowMap, m);
  if (t.w < 0) return 1.0;  // outside the map: no yarn there
  if (shadowMap.count.z != FT_SHADOW_FILTER_PCF)
    return ftShadowVisibility(m.z, shadowMapTexels[ftShadowMapIndex(shadowMap, i, t.x, t.y)]);
  int n = int(shadowMap.count.y);
  vec4 f = ftShadowPcfFootprint(m, n);
  int x0 = ftShadowPcfTexel(f.x, 0, n), x1 = ftShadowPcfTexel(f.x, 1, n);
  int y0 = ftShadowPcfTexel(f.y, 0, n), y1 = ftShadowPcfTexel(f.y, 1, n);
  return ftShadowPcfCombine(f, ftShadowVisibility(m.z, shadowMapTexels[ftShadowMapIndex(shadowMap, i, x0, y0)]),
                            ftShadowVisibility(m.z, shadowMapTexels[ftShadowMapIndex(shadowMap, i, x1, y0)]),
                            ftShadowVisibility(m.z, shadowMapTexels[ftShadowMapIndex(shadowMap, i, x0, y1)]),
                            ftShadowVisibility(m.z, shadowMapTexels[ftShadowMapIndex(shadowMap, i, x1, y1)]));
}

// The lobes' (Z_R, Z_TT) at angles a from the table (common/bcsdf.h), not
// the quadrature the ground truth runs.
vec2 lobeNormsAt(FiberAngles a) {
  float theta = ftLobeNormAngle(a), betaR = shading.fabric.colorR.w, betaTT = shading.fabric.colorTT.w;
  vec4 r = ftLobeNormLookup(theta, betaR, FT_LOBE_NORM_TABLE_SIZE);
  vec4 t = ftLobeNormLookup(theta, betaTT, FT_LOBE_NORM_TABLE_SIZE);
  vec2 z = vec2(ftLobeNormFromTable(r, theta, betaR, lobeNorm[int(r.x)].x, lobeNorm[int(r.y)].x),
                ftLobeNormFromTable(t, theta, betaTT, lobeNorm[int(t.x)].y, lobeNorm[int(t.y)].y));
#ifdef FT_FAULT_FRAME_LOBE_NORM_SWAPPED
  z = z.yx;  // each lobe normalised by the other's Z
#endif
  return z;
}

// Light i's direct term (common/fiber_shading.h) with the lobes' Z from the table.
vec3 directLight(int i, FiberHit h, vec3 v) {
  FiberAngles a = ftFiberAngles(h.tangent, vec3(shading.lightDirection[i]), v);
  return ftFiberDirectNormed(shading, i, a, h.normal, lobeNormsAt(a));
}

// ---- Dual scattering (001 §4.1 eq. 8, §4.3 eq. 11, notes A7 "Runtime") ----
DsTexel dsTexel(int k) {
  int o = k * FT_DS_ROWS;
  DsTexel t;
  t.aF = dsTable[o + FT_DS_ROW_A_F].xyz;
  t.aB = dsTable[o + FT_DS_ROW_A_B].xyz;
  t.alphaF = dsTable[o + FT_DS_ROW_ALPHA_F].xyz;
  t.alphaB = dsTable[o + FT_DS_ROW_ALPHA_B].xyz;
  t.betaF2 = dsTable[o + FT_DS_ROW_BETA_F2].xyz;
  t.betaB2 = dsTable[o + FT_DS_ROW_BETA_B2].xyz;
  t.ab = dsTable[o + FT_DS_ROW_AB].xyz;
  t.deltaB = dsTable[o + FT_DS_ROW_DELTA_B].xyz;
  t.sigmaB2 = dsTable[o + FT_DS_ROW_SIGMA_B2].xyz;
  return t;
}

// Light i's direct term with dual scattering, without the shadow map (the
// caller's Ψ_G^Yarn) and the self-shadow T (the caller's when no ξ bake is bound):
//   E_i [(1 − k_d) ξ_M ξ_N Ψ_M Ψ_N (f + d_b f_back^dir) cos θ_i + Ψ_M Ψ_N (k_d/π) max(0, n·ω_i)]
// f and f_back^dir at the fiber's angles (f_back from the DS table at θ_d);
// ξ and Ψ_G^Fiber at x = (u, v): u = the yarn's length coordinate s over P,
// v = the offset from the yarn centre along T × ω_o⊥ over W, and the angles
// of light and view about the *yarn* tangent T (common/ds_correction.h).
vec3 dualScatteringLight(int i, FiberHit h, CrossSection c, vec3 v) {
  vec3 wi = vec3(shading.lightDirection[i]);
  FiberAngles a = ftFiberAngles(h.tangent, wi, v);
  vec3 f = shading.flags.y == FT_SHADING_SIMPLE ? vec3(ftSimpleSpecular(shading.simple.x, shading.simple.y, a))
                                                : ftBcsdfNormed(shading.fabric, a, lobeNormsAt(a));
  vec3 k = ftDsLookup(ftDsThetaD(a), FT_DS_TABLE_SIZE);
  DsTexel t = ftDsMix(dsTexel(int(k.x)), dsTexel(int(k.y)), k.z);
  vec3 local = ftDsRuntime(f, ftDsBackscatter(t, a, vec3(0.0)), 1.0);  // k_fly = 1: no flyaway scaling (A8)
  // The yarn's frame at the hit.
  vec3 T = crossSectionAxis(c);
  vec4 cs = FT_HIT_YARN_C(h);
  vec3 vp = v - dot(v, T) * T;
  vec3 side = dot(vp, vp) > 1e-12 ? normalize(cross(T, vp)) : c.B;  // seen end-on: any side
  // cs is the yarn at the hit's place along the fiber's line (its axis); on a
  // thick core tube the hit lies off that place along T by up to its radius
  // times the ply's tilt: the hit's own length coordinate adds that offset.
  vec3 q = h.position - cs.xyz;
  vec2 uv = ftXiTexCoord(xiLayout, cs.w + dot(q, T), dot(q, side));
#ifdef FT_FAULT_FRAME_DS_FIBER_TANGENT
  vec2 angles = ftXiRelativeAngles(h.tangent, wi, v);  // about the fiber's tangent, not the yarn's
#else
  vec2 angles = ftXiRelativeAngles(T, wi, v);
#endif
#ifdef FT_FAULT_FRAME_DS_PHI_MIRRORED
  angles.y = angles.y > 0.0 ? FT_TWO_PI - angles.y : 0.0;  // φ measured the other way round
#endif
  XiLookup l = ftXiLookup(xiLayout, uv, angles);
  // The buffers hold logarithms (ftXiEncode); per corner log ξ + log Ψ first
  // (they cancel), Ψ alone for the diffuse term.
  vec3 m = vec3(0.0), n = vec3(0.0), pm = vec3(0.0), pn = vec3(0.0);
  for (int q = 0; q < 8; ++q) {
    float wm = ftXiCornerWeight(l, l.theta, q), wn = ftXiCornerWeight(l, l.phi, q);
    uint im = ftXiCorner(xiLayout, l, l.theta, q), iN = ftXiCorner(xiLayout, l, l.phi, q);
    vec3 lpm = psiM[im].rgb, lpn = psiN[iN].rgb;
    m += wm * (xiM[im].rgb + lpm);
    n += wn * (xiN[iN].rgb + lpn);
    pm += wm * lpm;
    pn += wn * lpn;
  }
  vec3 psi = ftXiDecode(pm + pn);         // Ψ_G^Fiber
  vec3 correction = ftXiDecode(m + n);    // ξ_M ξ_N Ψ_M Ψ_N
  float cosThetaI = FT_FAULT_SHADING_COS_DROPPED_ON ? 1.0 : cos(a.thetaI);
  vec3 diffuse = vec3(shading.diffuse) * (max(dot(h.normal, wi), 0.0) / FT_PI);
  return vec3(shading.lightIrradiance[i]) *
         ((vec3(1.0) - vec3(shading.diffuse)) * correction * local * cosThetaI + psi * diffuse);
}

#if defined(FT_FRAME_DUAL_SCATTERING) && defined(FT_FRAME_ENVIRONMENT)
// The ξ texture coordinate of the hit and the yarn tangent T, as
// dualScatteringLight forms them (for eq. 17's per-lobe lookups).
vec2 xiTexCoordAt(FiberHit h, CrossSection c, vec3 v, out vec3 T) {
  T = crossSectionAxis(c);
  vec4 cs = FT_HIT_YARN_C(h);
  vec3 vp = v - dot(v, T) * T;
  vec3 side = dot(vp, vp) > 1e-12 ? normalize(cross(T, vp)) : c.B;
  vec3 q = h.position - cs.xyz;
  return ftXiTexCoord(xiLayout, cs.w + dot(q, T), dot(q, side));
}
#endif

vec3 shadeFiber(FiberHit h) {
  vec3 v = normalize(view.cameraPos.xyz - h.position);
  vec3 radiance = vec3(0.0);
  bool selfShadowed = (shading.flags.w & FT_APPEARANCE_SELF_SHADOW) != 0u;
  bool occluded = (shading.flags.w & (FT_APPEARANCE_AO_FIT | FT_APPEARANCE_AO_TEXTURE)) != 0u;
  CrossSection c;
#ifdef FT_FRAME_DUAL_SCATTERING
  c = crossSection(h);  // the ξ lookup's yarn frame
  // A ξ bake's Ψ_G^Fiber replaces the self-shadow T: both are the shadowing
  // by the yarn's own fibers, never both. Without one T stays (plain DS).
#ifdef FT_FAULT_FRAME_DS_DOUBLE_SHADOW
  bool selfShadowT = selfShadowed;  // T on top of Ψ_G^Fiber
#else
  bool selfShadowT = selfShadowed && (shading.flags.w & FT_APPEARANCE_DS_CORRECTION) == 0u;
#endif
#else
  if (selfShadowed || occluded) c = crossSection(h);
  bool selfShadowT = selfShadowed;
#endif
  float ambientVisibility = occluded ? ambientOcclusion(c) : 1.0;
  for (int i = 0; i < int(shading.flags.x) && i < FT_MAX_LIGHTS; ++i) {
    float visibility = selfShadowT ? selfShadowTransmittance(c, shading.lightDirection[i].xyz) : 1.0;
#ifdef FT_FAULT_FRAME_AO_DIRECT
    visibility *= ambientVisibility;  // AO on the direct term too (000 Fig. 12d: it scales the ambient only)
#endif
#ifdef FT_FRAME_PCSS
    // Soft shadows: PCSS on the same map, the light a cone of radius α (common/pcss.h).
    if ((shading.flags.w & FT_APPEARANCE_SOFT_SHADOWS) != 0u) visibility *= ftPcssLightVisibility(shadowMap, pcss, i, h.position);
    else
#endif
    if ((shading.flags.w & FT_APPEARANCE_SHADOW_MAP) != 0u) visibility *= shadowMapVisibility(i, h.position);
#ifdef FT_FRAME_DUAL_SCATTERING
    radiance += dualScatteringLight(i, h, c, v) * visibility;
#else
    radiance += directLight(i, h, v) * visibility;
#endif
  }
  FiberAngles o = ftFiberAngles(h.tangent, v, v);
  vec3 k = ftAmbientLookup(o.thetaO, FT_AMBIENT_TABLE_SIZE);
  vec3 table = mix(ambientTable[int(k.x)].xyz, ambientTable[int(k.y)].xyz, k.z);
#ifdef FT_FRAME_ENVIRONMENT
  // The environment replaces the uniform ambient (docs/srbf-lighting.md):
  // T̃_j = the self-shadow T along the lobe's axis (eq. 17's fiber-level
  // shadowing at ω_d := μ_j) times, with --soft-shadows, T̃^Yarn_j by PCSS on
  // lobe j's map (1 without lobe maps); the DC term's visibility the AO, as
  // the uniform ambient's.
  float lobeT[FT_SRBF_LOBES];
  for (int j = 0; j < FT_SRBF_LOBES; ++j)
    lobeT[j] = (selfShadowT ? selfShadowTransmittance(c, environment.lobes[j].axisLambda.xyz) : 1.0) *
               softLobeVisibility(j, h.position);
  vec3 wo = v;
#ifdef FT_FAULT_FRAME_ENV_VIEW_REVERSED
  wo = -v;  // the eye ray's propagation taken for ω_o
#endif
#ifdef FT_FRAME_DUAL_SCATTERING
  // 001 eq. 17: ξ_M ξ_N Ψ_M Ψ_N per lobe at ω_d := μ_j (common/srbf_lighting.h).
  vec3 yarnT;
  vec2 xiUv = xiTexCoordAt(h, c, v, yarnT);
#ifdef FT_FAULT_FRAME_ENV_XI_ACROSS_MIRRORED
  xiUv.y = 1.0 - xiUv.y;  // the offset across the yarn measured the other way
#endif
  return radiance + ftSrbfFrameRadianceXi(shading, environment, srbfDims, h.tangent, h.normal, wo, table,
                                          ambientVisibility, lobeT, xiLayout, xiUv, yarnT);
#else
  return radiance + ftSrbfFrameRadiance(shading, environment, srbfDims, h.tangent, h.normal, wo, table,
                                        ambientVisibility, lobeT);
#endif
#else
  // 000 §4.2, Fig. 12d: AO scales the ambient term only.
  return radiance + ftFiberAmbient(shading, table) * ambientVisibility;
#endif
}

// The shaded colour of a fiber of `type` at h (the planted faults of fiber types too).
vec3 shadeFiberOfType(FiberHit h, uint type) {
  vec3 rgb = shadeFiber(h);
#ifdef FT_FAULT_SHADE_HAIR_BLACK
  if (type == FT_FIBER_HAIR) rgb = vec3(0.0);  // hair fibers drawn black
#endif
#ifdef FT_FAULT_SHADE_NONCORE_BRIGHT
  if (type != FT_FIBER_CORE) rgb *= 1.5;  // every explicit fiber 1.5x too bright
#endif
  return rgb;
}

// The deferred hit record (FT_VISIBILITY_TARGETS vec4s): every field of
// FiberHit that shadeFiber reads, bit for bit, and the fiber type; record 0's
// w is 1 + curve·4 + type (exact in a float), 0 where no fiber is drawn. At a
// textured core, tangent and normal hold (u, v, 0) and v̂_p, from which the
// kernel finishes the texture (finishCoreTexture).
void ftPackHit(FiberHit h, uint type, out vec4 r[FT_VISIBILITY_TARGETS]) {
  vec4 yc = FT_HIT_YARN_C(h);
  vec3 yn = FT_HIT_YARN_N(h), yb = FT_HIT_YARN_B(h);
  r[0] = vec4(h.position, float(1u + FT_HIT_CURVE(h) * 4u + type));
  r[1] = vec4(h.tangent, yc.w);
  r[2] = vec4(h.normal, yn.x);
  r[3] = vec4(yc.xyz, yn.y);
  r[4] = vec4(yb, yn.z);
}
void ftUnpackHit(vec4 r[FT_VISIBILITY_TARGETS], out FiberHit h, out uint type) {
  uint code = uint(r[0].w) - 1u;
  type = code & 3u;
  h.position = r[0].xyz;
  h.tangent = r[1].xyz;
  h.normal = r[2].xyz;
  h.along = 0.0;  // not read by the shading (the yarn fields carry the line)
  h.yarnC = vec4(r[3].xyz, r[1].w);
  h.yarnN = vec3(r[2].w, r[3].w, r[4].w);
  h.yarnB = r[4].xyz;
  h.curve = code >> 2u;
}

#ifdef FT_DEFERRED_SHADE
// The core-fiber texture's normal and fiber direction at a textured core's
// hit, as applyCoreTexture computes them in the forward pass, from the same
// floats: the record's yarn frame, v̂_p (normal's place) and (u, v)
// (tangent's place) as the visibility pass computed them. T̂ (from the yarn
// frame, crossSectionAxis), side (a cross product) and the lookup (fract,
// floor) round as there; the lerps are written out (coreMix). Where t = 0
// the forward pass keeps the cast's tangent, this T̂ (t_u > 0 at every solid
// texel and the nearest is solid, so it does not arise).
void finishCoreTexture(inout FiberHit h) {
  vec3 T = crossSectionAxis(crossSection(h)), vp = h.normal;
  vec3 side = cross(T, vp);
  CoreLookup l = ftCoreTextureLookup(coreTexture.width, coreTexture.height, h.tangent.x, h.tangent.y);
  h.tangent = T;
  coreTextureShadingFrame(l, coreLerp0(l), T, side, vp, h);
}
#endif

#ifndef FT_DEFERRED_SHADE
void main() {
#ifdef FT_OCCLUDER_PASS
  // The occluder pass (common/occlusion_cull.h): the rasterised depth of the
  // occluder rectangle stands (the capsule surely covers it), except where a
  // core strip's texture may have a hole for the shaded pass. Two draws
  // (FiberRenderer::drawOccluders): plain lines with nothing to compute here
  // (llvmpipe runs every statement of a fragment shader for every fragment,
  // masked, whatever the branches: only code the compiler removes is free),
  // and textured core strips.
#ifdef FT_OCCLUDER_PLAIN
  return;
#else
  FiberHit hc;
  if (!castCapsule(stripWorld, hc) || !applyCoreTexture(hc)) discard;
  return;
#endif
#endif
  // Behind the occluders at every sample of this pixel: the depth test would
  // reject it, so skip the ray casts and the shading (on a GPU that skips
  // discarded work; llvmpipe runs on, docs/llvmpipe-notes.md). Compiled in
  // only for frames with occluders (FiberRenderer::program).
#ifdef FT_OCCLUSION_TEST
  if (pyramid.size.w != 0u &&
      lineNearestDepth > occlusionTexels[ftOcclusionIndex(pyramid, 0u, uint(gl_FragCoord.x), uint(gl_FragCoord.y))])
    discard;
#endif
  // Coverage: the capsule tested at each multisample position (the rectangle
  // point there lies on that sample's eye ray), so a fiber thinner than a
  // pixel keeps the 4× coverage a plain strip had. Shading: once, at the
  // pixel centre's hit, or at the first covered sample's when the centre misses.
  bool centreCovered = capsuleCovers(stripWorld);
  // A centre ray that passes the axis well inside the radius (by more than the
  // pixel's diagonal at that depth) has every sample inside: skip the tests.
  vec3 eye = view.cameraPos.xyz;
  vec3 axis = lineP1 - lineP0;
  float len2 = max(dot(axis, axis), 1e-30);
  vec3 d = normalize(stripWorld - eye), m = stripWorld - lineP0;
  vec3 c = cross(d, axis);
  float u = dot(m - dot(m, d) * d, axis) / len2;  // ≈ the place of the ray's closest approach
  float axisDistance = dot(c, c) > 0.0 ? abs(dot(m, c)) * inversesqrt(dot(c, c)) : 3.0e38;
  float footprint = 0.75 * distance(eye, stripWorld) / view.cameraPos.w;
  bool deepInside = centreCovered && u > 0.0 && u < 1.0 &&
                    axisDistance + footprint < FT_COVERAGE_SCALE * min(lineHalfWidth.x, lineHalfWidth.y);
  int mask = deepInside ? (1 << gl_NumSamples) - 1 : 0;
  int firstCovered = -1;
  for (int i = 0; i < gl_NumSamples && !deepInside; ++i) {
    if (!capsuleCovers(stripWorldAtSample(i))) continue;
    mask |= 1 << i;
    if (firstCovered < 0) firstCovered = i;
  }
  // One ray cast for the shading hit: at the centre, or at the first covered
  // sample when the centre misses.
  FiberHit h;
  bool shadeHit = (centreCovered || firstCovered >= 0) &&
                  castCapsule(centreCovered ? stripWorld : stripWorldAtSample(max(firstCovered, 0)), h);
  mask &= gl_SampleMaskIn[0];
  if (mask == 0 || !shadeHit) discard;
  if (stripType == FT_FIBER_CORE && (shading.flags.w & FT_APPEARANCE_CORE_TEXTURE) != 0u && shaded != 0u &&
      !applyCoreTexture(h))
    discard;
  gl_SampleMask[0] = mask;
#ifndef FT_OCCLUDER_PASS
  // (The occluder pass, common/occlusion_cull.h, ends here: the rasterised
  // depth of its pushed-back rectangle stands at the samples the capsule
  // covers, less the core texture's holes, found as the shaded pass finds them.)
#ifdef FT_VISIBILITY_PASS
  // Deferred: the hit, shaded later by fiber_shade.comp.glsl.
  ftPackHit(h, stripType, hitRecord);
  hitLine = lineKey + 1u;
#elif defined(FT_STRIP_RAY_PROBE)
  // Red: the worst multisample ray's point; green: the pixel centre's;
  // blue: rays at the outline the coverage test accepts and the cast misses.
  float worst = 0.0;
  for (int i = 0; i < min(gl_NumSamples, 4); ++i)
    worst = max(worst, distance(probeWindow(stripWorldAtSample(i)), floor(gl_FragCoord.xy) + probeSamplePositions[i]));
  color = vec4(worst, distance(probeWindow(stripWorld), gl_FragCoord.xy), probeGrazingMisses(stripWorld), 1.0);
#else
  if (shaded != 0u) {
    color = vec4(shadeFiberOfType(h, stripType), 1.0);
  } else {
    float ct = dot(h.tangent, normalize(lightDir));
    float diffuse = sqrt(max(1.0 - ct * ct, 0.0));
    float facing = max(dot(h.normal, normalize(view.cameraPos.xyz - h.position)), 0.0);
    vec3 tint = stripType == FT_FIBER_CORE ? baseColor * 0.7 : baseColor;
    color = vec4(tint * (0.25 + 0.75 * diffuse) * (0.5 + 0.5 * facing), 1.0);
  }
#endif
  vec4 clip = view.viewProj * vec4(h.position, 1.0);
  gl_FragDepth = clamp(0.5 * (clip.z / clip.w) + 0.5, 0.0, 1.0);
#endif
}
#endif  // FT_DEFERRED_SHADE
