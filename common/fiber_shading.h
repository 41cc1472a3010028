// fiber_shading.h — the radiance a fiber point sends towards the eye, shared
// by the GPU fragment stage and the Embree ground truth (reference/).
// Wu & Yuksel 2019 (000) §4.3 eq. 7 with the cos θ_i that eq. 8 implies
// (notes-rendering A4 [X]) and the diffuse term of the simple model that 000
// adds to the BCSDF, as an energy-conserving mix (docs/shading.md):
//   L_o = Σ_i E_i V_i [ (1 − k_d) f(ω_i, ω_o) cos θ_i + (k_d/π) max(0, n·ω_i) ]
//         + L_amb [ (1 − k_d) A(θ_o) + k_d ]
// E_i: irradiance of directional light i (normal to it), V_i its visibility
// (the GPU path has none yet: 1; the ground truth traces it), n the surface
// normal of the round fiber, A the ambient table (bcsdf.h). k_d ∈ [0, 1] is
// the fraction of the scattered energy that leaves through a Lambertian lobe
// (albedo 1, reflecting k_d·L_amb under a uniform ambient); the BCSDF carries
// the rest. The BCSDF's albedo F + (1 − F) C_TT is ≤ 1 (B1), so one bounce
// returns ≤ 1: added on top (000's "we also add the diffuse component"), it
// returned up to 1 + k_d and a path tracer diverged.
// The simple model (eq. 5) replaces f by f_spec and drops A.
#ifndef FT_FIBER_SHADING_H
#define FT_FIBER_SHADING_H
#include "bcsdf.h"

// Planted fault (validation/faults.def), shared: run-time switch in C++, define in GLSL.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultShadingCosDropped = false;
}
#define FT_FAULT_SHADING_COS_DROPPED_ON ::ft::ftFaultShadingCosDropped
#elif defined(FT_FAULT_SHADING_COS_DROPPED)
#define FT_FAULT_SHADING_COS_DROPPED_ON true
#else
#define FT_FAULT_SHADING_COS_DROPPED_ON false
#endif

#define FT_MAX_LIGHTS 4
#define FT_SHADING_KHUNGURN 0u
#define FT_SHADING_SIMPLE 1u
// Bits of ShadingParams.flags.w: the approximations of 000 §4 a frame uses
// (scene/shading_inputs.h AppearanceOptions).
#define FT_APPEARANCE_SELF_SHADOW 1u  // 000 §4.1 self-shadow texture (common/self_shadow.h)
#define FT_APPEARANCE_CORE_TEXTURE 2u  // 000 §3.2 core-fiber texture on the core strips (common/core_texture.h)
#define FT_APPEARANCE_AO_FIT 4u       // 000 §4.2 AO, distance-based cubic (common/ambient_occlusion.h)
#define FT_APPEARANCE_AO_TEXTURE 8u   // 000 §4.2 AO, the rotated 2D texture
#define FT_APPEARANCE_SHADOW_MAP 16u  // 000 §4.1 yarn shadow map (common/shadow_map.h)
// 001 §4.1 eq. 8 dual scattering (common/dual_scattering.h) with the runtime of
// 001 eq. 11 (common/ds_correction.h); with DS_CORRECTION a ξ/Ψ_G^Fiber bake
// is bound, whose Ψ_G^Fiber replaces the self-shadow T (docs/shaded-frame.md).
#define FT_APPEARANCE_DUAL_SCATTERING 32u
#define FT_APPEARANCE_DS_CORRECTION 64u
// 001 §4.5 eq. 14–16 SRBF environment lighting (common/srbf_lighting.h): the
// fitted environment replaces the uniform ambient.
#define FT_APPEARANCE_ENVIRONMENT 128u
// 001 §4.4: the flyaway textures drawn in the frame's third pass (common/flyaway.h, docs/flyaways.md).
#define FT_APPEARANCE_FLYAWAYS 256u
// 001 §4.5 (eq. 17's T̃^Yarn): PCSS soft shadows on the yarn shadow map, each
// light a cone of PcssParams.lightTanAlpha (common/pcss.h); needs SHADOW_MAP.
#define FT_APPEARANCE_SOFT_SHADOWS 512u
// Texels of the ambient table A(θ_o) over [−π/2, π/2] (notes-rendering A4 [F]).
#define FT_AMBIENT_TABLE_SIZE 64
// Texels per lobe of the lobe-normalisation table Z_p(|θ_i|) (bcsdf.h).
#define FT_LOBE_NORM_TABLE_SIZE 256

FT_NAMESPACE_BEGIN

// Uniform block of the shaded render (std140); the ground truth reads the same.
struct ShadingParams {
  FabricParams fabric;
  vec4 lightDirection[FT_MAX_LIGHTS];   // xyz unit vector towards light i, w unused
  vec4 lightIrradiance[FT_MAX_LIGHTS];  // rgb irradiance E_i on a plane normal to the light, w unused
  vec4 ambient;                         // rgb L_amb (uniform ambient radiance), w unused
  vec4 diffuse;                         // rgb k_d ∈ [0, 1]: the diffuse share of the scattered energy, w unused
  vec4 simple;                          // x k_s, y β of eq. 5 (radians), zw unused
  uvec4 flags;                          // x light count, y model (FT_SHADING_*), z background alpha 0/1, w FT_APPEARANCE_* bits
  vec4 background;                      // rgb radiance where no fiber is hit, w unused
};
FT_ASSERT_OFFSET(ShadingParams, lightDirection, 48)
FT_ASSERT_OFFSET(ShadingParams, lightIrradiance, 112)
FT_ASSERT_OFFSET(ShadingParams, ambient, 176)
FT_ASSERT_OFFSET(ShadingParams, flags, 224)
FT_ASSERT_OFFSET(ShadingParams, background, 240)
FT_ASSERT_SIZE(ShadingParams, 256)

// The fiber's response to directional light i, without visibility:
// E_i [(1 − k_d) f cos θ_i + (k_d/π) max(0, n·ω_i)], a = ftFiberAngles(t, ω_i,
// ω_o), z = (Z_R, Z_TT) at ftLobeNormAngle(a) (bcsdf.h: exact, or the frame's
// table).
FT_FUNC vec3 ftFiberDirectNormed(ShadingParams s, int i, FiberAngles a, vec3 n, vec2 z) {
  vec3 wi = vec3(s.lightDirection[i]);
  vec3 f = s.flags.y == FT_SHADING_SIMPLE ? vec3(ftSimpleSpecular(s.simple.x, s.simple.y, a))
                                          : ftBcsdfNormed(s.fabric, a, z);
  vec3 diffuse = vec3(s.diffuse) * (max(dot(n, wi), 0.0f) / FT_PI);
  float cosThetaI = FT_FAULT_SHADING_COS_DROPPED_ON ? 1.0f : cos(a.thetaI);  // eq. 7 as printed: no cos θ_i
  return vec3(s.lightIrradiance[i]) * ((vec3(1.0f) - vec3(s.diffuse)) * f * cosThetaI + diffuse);
}
// ... with the exact Z (the ground truth).
FT_FUNC vec3 ftFiberDirect(ShadingParams s, int i, vec3 t, vec3 n, vec3 wo) {
  FiberAngles a = ftFiberAngles(t, vec3(s.lightDirection[i]), wo);
  return ftFiberDirectNormed(s, i, a, n, ftLobeNorms(s.fabric, ftLobeNormAngle(a)));
}

// The ambient term L_amb [(1 − k_d) A(θ_o) + k_d], given A(θ_o) from the table.
FT_FUNC vec3 ftFiberAmbient(ShadingParams s, vec3 ambientTableValue) {
  vec3 a = s.flags.y == FT_SHADING_SIMPLE ? vec3(0.0f) : ambientTableValue;
  return vec3(s.ambient) * ((vec3(1.0f) - vec3(s.diffuse)) * a + vec3(s.diffuse));
}

FT_NAMESPACE_END
#endif  // FT_FIBER_SHADING_H
