#include "cli/render_command.h"

#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <ostream>

#include <tbb/task_arena.h>

#include <iostream>
#include <memory>
#include <mutex>

#include "gpu/fiber_gpu.h"
#include "gpu/fiber_renderer.h"
#include "gpu/shading_inputs_gpu.h"
#include "reference/shading_inputs.h"
#include "reference/fiber_reference.h"
#include "reference/environment_sampling.h"
#include "reference/fiber_trace.h"
#include "scene/environment_map.h"
#include "scene/bcc_reader.h"
#include "scene/default_scene.h"
#include "scene/input_error.h"
#include "validation/draw_check.h"
#include "validation/faults.h"
#include "validation/report.h"

namespace ft {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

size_t nonFiniteValues(const ImageRgbaF& image) {
  size_t n = 0;
  for (float v : image.pixels) n += std::isfinite(v) ? 0 : 1;
  return n;
}

}  // namespace

PreparedView prepareView(const ViewOptions& o) {
  checkFrameImagePath(o.out, "--out");
  PreparedView v;
  v.model = o.model ? readBcc(*o.model) : makeDefaultScene();
  v.buffers = buildYarnBuffers(v.model);
  v.preset = overrideYarnPreset(findYarnPreset(o.yarn), o.presetOverrides);
  v.shading = makeShadingParams(o.lighting);  // bad lighting options fail before any work
  v.fibers = fitFibers(v.preset, v.model, o.fiber);
  v.lod = !o.fiber.allFibers;  // the all-fiber reference drops no fiber into the core
  v.camera = applyCameraOverride(namedViewCamera(o.distance, v.model, v.fibers.params, o.viewDir, o.width, o.height),
                                 o.camera, v.model);
  return v;
}

ViewParams viewParamsOf(const PreparedView& v) { return makeViewParams(v.camera, 1.0f, v.lod, true); }

std::vector<std::filesystem::path> writeImage(const ViewOptions& o, const ImageRgbaF& image) {
  return writeFrameImage(o.out, o.display, image);
}

void checkFrameImagePath(const std::filesystem::path& out, const char* option) {
  const std::string ext = out.extension().string();
  if (ext != ".exr" && ext != ".png")
    throw InputError(fmt::format("{}: '{}' must end in .exr (EXR and PNG) or .png", option, out.string()));
}

std::vector<std::filesystem::path> writeFrameImage(const std::filesystem::path& out, const DisplayMapping& display,
                                                   const ImageRgbaF& image) {
  std::vector<std::filesystem::path> written;
  if (out.extension() == ".exr") {
    writeExr(out, image, ExrPixelType::Float);  // float32: half overflows at 65,504
    written.push_back(out);
  }
  std::filesystem::path png = out;
  png.replace_extension(".png");
  writePngTonemapped(png, image, display);
  written.push_back(png);
  return written;
}

ShadingInputs bakeFrameInputs(const GlInfo& gl, const std::vector<std::string>& defines, const ShadingParams& shading,
                              const FittedFibers& fibers, const AppearanceOptions& appearance) {
  return ShadingBakeGpu(gl, defines).bake({shading, &fibers.fit.preset, appearance, &fibers.params, &fibers.table});
}

ImageRgbaF drawShadedFrame(FiberRenderer& renderer, FiberGpu& gpu, FiberPath path, int width, int height,
                           const std::string& who, FrameTimings* timings) {
  renderer.draw(gpu, path, width, height, timings);
  ImageRgbaF img = renderer.read();
  if (const size_t bad = nonFiniteValues(img))
    throw std::runtime_error(fmt::format("{}: {} non-finite pixel values; no image written", who, bad));
  return img;
}

TraceResult traceFrame(const std::string& name, const YarnBuffers& buffers, const FiberSetup& fibers,
                       const Camera& camera, bool lod, const ShadingParams& shading, const TraceSettings& settings,
                       std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(buffers);
  checkBeforeDrawing(name, buffers, frames);
  const FiberInput input{&buffers, &fibers.table, fibers.params, makeViewParams(camera, 1.0f, lod, true)};
  FiberTraceScene scene(generateFibersCpu(input, frames), fibers.params);
  const double buildSeconds = secondsSince(t0);
  log << fmt::format("{} fiber segments of {} fibers as Embree round curves, {:.1f} MiB, built in {:.1f} s\n",
                     scene.segmentCount(), scene.fiberCount(), scene.bytes() / 1048576.0, buildSeconds);
  const std::vector<glm::vec3> table = bakeShadingInputsCpu({shading, nullptr, AppearanceOptions::none()}).ambientTable;
  TraceOptions t;
  t.samplesPerPixel = settings.samplesPerPixel;
  t.shadows = settings.shadows;
  t.multipleScattering = settings.multipleScattering;
  t.maxDepth = settings.maxDepth;
  t.seed = settings.seed;
  t.lightAngularRadius = settings.lightAngularRadius;
  std::unique_ptr<EnvironmentSampler> environment;
  if (settings.environmentMap) {
    environment = std::make_unique<EnvironmentSampler>(readEnvironmentMap(*settings.environmentMap));
    t.environment = environment.get();
  }
  // Progress on stderr, every 5 %, for renders that take a while.
  std::mutex progressMutex;
  int lastStep = -1;
  t.progress = [&](double fraction) {
    const std::lock_guard<std::mutex> lock(progressMutex);
    const int step = static_cast<int>(fraction * 20.0);
    if (step == lastStep) return;
    lastStep = step;
    std::cerr << fmt::format("\rtrace: {:3d}% ({:.0f} s)", step * 5, secondsSince(t0) - buildSeconds)
              << (step == 20 ? "\n" : "") << std::flush;
  };
  const auto t1 = std::chrono::steady_clock::now();
  TraceResult r = traceFibers(scene, camera, shading, table, t);
  const double seconds = secondsSince(t1);
  if (r.stats.nonFinite > 0)
    throw std::runtime_error(fmt::format("the ground truth produced {} non-finite samples; no image written",
                                         r.stats.nonFinite));
  log << fmt::format("{} spp, {}{}, {:.3g} rays in {:.1f} s ({:.3g} rays/s, {} threads)\n", settings.samplesPerPixel,
                     settings.shadows ? "shadows" : "no shadows",
                     settings.multipleScattering ? ", multiple scattering" : "", double(r.stats.rays()), seconds,
                     r.stats.rays() / std::max(seconds, 1e-9), tbb::this_task_arena::max_concurrency());
  return r;
}

int runRenderCommand(const RenderCommandOptions& o, std::ostream& log) {
  if (o.path != "compute" && o.path != "tessellation")
    throw InputError(fmt::format("--path: '{}' is neither compute nor tessellation", o.path));
  const PreparedView v = prepareView(o.view);
  log << fmt::format("yarn {} scaled {:.3f}x to yarn radius {:.4g} ({}); fabric {}, {} shading\n", v.preset.name,
                     v.fibers.fit.scale, v.fibers.fit.radius, v.fibers.fit.source, o.view.lighting.fabric,
                     o.preview ? "preview" : o.view.lighting.model);
  auto ctx = GlContext::create(o.backend);
  const GlInfo& g = ctx->info();
  std::vector<std::string> defines;
  if (!o.inject.empty()) {
    const Fault* f = findFault(o.inject);
    if (!f) throw InputError(fmt::format("--inject: unknown fault '{}' (see `fibertwin faults`)", o.inject));
    defines.push_back(f->define);
    if (f->shared) setSharedFault(f->define, true);
  }
  FiberGpu gpu(g, defines);
  FiberRenderer renderer(g, defines);
  const FiberPath path = o.path == "compute" ? FiberPath::Compute : FiberPath::Tessellation;
  gpu.setModel(v.buffers, v.fibers.table);
  checkBeforeDrawing(v.model.name, v.buffers, gpu.readFrames());  // no partial image from NaN frames
  gpu.setParams(v.fibers.params, viewParamsOf(v));
  const int w = o.view.width, h = o.view.height;
  const auto t0 = std::chrono::steady_clock::now();
  if (o.preview) {
    RenderStyle style;
    style.lightDir = glm::vec3(v.shading.lightDirection[0]);
    const RgbaImage img = renderer.preview(gpu, path, w, h, style);
    std::filesystem::path png = o.view.out;
    png.replace_extension(".png");
    writePng(png, img);
    log << fmt::format("{}: {} yarn curves, {} segments, {} path, preview, {:.0f} ms on {}\n", png.string(),
                       v.model.curves.size(), v.buffers.segments.size(), o.path, 1e3 * secondsSince(t0), g.renderer);
    return 0;
  }
  renderer.setShading(bakeFrameInputs(g, defines, v.shading, v.fibers, o.appearance));
  const double bakeSeconds = secondsSince(t0);
  using Cull = FiberRenderer::OcclusionCull;
  renderer.setOcclusionCull(!o.occlusionCull || o.occlusionCullMode == "off" ? Cull::Off
                            : o.occlusionCullMode == "on"                     ? Cull::On
                                                                              : Cull::Auto);
  renderer.setDeferred(o.deferred);
  renderer.setTwoPassCull(o.twoPassCullMode == "on");
  FrameTimings cold, warm;
  if (o.profile) renderer.draw(gpu, path, w, h, &cold);  // then the same frame again, everything built
  const ImageRgbaF img = drawShadedFrame(renderer, gpu, path, w, h, fmt::format("the {} path", o.path),
                                         o.profile ? &warm : nullptr);
  const double seconds = secondsSince(t0);
  const auto files = writeImage(o.view, img);
  log << fmt::format("{}: {} yarn curves, {} segments, {} path, {:.0f} ms on {}\n", files.front().string(),
                     v.model.curves.size(), v.buffers.segments.size(), o.path, 1e3 * seconds, g.renderer);
  if (o.profile) {
    log << fmt::format("  bakes (shading inputs): {:.0f} ms\n", 1e3 * bakeSeconds);
    log << fmt::format("  occlusion culling: {} ({}); two-pass culling of the warm frame: {}\n",
                       renderer.cullsView(gpu) ? "occluder pass" : "off", o.occlusionCull ? o.occlusionCullMode : "off",
                       warm.twoPass ? fmt::format("on, its first draw {} of {} primitives, {:.0f} ms (CPU {:.0f} ms) "
                                                  "of the visibility pass",
                                                  warm.firstDrawPrimitives, warm.shadePrimitives, warm.firstDrawMs,
                                                  warm.firstDrawCpuMs)
                                    : "off");
    for (const auto& [name, t] : {std::pair<const char*, const FrameTimings&>{"cold frame", cold}, {"warm frame", warm}})
      log << fmt::format(
          "  {}: {:.0f} ms = shadow map {:.0f} + generation {:.0f} + depth pass {:.0f} + {} {:.0f}{}; CPU time "
          "(all threads) {:.0f} ms, of which depth pass {:.0f}, {} {:.0f}\n",
          name,
          t.totalMs(), t.shadowMapMs, t.generateMs, t.depthMs, o.deferred ? "visibility pass" : "shaded pass", t.shadeMs,
          o.deferred ? fmt::format(" + deferred shading {:.0f} ({} hits)", t.deferredMs, renderer.deferredEntries()) : "",
          t.totalCpuMs, t.depthCpuMs, o.deferred ? "visibility pass" : "shaded pass", t.shadeCpuMs);
    if (warm.shadeFragmentInvocations > 0)
      log << fmt::format("  {}: {} primitives out of the geometry stage, {} fragment-shader invocations\n",
                         o.deferred ? "visibility pass" : "shaded pass", warm.shadePrimitives,
                         warm.shadeFragmentInvocations);
  }
  return 0;
}

int runTraceCommand(const TraceCommandOptions& o, std::ostream& log) {
  const PreparedView v = prepareView(o.view);
  log << fmt::format("yarn {} scaled {:.3f}x to yarn radius {:.4g} ({}); fabric {}, {} shading\n", v.preset.name,
                     v.fibers.fit.scale, v.fibers.fit.radius, v.fibers.fit.source, o.view.lighting.fabric,
                     o.view.lighting.model);
  const TraceResult r = traceFrame(v.model.name, v.buffers, v.fibers, v.camera, v.lod, v.shading, o, log);
  const auto files = writeImage(o.view, r.image);
  log << fmt::format("wrote {}\n", files.front().string());
  return 0;
}

}  // namespace ft
