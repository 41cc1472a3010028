// flyaway_bench.cpp — ft_flyaway_bench: the flyaway curves and the three
// textures of 001 §4.4 (docs/flyaways.md), cotton1 at its own scale, at the
// harness's size (128 × 32) and the default (512 × 128):
//   BM_FlyawayCpu/{ci,default}  generateFlyawaysCpu + bakeFlyawaysCpu (TBB)
//   BM_FlyawayGpu/{ci,default}  FlyawayGpu::generate + bake (upload, dispatch, read-back)
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>

#include "gpu/flyaway_gpu.h"
#include "gpu/gl_context.h"
#include "reference/flyaway.h"
#include "scene/input_error.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_preset.h"

namespace {

std::unique_ptr<ft::GlContext> g_gl;
std::unique_ptr<ft::FlyawayGpu> g_gpu;

ft::FlyawayParams params(uint32_t w, uint32_t h) {
  const ft::YarnPreset& p = ft::findYarnPreset("cotton1");
  ft::FlyawaySettings s;
  s.width = w;
  s.height = h;
  return ft::makeFlyawayParams(p, ft::makeFiberSetup(p, ft::FiberOptions{}).params, s);
}

void BM_FlyawayCpu(benchmark::State& state, ft::FlyawayParams f) {
  for (auto _ : state) benchmark::DoNotOptimize(ft::bakeFlyawaysCpu(ft::generateFlyawaysCpu(f)));
  state.counters["texels"] = 3.0 * f.width * f.height;
}

void BM_FlyawayGpu(benchmark::State& state, ft::FlyawayParams f) {
  for (auto _ : state) benchmark::DoNotOptimize(g_gpu->bake(g_gpu->generate(f)));
  state.counters["texels"] = 3.0 * f.width * f.height;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const ft::FlyawayParams ci = params(ft::FT_FLYAWAY_CI_WIDTH, ft::FT_FLYAWAY_CI_HEIGHT);
    const ft::FlyawayParams def = params(ft::FT_FLYAWAY_WIDTH, ft::FT_FLYAWAY_HEIGHT);
    for (const auto& [name, p] : {std::pair{"ci", ci}, std::pair{"default", def}})
      benchmark::RegisterBenchmark((std::string("BM_FlyawayCpu/") + name).c_str(), BM_FlyawayCpu, p)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    try {
      g_gl = ft::GlContext::create(ft::glBackendFromEnv());
      g_gpu = std::make_unique<ft::FlyawayGpu>(g_gl->info());
      benchmark::AddCustomContext("gl_renderer", g_gl->info().renderer);
      for (const auto& [name, p] : {std::pair{"ci", ci}, std::pair{"default", def}})
        benchmark::RegisterBenchmark((std::string("BM_FlyawayGpu/") + name).c_str(), BM_FlyawayGpu, p)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    } catch (const std::exception& e) {
      std::cerr << "ft_flyaway_bench: no GL context, CPU benchmarks only (" << e.what() << ")\n";
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    g_gpu.reset();  // GL objects before the context
    g_gl.reset();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_flyaway_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_flyaway_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
