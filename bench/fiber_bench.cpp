// fiber_bench.cpp — ft_fiber_bench: throughput of procedural fiber generation
// (000_cc9bd0fbd0e08a03.txt §3, §5) on the three paths, over every yarn
// segment of one model at the three standard LoD distances (scene/camera.h),
// and at full detail (LoD and culling off) over the first --full_segments:
//   BM_FiberCpu/{near,mid,far,full}           CPU reference (TBB over segments), wall clock;
//   BM_FiberCompute/{near,mid,far,full}       the compute passes (decide → scan → owners →
//                                             samples → generate);
//   BM_FiberTessellation/{near,mid,far,full}  isoline tessellation captured with transform
//                                             feedback and rasterizer discard.
// GPU benchmarks use manual time from ft::GpuTimer (glFinish+steady_clock on
// software renderers, GL_TIME_ELAPSED on real GPUs; the JSON context says which).
// Counters and how to compare runs: docs/benchmarks.md.
//
// Own flags (parsed and removed before benchmark::Initialize):
//   --model=PATH          BCC yarn-level model (default: data/yarn-models/glove.bcc
//                         next to the source tree)
//   --yarn=NAME           built-in yarn preset (default cotton1)
//   --tess_iterations=N   iterations per tessellation repetition (default 2: llvmpipe's
//                         tessellator is slow; 0 = as many as --benchmark_min_time needs,
//                         for real GPUs)
//   --full_segments=N     segments of the full-detail scenario (default 2000)
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gpu/fiber_gpu.h"
#include "bench/bench_flags.h"
#include "gpu/gl_context.h"
#include "gpu/gpu_timer.h"
#include "reference/fiber_reference.h"
#include "scene/bcc_reader.h"
#include "scene/camera.h"
#include "scene/input_error.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_model.h"
#include "scene/yarn_preset.h"

#ifndef FT_SOURCE_DIR
#define FT_SOURCE_DIR "."
#endif

namespace {

// Bytes one vertex would take as explicit geometry: xyz as three floats. The
// strip half-width, ids and any index buffer are left out, so this is the
// least an explicit representation of the same fibers needs.
constexpr double kExplicitBytesPerVertex = 12.0;

// What a benchmark generates: the three LoD distances over the whole model,
// and "full": every fiber at full detail (LoD and culling off) over a fixed
// subset (the first --full_segments segments), so the paths are compared on
// identical, unculled work.
struct Scenario {
  std::string name;
  ft::ViewParams view{};
  std::vector<uint32_t> segments;  // empty: all
};

struct Setup {
  std::string modelPath;
  std::string yarnName = "cotton1";
  int tessIterations = 2;  // 0: let --benchmark_min_time decide
  size_t fullSegments = 2000;
  std::vector<Scenario> scenarios;

  ft::YarnModel model;
  ft::YarnBuffers buffers;
  const ft::YarnPreset* preset = nullptr;
  std::vector<ft::FiberCoord> table;
  ft::YarnParams params{};
  std::vector<ft::FrameNormal> cpuFrames;

  std::unique_ptr<ft::GlContext> gl;
  std::unique_ptr<ft::FiberGpu> gpu;
  std::unique_ptr<ft::GpuTimer> timer;

  // Seconds per fiber vertex of every timed iteration, by "path/distance",
  // for the compute-vs-tessellation ratio.
  std::map<std::string, std::vector<double>> secondsPerVertex;
};

Setup* g = nullptr;

std::vector<Scenario> makeScenarios(size_t fullSegments) {
  std::vector<Scenario> out;
  for (ft::LodDistance d : {ft::LodDistance::Near, ft::LodDistance::Mid, ft::LodDistance::Far}) {
    const ft::Camera cam = ft::lodCamera(g->model, g->params, d, 1.0f, 640, 480);
    out.push_back({ft::lodDistanceName(d), ft::makeViewParams(cam, 1.0f, true, true), {}});
  }
  Scenario full{"full", ft::makeViewParams(ft::frameModel(g->model, {0.3f, 0.5f, 1.0f}, 640, 480), 1.0f, false, false),
                {}};
  const size_t n = std::min(fullSegments, g->buffers.segments.size());
  for (uint32_t i = 0; i < n; ++i) full.segments.push_back(i);
  out.push_back(full);
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string key(const char* path, const Scenario& sc) { return fmt::format("{}/{}", path, sc.name); }

// Counters shared by all three benchmarks. `vertices` = vertices generated per
// iteration (for tessellation: the captured line endpoints, 2 per line);
// `fiberVertices` = distinct fiber vertices they describe (the explicit
// geometry of the same fibers stores each once).
void setCounters(benchmark::State& state, double vertices, double totalVertices, double fiberVertices) {
  const double inputBytes = static_cast<double>(g->gpu->inputBytes());
  state.counters["vertices"] = vertices;
  state.counters["vertices_per_second"] = benchmark::Counter(totalVertices, benchmark::Counter::kIsRate);
  state.counters["input_bytes"] = inputBytes;
  state.counters["explicit_bytes"] = fiberVertices * kExplicitBytesPerVertex;
  state.counters["explicit_to_input_ratio"] = inputBytes > 0 ? fiberVertices * kExplicitBytesPerVertex / inputBytes : 0;
}

void BM_FiberCpu(benchmark::State& state, const Scenario* sc) {
  const ft::FiberInput input{&g->buffers, &g->table, g->params, sc->view};
  double vertices = 0, total = 0;
  for (auto _ : state) {
    ft::FiberGeometry geo = ft::generateFibersCpu(input, g->cpuFrames, sc->segments);
    vertices = static_cast<double>(geo.vertices.size());
    total += vertices;
    benchmark::DoNotOptimize(geo.vertices.data());
    state.PauseTiming();  // freeing the result is not generation
    geo = {};
    state.ResumeTiming();
  }
  setCounters(state, vertices, total, vertices);
}

void BM_FiberCompute(benchmark::State& state, const Scenario* sc) {
  ft::FiberGpu& gpu = *g->gpu;
  gpu.setParams(g->params, sc->view);
  gpu.setSegmentList(sc->segments);
  gpu.generateCompute();  // warm-up: llvmpipe compiles shader variants and sizes buffers on first use
  glFinish();
  double vertices = 0, total = 0;
  for (auto _ : state) {
    g->timer->begin();
    gpu.generateCompute();
    const double ms = g->timer->endMs();
    state.SetIterationTime(ms * 1e-3);
    vertices = gpu.readDrawCommand().vertexTotal;
    total += vertices;
    if (vertices > 0) g->secondsPerVertex[key("compute", *sc)].push_back(ms * 1e-3 / vertices);
  }
  setCounters(state, vertices, total, vertices);
}

void BM_FiberTessellation(benchmark::State& state, const Scenario* sc) {
  ft::FiberGpu& gpu = *g->gpu;
  gpu.setParams(g->params, sc->view);
  gpu.setSegmentList(sc->segments);
  gpu.captureTessellation();  // warm-up (shader variants, capture buffer size); 0.1-0.3 s for the glove on llvmpipe
  glFinish();
  double captured = 0, unique = 0, totalCaptured = 0, totalUnique = 0;
  std::vector<double> secondsPerVertex;  // this repetition's iterations
  for (auto _ : state) {
    g->timer->begin();
    const size_t lines = gpu.captureTessellation();  // includes its decide + scan passes (they size the capture)
    const double ms = g->timer->endMs();
    state.SetIterationTime(ms * 1e-3);
    // decide/scan ran in the capture: the draw command holds this view's totals.
    // A strip of n vertices is n - 1 lines, so lines + strips = vertexTotal.
    const ft::DrawElementsCommand cmd = gpu.readDrawCommand();
    if (static_cast<size_t>(cmd.vertexTotal) - cmd.stripTotal != lines) {
      state.SkipWithError(fmt::format("captured {} lines, the decisions give {}", lines,
                                      static_cast<size_t>(cmd.vertexTotal) - cmd.stripTotal)
                              .c_str());
      break;
    }
    captured = 2.0 * static_cast<double>(lines);
    unique = cmd.vertexTotal;
    totalCaptured += captured;
    totalUnique += unique;
    if (unique > 0) {
      secondsPerVertex.push_back(ms * 1e-3 / unique);
      g->secondsPerVertex[key("tessellation", *sc)].push_back(ms * 1e-3 / unique);
    }
  }
  setCounters(state, captured, totalCaptured, unique);
  // The fiber vertices the lines stand for (what the compute path writes once each).
  state.counters["unique_vertices"] = unique;
  state.counters["unique_vertices_per_second"] = benchmark::Counter(totalUnique, benchmark::Counter::kIsRate);
  state.counters["lines"] = captured / 2.0;
  // Compute-vs-tessellation throughput on the same fiber vertices: this
  // repetition against the median of every compute iteration of this distance,
  // when BM_FiberCompute ran earlier in this process (not filtered out).
  const auto it = g->secondsPerVertex.find(key("compute", *sc));
  if (it != g->secondsPerVertex.end() && !secondsPerVertex.empty())
    state.counters["compute_over_tessellation"] = median(secondsPerVertex) / median(it->second);
}


// benchmark's own --benchmark_out / --benchmark_out_format, peeked at (not removed).
std::string peekFlag(int argc, char** argv, const char* name) {
  const std::string prefix = std::string("--") + name + "=";
  std::string value;
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], prefix.c_str(), prefix.size()) == 0) value = argv[i] + prefix.size();
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  Setup setup;
  g = &setup;
  try {
    setup.modelPath = FT_SOURCE_DIR "/data/yarn-models/glove.bcc";
    ft::takeFlag(argc, argv, "model", setup.modelPath);
    ft::takeFlag(argc, argv, "yarn", setup.yarnName);
    if (std::string n; ft::takeFlag(argc, argv, "tess_iterations", n)) setup.tessIterations = std::max(0, std::atoi(n.c_str()));
    if (std::string n; ft::takeFlag(argc, argv, "full_segments", n))
      setup.fullSegments = static_cast<size_t>(std::max(1, std::atoi(n.c_str())));
    const std::string outPath = peekFlag(argc, argv, "benchmark_out");
    const std::string outFormat = peekFlag(argc, argv, "benchmark_out_format");

    setup.model = ft::readBcc(setup.modelPath);
    setup.buffers = ft::buildYarnBuffers(setup.model);
    setup.preset = &ft::findYarnPreset(setup.yarnName);
    const ft::FiberOptions options;  // defaults
    ft::FiberSetup fibers = ft::makeFiberSetup(*setup.preset, options);
    setup.table = std::move(fibers.table);
    setup.params = fibers.params;
    setup.cpuFrames = ft::computeKnotFramesCpu(setup.buffers);

    setup.gl = ft::GlContext::create(ft::glBackendFromEnv());
    const ft::GlInfo& gi = setup.gl->info();
    setup.gpu = std::make_unique<ft::FiberGpu>(gi);
    setup.gpu->setModel(setup.buffers, setup.table);
    setup.timer = std::make_unique<ft::GpuTimer>(gi);

    benchmark::AddCustomContext("gl_vendor", gi.vendor);
    benchmark::AddCustomContext("gl_renderer", gi.renderer);
    benchmark::AddCustomContext("gl_version", gi.version);
    benchmark::AddCustomContext("gl_backend", gi.backend);
    benchmark::AddCustomContext("gpu_timing_method", setup.timer->method());
    benchmark::AddCustomContext("model", std::filesystem::weakly_canonical(setup.modelPath).string());
    benchmark::AddCustomContext("curves", std::to_string(setup.buffers.curves.size()));
    benchmark::AddCustomContext("segments", std::to_string(setup.buffers.segments.size()));
    benchmark::AddCustomContext("yarn", setup.preset->name);
    benchmark::AddCustomContext("explicit_bytes_per_vertex", "12 (xyz float32)");
    benchmark::AddCustomContext("tess_iterations", std::to_string(setup.tessIterations));
    setup.scenarios = makeScenarios(setup.fullSegments);
    benchmark::AddCustomContext("full_segments", std::to_string(setup.scenarios.back().segments.size()));

    for (const Scenario& sc : setup.scenarios)
      benchmark::RegisterBenchmark(fmt::format("BM_FiberCpu/{}", sc.name).c_str(), BM_FiberCpu, &sc)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    for (const Scenario& sc : setup.scenarios)
      benchmark::RegisterBenchmark(fmt::format("BM_FiberCompute/{}", sc.name).c_str(), BM_FiberCompute, &sc)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
    for (const Scenario& sc : setup.scenarios) {
      auto* b = benchmark::RegisterBenchmark(fmt::format("BM_FiberTessellation/{}", sc.name).c_str(),
                                             BM_FiberTessellation, &sc)
                    ->Unit(benchmark::kMillisecond)
                    ->UseManualTime();
      if (setup.tessIterations > 0) b->Iterations(setup.tessIterations);
    }

    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();

    // Derived check: compute vs tessellation throughput on the same fiber
    // vertices (median seconds per vertex over all timed iterations).
    nlohmann::json ratios = nlohmann::json::object();
    for (const Scenario& sc : setup.scenarios) {
      const auto c = setup.secondsPerVertex.find(key("compute", sc));
      const auto t = setup.secondsPerVertex.find(key("tessellation", sc));
      if (c == setup.secondsPerVertex.end() || t == setup.secondsPerVertex.end()) continue;
      const double ratio = median(t->second) / median(c->second);
      ratios[sc.name] = ratio;
      std::cerr << fmt::format("compute/tessellation throughput at {:<4}: {:8.1f}x  (compute {:.3g} vertices/s, "
                               "tessellation {:.3g} vertices/s, {}){}\n",
                               sc.name, ratio, 1.0 / median(c->second), 1.0 / median(t->second),
                               setup.timer->method(),
                               "");
    }
    // Append the ratios to the JSON output's context (the library writes the
    // context before the runs, so this is done on the finished file).
    if (!ratios.empty() && !outPath.empty() && (outFormat.empty() || outFormat == "json")) {
      try {
        nlohmann::json doc;
        {
          std::ifstream in(outPath);
          doc = nlohmann::json::parse(in);
        }
        doc["context"]["compute_over_tessellation"] = ratios;
        std::ofstream(outPath) << doc.dump(2) << "\n";
      } catch (const std::exception& e) {
        std::cerr << "ft_fiber_bench: could not add the ratios to " << outPath << ": " << e.what() << "\n";
      }
    }
  } catch (const ft::InputError& e) {
    std::cerr << "ft_fiber_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_fiber_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
