// prt_multiple_scattering_cases.cpp — local multiple scattering of Khungurn et
// al. 2017 (004) §4.2, §4.3, §5.3.1 (common/sh.h, common/
// prt_multiple_scattering.h, reference/prt_multiple_scattering.h,
// gpu/prt_multiple_scattering_gpu.h; docs/prt-multiple-scattering.md). Path "ms".
//   prt/ms/sh      SH on both sides vs an oracle written here (std::sph_legendre without
//                  the Condon–Shortley phase): CPU orthonormality by quadrature, GPU Y(ω)
//                  and M(R)Y(ω) vs the oracle's Y(Rω);
//   prt/ms/tables  C_G vs its closed forms (Y_00, Langevin, limits) on both sides; C_S CPU
//                  (double) vs GPU (float) for silk (1° R lobe);
//   prt/ms/frame   L̃^multi per query, CPU (double) vs GPU (float), directional and SG
//                  lights, on IIRTF cells path traced here; the dot vs a brute-force
//                  ∫ f S cos for a transfer whose c_T is known;
//   prt/ms/accumulate  the estimator of §4.2c summed on the GPU over the CPU bake's samples
//                  of one cell vs the bake's A_C;
//   prt/ms/vglo    V̄_glo (§5.3.2) on both sides and by 004's CPU Monte Carlo vs the closed
//                  form of a quarter-plane shadow cast by a plate (erfc profiles).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "common/prt_multiple_scattering.h"
#include "gpu/prt_multiple_scattering_gpu.h"
#include "common/fiber_shading.h"
#include "reference/bcsdf_sampling.h"
#include "reference/exemplar.h"
#include "reference/prt_multiple_scattering.h"
#include "scene/fabric.h"
#include "validation/case_support.h"
#include "validation/draw_order.h"
#include "validation/harness.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

// The 2-fiber plain-weave block (64 segments) of the accumulate and stderr cases.
Exemplar smallBlock() {
  ExemplarSettings ex;
  ex.fibersPerPly = 2;
  ex.spansPerYarn = 4;
  ex.subdivisions = 1;
  return makePlainWeaveExemplar(ex);
}

CaseResult start(const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "prt-ms";
  r.path = "ms";
  return r;
}

// ---- the oracle (no common/) ---------------------------------------------------
double oracleY(int l, int m, glm::dvec3 w) {
  const double theta = std::acos(std::clamp(w.z, -1.0, 1.0));
  const double phi = std::atan2(w.y, w.x);
  const int am = std::abs(m);
  const double p = std::sph_legendre(unsigned(l), unsigned(am), theta) * ((am % 2) ? -1.0 : 1.0);
  if (m == 0) return p;
  return std::sqrt(2.0) * p * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}
std::vector<double> oracleAll(glm::dvec3 w) {
  std::vector<double> y;
  for (int l = 0; l < FT_SH_BANDS; ++l)
    for (int m = -l; m <= l; ++m) y.push_back(oracleY(l, m, w));
  return y;
}
double langevin(double x) {
  if (x < 1e-3) return x / 3.0 - x * x * x / 45.0 + 2.0 * std::pow(x, 5) / 945.0;
  return 1.0 / std::tanh(x) - 1.0 / x;
}
glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  const glm::dvec3 v = drawVec3<glm::dvec3>(n, rng);
  return v / glm::length(v);
}

// ---- prt/ms/sh -----------------------------------------------------------------
CaseResult runShCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  const auto t0 = Clock::now();
  // CPU orthonormality: 24 Gauss–Legendre-free nodes would not do; a 96 × 96 midpoint grid in
  // (z, φ) integrates products of degree ≤ 10 to ~1e-4 — too coarse for 1e-12, so z uses
  // 48-point Gauss–Legendre computed here (Newton on P_48) and φ a 64-point trapezoid (exact).
  std::vector<double> gx, gw;
  {
    const int n = 48;
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      gx.push_back(z);
      gw.push_back(2.0 / ((1.0 - z * z) * dp * dp));
    }
  }
  std::vector<double> gram(FT_SH_COEFFS * FT_SH_COEFFS, 0.0);
  double cpuOracle = 0.0;
  for (size_t i = 0; i < gx.size(); ++i)
    for (int k = 0; k < 64; ++k) {
      const double z = gx[i], s = std::sqrt(1.0 - z * z), ph = 2.0 * kPi * (k + 0.5) / 64;
      const glm::dvec3 w(s * std::cos(ph), s * std::sin(ph), z);
      const ShCoeffs y = shEval(w);
      if (k % 8 == 0) {
        const std::vector<double> o = oracleAll(w);
        for (int j = 0; j < FT_SH_COEFFS; ++j) cpuOracle = maxKeepNaN(cpuOracle, std::abs(y.c[j] - o[size_t(j)]));
      }
      for (int a = 0; a < FT_SH_COEFFS; ++a)
        for (int b = 0; b < FT_SH_COEFFS; ++b) gram[size_t(a * FT_SH_COEFFS + b)] += gw[i] * (2.0 * kPi / 64) * y.c[a] * y.c[b];
    }
  double orth = 0.0;
  for (int a = 0; a < FT_SH_COEFFS; ++a)
    for (int b = 0; b < FT_SH_COEFFS; ++b)
      orth = maxKeepNaN(orth, std::abs(gram[size_t(a * FT_SH_COEFFS + b)] - (a == b ? 1.0 : 0.0)));
  r.cpuMilliseconds = msSince(t0);

  // GPU: Y(ω) and M(R) Y(ω) for random ω and rotations (rows from a random orthonormal frame).
  std::mt19937_64 rng(42);
  const int n = 512;
  std::vector<glm::vec3> dirs, rx, ry;
  std::vector<glm::dvec3> rxd, ryd, rzd;
  for (int i = 0; i < n; ++i) {
    dirs.push_back(glm::vec3(randomUnit(rng)));
    const glm::dvec3 a = randomUnit(rng);
    glm::dvec3 b = randomUnit(rng);
    b = glm::normalize(b - glm::dot(a, b) * a);
    rx.push_back(glm::vec3(a));
    ry.push_back(glm::vec3(b));
    rxd.push_back(glm::dvec3(glm::vec3(a)));
    ryd.push_back(glm::dvec3(glm::vec3(b)));
    rzd.push_back(glm::cross(glm::dvec3(glm::vec3(a)), glm::dvec3(glm::vec3(b))));
  }
  PrtMultipleScatteringGpu& gpu = ctx.gpu<PrtMultipleScatteringGpu>();
  const auto g0 = Clock::now();
  const std::vector<float> probe = gpu.shProbe(dirs, rx, ry);
  r.gpuMilliseconds = msSince(g0);
  double gpuY = 0.0, gpuRot = 0.0;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 w(dirs[size_t(i)]);
    const std::vector<double> y = oracleAll(w);
    const glm::dvec3 rw(glm::dot(rxd[size_t(i)], w), glm::dot(ryd[size_t(i)], w), glm::dot(rzd[size_t(i)], w));
    const std::vector<double> yr = oracleAll(rw);
    for (int j = 0; j < FT_SH_COEFFS; ++j) {
      gpuY = maxKeepNaN(gpuY, std::abs(double(probe[size_t(i) * 72 + size_t(j)]) - y[size_t(j)]));
      gpuRot = maxKeepNaN(gpuRot, std::abs(double(probe[size_t(i) * 72 + 36 + size_t(j)]) - yr[size_t(j)]));
    }
  }
  r.metrics = {
      Metric{"sh.cpu_oracle_max_abs", cpuOracle, 1e-13, "",
             "CPU Y_lm (double) vs std::sph_legendre without the (−1)^m phase: |Y| ≤ 1.5, rounding ~1e-15"},
      Metric{"sh.orthonormality_max_err", orth, 1e-12, "",
             "|∫ Y_a Y_b − δ_ab| by 48-point Gauss–Legendre × 64-point trapezoid (exact for degree ≤ 10), double"},
      Metric{"sh.gpu_oracle_max_abs", gpuY, 2e-6, "",
             "GPU Y_lm (float) vs the oracle: |Y| ≤ 1.5, float recurrences of ≤ 10 steps: ~10 ulp of 1.5 = 1.8e-6"},
      Metric{"sh.gpu_rotation_max_abs", gpuRot, 1e-5, "",
             "GPU M(R)Y(ω) vs the oracle's Y(Rω): 4 recurrence levels of 3×3 float products, measured ≤ 3e-6"},
      Metric{"sh.gpu_ubo_bindings", double(gpu.uniformBufferBindings()), 1e9, "count",
             fmt::format("GL_MAX_UNIFORM_BUFFER_BINDINGS of this driver; FT_UBO_PRT_MS = {}", FT_UBO_PRT_MS), false},
      nonFiniteMetric("gpu", nonFiniteCount(probe), "GPU Y and M(R)Y values"),
  };
  r.finish();
  return r;
}

// ---- prt/ms/tables -------------------------------------------------------------
CaseResult runTablesCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  const FabricParams p = findFabricPreset("silk").params();
  const auto t0 = Clock::now();
  const PrtMsTables cpu = prtMsTablesCpu(p);
  r.cpuMilliseconds = msSince(t0);
  PrtMultipleScatteringGpu& gpu = ctx.gpu<PrtMultipleScatteringGpu>();
  const auto g0 = Clock::now();
  const PrtMsGpuTables g = gpu.tables(p);
  r.gpuMilliseconds = msSince(g0);
  const double y00 = 1.0 / std::sqrt(4.0 * kPi), k1 = std::sqrt(3.0 / (4.0 * kPi));
  double cg0 = 0.0, cg1 = 0.0, gcg0 = 0.0, gcg1 = 0.0, limits = 0.0;
  for (int k = 0; k < cpu.lambdaNodes; ++k) {
    const double u = double(k) / (cpu.lambdaNodes - 1), lambda = u / (1.0 - u);
    const double e1 = k == cpu.lambdaNodes - 1 ? k1 : k1 * langevin(lambda);
    cg0 = maxKeepNaN(cg0, std::abs(cpu.cg[size_t(k) * FT_SH_BANDS] - y00));
    cg1 = maxKeepNaN(cg1, std::abs(cpu.cg[size_t(k) * FT_SH_BANDS + 1] - e1));
    gcg0 = maxKeepNaN(gcg0, std::abs(double(g.cg[size_t(k) * FT_SH_BANDS]) - y00));
    gcg1 = maxKeepNaN(gcg1, std::abs(double(g.cg[size_t(k) * FT_SH_BANDS + 1]) - e1));
  }
  for (int l = 0; l < FT_SH_BANDS; ++l) {  // λ = 0: only l = 0; λ = ∞: √((2l + 1)/4π)
    limits = maxKeepNaN(limits, std::abs(cpu.cg[size_t(l)] - (l == 0 ? y00 : 0.0)));
    limits = maxKeepNaN(limits, std::abs(cpu.cg[size_t(cpu.lambdaNodes - 1) * FT_SH_BANDS + size_t(l)] -
                                         std::sqrt((2 * l + 1) / (4.0 * kPi))));
  }
  double scale = 0.0, csErr = 0.0;
  size_t worst = 0;
  for (size_t i = 0; i < cpu.cs.size(); ++i) {
    scale = std::max(scale, std::abs(cpu.cs[i]));
    const double e = std::abs(cpu.cs[i] - double(g.cs[i]));
    if (!(e <= csErr)) worst = i;
    csErr = maxKeepNaN(csErr, e);
  }
  const std::vector<double> phiCpu = prtMsPhiCpu(p, FT_MS_THETA_I_NODES, FT_MS_PHI_NODES);
  double phiErr = 0.0, phiScale = 0.0;
  for (size_t i = 0; i < phiCpu.size(); ++i) {
    phiErr = maxKeepNaN(phiErr, std::abs(phiCpu[i] - double(g.phi[i])));
    phiScale = std::max(phiScale, std::abs(phiCpu[i]));
  }
  r.details = fmt::format("worst C_S: θ_o row {}, j {}, channel {}: cpu {:.8g} gpu {:.8g}", worst / 108, worst / 3 % 36,
                          worst % 3, cpu.cs[worst], g.cs[worst]);
  r.metrics = {
      Metric{"cg.l0_max_abs", cg0, 1e-12, "", "CPU C_G[λ, 0] = Y_00 = 0.28209 for every λ (normalized SG), double"},
      Metric{"cg.l1_max_abs", cg1, 1e-10, "", "CPU C_G[λ, 1] = √(3/4π)(coth λ − 1/λ) (Langevin), double quadrature"},
      Metric{"cg.limits_max_abs", limits, 1e-12, "", "λ = 0: δ_l0 Y_00; λ → ∞: √((2l + 1)/4π) (the grid's end nodes)"},
      Metric{"cg.gpu_l0_max_abs", gcg0, 4e-6, "",
             "GPU C_G[λ, 0] vs Y_00: 128 float terms summed, then scaled by K/(1 − e^{−2λ}): ~128 ulp of 0.28 = "
             "4e-6 worst (measured 1.8e-6)"},
      Metric{"cg.gpu_l1_max_abs", gcg1, 2e-6, "", "GPU C_G[λ, 1] vs Langevin: float quadrature, P_1(1 − τ/λ) cancels near τ = λ"},
      Metric{"phi.gpu_max_abs", phiErr, 2e-5 * phiScale, "",
             fmt::format("GPU Φ_p,j(θ_i) (float, 512 φ terms) vs CPU (double): 2e-5 of the largest ({:.4g}); a loop cut "
                         "short by llvmpipe's 65,535-iteration budget shows as O(1)",
                         phiScale)},
      Metric{"cs.gpu_max_abs", csErr, 2e-4 * scale, "",
             fmt::format("GPU C_S (float) vs CPU (double), silk: 2,048-term sums of float lobes; 2e-4 of the largest "
                         "entry ({:.4g}), the float sum's ~√n·ulp growth with margin",
                         scale)},
      nonFiniteMetric("cpu", nonFiniteCount(cpu.cs) + nonFiniteCount(cpu.cg), "CPU C_S and C_G"),
      nonFiniteMetric("gpu", nonFiniteCount(g.cs) + nonFiniteCount(g.cg) + nonFiniteCount(g.phi), "GPU Φ, C_S and C_G"),
  };
  r.finish();
  return r;
}

// ---- prt/ms/frame --------------------------------------------------------------
struct MsFrameSetup {
  PrtMsTables tables;
  std::vector<std::vector<double>> cells;  // A_C per cell
  std::vector<float> transfer;
  Exemplar block;
  double ell = 0.0;
  size_t nonEmpty = 0;
  uint64_t rays = 0;
  double bakeMs = 0.0;
};

CaseResult runFrameCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  const FabricParams p = findFabricPreset("fleece").params();
  const auto t0 = Clock::now();
  MsFrameSetup s;
  s.tables = prtMsTablesCpu(p, 1024, 256);
  ExemplarSettings ex;
  ex.fibersPerPly = 2;
  ex.spansPerYarn = 4;
  ex.subdivisions = 1;
  s.block = makePlainWeaveExemplar(ex);
  IirtfSettings is;
  is.tiles = 3;
  is.pathsPerCell = 1500;
  is.ellPaths = 300;
  const IirtfScene scene(tileExemplar(s.block, is.tiles));
  const MeanFreePath ell = estimateMeanFreePath(scene, s.block, is.tiles, p, is);
  s.ell = ell.ell;
  const IirtfCells cells = makeIirtfCells(s.block, s.block.period / 2.0);
  const auto b0 = Clock::now();
  for (size_t c = 0; c < cells.count() && s.nonEmpty < 4; ++c) {
    if (cells.members[c].empty()) continue;
    IirtfCell cell = iirtfCellCpu(scene, s.block, is.tiles, p, is, cells.members[c]);
    s.rays += cell.rays;
    s.cells.push_back(cell.a);
    ++s.nonEmpty;
  }
  s.bakeMs = msSince(b0);
  for (const std::vector<double>& a : s.cells)
    for (double v : a) s.transfer.push_back(float(v));
  // The CPU evaluates with the float matrices and tables the GPU gets, so the comparison is of the arithmetic.
  PrtMsTables tf = s.tables;
  for (double& v : tf.cs) v = double(float(v));
  for (double& v : tf.cg) v = double(float(v));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<PrtMsQuery> queries;
  for (int i = 0; i < 1024; ++i) {
    PrtMsQuery q{};
    const glm::dvec3 wo = glm::normalize(randomUnit(rng) + glm::dvec3(0, 0, 1.2));
    q.wo = vec4(glm::vec3(wo), 0.0f);
    q.tangent = vec4(glm::vec3(randomUnit(rng)), 0.0f);
    const glm::dvec3 l = glm::normalize(randomUnit(rng) + glm::dvec3(0, 0, 1.0));
    const double lambda = i % 2 ? 0.0 : std::exp(std::log(0.1) + u(rng) * (std::log(2000.0) - std::log(0.1)));
    q.light = vec4(glm::vec3(l), float(lambda));
    q.cell = uvec4(uint32_t(i % int(s.cells.size())), 0u, 0u, 0u);
    queries.push_back(q);
  }
  std::vector<glm::dvec3> cpu(queries.size());
  std::vector<double> bound(queries.size());
  std::vector<std::vector<double>> af(s.cells.size());
  for (size_t c = 0; c < s.cells.size(); ++c)
    af[c].assign(s.transfer.begin() + std::ptrdiff_t(c * kIirtfMatrixSize),
                 s.transfer.begin() + std::ptrdiff_t((c + 1) * kIirtfMatrixSize));
  for (size_t i = 0; i < queries.size(); ++i) {
    cpu[i] = prtMsRadianceCpu(tf, af[queries[i].cell.x], FT_SH_BANDS, queries[i]);
    // ‖c_T‖‖c_S‖ per query (any channel's max): the scale of the dot's rounding.
    const glm::dvec3 wo(queries[i].wo), t(queries[i].tangent), lt(queries[i].light);
    const ShCoeffs cd = shEval(lt);
    const glm::dvec3 lk = prtMsCsLookup(prtMsThetaO(t, wo), tf.thetaO);
    double b = 0.0;
    for (int ch = 0; ch < 3; ++ch) {
      double nt = 0.0, ns = 0.0;
      for (int j1 = 0; j1 < FT_SH_COEFFS; ++j1) {
        double sum = 0.0;
        for (int j0 = 0; j0 < FT_SH_COEFFS; ++j0)
          sum += std::abs(af[queries[i].cell.x][(size_t(ch) * FT_SH_COEFFS + size_t(j1)) * FT_SH_COEFFS + size_t(j0)] * cd.c[j0]);
        nt += sum * sum;
        const double sv = std::max(std::abs(tf.cs[(size_t(lk.x) * FT_SH_COEFFS + size_t(j1)) * 3 + size_t(ch)]),
                                   std::abs(tf.cs[(size_t(lk.y) * FT_SH_COEFFS + size_t(j1)) * 3 + size_t(ch)]));
        ns += sv * sv;
      }
      b = std::max(b, std::sqrt(nt) * std::sqrt(ns));
    }
    bound[i] = b;
  }
  r.cpuMilliseconds = msSince(t0);
  PrtMultipleScatteringGpu& gpu = ctx.gpu<PrtMultipleScatteringGpu>();
  std::vector<float> csf(tf.cs.begin(), tf.cs.end()), cgf(tf.cg.begin(), tf.cg.end());
  const auto g0 = Clock::now();
  const std::vector<glm::vec3> g = gpu.evaluate(queries, s.transfer, FT_SH_BANDS, csf, tf.thetaO, cgf, tf.lambdaNodes);
  r.gpuMilliseconds = msSince(g0);
  double worstRatio = 0.0, maxRel = 0.0, meanL = 0.0;
  size_t worst = 0;
  uint64_t nonFiniteGpu = 0, nonFiniteCpu = 0;
  for (size_t i = 0; i < queries.size(); ++i)
    for (int ch = 0; ch < 3; ++ch) {
      if (!std::isfinite(g[i][ch])) ++nonFiniteGpu;
      if (!std::isfinite(cpu[i][ch])) ++nonFiniteCpu;
      const double e = std::abs(double(g[i][ch]) - cpu[i][ch]);
      const double ratio = e / (1e-4 * bound[i] + 1e-6);
      if (!(ratio <= worstRatio)) worst = i;
      worstRatio = maxKeepNaN(worstRatio, ratio);
      maxRel = maxKeepNaN(maxRel, e / std::max(1e-3, std::abs(cpu[i][ch])));
      meanL += cpu[i][ch] / double(3 * queries.size());
    }
  r.details = fmt::format("worst query {} (cell {}, λ {}): cpu ({:.6g}, {:.6g}, {:.6g}) gpu ({:.6g}, {:.6g}, {:.6g}), "
                          "‖c_T‖‖c_S‖ {:.4g}",
                          worst, queries[worst].cell.x, queries[worst].light.w, cpu[worst].x, cpu[worst].y, cpu[worst].z,
                          g[worst].x, g[worst].y, g[worst].z, bound[worst]);

  // Independent: a transfer whose c_T is f whatever the light (a[0, j1] = √(4π) f_j1) makes
  // L̃ = ∫ f S cos dω_i; f random, brute force here about t with the oracle's Y and bcsdf.h.
  std::normal_distribution<double> nd;
  std::vector<double> f(FT_SH_COEFFS), a(kIirtfMatrixSize, 0.0);
  for (double& v : f) v = nd(rng);
  f[0] += 4.0;
  for (int ch = 0; ch < 3; ++ch)
    for (int j1 = 0; j1 < FT_SH_COEFFS; ++j1) a[(size_t(ch) * FT_SH_COEFFS + size_t(j1)) * FT_SH_COEFFS] = std::sqrt(4 * kPi) * f[size_t(j1)];
  double bruteRel = 0.0;
  for (int trial = 0; trial < 2; ++trial) {
    const glm::dvec3 tt = randomUnit(rng), wo = randomUnit(rng);
    PrtMsQuery q{};
    q.wo = vec4(glm::vec3(wo), 0.0f);
    q.tangent = vec4(glm::vec3(tt), 0.0f);
    q.light = vec4(0.0f, 0.0f, 1.0f, 0.0f);
    const glm::dvec3 L = prtMsRadianceCpu(s.tables, a, FT_SH_BANDS, q);
    const glm::dvec3 u0 = glm::normalize(std::abs(tt.x) < 0.9 ? glm::cross(tt, glm::dvec3(1, 0, 0)) : glm::cross(tt, glm::dvec3(0, 1, 0)));
    const glm::dvec3 v0 = glm::cross(tt, u0);
    const int nt = 512, np = 128;
    glm::dvec3 B(0.0);
    for (int i = 0; i < nt; ++i) {
      const double th = -kPi / 2 + (i + 0.5) * kPi / nt;
      for (int k = 0; k < np; ++k) {
        const double ph = 2 * kPi * (k + 0.5) / np;
        const glm::dvec3 w = std::sin(th) * tt + std::cos(th) * (std::cos(ph) * u0 + std::sin(ph) * v0);
        const std::vector<double> y = oracleAll(w);
        double fv = 0.0;
        for (int j = 0; j < FT_SH_COEFFS; ++j) fv += f[size_t(j)] * y[size_t(j)];
        const glm::vec3 sv = ftBcsdf(p, ftFiberAngles(glm::vec3(tt), glm::vec3(w), glm::vec3(wo)));
        B += glm::dvec3(sv) * (fv * std::cos(th) * std::cos(th) * (kPi / nt) * (2 * kPi / np));
      }
    }
    for (int ch = 0; ch < 3; ++ch) bruteRel = maxKeepNaN(bruteRel, std::abs(L[ch] - B[ch]) / std::max(1e-6, std::abs(B[ch])));
  }
  r.metrics = {
      Metric{"radiance.max_ratio", worstRatio, 1.0, "of bound",
             "|GPU − CPU| / (1e-4‖c_T‖‖c_S‖ + 1e-6) per query and channel (notes-appearance §7.6): float rotation, "
             "36×36 mat-vec and 36-term dot on the same float inputs"},
      Metric{"radiance.max_rel", maxRel, 1e9, "relative", "|GPU − CPU| / max(1e-3, |CPU|), for reading", false},
      Metric{"dot.brute_force_rel", bruteRel, 2e-3, "relative",
             "L̃ with c_T = f (random, L = 5) vs ∫ f S cos dω_i by a 512 × 128 grid about t (oracle Y, fleece): "
             "C_S rows 0.35° apart lerped, ≤ 1e-4; the grid ≤ 1e-3"},
      Metric{"radiance.mean", meanL, 1e9, "", "mean L̃^multi over the queries (unit irradiance / unit SG)", false},
      Metric{"iirtf.cells", double(s.cells.size()), 1e9, "count",
             fmt::format("{}; ℓ = {:.4g} (P = {:.4g}), cells of side P/2, {} paths per cell, {} rays in {:.0f} ms = "
                         "{:.3g} rays/s",
                         s.block.label, s.ell, s.block.period, is.pathsPerCell, s.rays, s.bakeMs,
                         double(s.rays) / std::max(1e-3, s.bakeMs * 1e-3)),
             false},
      nonFiniteMetric("cpu", nonFiniteCpu + nonFiniteCount(s.transfer), "CPU radiances and A_C entries"),
      nonFiniteMetric("gpu", nonFiniteGpu, "GPU radiances"),
  };
  r.finish();
  return r;
}

// ---- prt/ms/end-to-end ------------------------------------------------------------
// 004 §5.3.1 against path tracing (§7.4c of the notes): the flat tiled fabric under a directional
// light ω_d, orthographic eye rays along −ω_o over the centre block; at each first hit y (segment
// k): truth = E[h(ω_i)/p(ω_i) · T(ω_d, ω_i, y)] with ω_i from the BCSDF sampling and T the path
// radiance from y (reference/prt_multiple_scattering.h), PRT = L̃ from A_C of k's cell. The
// relative error of the average intensity over the image, per SH order L; L = 4 gates.
CaseResult runEndToEndCase(ValidationContext&, const std::string& name) {
  CaseResult r = start(name);
  r.path = "";
  const FabricParams p = findFabricPreset("fleece").params();
  const auto t0 = Clock::now();
  const PrtMsTables tables = prtMsTablesCpu(p, 1024, 256);
  // The preset's fiber count (7,680 segments): on the sparse 6-fibers-per-ply CI block few paths
  // scatter and L̃ at low L was several times the truth (docs/prt-multiple-scattering.md).
  ExemplarSettings ex;
  ex.fibersPerPly = 0;
  const Exemplar block = makePlainWeaveExemplar(ex);
  IirtfSettings is;
  is.tiles = 5;  // grazing light reaches the centre block through the tiling's sides less
  is.pathsPerCell = 3000;
  is.ellPaths = 300;
  const IirtfScene scene(tileExemplar(block, is.tiles));
  const MeanFreePath ell = estimateMeanFreePath(scene, block, is.tiles, p, is);
  const IirtfCells cells = makeIirtfCells(block, ell.ell > 0.0 ? 2.0 * ell.ell : block.period / 2.0);  // ℓ̃ = 2ℓ (004: ≤ 2ℓ)
  std::vector<std::vector<double>> A(cells.count());
  uint64_t rays = 0;
  const auto b0 = Clock::now();
  for (size_t c = 0; c < cells.count(); ++c) {
    IirtfCell cell = iirtfCellCpu(scene, block, is.tiles, p, is, cells.members[c]);
    rays += cell.rays;
    A[c] = std::move(cell.a);
  }
  const double bakeSeconds = msSince(b0) * 1e-3;
  const glm::vec3 wd = glm::normalize(glm::vec3(0.5f, 0.2f, 0.84f));
  const glm::vec3 wo = glm::normalize(glm::vec3(-0.3f, 0.1f, 0.95f));
  ShadingParams light{};
  light.fabric = p;
  light.lightDirection[0] = vec4(wd, 0.0f);
  light.lightIrradiance[0] = vec4(1.0f);
  light.flags = uvec4(1u, FT_SHADING_KHUNGURN, 0u, 0u);
  double ztop = -1e30;
  for (const ExemplarSegment& sg : block.segments) ztop = std::max({ztop, double(sg.a.z), double(sg.b.z)});
  const int side = 24, spp = 24;
  const size_t S = block.segments.size();
  glm::dvec3 truth(0.0), truthMid(0.0);
  double sampleSq = 0.0;  // Σ over camera samples of (intensity)², for the truth's standard error
  uint64_t samples = 0;
  std::vector<glm::dvec3> prt(FT_SH_BANDS, glm::dvec3(0.0));
  uint64_t hits = 0, truthRays = 0;
  for (int py = 0; py < side; ++py)
    for (int px = 0; px < side; ++px) {
      const glm::vec3 target(float((px + 0.5) / side * block.period), float((py + 0.5) / side * block.period), 0.0f);
      const glm::vec3 org = target + wo * float((ztop + 2.0 * block.reach) / wo.z);
      IirtfScene::Hit hit;
      if (!scene.intersect(org, -wo, 0xFFFFFFFFu, hit)) continue;
      const uint32_t seg = hit.segment;
      const uint32_t k = uint32_t(seg % S);
      const ExemplarSegment& sgm = scene.segments()[seg];
      const glm::vec3 y = org - wo * hit.t, t = glm::normalize(sgm.b - sgm.a);
      ++hits;
      const FiberScatter sc(light, t, hit.normal, wo);
      for (int i = 0; i < spp; ++i) {
        RandomStream rng(uint32_t(py * side + px), uint32_t(i), 0xE2Eu);
        const glm::vec3 wi = sc.sample(rng);
        const glm::dvec3 w = glm::dvec3(sc.weight(wi));
        const glm::dvec3 v = w * iirtfPathRadiance(scene, p, 1.0, is.maxDepth, y, sgm.fiber, wd, wi,
                                                   uint32_t(py * side + px), uint32_t(i), 0xE2Fu, truthRays);
        truth += v / double(spp);
        // The same estimate at the segment's midpoint μ_k, where the IIRTF is defined (004 §4.2b).
        truthMid += w * iirtfPathRadiance(scene, p, 1.0, is.maxDepth, sgm.mid(), sgm.fiber, wd, wi,
                                          uint32_t(py * side + px), uint32_t(i), 0xE2Fu, truthRays) / double(spp);
        const double vi = (v.x + v.y + v.z) / 3.0;
        sampleSq += vi * vi;
        ++samples;
      }
      PrtMsQuery q{};
      q.wo = vec4(wo, 0.0f);
      q.tangent = vec4(t, 0.0f);
      q.light = vec4(wd, 0.0f);
      q.cell = uvec4(cells.cellOf[k], 0u, 0u, 0u);
      for (int bands = 1; bands <= FT_SH_BANDS; ++bands) prt[size_t(bands - 1)] += prtMsRadianceCpu(tables, A[cells.cellOf[k]], bands, q);
    }
  r.cpuMilliseconds = msSince(t0);
  auto intensity = [](glm::dvec3 v) { return (v.x + v.y + v.z) / 3.0; };
  const double ti = intensity(truth);
  const double tm = intensity(truthMid);
  std::vector<double> rel(FT_SH_BANDS), relMid(FT_SH_BANDS);
  std::string perL, perLMid;
  for (int l = 0; l < FT_SH_BANDS; ++l) {
    rel[size_t(l)] = std::abs(intensity(prt[size_t(l)]) - ti) / std::max(1e-12, std::abs(ti));
    perL += fmt::format("{}L={}: {:.3f}", l ? ", " : "", l, rel[size_t(l)]);
    relMid[size_t(l)] = std::abs(intensity(prt[size_t(l)]) - tm) / std::max(1e-12, std::abs(tm));
    perLMid += fmt::format("{}L={}: {:.3f}", l ? ", " : "", l, relMid[size_t(l)]);
  }
  const double raysPerSecond = double(rays) / std::max(1e-6, bakeSeconds);
  // Standard error of the truth's mean intensity (per sample variance / samples), relative.
  const double meanSample = ti / double(std::max<uint64_t>(1, hits));
  const double var = sampleSq / double(std::max<uint64_t>(1, samples)) - meanSample * meanSample;
  const double sigmaRel = std::sqrt(std::max(0.0, var) / double(std::max<uint64_t>(1, samples))) / std::max(1e-30, meanSample);
  r.details = fmt::format("{} hits of {}², {} spp; truth mean {:.5g}, PRT L=4 mean {:.5g}; ℓ = {:.4g}, {} cells ({}×{}×{})",
                          hits, side, spp, ti / double(std::max<uint64_t>(1, hits)),
                          intensity(prt[4]) / double(std::max<uint64_t>(1, hits)), ell.ell, cells.count(), cells.nx,
                          cells.ny, cells.nz);
  r.metrics = {
      Metric{"e2e.rel_err_L4", rel[4], 3.0 * sigmaRel + 0.10, "relative",
             fmt::format("|avg L̃^multi − avg path-traced multiple scattering| / avg, L = 4 (Fleece's order, 004 Table 1); "
                         "all L: {}. Tolerance: 3σ of the truth's Monte Carlo mean (σ = {:.3f}, measured) + 0.10 for the "
                         "approximation itself (cell average at μ_k for the hit, SH truncation, A_C noise of 3,000 "
                         "paths per cell; measured 0.06 at L = 4, 0.04–0.25 at L = 1–5)",
                         perL, sigmaRel)},
      Metric{"e2e.rel_err_mid_L4", relMid[4], 1e9, "relative",
             fmt::format("the same against the path-traced estimate at the hit segment's midpoint μ_k (where the "
                         "IIRTF is defined), all L: {}; truth at μ_k / truth at the hit: {:.3f}",
                         perLMid, tm / std::max(1e-30, ti)),
             false},
      Metric{"e2e.truth_sigma_rel", sigmaRel, 1e9, "relative", "standard error of the path-traced mean intensity", false},
      Metric{"e2e.rel_err_L0", rel[0], 1e9, "relative", "the same with L = 0 (for reading)", false},
      Metric{"iirtf.rays_per_second", raysPerSecond, 1e18, "rays/s",
             fmt::format("IIRTF bake here: {} rays in {:.2f} s (TBB, this machine's cores)", rays, bakeSeconds), false},
      nonFiniteMetric("cpu", uint64_t(!std::isfinite(ti)) + uint64_t(!std::isfinite(intensity(prt[4]))), "averages"),
  };
  r.finish();
  return r;
}

// ---- prt/ms/vglo ------------------------------------------------------------------
// V̄_glo of 004 §5.3.2 against its closed form: an opaque quarter plate {x < a, y < b} at height
// H above the flat fabric (z = 0) under a directional light ω_d shadows the quarter plane
// {x < x_s, y < y_s}, x_s = a − H ω_x/ω_z (ray–plane test written here). Gaussian-filtered with
// std σ over the unbounded plane: V̄(x, y) = 1 − Φ((x_s − x)/σ) Φ((y_s − y)/σ), Φ the normal CDF.
// Compared: the CPU filter (double) and the GPU filter (float) of the texel grid, 004's CPU Monte
// Carlo estimator (x′ drawn from the Gaussian) in z-scores, and constant V → 1 on both sides.
CaseResult runVgloCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  const auto t0 = Clock::now();
  const int n = 128;                    // texels per side of the unit fabric square
  const double texel = 1.0 / n, sigma = 0.04;  // σ_glo = 5.12 texels
  const glm::dvec3 wd = glm::normalize(glm::dvec3(0.3, 0.2, 0.9));
  const double H = 0.3, xs = 64.0 / n, ys = 72.0 / n;  // the shadow's corner on texel boundaries
  const double a = xs + H * wd.x / wd.z, b = ys + H * wd.y / wd.z;
  auto visible = [&](glm::dvec2 x) {  // the shadow ray from (x, 0) towards ω_d against the plate z = H
    const double t = H / wd.z;
    const glm::dvec2 q = x + t * glm::dvec2(wd.x, wd.y);
    return (q.x < a && q.y < b) ? 0.0 : 1.0;
  };
  auto Phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  auto closed = [&](glm::dvec2 x) { return 1.0 - Phi((xs - x.x) / sigma) * Phi((ys - x.y) / sigma); };
  std::vector<double> v(size_t(n) * n), ones(size_t(n) * n, 1.0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) v[size_t(y) * n + size_t(x)] = visible(glm::dvec2((x + 0.5) * texel, (y + 0.5) * texel));
  const std::vector<double> cpu = prtMsVgloFilterCpu(v, n, n, texel, sigma);
  const std::vector<double> cpuOnes = prtMsVgloFilterCpu(ones, n, n, texel, sigma);
  double cpuErr = 0.0, cpuOnesErr = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const size_t i = size_t(y) * n + size_t(x);
      cpuErr = maxKeepNaN(cpuErr, std::abs(cpu[i] - closed(glm::dvec2((x + 0.5) * texel, (y + 0.5) * texel))));
      cpuOnesErr = maxKeepNaN(cpuOnesErr, std::abs(cpuOnes[i] - 1.0));
    }
  // 004's CPU estimator: 4,096 Gaussian draws at 48 points on a line through the corner.
  const int points = 48, draws = 4096;
  double maxZ = 0.0, rms40 = 0.0;
  for (int i = 0; i < points; ++i) {
    const double s = (i + 0.5) / points;
    const glm::dvec2 x(xs - 3.0 * sigma + 6.0 * sigma * s, ys - 2.0 * sigma + 4.0 * sigma * s);
    const double p = closed(x);
    const double mc = prtMsVgloSampleCpu(visible, x, sigma, draws, uint32_t(i), 0x61u);
    const double sd = std::sqrt(std::max(p * (1.0 - p), 1.0 / draws) / draws);
    maxZ = maxKeepNaN(maxZ, std::abs(mc - p) / sd);
    const double mc40 = prtMsVgloSampleCpu(visible, x, sigma, 40, uint32_t(i), 0x62u);
    rms40 += (mc40 - p) * (mc40 - p) / points;
  }
  rms40 = std::sqrt(rms40);
  r.cpuMilliseconds = msSince(t0);
  PrtMultipleScatteringGpu& gpu = ctx.gpu<PrtMultipleScatteringGpu>();
  const std::vector<float> vf(v.begin(), v.end()), onesf(ones.begin(), ones.end());
  const auto g0 = Clock::now();
  const std::vector<float> g = gpu.vgloFilter(vf, n, n, float(texel), float(sigma));
  const std::vector<float> gOnes = gpu.vgloFilter(onesf, n, n, float(texel), float(sigma));
  r.gpuMilliseconds = msSince(g0);
  double gpuCpu = 0.0, gpuErr = 0.0, gpuOnesErr = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const size_t i = size_t(y) * n + size_t(x);
      gpuCpu = maxKeepNaN(gpuCpu, std::abs(double(g[i]) - cpu[i]));
      gpuErr = maxKeepNaN(gpuErr, std::abs(double(g[i]) - closed(glm::dvec2((x + 0.5) * texel, (y + 0.5) * texel))));
      gpuOnesErr = maxKeepNaN(gpuOnesErr, std::abs(double(gOnes[i]) - 1.0));
    }
  r.details = fmt::format("{}² texels of {:.4g}, σ_glo = {} ({:.2f} texels), shadow corner ({}, {}); MC {} points × {} draws",
                          n, texel, sigma, sigma / texel, xs, ys, points, draws);
  r.metrics = {
      Metric{"vglo.cpu_closed_form_max_abs", cpuErr, 1e-3, "visibility",
             "CPU filter vs 1 − Φ((x_s − x)/σ)Φ((y_s − y)/σ), all texels. Tolerance: per axis the midpoint rule "
             "of a half-line Gaussian sum (Euler–Maclaurin, h²/24σ² · max|φ′| = 3.8e-4 at σ = 5.12 texels) + the "
             "4σ truncation (6e-5); two axes at the corner: 8.9e-4; measured 6.7e-4"},
      Metric{"vglo.gpu_closed_form_max_abs", gpuErr, 1e-3 + 1e-5, "visibility", "the GPU filter likewise (+ float rounding)"},
      Metric{"vglo.gpu_cpu_max_abs", gpuCpu, 1e-5, "visibility",
             "GPU (float) vs CPU (double) filter: ≤ 43 taps of weights ≤ 1 per pass, two passes (~40 ulp of 1)"},
      Metric{"vglo.constant_cpu_max_abs", cpuOnesErr, 1e-12, "visibility", "V ≡ 1 → V̄ ≡ 1, edges included (the ∫_A K normalisation)"},
      Metric{"vglo.constant_gpu_max_abs", gpuOnesErr, 1e-6, "visibility", "the same on the GPU (float)"},
      Metric{"vglo.mc_max_z", maxZ, 5.0, "sigma",
             fmt::format("004's CPU estimator (x′ from the Gaussian, {} draws, V by the ray–plate test) vs the closed "
                         "form at {} points: max |z| with the binomial σ (chance of > 5 in 48 points: 3e-5)",
                         draws, points)},
      Metric{"vglo.mc40_rms", rms40, 1e9, "visibility",
             "the same with 004's 40 samples per fragment (for reading: ≈ 0.5/√40 = 0.08 at most)", false},
      nonFiniteMetric("cpu", nonFiniteCount(cpu), "CPU V̄_glo"),
      nonFiniteMetric("gpu", nonFiniteCount(g), "GPU V̄_glo"),
  };
  r.finish();
  return r;
}

// ---- prt/ms/accumulate ------------------------------------------------------------
// The IIRTF estimator of 004 §4.2c accumulated on the GPU (notes §7.5's bake twin) over the very
// samples the CPU bake draws for one cell (same streams: directions from (k, i, seed), the walk
// from its own), against the bake's A_C (iirtfCellCpu, double).
CaseResult runAccumulateCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  const FabricParams p = findFabricPreset("fleece").params();
  const auto t0 = Clock::now();
  const Exemplar block = smallBlock();
  IirtfSettings is;
  is.tiles = 3;
  is.pathsPerCell = 4000;
  const IirtfScene scene(tileExemplar(block, is.tiles));
  const IirtfCells cells = makeIirtfCells(block, block.period / 2.0);
  size_t cellIndex = 0;
  while (cellIndex + 1 < cells.count() && cells.members[cellIndex].empty()) ++cellIndex;
  const std::vector<uint32_t>& members = cells.members[cellIndex];
  const IirtfCell cell = iirtfCellCpu(scene, block, is.tiles, p, is, members);
  // The bake's samples, re-drawn: path i of segment k as reference/prt_multiple_scattering.cpp draws it.
  const size_t S = block.segments.size();
  const uint32_t perSegment = uint32_t((size_t(is.pathsPerCell) + members.size() - 1) / members.size());
  std::vector<PrtMsSample> samples;
  std::vector<double> absSum(kIirtfMatrixSize, 0.0);
  uint64_t rays = 0, nonZero = 0;
  for (uint32_t k : members) {
    const ExemplarSegment& own = scene.segments()[centreCopy(is.tiles) * S + k];
    for (uint32_t i = 0; i < perSegment; ++i) {
      RandomStream rng(k, i, is.seed);
      const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next(), u3 = rng.next();
      glm::dvec3 w0, w1;
      iirtfDirections(u0, u1, u2, u3, w0, w1);
      const glm::dvec3 T = iirtfPathRadiance(scene, p, is.albedo, is.maxDepth, own.mid(), own.fiber, glm::vec3(w0),
                                             glm::vec3(w1), k, i, is.seed, rays);
      PrtMsSample smp{};
      smp.w0 = vec4(glm::vec3(w0), 0.0f);
      smp.w1 = vec4(glm::vec3(w1), 0.0f);
      smp.t = vec4(glm::vec3(T), 0.0f);
      samples.push_back(smp);
      nonZero += (T.x != 0.0 || T.y != 0.0 || T.z != 0.0) ? 1u : 0u;
      const ShCoeffs y0 = shEval(w0), y1 = shEval(w1);
      for (int ch = 0; ch < 3; ++ch)
        for (int j1 = 0; j1 < FT_SH_COEFFS; ++j1)
          for (int j0 = 0; j0 < FT_SH_COEFFS; ++j0)
            absSum[(size_t(ch) * FT_SH_COEFFS + size_t(j1)) * FT_SH_COEFFS + size_t(j0)] +=
                std::abs(T[ch] * y1.c[j1] * y0.c[j0]) * 8.0 * kPi * kPi / double(cell.paths);
    }
  }
  r.cpuMilliseconds = msSince(t0);
  PrtMultipleScatteringGpu& gpu = ctx.gpu<PrtMultipleScatteringGpu>();
  const auto g0 = Clock::now();
  const std::vector<double> g = gpu.accumulateIirtf(samples);
  r.gpuMilliseconds = msSince(g0);
  double worst = 0.0, maxA = 0.0;
  for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
    worst = maxKeepNaN(worst, std::abs(g[i] - cell.a[i]) / std::max(absSum[i], 1e-300));
    maxA = std::max(maxA, std::abs(cell.a[i]));
  }
  r.details = fmt::format("cell {} ({} segments), {} samples ({} with T ≠ 0), {} rays; max |a| {:.4g}", cellIndex,
                          members.size(), samples.size(), nonZero, rays, maxA);
  r.metrics = {
      Metric{"accumulate.max_rel_abs_sum", worst, 1.3e-4, "relative",
             "per entry |A_GPU − A_CPU| / Σ|terms| (the bake's A_C in double vs float sums over chunks of 2,048 "
             "samples added in double). Tolerance: the float summation bound 2,048 · 2⁻²⁴ = 1.2e-4 of Σ|terms| "
             "(plus the products' rounding)"},
      Metric{"accumulate.samples_match", double(samples.size() == cell.paths ? 0 : 1), 0.0, "flag",
             "the re-drawn sample count equals the bake's paths for the cell"},
      nonFiniteMetric("cpu", nonFiniteCount(cell.a), "CPU A_C"),
      nonFiniteMetric("gpu", nonFiniteCount(g), "GPU A_C"),
  };
  r.finish();
  return r;
}

// ---- prt/ms/stderr ------------------------------------------------------------------
// The standard error the IIRTF bake stores with A_C (IirtfCell::stdError: per-path second
// moments, stratified over the cell's segments) against what it estimates: the spread of A_C
// over bakes with different seeds, computed here from the repeated bakes alone (no code of the
// estimate). Per band l = max(l1, l0) the ratio of the summed seed variances to the summed
// claimed variances (1 for a right estimate), and each bake against the mean of the others in
// units of the claimed σ.
CaseResult runStdErrorCase(ValidationContext&, const std::string& name) {
  CaseResult r = start(name);
  const auto t0 = Clock::now();
  const FabricParams p = findFabricPreset("fleece").params();
  const Exemplar block = smallBlock();
  IirtfSettings is;
  is.tiles = 3;
  is.pathsPerCell = 600;  // 200 per segment
  const IirtfScene scene(tileExemplar(block, is.tiles));
  const std::vector<uint32_t> members = {3, 17, 40};
  constexpr int R = 24;
  std::vector<std::vector<double>> a(R), se(R);
  for (int k = 0; k < R; ++k) {
    is.seed = uint32_t(1000 + 7 * k);
    IirtfCell c = iirtfCellCpu(scene, block, is.tiles, p, is, members);
    a[size_t(k)] = std::move(c.a), se[size_t(k)] = std::move(c.stdError);
  }
  const auto band = [](size_t j) { return int(std::sqrt(double(j) + 0.5)); };  // j = l(l + 1) + m, own copy
  std::vector<double> spread(FT_SH_BANDS, 0.0), claimed(FT_SH_BANDS, 0.0);
  uint64_t beyond3 = 0, counted = 0, bad = 0;
  for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
    double mean = 0.0, e2 = 0.0;
    for (int k = 0; k < R; ++k) mean += a[size_t(k)][i] / R, e2 += se[size_t(k)][i] * se[size_t(k)][i] / R;
    double var = 0.0;
    for (int k = 0; k < R; ++k) var += (a[size_t(k)][i] - mean) * (a[size_t(k)][i] - mean) / (R - 1);
    const size_t e = i % size_t(FT_SH_COEFFS * FT_SH_COEFFS);
    const int l = std::max(band(e / FT_SH_COEFFS), band(e % FT_SH_COEFFS));
    spread[size_t(l)] += var, claimed[size_t(l)] += e2;
    for (int k = 0; k < R; ++k) bad += !std::isfinite(se[size_t(k)][i]) || se[size_t(k)][i] < 0.0;
    if (!(e2 > 0.0)) continue;
    for (int k = 0; k < R; ++k) {
      const double others = (mean * R - a[size_t(k)][i]) / (R - 1);
      const double z = (a[size_t(k)][i] - others) / std::sqrt(se[size_t(k)][i] * se[size_t(k)][i] + e2 / (R - 1));
      beyond3 += std::abs(z) > 3.0, ++counted;
    }
  }
  r.cpuMilliseconds = msSince(t0);
  double worstBand = 0.0, sAll = 0.0, cAll = 0.0;
  std::string perBand;
  for (int l = 0; l < FT_SH_BANDS; ++l) {
    const double ratio = spread[size_t(l)] / claimed[size_t(l)];
    if (l > 0) worstBand = maxKeepNaN(worstBand, std::abs(std::log(ratio)));
    sAll += spread[size_t(l)], cAll += claimed[size_t(l)];
    perBand += fmt::format("{}l={}: {:.3f}", l ? ", " : "", l, ratio);
  }
  const double beyond = counted ? double(beyond3) / double(counted) : 1.0;
  r.details = fmt::format("a 3-segment cell of the 2-fiber block, {} bakes × {} paths; seed variance / claimed variance "
                          "per band: {}; all: {:.3f}; {} of {} |z| > 3",
                          R, is.pathsPerCell, perBand, sAll / cAll, beyond3, counted);
  r.metrics = {
      Metric{"stderr.variance_ratio_log", std::abs(std::log(sAll / cAll)), 0.25, "ln",
             "|ln(Σ seed variance / Σ claimed SE²)| over all entries. The per-entry variance over 24 seeds has 23 "
             "degrees of freedom (±30 %), the entries of one cell move together (one T per path), and the SE² of a "
             "heavy-tailed T is itself noisy: measured ratios 0.96–1.04 over four seed sets (1.02 with 96 bakes); "
             "±0.25 is 0.78–1.28. A lost stratification factor |C| (×9 in variance) or 1/n reads ≥ 2.2"},
      Metric{"stderr.band_ratio_log_max", worstBand, 0.4, "ln",
             "the same per band l = max(l1, l0) ≥ 1, worst band: 15–11 × 3 strongly correlated entries per band, "
             "measured 0.80–1.07 over four seed sets (|ln| ≤ 0.23); 0.4 is 0.67–1.49"},
      Metric{"stderr.band0_ratio", spread[0] / claimed[0], 1e9, "ratio",
             "band 0 alone (a_00 of 3 channels moving together: one χ²₂₃/23 draw, 0.55–0.99 over four seed sets, "
             "0.90 with 96 bakes); for reading",
             false},
      Metric{"stderr.beyond_3sigma", beyond, 0.02, "fraction",
             "share of (bake, entry) with |A − mean of the other bakes| > 3 σ_claimed (normal: 0.27 %; the heavy "
             "tail of T adds some; an underestimated σ multiplies it)"},
      Metric{"nonfinite.cpu", double(bad), 0.0, "count", "standard errors that are NaN, Inf or negative"},
  };
  r.finish();
  return r;
}

}  // namespace

void addPrtMultipleScatteringCases(ValidationContext&, std::vector<ValidationCase>& out) {
  out.push_back({"prt/ms/sh", [](ValidationContext& c) { return runShCase(c, "prt/ms/sh"); }});
  out.push_back({"prt/ms/tables", [](ValidationContext& c) { return runTablesCase(c, "prt/ms/tables"); }});
  out.push_back({"prt/ms/frame", [](ValidationContext& c) { return runFrameCase(c, "prt/ms/frame"); }});
  out.push_back({"prt/ms/vglo", [](ValidationContext& c) { return runVgloCase(c, "prt/ms/vglo"); }});
  out.push_back({"prt/ms/accumulate", [](ValidationContext& c) { return runAccumulateCase(c, "prt/ms/accumulate"); }});
  out.push_back({"prt/ms/stderr", [](ValidationContext& c) { return runStdErrorCase(c, "prt/ms/stderr"); }});
  out.push_back({"prt/ms/end-to-end", [](ValidationContext& c) { return runEndToEndCase(c, "prt/ms/end-to-end"); }});
}

}  // namespace ft
