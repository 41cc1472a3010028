// exemplar_volume_bench.cpp — ft_exemplar_volume_bench: the exemplar volume
// and eye-ray casting of Khungurn et al. 2017 (004) §5.1 on the GPU
// (docs/exemplar-volume.md "Throughput"):
//   BM_VolBuildGpu      the ID volume (one invocation per voxel over the
//                       candidate list of its cell), upload + dispatch + glFinish;
//   BM_VolSampleGpu/N   1024² eye rays × N samples (32, 64, 128) into the
//                       G-buffer, dispatch + glFinish (no read-back);
//   BM_VolBuildCpu      the CPU builder (TBB) on the same volume, for scale.
// The exemplar: plain weave, polyester1, --fibers-per-ply=N (24), fiber radius
// r_f = --fiber-radius (0.0008: h = 2 r_f, 143 voxels a period, notes A1).
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>
#include <string>

#include "bench/bench_flags.h"
#include "gpu/exemplar_volume_gpu.h"
#include "gpu/gl_context.h"
#include "reference/exemplar.h"
#include "reference/exemplar_volume.h"
#include "scene/input_error.h"

namespace {

ft::Exemplar g_block;
ft::VolParams g_layout{};
ft::VolumeCandidates g_cand;
std::vector<ft::VolSegment> g_segs;
std::unique_ptr<ft::GlContext> g_gl;
std::unique_ptr<ft::ExemplarVolumeGpu> g_gpu;

void BM_VolBuildCpu(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(ft::buildExemplarVolumeCpu(g_block, g_layout, g_cand));
  state.counters["voxels_per_s"] = benchmark::Counter(double(g_layout.dims.x) * g_layout.dims.y * g_layout.dims.z,
                                                      benchmark::Counter::kIsIterationInvariantRate);
}

void BM_VolBuildGpu(benchmark::State& state) {
  for (auto _ : state) {
    g_gpu->build(g_layout, g_segs, g_cand.start, g_cand.entries);
    glFinish();
  }
  state.counters["voxels_per_s"] = benchmark::Counter(double(g_layout.dims.x) * g_layout.dims.y * g_layout.dims.z,
                                                      benchmark::Counter::kIsIterationInvariantRate);
}

// 1024² orthographic rays over [−2P, 2P]², 27° off the normal; samples 0:
// the capsule ids, else the midpoint ids with N = samples.
ft::VolParams benchRays(int samples) {
  ft::VolParams rays = g_layout;
  ft::VolCamera cam;
  const float P = ft::ftVolPeriod(g_layout);
  cam.direction = glm::normalize(glm::vec3(0.5f, 0.3f, -1.0f));
  cam.up = glm::vec3(0.0f, 0.0f, 1.0f);
  cam.position = -3.0f * P * cam.direction;
  cam.halfWidth = cam.halfHeight = 2.0f * P;
  ft::setVolumeRays(rays, cam, 1024, 1024, samples > 0 ? samples : 1,
                    samples > 0 ? FT_VOL_IDS_MIDPOINT : FT_VOL_IDS_CAPSULE);
  return rays;
}

// The CPU capsule ids (TBB over rows), the rays of BM_VolSampleGpu.
void BM_VolSampleCpuCapsule(benchmark::State& state) {
  const ft::ExemplarVolume vol = ft::buildExemplarVolumeCpu(g_block, g_layout, g_cand);
  const ft::VolParams rays = benchRays(0);
  for (auto _ : state) benchmark::DoNotOptimize(ft::sampleVolumeCpu(vol, rays));
  state.counters["rays_per_s"] = benchmark::Counter(1024.0 * 1024.0, benchmark::Counter::kIsIterationInvariantRate);
}

// samples 0: the capsule ids (the first exact capsule hit; N unused).
void BM_VolSampleGpu(benchmark::State& state, int samples) {
  g_gpu->build(g_layout, g_segs, g_cand.start, g_cand.entries);
  const ft::VolParams rays = benchRays(samples);
  for (auto _ : state) {
    g_gpu->sampleNoReadback(rays);
    glFinish();
  }
  state.counters["rays_per_s"] = benchmark::Counter(1024.0 * 1024.0, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string fibers = "24", radius = "0.0008", cell = "4";
    ft::takeFlag(argc, argv, "fibers-per-ply", fibers);
    ft::takeFlag(argc, argv, "fiber-radius", radius);
    ft::takeFlag(argc, argv, "cell-voxels", cell);  // voxels per candidate cell side
    ft::ExemplarSettings es;
    es.fibersPerPly = std::stoi(fibers);
    es.fiberRadius = std::stof(radius);
    g_block = ft::makePlainWeaveExemplar(es);
    g_layout = ft::makeVolumeLayout(g_block, 0, std::stoi(cell));
    g_cand = ft::buildVolumeCandidates(g_block, g_layout);
    g_segs = ft::volumeSegments(g_block);
    benchmark::AddCustomContext("exemplar", g_block.label);
    benchmark::AddCustomContext("volume", std::to_string(g_layout.dims.x) + "x" + std::to_string(g_layout.dims.y) +
                                              "x" + std::to_string(g_layout.dims.z));
    benchmark::AddCustomContext("segments", std::to_string(g_block.segments.size()));
    benchmark::AddCustomContext("cell_voxels", cell);
    benchmark::AddCustomContext("candidates_max_per_cell", std::to_string(g_cand.maxPerCell));
    benchmark::AddCustomContext("candidates_mean_per_cell",
                                std::to_string(double(g_cand.entries.size()) / double(g_cand.start.size() - 1)));
    benchmark::RegisterBenchmark("BM_VolBuildCpu", BM_VolBuildCpu)->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark("BM_VolSampleCpuCapsule", BM_VolSampleCpuCapsule)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    try {
      g_gl = ft::GlContext::create(ft::glBackendFromEnv());
      g_gpu = std::make_unique<ft::ExemplarVolumeGpu>(g_gl->info());
      benchmark::AddCustomContext("gl_renderer", g_gl->info().renderer);
      benchmark::RegisterBenchmark("BM_VolBuildGpu", BM_VolBuildGpu)->Unit(benchmark::kMillisecond)->UseRealTime();
      for (int n : {32, 64, 128})
        benchmark::RegisterBenchmark(("BM_VolSampleGpu/" + std::to_string(n)).c_str(), BM_VolSampleGpu, n)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      benchmark::RegisterBenchmark("BM_VolSampleGpuCapsule", BM_VolSampleGpu, 0)->Unit(benchmark::kMillisecond)->UseRealTime();
    } catch (const std::exception& e) {
      std::cerr << "ft_exemplar_volume_bench: no GL context, CPU benchmarks only (" << e.what() << ")\n";
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    g_gpu.reset();
    g_gl.reset();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_exemplar_volume_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_exemplar_volume_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
