// prt_single_scattering_bench.cpp — ft_prt_single_scattering_bench: query
// throughput of single scattering of the fabric PRT, 004 §5.2
// (common/prt_single_scattering.h, docs/prt-single-scattering.md):
//   BM_PrtSsCpu/{directional,soft,blend,sharp}  CPU reference (double, TBB over requests);
//   BM_PrtSsGpu/{directional,soft,blend,sharp}  the GPU evaluator (upload + dispatch + read-back);
// 16,384 requests each: directional, λ = 50 (sum of 48 SGs), 150 (both
// branches), 400 (SSDF + erf); light axes uniform on the upper hemisphere,
// ω_o fixed, fleece, a lone segment's weights. items/s = shaded points per second.
// Own flag: --fabric=NAME (fleece).
#include <benchmark/benchmark.h>

#include <iostream>
#include <memory>
#include <random>
#include <string>

#include "bench/bench_flags.h"
#include "gpu/gl_context.h"
#include "gpu/prt_single_scattering_gpu.h"
#include "reference/prt_single_scattering.h"
#include "reference/segment_visibility.h"
#include "scene/fabric.h"
#include "scene/input_error.h"

namespace {

constexpr int kRequests = 16384;
std::vector<ft::FabricParams> g_fabrics;
std::vector<double> g_table;
std::vector<float> g_tableF;
ft::PrtSsSegments g_segments;
std::unique_ptr<ft::GlContext> g_gl;
std::unique_ptr<ft::PrtSingleScatteringGpu> g_gpu;

std::vector<ft::PrtSsRequest> makeRequests(float lambda) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<ft::PrtSsRequest> r(kRequests);
  const glm::vec3 t = glm::normalize(glm::vec3(1.0f, 0.2f, 0.1f)), wo = glm::normalize(glm::vec3(0.2f, -0.5f, 0.8f));
  for (ft::PrtSsRequest& q : r) {
    const float z = u(rng), phi = 6.2831853f * u(rng), s = std::sqrt(1.0f - z * z);
    q.tangent = glm::vec4(t, 0.0f);
    q.outgoing = glm::vec4(wo, 1.0f);
    q.light = glm::vec4(s * std::cos(phi), s * std::sin(phi), z, lambda);
    q.segment = glm::vec4(0.3f, ft::ftSvfRotationAngle(0u, 1u), 0.0f, 0.0f);
  }
  return r;
}

void BM_PrtSsCpu(benchmark::State& state, float lambda) {
  const std::vector<ft::PrtSsRequest> r = makeRequests(lambda);
  for (auto _ : state) benchmark::DoNotOptimize(ft::evaluatePrtSsCpu(g_fabrics, g_table, r, g_segments));
  state.SetItemsProcessed(int64_t(state.iterations()) * kRequests);
}

void BM_PrtSsGpu(benchmark::State& state, float lambda) {
  const std::vector<ft::PrtSsRequest> r = makeRequests(lambda);
  for (auto _ : state)
    benchmark::DoNotOptimize(g_gpu->evaluate(g_fabrics, g_tableF, r, g_segments.weights, g_segments.axes,
                                             g_segments.lambdaSvf));
  state.SetItemsProcessed(int64_t(state.iterations()) * kRequests);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    std::string fabric = "fleece";
    ft::takeFlag(argc, argv, "fabric", fabric);
    g_fabrics = {ft::findFabricPreset(fabric).params()};
    g_table = ft::bakePrtSsTableCpu(g_fabrics);
    g_tableF.assign(g_table.begin(), g_table.end());
    const std::vector<uint8_t> visible(64 * 64, 1);
    g_segments.weights = ft::svfWeightsCpu(visible, 64, 64, FT_SVF_DEFAULT_AXES, ft::ftSvfRotationAngle(0u, 1u));
    benchmark::AddCustomContext("fabric", fabric);
    benchmark::AddCustomContext("requests", std::to_string(kRequests));
    const std::pair<const char*, float> kinds[] = {{"directional", 0.0f}, {"soft", 50.0f}, {"blend", 150.0f}, {"sharp", 400.0f}};
    for (const auto& [name, lambda] : kinds)
      benchmark::RegisterBenchmark((std::string("BM_PrtSsCpu/") + name).c_str(), BM_PrtSsCpu, lambda)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    try {
      g_gl = ft::GlContext::create(ft::glBackendFromEnv());
      g_gpu = std::make_unique<ft::PrtSingleScatteringGpu>(g_gl->info());
      benchmark::AddCustomContext("gl_renderer", g_gl->info().renderer);
      for (const auto& [name, lambda] : kinds)
        benchmark::RegisterBenchmark((std::string("BM_PrtSsGpu/") + name).c_str(), BM_PrtSsGpu, lambda)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    } catch (const std::exception& e) {
      std::cerr << "ft_prt_single_scattering_bench: no GL context, CPU benchmarks only (" << e.what() << ")\n";
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    g_gpu.reset();
    g_gl.reset();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_prt_single_scattering_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_prt_single_scattering_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
