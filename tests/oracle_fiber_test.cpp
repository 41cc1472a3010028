// Independent oracles for procedural fiber generation: the CPU reference runs
// on straight yarns, and its output vertices are measured with formulas
// written here, from the paper (000_cc9bd0fbd0e08a03.txt, Wu & Yuksel 2017,
// §2.2 eq. 1–2, §3.1) and the preset rows (reference-data §2). Nothing from
// common/ is called here: a wrong formula there runs on the CPU and the GPU
// alike and passes every cross-check, but not these (docs/fiber-oracles.md).
//
// Conventions this file assumes (and so checks):
//   * a yarn along +x; the ply angle φ and the fiber angle ψ turn positively
//     about +x (right-handed) for `*_clock_wise` = 0, negatively for 1;
//   * the ply's short ellipse axis e_N (ellipse_short) points from the yarn
//     axis to the ply centre, the long one e_B (ellipse_long) across it;
//   * loop peak r1, hair root r0 and free end r0 + re are world distances from
//     the ply centre; hair axial extent ze along the yarn.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numeric>
#include <tuple>
#include <vector>

#include "reference/fiber_reference.h"
#include "scene/camera.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_model.h"
#include "scene/yarn_preset.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSpacing = 0.025;  // control-point spacing of the straight yarns
constexpr double kCurveGap = 2.0;   // yarn k lies along x at z = kCurveGap · k

// Vertex tags, decoded here (common/fiber_vertex.h documents the packing).
struct Tag {
  uint32_t yarn, segment, ply, fiber, type, vertex, period;
};
Tag decode(const FiberVertex& v) {
  return {v.id.x, v.id.y, v.id.z >> 16, v.id.z & 0xFFFFu, v.id.w & 0xFFu, (v.id.w >> 8) & 0xFFu, v.id.w >> 16};
}
constexpr uint32_t kCore = 0, kMigration = 1, kLoop = 2, kHair = 3, kCoreId = 0xFFFF;

struct StraightRun {
  const YarnPreset* preset = nullptr;
  FiberOptions options;
  std::vector<FiberCoord> table;
  YarnParams params{};
  FiberGeometry geometry;
  int curves = 0;
  double length = 0.0;  // per curve
};

// `curves` straight yarns of `length` along +x, LoD and culling off.
StraightRun runStraight(const char* name, FiberOptions options, int curves, double length) {
  StraightRun run;
  run.preset = &findYarnPreset(name);
  run.options = options;
  run.curves = curves;
  const int points = static_cast<int>(std::lround(length / kSpacing)) + 1;
  run.length = (points - 1) * kSpacing;
  YarnModel model;
  model.name = "oracle-straight";
  for (int c = 0; c < curves; ++c) {
    YarnCurve curve;
    for (int i = 0; i < points; ++i)
      curve.points.push_back(glm::vec3(float(i * kSpacing), 0.0f, float(kCurveGap * c)));
    model.curves.push_back(curve);
  }
  const YarnBuffers buffers = buildYarnBuffers(model);
  run.table = makeFiberTable(*run.preset, options.seed);
  run.params = makeYarnParams(*run.preset, run.table, options);
  FiberInput input{&buffers, &run.table, run.params,
                   makeViewParams(frameModel(model, {0, 1, 1}, 320, 240), 1.0f, false, false, 0.0f)};
  run.geometry = generateFibersCpu(input, computeKnotFramesCpu(buffers));
  return run;
}

FiberOptions optionsWith(uint32_t fibersPerPly, uint32_t subdivisions, uint32_t phase) {
  FiberOptions o;
  o.regularFibersPerPly = fibersPerPly;
  o.maxSubdivisions = subdivisions;
  o.migrationPhase = phase;
  return o;
}

double wrapAngle(double a) { return a - 2.0 * kPi * std::floor(a / (2.0 * kPi) + 0.5); }

// The yarn axis point and the radial vector of a vertex of yarn `c`: the yarn
// runs along +x, so x is the length coordinate.
glm::dvec3 radial(const FiberVertex& v, uint32_t yarn) {
  return glm::dvec3(0.0, v.position.y, v.position.z - kCurveGap * yarn);
}
// Angle about +x, from +y towards +z (+z = x̂ × ŷ: right-handed about +x).
double angleAboutX(glm::dvec3 r) { return std::atan2(r.z, r.y); }

// The ply model of the preset, in this file's own words (§3.1, reference-data §2).
struct PlyModel {
  double centreDistance, plySign, fiberSign, yarnAlpha, alpha, eN, eB, rhoMin, rhoMax, s;
  int plies;
  explicit PlyModel(const YarnPreset& p)
      : centreDistance(p.yarnRadius / 2.0),
        plySign(p.yarnClockWise ? -1.0 : 1.0),
        fiberSign(p.fiberClockWise ? -1.0 : 1.0),
        yarnAlpha(p.yarnAlpha),
        alpha(p.alpha),
        eN(p.ellipseShort),
        eB(p.ellipseLong),
        rhoMin(p.rhoMin),
        rhoMax(p.rhoMax),
        s(p.sI),
        plies(p.plyNum) {}
  // Ply angle at x for ply j, given the yarn's angle offset phi0 (its frame is arbitrary).
  double plyAngle(double phi0, double x, uint32_t j) const {
    return phi0 + plySign * 2.0 * kPi * x / yarnAlpha + 2.0 * kPi * j / plies;
  }
};

// Per yarn: the offset of ply 0's angle, measured at the yarn's first core vertex.
std::map<uint32_t, double> plyPhaseOffsets(const StraightRun& run, const PlyModel& m) {
  std::map<uint32_t, double> phi0;
  for (const FiberVertex& v : run.geometry.vertices) {
    const Tag t = decode(v);
    if (t.type != kCore || t.ply != 0 || phi0.count(t.yarn)) continue;
    phi0[t.yarn] = angleAboutX(radial(v, t.yarn)) - m.plyAngle(0.0, v.position.x, 0);
  }
  return phi0;
}

// The ply centre and the ply's (N, B) directions at x, as the oracle predicts them.
struct PlyAt {
  glm::dvec3 centre, N, B;
};
PlyAt plyAt(const PlyModel& m, double phi0, double x, uint32_t ply) {
  const double phi = m.plyAngle(phi0, x, ply);
  const glm::dvec3 yAxis(0, 1, 0), zAxis(0, 0, 1);
  PlyAt p;
  p.N = std::cos(phi) * yAxis + std::sin(phi) * zAxis;
  p.B = std::cos(phi) * zAxis - std::sin(phi) * yAxis;  // x̂ × N
  p.centre = m.centreDistance * p.N;
  return p;
}

// A fiber vertex in its ply's cross-section: offset (u along N, w along B) from the ply centre.
struct CrossSection {
  double x, u, w;
  double distance() const { return std::hypot(u, w); }
};
CrossSection crossSection(const FiberVertex& v, uint32_t yarn, const PlyModel& m, double phi0, uint32_t ply) {
  const PlyAt p = plyAt(m, phi0, v.position.x, ply);
  const glm::dvec3 o = radial(v, yarn) - p.centre;
  return {v.position.x, glm::dot(o, p.N), glm::dot(o, p.B)};
}

// Eq. 2 with θ_i as its phase (the fiber-angle option), and eq. 1's polar angle.
double migrationRadius(const PlyModel& m, double Ri, double thetaTurns, double x) {
  return Ri * (m.rhoMin + (m.rhoMax - m.rhoMin) * 0.5 * (std::cos(2.0 * kPi * (thetaTurns + m.s * x / m.alpha)) + 1.0));
}
double fiberAngle(const PlyModel& m, double thetaTurns, double x) {
  return m.fiberSign * 2.0 * kPi * (thetaTurns + x / m.alpha);
}

// Vertices of one fiber strip of one yarn, in x order.
using FiberKey = std::tuple<uint32_t, uint32_t, uint32_t>;  // yarn, ply, fiber
std::map<FiberKey, std::vector<const FiberVertex*>> strips(const StraightRun& run) {
  std::map<FiberKey, std::vector<const FiberVertex*>> out;
  for (const FiberVertex& v : run.geometry.vertices) {
    const Tag t = decode(v);
    if (t.type == kCore) continue;
    out[{t.yarn, t.ply, t.fiber}].push_back(&v);
  }
  for (auto& [key, list] : out) {
    std::stable_sort(list.begin(), list.end(),
                     [](const FiberVertex* a, const FiberVertex* b) { return a->position.x < b->position.x; });
    // Neighbouring segments repeat their shared end vertex: keep one.
    list.erase(std::unique(list.begin(), list.end(),
                           [](const FiberVertex* a, const FiberVertex* b) { return a->position.x == b->position.x; }),
               list.end());
  }
  return out;
}

// ---------------------------------------------------------------------------
// Normal draws as the presets mean them: N(mu, sigma), clamped to mu ± 3σ (the
// bound the culling needs) and folded to non-negative. Expectations by
// quadrature here, independent of common/rng.h.
struct ClampedNormal {
  double mu, sigma;
  // E[g(X)] for X = |mu + sigma · clamp(Z, -3, 3)|, Z standard normal, restricted to X > t.
  template <class G>
  double expect(G g, double t, double* probability = nullptr) const {
    const int n = 6000;
    double sum = 0.0, mass = 0.0;
    auto phi = [](double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * kPi); };
    for (int i = 0; i < n; ++i) {  // midpoint rule on [-3, 3]
      const double z = -3.0 + 6.0 * (i + 0.5) / n;
      const double x = std::abs(mu + sigma * z), w = phi(z) * 6.0 / n;
      if (x > t) sum += w * g(x), mass += w;
    }
    const double tail = 0.5 * std::erfc(3.0 / std::sqrt(2.0));  // each clamped atom
    for (double z : {-3.0, 3.0}) {
      const double x = std::abs(mu + sigma * z);
      if (x > t) sum += tail * g(x), mass += tail;
    }
    if (probability) *probability = mass;
    return mass > 0.0 ? sum / mass : 0.0;
  }
  double mean(double t = -1.0) const { return expect([](double x) { return x; }, t); }
  double variance(double t = -1.0) const {
    const double m = mean(t);
    return expect([m](double x) { return (x - m) * (x - m); }, t);
  }
};

// ---------------------------------------------------------------------------
// Plies: centre distance yarn_radius / 2, pitch yarn_alpha, handedness
// yarn_clock_wise, plies 2π / ply_num apart (§3.1, reference-data §2).
TEST(OracleFiber, PlyCentresFollowTheirHelix) {
  for (const char* name : {"cotton1", "rayon1", "silk1"}) {
    const StraightRun run = runStraight(name, optionsWith(4, 8, FT_MIGRATION_PHASE_FIBER_ANGLE), 2, 4.0);
    const PlyModel m(*run.preset);
    const auto phi0 = plyPhaseOffsets(run, m);
    double worstDistance = 0.0, worstAngle = 0.0;
    size_t cores = 0;
    for (const FiberVertex& v : run.geometry.vertices) {
      const Tag t = decode(v);
      if (t.type != kCore) continue;
      ++cores;
      const glm::dvec3 r = radial(v, t.yarn);
      ASSERT_TRUE(std::isfinite(r.y) && std::isfinite(r.z));
      worstDistance = std::max(worstDistance, std::abs(glm::length(r) / m.centreDistance - 1.0));
      worstAngle = std::max(worstAngle, std::abs(wrapAngle(angleAboutX(r) - m.plyAngle(phi0.at(t.yarn), v.position.x, t.ply))));
    }
    ASSERT_GT(cores, 1000u);
    // §3.2: the core fiber is as thick as the farthest fiber it stands for: the
    // largest R_i of the inner fiber_num − regular rows, at ρ_max, across the
    // long axis e_B. The drawn half-width (position.w) of every core vertex.
    double coreR = 0.0;
    for (size_t i = 0; i + run.params.regularFibers < run.table.size(); ++i) coreR = std::max(coreR, double(run.table[i].radius));
    const double coreWidth = m.eB * m.rhoMax * coreR;
    double worstWidth = 0.0;
    for (const FiberVertex& v : run.geometry.vertices)
      if (decode(v).type == kCore) worstWidth = std::max(worstWidth, std::abs(v.position.w / coreWidth - 1.0));
    EXPECT_LT(worstWidth, 1e-5) << name << ": core fiber half-width vs e_B ρ_max max(R_i of the core fibers)";
    // float positions of |x| ≤ 4: ~1e-6 relative; a 5 % error is 4 orders above.
    EXPECT_LT(worstDistance, 1e-4) << name << ": ply centre distance from the yarn axis vs yarn_radius / 2";
    // φ advances 2π·4/yarn_alpha ≈ 60 rad; float length coordinates: ~1e-5 rad.
    EXPECT_LT(worstAngle, 1e-3) << name << ": ply angle vs 2π x / yarn_alpha (pitch, handedness, ply spacing)";
    std::printf("%s: ply centre distance max rel err %.2e, ply angle max err %.2e rad\n", name, worstDistance,
                worstAngle);
  }
}

// Regular fibers, with eq. 2's phase tied to θ_i so every migration vertex is
// predictable: the whole position, then its parts (fiber pitch and handedness,
// ellipse axes, migration radius, ρ_min/ρ_max).
TEST(OracleFiber, MigrationFibersFollowEquations1And2) {
  for (const char* name : {"cotton1", "rayon1", "silk2"}) {
    const StraightRun run = runStraight(name, optionsWith(20, 8, FT_MIGRATION_PHASE_FIBER_ANGLE), 2, 4.0);
    const PlyModel m(*run.preset);
    const auto phi0 = plyPhaseOffsets(run, m);
    double worstPosition = 0.0, worstAngle = 0.0, worstRadius = 0.0;
    double fitN = 0.0, fitNN = 0.0, fitB = 0.0, fitBB = 0.0;  // least squares e_N, e_B
    double worstPitch = 0.0, worstRhoMin = 0.0, worstRhoMax = 0.0;
    size_t measured = 0;
    for (const auto& [key, list] : strips(run)) {
      const auto [yarn, ply, fiber] = key;
      const FiberCoord fc = run.table.at(fiber);
      double lo = 1e9, hi = 0.0;
      // Fiber pitch: ψ unwrapped along the strip over its migration vertices.
      double prevPsi = 0.0, unwrapped = 0.0, x0 = 0.0, psi0 = 0.0;
      bool started = false, contiguous = true;
      for (const FiberVertex* v : list) {
        const Tag t = decode(*v);
        if (t.type != kMigration) {
          contiguous = false;
          continue;
        }
        const CrossSection cs = crossSection(*v, yarn, m, phi0.at(yarn), ply);
        const double x = cs.x;
        const double R = migrationRadius(m, fc.radius, fc.thetaTurns, x), psi = fiberAngle(m, fc.thetaTurns, x);
        const double u = R * std::cos(psi) * m.eN, w = R * std::sin(psi) * m.eB;
        worstPosition = std::max(worstPosition, std::hypot(cs.u - u, cs.w - w) / m.eN);
        // ψ and the normalized radius ρ as measured (ellipse taken out).
        const double psiMeasured = std::atan2(cs.w / m.eB, cs.u / m.eN);
        const double rho = std::hypot(cs.u / m.eN, cs.w / m.eB);
        worstAngle = std::max(worstAngle, std::abs(wrapAngle(psiMeasured - psi)));
        worstRadius = std::max(worstRadius, std::abs(rho - R) / m.rhoMax);
        lo = std::min(lo, rho / fc.radius), hi = std::max(hi, rho / fc.radius);
        // Ellipse axes, free of the prediction's e_N/e_B: u = e_N·(R cos ψ), w = e_B·(R sin ψ).
        fitN += cs.u * R * std::cos(psi), fitNN += R * std::cos(psi) * R * std::cos(psi);
        fitB += cs.w * R * std::sin(psi), fitBB += R * std::sin(psi) * R * std::sin(psi);
        if (contiguous) {
          if (!started) {
            x0 = x, psi0 = psiMeasured, prevPsi = psiMeasured, unwrapped = psiMeasured, started = true;
          } else {
            unwrapped += wrapAngle(psiMeasured - prevPsi);
            prevPsi = psiMeasured;
            if (x - x0 > 0.5 * m.alpha) {
              const double slope = (unwrapped - psi0) / (x - x0);
              worstPitch = std::max(worstPitch, std::abs(slope / (m.fiberSign * 2.0 * kPi / m.alpha) - 1.0));
            }
          }
        }
        ++measured;
      }
      if (fc.radius > 0.2 && hi > 0.0) {  // every strip covers several migration periods
        worstRhoMin = std::max(worstRhoMin, std::abs(lo - m.rhoMin));
        worstRhoMax = std::max(worstRhoMax, std::abs(hi - m.rhoMax));
      }
    }
    ASSERT_GT(measured, 10000u) << name;
    const double eN = fitN / fitNN, eB = fitB / fitBB;
    std::printf("%s: position err %.2e e_N, angle %.2e rad, radius %.2e, pitch rel %.2e, e_N %.6f (%.6f) e_B %.6f "
                "(%.6f), rho_min err %.2e rho_max err %.2e\n",
                name, worstPosition, worstAngle, worstRadius, worstPitch, eN, m.eN, eB, m.eB, worstRhoMin,
                worstRhoMax);
    // Float rounding of positions (|x| ≤ 4) and of the twist phases: ~1e-5 of e_N.
    EXPECT_LT(worstPosition, 2e-3) << name << ": fiber position vs eq. 1–2";
    EXPECT_LT(worstAngle, 2e-3) << name << ": fiber polar angle θ_i + 2π x / alpha";
    EXPECT_LT(worstPitch, 1e-3) << name << ": fiber pitch and handedness (alpha, fiber_clock_wise)";
    EXPECT_LT(worstRadius, 2e-3) << name << ": migration radius, eq. 2 (period alpha / s_i)";
    EXPECT_NEAR(eN / m.eN, 1.0, 1e-4) << name << ": ellipse axis along the ply direction (ellipse_short)";
    EXPECT_NEAR(eB / m.eB, 1.0, 1e-4) << name << ": ellipse axis across (ellipse_long)";
    EXPECT_NEAR((eN / eB) / (m.eN / m.eB), 1.0, 1e-4) << name << ": ellipse ratio";
    // The vertex nearest a radius extremum lies ≤ ½ spacing away: ρ off by ≤ (π s Δx / α)²/2·(ρmax−ρmin).
    EXPECT_LT(worstRhoMin, 2e-3) << name << ": smallest radius R_i ρ_min";
    EXPECT_LT(worstRhoMax, 2e-3) << name << ": largest radius R_i ρ_max";
  }
}

// R_i of the fibers, measured from the vertices (largest normalized radius /
// ρ_max), against p(R) of reference-data §2 (uniform in the disk, accepted with
// p): one-sample Kolmogorov–Smirnov over the fiber tables of 10 seeds (5 migration periods each, so that
// some peak of every fiber is a migration peak); and θ_i
// (the polar angle at the first migration vertex less the twist) against uniform.
TEST(OracleFiber, FiberRadiiFollowTheCrossSectionDensity) {
  for (const char* name : {"cotton1", "rayon2", "polyester1"}) {
    const YarnPreset& preset = findYarnPreset(name);
    const PlyModel m(preset);
    std::vector<double> radii, thetas;
    for (uint32_t seed = 1; seed <= 10; ++seed) {
      FiberOptions o = optionsWith(uint32_t(preset.fiberNum), 4, FT_MIGRATION_PHASE_FIBER_ANGLE);
      o.seed = seed;
      const StraightRun run = runStraight(name, o, 1, 5.0 * std::max(m.alpha / m.s, 0.3));
      const auto phi0 = plyPhaseOffsets(run, m);
      for (const auto& [key, list] : strips(run)) {
        const auto [yarn, ply, fiber] = key;
        if (ply != 0) continue;  // the plies share one table
        double hi = 0.0, theta = -1.0;
        for (const FiberVertex* v : list)
          if (decode(*v).type == kMigration) {
            const CrossSection cs = crossSection(*v, yarn, m, phi0.at(yarn), ply);
            hi = std::max(hi, std::hypot(cs.u / m.eN, cs.w / m.eB));
            if (theta < 0.0) {  // θ_i: the polar angle less the twist 2π x / alpha, in turns
              const double turns = m.fiberSign * std::atan2(cs.w / m.eB, cs.u / m.eN) / (2.0 * kPi) - cs.x / m.alpha;
              theta = turns - std::floor(turns);
            }
          }
        radii.push_back(hi / m.rhoMax);
        if (theta >= 0.0) thetas.push_back(theta);
      }
    }
    ASSERT_EQ(radii.size(), size_t(10 * preset.fiberNum));
    // CDF of R: F(r) ∝ ∫_0^r t p(t) dt, Simpson's rule on a fine grid.
    const double e = std::exp(1.0);
    auto p = [&](double r) {
      return (1.0 - 2.0 * preset.epsilon) * std::pow((e - std::exp(r / preset.rMax)) / (e - 1.0), preset.beta) +
             preset.epsilon;
    };
    const int grid = 4000;
    std::vector<double> cdf(grid + 1, 0.0);
    for (int i = 0; i < grid; ++i) {
      const double a = preset.rMax * i / grid, b = preset.rMax * (i + 1) / grid, c = 0.5 * (a + b);
      cdf[i + 1] = cdf[i] + (b - a) / 6.0 * (a * p(a) + 4.0 * c * p(c) + b * p(b));
    }
    auto F = [&](double r) {
      const double t = std::clamp(r / preset.rMax, 0.0, 1.0) * grid;
      const int i = std::min(int(t), grid - 1);
      return (cdf[i] + (t - i) * (cdf[i + 1] - cdf[i])) / cdf[grid];
    };
    std::sort(radii.begin(), radii.end());
    double D = 0.0;
    const double n = double(radii.size());
    for (size_t i = 0; i < radii.size(); ++i)
      D = std::max({D, std::abs(F(radii[i]) - i / n), std::abs(F(radii[i]) - (i + 1) / n)});
    const double critical = 1.95 / std::sqrt(n);  // α = 0.001
    std::printf("%s: KS D = %.4f over %zu fibers (critical %.4f at alpha 0.001)\n", name, D, radii.size(), critical);
    EXPECT_LT(D, critical) << name << ": R_i distribution vs p(R)";
    // Uniform in the disk: θ_i uniform on [0, 1) turns (KS against the identity CDF).
    std::sort(thetas.begin(), thetas.end());
    double Dt = 0.0;
    const double nt = double(thetas.size());
    for (size_t i = 0; i < thetas.size(); ++i)
      Dt = std::max({Dt, std::abs(thetas[i] - i / nt), std::abs(thetas[i] - (i + 1) / nt)});
    std::printf("%s: KS D = %.4f for theta_i over %zu fibers (critical %.4f)\n", name, Dt, thetas.size(),
                1.95 / std::sqrt(nt));
    ASSERT_GT(thetas.size(), radii.size() / 2);
    EXPECT_LT(Dt, 1.95 / std::sqrt(nt)) << name << ": θ_i distribution vs uniform";
    EXPECT_LE(radii.back(), preset.rMax * (1.0 + 1e-3)) << name;
  }
}

// ---------------------------------------------------------------------------
// Flyaways per unit length per ply against loop_density and hair_density.
// A flyaway is a (fiber, period tag) run of loop or hair vertices; only runs
// strictly inside a strip are counted, over the length between the strip's
// first and last tag change (cells cut by a yarn end would bias the count).
struct Densities {
  double loops = 0.0, hairs = 0.0, length = 0.0;  // counts and the ply length they cover (all plies)
  size_t loopCount = 0, hairCount = 0;
};
Densities measureDensities(const StraightRun& run) {
  Densities d;
  const double fibers = run.params.regularFibers;
  for (const auto& [key, list] : strips(run)) {
    std::vector<size_t> starts;  // indices where a new tag run begins
    for (size_t i = 1; i < list.size(); ++i)
      if (decode(*list[i]).period != decode(*list[i - 1]).period) starts.push_back(i);
    if (starts.size() < 2) continue;
    auto boundary = [&](size_t i) { return 0.5 * (list[i - 1]->position.x + list[i]->position.x); };
    d.length += (boundary(starts.back()) - boundary(starts.front())) / fibers;
    for (size_t k = 0; k + 1 < starts.size(); ++k) {
      const uint32_t type = decode(*list[starts[k]]).type;
      d.loopCount += type == kLoop;
      d.hairCount += type == kHair;
    }
  }
  d.loops = d.loopCount / d.length;
  d.hairs = d.hairCount / d.length;
  return d;
}

void expectDensities(const char* name, uint32_t fibersPerPly, int curves, double length) {
  const YarnPreset& preset = findYarnPreset(name);
  const uint32_t fibers = fibersPerPly ? fibersPerPly : uint32_t(preset.fiberNum);
  const StraightRun run = runStraight(name, optionsWith(fibers, 2, FT_MIGRATION_PHASE_INDEPENDENT), curves, length);
  const Densities d = measureDensities(run);
  // Poisson: the count's standard deviation is at most √(expected count).
  const double loopsExpected = preset.loopDensity * d.length, hairsExpected = preset.hairDensity * d.length;
  std::printf("%s, %u fibers/ply: loops %.2f /unit/ply (preset %.2f, %+.1f %%), hairs %.2f (preset %.2f, %+.1f %%), "
              "over %.0f units of ply\n",
              name, fibers, d.loops, preset.loopDensity, 100.0 * (d.loops / preset.loopDensity - 1.0), d.hairs,
              preset.hairDensity, 100.0 * (d.hairs / preset.hairDensity - 1.0), d.length);
  EXPECT_NEAR(double(d.loopCount), loopsExpected, 4.5 * std::sqrt(loopsExpected)) << name << " loops";
  EXPECT_NEAR(double(d.hairCount), hairsExpected, 4.5 * std::sqrt(hairsExpected)) << name << " hairs";
}

TEST(OracleFiber, FlyawayDensitiesMatchThePresetsAtTheDefaultFiberCount) {
  for (const char* name : {"cotton1", "rayon2", "silk1", "polyester1"}) expectDensities(name, 20, 10, 10.0);
}

TEST(OracleFiber, FlyawayDensitiesMatchThePresetsAtFullFiberCount) {
  for (const char* name : {"cotton1", "silk1"}) expectDensities(name, 0, 4, 10.0);
}

// Every strip keeps regular migration vertices (silk1, s = 0.1: one period is
// 4.6 units long, yet fibers must not become all flyaways).
TEST(OracleFiber, RegularMigrationRemainsBesideFlyaways) {
  for (const char* name : {"silk1", "cotton1"}) {
    const StraightRun run = runStraight(name, optionsWith(20, 2, FT_MIGRATION_PHASE_INDEPENDENT), 4, 10.0);
    size_t counts[4] = {0, 0, 0, 0};
    for (const FiberVertex& v : run.geometry.vertices) counts[std::min(decode(v).type, 3u)]++;
    const double regular = counts[kMigration] + counts[kLoop] + counts[kHair];
    std::printf("%s: vertex share migration %.3f loop %.3f hair %.3f\n", name, counts[kMigration] / regular,
                counts[kLoop] / regular, counts[kHair] / regular);
    EXPECT_GT(counts[kMigration] / regular, 0.4) << name;
  }
}

// ---------------------------------------------------------------------------
// Loop peaks and hair ends, measured as distances from the predicted ply
// centre (eq. 2 with the fiber-angle phase, so the fiber's own radius is
// known everywhere), against r1, r0 + re of the preset.
struct FlyawayShapes {
  double loopSum = 0.0, loopExpected = 0.0, loopVariance = 0.0, loopAllowance = 0.0, loopInward = 0.0;
  size_t loops = 0;
  double hairEndSum = 0.0, hairEndAllowance = 0.0, hairRootSum = 0.0, hairRootAllowance = 0.0, hairLengthSum = 0.0;
  size_t hairs = 0, hairsWithRoot = 0;
};

FlyawayShapes measureShapes(const StraightRun& run) {
  const YarnPreset& preset = *run.preset;
  const PlyModel m(preset);
  const auto phi0 = plyPhaseOffsets(run, m);
  const ClampedNormal r1{preset.loopR1.mu, preset.loopR1.sigma};
  FlyawayShapes out;
  for (const auto& [key, list] : strips(run)) {
    const auto [yarn, ply, fiber] = key;
    const FiberCoord fc = run.table.at(fiber);
    size_t i = 0;
    while (i < list.size()) {
      size_t j = i;
      const Tag first = decode(*list[i]);
      while (j < list.size() && decode(*list[j]).period == first.period) ++j;
      const bool inside = i > 0 && j < list.size();  // not cut by a yarn end
      if (inside && (first.type == kLoop || first.type == kHair)) {
        std::vector<double> dist, own, xs;
        for (size_t k = i; k < j; ++k) {
          const CrossSection cs = crossSection(*list[k], yarn, m, phi0.at(yarn), ply);
          const double x = cs.x, R = migrationRadius(m, fc.radius, fc.thetaTurns, x), psi = fiberAngle(m, fc.thetaTurns, x);
          dist.push_back(cs.distance());
          own.push_back(R * std::hypot(std::cos(psi) * m.eN, std::sin(psi) * m.eB));
          xs.push_back(x);
        }
        const double spacing = xs.size() > 1 ? (xs.back() - xs.front()) / (xs.size() - 1) : kSpacing;
        if (first.type == kLoop) {
          const double peak = *std::max_element(dist.begin(), dist.end());
          const double ownMax = *std::max_element(own.begin(), own.end());
          for (size_t k = 0; k < dist.size(); ++k) out.loopInward = std::max(out.loopInward, own[k] - dist[k]);
          if (peak > ownMax * (1.0 + 1e-3) + 1e-6) {  // r1 above the fiber's own radius: the peak is r1
            out.loopSum += peak;
            out.loopExpected += r1.mean(ownMax);
            out.loopVariance += r1.variance(ownMax);
            // The vertex nearest the cell's middle lies ≤ ½ spacing off it: ≤ (π Δ / L)² of the rise.
            const double cell = xs.back() - xs.front() + spacing;
            out.loopAllowance += (peak - ownMax) * std::pow(kPi * spacing / cell, 2);
            ++out.loops;
          }
        } else {
          // The free end is the run's end vertex nearer the outside: the larger distance.
          const bool atEnd = dist.back() > dist.front();
          std::vector<double> d = dist, x = xs;
          if (atEnd) std::reverse(d.begin(), d.end()), std::reverse(x.begin(), x.end());
          out.hairEndSum += d[0];
          // The cell boundary lies ≤ one spacing beyond the end vertex: the hair's slope times that.
          if (d.size() > 1) out.hairEndAllowance += std::max(0.0, d[0] - d[1]);
          // The hair is straight in (x, distance): its root is where that line ends.
          size_t k = 1;
          while (k + 1 < d.size() && std::abs((d[k + 1] - d[k]) - (d[k] - d[k - 1])) < 1e-3 * std::abs(d[k] - d[k - 1]) + 2e-6)
            ++k;
          if (k >= 2 && k + 1 < d.size()) {
            out.hairRootSum += d[k];
            out.hairRootAllowance += std::abs(d[k] - d[k - 1]);
            out.hairLengthSum += std::abs(x[k] - x[0]);
            ++out.hairsWithRoot;
          }
          ++out.hairs;
        }
      }
      i = j;
    }
  }
  return out;
}

TEST(OracleFiber, LoopPeaksAndHairEndsMatchTheirRadii) {
  for (const char* name : {"cotton1", "rayon2", "silk1"}) {
    const YarnPreset& preset = findYarnPreset(name);
    const StraightRun run = runStraight(name, optionsWith(20, 16, FT_MIGRATION_PHASE_FIBER_ANGLE), 4, 6.0);
    const FlyawayShapes s = measureShapes(run);
    ASSERT_GT(s.loops, 100u) << name;
    ASSERT_GT(s.hairs, 200u) << name;
    const double loopMean = s.loopSum / s.loops, loopExpected = s.loopExpected / s.loops;
    const double loopTolerance = (5.0 * std::sqrt(s.loopVariance) + s.loopAllowance) / s.loops;
    const ClampedNormal r0{preset.hairR0.mu, preset.hairR0.sigma}, re{preset.hairRe.mu, preset.hairRe.sigma};
    const double endExpected = r0.mean() + re.mean();
    const double endSE = std::sqrt((r0.variance() + re.variance()) / s.hairs);
    const double endMean = s.hairEndSum / s.hairs, endAllowance = s.hairEndAllowance / s.hairs;
    std::printf("%s: loop peaks %.5f (expected %.5f ± %.5f, %zu loops above their fiber), loops inward by at most "
                "%.2e; hair ends %.5f (expected r0 + re = %.5f, -%.5f sampling ± %.5f SE, %zu hairs)\n",
                name, loopMean, loopExpected, loopTolerance, s.loops, s.loopInward, endMean, endExpected,
                endAllowance, endSE, s.hairs);
    EXPECT_NEAR(loopMean, loopExpected, loopTolerance) << name << ": loop peak distance vs r1";
    EXPECT_LT(s.loopInward, 1e-5) << name << ": a loop never pulls its fiber inwards";
    EXPECT_LE(endMean, endExpected + 5.0 * endSE) << name << ": hair free end vs r0 + re";
    EXPECT_GE(endMean, endExpected - 5.0 * endSE - endAllowance) << name << ": hair free end vs r0 + re";
    if (s.hairsWithRoot > 100) {
      const double rootMean = s.hairRootSum / s.hairsWithRoot;
      const double rootSE = std::sqrt(r0.variance() / s.hairsWithRoot);
      const double rootAllowance = s.hairRootAllowance / s.hairsWithRoot;
      std::printf("%s: hair roots %.5f (expected r0 = %.5f ± %.5f SE + %.5f sampling, %zu hairs), mean axial "
                  "length %.4f\n",
                  name, rootMean, r0.mean(), rootSE, rootAllowance, s.hairsWithRoot,
                  s.hairLengthSum / s.hairsWithRoot);
      EXPECT_NEAR(rootMean, r0.mean(), 5.0 * rootSE + rootAllowance) << name << ": hair root distance vs r0";
    }
  }
}

// Hair axial length against ze (folded, clamped normal): every hair is
// measured from its free end to its root along the yarn.
TEST(OracleFiber, HairAxialLengthMatchesZe) {
  for (const char* name : {"cotton1", "silk1"}) {
    const YarnPreset& preset = findYarnPreset(name);
    const StraightRun run = runStraight(name, optionsWith(20, 16, FT_MIGRATION_PHASE_FIBER_ANGLE), 4, 6.0);
    const FlyawayShapes s = measureShapes(run);
    ASSERT_GT(s.hairsWithRoot, 100u) << name;
    const ClampedNormal ze{preset.hairZe.mu, preset.hairZe.sigma};
    const double spacing = kSpacing / 16.0;
    // Hairs shorter than three vertex spacings have no measurable straight part:
    // compare with ze conditioned on being longer than that, within ± 1 spacing.
    const double expected = ze.mean(2.0 * spacing), sd = std::sqrt(ze.variance(2.0 * spacing) / s.hairsWithRoot);
    const double measured = s.hairLengthSum / s.hairsWithRoot;
    std::printf("%s: hair axial length %.4f (expected ze %.4f ± %.4f SE, ± %.4f spacing)\n", name, measured,
                expected, sd, 1.5 * spacing);
    EXPECT_NEAR(measured, expected, 5.0 * sd + 1.5 * spacing) << name << ": hair axial extent vs ze";
  }
}

// Every fiber is continuous along the yarn, except where a hair's free end
// meets the next cell: the distance from the predicted ply centre never jumps
// by much more than its neighbouring steps (a jump: one step > 8× both of its
// neighbours and > 0.5 % of e_N; real breaks measured 5–160 % of e_N).
TEST(OracleFiber, FibersAreContinuousExceptAtHairTips) {
  for (const char* name : {"cotton1", "rayon2", "silk1"}) {
    const StraightRun run = runStraight(name, optionsWith(20, 8, FT_MIGRATION_PHASE_INDEPENDENT), 2, 6.0);
    const PlyModel m(*run.preset);
    const auto phi0 = plyPhaseOffsets(run, m);
    size_t jumps = 0, steps = 0, tips = 0;
    double worst = 0.0;
    for (const auto& [key, list] : strips(run)) {
      const auto [yarn, ply, fiber] = key;
      std::vector<double> d;
      for (const FiberVertex* v : list) d.push_back(crossSection(*v, yarn, m, phi0.at(yarn), ply).distance());
      // Hair runs: the free end is the end where the polar angle has left the
      // fiber's own θ_i + 2π x / alpha (the hair's angular extent pe; the rest
      // of the cell keeps the fiber's angle). Allowed there: the step to the
      // neighbouring cell and the two inside steps next to it (a hair shorter
      // than a step); at the other end only the two inside steps (a hair that
      // fills 95 % of its cell rejoins within a step), never the step to the
      // next cell. A hair with pe ≈ 0 has no telling end: both are allowed.
      const FiberCoord fc = run.table.at(fiber);
      auto angleOff = [&](size_t q) {
        const CrossSection cs = crossSection(*list[q], yarn, m, phi0.at(yarn), ply);
        return std::abs(wrapAngle(std::atan2(cs.w / m.eB, cs.u / m.eN) - fiberAngle(m, fc.thetaTurns, cs.x)));
      };
      std::vector<char> allowed(list.size(), 0);  // step k → k + 1 allowed
      auto allowStart = [&](size_t i) {
        for (size_t k = (i > 0 ? i - 1 : 0); k < std::min(i + 2, list.size()); ++k) allowed[k] = 1;
      };
      auto allowEnd = [&](size_t j) {
        for (size_t k = (j >= 3 ? j - 3 : 0); k < j; ++k) allowed[k] = 1;
      };
      auto allowInsideStart = [&](size_t i) {
        for (size_t k = i; k < std::min(i + 2, list.size()); ++k) allowed[k] = 1;
      };
      auto allowInsideEnd = [&](size_t j) {
        for (size_t k = (j >= 3 ? j - 3 : 0); k + 1 < j; ++k) allowed[k] = 1;
      };
      for (size_t i = 0; i < list.size();) {
        size_t j = i;
        while (j < list.size() && decode(*list[j]).period == decode(*list[i]).period) ++j;
        if (decode(*list[i]).type == kHair) {
          const double a = angleOff(i), b = angleOff(j - 1);
          if (std::max(a, b) < 1e-3) {
            allowStart(i), allowEnd(j);
          } else if (a > b) {
            allowStart(i), allowInsideEnd(j);
          } else {
            allowEnd(j), allowInsideStart(i);
          }
        }
        i = j;
      }
      for (size_t k = 1; k + 2 < list.size(); ++k) {
        const double s = std::abs(d[k + 1] - d[k]);
        const double around = std::max(std::abs(d[k] - d[k - 1]), std::abs(d[k + 2] - d[k + 1]));
        ++steps;
        const bool tip = allowed[k] != 0;
        tips += tip;
        if (!tip && s > 8.0 * around + 5e-3 * m.eN) {
          ++jumps;
          worst = std::max(worst, s / m.eN);
          if (std::getenv("FT_ORACLE_DEBUG") && jumps < 6) {  // FT_ORACLE_DEBUG=1: print the first jumps
            for (size_t q = k - 1; q <= k + 2; ++q) {
              const Tag t = decode(*list[q]);
              std::printf("  x %.5f type %u cell %u d %.5f allowed %d\n", list[q]->position.x, t.type, t.period, d[q],
                          int(allowed[q]));
            }
          }
        }
      }
    }
    std::printf("%s: %zu jumps in %zu steps (%zu at hair tips, allowed), worst %.3f e_N\n", name, jumps, steps, tips,
                worst);
    EXPECT_EQ(jumps, 0u) << name << ": a fiber jumps away from a hair tip";
    EXPECT_GT(tips, 0u) << name;
  }
}

// ---------------------------------------------------------------------------
// The yarn frame is rotation-minimizing (Wang et al. 2008): against the Frenet
// frame its normal turns at −τ per unit length, τ the torsion, so over a
// stretch it has turned by −∫τ ds. Checked on a helix whose pitch grows
// (a cos u, a sin u, b u + e u²) — a plain helix would not do: its chords are
// symmetric, and there one reflection per step equals the double reflection —
// with τ from the curve's derivatives and the integral by the midpoint rule,
// at the knots of a Catmull-Rom yarn through points of the curve.
TEST(OracleFrame, FrameTurnsAgainstFrenetByMinusTheTorsionIntegral) {
  const double a = 0.2, b = 0.05, e = 0.004, du = 0.15;
  const int points = 400;
  auto d1 = [&](double u) { return glm::dvec3(-a * std::sin(u), a * std::cos(u), b + 2.0 * e * u); };
  auto d2 = [&](double u) { return glm::dvec3(-a * std::cos(u), -a * std::sin(u), 2.0 * e); };
  auto d3 = [&](double u) { return glm::dvec3(a * std::sin(u), -a * std::cos(u), 0.0); };
  auto torsionSpeed = [&](double u) {  // τ |c'|
    const glm::dvec3 c = glm::cross(d1(u), d2(u));
    return glm::dot(c, d3(u)) / glm::dot(c, c) * glm::length(d1(u));
  };
  YarnModel model;
  model.name = "oracle-helix";
  YarnCurve helix;
  for (int i = 0; i < points; ++i) {
    const double u = i * du;
    helix.points.push_back(glm::vec3(float(a * std::cos(u)), float(a * std::sin(u)), float(b * u + e * u * u)));
  }
  model.curves.push_back(helix);
  const YarnBuffers buffers = buildYarnBuffers(model);
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(buffers);
  // Away from the reflected ends, knot k sits on control point k.
  const int first = 20, last = points - 20;
  double unwrapped = 0.0, previous = 0.0, expected = 0.0, worst = 0.0, worstOrtho = 0.0, turned = 0.0;
  for (int k = first; k <= last; ++k) {
    const double u = k * du;
    const glm::dvec3 T = glm::normalize(d1(u)), BF = glm::normalize(glm::cross(d1(u), d2(u))), NF = glm::cross(BF, T);
    const glm::dvec3 n = glm::dvec3(glm::vec3(frames.at(buffers.curves[0].frameBase + k).normal));
    worstOrtho = std::max(worstOrtho, std::abs(glm::dot(n, T)));
    const double angle = std::atan2(glm::dot(n, BF), glm::dot(n, NF));
    if (k > first) {
      unwrapped += wrapAngle(angle - previous);
      const int steps = 64;
      for (int j = 0; j < steps; ++j) expected -= torsionSpeed(u - du + (j + 0.5) * du / steps) * du / steps;
      worst = std::max(worst, std::abs(unwrapped - expected));
    }
    previous = angle;
  }
  turned = expected;
  std::printf("frame vs -integral of torsion: worst %.2e rad over a turn of %.3f rad, |n.T| <= %.1e\n", worst, turned,
              worstOrtho);
  // The Catmull-Rom curve through the points is not quite the curve: measured 1.1e-4 rad over
  // a turn of 41 rad. Too coarse to tell one reflection per step from two (1.4e-4 rad): the
  // harness's fault rmf-one-reflection does that, CPU against GPU.
  EXPECT_LT(worst, 1e-3) << "the frame is not rotation-minimizing";
  EXPECT_LT(worstOrtho, 1e-2) << "the knot normal leaves the plane normal to the curve";
}

// ---------------------------------------------------------------------------
// A closed yarn: a circle of radius 5 (length 2π·5 in closed form). Its length
// coordinate spans the circle, and every fiber closes on itself.
TEST(OracleFiber, ClosedYarnLengthAndSeams) {
  const double radius = 5.0;
  const int points = 1200;
  YarnModel model;
  model.name = "oracle-circle";
  YarnCurve circle;
  circle.closed = true;
  for (int i = 0; i < points; ++i) {
    const double a = 2.0 * kPi * i / points;
    circle.points.push_back(glm::vec3(float(radius * std::cos(a)), 0.0f, float(radius * std::sin(a))));
  }
  model.curves.push_back(circle);
  const YarnBuffers buffers = buildYarnBuffers(model);
  // The control polygon's length: 2 n R sin(π / n) (closed form), within 1e-6 of 2πR here.
  const double polygon = 2.0 * points * radius * std::sin(kPi / points);
  EXPECT_NEAR(buffers.curves.at(0).totalLength / polygon, 1.0, 1e-6);
  EXPECT_NEAR(polygon / (2.0 * kPi * radius), 1.0, 2e-6);
  const YarnPreset& preset = findYarnPreset("rayon2");
  const std::vector<FiberCoord> table = makeFiberTable(preset, 1);
  const YarnParams params = makeYarnParams(preset, table, optionsWith(8, 2, FT_MIGRATION_PHASE_INDEPENDENT));
  FiberInput input{&buffers, &table, params, makeViewParams(frameModel(model, {0, 1, 1}, 320, 240), 1.0f, false, false, 0.0f)};
  const FiberGeometry g = generateFibersCpu(input, computeKnotFramesCpu(buffers));
  // Per fiber strip: the first vertex of segment 0 and the last of the last segment coincide.
  std::map<uint32_t, glm::dvec3> first, last;
  const uint32_t lastSegment = uint32_t(buffers.segments.size() - 1);
  size_t regular = 0;
  for (const FiberVertex& v : g.vertices) {
    const Tag t = decode(v);
    const uint32_t key = v.id.z;
    if (t.segment == 0 && t.vertex == 0) first[key] = glm::dvec3(v.position);
    if (t.segment == lastSegment && t.vertex == 2) last[key] = glm::dvec3(v.position);
    regular += t.type != kCore;
  }
  ASSERT_GT(regular, 0u);
  ASSERT_EQ(first.size(), last.size());
  double worst = 0.0;
  for (const auto& [key, p] : first) worst = std::max(worst, glm::length(p - last.at(key)));
  std::printf("closed circle: length %.6f (2πR %.6f), worst seam gap %.2e\n", buffers.curves[0].totalLength,
              2.0 * kPi * radius, worst);
  EXPECT_LT(worst, 1e-3 * preset.ellipseShort) << "fibers jump where the closed yarn meets itself";
}

}  // namespace
}  // namespace ft
