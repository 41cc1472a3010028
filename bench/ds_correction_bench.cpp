// ds_correction_bench.cpp — ft_ds_correction_bench: the dual-scattering bakes
// of Huang et al. 2025 (001) §4.1 and §4.3, on the CPU reference (2 threads
// here):
//   BM_DsTableCpu/<fabric>       the Zinke tables of eq. 8 (reference/dual_scattering.h);
//   BM_XiScene/{ci,default}      the all-fiber straight yarn as an Embree scene;
//   BM_XiDirection/{ci,default}  one light direction of the ξ bake (one shard
//                                of `fibertwin bake ds-correction`), path traced;
//   BM_XiBake/ci                 the whole CI bake in one process: every
//                                direction and the factorisation.
// The default bake (8 × 8 directions) costs 64 × BM_XiDirection/default; on
// N ranks that over N (docs/bakes.md measures the 1 → 2 rank speed-up with
// mpirun, which a benchmark process cannot start). 001 §5.1 baked all its
// textures in 5–7 min on a 32-core Threadripper 3970X (64 threads).
// Own flag: --yarn=NAME (cotton1).
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>
#include <string>

#include "bench/bench_flags.h"
#include "reference/dual_scattering.h"
#include "reference/ds_correction.h"
#include "scene/fabric.h"
#include "scene/input_error.h"

namespace {

ft::DsCorrectionSettings g_ci, g_default;
std::unique_ptr<ft::DsCorrectionScene> g_ciScene, g_defaultScene;

void BM_DsTableCpu(benchmark::State& state, std::string fabric) {
  const ft::FabricParams p = ft::findFabricPreset(fabric).params();
  for (auto _ : state) benchmark::DoNotOptimize(ft::bakeDualScatteringCpu(p));
}

void BM_XiScene(benchmark::State& state, const ft::DsCorrectionSettings* s) {
  size_t segments = 0;
  for (auto _ : state) {
    ft::DsCorrectionScene scene(*s);
    segments = scene.segmentCount();
  }
  state.counters["segments"] = double(segments);
}

void BM_XiDirection(benchmark::State& state, const ft::DsCorrectionScene* scene) {
  // A direction at 22.5° off the yarn's normal plane, from the side.
  const int d = scene->settings().phiSamples * (scene->settings().thetaSamples / 2) + scene->settings().phiSamples / 4;
  for (auto _ : state) benchmark::DoNotOptimize(scene->trace(d));
  const ft::DsCorrectionLayout l = scene->layout();
  const double samples = double(l.size.x) * l.size.y * scene->settings().samplesPerPixel *
                         scene->settings().pixelsPerTexel * scene->settings().pixelsPerTexel;
  state.counters["camera_samples"] = samples;
  state.counters["samples_per_s"] = benchmark::Counter(samples, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_XiBake(benchmark::State& state, const ft::DsCorrectionScene* scene) {
  for (auto _ : state) {
    std::vector<ft::DsDirectionSums> sums;
    for (int d = 0; d < scene->directionCount(); ++d) sums.push_back(scene->trace(d));
    const double perTexel = double(scene->settings().samplesPerPixel) * scene->settings().pixelsPerTexel *
                            scene->settings().pixelsPerTexel;
    benchmark::DoNotOptimize(ft::factorDsCorrection(scene->layout(), sums, perTexel));
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string yarn = "cotton1";
    ft::takeFlag(argc, argv, "yarn", yarn);
    g_default.yarn = yarn;
    g_ci = g_default;
    g_ci.height = 8;  // the harness's xi/bake size (validation/ds_correction_cases.cpp)
    g_ci.thetaSamples = 4;
    g_ci.phiSamples = 4;
    g_ci.samplesPerPixel = 16;
    g_ci.periods = 3;
    g_ciScene = std::make_unique<ft::DsCorrectionScene>(g_ci);
    g_defaultScene = std::make_unique<ft::DsCorrectionScene>(g_default);
    benchmark::AddCustomContext("yarn", yarn);
    benchmark::AddCustomContext("ci", "N_v 8, 4x4 directions, 2x2 pixels per texel at 16 spp, 3 periods");
    benchmark::AddCustomContext("default", "N_v 32, 8x8 directions, 2x2 pixels per texel at 64 spp, 5 periods");
    benchmark::AddCustomContext("paper", "001 §5.1: all textures in 5-7 min, Threadripper 3970X, 64 threads");
    for (const char* fabric : {"cotton", "fleece"})
      benchmark::RegisterBenchmark((std::string("BM_DsTableCpu/") + fabric).c_str(), BM_DsTableCpu, std::string(fabric))
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    for (const auto& [name, s] : {std::pair{"ci", &g_ci}, std::pair{"default", &g_default}})
      benchmark::RegisterBenchmark((std::string("BM_XiScene/") + name).c_str(), BM_XiScene, s)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    for (const auto& [name, s] : {std::pair{"ci", g_ciScene.get()}, std::pair{"default", g_defaultScene.get()}})
      benchmark::RegisterBenchmark((std::string("BM_XiDirection/") + name).c_str(), BM_XiDirection, s)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    benchmark::RegisterBenchmark("BM_XiBake/ci", BM_XiBake, g_ciScene.get())->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_ds_correction_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_ds_correction_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
