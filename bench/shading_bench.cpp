// shading_bench.cpp — ft_shading_bench: the cost of a shaded frame (000 §4.3:
// the shared BCSDF per directional light plus the ambient table, common/
// fiber_shading.h) on both GPU paths, at the three standard LoD distances, at
// 1280×960 (000 Table 1's viewport):
//   BM_ShadedCompute/{near,mid,far}       compute passes + indirect strip draw
//                                         (repeated frames: two-pass culling from the
//                                         second on, FiberRenderer::setTwoPassCull);
//   BM_ShadedTessellation/{near,mid,far}  one instanced tessellated draw;
//   BM_PreviewCompute/{near,mid,far}      the same draw with the preview shading,
//                                         so the BCSDF's own share can be read off;
//   BM_ShadowPass                         the yarn shadow map's depth pass alone
//                                         (000 §4.1, FiberRenderer::drawShadowMap:
//                                         every yarn segment as 8 tube pieces,
//                                         one light, --shadow-map-size texels per
//                                         side, default 2048, plus its copy to the
//                                         frame's SSBO); part of every shaded frame
//                                         while the shadow map is on.
//   BM_ShadedCompute/{frame,closeup}       the views of `render --distance frame`
//                                         (the whole glove) and `--distance closeup`,
//                                         as `render` draws them: occlusion culling
//                                         chosen per view (FiberRenderer::OcclusionCull::Auto,
//                                         the default) and deferred shading (the default);
//                                         counter culled = the choice;
//                                         a frame after another of the same view, so
//                                         two-pass culling (the lines the last frame
//                                         saw first, FiberRenderer::setTwoPassCull);
//   BM_ShadedComputeOnePass/{frame,closeup} the same without two-pass culling (every
//                                         frame a first frame);
//   BM_ShadedComputeOrbit/{frame,closeup}  frames while the camera orbits by 2° per
//                                         frame: two-pass culling from another view's lines;
//   BM_ShadedComputeCull/{frame,closeup}   the same, always the occluder pass;
//   BM_ShadedComputeNoCull/{frame,closeup} the same, never culled (same frame);
//   BM_ShadedComputeForward/{frame,closeup} culled, shaded in the fragment stage
//                                         (render --forward; same frame);
//   BM_Trace16/{frame,closeup}             the Embree ground truth of the same view
//                                         and fibers (LoD on), 16 spp, direct light
//                                         with shadow rays, the frame's light and
//                                         ambient: issue 14's yardstick (a frame
//                                         ≤ 1/4 of it), measured in the same run.
//   BM_Shaded{Compute,Tessellation}Env/{frame,closeup}  the same views lit by
//                                         the SRBF environment (001 §4.5 eq. 16,
//                                         --env=PATH, default data/env/sky.exr,
//                                         table 16x16x8x8) in place of the
//                                         uniform ambient; its bake (GPU fit sums
//                                         + table) once, counter env_bake_ms.
//                                         001 Table 1 (RTX 3090) in the context.
//   BM_ShadedComputeSoft/{frame,closeup}   the culled frame with soft yarn shadows
//                                         (PCSS, common/pcss.h; --light-angular-radius=DEG,
//                                         default 5.73): the PCSS variant of the shaded pass;
//   BM_LobeShadowPass                      the 16 SRBF lobes' depth passes
//                                         (FiberRenderer::drawLobeShadowMaps, every lobe
//                                         with energy, 1024² each) and their copy.
// Every named frame and trace: counter load1, the 1-minute load average when
// it ended (the 2 cores are shared; compare runs under like loads), and
// cpu_ms, the CPU time of all the process's threads per iteration
// (ft::processCpuMs), which other jobs on the cores disturb far less.
// Counters of the culled frames: the phases of one frame timed apart
// (FrameTimings: shadow map, generation, occluder pass, shaded pass) and the
// share of pixels an occluder covers.
// A frame is generation + draw into a kept 4× multisampled float target, no
// read-back. 000 Table 1's timings (GTX 1080) are in the JSON context, for
// scale only: a different GPU, and llvmpipe here.
//
// Own flags: --model=PATH (default data/yarn-models/glove.bcc), --yarn=NAME
// (cotton1), --fabric=NAME (cotton), --width=, --height= (1280, 960),
// --self-shadow=0 (the 000 §4.1 self-shadow texture is on by default),
// --shadow-map=0 (the yarn shadow map likewise), --shadow-map-size=N (2048).
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <stdlib.h>  // getloadavg
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_flags.h"
#include "gpu/fiber_gpu.h"
#include "gpu/fiber_renderer.h"
#include "gpu/shading_inputs_gpu.h"
#include "gpu/gl_context.h"
#include "gpu/gpu_timer.h"
#include "reference/fiber_reference.h"
#include "reference/fiber_trace.h"
#include "reference/shading_inputs.h"
#include "scene/bcc_reader.h"
#include "scene/camera.h"
#include "scene/input_error.h"
#include "scene/lighting.h"
#include "scene/yarn_radius.h"

#ifndef FT_SOURCE_DIR
#define FT_SOURCE_DIR "."
#endif

namespace {

struct Setup {
  int width = 1280, height = 960;
  ft::YarnModel model;
  ft::YarnBuffers buffers;
  ft::FittedFibers fibers;
  std::vector<std::pair<std::string, ft::ViewParams>> views;
  // The named views of `render` with their cameras, for the frame and its trace.
  std::vector<std::pair<std::string, ft::Camera>> namedViews;
  std::vector<ft::ViewParams> namedViewParams;
  ft::ShadingParams shading{};
  std::vector<ft::FrameNormal> frames;
  std::unique_ptr<ft::GlContext> gl;
  std::unique_ptr<ft::FiberGpu> gpu;
  std::unique_ptr<ft::FiberRenderer> renderer;
  std::unique_ptr<ft::GpuTimer> timer;
  // SRBF environment lighting (001 §4.5): a second renderer whose inputs add
  // --env's map (default data/env/sky.exr), baked on first use.
  ft::AppearanceOptions appearance;
  std::string envPath = FT_SOURCE_DIR "/data/env/sky.exr";
  std::unique_ptr<ft::FiberRenderer> envRenderer;
  double envBakeMs = 0.0;
  ft::ShadingInputs inputs, softInputs;  // the frame's, and the same with soft shadows
};
Setup* g = nullptr;

// A frame of a named view lit by the environment (the uniform ambient
// replaced; the light still adds), culled, on either path.
void BM_EnvFrame(benchmark::State& state, ft::FiberPath path, const ft::ViewParams* view) {
  if (!g->envRenderer) {
    const auto t0 = std::chrono::steady_clock::now();
    ft::AppearanceOptions a = g->appearance;
    a.environmentMap = g->envPath;
    g->envRenderer = std::make_unique<ft::FiberRenderer>(g->gl->info());
    g->envRenderer->setTwoPassCull(true);  // as `render` draws (its default)
    g->envRenderer->setShading(ft::ShadingBakeGpu(g->gl->info()).bake(
        {g->shading, &g->fibers.fit.preset, a, &g->fibers.params, &g->fibers.table}));
    g->envBakeMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  g->gpu->setParams(g->fibers.params, *view);
  g->envRenderer->draw(*g->gpu, path, g->width, g->height);  // warm-up: the variant's program
  glFinish();
  for (auto _ : state) {
    g->timer->begin();
    g->envRenderer->draw(*g->gpu, path, g->width, g->height);
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
  state.counters["env_bake_ms"] = g->envBakeMs;  // GPU fit sums + the 16x16x8x8 I_M table, once
}

void BM_Shaded(benchmark::State& state, ft::FiberPath path, const ft::ViewParams* view) {
  g->gpu->setParams(g->fibers.params, *view);
  g->renderer->draw(*g->gpu, path, g->width, g->height);  // warm-up: shader variants, buffer sizes, the target
  glFinish();
  for (auto _ : state) {
    g->timer->begin();
    g->renderer->draw(*g->gpu, path, g->width, g->height);
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
  if (path == ft::FiberPath::Compute) state.counters["vertices"] = g->gpu->readDrawCommand().vertexTotal;
}

// A culled or unculled compute-path frame of a named view; culled frames also
// report their phases (one more frame, each phase finished and timed).
double loadAverage() {
  double l[1] = {-1.0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

void BM_NamedFrame(benchmark::State& state, const ft::ViewParams* view, ft::FiberRenderer::OcclusionCull mode,
                   bool deferred, bool twoPass) {
  g->gpu->setParams(g->fibers.params, *view);
  g->renderer->setOcclusionCull(mode);
  const bool cull = g->renderer->cullsView(*g->gpu);
  g->renderer->setDeferred(deferred);
  g->renderer->setTwoPassCull(twoPass);
  g->renderer->forgetVisibility();  // the warm-up is a first frame
  g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height);  // warm-up
  glFinish();
  double cpuMs = 0.0;
  for (auto _ : state) {
    const double cpu0 = ft::processCpuMs();
    g->timer->begin();
    g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height);
    state.SetIterationTime(g->timer->endMs() * 1e-3);
    cpuMs += ft::processCpuMs() - cpu0;
  }
  // CPU time of all threads per frame: the work, steadier than wall time
  // when other jobs share the cores (ideal wall time on n idle cores ≈ cpu_ms / n).
  state.counters["cpu_ms"] = cpuMs / double(std::max<int64_t>(1, state.iterations()));
  if (cull || twoPass) {
    ft::FrameTimings t;
    g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height, &t);
    if (t.twoPass) {  // triangles of the first draw (the strips the last frame saw) and of both
      state.counters["first_draw_primitives"] = double(t.firstDrawPrimitives);
      state.counters["primitives"] = double(t.shadePrimitives);
    }
    state.counters["shadow_map_ms"] = t.shadowMapMs;
    state.counters["generate_ms"] = t.generateMs;
    state.counters["occluder_pass_ms"] = t.depthMs;
    state.counters["shaded_pass_ms"] = t.shadeMs;  // deferred: the visibility pass
    if (deferred) {
      state.counters["deferred_ms"] = t.deferredMs;  // compaction, shading of the list, resolve
      state.counters["deferred_hits"] = double(g->renderer->deferredEntries());
    }
    state.counters["occluded_fraction"] = g->renderer->occludedFraction();
  }
  state.counters["culled"] = cull ? 1.0 : 0.0;
  state.counters["two_pass"] = twoPass ? 1.0 : 0.0;
  state.counters["load1"] = loadAverage();
  g->renderer->setOcclusionCull(ft::FiberRenderer::OcclusionCull::Auto);
  g->renderer->setDeferred(true);
  g->renderer->setTwoPassCull(true);
}

// A named view's frames while the camera orbits the target about the up axis
// by kOrbitStepDegrees per frame (an interactive user's drag), as render
// draws them: each frame's two-pass culling starts from the lines the
// previous frame, from another angle, saw. The static views above reuse the
// same view's lines, the best case; this is the common one.
constexpr float kOrbitStepDegrees = 2.0f;

void BM_OrbitFrame(benchmark::State& state, const ft::Camera* camera) {
  g->renderer->setOcclusionCull(ft::FiberRenderer::OcclusionCull::Auto);
  g->renderer->forgetVisibility();
  int frame = 0;
  const auto orbit = [&](int k) {
    ft::Camera c = *camera;
    const glm::mat4 turn =
        glm::rotate(glm::mat4(1.0f), glm::radians(kOrbitStepDegrees * float(k)), glm::normalize(c.up));
    c.eye = c.target + glm::vec3(turn * glm::vec4(c.eye - c.target, 0.0f));
    return ft::makeViewParams(c, 1.0f, true, true);
  };
  g->gpu->setParams(g->fibers.params, orbit(frame++));
  g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height);  // warm-up: a first frame
  glFinish();
  double cpuMs = 0.0;
  uint64_t firstDraw = 0, primitives = 0;
  for (auto _ : state) {
    const double cpu0 = ft::processCpuMs();
    g->timer->begin();
    g->gpu->setParams(g->fibers.params, orbit(frame++));
    g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height);
    state.SetIterationTime(g->timer->endMs() * 1e-3);
    cpuMs += ft::processCpuMs() - cpu0;
  }
  {  // one more step, its pipeline statistics
    ft::FrameTimings t;
    g->gpu->setParams(g->fibers.params, orbit(frame++));
    g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height, &t);
    firstDraw = t.firstDrawPrimitives;
    primitives = t.shadePrimitives;
  }
  state.counters["cpu_ms"] = cpuMs / double(std::max<int64_t>(1, state.iterations()));
  state.counters["first_draw_primitives"] = double(firstDraw);
  state.counters["primitives"] = double(primitives);
  state.counters["orbit_step_deg"] = kOrbitStepDegrees;
  state.counters["load1"] = loadAverage();
}

// The Embree trace of a named view: the CPU reference's fibers at that view
// (LoD and culling on, as drawn), 16 spp, shadow rays, the frame's shading.
void BM_Trace16(benchmark::State& state, const ft::Camera* camera) {
  const ft::FiberInput input{&g->buffers, &g->fibers.table, g->fibers.params, ft::makeViewParams(*camera, 1.0f, true, true)};
  const ft::FiberTraceScene scene(ft::generateFibersCpu(input, g->frames), g->fibers.params);
  const std::vector<glm::vec3> table =
      ft::bakeShadingInputsCpu({g->shading, nullptr, ft::AppearanceOptions::none()}).ambientTable;
  ft::TraceOptions o;
  o.samplesPerPixel = 16;
  o.shadows = true;
  size_t nonFinite = 0;
  double cpuMs = 0.0;
  for (auto _ : state) {
    const double cpu0 = ft::processCpuMs();
    const auto t0 = std::chrono::steady_clock::now();
    const ft::TraceResult r = ft::traceFibers(scene, *camera, g->shading, table, o);
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    cpuMs += ft::processCpuMs() - cpu0;
    nonFinite += r.stats.nonFinite;
    benchmark::DoNotOptimize(r.image.pixels.data());
  }
  state.counters["segments"] = double(scene.segmentCount());
  state.counters["cpu_ms"] = cpuMs / double(std::max<int64_t>(1, state.iterations()));
  state.counters["load1"] = loadAverage();
  if (nonFinite > 0) state.SkipWithError(fmt::format("{} non-finite samples", nonFinite).c_str());
}

void BM_Preview(benchmark::State& state, const ft::ViewParams* view) {
  g->gpu->setParams(g->fibers.params, *view);
  const ft::RenderStyle style;
  g->renderer->preview(*g->gpu, ft::FiberPath::Compute, g->width, g->height, style);
  for (auto _ : state) {
    g->timer->begin();
    benchmark::DoNotOptimize(g->renderer->preview(*g->gpu, ft::FiberPath::Compute, g->width, g->height, style));  // includes an RGBA8 read-back
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
}

// The culled frame with soft shadows (the PCSS variant), inputs restored after.
void BM_SoftFrame(benchmark::State& state, const ft::ViewParams* view) {
  g->gpu->setParams(g->fibers.params, *view);
  g->renderer->setShading(g->softInputs);
  g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height);  // warm-up: the variant, the map
  glFinish();
  for (auto _ : state) {
    g->timer->begin();
    g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height);
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
  ft::FrameTimings t;
  g->renderer->draw(*g->gpu, ft::FiberPath::Compute, g->width, g->height, &t);
  state.counters["shaded_pass_ms"] = t.shadeMs;
  g->renderer->setShading(g->inputs);
}

// 16 lobes on Fibonacci axes, λ = 1.885 (notes A9's λ0), equal weights: every lobe gets a map.
void BM_LobeShadowPass(benchmark::State& state) {
  ft::SrbfEnvironment env{};
  for (int j = 0; j < FT_SRBF_LOBES; ++j) {
    const float z = 1.0f - (2.0f * j + 1.0f) / FT_SRBF_LOBES, r = std::sqrt(1.0f - z * z), phi = 2.39996323f * j;
    env.lobes[j].axisLambda = glm::vec4(r * std::cos(phi), r * std::sin(phi), z, 1.885f);
    env.lobes[j].weight = glm::vec4(1.0f);
  }
  g->renderer->drawLobeShadowMaps(*g->gpu, env, FT_PCSS_LOBE_DEFAULT_SIZE);  // warm-up
  glFinish();
  for (auto _ : state) {
    g->timer->begin();
    g->renderer->drawLobeShadowMaps(*g->gpu, env, FT_PCSS_LOBE_DEFAULT_SIZE);
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
  state.counters["layers"] = double(g->renderer->pcssParams().count.x);
}

void BM_ShadowPass(benchmark::State& state) {
  g->renderer->drawShadowMap(*g->gpu);  // warm-up: the program, the depth texture
  glFinish();
  for (auto _ : state) {
    g->timer->begin();
    g->renderer->drawShadowMap(*g->gpu);
    state.SetIterationTime(g->timer->endMs() * 1e-3);
  }
  state.counters["tube_pieces"] = double(g->gpu->segmentCount() * FT_SHADOW_MAP_SUBSEGMENTS);
}

}  // namespace

int main(int argc, char** argv) {
  Setup setup;
  g = &setup;
  try {
    std::string modelPath = FT_SOURCE_DIR "/data/yarn-models/glove.bcc", yarn = "cotton1", fabric = "cotton", n;
    ft::takeFlag(argc, argv, "model", modelPath);
    ft::takeFlag(argc, argv, "yarn", yarn);
    ft::takeFlag(argc, argv, "fabric", fabric);
    ft::AppearanceOptions appearance;  // every approximation of 000 §4 that is built: what a frame costs
    if (ft::takeFlag(argc, argv, "self-shadow", n)) appearance.selfShadow = n != "0";
    if (ft::takeFlag(argc, argv, "ao", n)) appearance.ao = ft::parseAoMode(n);  // none | fit | texture
    if (ft::takeFlag(argc, argv, "shadow-map", n)) appearance.shadowMap = n != "0";
    if (ft::takeFlag(argc, argv, "shadow-map-size", n)) appearance.shadowMapSize = uint32_t(std::max(16, std::atoi(n.c_str())));
    ft::takeFlag(argc, argv, "env", setup.envPath);
    if (ft::takeFlag(argc, argv, "width", n)) setup.width = std::max(16, std::atoi(n.c_str()));
    if (ft::takeFlag(argc, argv, "height", n)) setup.height = std::max(16, std::atoi(n.c_str()));
    ft::AppearanceOptions softAppearance = appearance;
    softAppearance.softShadows = true;
    if (ft::takeFlag(argc, argv, "light-angular-radius", n)) softAppearance.lightAngularRadius = float(std::atof(n.c_str()) * 3.14159265358979323846 / 180.0);
    setup.model = ft::readBcc(modelPath);
    setup.buffers = ft::buildYarnBuffers(setup.model);
    setup.fibers = ft::fitFibers(ft::findYarnPreset(yarn), setup.model, ft::FiberOptions{});
    ft::Lighting lighting;
    lighting.fabric = fabric;
    const ft::ShadingParams shading = ft::makeShadingParams(lighting);
    setup.shading = shading;
    setup.frames = ft::computeKnotFramesCpu(setup.buffers);
    for (const char* name : {"frame", "closeup"})
      setup.namedViews.emplace_back(name, ft::namedViewCamera(name, setup.model, setup.fibers.params,
                                                              {0.3f, 0.5f, 1.0f}, setup.width, setup.height));
    for (const auto& [name, cam] : setup.namedViews) setup.namedViewParams.push_back(ft::makeViewParams(cam, 1.0f, true, true));
    for (ft::LodDistance d : {ft::LodDistance::Near, ft::LodDistance::Mid, ft::LodDistance::Far}) {
      const ft::Camera cam = ft::lodCamera(setup.model, setup.fibers.params, d, 1.0f, setup.width, setup.height);
      setup.views.emplace_back(ft::lodDistanceName(d), ft::makeViewParams(cam, 1.0f, true, true));
    }

    setup.gl = ft::GlContext::create(ft::glBackendFromEnv());
    const ft::GlInfo& gi = setup.gl->info();
    setup.gpu = std::make_unique<ft::FiberGpu>(gi);
    setup.gpu->setModel(setup.buffers, setup.fibers.table);
    setup.renderer = std::make_unique<ft::FiberRenderer>(gi);
    setup.renderer->setTwoPassCull(true);  // as `render` draws (its default)
    {
      ft::ShadingBakeGpu bake(gi);
      setup.inputs = bake.bake({shading, &setup.fibers.fit.preset, appearance, &setup.fibers.params, &setup.fibers.table});
      if (softAppearance.shadowMap)
        setup.softInputs = bake.bake({shading, &setup.fibers.fit.preset, softAppearance, &setup.fibers.params, &setup.fibers.table});
    }
    setup.renderer->setShading(setup.inputs);
    setup.timer = std::make_unique<ft::GpuTimer>(gi);
    setup.appearance = appearance;

    benchmark::AddCustomContext("gl_renderer", gi.renderer);
    benchmark::AddCustomContext("frame_renderer",
                                "FiberRenderer: deferred shading, occlusion culling per view (Auto), two-pass culling from the "
                                "previous frame's lines when it drew the same model (on; OnePass: off) unless the name says");
    benchmark::AddCustomContext("load_average_at_start", fmt::format("{:.2f}", loadAverage()));
    benchmark::AddCustomContext("gpu_timing_method", setup.timer->method());
    benchmark::AddCustomContext("model", modelPath);
    benchmark::AddCustomContext("segments", std::to_string(setup.buffers.segments.size()));
    benchmark::AddCustomContext("yarn", yarn);
    benchmark::AddCustomContext("fabric", fabric);
    benchmark::AddCustomContext("self_shadow", appearance.selfShadow ? "on (000 §4.1, 128x128x16)" : "off");
    benchmark::AddCustomContext("ao", fmt::format("{} (000 §4.2, 128x128, GPU marched bake)", ft::aoModeName(appearance.ao)));
    benchmark::AddCustomContext("shadow_map", appearance.shadowMap ? fmt::format("on (000 §4.1, {0}x{0} per light, {1})", appearance.shadowMapSize, appearance.shadowMapFilter == FT_SHADOW_FILTER_PCF ? "2x2 PCF" : "nearest texel") : "off");
    benchmark::AddCustomContext("viewport", fmt::format("{}x{}, 4x MSAA, RGBA32F", setup.width, setup.height));
    // 000 Table 1 (Wu & Yuksel 2019, GTX 1080, 1280×960), ms as close / worst / full view:
    // not comparable hardware, context only.
    benchmark::AddCustomContext("paper_000_table1_glove_simple_ms", "9 / 19 / 9");
    benchmark::AddCustomContext("paper_000_table1_glove_pbs_ms", "13 / 37 / 14");
    benchmark::AddCustomContext("paper_000_table1_gpu", "NVIDIA GTX 1080, 148K control points, 8.3M fiber curves");
    // 001 Table 1 (Huang et al. 2025, RTX 3090): rendering ms with / without the
    // 16-SRBF environment light; Cable is the one model timed both ways.
    benchmark::AddCustomContext("env_map", setup.envPath + " (16 SRBFs + DC, I_M table 16x16x8x8, GPU bakes)");
    benchmark::AddCustomContext("paper_001_table1_cable_ms", "9.4 without env (118M fiber seg.) / 20.6 with env (96M)");
    benchmark::AddCustomContext("paper_001_table1_with_env_ms",
                                "Flame 23.6 (29M seg.), Photograph 31.1 (150M), Ribbing 15.7 (6.5M), Montague 16.5 (7.3M)");
    benchmark::AddCustomContext("paper_001_table1_without_env_ms", "Glove 3.0 (60M seg.), Relaxation 22.8 (180M)");
    benchmark::AddCustomContext("paper_001_table1_gpu", "NVIDIA RTX 3090, 1920x1280 (first six) / 1300x1300");

    for (const auto& [name, view] : setup.views) {
      benchmark::RegisterBenchmark(fmt::format("BM_ShadedCompute/{}", name).c_str(), BM_Shaded,
                                   ft::FiberPath::Compute, &view)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
      benchmark::RegisterBenchmark(fmt::format("BM_ShadedTessellation/{}", name).c_str(), BM_Shaded,
                                   ft::FiberPath::Tessellation, &view)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
      benchmark::RegisterBenchmark(fmt::format("BM_PreviewCompute/{}", name).c_str(), BM_Preview, &view)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
    }
    for (size_t i = 0; i < setup.namedViews.size(); ++i) {
      const std::string& name = setup.namedViews[i].first;
      using Cull = ft::FiberRenderer::OcclusionCull;
      // as render draws it (a frame after another of the same view: two-pass),
      // one pass (the occluder pass as the view chooses), always the occluder
      // pass, never culled (all deferred), culled forward
      for (int variant : {0, 4, 3, 1, 2})
        benchmark::RegisterBenchmark(
            fmt::format("BM_ShadedCompute{}/{}",
                        variant == 0   ? ""
                        : variant == 1 ? "NoCull"
                        : variant == 2 ? "Forward"
                        : variant == 3 ? "Cull"
                                       : "OnePass",
                        name)
                .c_str(),
            BM_NamedFrame, &setup.namedViewParams[i],
            variant == 0 || variant == 4 ? Cull::Auto : variant == 1 ? Cull::Off : Cull::On, variant != 2,
            variant == 0)
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime();
      benchmark::RegisterBenchmark(fmt::format("BM_ShadedComputeOrbit/{}", name).c_str(), BM_OrbitFrame,
                                   &setup.namedViews[i].second)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
      benchmark::RegisterBenchmark(fmt::format("BM_Trace16/{}", name).c_str(), BM_Trace16, &setup.namedViews[i].second)
          ->Unit(benchmark::kMillisecond)
          ->UseManualTime();
      for (ft::FiberPath path : {ft::FiberPath::Compute, ft::FiberPath::Tessellation})
        benchmark::RegisterBenchmark(
            fmt::format("BM_Shaded{}Env/{}", path == ft::FiberPath::Compute ? "Compute" : "Tessellation", name).c_str(),
            BM_EnvFrame, path, &setup.namedViewParams[i])
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime();
    }
    if (appearance.shadowMap)
      benchmark::RegisterBenchmark("BM_ShadowPass", BM_ShadowPass)->Unit(benchmark::kMillisecond)->UseManualTime();
    if (appearance.shadowMap)
      for (size_t i = 0; i < setup.namedViews.size(); ++i)
        benchmark::RegisterBenchmark(fmt::format("BM_ShadedComputeSoft/{}", setup.namedViews[i].first).c_str(), BM_SoftFrame,
                                     &setup.namedViewParams[i])
            ->Unit(benchmark::kMillisecond)
            ->UseManualTime();
    benchmark::RegisterBenchmark("BM_LobeShadowPass", BM_LobeShadowPass)->Unit(benchmark::kMillisecond)->UseManualTime();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  } catch (const ft::InputError& e) {
    std::cerr << "ft_shading_bench: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ft_shading_bench: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
