// shading_inputs.h — everything a shaded fiber frame reads besides the
// fibers: the shading parameters (lights, fabric, ambient) and every table
// baked from them or from the yarn (000 §4). One struct, so that a new
// precomputed input is added in one place: here, in the two bake functions
// (reference/shading_inputs.h on the CPU, gpu/shading_inputs_gpu.h on the
// GPU) and in the renderer's binding (gpu/fiber_renderer.cpp, at the
// "shading inputs" slots of common/constants.h); every caller — render,
// trace, the harness, the benches — goes through those.
#pragma once
#include <filesystem>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/ambient_occlusion.h"
#include "common/core_texture.h"
#include "common/ds_correction.h"
#include "common/dual_scattering.h"
#include "common/fiber_shading.h"
#include "common/pcss.h"
#include "common/self_shadow.h"
#include "common/shadow_map.h"
#include "common/srbf.h"
#include "common/yarn_density.h"
#include "scene/ambient_occlusion_setup.h"
#include "scene/core_texture_input.h"
#include "image/image.h"
#include "scene/flyaway_input.h"

namespace ft {

// Which of 000 §4's approximations a frame uses, and at what size (each is
// switchable, so the fidelity of each can be measured against the all-fiber
// reference).
// 000 §4.2's two ways of using the yarn's ambient occlusion: none, the
// distance-based cubic (000's results use it), the rotated 2D texture.
enum class AoMode { None, Fit, Texture };
// "none" | "fit" | "texture"; InputError naming --ao otherwise.
AoMode parseAoMode(const std::string& name);
const char* aoModeName(AoMode mode);

struct AppearanceOptions {
  bool selfShadow = true;  // 000 §4.1: the self-shadow 3D texture (common/self_shadow.h)
  uint32_t selfShadowSize = FT_SELF_SHADOW_DEFAULT_SIZE;
  uint32_t selfShadowSlices = FT_SELF_SHADOW_DEFAULT_SLICES;
  float selfShadowKappa = -1.0f;  // κ of T = exp(−κD); negative: the default 2 r_f (notes §0.3)
  // 000 §3.2: the core-fiber texture on the core strips (common/core_texture.h).
  bool coreTexture = true;
  uint32_t coreTextureWidth = FT_CORE_TEXTURE_WIDTH;
  uint32_t coreTextureHeight = FT_CORE_TEXTURE_HEIGHT;
  // ---- ambient occlusion (000 §4.2; common/ambient_occlusion.h) ----
  AoMode ao = AoMode::Fit;  // 000's results use the distance-based cubic
  AoSettings aoSettings{};  // texture size, directions, κ (0: 2 r_f) of the bake
  // 000 §4.1 last paragraph: the yarn shadow map (common/shadow_map.h), drawn
  // per frame by FiberRenderer; N × N texels per light.
  bool shadowMap = true;
  uint32_t shadowMapSize = FT_SHADOW_MAP_DEFAULT_SIZE;
  uint32_t shadowMapFilter = FT_SHADOW_FILTER_PCF;  // the lookup: FT_SHADOW_FILTER_PCF or _NEAREST
  // 001 §4.1 eq. 8 / §4.3 eq. 11: dual scattering (Zinke et al. 2008) per
  // light, off by default (every picture without it stays bit-identical);
  // with a ξ bake (`fibertwin bake ds-correction --out FILE`) its ξ_M ξ_N and
  // Ψ_G^Fiber = Ψ_M Ψ_N, the latter in place of the self-shadow T. A file
  // implies dualScattering (render --ds-correction FILE). docs/shaded-frame.md.
  bool dualScattering = false;
  std::optional<std::filesystem::path> dsCorrectionFile;
  // 001 §4.5 eq. 14–16: SRBF environment lighting (FT_APPEARANCE_ENVIRONMENT,
  // docs/srbf-lighting.md). An OpenEXR lat-long map (common/srbf.h
  // conventions; render --env FILE), fitted with 16 SGs + the DC term by each
  // bake, and the I_M table at environmentTableDims (N_θo, N_θj, N_Δφ, N_λ).
  // It replaces the uniform ambient (params.ambient unused); lights still add.
  // environmentImage: a map in memory instead of the file (the harness).
  std::optional<std::filesystem::path> environmentMap;
  std::shared_ptr<const ImageRgbaF> environmentImage;
  glm::ivec4 environmentTableDims{16, 16, 8, 8};
  // 001 §4.4: flyaway fibers (eq. 12–13) baked into three seamless textures
  // and drawn in the frame's third pass (common/flyaway.h, docs/flyaways.md).
  // Off by default: every existing picture stays bit-identical, and the
  // Embree ground truth has no flyaways to compare with.
  bool flyaways = false;
  FlyawaySettings flyawaySettings{};
  // 001 §4.5 (eq. 17's T̃^Yarn, Fernando 2005): soft yarn shadows by PCSS on
  // the shadow map of each directional light, seen as a cone of directions
  // of angular radius lightAngularRadius (radians, [0, 60°]; 0.1 ≈ the
  // 5.7° of a small window). Needs shadowMap. Off by default: every picture
  // without it stays bit-identical (docs/soft-shadows.md).
  bool softShadows = false;
  float lightAngularRadius = 0.1f;

  static AppearanceOptions none() {
    AppearanceOptions o;
    o.selfShadow = false;
    o.coreTexture = false;
    o.ao = AoMode::None;
    o.shadowMap = false;
    return o;
  }
};

struct ShadingInputs {
  ShadingParams params{};
  // A(θ_k) of 000 eq. 7–10 at the FT_AMBIENT_TABLE_SIZE texel centres
  // (common/bcsdf.h ftAmbientTexelAngle), rgb.
  std::vector<glm::vec3> ambientTable;
  // (Z_R, Z_TT) of the longitudinal lobes at FT_LOBE_NORM_TABLE_SIZE angles
  // (common/bcsdf.h ftLobeNormTexelAngle): the frame looks Z up instead of
  // integrating it per fragment.
  std::vector<glm::vec2> lobeNormTable;
  // The self-shadow texture (000 §4.1) of the frame's yarn; no texels: off
  // (the flag bit FT_APPEARANCE_SELF_SHADOW of params.flags.w says so too).
  SelfShadowParams selfShadow{};
  YarnDensityParams density{};
  std::vector<float> selfShadowTexels;
  // The core-fiber texture (000 §3.2) of the frame's preset; no texels: off
  // (FT_APPEARANCE_CORE_TEXTURE). coreTexture.columns × height texels each.
  CoreTextureParams coreTexture{};
  std::vector<glm::vec4> coreTex0;  // (h, n_u, n_v, 0)
  std::vector<glm::vec4> coreTex1;  // (t_u, t_v, t_w, 0)
  // ---- ambient occlusion (000 §4.2) ----
  // Its params (the cubic's a0..a3 in aoParams.cubic, W, κ) and the n × n
  // texture (texel j·n + i); empty unless a mode is on (FT_APPEARANCE_AO_FIT
  // or FT_APPEARANCE_AO_TEXTURE of params.flags.w). Both modes carry both, so
  // the frame can be compared with either.
  AmbientOcclusionParams aoParams{};
  std::vector<float> aoTexels;
  // The yarn shadow map (000 §4.1): nothing baked, the renderer draws it per
  // frame with tubes of radius density.supportRadius (W); on when the bit
  // FT_APPEARANCE_SHADOW_MAP of params.flags.w is set.
  uint32_t shadowMapSize = 0;
  uint32_t shadowMapFilter = FT_SHADOW_FILTER_PCF;  // ShadowMapParams::count.z of the frame's lookup
  // ---- dual scattering (001 §4.1, §4.3; FT_APPEARANCE_DUAL_SCATTERING) ----
  // The DS table of the frame's fabric (FT_DS_ROWS vec4 per texel,
  // FT_DS_TABLE_SIZE texels, texel-major; each side's own bake), and the ξ
  // textures of 001 eq. 11 with their layout scaled to the model (P and W
  // times the fit's scale). Without a file (FT_APPEARANCE_DS_CORRECTION
  // clear): 1 × 1 × 1 × 1 textures of ones, so the shader has one path.
  // Empty when dual scattering is off.
  std::vector<glm::vec4> dsTable;
  DsCorrectionLayout dsCorrection{};
  std::vector<glm::vec4> xiM, xiN, psiM, psiN;
  // ---- SRBF environment lighting (001 §4.5; FT_APPEARANCE_ENVIRONMENT) ----
  // The fitted map (16 lobes + DC, the frame's UBO block) and the I_M table
  // of the frame's fabric (rgb at ftSrbfTableIndex, srbfTableDims); each
  // side's own fit sums and table bake. Empty table when off.
  SrbfEnvironment environment{};
  glm::ivec4 srbfTableDims{0};
  std::vector<glm::vec3> srbfTable;
  // ---- flyaways (001 §4.4; FT_APPEARANCE_FLYAWAYS) ----
  // The block and the three RGBA8 layers of pattern 0 (each side's own
  // curves and bake); empty when off.
  FlyawayParams flyaway{};
  std::vector<uint32_t> flyawayTexels;
  // ---- soft yarn shadows (001 §4.5, common/pcss.h) ----
  // tan α of each directional light's cone; used when FT_APPEARANCE_SOFT_SHADOWS is set.
  glm::vec4 lightTanAlpha{0.0f};
  // The SRBF environment whose lobes get shadow maps for T̃^Yarn_j (eq. 17):
  // FiberRenderer draws them when this is set (the environment's bake sets
  // it), lobeShadowMapSize² texels per lobe.
  std::optional<SrbfEnvironment> lobeShadowEnvironment;
  uint32_t lobeShadowMapSize = FT_PCSS_LOBE_DEFAULT_SIZE;
};

// What the bakes need of the frame's yarn besides the shading parameters:
// the preset fitted to the model (its ply-density field).
struct ShadingBakeRequest {
  ShadingParams params{};
  const struct YarnPreset* fittedPreset = nullptr;  // needed when an approximation is on
  AppearanceOptions appearance;
  // The frame's generator inputs (the core texture is baked from its fiber
  // table): needed when the core texture is on.
  const YarnParams* yarnParams = nullptr;
  const std::vector<FiberCoord>* fiberTable = nullptr;
};

// The frame's self-shadow layout for `density` (ftSelfShadowParams); InputError
// naming the option for a size outside [3, 4096] (slices [1, 4096]) or a κ
// that is NaN or infinite.
SelfShadowParams frameSelfShadowParams(const YarnDensityParams& density, const AppearanceOptions& options);

// The core texture a request asks for (AppearanceOptions.coreTextureWidth ×
// Height, the request's fiber table), or nothing (coreFibers 0) when the
// preset has no core fibers. std::invalid_argument naming `who` without the
// fiber table; InputError (naming the option) for a bad size.
CoreTextureInput frameCoreTextureInput(const ShadingBakeRequest& request, const char* who);
// Sets the shadow-map members of `in` for `options` (size in [16, 8192],
// InputError naming --shadow-map-size otherwise): one line in each bake.
void frameShadowMap(ShadingInputs& in, const YarnDensityParams& density, const AppearanceOptions& options);
// Sets the soft-shadow members of `in` for `options` (InputError naming
// --light-angular-radius outside [0, 60°] or --soft-shadows without the
// shadow map): one line in each bake, after frameShadowMap.
void frameSoftShadows(ShadingInputs& in, const AppearanceOptions& options);

// Sets the ξ members of `in` and the DS bits of in.params.flags.w for
// options.dualScattering (the caller bakes in.dsTable): the file of
// options.dsCorrectionFile read (InputError naming --ds-correction and the
// file: unreadable, or baked for another yarn preset or fabric than
// `preset` / params.fabric: refused), its layout scaled to the model (P' =
// preset.yarnAlpha, W' = W P'/P), or identity textures without a file.
void frameDsCorrection(ShadingInputs& in, const struct YarnPreset* preset, const AppearanceOptions& options);

// The environment map a request asks for (options.environmentImage, else the
// file of options.environmentMap read by readEnvironmentMap), or nothing;
// InputError naming --env (the file, the pixel) or --env-table (a size
// outside [2, 64]).
std::optional<ImageRgbaF> frameEnvironmentMap(const AppearanceOptions& options);
// The flyaway block of a request (AppearanceOptions::flyawaySettings, the
// fitted preset and its YarnParams); InputError naming the preset and value.
FlyawayParams frameFlyawayParams(const ShadingBakeRequest& request, const char* who);

// Throws std::invalid_argument naming the input when a table has the wrong
// size or a non-finite value (a bake that went wrong must not be drawn).
void checkShadingInputs(const ShadingInputs& inputs);

}  // namespace ft
