// bcsdf_cases.cpp — the shared fiber BCSDF (common/bcsdf.h; Wu & Yuksel 2019
// (000) §4.3 eq. 5–10) on the GPU, checked two ways:
//   agreement (CPU C++ float or double vs GPU GLSL float, same header):
//     bcsdf/grid/<fabric>, bcsdf/grid/simple-model: f on angle and direction grids;
//     bcsdf/ambient/<fabric>: the ambient table, CPU adaptive quadrature in
//       double vs the GPU's float midpoint bake;
//   correctness (expectations from bcsdf_oracle.h, which shares no code with
//   the header: a formula wrong on both sides fails here):
//     bcsdf/albedo/<fabric>: B1, ∫∫ f cos²θ_o of GPU-evaluated f = F + (1 − F) C_TT;
//     bcsdf/lobes/<fabric>, bcsdf/lobes/simple-model: the shapes of GPU f
//       (TT von Mises at φ = π, R flat in φ, Gaussians on the specular cone,
//       eq. 5 as written);
//     bcsdf/ambient-lookup: ftAmbientLookup + mix on the GPU vs linear interpolation.
// Every case reports NaN/Inf counts (gating, 0) and runs on path "bcsdf".
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "gpu/bcsdf_gpu.h"
#include "reference/bcsdf_tables.h"
#include "scene/fabric.h"
#include "validation/bcsdf_oracle.h"
#include "validation/case_support.h"
#include "validation/draw_order.h"
#include "validation/harness.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kDeg = kPi / 180.0;

// ---- Tolerances, each with its reason ------------------------------------------

// f relative to max(|f|, kFloor · the largest |f| at the same θ_i and channel):
// below a thousandth of the lobe's own peak nothing a render shows depends on
// the value, and there the far tails of the 1° lobe (exp of arguments down to
// −(π/β)²/2) underflow, flush to zero or lose relative precision differently
// on the two sides.
constexpr double kFloor = 1e-3;
// Angles in, CPU vs GPU: the same float expressions; they differ by the
// libraries' exp/cos (GLSL 4.50 §4.7.1: exp within (3 + 2|x|) ulp; |x| ≤ ~7
// above the floor) and by contraction on the GPU: ~1e-6 (notes §0.4: smooth
// quantities 1e-5…1e-4).
constexpr double kGridAnglesTolerance = 1e-4;
const char* kGridAnglesWhy = "same float formula on both sides: exp/cos ulp differences, ~1e-6 (notes §0.4, 1e-4)";
// Directions in: both sides turn them into angles with ftAtan2 (3e-7 rad), but
// from float projections rounded differently (contraction on the GPU); at
// the grid's ±88° that is ~1e-6 rad, which f of the 1° lobe amplifies by up
// to 3/β = 170 at its flanks: ~2e-4 (notes §0.4: 1e-3).
constexpr double kGridDirectionsTolerance = 1e-3;
const char* kGridDirectionsWhy =
    "angles from float projections on each side, amplified by the 1° lobe (notes §0.4: 2e-4 expected, 1e-3)";
// ftFiberAngles on the GPU against the angles the directions were built from
// (in double). θ: an error δ moves f of a 1° lobe by up to 3δ/β at its
// flanks; ftAtan2 is good to 3e-7 rad and float directions add ~1e-7, so
// 1e-6 rad (f within 2e-4). GLSL's own asin on Mesa is off by 4e-4.
// φ: its conditioning is 1/|ω⊥| (29 at the grid's 88°): ~4e-6; the widest
// TT slope |d ln N_TT/dφ| = κ|sin φ| ≤ 8.4 turns 2e-5 rad into 2e-4 of f.
constexpr double kThetaTolerance = 1e-6, kPhiTolerance = 2e-5;
const char* kThetaWhy = "GPU ftFiberAngles vs the constructing angles: 1e-6 rad keeps f of a 1° lobe within 2e-4";
const char* kPhiWhy =
    "GPU ftFiberAngles vs the constructing angles; conditioning 1/|ω⊥| ≤ 29: 2e-5 rad is 2e-4 of N_TT";
// Ambient table, CPU adaptive Gauss–Kronrod in double vs GPU 4096-step
// midpoint in float: the midpoint error is below 1e-10 here (π/4096 is β/23
// at β = 1°, and the integrand's ends have zero slope); the float integrand
// rounds at ~1e-6 (bcsdf_test: Z near its window's edge) and the pairwise sum
// adds log2(4096) × 6e-8: ~2e-6 in all (notes A4: 1e-4).
constexpr double kAmbientTolerance = 1e-4;
// B1 from GPU f: the case's own quadrature (checked below on known integrals,
// ~1e-15) leaves the float evaluation of f, ~2e-6 (bcsdf_test measures 1.7e-6
// on the CPU). Tolerance 1e-4 (notes A4 C1); the planted normaliser fault
// moves the albedo by ~β²(2 − 1/cos²θ_i) of the TT part: 0.66 at worst here.
constexpr double kAlbedoTolerance = 1e-4;
constexpr double kQuadratureSelfTolerance = 1e-8;
// Lobe shapes: ratios of GPU f against exp(−κ(1 + cos φ)), exp(−(θ_i + θ_o)²/2β²)
// and eq. 5 in double: the float argument of exp rounds at ≤ 2κ·6e-8 ≈ 1e-6
// (κ ≤ 8.4), resp. r²/2·6e-8 above the floor: 1e-4 leaves GPU libraries room.
constexpr double kShapeTolerance = 1e-4;
// Symmetries that hold exactly in float on both sides (R's φ independence,
// eq. 5 under i ↔ o): 1e-6 of the peak only allows a different rounding order.
constexpr double kExactTolerance = 1e-6;
// TT's φ ↔ 2π − φ: the two φ are rounded to float independently (≤ 2.4e-7 rad
// each at 2π) and |dN/dφ| / N(π) ≤ 0.61 √κ ≤ 1.8: ~1e-6; 1e-5.
constexpr double kMirrorTolerance = 1e-5;
// Lookup position, in texels: u = (θ + π/2)/π·n − ½ rounds at a few ulp of
// n ≤ 64, i.e. ~1e-5 texel; a lookup half a texel off (the planted fault) is
// 0.5.
constexpr double kLookupTolerance = 1e-3;

// ---- Helpers ---------------------------------------------------------------------

CaseResult newBcsdfResult(const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "bcsdf";
  r.path = "bcsdf";
  r.gpuTiming = "wall clock: upload, dispatch, read-back";
  return r;
}

uint64_t nonFinite(const std::vector<glm::vec3>& v) {
  uint64_t n = 0;
  for (const glm::vec3& x : v) n += !std::isfinite(x.x) + !std::isfinite(x.y) + !std::isfinite(x.z);
  return n;
}
uint64_t nonFinite(const std::vector<glm::dvec3>& v) {
  uint64_t n = 0;
  for (const glm::dvec3& x : v) n += !std::isfinite(x.x) + !std::isfinite(x.y) + !std::isfinite(x.z);
  return n;
}

// The largest error and where; a NaN sticks.
struct Worst {
  double value = 0.0;
  size_t at = 0;
  void add(double e, size_t i) {
    if (std::isnan(value)) return;
    if (!(e <= value)) {
      value = e;
      at = i;
    }
  }
};

oracle::Fabric oracleFabric(const FabricPreset& p) {
  oracle::Fabric f;
  for (int c = 0; c < 3; ++c) {
    f.colorR[c] = p.colorR[c];
    f.colorTT[c] = p.colorTT[c];
  }
  f.betaRDegrees = p.betaRDegrees;
  f.betaTTDegrees = p.betaTTDegrees;
  f.gammaTTDegrees = p.gammaTTDegrees;
  return f;
}

// n angles over [lo, hi], ends included, as the float the header gets.
std::vector<float> angleRange(int n, double lo, double hi) {
  std::vector<float> out;
  for (int i = 0; i < n; ++i) out.push_back(float(lo + (hi - lo) * i / (n - 1)));
  return out;
}

// The 33 × 33 × 32 grid of notes A4: θ_i, θ_o over [lo, hi], φ over [0, π].
std::vector<FiberAngles> angleGrid(double lo, double hi) {
  std::vector<FiberAngles> out;
  for (float ti : angleRange(33, lo, hi))
    for (float to : angleRange(33, lo, hi))
      for (float phi : angleRange(32, 0.0, kPi)) out.push_back({ti, to, phi});
  return out;
}

// Directions with the grid's angles about random unit tangents (double, then float).
struct Directions {
  std::vector<glm::vec3> t, wi, wo;
};
Directions directionsOf(const std::vector<FiberAngles>& grid) {
  std::mt19937 rng(20190101);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> turn(0.0, 2.0 * kPi);
  Directions d;
  for (const FiberAngles& a : grid) {
    const glm::dvec3 t = glm::normalize(drawVec3<glm::dvec3>(normal, rng));
    const glm::dvec3 u = glm::normalize(glm::cross(t, std::abs(t.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 v = glm::cross(t, u);
    const double phi0 = turn(rng);
    const auto dir = [&](double theta, double phi) {
      return glm::vec3(std::sin(theta) * t + std::cos(theta) * (std::cos(phi) * u + std::sin(phi) * v));
    };
    d.t.push_back(glm::vec3(t));
    d.wi.push_back(dir(a.thetaI, phi0));
    d.wo.push_back(dir(a.thetaO, phi0 + a.phi));
  }
  return d;
}

// Relative error with the floor of kFloor × the largest reference value at
// the same θ_i (rows of `rowLength` consecutive entries), per channel.
Worst gridError(const std::vector<glm::vec3>& ref, const std::vector<glm::vec3>& got, size_t rowLength,
                ErrorHistogram* histogram = nullptr) {
  Worst w;
  for (size_t row = 0; row < ref.size(); row += rowLength) {
    glm::dvec3 peak(0.0);
    for (size_t i = row; i < row + rowLength; ++i) peak = glm::max(peak, glm::abs(glm::dvec3(ref[i])));
    for (size_t i = row; i < row + rowLength; ++i)
      for (int c = 0; c < 3; ++c) {
        const double a = ref[i][c], b = got[i][c];
        const double e = std::abs(b - a) / std::max(std::abs(a), kFloor * peak[c]);
        w.add(e, i);
        if (histogram) histogram->add(e);
      }
  }
  return w;
}

std::vector<glm::vec3> splat(const std::vector<float>& v) {
  std::vector<glm::vec3> out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = glm::vec3(v[i]);
  return out;
}

std::string describeAngles(const FiberAngles& a) {
  return fmt::format("θ_i {:.4f}, θ_o {:.4f}, φ {:.4f}", a.thetaI, a.thetaO, a.phi);
}

// Direction grids stay within ±88°: at the poles ω⊥ vanishes and φ is
// undefined (f's TT lobe still depends on it), a property of directions.
constexpr double kDirectionsMaxTheta = 88.0 * kDeg;

// ---- bcsdf/grid/<fabric> ------------------------------------------------------------

CaseResult runGridCase(ValidationContext& ctx, const FabricPreset& preset, const std::string& name) {
  CaseResult r = newBcsdfResult(name);
  const FabricParams p = preset.params();
  const std::vector<FiberAngles> grid = angleGrid(-0.5 * kPi, 0.5 * kPi);
  const std::vector<FiberAngles> dgrid = angleGrid(-kDirectionsMaxTheta, kDirectionsMaxTheta);
  const Directions d = directionsOf(dgrid);
  auto t0 = Clock::now();
  const std::vector<glm::vec3> cpu = evaluateBcsdfCpu(p, grid);
  const std::vector<glm::vec3> cpuDir = evaluateBcsdfCpu(p, fiberAnglesCpu(d.t, d.wi, d.wo));
  r.cpuMilliseconds = msSince(t0);
  t0 = Clock::now();
  const std::vector<glm::vec3> gpu = ctx.gpu<BcsdfGpu>().evaluateAngles(p, grid);
  const std::vector<glm::vec3> gpuDir = ctx.gpu<BcsdfGpu>().evaluateDirections(p, d.t, d.wi, d.wo);
  const std::vector<FiberAngles> gpuAngles = ctx.gpu<BcsdfGpu>().fiberAngles(d.t, d.wi, d.wo);
  r.gpuMilliseconds = msSince(t0);
  double thetaError = 0.0, phiError = 0.0;
  for (size_t i = 0; i < dgrid.size(); ++i) {
    thetaError = maxKeepNaN(thetaError, std::abs(double(gpuAngles[i].thetaI) - dgrid[i].thetaI));
    thetaError = maxKeepNaN(thetaError, std::abs(double(gpuAngles[i].thetaO) - dgrid[i].thetaO));
    phiError = maxKeepNaN(phiError, std::abs(double(gpuAngles[i].phi) - dgrid[i].phi));
  }
  const size_t row = 33 * 32;
  const Worst a = gridError(cpu, gpu, row, &r.histogram), b = gridError(cpuDir, gpuDir, row);
  r.histogramMetric = "angles.max_rel";
  r.metrics = {
      Metric{"angles.max_rel", a.value, kGridAnglesTolerance, "relative", kGridAnglesWhy},
      Metric{"directions.max_rel", b.value, kGridDirectionsTolerance, "relative", kGridDirectionsWhy},
      Metric{"directions.theta_error", thetaError, kThetaTolerance, "radians", kThetaWhy},
      Metric{"directions.phi_error", phiError, kPhiTolerance, "radians", kPhiWhy},
      Metric{"evaluations", double(grid.size() + dgrid.size()), 0, "count",
             "33 θ_i × 33 θ_o × 32 φ, angles over ±90°, directions over ±88°", false},
      nonFiniteMetric("cpu", nonFinite(cpu) + nonFinite(cpuDir), "CPU f values"),
      nonFiniteMetric("gpu",
                      nonFinite(gpu) + nonFinite(gpuDir) + uint64_t(std::isnan(thetaError) || std::isnan(phiError)),
                      "GPU f values and angles"),
  };
  r.details = fmt::format("worst (angles) at {}: cpu {:.7g} gpu {:.7g}; worst (directions) at {}",
                          describeAngles(grid[a.at]), cpu[a.at].x, gpu[a.at].x, describeAngles(dgrid[b.at]));
  r.finish();
  return r;
}

// The simple model (eq. 5) at k_s = 1, β = 5° (notes A4 default) and 1°.
CaseResult runSimpleGridCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = newBcsdfResult(name);
  const std::vector<FiberAngles> grid = angleGrid(-0.5 * kPi, 0.5 * kPi);
  const std::vector<FiberAngles> dgrid = angleGrid(-kDirectionsMaxTheta, kDirectionsMaxTheta);
  const Directions d = directionsOf(dgrid);
  const std::vector<FiberAngles> dAngles = fiberAnglesCpu(d.t, d.wi, d.wo);
  Worst a, b;
  uint64_t badCpu = 0, badGpu = 0;
  for (double betaDeg : {5.0, 1.0}) {
    BcsdfEvalMode mode;
    mode.model = FT_SHADING_SIMPLE;
    mode.ks = 1.0f;
    mode.beta = float(betaDeg * kDeg);
    auto t0 = Clock::now();
    const std::vector<glm::vec3> cpu = splat(evaluateSimpleSpecularCpu(mode.ks, mode.beta, grid));
    const std::vector<glm::vec3> cpuDir = splat(evaluateSimpleSpecularCpu(mode.ks, mode.beta, dAngles));
    r.cpuMilliseconds += msSince(t0);
    t0 = Clock::now();
    const std::vector<glm::vec3> gpu = ctx.gpu<BcsdfGpu>().evaluateAngles(FabricParams{}, grid, mode);
    const std::vector<glm::vec3> gpuDir = ctx.gpu<BcsdfGpu>().evaluateDirections(FabricParams{}, d.t, d.wi, d.wo, mode);
    r.gpuMilliseconds += msSince(t0);
    const Worst wa = gridError(cpu, gpu, 33 * 32, &r.histogram), wb = gridError(cpuDir, gpuDir, 33 * 32);
    if (!std::isnan(a.value) && !(wa.value <= a.value)) a = wa;  // a NaN sticks
    if (!std::isnan(b.value) && !(wb.value <= b.value)) b = wb;
    badCpu += nonFinite(cpu) + nonFinite(cpuDir);
    badGpu += nonFinite(gpu) + nonFinite(gpuDir);
  }
  r.histogramMetric = "angles.max_rel";
  r.metrics = {
      Metric{"angles.max_rel", a.value, kGridAnglesTolerance, "relative", kGridAnglesWhy},
      Metric{"directions.max_rel", b.value, kGridDirectionsTolerance, "relative", kGridDirectionsWhy},
      nonFiniteMetric("cpu", badCpu, "CPU f_spec values"),
      nonFiniteMetric("gpu", badGpu, "GPU f_spec values"),
  };
  r.details = fmt::format("k_s = 1, β = 5° and 1°; worst (angles) at {}; worst (directions) at {}",
                          describeAngles(grid[a.at]), describeAngles(dgrid[b.at]));
  r.finish();
  return r;
}

// ---- bcsdf/ambient/<fabric> -----------------------------------------------------------

CaseResult runAmbientCase(ValidationContext& ctx, const FabricPreset& preset, const std::string& name) {
  CaseResult r = newBcsdfResult(name);
  const FabricParams p = preset.params();
  auto t0 = Clock::now();
  const AmbientTableCpu cpu = bakeAmbientTableCpuParts(p);
  const std::vector<glm::dvec3> ref = cpu.total();
  r.cpuMilliseconds = msSince(t0);
  t0 = Clock::now();
  const std::vector<glm::vec3> gpu = ctx.gpu<BcsdfGpu>().bakeAmbientTable(p);
  r.gpuMilliseconds = msSince(t0);
  Worst w;
  for (size_t k = 0; k < ref.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const double e = std::abs(double(gpu[k][c]) - ref[k][c]) / std::abs(ref[k][c]);
      w.add(e, k);
      r.histogram.add(e);
    }
  r.histogramMetric = "table.max_rel";
  r.metrics = {
      Metric{"table.max_rel", w.value, kAmbientTolerance, "relative",
             "CPU G7-K15 (double) vs GPU 4096-step midpoint (float, pairwise sum): float integrand ~1e-6 (notes A4: "
             "1e-4)"},
      Metric{"cpu.error_estimate", cpu.errorEstimate, 1e-5, "relative",
             "the CPU table's own Gauss-Kronrod estimate: 1e-9 requested, float integrand rounding ~1e-6 allowed"},
      Metric{"texels", double(ref.size()), 0, "count", "FT_AMBIENT_TABLE_SIZE texels over θ_o", false},
      Metric{"cpu.evaluations", double(cpu.evaluations), 0, "count", "integrand evaluations of the CPU bake", false},
      nonFiniteMetric("cpu", nonFinite(ref), "CPU table texels"),
      nonFiniteMetric("gpu", nonFinite(gpu), "GPU table texels"),
  };
  const size_t k = w.at;
  r.details = fmt::format("worst texel {} (θ_o {:.4f}): cpu {:.8g} {:.8g} {:.8g}, gpu {:.8g} {:.8g} {:.8g}", k,
                          ftAmbientTexelAngle(int(k), int(ref.size())), ref[k].x, ref[k].y, ref[k].z, gpu[k].x,
                          gpu[k].y, gpu[k].z);
  r.finish();
  return r;
}

// ---- bcsdf/lobe-norm/<fabric> ------------------------------------------------------------
// The frame's lobe-normalisation table (common/bcsdf.h): CPU and GPU bakes,
// and Z looked up in it against the oracle's Z in double at random θ_i and
// densely over the table's window, where linear interpolation of 255 steps
// over 6β is within 1.3e-4 of Z for every β (docs/shading.md).

CaseResult runLobeNormCase(ValidationContext& ctx, const FabricPreset& preset, const std::string& name) {
  CaseResult r = newBcsdfResult(name);
  const FabricParams p = preset.params();
  const oracle::Fabric fabric = oracleFabric(preset);
  auto t0 = Clock::now();
  const std::vector<glm::vec2> cpu = bakeLobeNormTableCpu(p);
  r.cpuMilliseconds = msSince(t0);
  std::vector<float> thetas;
  std::mt19937 rng(38);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 400; ++i) thetas.push_back(float(-0.5 * kPi + kPi * unit(rng)));
  for (const double beta : {fabric.betaR(), fabric.betaTT()}) {  // the window, where the table is read
    const double lo = std::max(0.0, 0.5 * kPi - 6.0 * beta);
    for (int i = 0; i <= 600; ++i) thetas.push_back(float((i % 2 ? -1.0 : 1.0) * (lo + (0.5 * kPi - lo) * i / 600.0)));
  }
  t0 = Clock::now();
  BcsdfGpu& gpu = ctx.gpu<BcsdfGpu>();
  const std::vector<glm::vec2> table = gpu.bakeLobeNormTable(p);
  const std::vector<glm::vec2> got = gpu.lookupLobeNorm(p, table, thetas);
  r.gpuMilliseconds = msSince(t0);
  Worst tables, lookups, sides;
  uint64_t bad = 0;
  for (size_t k = 0; k < cpu.size(); ++k)
    for (int c = 0; c < 2; ++c) {
      bad += !std::isfinite(cpu[k][c]) + !std::isfinite(table[k][c]);
      tables.add(std::abs(double(table[k][c]) - cpu[k][c]) / std::abs(double(cpu[k][c])), k);
    }
  std::string details;
  for (size_t i = 0; i < thetas.size(); ++i) {
    const glm::vec2 mine = lookupLobeNormCpu(p, cpu, thetas[i]);
    const double want[2] = {oracle::lobeNorm(fabric.betaR(), thetas[i]), oracle::lobeNorm(fabric.betaTT(), thetas[i])};
    for (int c = 0; c < 2; ++c) {
      bad += !std::isfinite(got[i][c]);
      const double e = std::abs(got[i][c] - want[c]) / want[c];
      r.histogram.add(e);
      if (!std::isnan(lookups.value) && !(e <= lookups.value))
        details = fmt::format("worst lookup: θ_i {:.6f}, Z_{} gpu {:.8g}, oracle {:.8g}", thetas[i], c ? "TT" : "R",
                              got[i][c], want[c]);
      lookups.add(e, i);
      sides.add(std::abs(double(got[i][c]) - mine[c]) / want[c], i);
    }
  }
  r.histogramMetric = "lookup.max_rel";
  r.metrics = {
      Metric{"lookup.max_rel", lookups.value, 3e-4, "relative",
             "GPU table lookup vs the oracle's Z in double (independent quadrature): linear interpolation over 6β in "
             "255 steps ≤ 1.3e-4 for every β, float quadrature ~1e-6"},
      Metric{"table.max_rel", tables.value, 1e-5, "relative",
             "GPU vs CPU bake of the same float Z (closed form or 20-point Gauss-Legendre): GPU exp/cos rounding"},
      Metric{"sides.max_rel", sides.value, 1e-5, "relative", "GPU vs CPU lookups in their own tables"},
      Metric{"texels", double(cpu.size()), 0, "count", "FT_LOBE_NORM_TABLE_SIZE texels per lobe", false},
      nonFiniteMetric("cpu+gpu", bad, "table texels and lookups"),
  };
  r.details = details;
  r.finish();
  return r;
}

// ---- bcsdf/albedo/<fabric> --------------------------------------------------------------

// B1 by quadrature of GPU-evaluated f: θ_o by 10-point Gauss–Legendre on
// panels cut at every lobe width around the specular cone (≤ 0.1 rad
// elsewhere), φ by the trapezoid rule on [0, π] doubled (f is even and
// 2π-periodic in φ: spectrally accurate; 33 nodes resolve the von Mises of
// κ ≤ 8.4 to ~1e-16).
CaseResult runAlbedoCase(ValidationContext& ctx, const FabricPreset& preset, const std::string& name) {
  CaseResult r = newBcsdfResult(name);
  const FabricParams p = preset.params();
  const oracle::Fabric fabric = oracleFabric(preset);
  const double thetas[] = {-1.56, -1.45, -1.2, -0.8, -0.4, 0.0, 0.25, 0.6, 1.0, 1.3, 1.5, 1.56};
  constexpr int kPhi = 32;
  struct Row {
    float thetaI;
    oracle::Nodes nodes;
  };
  std::vector<Row> rows;
  std::vector<FiberAngles> requests;
  double selfError = 0.0;
  for (double t : thetas) {
    Row row{float(t), {}};
    std::vector<double> cuts;
    for (double beta : {fabric.betaR(), fabric.betaTT()})
      for (int j = -8; j <= 8; ++j) cuts.push_back(-double(row.thetaI) + j * beta);
    row.nodes = oracle::panelNodes(-0.5 * kPi, 0.5 * kPi, cuts, 0.1, 10);
    // The nodes on known integrals: each lobe's Gaussian over [−π/2, π/2] (erf).
    for (double beta : {fabric.betaR(), fabric.betaTT()}) {
      double q = 0.0;
      for (size_t i = 0; i < row.nodes.x.size(); ++i) {
        const double z = (row.nodes.x[i] + row.thetaI) / beta;
        q += row.nodes.w[i] * std::exp(-0.5 * z * z) / (std::sqrt(2.0 * kPi) * beta);
      }
      const double s = std::sqrt(2.0) * beta;
      const double exact = 0.5 * (std::erf((0.5 * kPi + row.thetaI) / s) - std::erf((-0.5 * kPi + row.thetaI) / s));
      selfError = std::max(selfError, std::abs(q - exact) / exact);
    }
    for (double to : row.nodes.x)
      for (int m = 0; m <= kPhi; ++m) requests.push_back({row.thetaI, float(to), float(kPi * m / kPhi)});
    rows.push_back(std::move(row));
  }
  // ... and the φ rule on the von Mises (double, std::cyl_bessel_i).
  {
    const double kappa = fabric.kappa();
    double q = 0.0;
    for (int m = 0; m <= kPhi; ++m)
      q += (m == 0 || m == kPhi ? 0.5 : 1.0) * (2.0 * kPi / kPhi) * std::exp(kappa * std::cos(kPi * m / kPhi - kPi)) /
           (2.0 * kPi * std::cyl_bessel_i(0.0, kappa));
    selfError = std::max(selfError, std::abs(q - 1.0));
  }
  const auto t0 = Clock::now();
  const std::vector<glm::vec3> f = ctx.gpu<BcsdfGpu>().evaluateAngles(p, requests);
  r.gpuMilliseconds = msSince(t0);
  Worst w;
  std::string details;
  size_t i = 0;
  for (size_t k = 0; k < rows.size(); ++k) {
    glm::dvec3 sum(0.0);
    for (size_t n = 0; n < rows[k].nodes.x.size(); ++n) {
      const double c = std::cos(rows[k].nodes.x[n]);
      for (int m = 0; m <= kPhi; ++m, ++i)
        sum += glm::dvec3(f[i]) * (rows[k].nodes.w[n] * (m == 0 || m == kPhi ? 0.5 : 1.0) * (2.0 * kPi / kPhi) * c * c);
    }
    const glm::dvec3 want = oracle::albedo(fabric, double(rows[k].thetaI));
    for (int c = 0; c < 3; ++c) {
      const double e = std::abs(sum[c] - want[c]) / want[c];
      w.add(e, k);
      r.histogram.add(e);
    }
    if (w.at == k)
      details = fmt::format("worst at θ_i {:.3f}: ρ {:.7g} {:.7g} {:.7g}, F + (1 − F) C_TT {:.7g} {:.7g} {:.7g}",
                            rows[k].thetaI, sum.x, sum.y, sum.z, want.x, want.y, want.z);
  }
  r.histogramMetric = "albedo.max_rel";
  r.metrics = {
      Metric{
          "albedo.max_rel", w.value, kAlbedoTolerance, "relative",
          "B1 from GPU f against F + (1 - F) C_TT of the preset (oracle): float f ~2e-6, quadrature ~1e-15 (notes A4 "
          "C1: 1e-4)"},
      Metric{"quadrature.self_error", selfError, kQuadratureSelfTolerance, "relative",
             "the case's nodes on the lobes' Gaussians (erf) and the von Mises (std::cyl_bessel_i): the quadrature is "
             "not what the albedo metric measures"},
      Metric{"evaluations", double(requests.size()), 0, "count",
             fmt::format("{} θ_i from -1.56 to 1.56, ~{} θ_o nodes × {} φ each", rows.size(),
                         requests.size() / rows.size() / (kPhi + 1), kPhi + 1),
             false},
      nonFiniteMetric("gpu", nonFinite(f), "GPU f values"),
  };
  r.details = details;
  r.finish();
  return r;
}

// ---- bcsdf/lobes/<fabric> ------------------------------------------------------------------

const double kLobeThetas[] = {-1.2, -0.5, 0.0, 0.3, 0.9, 1.4};

CaseResult runLobesCase(ValidationContext& ctx, const FabricPreset& preset, const std::string& name) {
  CaseResult r = newBcsdfResult(name);
  const FabricParams p = preset.params();
  const oracle::Fabric fabric = oracleFabric(preset);
  BcsdfGpu& gpu = ctx.gpu<BcsdfGpu>();
  BcsdfEvalMode onlyR, onlyTT;
  onlyR.lobes = BcsdfEvalMode::kLobeR;
  onlyTT.lobes = BcsdfEvalMode::kLobeTT;
  uint64_t bad = 0;
  const auto t0 = Clock::now();

  // Azimuthal profiles on φ ∈ [0, 2π], 1° steps (index 180 is π), on the
  // specular cone and half a TT width off it.
  constexpr int kSteps = 360;
  double peakOffset = 0.0, shape = 0.0, mirror = 0.0, flat = 0.0;
  for (double t : kLobeThetas)
    for (double off : {0.0, 0.5 * fabric.betaTT()}) {
      const float ti = float(t), to = float(std::clamp(-t + off, -0.5 * kPi, 0.5 * kPi));
      std::vector<FiberAngles> a;
      for (int m = 0; m <= kSteps; ++m) a.push_back({ti, to, float(2.0 * kPi * m / kSteps)});
      const std::vector<glm::vec3> tt = gpu.evaluateAngles(p, a, onlyTT), rr = gpu.evaluateAngles(p, a, onlyR);
      bad += nonFinite(tt) + nonFinite(rr);
      for (int c = 0; c < 3; ++c) {
        if (p.colorTT[c] == 0.0f) continue;  // no TT in this channel (polyester green)
        int best = 0;
        for (int m = 0; m <= kSteps; ++m)
          if (tt[size_t(m)][c] > tt[size_t(best)][c]) best = m;
        peakOffset = std::max(peakOffset, std::abs(2.0 * kPi * best / kSteps - kPi));
        const double peak = tt[kSteps / 2][c];
        for (int m = 0; m <= kSteps; ++m) {
          const double want = oracle::vonMisesRelative(fabric.kappa(), double(a[size_t(m)].phi));
          const double e = std::abs(tt[size_t(m)][c] / peak - want) / std::max(want, kFloor);
          shape = maxKeepNaN(shape, e);
          const double d = std::abs(double(tt[size_t(m)][c]) - tt[size_t(kSteps - m)][c]) / peak;
          mirror = maxKeepNaN(mirror, d);
          if (off != 0.0) continue;  // R off the cone of a 1° lobe underflows to 0
          const double v = std::abs(double(rr[size_t(m)][c]) - rr[kSteps / 2][c]) / rr[kSteps / 2][c];
          flat = maxKeepNaN(flat, v);
        }
      }
    }

  // Longitudinal profiles: θ_o = −θ_i + jβ/8, |j| ≤ 24, at φ = π.
  double peakR = 0.0, peakTT = 0.0, gauss = 0.0;
  for (double t : kLobeThetas)
    for (int lobe = 0; lobe < 2; ++lobe) {
      const double beta = lobe == 0 ? fabric.betaR() : fabric.betaTT();
      const float ti = float(t);
      std::vector<FiberAngles> a;
      for (int j = -24; j <= 24; ++j) {
        const double to = -double(ti) + j * beta / 8.0;
        if (std::abs(to) <= 0.5 * kPi) a.push_back({ti, float(to), float(kPi)});
      }
      const std::vector<glm::vec3> v = gpu.evaluateAngles(p, a, lobe == 0 ? onlyR : onlyTT);
      bad += nonFinite(v);
      size_t centre = 0;
      while (a[centre].thetaO != -ti) ++centre;  // j = 0 is always inside
      for (int c = 0; c < 3; ++c) {
        if (lobe == 1 && p.colorTT[c] == 0.0f) continue;
        size_t best = 0;
        for (size_t i = 0; i < v.size(); ++i)
          if (v[i][c] > v[best][c]) best = i;
        (lobe == 0 ? peakR : peakTT) = std::max(lobe == 0 ? peakR : peakTT, std::abs(double(a[best].thetaO) + ti));
        for (size_t i = 0; i < v.size(); ++i) {
          const double want = oracle::gaussianRelative(beta, double(ti), double(a[i].thetaO));
          const double e = std::abs(v[i][c] / v[centre][c] - want) / std::max(want, kFloor);
          gauss = maxKeepNaN(gauss, e);
        }
      }
    }
  r.gpuMilliseconds = msSince(t0);
  r.metrics = {
      Metric{"tt.peak_phi_offset", peakOffset, 0.5 * kDeg, "radians",
             "the TT lobe peaks at φ = π (forward scattering, 000 §4.3): the argmax of a 1° grid must be π"},
      Metric{"tt.phi_shape_rel", shape, kShapeTolerance, "relative",
             "N_TT(φ)/N_TT(π) = exp(-κ(1 + cos φ)), κ = γ_TT^-2 from the preset (von Mises); float exp argument ~1e-6"},
      Metric{"tt.phi_mirror", mirror, kMirrorTolerance, "of the peak",
             "TT(φ) = TT(2π - φ): φ and 2π - φ rounded to float independently, ~1e-6"},
      Metric{"r.phi_variation", flat, kExactTolerance, "of the value", "N_R = 1/(2π): the R lobe does not depend on φ"},
      Metric{"r.peak_theta_offset", peakR, fabric.betaR() / 16.0, "radians",
             "M_R peaks on the specular cone θ_o = -θ_i: the argmax of a β_R/8 grid must be there"},
      Metric{"tt.peak_theta_offset", peakTT, fabric.betaTT() / 16.0, "radians",
             "M_TT peaks on the specular cone θ_o = -θ_i (β_TT/8 grid)"},
      Metric{"m.shape_rel", gauss, kShapeTolerance, "relative",
             "M(θ_i, θ_o)/M(θ_i, -θ_i) = exp(-(θ_i + θ_o)²/2β²) for R and TT (Z depends on θ_i only): float exp "
             "argument ~1e-6"},
      nonFiniteMetric("gpu", bad, "GPU lobe values"),
  };
  r.details = fmt::format("θ_i in {{-1.2, -0.5, 0, 0.3, 0.9, 1.4}}; κ = {:.4f}, β_R = {:.4f}, β_TT = {:.4f}",
                          fabric.kappa(), fabric.betaR(), fabric.betaTT());
  r.finish();
  return r;
}

// Eq. 5: peak on the specular cone, symmetric in (i, o), and the formula as written.
CaseResult runSimpleLobesCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = newBcsdfResult(name);
  BcsdfGpu& gpu = ctx.gpu<BcsdfGpu>();
  const double ks = 0.8;
  double peakOffset = 0.0, asym = 0.0, formula = 0.0, peakTolerance = 1.0;
  uint64_t bad = 0;
  const auto t0 = Clock::now();
  for (double betaDeg : {5.0, 1.0}) {
    const double beta = double(float(betaDeg * kDeg));
    BcsdfEvalMode mode;
    mode.model = FT_SHADING_SIMPLE;
    mode.ks = float(ks);
    mode.beta = float(beta);
    peakTolerance = std::min(peakTolerance, beta / 16.0);
    for (double t : kLobeThetas) {
      const float ti = float(t);
      std::vector<FiberAngles> a;
      for (int j = -40; j <= 40; ++j) {
        const double to = -double(ti) + j * beta / 8.0;
        if (std::abs(to) <= 0.5 * kPi) a.push_back({ti, float(to), 0.3f});
      }
      const std::vector<glm::vec3> v = gpu.evaluateAngles(FabricParams{}, a, mode);
      bad += nonFinite(v);
      size_t best = 0;
      for (size_t i = 0; i < v.size(); ++i)
        if (v[i].x > v[best].x) best = i;
      peakOffset = std::max(peakOffset, std::abs(double(a[best].thetaO) + ti));
    }
    const std::vector<FiberAngles> grid = angleGrid(-0.5 * kPi, 0.5 * kPi);
    std::vector<FiberAngles> swapped(grid.size());
    for (size_t i = 0; i < grid.size(); ++i) swapped[i] = {grid[i].thetaO, grid[i].thetaI, grid[i].phi};
    const std::vector<glm::vec3> f = gpu.evaluateAngles(FabricParams{}, grid, mode);
    const std::vector<glm::vec3> g = gpu.evaluateAngles(FabricParams{}, swapped, mode);
    bad += nonFinite(f) + nonFinite(g);
    for (size_t i = 0; i < grid.size(); ++i) {
      const double d = std::abs(double(f[i].x) - g[i].x) / ks;
      asym = maxKeepNaN(asym, d);
      const double want = oracle::simpleSpecular(ks, beta, grid[i].thetaI, grid[i].thetaO, grid[i].phi);
      const double e = std::abs(f[i].x - want) / std::max(want, kFloor * ks);
      formula = maxKeepNaN(formula, e);
      r.histogram.add(e);
    }
  }
  r.gpuMilliseconds = msSince(t0);
  r.histogramMetric = "simple.formula_rel";
  r.metrics = {
      Metric{"simple.peak_offset", peakOffset, peakTolerance, "radians",
             "f_spec peaks on the specular cone θ_o = -θ_i (θ_h = 0): the argmax of a β/8 grid must be there"},
      Metric{"simple.asymmetry", asym, kExactTolerance, "of k_s", "eq. 5 is symmetric under i <-> o"},
      Metric{"simple.formula_rel", formula, kShapeTolerance, "relative",
             "k_s cos(φ/2) exp(-θ_h²/2β²) in double (oracle) on the 33×33×32 grid, floor 1e-3 k_s: float exp ~1e-5"},
      nonFiniteMetric("gpu", bad, "GPU f_spec values"),
  };
  r.details = "k_s = 0.8, β = 5° and 1°";
  r.finish();
  return r;
}

// ---- bcsdf/ambient-lookup --------------------------------------------------------------------

CaseResult runLookupCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = newBcsdfResult(name);
  std::mt19937 rng(64);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0, worstCentre = 0.0;
  uint64_t bad = 0;
  std::string details;
  const auto t0 = Clock::now();
  for (int n : {FT_AMBIENT_TABLE_SIZE, 32}) {
    // Random texels: the lookup does not care what the table holds, and
    // neighbours that differ make any offset visible.
    std::vector<glm::vec3> table(static_cast<size_t>(n));
    for (glm::vec3& t : table) t = drawVec3<glm::vec3>(unit, rng);
    glm::dvec3 step(0.0);
    for (int k = 0; k + 1 < n; ++k)
      step = glm::max(step, glm::abs(glm::dvec3(table[size_t(k + 1)] - table[size_t(k)])));
    std::vector<float> thetas;
    std::vector<bool> centre;
    const auto texelAngle = [&](double k) { return -0.5 * kPi + (k + 0.5) * kPi / n; };
    for (int k = 0; k < n; ++k) {
      thetas.push_back(float(texelAngle(k)));
      centre.push_back(true);
      thetas.push_back(float(texelAngle(k + 0.5)));  // half-way, and past the last centre
      centre.push_back(false);
    }
    for (double t : {-0.5 * kPi, 0.5 * kPi, texelAngle(-0.3), texelAngle(n - 0.7)}) {
      thetas.push_back(float(t));
      centre.push_back(false);
    }
    for (int i = 0; i < 500; ++i) {
      thetas.push_back(float(-0.5 * kPi + kPi * unit(rng)));
      centre.push_back(false);
    }
    const std::vector<glm::vec3> got = ctx.gpu<BcsdfGpu>().lookupAmbient(table, thetas);
    bad += nonFinite(got);
    for (size_t i = 0; i < thetas.size(); ++i) {
      const glm::dvec3 want = oracle::lerpTable(table, double(thetas[i]));
      for (int c = 0; c < 3; ++c) {
        const double e = std::abs(got[i][c] - want[c]) / step[c];
        r.histogram.add(e);
        if (!std::isnan(worst) && !(e <= worst)) {  // a NaN sticks
          worst = e;
          details = fmt::format("worst: {} texels, θ_o {:.6f}: gpu {:.7g}, expected {:.7g}", n, thetas[i], got[i][c],
                                want[c]);
        }
        if (centre[i]) worstCentre = maxKeepNaN(worstCentre, e);
      }
    }
  }
  r.gpuMilliseconds = msSince(t0);
  r.histogramMetric = "lookup.max_error_texels";
  const char* why = "float texel coordinate (θ + π/2)/π n - 1/2: ~1e-5 texel; half a texel off is 0.5";
  r.metrics = {
      Metric{"lookup.max_error_texels", worst, kLookupTolerance, "texel steps",
             std::string("ftAmbientLookup + mix vs the oracle's linear interpolation (clamped ends), 64 and 32 texels, "
                         "error / largest neighbour difference: ") +
                 why},
      Metric{"lookup.centre_error_texels", worstCentre, kLookupTolerance, "texel steps",
             std::string("at texel centres the lookup returns the texel: ") + why},
      nonFiniteMetric("gpu", bad, "GPU lookups"),
  };
  r.details = details;
  r.finish();
  return r;
}

}  // namespace

void addBcsdfCases(ValidationContext&, std::vector<ValidationCase>& out) {
  for (const FabricPreset& f : builtinFabricPresets()) {
    const auto add = [&](const std::string& kind,
                         CaseResult (*run)(ValidationContext&, const FabricPreset&, const std::string&)) {
      const std::string name = "bcsdf/" + kind + "/" + f.name;
      out.push_back({name, [run, &f, name](ValidationContext& c) { return run(c, f, name); }});
    };
    add("grid", runGridCase);
    add("ambient", runAmbientCase);
    add("lobe-norm", runLobeNormCase);
    add("albedo", runAlbedoCase);
    add("lobes", runLobesCase);
  }
  out.push_back({"bcsdf/grid/simple-model",
                 [](ValidationContext& c) { return runSimpleGridCase(c, "bcsdf/grid/simple-model"); }});
  out.push_back({"bcsdf/lobes/simple-model",
                 [](ValidationContext& c) { return runSimpleLobesCase(c, "bcsdf/lobes/simple-model"); }});
  out.push_back(
      {"bcsdf/ambient-lookup", [](ValidationContext& c) { return runLookupCase(c, "bcsdf/ambient-lookup"); }});
}

}  // namespace ft
