// appearance_bench.cpp — ft_appearance_bench: the bakes of the fiber
// appearance tables of 000 §4 (issue 14: each under 1 s at CI size on the CPU
// reference, 2 cores):
//   BM_SelfShadowCpu/{ci,default}       the exact CPU bake (reference/self_shadow.h),
//                                       TBB limited to --threads (default 2);
//   BM_SelfShadowGpuExact/{ci,default}  the same integral in GLSL (gpu/self_shadow_gpu.h),
//   BM_SelfShadowGpuGrid/{ci,default}   the paper's density grid + prefix sum,
//                                       wall clock incl. upload and read-back.
// ci = 64 × 64 × 8, default = 128 × 128 × 16 texels (common/self_shadow.h).
// Own flags: --yarn=NAME (cotton1), --threads=N (2).
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>

#include "bench/bench_flags.h"
#include "gpu/gl_context.h"
#include "gpu/self_shadow_gpu.h"
#include "reference/self_shadow.h"
#include "scene/input_error.h"
#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace {

struct Size {
  const char* name;
  uint32_t size, slices;
};
constexpr Size kSizes[] = {{"ci", FT_SELF_SHADOW_CI_SIZE, FT_SELF_SHADOW_CI_SLICES},
                           {"default", FT_SELF_SHADOW_DEFAULT_SIZE, FT_SELF_SHADOW_DEFAULT_SLICES}};

ft::YarnDensityParams g_density{};
ft::SelfShadowGpu* g_gpu = nullptr;  // owned by main, destroyed before its GL context

ft::SelfShadowParams paramsOf(const Size* s) {
  return ft::makeSelfShadowParams(g_density, s->size, s->size, s->slices);
}

void BM_SelfShadowCpu(benchmark::State& state, const Size* s) {
  const ft::SelfShadowParams p = paramsOf(s);
  for (auto _ : state) benchmark::DoNotOptimize(ft::bakeSelfShadowCpu(g_density, p).texels.data());
  state.counters["texels"] = double(p.width) * p.height * p.slices;
}

void BM_SelfShadowGpu(benchmark::State& state, const Size* s, bool grid) {
  const ft::SelfShadowParams p = paramsOf(s);
  (void)(grid ? g_gpu->bakeGrid(g_density, p) : g_gpu->bakeExact(g_density, p));  // warm-up: shader compile
  for (auto _ : state)
    benchmark::DoNotOptimize((grid ? g_gpu->bakeGrid(g_density, p) : g_gpu->bakeExact(g_density, p)).data());
  state.counters["texels"] = double(p.width) * p.height * p.slices;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string yarn = "cotton1", n;
    int threads = 2;
    ft::takeFlag(argc, argv, "yarn", yarn);
    if (ft::takeFlag(argc, argv, "threads", n)) threads = std::max(1, std::atoi(n.c_str()));
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    g_density = ft::makeYarnDensity(ft::findYarnPreset(yarn));
    const std::unique_ptr<ft::GlContext> gl = ft::GlContext::create(ft::glBackendFromEnv());
    const std::unique_ptr<ft::SelfShadowGpu> gpu = std::make_unique<ft::SelfShadowGpu>(gl->info());
    g_gpu = gpu.get();
    benchmark::AddCustomContext("gl_renderer", gl->info().renderer);
    benchmark::AddCustomContext("yarn", yarn);
    benchmark::AddCustomContext("cpu_threads", std::to_string(threads));
    benchmark::AddCustomContext("paper_000", "no bake timings, texture sizes or slice counts published");
    for (const Size& s : kSizes) {
      benchmark::RegisterBenchmark(fmt::format("BM_SelfShadowCpu/{}", s.name).c_str(), BM_SelfShadowCpu, &s)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(fmt::format("BM_SelfShadowGpuExact/{}", s.name).c_str(), BM_SelfShadowGpu, &s,
                                   false)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(fmt::format("BM_SelfShadowGpuGrid/{}", s.name).c_str(), BM_SelfShadowGpu, &s, true)
          ->Unit(benchmark::kMillisecond);
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_appearance_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_appearance_bench: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
