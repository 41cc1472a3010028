// faults.h — realistic shader bugs that `--inject` builds into the GPU side
// (as preprocessor defines of the shared headers / shaders). Each must make
// at least one validation case fail; tests/fault_injection_test.cpp checks it.
// The faults themselves are listed once, in validation/faults.def.
#pragma once
#include <string_view>

#include "common/ambient_occlusion.h"
#include "common/bcsdf.h"
#include "common/core_texture.h"
#include "common/ds_correction.h"
#include "common/dual_scattering.h"
#include "common/fiber_shading.h"
#include "common/lod.h"
#include "common/pcss.h"
#include "common/self_shadow.h"
#include "common/shadow_map.h"
#include "common/srbf.h"
#include "common/srbf_bcsdf.h"
#include "common/yarn_frame.h"
#include "reference/ds_correction.h"

namespace ft {

struct Fault {
  const char* name;         // --inject value
  const char* define;       // preprocessor symbol seen by the shaders
  const char* description;
  const char* caughtBy;     // metric expected to fail
  const char* paths;        // CaseResult::path values that must each fail a case, comma-separated
  const char* filter;       // the cases that can see it (regex; "" = all), to keep fault runs short
  const char* model;        // BCC (path from the repository root) the fault shows on; nullptr: built-in scene
  bool shared;              // lives in common/: planted on the CPU side too (at run time), not only the GPU's
};

inline constexpr Fault kFaults[] = {
#define FT_FAULT(name, define, caughtBy, paths, filter, model, shared, description) \
  {name, #define, description, caughtBy, paths, filter, (model)[0] ? (model) : nullptr, shared},
#include "validation/faults.def"
#undef FT_FAULT
};

// Switches a shared fault's CPU side (the GPU side is the define); the
// harness turns it on for its run and off again when the run ends.
inline void setSharedFault(std::string_view define, bool on) {
  if (define == "FT_FAULT_TANGENT_FALLBACK") ftFaultTangentFallback = on;
  if (define == "FT_FAULT_BCSDF_NORM_THETA_I") ftFaultBcsdfNormThetaI = on;
  if (define == "FT_FAULT_LOBE_NORM_TEXEL_ANGLE") ftFaultLobeNormTexelAngle = on;
  if (define == "FT_FAULT_CORE_LINES_ONE") ftFaultCoreLinesOne = on;
  if (define == "FT_FAULT_SHADING_COS_DROPPED") ftFaultShadingCosDropped = on;
  if (define == "FT_FAULT_SELF_SHADOW_SLICE_RANGE") ftFaultSelfShadowSliceRange = on;
  if (define == "FT_FAULT_SELF_SHADOW_PSI_SIGN") ftFaultSelfShadowPsiSign = on;
  if (define == "FT_FAULT_CORE_TEXTURE_PRESET_S") ftFaultCoreTexturePresetS = on;
  if (define == "FT_FAULT_CORE_TEXTURE_TANGENT_SIGN") ftFaultCoreTextureTangentSign = on;
  if (define == "FT_FAULT_CORE_TEXTURE_VIEW_SIGN") ftFaultCoreTextureViewSign = on;
  if (define == "FT_FAULT_AO_HALF_CIRCLE") ftFaultAoHalfCircle = on;
  if (define == "FT_FAULT_AO_LINEAR_VISIBILITY") ftFaultAoLinearVisibility = on;
  if (define == "FT_FAULT_SHADOW_MAP_FRONT_DEPTH") ftFaultShadowMapFrontDepth = on;
  if (define == "FT_FAULT_SHADOW_MAP_NO_REMAP") ftFaultShadowMapNoRemap = on;
  if (define == "FT_FAULT_XI_AXES_SWAPPED") ftFaultXiAxesSwapped = on;
  if (define == "FT_FAULT_XI_PHI_CLAMPED") ftFaultXiPhiClamped = on;
  if (define == "FT_FAULT_XI_BAKE_LIGHT_MIRRORED") ftFaultXiBakeLightMirrored = on;
  if (define == "FT_FAULT_DS_AB_DENOMINATOR") ftFaultDsAbDenominator = on;
  if (define == "FT_FAULT_DS_FORWARD_VARIANCE") ftFaultDsForwardVariance = on;
  if (define == "FT_FAULT_DS_HEMISPHERES_SWAPPED") ftFaultDsHemispheresSwapped = on;
  if (define == "FT_FAULT_DS_BETA_THETA_O") ftFaultDsBetaThetaO = on;
  if (define == "FT_FAULT_SRBF_SOLID_ANGLE_FLAT") ftFaultSrbfSolidAngleFlat = on;
  if (define == "FT_FAULT_SRBF_PHI_MIRROR") ftFaultSrbfPhiMirror = on;
  if (define == "FT_FAULT_SRBF_TABLE_NO_COSINE") ftFaultSrbfTableNoCosine = on;
  if (define == "FT_FAULT_SRBF_TABLE_COS_INDEX") ftFaultSrbfTableCosIndex = on;
  if (define == "FT_FAULT_SRBF_TABLE_LAMBDA_INVERSE") ftFaultSrbfTableLambdaInverse = on;
  if (define == "FT_FAULT_FRAME_DS_UNSCALED") ftFaultFrameDsUnscaled = on;
  if (define == "FT_FAULT_PCSS_RECEIVER_DEPTH") ftFaultPcssReceiverDepth = on;
  if (define == "FT_FAULT_PCSS_ALPHA_INVERSE_LAMBDA") ftFaultPcssAlphaInverseLambda = on;
}

inline const Fault* findFault(std::string_view name) {
  for (const Fault& f : kFaults)
    if (name == f.name) return &f;
  return nullptr;
}

}  // namespace ft
