// pcss_cases.cpp — soft yarn shadows by PCSS (001 §4.5 eq. 17, Fernando
// 2005; common/pcss.h, docs/soft-shadows.md):
//
//  pcss/lobe-cone  the lobe → cone mapping: the cap of half-angle α(λ) holds
//                  FT_PCSS_SG_ENERGY_FRACTION of G's energy, by a quadrature
//                  of e^{λ(cos θ − 1)} written here (no common/ code but α);
//  pcss/tube       closed form: straight yarns (tubes of radius W) at heights
//                  h over a plane, a cone light of radius α straight above.
//                  The visibility of the cone through an infinite cylinder
//                  (blocked where the ray's distance to the axis is < W) is
//                  integrated here over the cap; its penumbra spans 2h·tan α
//                  on each side (checked against the closed form), and the
//                  GPU's and the CPU's PCSS profiles are compared with it;
//  pcss/embree     the built-in scene: T̃ of two cone lights and four SRBF
//                  lobes (their maps) at points inside the tubes against
//                  Embree shadow rays through the tubes of radius W
//                  (reference/pcss_reference.h), and CPU vs GPU;
//  pcss/frame/<path> the shaded frame: soft shadows with α = 0 equal the hard
//                  frame bit for bit; with α = 10° they differ, no NaN.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include "gpu/fiber_renderer.h"
#include "gpu/shading_inputs_gpu.h"
#include "reference/pcss_reference.h"
#include "reference/shadow_map_reference.h"
#include "scene/camera.h"
#include "scene/default_scene.h"
#include "scene/lighting.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_preset.h"
#include "validation/case_support.h"
#include "validation/harness.h"
#include "validation/shadow_scene.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;


// The tube radius of notes §0.3 written out from the preset's fields.
double reachW(const YarnPreset& p) { return p.yarnRadius / 2.0 + std::max(p.ellipseLong, p.ellipseShort) * p.rMax; }

size_t countNonFinite(const std::vector<float>& v) {
  size_t n = 0;
  for (float x : v) n += std::isfinite(x) ? 0 : 1;
  return n;
}

// The shadow maps of `buffers` under up to four lights, each a cone of
// angular radius alphas[i], drawn by the renderer (left bound for lookups).
FiberRenderer& drawLightMaps(ValidationContext& ctx, const YarnBuffers& buffers, const FiberSetup& setup,
                             const YarnPreset& preset, const std::vector<glm::vec3>& toLights,
                             const std::vector<double>& alphas, uint32_t size) {
  Lighting lighting;
  lighting.lights.clear();
  for (glm::vec3 l : toLights) lighting.lights.push_back(DirectionalLight{l, glm::vec3(1.0f)});
  AppearanceOptions appearance = AppearanceOptions::none();
  appearance.shadowMap = true;
  appearance.shadowMapSize = size;
  appearance.softShadows = true;
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  gpu.setModel(buffers, setup.table);
  FiberRenderer& renderer = ctx.gpu<FiberRenderer>();
  ShadingInputs inputs = ctx.gpu<ShadingBakeGpu>().bake({makeShadingParams(lighting), &preset, appearance});
  for (size_t i = 0; i < alphas.size() && i < 4; ++i) inputs.lightTanAlpha[int(i)] = float(std::tan(alphas[i]));
  renderer.setShading(inputs);
  renderer.drawShadowMap(gpu);
  return renderer;
}

std::vector<glm::vec4> requests(const std::vector<glm::vec3>& points, int index) {
  std::vector<glm::vec4> r;
  r.reserve(points.size());
  for (const glm::vec3& p : points) r.emplace_back(p, float(index));
  return r;
}

// CPU vs GPU: the same formulas on the same map; a texel decided differently
// (trig rounding of a sample offset at a texel edge, GLSL does not bound it)
// moves T̃ by 1/FT_PCSS_SAMPLES. Tolerance: such steps on ≤ 1 % of the points.
struct Cross {
  size_t compared = 0, differing = 0;
  double maxAbs = 0.0;
  void add(const std::vector<float>& cpu, const std::vector<float>& gpu) {
    for (size_t k = 0; k < cpu.size(); ++k) {
      const double d = std::abs(double(cpu[k]) - double(gpu[k]));
      ++compared;
      differing += d > 1e-6 ? 1 : 0;
      maxAbs = std::isnan(d) ? d : std::max(maxAbs, d);
    }
  }
  void metrics(std::vector<Metric>& m) const {
    m.push_back(Metric{"cross.differing_fraction", compared ? double(differing) / double(compared) : 1.0, 0.01,
                       "fraction", "CPU vs GPU PCSS on one map: a sample at a texel edge may fall either way"});
    m.push_back(Metric{"cross.max_abs", maxAbs, 2.0 / FT_PCSS_SAMPLES + 1e-6, "T̃",
                       "CPU vs GPU: at most two of the 16 PCF samples decided differently"});
  }
};

// ---- pcss/lobe-cone ----
// Share of ∫G dω inside the cap of half-angle α: ∫_0^α e^{λ(cos θ − 1)} sin θ dθ
// over the same from 0 to π, by composite Simpson in θ (20,000 intervals,
// error ≪ 1e-6 for λ ≤ 512: the integrand's width is ≥ 1/√512 = 0.044 rad).
double capShare(double lambda, double alpha) {
  auto integral = [&](double b) {
    const int n = 20000;
    const double h = b / n;
    double s = 0.0;
    for (int k = 0; k <= n; ++k) {
      const double t = k * h;
      const double f = std::exp(lambda * (std::cos(t) - 1.0)) * std::sin(t);
      s += f * (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0));
    }
    return s * h / 3.0;
  };
  return integral(alpha) / integral(kPi);
}

CaseResult runLobeCone(ValidationContext&) {
  CaseResult r;
  r.name = "pcss/lobe-cone";
  r.group = "pcss";
  r.path = "pcss";
  const auto t0 = Clock::now();
  double worst = 0.0;
  size_t nonFinite = 0;
  std::string details;
  for (double lambda : {2.5, 4.0, 8.0, 32.0, 128.0, 512.0}) {
    const double alpha = ftPcssLobeAngle(float(lambda));
    nonFinite += std::isfinite(alpha) ? 0 : 1;
    const double share = capShare(lambda, alpha);
    worst = std::max(worst, std::abs(share - 0.8244));
    details += fmt::format("λ {}: α {:.3f}° holds {:.5f}; ", lambda, alpha * 180.0 / kPi, share);
  }
  // Broad lobes: α clamped to 80° (FT_PCSS_MAX_ANGLE), the cap then holds less.
  const double broad = ftPcssLobeAngle(1.0f);
  const double clampError = std::abs(broad - 80.0 * kPi / 180.0);
  r.cpuMilliseconds = msSince(t0);
  r.metrics = {
      Metric{"nonfinite.cpu", double(nonFinite), 0.0, "count", "NaN/Inf are failures"},
      Metric{"share.max_abs", worst, 1e-3, "fraction",
             "the cone of α(λ) holds 82.44 % of the SG's energy (docs/soft-shadows.md); float log/asin ≈ 1e-6, Simpson ≪ 1e-6"},
      Metric{"broad.clamp_error", clampError, 1e-5, "rad", "λ = 1 wants α > 80°: clamped to 80° (tan α finite)"},
  };
  r.details = details + fmt::format("λ 1: α {:.3f}°", broad * 180.0 / kPi);
  r.finish();
  return r;
}

// ---- pcss/tube ----
// Visibility of a cone of half-angle α around +z, uniform in solid angle, from
// (x, ·, 0) through an infinite cylinder of radius R along y at height h:
// a ray (d_x, d_y, d_z) misses when its distance to the axis, |x d_z + h d_x| /
// √(d_x² + d_z²) (the distance in the x-z projection), is ≥ R. Midpoint rule
// over (cos θ, φ), 300 × 360 cells: error ≤ ~1/300 near the edges.
double cylinderConeVisibility(double x, double h, double radius, double alpha) {
  const int nu = 300, nphi = 360;
  const double c0 = std::cos(alpha);
  size_t lit = 0;
  for (int i = 0; i < nu; ++i) {
    const double c = 1.0 - (i + 0.5) / nu * (1.0 - c0), s = std::sqrt(1.0 - c * c);
    for (int j = 0; j < nphi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / nphi;
      const double dx = s * std::cos(phi), dz = c;
      lit += std::abs(x * dz + h * dx) / std::sqrt(dx * dx + dz * dz) >= radius ? 1 : 0;
    }
  }
  return double(lit) / double(nu * nphi);
}

YarnCurve straightCurve(glm::dvec3 from, glm::dvec3 to, int pieces) {
  YarnCurve c;
  for (int i = 0; i <= pieces; ++i) c.points.push_back(glm::vec3(from + (to - from) * (double(i) / pieces)));
  return c;
}

struct Cotton {
  YarnPreset preset;
  FiberSetup setup;
  double w = 0.0;
};
const Cotton& cotton(ValidationContext& ctx) {
  return ctx.cached(CacheKey<Cotton>{"pcss/cotton1"}, [&] {
    Cotton c;
    c.preset = findYarnPreset("cotton1");
    FiberOptions fo;
    fo.seed = ctx.options().fiber.seed;
    c.setup = makeFiberSetup(c.preset, fo);
    c.w = reachW(c.preset);
    return c;
  });
}

// Two yarns along y, at x = ∓15W and heights 4W and 8W, over the plane z = 0;
// two lights straight down with α = 10° and 20°. Receivers: lines across each
// yarn at z = 0, 16 rows in y (the pattern's rotation differs per texel: the
// profile is the mean over the rows), step W/16.
// Tolerances: the map stores the tube's far side plus bias, so PCSS takes the
// blocker ~W nearer to the receiver than its centre and the penumbra comes out
// narrower by ~W/h (25 % at h = 4W); a PCF of 16 samples quantises T̃ in 1/16.
// Mean |error| over the shadow's extent ≤ 0.08, the shadow's spread (std. dev.
// of x under 1 − T̃) within 25 % of the closed form's (measured figures:
// docs/soft-shadows.md).
CaseResult runTube(ValidationContext& ctx) {
  CaseResult r;
  r.name = "pcss/tube";
  r.group = "pcss";
  r.path = "pcss";
  const Cotton& c = cotton(ctx);
  const double w = c.w;
  const double heights[2] = {4.0 * w, 8.0 * w}, xs[2] = {-15.0 * w, 15.0 * w};
  YarnModel m;
  m.name = "yarns over a plane";
  for (int k = 0; k < 2; ++k) m.curves.push_back(straightCurve({xs[k], -20.0 * w, heights[k]}, {xs[k], 20.0 * w, heights[k]}, 40));
  const YarnBuffers yarn = buildYarnBuffers(m);
  const std::vector<double> alphas = {10.0 * kPi / 180.0, 20.0 * kPi / 180.0};
  const auto t0 = Clock::now();
  FiberRenderer& renderer = drawLightMaps(ctx, yarn, c.setup, c.preset, {glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)}, alphas,
                                          FT_SHADOW_MAP_CI_SIZE);
  const ShadowMapParams sm = renderer.shadowMapParams();
  const PcssParams pc = renderer.pcssParams();
  const std::vector<float> texels = renderer.readShadowMap();
  size_t nonFiniteGpu = countNonFinite(texels), nonFiniteCpu = 0;
  const int rows = 16;
  const double step = w / 16.0;
  double worstMean = 0.0, worstWidth = 0.0, worstMax = 0.0, worstOracle = 0.0;
  Cross cross;
  std::string details;
  double gpuMs = msSince(t0), cpuMs = 0.0;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 2; ++i) {
      const double h = heights[k], a = alphas[size_t(i)];
      const double xOut = h * std::tan(a) + w / std::cos(a);  // the closed form's outer edge
      const int half = int(std::ceil((xOut + 2.0 * w) / step));
      std::vector<glm::vec3> points;
      for (int row = 0; row < rows; ++row)
        for (int s = -half; s <= half; ++s)
          points.push_back(glm::vec3(float(xs[k] + s * step), float((row - rows / 2) * 0.37 * w), 0.0f));
      const auto t1 = Clock::now();
      const std::vector<float> gpu = renderer.pcssLookup(requests(points, i), false);
      gpuMs += msSince(t1);
      const auto t2 = Clock::now();
      const std::vector<float> cpu = pcssLightLookup(sm, pc, texels, i, points);
      nonFiniteGpu += countNonFinite(gpu);
      nonFiniteCpu += countNonFinite(cpu);
      cross.add(cpu, gpu);
      // Mean profile over the rows; the closed form at each x.
      const int nx = 2 * half + 1;
      std::vector<double> profile(static_cast<size_t>(nx), 0.0), truth(static_cast<size_t>(nx), 0.0);
      for (int row = 0; row < rows; ++row)
        for (int s = 0; s < nx; ++s) profile[size_t(s)] += gpu[size_t(row * nx + s)] / double(rows);
      double sumAbs = 0.0, maxAbs = 0.0;
      double oracleEdge = 0.0;  // the closed form's outermost x with V < 1
      for (int s = 0; s < nx; ++s) {
        const double x = (s - half) * step;
        truth[size_t(s)] = cylinderConeVisibility(x, h, w, a);
        if (truth[size_t(s)] < 1.0) oracleEdge = std::max(oracleEdge, std::abs(x));
        const double e = std::abs(profile[size_t(s)] - truth[size_t(s)]);
        sumAbs += e;
        maxAbs = std::max(maxAbs, e);
      }
      cpuMs += msSince(t2);
      // The shadow's spread: the standard deviation of x under the weight
      // 1 − T̃ (the umbra's width and the penumbrae's 2h tan α both set it; no
      // threshold, so profiles without an umbra compare too).
      auto spread = [&](const std::vector<double>& v) {
        double w0 = 0.0, w1 = 0.0, w2 = 0.0;
        for (int s = 0; s < nx; ++s) {
          const double x = (s - half) * step, wt = 1.0 - v[size_t(s)];
          w0 += wt;
          w1 += wt * x;
          w2 += wt * x * x;
        }
        return w0 > 0.0 ? std::sqrt(std::max(w2 / w0 - (w1 / w0) * (w1 / w0), 0.0)) : 0.0;
      };
      const double spreadTruth = spread(truth), spreadPcss = spread(profile);
      const double widthError = std::abs(spreadPcss / spreadTruth - 1.0);
      const double mean = sumAbs / nx;
      worstMean = std::max(worstMean, std::isnan(mean) ? 1e30 : mean);
      worstWidth = std::max(worstWidth, std::isfinite(widthError) ? widthError : 1e30);
      worstMax = std::max(worstMax, maxAbs);
      // The closed form's penumbra: V < 1 out to h tan α + W / cos α (±1 step).
      worstOracle = std::max(worstOracle, std::abs(oracleEdge - xOut) / step);
      details += fmt::format("h {:.0f}W α {:.0f}°: mean |ΔT̃| {:.4f}, max {:.3f}, spread {:.4g} vs {:.4g} (2h tan α {:.4g}); ",
                             h / w, a * 180.0 / kPi, mean, maxAbs, spreadPcss, spreadTruth, 2.0 * h * std::tan(a));
    }
  r.gpuMilliseconds = gpuMs;
  r.gpuTiming = "steady_clock: depth pass at 256², read-back, PCSS lookups";
  r.cpuMilliseconds = cpuMs;
  r.metrics = {
      Metric{"nonfinite.gpu", double(nonFiniteGpu), 0.0, "count", "NaN/Inf are failures"},
      Metric{"nonfinite.cpu", double(nonFiniteCpu), 0.0, "count", "NaN/Inf are failures"},
      Metric{"oracle.edge_error_steps", worstOracle, 1.0, "steps",
             "the quadrature's shadow ends at h tan α + W/cos α (closed form), within one W/16 step"},
      Metric{"profile.mean_abs", worstMean, 0.08, "T̃",
             "PCSS vs the closed-form cone visibility, mean over the shadow (far side as blocker, 16 samples)"},
      Metric{"spread.rel_error", worstWidth, 0.25, "fraction",
             "the shadow's spread (std. dev. of x under 1 − T̃) vs the closed form's; the far side as blocker shortens d by ≤ W"},
      Metric{"profile.max_abs", worstMax, 1.0, "T̃", "informational: worst single x", false},
  };
  cross.metrics(r.metrics);
  r.details = details + fmt::format("texel {:.4g}, W {:.4g}", sm.extent.z, w);
  r.finish();
  return r;
}

// ---- pcss/embree ----
// The built-in scene, cotton1 fitted: two cone lights (α = 5°, 15°) and an
// SRBF environment with four lobes (λ = 8, 32, 128, 512: α 37°, 19°, 9.5°,
// 4.7°) and twelve of zero weight (no maps: T̃ must be exactly 1). Points:
// uniform in balls of radius 0.95 W around the centre lines. Truth: 192
// Embree rays per point uniform over the cone (reference/pcss_reference.h; a
// stratified spiral: its error per point is far below PCSS's 1/16 steps).
// Tolerance: mean |T̃_PCSS − T̃_Embree| ≤ 0.12 per light or lobe (measured
// 0.023 at 5° … 0.096 at 38.5°: the error grows with the cone), and the mean
// signed error within ±0.06 (measured ≤ +0.04: no systematic bias). PCSS sees one
// depth per texel (a tube's far side: the blocker's depth ~W off, and what
// lies behind a nearer blocker is missed), averages blockers at different
// depths into one penumbra, and counts the receiver's own tube where its far
// side lies nearer the light in a neighbouring texel (the reference ignores
// the tube the point is in). The max error is reported, not gated.
CaseResult runEmbree(ValidationContext& ctx) {
  CaseResult r;
  r.name = "pcss/embree";
  r.group = "pcss";
  r.path = "pcss";
  const ShadowCaseScene& scene = shadowCaseScene(ctx);
  const FittedFibers& fitted = scene.fitted;
  const float w = float(reachW(fitted.fit.preset));
  const std::vector<glm::vec3> lights = {glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f)),
                                         glm::normalize(glm::vec3(-0.6f, 0.3f, 0.75f))};
  const std::vector<double> alphas = {5.0 * kPi / 180.0, 15.0 * kPi / 180.0};
  SrbfEnvironment env{};
  const glm::vec3 axes[4] = {glm::normalize(glm::vec3(0.2f, 0.3f, 0.9f)), glm::normalize(glm::vec3(-0.7f, 0.1f, 0.6f)),
                             glm::normalize(glm::vec3(0.5f, -0.6f, 0.6f)), glm::normalize(glm::vec3(0.1f, 0.9f, 0.4f))};
  const float lambdas[4] = {8.0f, 32.0f, 128.0f, 512.0f};
  for (int j = 0; j < FT_SRBF_LOBES; ++j) {
    const float z = 1.0f - (2.0f * j + 1.0f) / FT_SRBF_LOBES, s = std::sqrt(1.0f - z * z), phi = 2.39996323f * j;
    env.lobes[j].axisLambda = glm::vec4(s * std::cos(phi), s * std::sin(phi), z, 4.0f);
    env.lobes[j].weight = glm::vec4(0.0f);
  }
  const int lobeIds[4] = {1, 6, 9, 14};  // not the first ones: a layer differs from its lobe index
  for (int k = 0; k < 4; ++k) {
    env.lobes[lobeIds[k]].axisLambda = glm::vec4(axes[k], lambdas[k]);
    env.lobes[lobeIds[k]].weight = glm::vec4(1.0f);
  }
  const auto t0 = Clock::now();
  // The map must resolve the tubes (as shadowmap/embree): texel ≤ W/4.
  FiberRenderer* renderer = &drawLightMaps(ctx, scene.buffers, fitted, fitted.fit.preset, lights, alphas, FT_SHADOW_MAP_CI_SIZE);
  const uint32_t size = tubeResolvingMapSize(FT_SHADOW_MAP_CI_SIZE, renderer->shadowMapParams().extent.z, w);
  if (size != FT_SHADOW_MAP_CI_SIZE)
    renderer = &drawLightMaps(ctx, scene.buffers, fitted, fitted.fit.preset, lights, alphas, size);
  renderer->drawLobeShadowMaps(ctx.gpu<FiberGpu>(), env, size);
  const ShadowMapParams sm = renderer->shadowMapParams();
  const PcssParams pc = renderer->pcssParams();
  const std::vector<float> lightTexels = renderer->readShadowMap(), lobeTexels = renderer->readLobeShadowMaps();
  size_t nonFiniteGpu = countNonFinite(lightTexels) + countNonFinite(lobeTexels), nonFiniteCpu = 0;
  double gpuMs = msSince(t0);

  const ShadowTubes tubes = shadowTubes(scene.buffers, w);
  const ShadowMapReference reference(tubes);
  const std::vector<glm::vec3> points = pointsInTubes(tubes, w, 300, 77u);
  Cross cross;
  double cpuMs = 0.0, worstMean = 0.0, worstBias = 0.0, worstMax = 0.0, worstSg = 0.0;
  size_t partial = 0, unmappedNotOne = 0;
  std::string details;
  auto compare = [&](const std::string& what, const std::vector<float>& gpu, const std::vector<float>& cpu,
                     const std::vector<float>& truth, const std::vector<float>* sgTruth) {
    nonFiniteGpu += countNonFinite(gpu);
    nonFiniteCpu += countNonFinite(cpu) + countNonFinite(truth);
    cross.add(cpu, gpu);
    double sum = 0.0, signedSum = 0.0, mx = 0.0, sg = 0.0, shadowed = 0.0;
    for (size_t k = 0; k < points.size(); ++k) {
      const double e = std::abs(double(gpu[k]) - double(truth[k]));
      sum += e;
      signedSum += double(gpu[k]) - double(truth[k]);
      mx = std::max(mx, e);
      shadowed += 1.0 - truth[k];
      partial += truth[k] > 0.05f && truth[k] < 0.95f ? 1 : 0;
      if (sgTruth) sg += std::abs(double(gpu[k]) - double((*sgTruth)[k]));
    }
    const double mean = sum / double(points.size());
    worstMean = std::max(worstMean, std::isnan(mean) ? 1e30 : mean);
    const double bias = std::abs(signedSum / double(points.size()));
    worstBias = std::max(worstBias, std::isnan(bias) ? 1e30 : bias);
    worstMax = std::max(worstMax, mx);
    if (sgTruth) worstSg = std::max(worstSg, sg / double(points.size()));
    details += fmt::format("{}: mean |ΔT̃| {:.4f} (signed {:+.4f}), max {:.3f}, mean 1 − T̃_Embree {:.3f}{}; ", what, mean,
                           signedSum / double(points.size()), mx,
                           shadowed / double(points.size()),
                           sgTruth ? fmt::format(", vs the SG-weighted truth {:.4f}", sg / double(points.size())) : "");
  };
  for (int i = 0; i < 2; ++i) {
    const auto t1 = Clock::now();
    const std::vector<float> gpu = renderer->pcssLookup(requests(points, i), false);
    gpuMs += msSince(t1);
    const auto t2 = Clock::now();
    const std::vector<float> cpu = pcssLightLookup(sm, pc, lightTexels, i, points);
    const std::vector<glm::vec3> dirs = coneDirections(lights[size_t(i)], alphas[size_t(i)], 192);
    const std::vector<float> truth = directionsVisibility(reference, points, dirs);
    cpuMs += msSince(t2);
    compare(fmt::format("light {} (α {:.0f}°)", i, alphas[size_t(i)] * 180.0 / kPi), gpu, cpu, truth, nullptr);
  }
  for (int j = 0; j < FT_SRBF_LOBES; ++j) {
    const auto t1 = Clock::now();
    const std::vector<float> gpu = renderer->pcssLookup(requests(points, j), true);
    gpuMs += msSince(t1);
    const std::vector<float> cpu = pcssLobeLookup(pc, lobeTexels, j, points);
    const bool mapped = pc.lobeCone[j].y >= 0.0f;
    if (!mapped) {
      for (size_t k = 0; k < points.size(); ++k) unmappedNotOne += gpu[k] != 1.0f || cpu[k] != 1.0f ? 1 : 0;
      cross.add(cpu, gpu);
      continue;
    }
    const auto t2 = Clock::now();
    const glm::vec3 mu(env.lobes[j].axisLambda);
    const float lambda = env.lobes[j].axisLambda.w;
    const std::vector<float> truth = directionsVisibility(reference, points, coneDirections(mu, pc.lobeCone[j].z, 192));
    const std::vector<float> sgTruth = directionsVisibility(reference, points, sgDirections(mu, lambda, 96));
    cpuMs += msSince(t2);
    compare(fmt::format("lobe {} (λ {}, α {:.1f}°, layer {})", j, lambda, pc.lobeCone[j].z * 180.0 / kPi,
                        int(pc.lobeCone[j].y)),
            gpu, cpu, truth, &sgTruth);
  }
  r.gpuMilliseconds = gpuMs;
  r.gpuTiming = fmt::format("steady_clock: light and lobe depth passes at {}², read-back, PCSS lookups", size);
  r.cpuMilliseconds = cpuMs;
  r.metrics = {
      Metric{"nonfinite.gpu", double(nonFiniteGpu), 0.0, "count", "NaN/Inf are failures"},
      Metric{"nonfinite.cpu", double(nonFiniteCpu), 0.0, "count", "NaN/Inf are failures"},
      Metric{"embree.mean_abs", worstMean, 0.12, "T̃",
             "PCSS vs Embree cone visibility through the tubes, mean per light or lobe (an approximation, header)"},
      Metric{"embree.mean_signed_abs", worstBias, 0.06, "T̃",
             "|mean of T̃_PCSS − T̃_Embree| per light or lobe: PCSS neither lightens nor darkens systematically"},
      Metric{"embree.max_abs", worstMax, 1.0, "T̃", "informational: worst point", false},
      Metric{"sg.mean_abs", worstSg, 1.0, "T̃", "informational: lobes against the SG-weighted truth (notes A11 (b))", false},
      Metric{"unmapped.not_one", double(unmappedNotOne), 0.0, "count",
             "lobes without energy get no map and T̃ = 1 exactly (FT_PCSS_LOBE_MIN_SHARE)"},
  };
  cross.metrics(r.metrics);
  if (partial == 0) r.error = "no point is in a penumbra: the comparison would see nothing soft";
  r.details = fmt::format("{} points, map {}², {} lobe layers, {} capsules, {} penumbra samples. ", points.size(), size,
                          pc.count.x, reference.capsuleCount(), partial) +
              details;
  r.finish();
  return r;
}

// ---- pcss/frame/<path> ----
// The shaded frame with soft shadows (FT_FRAME_PCSS): α = 0 is the hard
// lookup (ftPcssFiltered falls back to V_map, filtered as the map says), so the frame must equal the
// frame without soft shadows bit for bit; α = 10° must change it (the case
// is not vacuous) without a NaN.
CaseResult runFrame(ValidationContext& ctx, bool tessellation) {
  CaseResult r;
  const char* pathName = tessellation ? "tessellation" : "compute";
  r.name = fmt::format("pcss/frame/{}", pathName);
  r.group = "pcss";
  r.path = pathName;
  const auto t0 = Clock::now();
  const YarnPreset& preset = findYarnPreset("cotton1");
  const FiberSetup& setup = ctx.fiberSetup(preset);
  const FittedFibers& fitted = ctx.fittedFibers(preset);
  constexpr int kW = 240, kH = 180;
  Lighting lighting;
  lighting.fabric = "cotton";
  lighting.lights = {DirectionalLight{glm::normalize(glm::vec3(-0.3f, 0.4f, -0.8f)), glm::vec3(2.0f)}};  // from behind
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  FiberRenderer& renderer = ctx.gpu<FiberRenderer>();
  const FiberPath path = tessellation ? FiberPath::Tessellation : FiberPath::Compute;
  gpu.setModel(ctx.buffers(), setup.table);
  gpu.setSegmentList({});
  const Camera cam = namedViewCamera("closeup", ctx.model(), setup.params, glm::vec3(0.3f, 0.5f, 1.0f), kW, kH);
  gpu.setParams(setup.params, makeViewParams(cam, ctx.options().lodThresholdPx, true, true));
  AppearanceOptions a = AppearanceOptions::none();  // the shadow map alone: no other bake to wait for
  a.shadowMap = true;
  a.shadowMapSize = FT_SHADOW_MAP_CI_SIZE * 2;
  const ShadingInputs base =
      ctx.gpu<ShadingBakeGpu>().bake({makeShadingParams(lighting), &fitted.fit.preset, a, &setup.params, &setup.table});
  // Soft shadows bake nothing: the bit and tan α on the same inputs (frameSoftShadows).
  auto frame = [&](bool soft, float alpha) {
    ShadingInputs in = base;
    if (soft) {
      in.params.flags.w |= FT_APPEARANCE_SOFT_SHADOWS;
      in.lightTanAlpha = glm::vec4(std::tan(alpha));
    }
    renderer.setShading(in);
    return renderer.render(gpu, path, kW, kH);
  };
  const ImageRgbaF hard = frame(false, 0.0f);
  const ImageRgbaF zero = frame(true, 0.0f);
  const ImageRgbaF soft = frame(true, float(10.0 * kPi / 180.0));
  size_t differingZero = 0, differingSoft = 0, nonFinite = 0;
  for (size_t k = 0; k < hard.pixels.size(); ++k) {
    nonFinite += !std::isfinite(hard.pixels[k]) + !std::isfinite(zero.pixels[k]) + !std::isfinite(soft.pixels[k]);
    differingZero += hard.pixels[k] != zero.pixels[k];
    differingSoft += hard.pixels[k] != soft.pixels[k];
  }
  r.gpuMilliseconds = msSince(t0);
  r.gpuTiming = "steady_clock: bakes + 3 frames with read-back";
  r.metrics = {
      Metric{"nonfinite.gpu", double(nonFinite), 0.0, "count", "NaN/Inf are failures"},
      Metric{"zero_radius.channels_differing", double(differingZero), 0.0, "channels",
             "α = 0: PCSS is the hard lookup, the frame equals the frame without soft shadows"},
      Metric{"soft.channels_unchanged", differingSoft >= 100 ? 0.0 : 1.0, 0.0, "flag",
             "α = 10° changes ≥ 100 channels (the soft path is drawn)"},
  };
  r.details = fmt::format("{} channels: α = 0 differs in {}, α = 10° in {}", hard.pixels.size(), differingZero,
                          differingSoft);
  r.finish();
  return r;
}

}  // namespace

void addPcssCases(ValidationContext& /*ctx*/, std::vector<ValidationCase>& out) {
  out.push_back({"pcss/lobe-cone", [](ValidationContext& c) { return runLobeCone(c); }});
  out.push_back({"pcss/tube", [](ValidationContext& c) { return runTube(c); }});
  out.push_back({"pcss/embree", [](ValidationContext& c) { return runEmbree(c); }});
  // The compute path only: the PCSS code is the fragment stage's, which both paths share.
  out.push_back({"pcss/frame/compute", [](ValidationContext& c) { return runFrame(c, false); }});
}

}  // namespace ft
