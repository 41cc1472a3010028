// trace_bench.cpp — ft_trace_bench: throughput of the Embree ground truth
// (reference/fiber_trace.h) on a whole model framed at 1280×960
// (frameModel(model, {0.3, 0.5, 1}, 1280, 960), the glove by default), in two
// scenarios of the same camera:
//   lod   the fibers the harness draws (LoD and culling on);
//   full  every fiber at full detail (LoD off, culling on).
// Benchmarks, per scenario:
//   BM_TraceBuild/S   FiberTraceScene construction: the per-segment arrays,
//                     the tangents and Embree's BVH (the fibers are generated
//                     once beforehand, untimed);
//   BM_TraceDirect/S  one 1-spp frame, direct lighting with shadow rays;
//   BM_TracePath/S    one 1-spp frame, path traced to --path_depth scattering events.
// Counters: segments, scene_bytes (FiberTraceScene::bytes), embree_bytes,
// rays_per_second (camera + shadow + continuation rays over the frame time),
// rays_per_cpu_second (the same over the CPU time of all threads),
// seconds_per_frame, peak_rss_bytes (VmHWM of the process after the
// benchmark). docs/ground-truth.md lists a run.
//
// Own flags (parsed and removed before benchmark::Initialize):
//   --model=PATH       BCC model (default data/yarn-models/glove.bcc in the source tree)
//   --yarn=NAME        built-in yarn preset (default cotton1)
//   --fabric=NAME      built-in fabric (default cotton)
//   --scenarios=LIST   comma-separated subset of lod,full (default both)
//   --path_depth=N     maxDepth of BM_TracePath (default 4)
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_flags.h"
#include "reference/fiber_reference.h"
#include "reference/fiber_trace.h"
#include "scene/bcc_reader.h"
#include "scene/camera.h"
#include "scene/fabric.h"
#include "scene/input_error.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_model.h"
#include "scene/yarn_preset.h"
#include "scene/yarn_radius.h"

#ifndef FT_SOURCE_DIR
#define FT_SOURCE_DIR "."
#endif

namespace {

// Peak resident set size of this process (VmHWM), bytes; 0 if unknown.
double peakRssBytes() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) * 1024.0;  // "VmHWM:  123 kB"
  return 0.0;
}

// CPU seconds of every thread of this process so far.
double processCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Scenario {
  std::string name;
  bool lod = true;
  std::unique_ptr<ft::FiberGeometry> fibers;  // until the scene is built
  std::unique_ptr<ft::FiberTraceScene> scene;
};

struct Setup {
  std::string modelPath, yarnName = "cotton1", fabricName = "cotton", scenarioList = "lod,full";
  int pathDepth = 4;
  ft::YarnModel model;
  ft::YarnBuffers buffers;
  ft::FittedFibers fitted;
  std::vector<ft::FrameNormal> frames;
  ft::Camera camera;
  ft::ShadingParams shading{};
  std::vector<glm::vec3> ambientTable;
  std::map<std::string, Scenario> scenarios;
};

Setup* g = nullptr;

// Two lights and an ambient of moderate strength, the fabric's BCSDF.
ft::ShadingParams benchShading(const ft::FabricParams& fabric) {
  ft::ShadingParams s{};
  s.fabric = fabric;
  s.flags = glm::uvec4(2u, FT_SHADING_KHUNGURN, 0u, 0u);
  s.lightDirection[0] = glm::vec4(glm::normalize(glm::vec3(0.4f, 1.0f, 0.6f)), 0.0f);
  s.lightIrradiance[0] = glm::vec4(2.0f, 2.0f, 2.0f, 0.0f);
  s.lightDirection[1] = glm::vec4(glm::normalize(glm::vec3(-0.8f, 0.2f, 0.3f)), 0.0f);
  s.lightIrradiance[1] = glm::vec4(0.6f, 0.6f, 0.7f, 0.0f);
  s.ambient = glm::vec4(0.2f, 0.2f, 0.22f, 0.0f);
  s.diffuse = glm::vec4(0.05f, 0.05f, 0.05f, 0.0f);
  return s;
}

// The ambient table's narrow-lobe limit A(θ) → F + (1 − F) C_TT (notes-rendering
// A4 C3): the values do not change the timing.
std::vector<glm::vec3> albedoTable(const ft::FabricParams& fabric) {
  std::vector<glm::vec3> t;
  for (int k = 0; k < FT_AMBIENT_TABLE_SIZE; ++k)
    t.push_back(ft::ftBcsdfAlbedo(fabric, ft::ftAmbientTexelAngle(k, FT_AMBIENT_TABLE_SIZE)));
  return t;
}

void BM_TraceBuild(benchmark::State& state, Scenario* sc) {
  for (auto& [name, other] : g->scenarios) other.scene.reset();  // one scene alive at a time
  if (!sc->fibers) {
    const ft::FiberInput input{&g->buffers, &g->fitted.table, g->fitted.params,
                               ft::makeViewParams(g->camera, 1.0f, sc->lod, true)};
    sc->fibers = std::make_unique<ft::FiberGeometry>(ft::generateFibersCpu(input, g->frames));
  }
  double cpuSeconds = 0.0;
  for (auto _ : state) {
    sc->scene.reset();  // the previous iteration's scene is not part of this one's
    const double c0 = processCpuSeconds();
    sc->scene = std::make_unique<ft::FiberTraceScene>(*sc->fibers, g->fitted.params);
    cpuSeconds += processCpuSeconds() - c0;
  }
  state.counters["cpu_seconds"] = cpuSeconds / static_cast<double>(state.iterations());
  const double vertices = static_cast<double>(sc->fibers->vertices.size());
  sc->fibers.reset();  // the frames need only the scene
  state.counters["vertices"] = vertices;
  state.counters["segments"] = static_cast<double>(sc->scene->segmentCount());
  state.counters["fibers"] = static_cast<double>(sc->scene->fiberCount());
  state.counters["scene_bytes"] = static_cast<double>(sc->scene->bytes());
  state.counters["embree_bytes"] = static_cast<double>(sc->scene->embreeBytes());
  state.counters["bytes_per_segment"] = static_cast<double>(sc->scene->bytes()) / sc->scene->segmentCount();
  state.counters["peak_rss_bytes"] = peakRssBytes();
}

void traceFrame(benchmark::State& state, Scenario* sc, bool path) {
  if (!sc->scene) {
    state.SkipWithError("BM_TraceBuild of this scenario did not run (filtered out?)");
    return;
  }
  ft::TraceOptions o;
  o.samplesPerPixel = 1;
  o.shadows = true;
  o.multipleScattering = path;
  o.maxDepth = g->pathDepth;
  double rays = 0.0, seconds = 0.0, cpuSeconds = 0.0, nonFinite = 0.0;
  ft::TraceStats last;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = processCpuSeconds();
    const ft::TraceResult r = ft::traceFibers(*sc->scene, g->camera, g->shading, g->ambientTable, o);
    cpuSeconds += processCpuSeconds() - c0;
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rays += static_cast<double>(r.stats.rays());
    nonFinite += static_cast<double>(r.stats.nonFinite);
    last = r.stats;
    benchmark::DoNotOptimize(r.image.pixels.data());
  }
  if (nonFinite > 0) state.SkipWithError(fmt::format("{} non-finite samples", nonFinite).c_str());
  const double frames = static_cast<double>(state.iterations());
  state.counters["rays_per_second"] = rays / seconds;
  state.counters["rays_per_cpu_second"] = rays / cpuSeconds;  // all threads: independent of the machine's load
  state.counters["seconds_per_frame"] = seconds / frames;
  state.counters["rays_per_frame"] = rays / frames;
  state.counters["camera_rays"] = static_cast<double>(last.cameraRays);
  state.counters["shadow_rays"] = static_cast<double>(last.shadowRays);
  state.counters["bounce_rays"] = static_cast<double>(last.bounceRays);
  state.counters["coverage"] = static_cast<double>(last.hitSamples) / static_cast<double>(last.cameraRays);
  state.counters["peak_rss_bytes"] = peakRssBytes();
}

void BM_TraceDirect(benchmark::State& state, Scenario* sc) { traceFrame(state, sc, false); }
void BM_TracePath(benchmark::State& state, Scenario* sc) { traceFrame(state, sc, true); }

}  // namespace

int main(int argc, char** argv) {
  Setup setup;
  g = &setup;
  try {
    setup.modelPath = FT_SOURCE_DIR "/data/yarn-models/glove.bcc";
    ft::takeFlag(argc, argv, "model", setup.modelPath);
    ft::takeFlag(argc, argv, "yarn", setup.yarnName);
    ft::takeFlag(argc, argv, "fabric", setup.fabricName);
    ft::takeFlag(argc, argv, "scenarios", setup.scenarioList);
    if (std::string n; ft::takeFlag(argc, argv, "path_depth", n)) setup.pathDepth = std::max(1, std::atoi(n.c_str()));

    setup.model = ft::readBcc(setup.modelPath);
    setup.buffers = ft::buildYarnBuffers(setup.model);
    setup.fitted = ft::fitFibers(ft::findYarnPreset(setup.yarnName), setup.model, ft::FiberOptions{});
    setup.frames = ft::computeKnotFramesCpu(setup.buffers);
    setup.camera = ft::frameModel(setup.model, {0.3f, 0.5f, 1.0f}, 1280, 960);
    const ft::FabricParams fabric = ft::findFabricPreset(setup.fabricName).params();
    setup.shading = benchShading(fabric);
    setup.ambientTable = albedoTable(fabric);

    benchmark::AddCustomContext("model", std::filesystem::weakly_canonical(setup.modelPath).string());
    benchmark::AddCustomContext("segments", std::to_string(setup.buffers.segments.size()));
    benchmark::AddCustomContext("yarn", setup.yarnName);
    benchmark::AddCustomContext("fabric", setup.fabricName);
    benchmark::AddCustomContext("image", "1280x960, 1 spp, frameModel(model, {0.3, 0.5, 1})");
    benchmark::AddCustomContext("path_depth", std::to_string(setup.pathDepth));

    std::stringstream list(setup.scenarioList);
    for (std::string name; std::getline(list, name, ',');) {
      if (name != "lod" && name != "full") throw std::invalid_argument("--scenarios: unknown scenario " + name);
      Scenario& sc = setup.scenarios[name];
      sc.name = name;
      sc.lod = name == "lod";
    }
    // Scenario by scenario (lod before full): build, then its frames.
    for (const char* name : {"lod", "full"}) {
      const auto it = setup.scenarios.find(name);
      if (it == setup.scenarios.end()) continue;
      Scenario* sc = &it->second;
      benchmark::RegisterBenchmark(fmt::format("BM_TraceBuild/{}", name).c_str(), BM_TraceBuild, sc)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(1);
      benchmark::RegisterBenchmark(fmt::format("BM_TraceDirect/{}", name).c_str(), BM_TraceDirect, sc)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(1);
      benchmark::RegisterBenchmark(fmt::format("BM_TracePath/{}", name).c_str(), BM_TracePath, sc)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->Iterations(1);
    }

    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_trace_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_trace_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
