// core_texture_bench.cpp — ft_core_texture_bench: the core-fiber texture bake
// (000 §3.2; reference/core_texture.h) on the CPU, Embree round curves with
// TBB over rows, for cotton1 at its own scale:
//   BM_CoreTextureEmbree/ci       128 × 16 (the harness's size; target < 1 s on 2 cores)
//   BM_CoreTextureEmbree/default  512 × 64
//   BM_CoreTextureCapsules/ci     the shared capsule chain run in C++ (the GPU
//                                 shader's loop), for scale.
// Each iteration builds the Embree scene and casts every ray.
#include <benchmark/benchmark.h>

#include "reference/core_texture.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_preset.h"

namespace {

ft::CoreTextureInput input(uint32_t w, uint32_t h) {
  const ft::FiberSetup s = ft::makeFiberSetup(ft::findYarnPreset("cotton1"), ft::FiberOptions{});
  return ft::makeCoreTextureInput(s.params, s.table, w, h);
}

void BM_CoreTextureEmbree(benchmark::State& state, uint32_t w, uint32_t h) {
  const ft::CoreTextureInput in = input(w, h);
  for (auto _ : state) benchmark::DoNotOptimize(ft::bakeCoreTextureEmbree(in));
  state.counters["texels"] = double(w) * h;
  state.counters["fibers"] = double(in.fibers.size());
}

void BM_CoreTextureCapsules(benchmark::State& state, uint32_t w, uint32_t h) {
  const ft::CoreTextureInput in = input(w, h);
  for (auto _ : state) benchmark::DoNotOptimize(ft::bakeCoreTextureCapsules(in));
  state.counters["texels"] = double(w) * h;
}

}  // namespace

BENCHMARK_CAPTURE(BM_CoreTextureEmbree, ci, ft::FT_CORE_TEXTURE_CI_WIDTH, ft::FT_CORE_TEXTURE_CI_HEIGHT)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CoreTextureEmbree, default, ft::FT_CORE_TEXTURE_WIDTH, ft::FT_CORE_TEXTURE_HEIGHT)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CoreTextureCapsules, ci, ft::FT_CORE_TEXTURE_CI_WIDTH, ft::FT_CORE_TEXTURE_CI_HEIGHT)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
