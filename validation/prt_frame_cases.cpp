// prt_frame_cases.cpp — prt/frame/*: the fabric PRT frame of Khungurn et al.
// 2017 (004 §5) against the Embree path tracer with the same tiled exemplar,
// fibers, BCSDF, eye rays and lights (reference/prt_frame.h;
// docs/prt-frame.md), as 004 Fig. 13 judges it: the error of each image's
// average intensity over a sweep of configurations (view, light direction,
// directional and SG lights), and the images' FLIP and RMSE.
// The truth shares no PRT code: path tracing through the capsules, not the
// volume, the SSDF, the sums of SGs, SH or the IIRTF. prt/frame/gpu: the GPU
// frame and the twin (gpu/prt_frame_gpu.h) against the CPU frame (agreement only).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "gpu/exemplar_volume_gpu.h"
#include "gpu/prt_frame_gpu.h"
#include "gpu/prt_multiple_scattering_gpu.h"
#include "gpu/prt_single_scattering_gpu.h"
#include "reference/prt_frame.h"
#include "scene/fabric.h"
#include "validation/case_support.h"
#include "validation/harness.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

// CI sizes (the whole case ≤ ~3 s on 2 cores): a block of 20 fibers per ply
// (2,560 segments), 3 × 3 tiles, 24² images, 16² visibility images, 600 IIRTF
// paths per cell, 32 path-traced samples per pixel (16 for the direct light
// alone, whose noise is a few per cent).
PrtFrameSettings ciSettings() {
  PrtFrameSettings s;
  s.exemplar.fibersPerPly = 20;
  s.tiles = 3;
  s.width = s.height = 24;
  s.svfSize = 16;
  s.pathsPerCell = 600;
  s.ellPaths = 200;
  s.msThetaINodes = 512;
  s.msPhiNodes = 128;
  s.ptSamples = 32;
  return s;
}

// Tolerances (measured on the CI settings above, docs/prt-frame.md), with the
// G-buffer's default capsule ids (docs/exemplar-volume.md "Ids"). With 004
// §5.1's midpoint ids the frame was 8–99 % too bright (coverage +39 %, single
// +10 … +33 % per pixel) and the darker bands were 0 and 0.05; the capsule ids
// cover exactly the capsules' pixels and shade the fiber the eye sees, which
// leaves the shading's own biases in both directions (single −13 … +8 %,
// multiple −35 … +36 % per pixel), so the darker bands now hold those and the
// brighter bands are tightened to them.
constexpr double kDarker = 0.2, kBrighter = 0.3, kSingleDarker = 0.2, kSingleBrighter = 0.25, kMulti = 1.0;
constexpr const char* kDarkerWhy =
    "max over configurations of (PT − PRT)/PT − 3σ (σ: the path-traced average's standard error): measured 0.099 "
    "(ω_o (−0.6, 0.1, 0.8), directional: multiple −35 %, single −13 % per pixel; −0.35 with the midpoint ids, whose "
    "extra coverage hid it); 0.2 fails a frame that loses a part (multiple scattering is ~2/3 of the light)";
constexpr const char* kBrighterWhy =
    "max of (PRT − PT)/PT − 3σ: measured 0.03 (0.78 with the midpoint ids: coverage × per-pixel excess); 0.3 holds "
    "the multiple scattering's known excess (+36 % per pixel on one configuration) and fails gross errors (a lost "
    "1/M, a flipped lobe: ×10–100)";
constexpr const char* kSingleDarkerWhy =
    "max of −(PRT single / path-traced direct − 1), per covered pixel: measured 0.13 (the SSDF at 16² and the "
    "segment's straight tangent against next-event estimation at the true hit; −10 % at README size, and the same "
    "with Embree's own first hits); 0.2 adds the direct pass's noise (16 spp, ≤ 3 %): a visibility read at the wrong "
    "direction shows as darker";
constexpr const char* kSingleBrighterWhy =
    "max of PRT single / path-traced direct − 1, per covered pixel: measured 0.079 (0.33 with the midpoint ids: the "
    "midpoint's segment is often not the one seen); 0.25 is that with margin";
constexpr const char* kMultiWhy =
    "max of |PRT multiple / path-traced indirect − 1| − 3σ, per covered pixel: measured 0.18 here, and +0.86 on "
    "(ω_o (−0.6, 0.1, 0.8), λ = 30) at 400 spp (IIRTF cells of 600 paths, SH L = 4, cell average at μ_k: "
    "docs/prt-multiple-scattering.md); 1.0 covers the known bias and fails a wrong frame (×20 for a flipped ω_o)";

constexpr double kGpuTolerance = 1e-4;
constexpr const char* kGpuWhy =
    "max over pixels with equal ids and channels of |GPU − CPU| / the CPU frame's peak: float tables (GPU-baked 𝒢, "
    "C_S, C_G) and arithmetic against double; measured 2.3e-6 (the evaluators' own cross-checks hold 1e-4 relative)";

struct Config {
  glm::vec3 wo, light;
  float lambda;
};
// 004 Fig. 13 sweeps light and view: two views (near-normal, 37° off), two
// light directions, directional and SG lights (λ = 30: sums of SGs; λ = 150:
// the blend of the two branches; 004 §5.2.2).
std::vector<Config> sweep() {
  const glm::vec3 v0 = glm::normalize(glm::vec3(0.3f, -0.2f, 0.93f)), v1 = glm::normalize(glm::vec3(-0.6f, 0.1f, 0.8f));
  const glm::vec3 l0 = glm::normalize(glm::vec3(0.5f, 0.3f, 0.81f)), l1 = glm::normalize(glm::vec3(-0.2f, -0.7f, 0.68f));
  return {{v0, l0, 0.0f}, {v0, l1, 150.0f}, {v1, l0, 30.0f}, {v1, l1, 0.0f}, {v0, l0, 30.0f}, {v1, l1, 150.0f}};
}

CaseResult runPathTracedCase(ValidationContext&, const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "prt-frame";
  r.path = "prtframe";
  const auto t0 = Clock::now();
  PrtFrameScene scene(ciSettings());
  const PrtFrameSettings& s = scene.settings();
  double sumSq = 0.0, darker = -1e30, brighter = -1e30, single = -1e30, singleDarker = -1e30, multi = -1e30;
  double sigmaMax = 0.0, coverage = 0.0, flipMax = 0.0;
  double prtSeconds = 0.0, ptSeconds = 0.0;
  uint64_t nonFinite = 0;
  std::string details;
  const std::vector<Config> configs = sweep();
  for (const Config& c : configs) {
    const PrtFrameView v{c.wo, c.light, c.lambda};
    const PrtFrameParts prt = scene.renderPrt(v);
    const PrtFrameImage pt = scene.renderPathTraced(v, s.ptSamples, s.maxDepth);
    const PrtFrameImage direct = scene.renderPathTraced(v, 16, 1);  // next-event estimation at the first hit only
    const PrtFrameComparison cmp = comparePrtFrame(prt.total, pt);
    nonFinite += cmp.nonFinite + comparePrtFrame(prt.single, direct, false).nonFinite +
                 comparePrtFrame(prt.multi, pt, false).nonFinite;
    // 004 Fig. 13: the image's average intensity, relative to the path tracer's.
    const double e = (cmp.averagePrt - cmp.averageReference) / cmp.averageReference;
    const double sigma = pt.averageStdError / pt.average();  // the truth's relative standard error
    const double sigmaIndirect = std::hypot(pt.averageStdError, direct.averageStdError) / (pt.average() - direct.average());
    // Per covered pixel (the midpoint ids' conservative fill covers more pixels than the capsules:
    // docs/exemplar-volume.md), single vs direct and multiple vs indirect.
    const double es = prt.single.coveredAverage() / direct.coveredAverage() - 1.0;
    const double indirect = pt.coveredAverage() - direct.coveredAverage();
    const double em = prt.multi.coveredAverage() / indirect - 1.0;
    const double cov = double(prt.total.covered) / double(std::max<uint64_t>(1, pt.covered)) - 1.0;
    sumSq += e * e;
    darker = maxKeepNaN(darker, -e - 3.0 * sigma);
    brighter = maxKeepNaN(brighter, e - 3.0 * sigma);
    singleDarker = maxKeepNaN(singleDarker, -es);
    single = maxKeepNaN(single, es);
    multi = maxKeepNaN(multi, std::abs(em) - 3.0 * sigmaIndirect);
    sigmaMax = maxKeepNaN(sigmaMax, sigma);
    coverage = maxKeepNaN(coverage, cov);
    flipMax = maxKeepNaN(flipMax, cmp.flipMean);
    prtSeconds += prt.total.seconds;
    ptSeconds += pt.seconds;
    details += fmt::format("ω_o ({:.2f},{:.2f},{:.2f}) light ({:.2f},{:.2f},{:.2f}) λ={:g}: avg PRT {:.4g} PT {:.4g} ± {:.2g} ({:+.3f}); "
                           "per covered px single {:.4g} vs direct {:.4g} ({:+.3f}), multiple {:.4g} vs indirect {:.4g} "
                           "({:+.3f}); covered {} vs {}; FLIP {:.3f}\n",
                           c.wo.x, c.wo.y, c.wo.z, c.light.x, c.light.y, c.light.z, c.lambda, cmp.averagePrt,
                           cmp.averageReference, pt.averageStdError, e, prt.single.coveredAverage(), direct.coveredAverage(), es,
                           prt.multi.coveredAverage(), indirect, em, prt.total.covered, pt.covered, cmp.flipMean);
  }
  const double rmse = std::sqrt(sumSq / double(configs.size()));
  r.cpuMilliseconds = msSince(t0);
  r.details = fmt::format("{}; ℓ = {:.4g}, {} cells, bakes {:.2f} s; {} configurations, {}² pixels, {} spp:\n{}",
                          scene.block().label, scene.meanFreePath(), scene.cellCount(), scene.bakeSeconds(),
                          configs.size(), s.width, s.ptSamples, details);
  r.metrics = {
      Metric{"average.rmse_rel", rmse, 1e9, "relative",
             "004 Fig. 13's figure: RMSE over the configurations of the relative error of the image's average intensity",
             false},
      Metric{"average.darker_max", darker, kDarker, "relative", kDarkerWhy},
      Metric{"average.brighter_max", brighter, kBrighter, "relative", kBrighterWhy},
      Metric{"single.darker_max", singleDarker, kSingleDarker, "relative", kSingleDarkerWhy},
      Metric{"single.brighter_max", single, kSingleBrighter, "relative", kSingleBrighterWhy},
      Metric{"multi.max_rel", multi, kMulti, "relative", kMultiWhy},
      Metric{"truth.sigma_rel_max", sigmaMax, 1e9, "relative",
             "the path-traced average's standard error (per-pixel sample variances), worst configuration", false},
      Metric{"coverage.excess_max", coverage, 1e9, "relative",
             "pixels the G-buffer covers beyond the capsules' (informational: 0 with the capsule ids, +39 % with the "
             "midpoint ids)",
             false},
      Metric{"flip.max_mean", flipMax, 1e9, "", "HDR-FLIP mean (image/flip.h), worst configuration", false},
      Metric{"time.ratio", ptSeconds / std::max(1e-9, prtSeconds), 1e18, "×",
             fmt::format("path-traced ({} spp) / PRT frame time, bakes excluded (004: 2–9× on CPU)", s.ptSamples), false},
      nonFiniteMetric("cpu", nonFinite, "PRT and path-traced pixels"),
  };
  r.finish();
  return r;
}

// ---- prt/frame/gpu -----------------------------------------------------------------
// The GPU frame (PrtFrameRendererGpu): the GPU volume's G-buffer left on the GPU → c_T per cell,
// L^single and L̃^multi per segment, the composition per pixel (prt_frame_gpu.comp.glsl, one
// read-back), and the twin of the arithmetic (PrtFrameGpu: prt_frame.comp.glsl's requests read
// back, the GPU single- and multiple-scattering evaluators, the GPU composition), both from the
// evaluators' own GPU-baked 𝒢, C_S and C_G tables (float), against the CPU frame (double) on the
// pixels whose ids agree. Agreement only: the path tracer above is the truth.
CaseResult runGpuCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "prt-frame";
  r.path = "prtframe";
  const auto t0 = Clock::now();
  PrtFrameSettings settings = ciSettings();
  PrtFrameScene scene(settings);
  const Config configs[] = {sweep()[0], sweep()[1], sweep()[2]};  // directional, SG λ = 150 (blend), SG λ = 30
  double cpuMs = 0.0, twinMs = 0.0, frameMs = 0.0;
  double maxRel = 0.0, maxSingle = 0.0, maxMulti = 0.0, twinRel = 0.0;
  uint64_t compared = 0, idsDiffer = 0, nonFinite = 0, coverage = 0;
  // Once per run: the tables (GPU bakes) and the volume (the block does not change between views).
  const auto b0 = Clock::now();
  const FabricParams fabric = findFabricPreset(settings.fabric).params();
  PrtSingleScatteringGpu& ssGpu = ctx.gpu<PrtSingleScatteringGpu>();
  const std::vector<float> table = ssGpu.bakeTable(std::span<const FabricParams>(&fabric, 1));
  PrtMultipleScatteringGpu& msGpu = ctx.gpu<PrtMultipleScatteringGpu>();
  const PrtMsGpuTables tables = msGpu.tables(fabric, settings.msThetaINodes, settings.msPhiNodes);
  const double bakeMs = msSince(b0);
  ExemplarVolumeGpu& vol = ctx.gpu<ExemplarVolumeGpu>();
  PrtFrameRendererGpu& renderer = ctx.gpu<PrtFrameRendererGpu>();
  bool built = false;
  for (const Config& c : configs) {
    const PrtFrameView v{c.wo, c.light, c.lambda};
    const PrtFrameParts cpu = scene.renderPrt(v);  // bakes what the view hits first (outside the timing)
    cpuMs += cpu.total.seconds * 1e3;
    const PrtFrameData d = scene.gpuData();
    const VolParams rays = scene.rays(v);
    if (!built) vol.build(d.layout, d.segments, d.candidates.start, d.candidates.entries), built = true;
    const PrtFrameGpuInputs in = prtFrameGpuInputs(d, rays, table, tables, settings.bands, glm::vec4(v.light, v.lambda));
    const auto g0 = Clock::now();
    const std::vector<VolHit> gbuffer = vol.sample(rays);  // the ids both GPU paths see (the twin's input)
    const std::vector<PrtFramePixel> twin = ctx.gpu<PrtFrameGpu>().render(in, gbuffer, ssGpu, msGpu);
    twinMs += msSince(g0);
    renderer.upload(in);  // the bakes of this view changed the data (a viewer uploads once)
    const auto f0 = Clock::now();
    const PrtFrameGpuImage frame = renderer.render(vol, rays, glm::vec4(v.light, v.lambda), true);
    frameMs += msSince(f0);
    // Per pixel with the same id on both sides: |GPU − CPU| relative to the CPU frame's brightest
    // pixel (float tables and arithmetic against double; relative to each pixel would let
    // dark pixels' rounding dominate).
    double peak = 0.0;
    for (const glm::vec3& p : cpu.total.rgb) peak = std::max({peak, double(p.x), double(p.y), double(p.z)});
    for (size_t i = 0; i < gbuffer.size(); ++i) {
      for (int ch = 0; ch < 4; ++ch)
        nonFinite += uint64_t(!std::isfinite(frame.total[i][ch])) + uint64_t(ch < 3 && !std::isfinite(twin[i].total[ch]));
      coverage += uint64_t((frame.total[i].w > 0.5f) != (gbuffer[i].id != 0));
      if (gbuffer[i].id != cpu.ids[i]) {
        ++idsDiffer;
        continue;
      }
      if (gbuffer[i].id == 0) continue;
      ++compared;
      for (int ch = 0; ch < 3; ++ch) {
        maxRel = maxKeepNaN(maxRel, std::abs(double(frame.total[i][ch]) - cpu.total.rgb[i][ch]) / peak);
        maxSingle = maxKeepNaN(maxSingle, std::abs(double(frame.single[i][ch]) - cpu.single.rgb[i][ch]) / peak);
        maxMulti = maxKeepNaN(maxMulti, std::abs(double(frame.multi[i][ch]) - cpu.multi.rgb[i][ch]) / peak);
        twinRel = maxKeepNaN(twinRel, std::abs(double(twin[i].total[ch]) - cpu.total.rgb[i][ch]) / peak);
      }
    }
  }
  r.cpuMilliseconds = cpuMs;
  r.gpuMilliseconds = frameMs;
  r.gpuTiming = "wall clock of the GPU frame: volume sample, three passes, the image's read-back (data uploaded, tables baked)";
  r.details = fmt::format("{} pixels compared over {} configurations; {} G-buffer ids differ (float ties); GPU frame "
                          "max |Δ|/peak: total {:.3g}, single {:.3g}, multiple {:.3g}; twin {:.3g}; CPU frames {:.0f} ms, "
                          "GPU frames {:.0f} ms, twin {:.0f} ms; GPU table bakes {:.0f} ms; {:.0f} ms in all",
                          compared, std::size(configs), idsDiffer, maxRel, maxSingle, maxMulti, twinRel, cpuMs, frameMs,
                          twinMs, bakeMs, msSince(t0));
  r.metrics = {
      Metric{"radiance.max_rel", maxRel, kGpuTolerance, "of the peak", kGpuWhy},
      Metric{"twin.max_rel", twinRel, kGpuTolerance, "of the peak",
             "the same for the twin of the arithmetic (PrtFrameGpu: requests read back, the evaluators); same reason"},
      Metric{"coverage.differing", double(coverage), 0.0, "pixels",
             "pixels the GPU frame marks covered (w) against the G-buffer's ids: the same buffer, none may differ"},
      Metric{"ids.differing", double(idsDiffer), 1e9, "pixels",
             "G-buffer ids that differ between the CPU and GPU volumes (float ties: of the nearest midpoint, or of two capsule entries)", false},
      Metric{"pixels.compared", double(compared), 1e9, "pixels", "covered pixels with equal ids", false},
      nonFiniteMetric("gpu", nonFinite, "GPU frame and twin pixels"),
  };
  r.finish();
  return r;
}

}  // namespace

void addPrtFrameCases(ValidationContext&, std::vector<ValidationCase>& out) {
  out.push_back({"prt/frame/gpu", [](ValidationContext& c) { return runGpuCase(c, "prt/frame/gpu"); }});
  out.push_back({"prt/frame/path-traced", [](ValidationContext& c) { return runPathTracedCase(c, "prt/frame/path-traced"); }});
}

}  // namespace ft
