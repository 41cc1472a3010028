// prt_ms_frame.glsl — GLSL-only include: the per-frame steps of local multiple
// scattering, 004 §5.3.1, on the GPU tables (common/prt_multiple_scattering.h
// holds the math; this file only reads the buffers). Shared by
// prt_multiple_scattering.comp.glsl (all steps per query) and
// prt_frame_gpu.comp.glsl (c_T once per cell, the rotation and dot once per
// segment). Not a stage of its own. The includer declares, before including
// this file and after common/prt_multiple_scattering.h:
//   tables[]   C_S as float[θ_o][36][4] (rgb, 0), then C_G as float[λ][6];
//   transfer[] A_C as float[cell][3][36][36], row j1, column j0.

// c_d of the light (xyz ω_d or the SG axis ξ, w λ; λ ≤ 0 directional): Y(ω_d),
// or the C_G row lerped at λ and turned to ξ.
ShCoeffs prtMsGpuLightCoeffs(vec4 light, uint thetaONodes, uint lambdaNodes, int bands) {
  uint cgBase = thetaONodes * uint(FT_SH_COEFFS) * 4u;
  vec3 lg = prtMsCgLookup(max(light.w, 0.0f), int(lambdaNodes));
  PrtMsZonal g;
  for (int l = 0; l < FT_SH_BANDS; ++l)
    g.c[l] = mix(tables[cgBase + uint(lg.x) * uint(FT_SH_BANDS) + uint(l)],
                 tables[cgBase + uint(lg.y) * uint(FT_SH_BANDS) + uint(l)], lg.z);
  return prtMsLightCoeffs(shEval(light.xyz), g, light.w > 0.0f, bands);
}

// c_T = A_C c_d of cell `cell` (rgb per coefficient; zero beyond bands²).
ShCoeffs3 prtMsGpuTransfer(uint cell, ShCoeffs cd, int bands) {
  int J = bands * bands;
  uint base = cell * 3u * uint(FT_SH_COEFFS * FT_SH_COEFFS);
  const uint plane = uint(FT_SH_COEFFS * FT_SH_COEFFS);
  ShCoeffs3 cT;
  for (int j1 = 0; j1 < FT_SH_COEFFS; ++j1) cT.c[j1] = vec3(0.0f);
  for (int j1 = 0; j1 < J; ++j1) {
    vec3 s = vec3(0.0f);
    for (int j0 = 0; j0 < J; ++j0) {
#ifdef FT_FAULT_MS_IIRTF_TRANSPOSED
      uint at = base + uint(j0 * FT_SH_COEFFS + j1);  // planted: A_Cᵀ c_d
#else
      uint at = base + uint(j1 * FT_SH_COEFFS + j0);
#endif
      s += vec3(transfer[at], transfer[at + plane], transfer[at + 2u * plane]) * cd.c[j0];
    }
    cT.c[j1] = s;
  }
  return cT;
}

// L̃^multi = C_S[θ_o] · (R_ωo c_T), C_S lerped between its two nearest rows.
// The rotation's storage is the includer's (SH_ROT_LOAD / SH_ROT_STORE).
vec3 prtMsGpuRadiance(ShCoeffs3 cT, vec3 t, vec3 wo, uint thetaONodes, int bands) {
  int J = bands * bands;
  ShCoeffs3 c = prtMsToOmegaOSpace(prtMsOmegaORotation(t, wo, bands), cT, bands);
  vec3 lk = prtMsCsLookup(prtMsThetaO(t, wo), int(thetaONodes));
  vec3 L = vec3(0.0f);
  for (int j = 0; j < J; ++j) {
    uint i0 = (uint(lk.x) * uint(FT_SH_COEFFS) + uint(j)) * 4u, i1 = (uint(lk.y) * uint(FT_SH_COEFFS) + uint(j)) * 4u;
    vec3 s0 = vec3(tables[i0], tables[i0 + 1u], tables[i0 + 2u]);
    vec3 s1 = vec3(tables[i1], tables[i1 + 1u], tables[i1 + 2u]);
    L += mix(s0, s1, lk.z) * c.c[j];
  }
  return L;
}
