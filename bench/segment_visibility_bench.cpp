// segment_visibility_bench.cpp — ft_segment_visibility_bench: the steps of the
// segment visibility bake of Khungurn et al. 2017 (004) §4.1 on one thread
// (docs/segment-visibility.md "Throughput"):
//   BM_SvfRays/<res>     one segment's visibility image: res² Embree occlusion rays
//                        from μ_k through the 7 × 7 tiled plain-weave exemplar;
//   BM_SvfSsdf/<res>     its SSDF (boundary lists, rows pruned);
//   BM_SvfWeights/<res>  its 48 Voronoi weights;
//   BM_SvfPca/<rows>     the PCA of <rows> 32² SSDFs (the bake's global step).
// Segments cycle through the block, so the rays see every part of the weave.
// Own flags: --fibers-per-ply=N (0: the preset's, 60 for polyester1), --tiles=N (7).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <iostream>
#include <memory>
#include <string>

#include "bench/bench_flags.h"
#include "reference/exemplar.h"
#include "reference/segment_visibility.h"
#include "scene/input_error.h"

namespace {

ft::Exemplar g_block;
int g_tiles = 7;
std::unique_ptr<ft::SvfScene> g_scene;

uint32_t segmentAt(size_t i) { return uint32_t((i * 7919u) % g_block.segments.size()); }

void BM_SvfRays(benchmark::State& state, int res) {
  size_t i = 0;
  const size_t copy = ft::centreCopy(g_tiles);
  for (auto _ : state) {
    const uint32_t k = segmentAt(i++);
    const ft::ExemplarSegment& s = g_block.segments[k];
    benchmark::DoNotOptimize(g_scene->visibilityImage(s.mid(), uint32_t(copy) * g_block.fibers + s.fiber,
                                                      uint32_t(copy * g_block.segments.size() + k), res, res));
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(res) * res, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_SvfSteps(benchmark::State& state, int res, int step) {
  ft::SvfSettings s;
  s.width = s.height = res;
  std::vector<ft::SvfSegment> segs;
  for (size_t i = 0; i < 16; ++i) segs.push_back(ft::svfSegmentCpu(*g_scene, g_block, g_tiles, segmentAt(i), s));
  size_t i = 0;
  for (auto _ : state) {
    const ft::SvfSegment& g = segs[i++ % segs.size()];
    if (step == 0) benchmark::DoNotOptimize(ft::svfSsdfCpu(g.image, res, res));
    else benchmark::DoNotOptimize(ft::svfWeightsCpu(g.image, res, res, 48, g.angle));
  }
}

void BM_SvfPca(benchmark::State& state, int rows) {
  ft::SvfSettings s;
  s.width = s.height = 32;
  std::vector<float> ssdf;
  for (int i = 0; i < rows; ++i) {
    const ft::SvfSegment g = ft::svfSegmentCpu(*g_scene, g_block, g_tiles, segmentAt(size_t(i)), s);
    ssdf.insert(ssdf.end(), g.ssdf.begin(), g.ssdf.end());
  }
  for (auto _ : state) benchmark::DoNotOptimize(ft::svfPcaCpu(ssdf, size_t(rows), 32 * 32, 48));
}

}  // namespace

int main(int argc, char** argv) {
  try {
    ft::ExemplarSettings e;
    std::string fibers = "6", tiles = "7";
    ft::takeFlag(argc, argv, "fibers-per-ply", fibers);
    ft::takeFlag(argc, argv, "tiles", tiles);
    e.fibersPerPly = std::stoi(fibers);
    g_tiles = std::stoi(tiles);
    g_block = ft::makePlainWeaveExemplar(e);
    const std::vector<ft::ExemplarSegment> tiled = ft::tileExemplar(g_block, g_tiles);
    g_scene = std::make_unique<ft::SvfScene>(tiled);
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    benchmark::AddCustomContext("exemplar", g_block.label);
    benchmark::AddCustomContext("segments", std::to_string(g_block.segments.size()) + " per block, " +
                                                std::to_string(tiled.size()) + " tiled");
    for (int res : {32, 64, 128}) {
      benchmark::RegisterBenchmark(("BM_SvfRays/" + std::to_string(res)).c_str(), BM_SvfRays, res)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("BM_SvfSsdf/" + std::to_string(res)).c_str(), BM_SvfSteps, res, 0)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("BM_SvfWeights/" + std::to_string(res)).c_str(), BM_SvfSteps, res, 1)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
    benchmark::RegisterBenchmark("BM_SvfPca/256", BM_SvfPca, 256)->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_segment_visibility_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_segment_visibility_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
