// knit_appearance_cases.cpp — the knit patch in the shaded frame of `render`,
// as `fibertwin knit` draws it (knit/knit_render.h, docs/knit-rendering.md):
// a small stockinette patch stretched 1.4× along the course, its yarns
// optimized, fibers fitted to the knot yarn radius, the rest state's length
// coordinates, the sequence camera.
//
//   knit/appearance/twin/<path>: the GPU frame (GPU solve in float, the
//     command's buffers, GPU bake, no approximation of 000 §4) against its
//     CPU twin: the CPU solve (double), buffers whose length coordinates are
//     the rest yarns' arc lengths computed HERE (no call of the shared
//     adoption), the CPU reference's fibers traced by Embree at the
//     rasteriser's own sample positions, direct light, no shadows. Compared
//     as shading/direct compares its frames (validation/direct_compare.h):
//     interior LDR-FLIP, coverage, and the pooled bias over every covered
//     pixel, with shading/direct's tolerances (stated in shading_cases.cpp).
//     What only a knit frame can get wrong shows here: fibers that slide
//     along the stretched yarn (length coordinates not adopted) are in other
//     places on the two sides.
//   knit/appearance/fidelity: the frame with every approximation at its
//     default (CI sizes) against the all-fiber reference of the same frame
//     (every fiber of the preset explicit, no core, no LoD) with shadow rays,
//     as the shading/fidelity rows: informational, the report shows the
//     real-time image, the reference and the error map. Row "environment":
//     the patch under the procedural sky alone (bit for bit data/env/sky.exr),
//     the frame with the defaults + `--env --soft-shadows` (the 16-SRBF + DC
//     fit through the I_M table, T̃_j with PCSS lobe maps), the reference
//     lit by the map itself, importance-sampled with MIS, shadow rays.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "gpu/fiber_gpu.h"
#include "gpu/fiber_renderer.h"
#include "gpu/knit_gpu.h"
#include "gpu/shading_inputs_gpu.h"
#include "image/flip.h"
#include "image/image_io.h"
#include "image/image_metrics.h"
#include "knit/knit_problem.h"
#include "knit/knit_render.h"
#include "knit/stitch_mesh.h"
#include "reference/fiber_reference.h"
#include "reference/fiber_trace.h"
#include "reference/knit_reference.h"
#include "reference/environment_sampling.h"
#include "reference/srbf_fit.h"
#include "reference/srbf_table.h"
#include "reference/shading_inputs.h"
#include "scene/lighting.h"
#include "scene/yarn_preset.h"
#include "validation/case_support.h"
#include "validation/direct_compare.h"
#include "validation/fidelity_xi.h"
#include "validation/harness.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

// 3 × 3 stitches at 320 × 240: the yarns ~20 px wide, so the frame holds core,
// regular fibers and interior pixels (shading/direct asks ≥ 500) at CI cost.
constexpr int kPatchRows = 3, kPatchCols = 3;
const Deformation kDeformation{Deformation::StretchCourse, 1.4};
// The twin looks closer, at the patch's centre: at the whole patch the fibers
// are 0.13 px wide and LoD (000 eq. 4) merges every one into the core, so the
// regular fibers' pool would be empty; ZOOM× closer they are drawn.
constexpr float kCloseupZoom = 6.0f;

struct KnitFrameInputs {
  KnitSetup setup;
  YarnModel gpuModel, cpuModel;
  YarnBuffers gpuBuffers;  // as `fibertwin knit` makes them (knitFrameBuffers)
  YarnBuffers cpuBuffers;  // the twin's: length coordinates computed here
  YarnPreset preset;
  FittedFibers fibers;
  Camera camera;      // the command's: the whole patch (fidelity)
  Camera closeup;     // the twin's: kCloseupZoom× closer along the same view
  double slide = 0.0;  // the largest |s_frame − s_rest| of a control point: what adoption moves (informational)
};

// The rest yarns' arc lengths along each control polygon, in double, and the
// closing chord of a closed yarn: 000 §5's length coordinate, written out
// here so that the twin shares no code with the adoption under test.
void setRestLengths(YarnBuffers& frame, const YarnModel& rest) {
  size_t point = 0;
  for (size_t c = 0; c < rest.curves.size(); ++c) {
    const std::vector<glm::vec3>& p = rest.curves[c].points;
    double s = 0.0;
    for (size_t i = 0; i < p.size(); ++i) {
      if (i > 0) s += glm::distance(glm::dvec3(p[i - 1]), glm::dvec3(p[i]));
      frame.points[point++].positionLength.w = static_cast<float>(s);
    }
    if (rest.curves[c].closed) s += glm::distance(glm::dvec3(p.back()), glm::dvec3(p.front()));
    frame.curves[c].totalLength = static_cast<float>(s);
  }
}

const KnitFrameInputs& knitFrame(ValidationContext& ctx) {
  return ctx.cached(CacheKey<KnitFrameInputs>{"knit-appearance/frame"}, [&] {
    KnitFrameInputs in;
    const StitchMesh rest = makeStockinette(kPatchRows, kPatchCols);
    const KnitOptions options;
    in.setup = buildKnitSetup(rest, deform(rest, kDeformation), options);
    KnitGpu& gpu = ctx.gpu<KnitGpu>();
    gpu.setStitches(knitGpuRecords(in.setup), knitSolveParams(in.setup));
    gpu.setYarnList(knitYarnList(in.setup));
    gpu.run();
    in.gpuModel = knitYarnModelFromVertices(in.setup, gpu.readVertices());
    in.gpuModel.name = "knit patch (GPU solve)";
    in.cpuModel = knitYarnModel(in.setup, solveKnitCpu(in.setup).worldPoints, true);
    in.cpuModel.name = "knit patch (CPU solve)";
    in.gpuBuffers = knitFrameBuffers(in.gpuModel, knitRestBuffers(rest, options));
    const KnitSetup restSetup = buildKnitSetup(rest, rest, options);
    const YarnModel restModel = knitYarnModel(restSetup, liftKnitPoints(restSetup, initialKnitPoints(restSetup)), true);
    in.cpuBuffers = buildYarnBuffers(in.cpuModel);
    const YarnBuffers own = in.cpuBuffers;
    setRestLengths(in.cpuBuffers, restModel);
    for (size_t i = 0; i < own.points.size(); ++i)
      in.slide = std::max(in.slide, double(std::abs(own.points[i].positionLength.w -
                                                    in.cpuBuffers.points[i].positionLength.w)));
    in.preset = findYarnPreset("cotton1");
    FiberOptions fo;
    fo.seed = ctx.options().fiber.seed;
    in.fibers = knitFibers(in.preset, options, fo);
    in.camera = knitCamera(in.setup, kFrameWidth, kFrameHeight);
    in.closeup = in.camera;
    in.closeup.eye = in.camera.target + (in.camera.eye - in.camera.target) / kCloseupZoom;
    in.closeup.zNear = in.camera.zNear / kCloseupZoom;
    return in;
  });
}

Lighting frontLight() {
  Lighting l;
  l.fabric = "cotton";
  l.lights = {DirectionalLight{{0.3f, 0.8f, 0.5f}, glm::vec3(3.0f)}};
  return l;
}

size_t nonFinite(const ImageRgbaF& img) {
  size_t n = 0;
  for (float v : img.pixels) n += std::isfinite(v) ? 0 : 1;
  return n;
}

RgbaImage toRgba(const ImageRgbaF& img) { return RgbaImage{img.width, img.height, tonemapToRgba8(img)}; }
RgbaImage flipImage(const FlipResult& f) { return RgbaImage{f.width, f.height, magmaRgba8(f.errorMap)}; }

ImageRgbaF renderKnit(ValidationContext& ctx, const KnitFrameInputs& in, const Camera& camera, const ShadingParams& s,
                      const AppearanceOptions& appearance, bool tessellation) {
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  gpu.setModel(in.gpuBuffers, in.fibers.table);
  gpu.setParams(in.fibers.params, makeViewParams(camera, 1.0f, true, true));
  gpu.setSegmentList({});
  FiberRenderer& renderer = ctx.gpu<FiberRenderer>();
  renderer.setShading(ctx.gpu<ShadingBakeGpu>().bake(
      {s, &in.fibers.fit.preset, appearance, &in.fibers.params, &in.fibers.table}));
  return renderer.render(gpu, tessellation ? FiberPath::Tessellation : FiberPath::Compute, kFrameWidth, kFrameHeight);
}

struct TwinTruth {
  TraceResult truth, truth16;
  size_t segments = 0;
};

CaseResult runTwin(ValidationContext& ctx, bool tessellation, const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "knit";
  r.path = tessellation ? "tessellation" : "compute";
  const auto t0 = Clock::now();
  const KnitFrameInputs& in = knitFrame(ctx);
  const ShadingParams s = makeShadingParams(frontLight());
  const auto t1 = Clock::now();
  const ImageRgbaF gpu = renderKnit(ctx, in, in.closeup, s, AppearanceOptions::none(), tessellation);
  r.gpuMilliseconds = msSince(t1);
  const auto t2 = Clock::now();
  const TwinTruth& t = ctx.cached(CacheKey<TwinTruth>{"knit-appearance/twin-truth"}, [&] {
    TwinTruth tt;
    const FiberInput input{&in.cpuBuffers, &in.fibers.table, in.fibers.params,
                           makeViewParams(in.closeup, 1.0f, true, true)};
    const FiberTraceScene scene(generateFibersCpu(input, computeKnotFramesCpu(in.cpuBuffers)), in.fibers.params);
    tt.segments = scene.segmentCount();
    const std::vector<glm::vec3> table = bakeShadingInputsCpu({s, nullptr, AppearanceOptions::none()}).ambientTable;
    TraceOptions o;
    o.samplePositions = ctx.gpu<FiberRenderer>().samplePositions();
    o.samplesPerPixel = static_cast<int>(o.samplePositions.size());
    o.shadows = false;
    tt.truth = traceFibers(scene, in.closeup, s, table, o);
    TraceOptions coverage;
    coverage.samplesPerPixel = 16;
    coverage.shadows = false;
    tt.truth16 = traceFibers(scene, in.closeup, s, table, coverage);
    return tt;
  });
  r.cpuMilliseconds = msSince(t2);
  const DirectComparison c = compareWithDirectTruth(r, gpu, t.truth, t.truth16);
  r.metrics.push_back(Metric{"length.slide_max", in.slide, 0.0, "mesh units",
                             "informational: the largest change of a control point's length coordinate that adopting "
                             "the rest state's makes (the fibers would slide that far along the yarn)",
                             false});
  if (ctx.options().images) {
    r.images.push_back(ctx.saveImage(toRgba(gpu), name + "-gpu"));
    r.images.push_back(ctx.saveImage(toRgba(t.truth.image), name + "-truth"));
    r.images.push_back(ctx.saveImage(flipImage(c.flip), name + "-flip"));
    r.imageCaptions = {"GPU " + r.path + " (GPU solve, GPU bake)", "CPU twin: CPU solve, Embree",
                       "LDR-FLIP (interior)"};
  }
  r.details = fmt::format(
      "{}×{} stockinette stretched 1.4× along the course, cotton1 at yarn radius {:.3g} (scale {:.3f}), cotton, "
      "{}x{} at {:g}× the knit camera's closeness; {} interior of {} covered pixels{}; twin: {} curve segments, {} rays; inputs {:.0f} ms",
      kPatchRows, kPatchCols, in.fibers.fit.radius, in.fibers.fit.scale, kFrameWidth, kFrameHeight, kCloseupZoom, c.interior, c.covered, c.pools,
      t.segments, t.truth.stats.rays() + t.truth16.stats.rays(), msSince(t0) - r.gpuMilliseconds - r.cpuMilliseconds);
  r.finish();
  return r;
}

// The knit command's defaults, at the harness's CI sizes.
AppearanceOptions ciDefaults() {
  AppearanceOptions a;
  a.selfShadowSize = FT_SELF_SHADOW_CI_SIZE;
  a.selfShadowSlices = FT_SELF_SHADOW_CI_SLICES;
  a.aoSettings = AoSettings::ci();
  a.shadowMapSize = 256;
  return a;
}

// EnvironmentXi: the environment row with dual scattering and the CI ξ bake of
// cotton1/cotton (validation/fidelity_xi.h): 001 eq. 17's ξΨ per lobe.
enum class KnitFidelity { None, Defaults, Environment, EnvironmentXi };
const char* fidelityName(KnitFidelity f) {
  return f == KnitFidelity::None           ? "none"
         : f == KnitFidelity::Defaults     ? "defaults"
         : f == KnitFidelity::Environment ? "environment"
                                          : "environment+xi";
}

std::shared_ptr<const ImageRgbaF> knitSky() {
  static const std::shared_ptr<const ImageRgbaF> sky = std::make_shared<ImageRgbaF>(makeProceduralSky(256, 128));
  return sky;
}

struct FidelityTruth {
  TraceResult truth;
  size_t segments = 0;
  uint32_t fibersPerPly = 0;
};

CaseResult runFidelity(ValidationContext& ctx, KnitFidelity variant, const std::string& name) {
  const bool approximations = variant != KnitFidelity::None;
  const bool env = variant == KnitFidelity::Environment || variant == KnitFidelity::EnvironmentXi;
  const bool xi = variant == KnitFidelity::EnvironmentXi;
  CaseResult r;
  r.name = name;
  r.group = "knit";
  r.path = "compute";
  const KnitFrameInputs& in = knitFrame(ctx);
  Lighting lighting = frontLight();
  AppearanceOptions appearance = approximations ? ciDefaults() : AppearanceOptions::none();
  if (env) {  // the sky alone
    lighting.lights.clear();
    lighting.ambient = glm::vec3(0.0f);
    appearance.environmentImage = knitSky();
    appearance.environmentTableDims = kSrbfTableCiDims;
    appearance.softShadows = true;
  }
  if (xi) {
    appearance.dualScattering = true;
    appearance.dsCorrectionFile = fidelityXiFile(ctx, in.preset, lighting.fabric);
  }
  const ShadingParams s = makeShadingParams(lighting);
  const auto t0 = Clock::now();
  const ImageRgbaF img = renderKnit(ctx, in, in.camera, s, appearance, false);
  r.gpuMilliseconds = msSince(t0);
  const auto t1 = Clock::now();
  // One reference for both rows: the twin's buffers (rest lengths computed here), every fiber explicit.
  const FidelityTruth& ft = ctx.cached(CacheKey<FidelityTruth>{env ? "knit-appearance/fidelity-truth-env" : "knit-appearance/fidelity-truth"}, [&] {
    FidelityTruth f;
    FiberOptions all;
    all.seed = ctx.options().fiber.seed;
    all.allFibers = true;
    const FittedFibers allFibers = knitFibers(in.preset, KnitOptions{}, all);
    const FiberInput input{&in.cpuBuffers, &allFibers.table, allFibers.params,
                           makeViewParams(in.camera, 1.0f, false, true)};
    const FiberTraceScene scene(generateFibersCpu(input, computeKnotFramesCpu(in.cpuBuffers)), allFibers.params);
    TraceOptions o;
    o.samplePositions = ctx.gpu<FiberRenderer>().samplePositions();
    o.samplesPerPixel = static_cast<int>(o.samplePositions.size());
    o.shadows = true;
    std::unique_ptr<EnvironmentSampler> sampler;
    if (env) {
      sampler = std::make_unique<EnvironmentSampler>(*knitSky());
      o.environment = sampler.get();
    }
    f.truth = traceFibers(scene, in.camera, s,
                          bakeShadingInputsCpu({s, nullptr, AppearanceOptions::none()}).ambientTable, o);
    f.segments = scene.segmentCount();
    f.fibersPerPly = allFibers.params.regularFibers;
    return f;
  });
  const TraceResult& truth = ft.truth;
  r.cpuMilliseconds = msSince(t1);
  r.metrics.push_back(nonFiniteMetric("gpu", nonFinite(img), "shaded GPU pixel values"));
  r.metrics.push_back(nonFiniteMetric("cpu", truth.stats.nonFinite + nonFinite(truth.image), "reference samples"));
  ImageRgbaF gpuLdr = img, truthLdr = truth.image;
  for (ImageRgbaF* im : {&gpuLdr, &truthLdr})
    for (size_t i = 0; i < im->pixels.size(); ++i)
      if (i % 4 != 3) im->pixels[i] = tonemapAces(im->pixels[i]);
  const FlipResult flipL = flipLdr(truthLdr, gpuLdr);
  const FlipResult flipH = flipHdr(truth.image, img);
  double sumGpu = 0.0, sumTruth = 0.0;
  for (size_t p = 0; p + 3 < img.pixels.size(); p += 4) {
    if (img.pixels[p + 3] < 0.5f || truth.image.pixels[p + 3] < 0.5f) continue;
    sumGpu += double(img.pixels[p]) + img.pixels[p + 1] + img.pixels[p + 2];
    sumTruth += double(truth.image.pixels[p]) + truth.image.pixels[p + 1] + truth.image.pixels[p + 2];
  }
  r.metrics.push_back(Metric{"flip.ldr.mean", double(flipL.pooled.mean), 0.0, "FLIP",
                             "informational: LDR-FLIP against the shadowed all-fiber reference, whole frame", false});
  r.metrics.push_back(Metric{"flip.hdr.mean", double(flipH.pooled.mean), 0.0, "FLIP",
                             "informational: HDR-FLIP against the shadowed all-fiber reference, whole frame", false});
  r.metrics.push_back(Metric{"rmse", compareImages(truth.image, img).rmse, 0.0, "radiance",
                             "informational: RMSE of linear radiance against the shadowed all-fiber reference", false});
  r.metrics.push_back(Metric{"mean.gpu_over_truth", sumTruth > 0.0 ? sumGpu / sumTruth : std::nan(""), 0.0, "ratio",
                             "informational: mean radiance of the frame over the reference's, both covered", false});
  r.metrics.push_back(blueOverRedMetric(img, truth.image));
  if (ctx.options().images) {
    r.images.push_back(ctx.saveImage(toRgba(img), name + "-gpu"));
    r.images.push_back(ctx.saveImage(toRgba(truth.image), name + "-truth"));
    r.images.push_back(ctx.saveImage(flipImage(flipL), name + "-flip"));
    r.imageCaptions = {xi               ? "GPU, the knit defaults + --env sky --soft-shadows --ds-correction (CI sizes)"
                       : env            ? "GPU, the knit defaults + --env sky --soft-shadows (CI sizes)"
                       : approximations ? "GPU, the knit defaults (CI sizes)"
                                        : "GPU, no approximation of 000 §4",
                       "all-fiber reference with shadow rays", "LDR-FLIP"};
  }
  r.details = fmt::format("{}×{} stockinette stretched 1.4×, cotton1, cotton, {}, {}x{}, the knit camera; "
                          "approximations: {}; reference: {} fibers per ply, {} curve segments, 4 spp, shadow rays{}",
                          kPatchRows, kPatchCols, env ? "the procedural sky (data/env/sky.exr) alone" : "front light", kFrameWidth,
                          kFrameHeight,
                          xi    ? "the defaults, --env (CI table), --soft-shadows, dual scattering with the CI xi bake"
                          : env ? "the defaults, --env (CI table), --soft-shadows"
                          : approximations ? "the defaults"
                                           : "none",
                          ft.fibersPerPly, ft.segments, env ? ", the map sampled directly (MIS)" : "");
  r.finish();
  return r;
}

}  // namespace

void addKnitAppearanceCases(ValidationContext& ctx, std::vector<ValidationCase>& out) {
  // The patch is built here, whatever --model says: once per CI run, on the built-in scene's.
  if (ctx.options().model) return;
  for (bool tess : {false, true}) {
    const std::string name = fmt::format("knit/appearance/twin/{}", tess ? "tessellation" : "compute");
    out.push_back({name, [=](ValidationContext& c) { return runTwin(c, tess, name); }});
  }
  for (KnitFidelity f :
       {KnitFidelity::None, KnitFidelity::Defaults, KnitFidelity::Environment, KnitFidelity::EnvironmentXi}) {
    const std::string name = fmt::format("knit/appearance/fidelity/{}", fidelityName(f));
    out.push_back({name, [=](ValidationContext& c) { return runFidelity(c, f, name); }});
  }
}

}  // namespace ft
