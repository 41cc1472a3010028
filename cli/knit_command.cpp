#include "cli/knit_command.h"

#include "validation/draw_check.h"

#include <fmt/format.h>

#include <chrono>
#include <memory>
#include <ostream>

#include "gpu/fiber_gpu.h"
#include "gpu/fiber_renderer.h"
#include "gpu/knit_gpu.h"
#include "knit/knit_render.h"
#include "reference/knit_reference.h"
#include "scene/bcc_reader.h"
#include "scene/camera.h"
#include "scene/input_error.h"
#include "scene/yarn_preset.h"
#include "scene/yarn_radius.h"
#include "validation/report.h"

namespace ft {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct Frame {
  StitchMesh mesh;
  std::string label;
};

std::pair<StitchMesh, std::vector<Frame>> loadFrames(const KnitCommandOptions& o) {
  if (o.meshes.size() >= 2) {
    if (o.frames != 1) throw InputError("--frames: not used with an OBJ frame sequence (--mesh given more than once)");
    std::vector<StitchMesh> seq = readStitchObjSequence(o.meshes);
    std::vector<Frame> frames;
    for (size_t i = 1; i < seq.size(); ++i) frames.push_back({seq[i], seq[i].name});
    return {seq.front(), frames};
  }
  StitchMesh rest;
  if (o.meshes.size() == 1) {
    rest = readStitchObj(o.meshes.front());
  } else {
    if (o.rows < 1 || o.rows > 1000 || o.cols < 1 || o.cols > 1000)
      throw InputError(fmt::format("--rows/--cols: {} x {} is out of range (1 to 1000)", o.rows, o.cols));
    if (o.pattern == "stockinette") rest = makeStockinette(o.rows, o.cols);
    else if (o.pattern == "ribbing") rest = makeRibbing1x1(o.rows, o.cols);
    else if (o.pattern == "lace") rest = makeLacePatch(o.rows, o.cols);
    else throw InputError(fmt::format("--pattern: '{}' is not stockinette, ribbing or lace", o.pattern));
  }
  const Deformation d = parseDeformation(o.deformation);
  if (o.frames < 1 || o.frames > 1000) throw InputError(fmt::format("--frames: {} is out of range (1 to 1000)", o.frames));
  std::vector<Frame> frames;
  if (o.frames == 1) {
    frames.push_back({deform(rest, d), o.deformation});
  } else {
    const std::vector<StitchMesh> seq = animate(rest, d, o.frames);
    for (int i = 0; i < o.frames; ++i) frames.push_back({seq[i], fmt::format("{} frame {}", o.deformation, i)});
  }
  return {rest, frames};
}

}  // namespace

std::filesystem::path frameFileName(const std::filesystem::path& path, int index) {
  std::filesystem::path out = path;
  out.replace_filename(fmt::format("{}_{:03d}{}", path.stem().string(), index, path.extension().string()));
  return out;
}

int runKnitCommand(const KnitCommandOptions& o, std::ostream& log) {
  if (o.solver != "gpu" && o.solver != "cpu")
    throw InputError(fmt::format("--solver: '{}' is neither gpu nor cpu", o.solver));
  if (o.path != "compute" && o.path != "tessellation")
    throw InputError(fmt::format("--path: '{}' is neither compute nor tessellation", o.path));
  if (!o.image.empty()) {
    if (o.preview && o.image.extension() != ".png")
      throw InputError(fmt::format("--image: '{}' must end in .png with --preview", o.image.string()));
    checkFrameImagePath(o.image, "--image");
  }
  if (!o.reference.empty()) checkFrameImagePath(o.reference, "--reference");
  validateKnitOptions(o.knit);
  const YarnPreset preset = overrideYarnPreset(findYarnPreset(o.yarn), o.presetOverrides);
  checkFiberOptions(preset, o.fiber);
  const ShadingParams shading = makeShadingParams(o.lighting);  // bad lighting options fail before any work
  auto [rest, frames] = loadFrames(o);
  // Every frame's problems before any GL work: bad meshes are rejected first.
  std::vector<KnitSetup> setups;
  std::vector<double> setupMs;
  for (const Frame& f : frames) {
    const auto t0 = std::chrono::steady_clock::now();
    setups.push_back(buildKnitSetup(rest, f.mesh, o.knit));
    setupMs.push_back(msSince(t0));
  }

  std::unique_ptr<GlContext> context;
  std::unique_ptr<KnitGpu> knitGpu;
  std::unique_ptr<FiberGpu> fiberGpu;
  std::unique_ptr<FiberRenderer> renderer;
  const bool needGl = o.solver == "gpu" || !o.image.empty();
  if (needGl) context = GlContext::create(o.backend);
  if (o.solver == "gpu") knitGpu = std::make_unique<KnitGpu>(context->info());

  const bool drawn = !o.image.empty() || !o.reference.empty();
  const FiberPath path = o.path == "compute" ? FiberPath::Compute : FiberPath::Tessellation;
  FittedFibers fibers, allFibers;
  YarnBuffers restBuffers;
  // One camera for a whole sequence, framing the last (most deformed) frame.
  const Camera camera = knitCamera(setups.back(), o.width, o.height);
  if (drawn) {
    fibers = knitFibers(preset, o.knit, o.fiber);
    log << fmt::format("yarn {} scaled {:.3f}x to yarn radius {:.4g} ({}); fabric {}, {} shading\n", preset.name,
                       fibers.fit.scale, fibers.fit.radius, fibers.fit.source, o.lighting.fabric,
                       o.preview ? "preview" : o.lighting.model);
    // Fibers follow the yarn material: every frame keeps the rest state's
    // length coordinates, so twist and flyaways stretch with the yarn instead
    // of sliding along it.
    restBuffers = knitRestBuffers(rest, o.knit);
  }
  if (!o.reference.empty()) {
    FiberOptions all = o.fiber;
    all.allFibers = true;  // the all-fiber reference: every fiber of the preset, no core, no LoD
    allFibers = knitFibers(preset, o.knit, all);
  }
  if (!o.image.empty()) {
    fiberGpu = std::make_unique<FiberGpu>(context->info());
    renderer = std::make_unique<FiberRenderer>(context->info());
    if (!o.preview) {
      // The inputs depend on the lighting, the fabric and the fitted preset
      // only: baked once for the whole sequence. The shadow map follows each
      // frame's yarns (FiberRenderer::draw redraws it after setModel).
      const auto t0 = std::chrono::steady_clock::now();
      renderer->setShading(bakeFrameInputs(context->info(), {}, shading, fibers, o.appearance));
      renderer->setOcclusionCull(o.occlusionCull ? FiberRenderer::OcclusionCull::Auto : FiberRenderer::OcclusionCull::Off);
      log << fmt::format("shading inputs baked once for {} frame(s): {:.0f} ms\n", frames.size(), msSince(t0));
    }
  }
  const bool sequence = frames.size() > 1;
  for (size_t fi = 0; fi < frames.size(); ++fi) {
    const KnitSetup& setup = setups[fi];
    const auto t1 = std::chrono::steady_clock::now();
    YarnModel model;
    double before = 0, after = 0;
    if (knitGpu) {
      knitGpu->setStitches(knitGpuRecords(setup), knitSolveParams(setup));
      knitGpu->setYarnList(knitYarnList(setup));
      knitGpu->run();
      model = knitYarnModelFromVertices(setup, knitGpu->readVertices());
      const auto e = knitGpu->readEnergies();
      for (uint32_t t = 0; t < setup.tileCount(); ++t) {
        before += e[t].energy[0];
        after += e[t].energy[o.knit.iterations];
      }
    } else {
      const KnitSolution sol = solveKnitCpu(setup);
      model = knitYarnModel(setup, sol.worldPoints, true);
      for (const auto& e : sol.energy) {
        before += e[0];
        after += e[o.knit.iterations];
      }
    }
    const double solveMs = msSince(t1);
    model.name = fmt::format("knit ({})", frames[fi].label);
    const std::filesystem::path bccPath = sequence ? frameFileName(o.bcc, int(fi)) : o.bcc;
    writeBcc(model, bccPath);
    size_t vertices = 0;
    for (const YarnCurve& c : model.curves) vertices += c.points.size();
    log << fmt::format(
        "{}: {} stitches ({} tiles, {} with the bind-off), {} yarns, {} vertices; eq. 3 energy {:.4g} -> {:.4g} "
        "after {} Gauss-Newton iterations; setup {:.1f} ms, {} solve + read-back {:.1f} ms\n",
        bccPath.string(), setup.faceCount, setup.stitchCount, setup.tileCount(), model.curves.size(), vertices,
        before, after,
        o.knit.iterations, setupMs[fi], o.solver, solveMs);
    if (!drawn) continue;
    const YarnBuffers buffers = knitFrameBuffers(model, restBuffers);
    if (!o.image.empty()) {
      const auto t2 = std::chrono::steady_clock::now();
      fiberGpu->setModel(buffers, fibers.table);
      checkBeforeDrawing(model.name, buffers, fiberGpu->readFrames());  // no partial image from NaN frames
      fiberGpu->setParams(fibers.params, makeViewParams(camera, 1.0f, true, true));
      const std::filesystem::path imagePath = sequence ? frameFileName(o.image, int(fi)) : o.image;
      if (o.preview) {
        RenderStyle style;
        style.lightDir = glm::vec3(shading.lightDirection[0]);
        writePng(imagePath, renderer->preview(*fiberGpu, path, o.width, o.height, style));
        log << fmt::format("{}: {}x{}, yarn {}, {} path, preview, {:.0f} ms on {}\n", imagePath.string(), o.width,
                           o.height, preset.name, o.path, msSince(t2), context->info().renderer);
      } else {
        FrameTimings t;
        const ImageRgbaF image = drawShadedFrame(*renderer, *fiberGpu, path, o.width, o.height,
                                                 fmt::format("{}, the {} path", model.name, o.path), &t);
        const double frameMs = msSince(t2);
        const auto files = writeFrameImage(imagePath, o.display, image);
        log << fmt::format("{}: {}x{}, {} path, frame {:.0f} ms = shadow map {:.0f} + generation {:.0f} + occluder pass "
                           "{:.0f} + shaded pass {:.0f} + upload and read-back {:.0f}, on {}\n",
                           files.front().string(), o.width, o.height, o.path, frameMs, t.shadowMapMs, t.generateMs,
                           t.depthMs, t.shadeMs, frameMs - t.totalMs(),
                           context->info().renderer);
      }
    }
    if (!o.reference.empty()) {
      const std::filesystem::path refPath = sequence ? frameFileName(o.reference, int(fi)) : o.reference;
      const auto t3 = std::chrono::steady_clock::now();
      // The reference is lit as the frame is: render's --env map, sampled directly.
      TraceSettings trace = o.trace;
      if (o.appearance.environmentMap) trace.environmentMap = o.appearance.environmentMap;
      const TraceResult r = traceFrame(model.name, buffers, allFibers, camera, false, shading, trace, log);
      const auto files = writeFrameImage(refPath, o.display, r.image);
      log << fmt::format("{}: the path-traced all-fiber reference ({} fibers per ply), {:.1f} s\n",
                         files.front().string(), allFibers.params.regularFibers, msSince(t3) * 1e-3);
    }
  }
  return 0;
}

}  // namespace ft
