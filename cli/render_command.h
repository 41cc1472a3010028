// render_command.h — `fibertwin render` (the GPU paths, shaded with the
// shared BCSDF of 000 §4.3, or the preview style) and `fibertwin trace` (the
// Embree ground truth of the same view): a yarn model in, an OpenEXR (linear)
// and a PNG (tone-mapped) out.
#pragma once
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>

#include "gpu/gl_context.h"
#include "image/image.h"
#include "image/image_io.h"
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
  bool occlusionCull = true;                   // exact occlusion culling (common/occlusion_cull.h)                        // time the bakes and the frame's phases, cold and warm
  AppearanceOptions appearance;                // 000 §4's approximations (--no-self-shadow, ...)
  GlBackend backend = GlBackend::Auto;
  std::string inject;                          // planted fault (faults.def)
};

struct TraceCommandOptions {
  ViewOptions view;
  int samplesPerPixel = 16;
  bool shadows = true;
  bool multipleScattering = false;
  int maxDepth = 16;
  uint32_t seed = 1;
  // --env FILE: the map lights the fibers in place of --ambient, sampled
  // directly (reference/environment_sampling.h), not through its SRBF fit.
  std::optional<std::filesystem::path> environmentMap;
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

// Both return the exit status and throw InputError for bad input.
int runRenderCommand(const RenderCommandOptions& options, std::ostream& log);
int runTraceCommand(const TraceCommandOptions& options, std::ostream& log);

}  // namespace ft
