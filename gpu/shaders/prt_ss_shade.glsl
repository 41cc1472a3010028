// prt_ss_shade.glsl — GLSL-only include: single scattering of one shading
// point, 004 §5.2 (common/prt_single_scattering.h holds the math; this file
// only picks the branch and reads the segment's SG weights). Shared by
// prt_single_scattering.comp.glsl (per request) and prt_frame_gpu.comp.glsl
// (per segment). Not a stage of its own. The includer declares svfWeights[]
// (float[rows][Q], the SVF group's layout) and includes
// common/prt_single_scattering.h first.

// Radiance of fabric `fabric` (p) at tangent t, ω_o, light (xyz ω_d or ξ, w λ;
// λ ≤ 0 directional), d_k at the light (ssdf), R_k (angle), weights row `row`
// of `axes` weights, λ_svf, V_glo.
vec3 prtSsShadeGpu(FabricParams p, int fabric, vec3 t, vec3 wo, vec4 light, float ssdf, float angle, uint row,
                   uint axes, float lambdaSvf, float vGlo) {
  if (light.w <= 0.0f) return ftPrtSsDirectional(p, t, wo, light.xyz, ssdf, vGlo);
  float w[FT_SVF_MAX_AXES];
  uint base = row * axes;
  for (int k = 0; k < FT_SVF_MAX_AXES; ++k) w[k] = k < int(axes) ? svfWeights[base + uint(k)] : 0.0f;
  return ftPrtSsSgLight(p, fabric, t, wo, light.xyz, light.w, ssdf, w, int(axes), angle, lambdaSvf, vGlo);
}
