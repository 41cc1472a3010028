// fibertwin — command-line program: cross-check the GPU paths against the CPU
// reference (`validate`), render a yarn model on the GPU (`render`) and its
// Embree ground truth (`trace`), compare two images (`compare`), optimize a
// deformed stitch mesh into yarn curves (`knit`), describe the GL renderer
// (`info`), list injectable faults (`faults`), run the sharded bakes of
// bake/bakes.def in one process or across MPI ranks (`bake`) and write the
// procedural environment map of the SRBF fit (`env-sky`).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fmt/format.h>
#include <iostream>
#include <map>

#include "gpu/gl_context.h"
#include "image/image_io.h"
#include "reference/srbf_fit.h"
#include "scene/bcc_reader.h"
#include "scene/camera.h"
#include "scene/default_scene.h"
#include "scene/environment_map.h"
#include "scene/input_error.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_radius.h"
#include "validation/build_info.h"
#include "cli/bake_command.h"
#include "cli/compare_command.h"
#include "validation/draw_check.h"
#include "validation/faults.h"
#include "validation/harness.h"
#include "cli/knit_command.h"
#include "cli/prt_frame_command.h"
#include "cli/prt_sweep_command.h"
#include "cli/render_command.h"
#include "validation/report.h"

namespace {

// Unsigned options take digits only: CLI11 would wrap "-1" into 4294967295.
const CLI::Validator kUnsignedInteger(
    [](std::string& s) {
      return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos
                 ? std::string()
                 : "'" + s + "' is not a non-negative integer";
    },
    "");
const CLI::Validator kPositiveInteger(
    [](std::string& s) {
      return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos &&
                     s.find_first_not_of('0') != std::string::npos
                 ? std::string()
                 : "'" + s + "' is not a positive integer";
    },
    "");

void addFiberOptions(CLI::App* app, ft::FiberOptions& f, bool yarnRadius = true) {
  app->add_option("--fibers-per-ply", f.regularFibersPerPly, "regular fibers drawn per ply (the rest form the core)")
      ->capture_default_str()
      ->check(kUnsignedInteger);
  app->add_option("--subdivisions", f.maxSubdivisions, "cap on the line segments per fiber per yarn segment; the count follows the screen (1-64)")
      ->capture_default_str()
      ->check(kUnsignedInteger);
  app->add_option("--fiber-radius", f.fiberRadius,
                  "drawn fiber half-width at the preset's own scale (scaled with the preset to the model)")
      ->capture_default_str();
  if (yarnRadius)
    app->add_option("--yarn-radius", f.yarnRadius,
                    "yarn radius the preset is scaled to, model units (default: estimated from the spacing of "
                    "neighbouring yarns)");
  app->add_option("--seed", f.seed, "seed of the fiber table and fiber types")
      ->capture_default_str()
      ->check(kUnsignedInteger);
  app->add_option("--migration-phase", f.migrationPhase,
                  "phase of eq. 2: independent (random per fiber, as the presets were fitted; default) or "
                  "fiber-angle (θ_i, as eq. 2 writes it)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, uint32_t>{{"independent", FT_MIGRATION_PHASE_INDEPENDENT},
                                          {"fiber-angle", FT_MIGRATION_PHASE_FIBER_ANGLE}}));
}

ft::GlBackend parseBackend(const std::string& s) {
  if (s.empty()) return ft::glBackendFromEnv();
  auto b = ft::parseGlBackend(s);
  if (!b) throw ft::InputError(fmt::format("--backend: unknown backend '{}' (auto, surfaceless, device, osmesa)", s));
  return *b;
}

glm::vec3 parseVec3(const std::string& s, const char* option) {
  glm::vec3 v;
  char tail = 0;
  if (std::sscanf(s.c_str(), "%f,%f,%f%c", &v.x, &v.y, &v.z, &tail) != 3 || !std::isfinite(v.x) ||
      !std::isfinite(v.y) || !std::isfinite(v.z) || glm::length(v) == 0.0f)
    throw ft::InputError(fmt::format("{}: '{}' is not a non-zero vector x,y,z", option, s));
  return v;
}

// A point (may be the origin), finite: --eye and --target.
glm::vec3 parsePoint(const std::string& s, const char* option) {
  glm::vec3 v;
  char tail = 0;
  if (std::sscanf(s.c_str(), "%f,%f,%f%c", &v.x, &v.y, &v.z, &tail) != 3 || !std::isfinite(v.x) ||
      !std::isfinite(v.y) || !std::isfinite(v.z))
    throw ft::InputError(fmt::format("{}: '{}' is not a finite point x,y,z", option, s));
  return v;
}

// The explicit camera and the preset overrides, as typed; render, trace and
// validate share them (knit takes --set only).
struct CameraText {
  std::string eye, target, fov;
};
void addCameraOptions(CLI::App* app, CameraText& text) {
  app->add_option("--eye", text.eye, "explicit camera position x,y,z (replaces the --distance view's)");
  app->add_option("--target", text.target, "explicit point the camera looks at, x,y,z");
  app->add_option("--fov", text.fov, "explicit vertical field of view in degrees, in (0, 180) (default 40)");
}
ft::CameraOverride parseCameraText(const CameraText& text) {
  ft::CameraOverride c;
  if (!text.eye.empty()) c.eye = parsePoint(text.eye, "--eye");
  if (!text.target.empty()) c.target = parsePoint(text.target, "--target");
  if (!text.fov.empty()) {
    float f = 0.0f;
    char tail = 0;
    if (std::sscanf(text.fov.c_str(), "%f%c", &f, &tail) != 1 || !std::isfinite(f) || !(f > 0.0f && f < 180.0f))
      throw ft::InputError(fmt::format("--fov: '{}' is not a vertical field of view in (0, 180) degrees", text.fov));
    c.fovyDegrees = f;
  }
  return c;
}
void addSetOption(CLI::App* app, std::vector<std::string>& sets) {
  app->add_option("--set", sets,
                  "override a yarn preset parameter by its data/yarn-presets.tsv column, name=value (repeatable), "
                  "e.g. --set ply_num=4")
      ->allow_extra_args(false);
}

// For the report: the command line as one could paste it into a shell.
std::string shellQuote(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_=./,:+@%^") ==
                        std::string::npos)
    return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The options `render` and `trace` share, as typed (vectors parsed later).
// Defaults come from ft::ViewOptions / ft::Lighting, written once there.
std::string vec3Text(glm::vec3 v) {
  return v.x == v.y && v.y == v.z ? fmt::format("{:g}", v.x) : fmt::format("{:g},{:g},{:g}", v.x, v.y, v.z);
}
// The lighting and display options of every command that shades a frame
// (render, trace, knit), as typed; defaults from ft::Lighting.
struct LightingOptionText {
  ft::Lighting defaults;
  std::string light = vec3Text(defaults.lights[0].direction), irradiance = vec3Text(defaults.lights[0].irradiance),
              ambient = vec3Text(defaults.ambient), diffuse = vec3Text(defaults.diffuse), tone = "aces";
};
void addLightingOptions(CLI::App* app, ft::Lighting& lighting, ft::DisplayMapping& display, LightingOptionText& text) {
  app->add_option("--fabric", lighting.fabric, "fiber scattering preset: fleece, gabardine, silk, cotton, polyester")
      ->capture_default_str();
  app->add_option("--shading", lighting.model, "khungurn (000 eq. 6 with the ambient table) or simple (eq. 5)")
      ->capture_default_str();
  app->add_option("--light", text.light, "direction towards the (one) directional light, x,y,z")->capture_default_str();
  app->add_option("--light-irradiance", text.irradiance, "its irradiance: one value or r,g,b")->capture_default_str();
  app->add_option("--ambient", text.ambient, "uniform ambient radiance L_amb: one value or r,g,b")->capture_default_str();
  app->add_option("--diffuse", text.diffuse, "k_d in [0, 1]: the diffuse share of the scattered energy (the BCSDF gets 1 - k_d): one value or r,g,b")
      ->capture_default_str();
  app->add_option("--exposure", display.exposure, "PNG only: exposure in stops before tone mapping")
      ->capture_default_str();
  app->add_option("--tonemap", text.tone, "PNG only: aces or clamp")->capture_default_str();
}

struct ViewOptionText {
  ft::ViewOptions defaults;
  CameraText camera;
  LightingOptionText lighting;
  std::string model, view = vec3Text(defaults.viewDir);
};

void addViewOptions(CLI::App* app, ft::ViewOptions& v, ViewOptionText& text) {
  app->add_option("--model", text.model, "BCC yarn model (default: the built-in scene)");
  app->add_option("--yarn", v.yarn, "yarn preset")->capture_default_str();
  app->add_option("--out", v.out, "output: .exr writes the linear EXR and a tone-mapped PNG beside it; .png the PNG only")
      ->capture_default_str();
  app->add_option("--width", v.width)->capture_default_str()->check(CLI::Range(16, 8192));
  app->add_option("--height", v.height)->capture_default_str()->check(CLI::Range(16, 8192));
  addLightingOptions(app, v.lighting, v.display, text.lighting);
  app->add_option("--view", text.view, "direction from the model towards the camera, x,y,z")->capture_default_str();
  app->add_option("--distance", v.distance,
                  "frame (whole model), closeup (a yarn segment spans 1/16 of the frame height), near, mid or far "
                  "(LoD distances, exact at 960 px high); the framing does not depend on the resolution")
      ->capture_default_str();
  addCameraOptions(app, text.camera);
  addSetOption(app, v.presetOverrides);
  addFiberOptions(app, v.fiber);
}

glm::vec3 parseColor(const std::string& s, const char* option) {
  glm::vec3 c;
  char tail = 0;
  if (std::sscanf(s.c_str(), "%f,%f,%f%c", &c.x, &c.y, &c.z, &tail) == 3) return c;
  if (std::sscanf(s.c_str(), "%f%c", &c.x, &tail) == 1) return glm::vec3(c.x);
  throw ft::InputError(fmt::format("{}: '{}' is neither a number nor r,g,b", option, s));
}

void finishLightingOptions(ft::Lighting& lighting, ft::DisplayMapping& display, const LightingOptionText& text) {
  lighting.lights = {ft::DirectionalLight{parseVec3(text.light, "--light"), parseColor(text.irradiance, "--light-irradiance")}};
  lighting.ambient = parseColor(text.ambient, "--ambient");
  lighting.diffuse = parseColor(text.diffuse, "--diffuse");
  if (text.tone == "aces") display.tone = ft::ToneMap::Aces;
  else if (text.tone == "clamp") display.tone = ft::ToneMap::Clamp;
  else throw ft::InputError(fmt::format("--tonemap: '{}' is neither aces nor clamp", text.tone));
  if (!std::isfinite(display.exposure)) throw ft::InputError("--exposure: not a finite number");
}

void finishViewOptions(ft::ViewOptions& v, const ViewOptionText& text) {
  if (!text.model.empty()) v.model = text.model;
  v.viewDir = parseVec3(text.view, "--view");
  finishLightingOptions(v.lighting, v.display, text.lighting);
  v.camera = parseCameraText(text.camera);
}

// How the ground truth is traced: `trace`, and `knit --reference`.
void addTraceSettings(CLI::App* app, ft::TraceSettings& t) {
  app->add_option("--spp", t.samplesPerPixel, "samples per pixel of the trace")
      ->capture_default_str()
      ->check(CLI::Range(1, 65536));
  app->add_flag("!--no-shadows", t.shadows, "trace without shadow rays (the configuration the GPU render matches)");
  app->add_flag("--multiple-scattering", t.multipleScattering,
                "path-trace multiple scattering; the ambient then comes from escaping rays")
      ->capture_default_str();
  app->add_option("--max-depth", t.maxDepth, "path length cap with --multiple-scattering")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  app->add_option("--trace-seed", t.seed, "seed of the trace's pixel samples")
      ->capture_default_str()
      ->check(kUnsignedInteger);
}

// 000 §4 / 001 §4's approximations of the shaded frame, as typed: one place
// for every command that draws it (render, knit), so that a new approximation
// adds its flags here once.
struct AppearanceOptionText {
  std::string ao = "fit", dsCorrection;
  std::string env, envTable;  // --env FILE, --env-table N_θo,N_θj,N_Δφ,N_λ
  float flyawayLength = 1.0f;
  double lightAngularRadiusDeg = 0.0;  // --light-angular-radius (degrees), when given
  CLI::Option* lightAngularRadius = nullptr;
};
void addAppearanceOptions(CLI::App* app, ft::AppearanceOptions& a, AppearanceOptionText& text) {
  app->add_flag("!--no-self-shadow", a.selfShadow,
                "without the self-shadow texture of 000 §4.1 (light through the yarn's own fibers)");
  app->add_option("--self-shadow-size", a.selfShadowSize,
                  "self-shadow texels across the yarn (default 128)");
  app->add_option("--self-shadow-slices", a.selfShadowSlices,
                  "self-shadow slices over the ply twist (default 16)");
  app->add_flag("!--no-core-texture", a.coreTexture,
                "core strips without the core-fiber texture of 000 §3.2 (a smooth tube)");
  app->add_option("--self-shadow-kappa", a.selfShadowKappa,
                  "κ of T = exp(-κD) (default 2 r_f, notes §0.3; 0: no self-shadow)");
  app->add_option("--ao", text.ao,
                  "ambient occlusion of 000 §4.2: none, fit (the distance-based cubic, default) or texture");
  app->add_flag("!--no-shadow-map", a.shadowMap,
                "without the yarn shadow map of 000 §4.1 (yarns shadowing other yarns)");
  app->add_option("--shadow-map-size", a.shadowMapSize,
                  "shadow-map texels per side, per light (default 2048)");
  app->add_option("--shadow-map-filter", a.shadowMapFilter,
                  "the shadow map's lookup: pcf (2 x 2 percentage-closer filtering: soft texel edges; default) or "
                  "nearest (the nearest texel: hard texel-sized steps; 000 is silent on filtering)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, uint32_t>{{"pcf", FT_SHADOW_FILTER_PCF},
                                                                          {"nearest", FT_SHADOW_FILTER_NEAREST}}));
  app->add_flag("--dual-scattering", a.dualScattering,
                "dual scattering (Zinke 2008, 001 §4.1 eq. 8) per light: f + d_b f_back^dir (docs/shaded-frame.md)");
  app->add_option("--ds-correction", text.dsCorrection,
                  "with --dual-scattering (implied): the ξ and Ψ_G^Fiber bake of `fibertwin bake ds-correction` "
                  "(001 eq. 11), for the frame's yarn preset and fabric; its Ψ_G^Fiber replaces the self-shadow T");
  app->add_option("--env", text.env,
                  "environment lighting (001 §4.5): an OpenEXR lat-long map (y up, row 0 at the top, φ = atan2(z, x); "
                  "docs/srbf.md), fitted with 16 SRBFs + a constant; it replaces --ambient, lights still add");
  app->add_option("--env-table", text.envTable,
                  "with --env: the I_M table's size N_θo,N_θj,N_Δφ,N_λ (default 16,16,8,8; each in [2, 64])");
  app->add_flag("--flyaways", a.flyaways,
                "flyaway fibers of 001 §4.4 (eq. 12-13): three seamless baked textures drawn in a third pass "
                "(docs/flyaways.md)");
  app->add_option("--flyaway-alpha", a.flyawaySettings.alpha, "eq. 13's curvature exponent α (default 1: eq. 12)");
  app->add_option("--flyaway-noise", a.flyawaySettings.noise,
                  "random walk on the flyaways' steps, σ_n as a fraction of a step (default 0.1)");
  app->add_option("--flyaway-length", text.flyawayLength,
                  "scales z_e and R_e (001 Fig. 15's extended flyaways: 3; default 1)");
  app->add_option("--flyaway-size", a.flyawaySettings.width, "flyaway texels along one period (default 512; height: a quarter)");
  app->add_flag("--soft-shadows", a.softShadows,
                "soft yarn shadows: PCSS (Fernando 2005; 001 §4.5) on the yarn shadow map, each light a cone of "
                "--light-angular-radius (docs/soft-shadows.md)");
  text.lightAngularRadius = app->add_option("--light-angular-radius", text.lightAngularRadiusDeg,
                  "with --soft-shadows (implied): the lights' angular radius in degrees, [0, 60] (default 5.73)");
}
void finishAppearanceOptions(ft::AppearanceOptions& a, const AppearanceOptionText& text) {
  a.ao = ft::parseAoMode(text.ao);
  a.flyawaySettings.lengthScale = text.flyawayLength;
  a.flyawaySettings.height = std::max<uint32_t>(2u, a.flyawaySettings.width / 4u);
  const bool flyawayTuned = a.flyawaySettings.alpha != ft::FlyawaySettings{}.alpha ||
                            a.flyawaySettings.noise != ft::FlyawaySettings{}.noise || text.flyawayLength != 1.0f ||
                            a.flyawaySettings.width != ft::FlyawaySettings{}.width;
  if (flyawayTuned && !a.flyaways)
    throw ft::InputError("--flyaway-alpha, --flyaway-noise, --flyaway-length and --flyaway-size need --flyaways");
  if (text.lightAngularRadius && text.lightAngularRadius->count() > 0) {  // checked with the bake (frameSoftShadows)
    a.lightAngularRadius = float(text.lightAngularRadiusDeg * 3.14159265358979323846 / 180.0);
    a.softShadows = true;
  }
  if (!text.dsCorrection.empty()) {
    a.dsCorrectionFile = text.dsCorrection;
    a.dualScattering = true;
  }
  if (!text.envTable.empty()) {
    int d[4];
    char tail = 0;
    if (std::sscanf(text.envTable.c_str(), "%d,%d,%d,%d%c", &d[0], &d[1], &d[2], &d[3], &tail) != 4)
      throw ft::InputError(fmt::format("--env-table: '{}' is not four integers N_θo,N_θj,N_Δφ,N_λ", text.envTable));
    a.environmentTableDims = glm::ivec4(d[0], d[1], d[2], d[3]);
  }
  if (!text.env.empty()) {
    a.environmentMap = text.env;
    ft::frameEnvironmentMap(a);  // a bad map or table size is refused before anything is baked
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fibertwin — fiber-level cloth: CPU reference and GPU paths, cross-checked"};
  app.require_subcommand(1);
  app.set_version_flag("--version", ft::versionLine(), "print the version and the git commit it was built from");

  ft::HarnessOptions vo;
  std::string modelPath, yarn, backend;
  auto* validate = app.add_subcommand("validate", "run the CPU-vs-GPU cross-checks and write a report");
  validate->add_option("--filter", vo.filter, "regular expression on case names");
  validate->add_option("--model", modelPath, "BCC yarn model (default: the built-in scene)");
  validate->add_option("--yarn", vo.yarns, "yarn preset(s) (default: all nine)");
  validate->add_option("--report", vo.reportDir, "report folder")->capture_default_str();
  validate->add_option("--inject", vo.inject, "build the GPU side with a planted fault (see `fibertwin faults`)");
  validate->add_option("--backend", backend, "GL backend: auto, surfaceless, device, osmesa (env FT_GL_BACKEND)");
  validate->add_option("--tess-segments", vo.tessSegmentBudget,
                       "segments in the fixed subset tessellation cases use on large models")
      ->capture_default_str()
      ->check(kPositiveInteger);
  validate->add_flag("!--no-images", vo.images, "skip the report thumbnails");
  addFiberOptions(validate, vo.fiber);
  CameraText validateCamera;
  addCameraOptions(validate, validateCamera);  // the closeup/* cases' camera
  addSetOption(validate, vo.presetOverrides);

  ft::RenderCommandOptions ro;
  ViewOptionText renderText;
  std::string renderShading;
  auto* render = app.add_subcommand("render", "render a yarn model with procedural fibers on the GPU: shaded EXR + PNG");
  addViewOptions(render, ro.view, renderText);
  render->add_option("--path", ro.path, "compute or tessellation")->capture_default_str();
  render->add_flag("--preview", ro.preview, "the harness thumbnails' preview style instead of the BCSDF (PNG only)");
  render->add_flag("!--no-occlusion-cull", ro.occlusionCull,
                   "shade every fragment: without the occluder pass that skips hidden lines (the frame is the same; "
                   "by default the pass runs unless the whole model is in view)");
  render->add_option("--occlusion-cull", ro.occlusionCullMode,
                     "auto: the occluder pass only when the model is not wholly in view (what it costs and saves "
                     "depends on the view); on; off (the frame is the same)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  render->add_option("--two-pass-cull", ro.twoPassCullMode,
                     "on: a frame after another of the same model (the warm frame of --profile) draws first the "
                     "fiber strips the last frame saw, then the others against their depth, instead of the occluder "
                     "pass; off (the depth is the same; docs/shaded-frame.md)")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  render->add_flag("!--forward", ro.deferred,
                   "shade every fragment in the fragment stage instead of deferred shading of the visible hits "
                   "(the frame is the same)");
  render->add_flag("--profile", ro.profile,
                   "time the bakes and each phase of the frame (glFinish after each), cold and then warm (drawn twice)");
  AppearanceOptionText renderAppearance;
  addAppearanceOptions(render, ro.appearance, renderAppearance);
  render->add_option("--backend", backend, "GL backend");
  render->add_option("--inject", ro.inject,
                     "draw with a planted fault (`fibertwin faults`): a NaN frame must stop the render");

  ft::TraceCommandOptions to;
  ViewOptionText traceText;
  auto* trace = app.add_subcommand(
      "trace", "ray-trace the same view with Embree (every fiber a round curve): the ground truth, EXR + PNG");
  addViewOptions(trace, to.view, traceText);
  addTraceSettings(trace, to);
  trace->add_flag("--all-fibers", to.view.fiber.allFibers,
                  "the all-fiber reference: every fiber of the preset explicit (fiber_num per ply), no core, no LoD "
                  "(docs/ground-truth.md)");
  double traceAngularRadiusDeg = 0.0;
  trace->add_option("--light-angular-radius", traceAngularRadiusDeg,
                    "each light a cone of this angular radius in degrees, [0, 60] (default 0: one direction): shadow "
                    "rays sample the cone uniformly, the reference of render --soft-shadows (docs/soft-shadows.md)")
      ->check(CLI::Range(0.0, 60.0));
  std::string traceEnv;
  trace->add_option("--env", traceEnv,
                    "light by an OpenEXR lat-long map (y up, row 0 at the top; docs/srbf.md) in place of --ambient, "
                    "sampled directly with MIS against the BCSDF (not its SRBF fit): the frame's --env ground truth");

  ft::KnitCommandOptions ko;
  std::vector<std::string> knitMeshes;
  std::string knitBcc = ko.bcc.string(), knitImage = ko.image.string(), knitReference;
  bool knitNoImage = false;
  auto* knit = app.add_subcommand(
      "knit", "optimize the yarn curves of a deformed stitch mesh (knot-based Gauss-Newton); write BCC and the "
              "shaded frame (EXR + PNG)");
  knit->add_option("--mesh", knitMeshes,
                   "stitch mesh OBJ (docs/stitch-meshes.md); give several for animation frames, the first being the "
                   "rest state (default: a built-in patch)");
  knit->add_option("--pattern", ko.pattern, "built-in patch: stockinette, ribbing or lace (eyelets, increases, decreases)")->capture_default_str();
  knit->add_option("--rows", ko.rows, "built-in patch rows")->capture_default_str();
  knit->add_option("--cols", ko.cols, "built-in patch columns")->capture_default_str();
  knit->add_option("--deform", ko.deformation,
                   "none, stretch-course=F or stretch-wale=F (F in 1-1.6), shear=DEGREES (0-30)")
      ->capture_default_str();
  knit->add_option("--frames", ko.frames, "animate the deformation from rest over N frames (writes _000, _001, ...)")
      ->capture_default_str();
  knit->add_option("--solver", ko.solver, "gpu (compute shader) or cpu (the double-precision reference)")
      ->capture_default_str();
  knit->add_option("--yarn-radius", ko.knit.yarnRadius, "knot yarn radius r of eq. 1-2, mesh units")
      ->capture_default_str();
  knit->add_option("--beta", ko.knit.beta, "knot spacing blend of section 6.1 (0: rest spacing, 1: the mesh's)")
      ->capture_default_str();
  knit->add_option("--iterations", ko.knit.iterations, "Gauss-Newton iterations (0: plain interpolation)")
      ->capture_default_str();
  knit->add_option("--w-angle", ko.knit.wAngle, "eq. 3 weight of the angle energy")->capture_default_str();
  knit->add_option("--w-length", ko.knit.wLength, "eq. 3 weight of the length energy")->capture_default_str();
  knit->add_option("--out", knitBcc, "output BCC yarn curves")->capture_default_str();
  knit->add_option("--image", knitImage,
                   "the shaded frame of `render`: .exr writes the linear EXR and a tone-mapped PNG beside it, .png "
                   "the PNG only (sequences: _000, _001, ...)")
      ->capture_default_str();
  knit->add_flag("--no-image", knitNoImage, "write the BCC only");
  knit->add_flag("--preview", ko.preview, "the harness thumbnails' preview style instead of the shaded frame (PNG)");
  knit->add_option("--path", ko.path, "compute or tessellation")->capture_default_str();
  knit->add_flag("!--no-occlusion-cull", ko.occlusionCull,
                 "shade every fragment: without the occluder pass that skips hidden lines (the frame is the same)");
  knit->add_option("--reference", knitReference,
                   "also path-trace each frame's all-fiber reference (Embree: every fiber of the preset, no core, no "
                   "LoD; same fibers, camera and lights) to this .exr/.png; --spp, --multiple-scattering, ... set it");
  addTraceSettings(knit, ko.trace);
  LightingOptionText knitLighting;
  addLightingOptions(knit, ko.lighting, ko.display, knitLighting);
  AppearanceOptionText knitAppearance;
  addAppearanceOptions(knit, ko.appearance, knitAppearance);
  knit->add_option("--width", ko.width)->capture_default_str()->check(CLI::Range(16, 8192));
  knit->add_option("--height", ko.height)->capture_default_str()->check(CLI::Range(16, 8192));
  knit->add_option("--yarn", ko.yarn, "yarn preset for the fibers")->capture_default_str();
  knit->add_option("--backend", backend, "GL backend");
  addFiberOptions(knit, ko.fiber, false);
  addSetOption(knit, ko.presetOverrides);  // the fibers take the knot yarn radius

  auto* info = app.add_subcommand("info", "print the GL renderer and its limits");
  info->add_option("--backend", backend, "GL backend");
  app.add_subcommand("faults", "list the faults --inject can plant");
  std::string envSkyOut = "data/env/sky.exr";
  int envSkyWidth = 256, envSkyHeight = 128;
  auto* envSky = app.add_subcommand(
      "env-sky", "write the procedural HDR environment map (sky, sun, ground; float EXR, equirect, y up: docs/srbf.md) "
                 "and print its SRBF fit error");
  envSky->add_option("--out", envSkyOut, "EXR to write")->capture_default_str();
  envSky->add_option("--width", envSkyWidth)->capture_default_str()->check(CLI::Range(8, 8192));
  envSky->add_option("--height", envSkyHeight)->capture_default_str()->check(CLI::Range(4, 4096));

  ft::CompareCommandOptions compareOptions;
  CLI::App* compare = ft::addCompareCommand(app, compareOptions);
  ft::BakeCommandOptions bakeOptions;
  CLI::App* bake = ft::addBakeCommand(app, bakeOptions);
  ft::PrtFrameCommandOptions prtFrameOptions;
  CLI::App* prtFrame = ft::addPrtFrameCommand(app, prtFrameOptions);
  ft::PrtSweepCommandOptions prtSweepOptions;
  CLI::App* prtSweep = ft::addPrtSweepCommand(app, prtSweepOptions);
  ft::PrtMsProbeCommandOptions prtMsProbeOptions;
  CLI::App* prtMsProbe = ft::addPrtMsProbeCommand(app, prtMsProbeOptions);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; any other parse error is bad input: exit 2,
    // before any file is read or GL context created.
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (compare->parsed()) return ft::runCompareCommand(compareOptions, std::cout);
    if (bake->parsed()) return ft::runBakeCommand(bakeOptions, std::cout);
    if (prtFrame->parsed()) return ft::runPrtFrameCommand(prtFrameOptions, std::cout);
    if (prtSweep->parsed()) return ft::runPrtSweepCommand(prtSweepOptions, std::cout);
    if (prtMsProbe->parsed()) return ft::runPrtMsProbeCommand(prtMsProbeOptions, std::cout);
    if (validate->parsed()) {
      if (!modelPath.empty()) vo.model = modelPath;
      for (int i = 0; i < argc; ++i) vo.commandLine += (i ? " " : "") + shellQuote(argv[i]);
      vo.backend = parseBackend(backend);
      vo.camera = parseCameraText(validateCamera);
      return ft::runValidation(vo, std::cout).allPassed ? 0 : 1;
    }
    if (knit->parsed()) {
      for (const std::string& m : knitMeshes) ko.meshes.emplace_back(m);
      ko.bcc = knitBcc;
      ko.image = knitNoImage ? std::filesystem::path() : std::filesystem::path(knitImage);
      if (ko.preview && ko.image.extension() == ".exr") ko.image.replace_extension(".png");
      ko.reference = knitReference;
      finishLightingOptions(ko.lighting, ko.display, knitLighting);
      finishAppearanceOptions(ko.appearance, knitAppearance);
      ko.backend = parseBackend(backend);
      return ft::runKnitCommand(ko, std::cout);
    }
    if (info->parsed()) {
      auto ctx = ft::GlContext::create(parseBackend(backend));
      const ft::GlInfo& g = ctx->info();
      std::cout << fmt::format(
          "backend {}\nvendor {}\nrenderer {}\nversion {}\nglsl {}\nmax tess gen level {}\nmax compute work groups "
          "{} {} {}\nsoftware {}\ntimer queries meaningful {}\n",
          g.backend, g.vendor, g.renderer, g.version, g.glslVersion, g.maxTessGenLevel, g.maxComputeWorkGroupCount[0],
          g.maxComputeWorkGroupCount[1], g.maxComputeWorkGroupCount[2], g.isSoftware, g.timerQueriesMeaningful);
      return 0;
    }
    if (app.got_subcommand("faults")) {
      for (const ft::Fault& f : ft::kFaults) std::cout << fmt::format("{:<16} {}\n", f.name, f.description);
      return 0;
    }
    if (envSky->parsed()) {
      const ft::ImageRgbaF sky = ft::makeProceduralSky(envSkyWidth, envSkyHeight);
      ft::writeExr(envSkyOut, sky, ft::ExrPixelType::Float);
      const ft::SrbfFit fit = ft::fitSrbfCpu(sky);
      std::cout << fmt::format("wrote {} ({} x {}); 16-lobe + DC SRBF fit: relative L2 error {:.4f}, {} lobes active\n",
                               envSkyOut, envSkyWidth, envSkyHeight, ft::srbfRelativeL2(sky, fit.environment),
                               fit.activeLobes);
      return 0;
    }
    if (render->parsed()) {
      finishViewOptions(ro.view, renderText);
      if (ro.preview && ro.view.out.extension() == ".exr") ro.view.out.replace_extension(".png");
      ro.backend = parseBackend(backend);
      finishAppearanceOptions(ro.appearance, renderAppearance);
      return ft::runRenderCommand(ro, std::cout);
    }
    if (trace->parsed()) {
      finishViewOptions(to.view, traceText);
      if (!traceEnv.empty()) {
        ft::readEnvironmentMap(traceEnv);  // a bad map is refused before the scene is built
        to.environmentMap = traceEnv;
      }
      to.lightAngularRadius = traceAngularRadiusDeg * 3.14159265358979323846 / 180.0;
      return ft::runTraceCommand(to, std::cout);
    }
  } catch (const ft::InputError& e) {
    std::cerr << "fibertwin: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {  // image files (image/ has no InputError)
    std::cerr << "fibertwin: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "fibertwin: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
