// knit_bench.cpp — ft_knit_bench: time of the knit-deformation optimization
// (001_dce8d4d1f783b802.txt §3.2, §5.2: knot-based Gauss–Newton, one problem
// per stitch, 3 iterations, w_angle 1, w_length 100) on a stockinette patch
// stretched 1.4× along the course, at three sizes (Args = rows, cols):
// 60×60 (3,600 stitches), 75×76 (5,700) and 250×200 (50,000):
//   BM_KnitCpu/R/C          solveKnitCpu: the CPU reference (double, TBB over stitches,
//                           including the lift to world space) into the buffers of the
//                           previous iteration, wall clock;
//   BM_KnitGpuOptimize/R/C  KnitGpu::optimize(): knit_optimize.comp.glsl, one invocation
//                           per stitch (float);
//   BM_KnitGpuFull/R/C      optimize() + upsample() (Catmull–Rom rendering vertices).
//   BM_KnitShaded{Compute,Tessellation}/20/20
//                           the shaded frame of `fibertwin knit` (docs/knit-rendering.md)
//                           of the 20×20 patch (the GPU solve's yarns, the rest state's
//                           length coordinates, the knit camera) at --shaded_width ×
//                           --shaded_height (1280×960), every approximation of 000 §4
//                           at its default, occlusion culling on; the inputs baked once
//                           (not timed), the shadow map redrawn every frame (as for a
//                           new frame of a sequence: the model changes); counters: the
//                           phases of one more frame (FrameTimings).
//   BM_KnitShaded{Compute,Tessellation}Env/20/20
//                           the same frame with `--env data/env/sky.exr` (001 §4.5: the
//                           16-SRBF + DC fit and the 16×16×8×8 I_M table, GPU bakes,
//                           once and not timed; counter env_bake_ms); the default light
//                           still adds, as in `render --env`.
// Not timed, on every path: the problem setup (buildKnitSetup: mesh → per-stitch
// problems), the GPU records and uploads (setStitches, setYarnList) and the
// read-backs. Each size is set up once per process, on first use.
// GPU benchmarks use manual time from ft::GpuTimer (glFinish+steady_clock on
// software renderers, GL_TIME_ELAPSED on real GPUs; the JSON context says which).
// Counters and the paper's figures: docs/benchmarks.md.
//
// Own flags (parsed and removed before benchmark::Initialize):
//   --large_iterations=N  iterations per repetition of the 50K-stitch benchmarks
//                         (default 5: on the 2-core llvmpipe machine one run takes
//                         0.2-0.5 s on the GPU paths and 0.6-1.2 s on the CPU;
//                         0 = as many as --benchmark_min_time needs)
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_flags.h"
#include "gpu/fiber_gpu.h"
#include "gpu/fiber_renderer.h"
#include "gpu/gl_context.h"
#include "gpu/gpu_timer.h"
#include "gpu/knit_gpu.h"
#include "gpu/shading_inputs_gpu.h"
#include "knit/knit_render.h"
#include "scene/lighting.h"
#include "knit/knit_problem.h"
#include "knit/stitch_mesh.h"
#include "reference/knit_reference.h"
#include "reference/srbf_fit.h"
#include "scene/input_error.h"

namespace {

// The benchmarked sizes (rows, cols): ~3.6K, ~5.7K and 50K stitches.
constexpr std::pair<int, int> kSizes[] = {{60, 60}, {75, 76}, {250, 200}};

// 001_dce8d4d1f783b802.txt Table 1 "Sim." (CUDA, RTX 3090) for the scenes of these
// sizes. Its "Yarn CPs" are rendering vertices, 56 per stitch (§5.2): Flame, 200K
// ≈ 3.6K stitches, 1.05 ms; Relaxation (Fig. 17), 319K ≈ 5.7K stitches, 2.50 ms.
// 0: no scene of that size in the paper.
double paperSimMs(int rows, int cols) {
  if (rows * cols == 3600) return 1.05;
  if (rows * cols == 5700) return 2.50;
  return 0;
}
constexpr int kLargeStitches = 20000;  // sizes above this use --large_iterations

// One size, built on first use and kept for every repetition.
struct Problem {
  ft::KnitSetup setup;
  std::unique_ptr<ft::KnitGpu> gpu;  // stitches and yarn list uploaded
};

struct Setup {
  int largeIterations = 5;  // 0: let --benchmark_min_time decide
  int shadedWidth = 1280, shadedHeight = 960;
  std::unique_ptr<ft::GlContext> gl;
  std::unique_ptr<ft::GpuTimer> timer;
  std::map<std::pair<int, int>, Problem> problems;
};

Setup* g = nullptr;

// Untimed: mesh, deformation, per-stitch problems (and for the GPU the records
// and uploads, plus one warm-up run: llvmpipe compiles the kernels on first use).
Problem& problem(int rows, int cols, bool withGpu) {
  Problem& p = g->problems[{rows, cols}];
  if (p.setup.tileCount() == 0) {
    const ft::StitchMesh rest = ft::makeStockinette(rows, cols);
    const ft::StitchMesh deformed = ft::deform(rest, ft::Deformation{ft::Deformation::StretchCourse, 1.4});
    p.setup = ft::buildKnitSetup(rest, deformed, ft::KnitOptions{});
  }
  if (withGpu && !p.gpu) {
    p.gpu = std::make_unique<ft::KnitGpu>(g->gl->info());
    const std::vector<ft::KnitStitchGpu> records = ft::knitGpuRecords(p.setup);
    const std::vector<glm::uvec4> list = ft::knitYarnList(p.setup);
    p.gpu->setStitches(records, ft::knitSolveParams(p.setup));
    p.gpu->setYarnList(list);
    p.gpu->run();
    glFinish();
  }
  return p;
}

// stitches: the mesh's faces; tiles: tiles on faces + ghost stitches above the top row
// (what is solved: one problem each); control points: 14 per tile.
void setCounters(benchmark::State& state, const ft::KnitSetup& s) {
  const double stitches = s.faceCount;
  state.counters["stitches"] = stitches;
  state.counters["tiles"] = s.tileCount();
  state.counters["control_points"] = double(s.tileCount()) * FT_KNIT_TILE_POINTS;
  state.counters["stitches_per_second"] =
      benchmark::Counter(stitches * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  if (const double ms = paperSimMs(static_cast<int>(state.range(0)), static_cast<int>(state.range(1))); ms > 0)
    state.counters["paper_sim_ms"] = ms;
}

void BM_KnitCpu(benchmark::State& state) {
  const Problem& p = problem(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), false);
  // Into the same buffers every iteration, as frame after frame of an animation
  // (the GPU benchmarks reuse their buffers too); sized by one untimed solve.
  ft::KnitSolution sol;
  ft::solveKnitCpu(p.setup, sol);
  for (auto _ : state) {
    ft::solveKnitCpu(p.setup, sol);
    benchmark::DoNotOptimize(sol.worldPoints.data());
    benchmark::ClobberMemory();
  }
  setCounters(state, p.setup);
}

// Both GPU benchmarks check the read-back once after timing: every point finite.
bool pointsFinite(benchmark::State& state, const ft::KnitGpu& gpu, const ft::KnitSetup& s) {
  const std::vector<glm::vec4> pts = gpu.readPoints();
  if (pts.size() != size_t(s.tileCount()) * FT_KNIT_TILE_POINTS) {
    state.SkipWithError(fmt::format("read {} points, expected {}", pts.size(),
                                    size_t(s.tileCount()) * FT_KNIT_TILE_POINTS)
                            .c_str());
    return false;
  }
  for (const glm::vec4& q : pts)
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
      state.SkipWithError("non-finite optimized point");
      return false;
    }
  return true;
}

void BM_KnitGpuOptimize(benchmark::State& state) {
  Problem& p = problem(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), true);
  for (auto _ : state) {
    g->timer->begin();
    p.gpu->optimize();  // dispatch only; endMs() waits (glFinish on llvmpipe)
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
  if (pointsFinite(state, *p.gpu, p.setup)) setCounters(state, p.setup);
}

void BM_KnitGpuFull(benchmark::State& state) {
  Problem& p = problem(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), true);
  for (auto _ : state) {
    g->timer->begin();
    p.gpu->optimize();
    p.gpu->upsample();
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
  if (pointsFinite(state, *p.gpu, p.setup)) setCounters(state, p.setup);
}

// The knit command's shaded frame of one patch (Args = rows, cols): solved on
// the GPU once, its buffers with the rest lengths, inputs baked once.
void BM_KnitShaded(benchmark::State& state, ft::FiberPath path, bool environment) {
  const int rows = static_cast<int>(state.range(0)), cols = static_cast<int>(state.range(1));
  Problem& p = problem(rows, cols, true);
  const ft::StitchMesh rest = ft::makeStockinette(rows, cols);
  const ft::KnitOptions options;
  const ft::YarnModel model = ft::knitYarnModelFromVertices(p.setup, p.gpu->readVertices());
  const ft::YarnBuffers buffers = ft::knitFrameBuffers(model, ft::knitRestBuffers(rest, options));
  const ft::FittedFibers fibers = ft::knitFibers(ft::findYarnPreset("cotton1"), options, ft::FiberOptions{});
  const ft::Camera camera = ft::knitCamera(p.setup, g->shadedWidth, g->shadedHeight);
  const ft::GlInfo& gi = g->gl->info();
  ft::FiberGpu gpu(gi);
  ft::FiberRenderer renderer(gi);
  gpu.setModel(buffers, fibers.table);
  gpu.setParams(fibers.params, ft::makeViewParams(camera, 1.0f, true, true));
  ft::AppearanceOptions appearance;
  // The procedural sky, bit for bit data/env/sky.exr (SrbfFit.ShippedSkyMap).
  if (environment) appearance.environmentImage = std::make_shared<ft::ImageRgbaF>(ft::makeProceduralSky(256, 128));
  const auto t0 = std::chrono::steady_clock::now();
  renderer.setShading(ft::ShadingBakeGpu(gi).bake(
      {ft::makeShadingParams(ft::Lighting{}), &fibers.fit.preset, appearance, &fibers.params, &fibers.table}));
  const double bakeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const int w = g->shadedWidth, h = g->shadedHeight;
  renderer.draw(gpu, path, w, h);  // warm-up: shader variants, buffer sizes, the target
  glFinish();
  for (auto _ : state) {
    gpu.setModel(buffers, fibers.table);  // a new frame of a sequence: the shadow map is redrawn
    glFinish();
    g->timer->begin();
    renderer.draw(gpu, path, w, h);
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
  gpu.setModel(buffers, fibers.table);
  ft::FrameTimings t;
  renderer.draw(gpu, path, w, h, &t);
  state.counters["shadow_map_ms"] = t.shadowMapMs;
  state.counters["generate_ms"] = t.generateMs;
  state.counters["occluder_pass_ms"] = t.depthMs;
  state.counters["shaded_pass_ms"] = t.shadeMs;
  // Culling is chosen per view (FiberRenderer::OcclusionCull::Auto): culled = 1
  // when this view culled; occluded_fraction then describes its occluders.
  state.counters["culled"] = renderer.cullsView(gpu) ? 1.0 : 0.0;
  state.counters["occluded_fraction"] = renderer.cullsView(gpu) ? renderer.occludedFraction() : 0.0;
  state.counters["segments"] = double(buffers.segments.size());
  if (environment) state.counters["env_bake_ms"] = bakeMs;  // every input of the frame, the SRBF fit and table among them
  const ft::ImageRgbaF img = renderer.read();
  double covered = 0.0;
  for (size_t i = 0; i < img.pixelCount(); ++i) {
    if (!std::isfinite(img.pixels[4 * i]) || !std::isfinite(img.pixels[4 * i + 1]) || !std::isfinite(img.pixels[4 * i + 2])) {
      state.SkipWithError("non-finite pixel value");
      return;
    }
    covered += img.pixels[4 * i + 3];
  }
  state.counters["covered_fraction"] = covered / double(img.pixelCount());
}

}  // namespace

int main(int argc, char** argv) {
  Setup setup;
  g = &setup;
  try {
    if (std::string n; ft::takeFlag(argc, argv, "large_iterations", n))
      setup.largeIterations = std::max(0, std::atoi(n.c_str()));
    if (std::string n; ft::takeFlag(argc, argv, "shaded_width", n)) setup.shadedWidth = std::max(16, std::atoi(n.c_str()));
    if (std::string n; ft::takeFlag(argc, argv, "shaded_height", n)) setup.shadedHeight = std::max(16, std::atoi(n.c_str()));

    setup.gl = ft::GlContext::create(ft::glBackendFromEnv());
    const ft::GlInfo& gi = setup.gl->info();
    setup.timer = std::make_unique<ft::GpuTimer>(gi);

    benchmark::AddCustomContext("gl_vendor", gi.vendor);
    benchmark::AddCustomContext("gl_renderer", gi.renderer);
    benchmark::AddCustomContext("gl_version", gi.version);
    benchmark::AddCustomContext("gl_backend", gi.backend);
    benchmark::AddCustomContext("gpu_timing_method", setup.timer->method());
    benchmark::AddCustomContext("cpu_threads", std::to_string(tbb::info::default_concurrency()));
    benchmark::AddCustomContext("pattern", "stockinette");
    benchmark::AddCustomContext("deformation", "stretch-course 1.4");
    const ft::KnitOptions o;
    benchmark::AddCustomContext("knit_options", fmt::format("w_angle {}, w_length {}, iterations {}, yarn radius {}",
                                                            o.wAngle, o.wLength, o.iterations, o.yarnRadius));
    benchmark::AddCustomContext("large_iterations", std::to_string(setup.largeIterations));
    // 001_dce8d4d1f783b802.txt Table 1 (simulation time, CUDA on an RTX 3090); counter paper_sim_ms.
    benchmark::AddCustomContext("paper_sim_ms",
                                "60/60: 1.05 (Flame, 200K yarn CPs = 56 per stitch, ~3.6K stitches); "
                                "75/76: 2.50 (Relaxation, Fig. 17, 319K yarn CPs, ~5.7K stitches); RTX 3090");
    benchmark::AddCustomContext("paper_source", "001_dce8d4d1f783b802.txt Table 1");

    struct Kind {
      const char* name;
      void (*fn)(benchmark::State&);
      bool manualTime;
    };
    for (const Kind& k : {Kind{"BM_KnitCpu", BM_KnitCpu, false}, Kind{"BM_KnitGpuOptimize", BM_KnitGpuOptimize, true},
                          Kind{"BM_KnitGpuFull", BM_KnitGpuFull, true}}) {
      for (const auto& [rows, cols] : kSizes) {
        auto* b = benchmark::RegisterBenchmark(k.name, k.fn)->Args({rows, cols})->Unit(benchmark::kMillisecond);
        if (k.manualTime)
          b->UseManualTime();
        else
          b->UseRealTime();
        if (rows * cols > kLargeStitches && setup.largeIterations > 0) b->Iterations(setup.largeIterations);
      }
    }

    for (bool environment : {false, true})
      for (const auto& [name, path] : {std::pair{"BM_KnitShadedCompute", ft::FiberPath::Compute},
                                       std::pair{"BM_KnitShadedTessellation", ft::FiberPath::Tessellation}})
        benchmark::RegisterBenchmark(environment ? fmt::format("{}Env", name).c_str() : name, BM_KnitShaded, path,
                                     environment)
            ->Args({20, 20})
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime()
            ->Iterations(2);
    // 001 Table 1 (Huang et al. 2025, RTX 3090): rendering ms with / without the
    // 16-SRBF environment light; Cable is the one model timed both ways.
    benchmark::AddCustomContext("env_map", "procedural sky 256x128 = data/env/sky.exr (16 SRBFs + DC, I_M table "
                                           "16x16x8x8, GPU bakes)");
    benchmark::AddCustomContext("paper_001_table1_cable_ms", "9.4 without env (118M fiber seg.) / 20.6 with env (96M)");
    benchmark::AddCustomContext("paper_001_table1_with_env_ms",
                                "Ribbing 15.7 (6.5M seg.), Montague 16.5 (7.3M), Flame 23.6 (29M), Photograph 31.1 (150M)");
    benchmark::AddCustomContext("paper_001_table1_gpu", "NVIDIA RTX 3090, 1920x1280 (first six) / 1300x1300");
    benchmark::AddCustomContext("shaded_viewport", fmt::format("{}x{}, 4x MSAA, RGBA32F; cotton1, cotton, defaults of "
                                                               "render", setup.shadedWidth, setup.shadedHeight));

    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_knit_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_knit_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
