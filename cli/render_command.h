// render_command.h — `fibertwin render` (the GPU paths, shaded with the
// shared BCSDF of 000 §4.3, or the preview style) and `fibertwin trace` (the
// Embree ground truth of the same view): a yarn model in, an OpenEXR (linear)
// and a PNG (tone-mapped) out.
#pragma once
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>

#include "gpu/fiber_renderer.h"
#include "gpu/gl_context.h"
#include "image/image.h"
#include "image/image_io.h"
#include "reference/fiber_trace.h"
#include "scene/camera.h"
#include "scene/lighting.h"
#include "scene/shading_inputs.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_model.h"
#include "scene/yarn_radius.h"

namespace ft {

// The view both commands share: same model, fitted yarn, camera and lighting
// give the same picture on both sides.
struct ViewOptions {
  std::optional<std::filesystem::path> model;  // default: the built-in scene
  std::string yarn = "cotton1";
  FiberOptions fiber;
  int width = 1280, height = 960;
  glm::vec3 viewDir{0.3f, 0.5f, 1.0f};         // from the model towards the camera
  std::string distance = "frame";              // frame, closeup, near, mid, far (scene/camera.h: namedViewCamera)
  CameraOverride camera;                       // --eye, --target, --fov over the named view
  std::vector<std::string> presetOverrides;    // --set name=value over the yarn preset
  Lighting lighting;
  std::filesystem::path out = "fibertwin.exr"; // .exr: EXR + PNG beside it; .png: PNG only
  DisplayMapping display;
};

struct RenderCommandOptions {
  ViewOptions view;
  std::string path = "compute";                // compute or tessellation
  bool preview = false;                        // the harness thumbnails' preview style (RGBA8 PNG)
  bool profile = false;
  bool deferred = true;                        // deferred shading (FiberRenderer::setDeferred); --forward: off
  bool occlusionCull = true;                   // false: --no-occlusion-cull (same as --occlusion-cull off)
  std::string twoPassCullMode = "on";         // two-pass culling from the last frame's lines (FiberRenderer::setTwoPassCull)
  std::string occlusionCullMode = "auto";     // exact occlusion culling (common/occlusion_cull.h): auto (per view), on, off                        // time the bakes and the frame's phases, cold and warm
  AppearanceOptions appearance;                // 000 §4's approximations (--no-self-shadow, ...)
  GlBackend backend = GlBackend::Auto;
  std::string inject;                          // planted fault (faults.def)
};

// How the ground truth is traced (`trace`, and `knit --reference`).
struct TraceSettings {
  int samplesPerPixel = 16;
  bool shadows = true;
  bool multipleScattering = false;
  int maxDepth = 16;
  uint32_t seed = 1;
  // --env FILE: the map lights the fibers in place of --ambient, sampled
  // directly (reference/environment_sampling.h), not through its SRBF fit.
  std::optional<std::filesystem::path> environmentMap;
  // --light-angular-radius (trace): each light a cone of this half-angle
  // (radians; 0: one direction), the soft-shadow reference (docs/soft-shadows.md).
  double lightAngularRadius = 0.0;
};

struct TraceCommandOptions : TraceSettings {
  ViewOptions view;
};

// A loaded view: model, fitted fibers, camera, shading.
struct PreparedView {
  YarnModel model;
  YarnBuffers buffers;
  YarnPreset preset;                           // with the --set overrides
  FittedFibers fibers;
  Camera camera;
  ShadingParams shading{};
  bool lod = true;  // off for the all-fiber reference (FiberOptions::allFibers)
};
PreparedView prepareView(const ViewOptions& options);
ViewParams viewParamsOf(const PreparedView& view);

// Writes `image` as options.out says; returns the files written.
std::vector<std::filesystem::path> writeImage(const ViewOptions& options, const ImageRgbaF& image);

// ---- The shaded frame, shared by `render` and `knit` (docs/shaded-frame.md) ----
// The frame's inputs, baked on the GPU (ShadingBakeGpu::bake): they depend on
// the lighting, the fabric, the fitted preset and its fiber table, not on the
// yarn curves, so a sequence bakes them once. The yarn shadow map, which does
// depend on the curves, is FiberRenderer::draw's: redrawn after every
// FiberGpu::setModel.
ShadingInputs bakeFrameInputs(const GlInfo& gl, const std::vector<std::string>& defines, const ShadingParams& shading,
                              const FittedFibers& fibers, const AppearanceOptions& appearance);
// Draws the shaded frame of the model and view `gpu` holds, with the inputs
// set on `renderer`, and reads it back; std::runtime_error naming `who` when a
// pixel value is not finite (no image is written then).
ImageRgbaF drawShadedFrame(FiberRenderer& renderer, FiberGpu& gpu, FiberPath path, int width, int height,
                           const std::string& who, FrameTimings* timings = nullptr);
// `out` ending in .exr: the linear float EXR and a tone-mapped PNG beside it;
// .png: the PNG only. Returns the files written.
std::vector<std::filesystem::path> writeFrameImage(const std::filesystem::path& out, const DisplayMapping& display,
                                                   const ImageRgbaF& image);
// InputError naming `option` unless `out` ends in .exr or .png.
void checkFrameImagePath(const std::filesystem::path& out, const char* option);
// The ground truth of a frame (`trace`'s body, shared by `knit --reference`):
// the CPU reference's fibers of `buffers` at `camera` (LoD as `lod` says) as
// an Embree scene, traced; progress on stderr, the scene and the rays in
// `log`. std::runtime_error for non-finite samples.
TraceResult traceFrame(const std::string& name, const YarnBuffers& buffers, const FiberSetup& fibers,
                       const Camera& camera, bool lod, const ShadingParams& shading, const TraceSettings& settings,
                       std::ostream& log);

// Both return the exit status and throw InputError for bad input.
int runRenderCommand(const RenderCommandOptions& options, std::ostream& log);
int runTraceCommand(const TraceCommandOptions& options, std::ostream& log);

}  // namespace ft
