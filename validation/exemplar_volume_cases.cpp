// exemplar_volume_cases.cpp — the exemplar volume and eye-ray casting of
// Khungurn et al. 2017 (004) §5.1 (common/exemplar_volume.h, reference/
// exemplar_volume.h, gpu/exemplar_volume_gpu.h; docs/exemplar-volume.md).
// Path "vol". One CI exemplar (plain weave, polyester1, 40 fibers/ply, fiber
// radius 0.0018 so that h = 2 r_f gives 64 voxels a period), 128² rays:
//   prt/vol/idvolume     GPU ids vs CPU ids (ties within 1e-6 h excluded);
//                        coverage and reach of the non-empty voxels against
//                        point–segment distances in double written here;
//   prt/vol/sampler      GPU G-buffer vs the scalar CPU sampler (rays with a
//                        sample within 1e-5 h of a voxel face excluded);
//   prt/vol/periodicity  lookup(p) = lookup(p + (i, j)·P) at points written
//                        here; the GPU G-buffer of a camera moved by whole
//                        periods = the G-buffer moved by them;
//   prt/vol/embree       the sampler vs Embree's first hit on the real
//                        capsules of the 7 × 7 tiled exemplar, N = 32, 64,
//                        128 (004 Fig. 13's trend) and 1024;
//   prt/vol/capsule      the capsule ids (the first exact capsule hit among
//                        the candidates of the cells crossed):
//                        GPU vs CPU, and against Embree's first hit (same
//                        segment, hit/miss, hit point, coverage).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>

#include "common/exemplar_volume.h"
#include "gpu/exemplar_volume_gpu.h"
#include "gpu/fiber_renderer.h"
#include "reference/exemplar.h"
#include "reference/exemplar_volume.h"
#include "validation/case_support.h"
#include "validation/draw_order.h"
#include "validation/harness.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

CaseResult start(const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "prt-volume";
  r.path = "vol";
  return r;
}

constexpr int kTiles = 7;         // the truth's tiling: rays stay within ±2.3 P of the origin
constexpr int kRays = 128;        // 128² rays
constexpr int kSamples = 64;      // N of the CPU–GPU cross-check (004 Table 1: 32 or 64)
// Ties: two midpoints equidistant within 1e-6 h (float keys of ~h² differ in
// their last bits between the two sides only there).
constexpr double kTieMargin = 1e-6;
// A sample within 1e-5 h of a voxel face: o + t d in float at |p| ≲ 3 P
// (≈ 200 h) carries ~1e-5 h of rounding; such a sample's voxel is a coin toss.
constexpr double kFaceMargin = 1e-5;
// The Embree comparison's gates (prt/vol/embree, measured values in its metrics).
constexpr double kDdaLimitPct = 2.0;
constexpr double kIdDisagreePct = 70.0;
constexpr double kFiberDisagreePct = 67.0;
constexpr double kHitMissPct = 6.0;
constexpr double kPointMedianH = 2.5;
// prt/vol/capsule (docs/exemplar-volume.md "Ids"): two capsule entries within
// 1e-3 h along the ray (a joint of two segments of a fiber, a grazing
// double root) are ties that float rounding decides: excluded from the
// cross-check and counted.
constexpr double kCapsuleTieMargin = 1e-3;
// Gates on the measured figures (docs/exemplar-volume.md, 2026-12-03), with
// room for another Embree / driver build; the planted faults cost far more.
constexpr double kCapsulePointsMeasured = 8.1e-4;
constexpr double kCapsulePointsMaxH = 5e-3;
constexpr double kCapsuleIdMeasured = 0.69;
constexpr double kCapsuleIdDisagreePct = 2.0;
constexpr double kCapsuleFiberDisagreePct = 0.5;
constexpr double kCapsuleHitMissPct = 0.1;
constexpr double kCapsuleCoveragePct = 0.1;
constexpr double kCapsulePointMedianH = 1e-3;
constexpr double kCapsulePointP90H = 1e-3;

struct VolSetup {
  Exemplar block;
  VolParams layout{};
  VolumeCandidates candidates;
  ExemplarVolume cpu;
  std::vector<ExemplarSegment> tiled;
  std::unique_ptr<VolumeTruth> truth;
  double cpuBuildMs = 0.0;
};

VolSetup& setup(ValidationContext& ctx) {
  return ctx.cached(CacheKey<VolSetup>{"prt/vol/setup"}, [] {
    VolSetup s;
    ExemplarSettings es;
    es.fibersPerPly = 40;
    es.spansPerYarn = 8;
    es.subdivisions = 2;
    es.fiberRadius = 0.0018f;  // h = 2 r_f → round(P / h) = 64 voxels a period (P = 0.229)
    s.block = makePlainWeaveExemplar(es);
    s.layout = makeVolumeLayout(s.block);
    s.candidates = buildVolumeCandidates(s.block, s.layout);
    const auto t0 = Clock::now();
    s.cpu = buildExemplarVolumeCpu(s.block, s.layout, s.candidates);
    s.cpuBuildMs = msSince(t0);
    s.tiled = tileExemplar(s.block, kTiles);
    s.truth = std::make_unique<VolumeTruth>(s.tiled);
    return s;
  });
}

struct GpuVolume {
  std::vector<uint32_t> ids;
  double ms = 0.0;
};
// The GPU's volume of the setup, built once per run (the GPU class keeps it
// for sampling).
GpuVolume& gpuVolume(ValidationContext& ctx) {
  VolSetup& s = setup(ctx);
  return ctx.cached(CacheKey<GpuVolume>{"prt/vol/gpu-volume"}, [&] {
    ExemplarVolumeGpu& gpu = ctx.gpu<ExemplarVolumeGpu>();
    const std::vector<VolSegment> segs = volumeSegments(s.block);
    const auto t0 = Clock::now();
    gpu.build(s.layout, segs, s.candidates.start, s.candidates.entries);
    GpuVolume g;
    g.ids = gpu.ids();
    g.ms = msSince(t0);
    return g;
  });
}

// The test camera: orthographic, 35° off the normal, azimuth 30°, over
// [−1.5 P, 1.5 P]² (negative coordinates: the wrap), from 3 P back.
VolParams testRays(const VolSetup& s, int samples, glm::vec2 shift = glm::vec2(0.0f), float halfWidthP = 1.5f) {
  const float P = ftVolPeriod(s.layout);
  const double th = 35.0 * 3.14159265358979 / 180.0, ph = 30.0 * 3.14159265358979 / 180.0;
  VolCamera cam;
  cam.type = FT_VOL_CAMERA_ORTHO;
  cam.direction = glm::vec3(float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(-std::cos(th)));
  cam.up = glm::vec3(0.0f, 0.0f, 1.0f);
  cam.position = glm::vec3(shift.x * P, shift.y * P, 0.0f) - 3.0f * P * cam.direction;
  cam.halfWidth = cam.halfHeight = halfWidthP * P;
  VolParams p = s.layout;
  setVolumeRays(p, cam, kRays, kRays, samples);
  return p;
}

// The pinhole camera (prt/vol/sampler, prt/vol/capsule): eye 1.2 P above the
// block's corner, looking down 20° off the normal, 60° field of view (rays
// from −25° to 45°).
VolParams pinholeRays(const VolSetup& s, int samples, uint32_t ids) {
  const float P = ftVolPeriod(s.layout);
  VolCamera cam;
  cam.type = FT_VOL_CAMERA_PINHOLE;
  cam.position = glm::vec3(0.0f, 0.0f, 1.2f * P);
  cam.direction = glm::vec3(0.342f, 0.0f, -0.940f);
  cam.up = glm::vec3(0.0f, 0.0f, 1.0f);
  cam.halfWidth = cam.halfHeight = 0.577f;  // tan 30°
  VolParams p = s.layout;
  setVolumeRays(p, cam, kRays, kRays, samples, ids);
  return p;
}

template <class T>
uint64_t nonFinitePoints(const std::vector<T>& hits) {
  uint64_t n = 0;
  for (const T& h : hits)
    if (!std::isfinite(h.point.x) || !std::isfinite(h.point.y) || !std::isfinite(h.point.z)) ++n;
  return n;
}

// Point–segment distance in double (written here, not common/'s).
double segmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = b - a;
  const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
  return glm::length(p - (a + t * d));
}

// ---- prt/vol/idvolume --------------------------------------------------------
CaseResult runIdVolumeCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  VolSetup& s = setup(ctx);
  const GpuVolume& g = gpuVolume(ctx);
  r.cpuMilliseconds = s.cpuBuildMs;
  r.gpuMilliseconds = g.ms;
  r.gpuTiming = "wall clock of upload + build dispatch + read-back of the ids";
  const VolParams& L = s.layout;
  const int nx = int(L.dims.x), ny = int(L.dims.y), nz = int(L.dims.z);
  const size_t count = s.cpu.ids.size();
  uint64_t mismatched = 0, ties = 0, emptyMismatch = 0;
  size_t firstBad = count;
  for (size_t i = 0; i < count; ++i) {
    if (s.cpu.ids[i] == g.ids[i]) continue;
    if (double(s.cpu.tieGap[i]) < kTieMargin) {
      ++ties;
      continue;
    }
    ++mismatched;
    if ((s.cpu.ids[i] == 0) != (g.ids[i] == 0)) ++emptyMismatch;
    if (firstBad == count) firstBad = i;
  }
  // Independent geometry (double, no common/): each voxel's centre
  // origin + (i + ½) h against every capsule axis of the block and its 8
  // translates: the nearest axis distance of every voxel within reach.
  const double h = double(L.origin.w), P = double(nx) * h;
  const glm::dvec3 o(L.origin.x, L.origin.y, L.origin.z);
  double rMax = 0.0;
  for (const ExemplarSegment& seg : s.block.segments) rMax = std::max(rMax, double(seg.radius));
  const double reach = std::sqrt(3.0) * (0.5 * h + rMax);  // the conservative test's farthest centre
  std::vector<double> nearest(count, 1e30), nearestR(count, 0.0);
  for (const ExemplarSegment& seg : s.block.segments)
    for (int cy = -1; cy <= 1; ++cy)
      for (int cx = -1; cx <= 1; ++cx) {
        const glm::dvec3 off(cx * P, cy * P, 0.0);
        const glm::dvec3 a = glm::dvec3(seg.a) + off, b = glm::dvec3(seg.b) + off;
        const glm::dvec3 lo = glm::min(a, b) - (reach + h), hi = glm::max(a, b) + (reach + h);
        const glm::ivec3 v0 = glm::max(glm::ivec3(glm::floor((lo - o) / h)), glm::ivec3(0));
        const glm::ivec3 v1 = glm::min(glm::ivec3(glm::floor((hi - o) / h)), glm::ivec3(nx - 1, ny - 1, nz - 1));
        for (int z = v0.z; z <= v1.z; ++z)
          for (int y = v0.y; y <= v1.y; ++y)
            for (int x = v0.x; x <= v1.x; ++x) {
              const glm::dvec3 c = o + (glm::dvec3(x, y, z) + 0.5) * h;
              const double d = segmentDistance(c, a, b);
              const size_t i = (size_t(z) * ny + size_t(y)) * nx + size_t(x);
              if (d - double(seg.radius) < nearest[i] - nearestR[i]) nearest[i] = d, nearestR[i] = double(seg.radius);
            }
      }
  uint64_t insideVoxels = 0, uncoveredCpu = 0, uncoveredGpu = 0, surfaceExcluded = 0, beyondReach = 0, nonEmpty = 0;
  for (size_t i = 0; i < count; ++i) {
    const double depth = nearest[i] - nearestR[i];  // < 0: the centre is inside a fiber
    if (s.cpu.ids[i] != 0) ++nonEmpty;
    if (std::abs(depth) < kTieMargin * h) {
      ++surfaceExcluded;
      continue;
    }
    if (depth < 0.0) {
      ++insideVoxels;
      if (s.cpu.ids[i] == 0) ++uncoveredCpu;
      if (g.ids[i] == 0) ++uncoveredGpu;
    }
    if (s.cpu.ids[i] != 0 && nearest[i] > reach * (1.0 + 1e-6)) ++beyondReach;
  }
  if (firstBad < count) {
    const glm::ivec3 v = ftVolVoxelOfIndex(uint32_t(firstBad), L.dims);
    r.details = fmt::format("first mismatch: voxel ({}, {}, {}): cpu id {} gpu id {} (tie gap {:.3g} h)", v.x, v.y,
                            v.z, s.cpu.ids[firstBad], g.ids[firstBad], s.cpu.tieGap[firstBad]);
  }
  r.metrics = {
      Metric{"idvolume.mismatched", double(mismatched), 0, "voxels",
             fmt::format("GPU id vs CPU id per voxel, same candidates and float arithmetic; {} voxels whose two "
                         "nearest midpoints are equidistant within {} h excluded ({} of them are empty/non-empty "
                         "flips among the counted)",
                         ties, kTieMargin, emptyMismatch)},
      Metric{"coverage.uncovered_cpu", double(uncoveredCpu), 0, "voxels",
             fmt::format("voxels whose centre is inside a fiber (double distance to the capsule axes written here) "
                         "but empty: the fill is conservative (notes §8.7), so none; {} inside, {} centres within "
                         "{} h of a fiber surface excluded",
                         insideVoxels, surfaceExcluded, kTieMargin)},
      Metric{"coverage.uncovered_gpu", double(uncoveredGpu), 0, "voxels", "the same for the GPU's volume"},
      Metric{"coverage.beyond_reach", double(beyondReach), 0, "voxels",
             fmt::format("non-empty voxels whose centre is farther than √3 (h/2 + r) = {:.3f} h from every axis: the "
                         "grown-box test can reach no farther",
                         reach / h)},
      Metric{"idvolume.nonempty_pct", 100.0 * double(nonEmpty) / double(count), 100.0, "%",
             fmt::format("{} × {} × {} voxels of h = {:.5g} (P = {:.4g}), {} segments, candidate lists ≤ {} a cell; "
                         "{} centres inside fibers",
                         nx, ny, nz, h, P, L.dims.w, s.candidates.maxPerCell, insideVoxels),
             false},
  };
  r.finish();
  return r;
}

// ---- prt/vol/sampler ---------------------------------------------------------
CaseResult runSamplerCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  VolSetup& s = setup(ctx);
  gpuVolume(ctx);
  // Two cameras, one G-buffer each, compared together: the orthographic test
  // camera and a pinhole one (eye 1.2 P above the block's corner, looking
  // down 20° off the normal, 60° field of view: rays from −25° to 45°).
  const VolParams ortho = testRays(s, kSamples);
  const VolParams pinhole = pinholeRays(s, kSamples, FT_VOL_IDS_MIDPOINT);
  std::vector<VolHit> cpu, gpu;
  std::vector<float> face;
  ExemplarVolumeGpu& g = ctx.gpu<ExemplarVolumeGpu>();
  for (const VolParams* rays : {&ortho, const_cast<const VolParams*>(&pinhole)}) {
    const auto t0 = Clock::now();
    std::vector<float> f;
    const std::vector<VolHit> c = sampleVolumeCpu(s.cpu, *rays, &f);
    r.cpuMilliseconds += msSince(t0);
    const auto g0 = Clock::now();
    const std::vector<VolHit> h = g.sample(*rays);
    r.gpuMilliseconds += msSince(g0);
    cpu.insert(cpu.end(), c.begin(), c.end());
    gpu.insert(gpu.end(), h.begin(), h.end());
    face.insert(face.end(), f.begin(), f.end());
  }
  r.gpuTiming = "wall clock of 2 sampling dispatches + read-backs";
  uint64_t mismatched = 0, excluded = 0, hits = 0;
  double pointErr = 0.0;
  size_t firstBad = cpu.size();
  for (size_t i = 0; i < cpu.size(); ++i) {
    if (double(face[i]) < kFaceMargin) {
      ++excluded;
      continue;
    }
    if (cpu[i].id != 0) ++hits;
    if (cpu[i].id != gpu[i].id) {
      ++mismatched;
      if (firstBad == cpu.size()) firstBad = i;
      continue;
    }
    if (cpu[i].id != 0) {
      const double e = double(glm::length(cpu[i].point - gpu[i].point)) / double(s.layout.origin.w);
      r.histogram.add(e);
      pointErr = maxKeepNaN(pointErr, e);
    }
  }
  if (firstBad < cpu.size())
    r.details = fmt::format("first mismatch: {} camera, pixel ({}, {}): cpu id {} gpu id {}",
                            firstBad < size_t(kRays) * kRays ? "orthographic" : "pinhole", firstBad % kRays,
                            firstBad / kRays % kRays, cpu[firstBad].id, gpu[firstBad].id);
  r.histogramMetric = "points.max_abs";
  r.metrics = {
      Metric{"ids.mismatched", double(mismatched), 0, "rays",
             fmt::format("first non-empty sample's id, GPU vs CPU, {}² rays × {} samples on the same volume, "
                         "orthographic and pinhole camera; {} rays with a sample within {} h of a voxel face excluded",
                         kRays, kSamples, excluded, kFaceMargin)},
      Metric{"points.max_abs", pointErr, 1e-4, "h",
             "hit point o + t_i d of the same sample, GPU vs CPU: orthographic rays agree exactly; the pinhole's "
             "normalised direction (GPU sqrt and division a few ulp apart) times t ≲ 250 h gives ≲ 5e-5 h "
             "(measured 1.7e-5 h)"},
      Metric{"rays.hit_pct", 100.0 * double(hits) / double(cpu.size()), 100.0, "%", "rays that hit (CPU)", false},
      nonFiniteMetric("cpu", nonFinitePoints(cpu), "CPU G-buffer points"),
      nonFiniteMetric("gpu", nonFinitePoints(gpu), "GPU G-buffer points"),
  };
  r.finish();
  return r;
}

// ---- prt/vol/periodicity -----------------------------------------------------
CaseResult runPeriodicityCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  VolSetup& s = setup(ctx);
  gpuVolume(ctx);
  const VolParams& L = s.layout;
  const double h = L.origin.w;
  const float P = ftVolPeriod(L);
  // (a) 20,000 points uniform in [−3P, 3P]² × the slab, shifted by (i, j)·P,
  // i, j ∈ [−3, 3]: same voxel id. The points' own voxel is floor((p − o)/h)
  // in double here; points within 1e-4 h of a face (the shifted float point
  // moves by ~|p| 6e-8 ≈ 1e-5 h) excluded.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(-3.0f * P, 3.0f * P), uz(L.origin.z, L.origin.z + float(L.dims.z) * L.origin.w);
  std::uniform_int_distribution<int> us(-3, 3);
  auto lookup = [&](glm::vec3 p) {
    const int idx = ftVolIndex(ftVolVoxelCoord(p, L.origin), L.dims);
    return idx < 0 ? 0u : s.cpu.ids[size_t(idx)];
  };
  auto nearFace = [&](glm::vec3 p) {
    for (int a = 0; a < 3; ++a) {
      const double c = (double(p[a]) - double(L.origin[a])) / h;
      if (std::abs(c - std::round(c)) < 1e-4) return true;
    }
    return false;
  };
  uint64_t bad = 0, tested = 0, skipped = 0, negative = 0;
  for (int k = 0; k < 20000; ++k) {
    const float pz = uz(rng), py = ux(rng), px = ux(rng);  // last first (validation/draw_order.h)
    const glm::vec3 p(px, py, pz);
    const float qy = float(us(rng)) * P, qx = float(us(rng)) * P;
    const glm::vec3 q = p + glm::vec3(qx, qy, 0.0f);
    if (nearFace(p) || nearFace(q)) {
      ++skipped;
      continue;
    }
    ++tested;
    if (p.x < 0.0f || p.y < 0.0f) ++negative;
    if (lookup(p) != lookup(q)) ++bad;
  }
  // (b) the GPU: the camera moved by (2, −1)·P and (−3, 1)·P sees the same
  // ids, its hit points moved by the same amount.
  ExemplarVolumeGpu& gpu = ctx.gpu<ExemplarVolumeGpu>();
  const auto g0 = Clock::now();
  const std::vector<VolHit> base = gpu.sample(testRays(s, kSamples));
  uint64_t gpuBad = 0, gpuExcluded = 0;
  double shiftErr = 0.0;
  std::vector<float> face;
  const std::vector<VolHit> cpuBase = sampleVolumeCpu(s.cpu, testRays(s, kSamples), &face);
  for (glm::vec2 sh : {glm::vec2(2.0f, -1.0f), glm::vec2(-3.0f, 1.0f)}) {
    const std::vector<VolHit> moved = gpu.sample(testRays(s, kSamples, sh));
    std::vector<float> faceMoved;
    sampleVolumeCpu(s.cpu, testRays(s, kSamples, sh), &faceMoved);
    for (size_t i = 0; i < base.size(); ++i) {
      if (face[i] < 1e-4f || faceMoved[i] < 1e-4f) {
        ++gpuExcluded;
        continue;
      }
      if (base[i].id != moved[i].id) {
        ++gpuBad;
        continue;
      }
      if (base[i].id != 0) {
        const glm::vec3 d = moved[i].point - base[i].point - glm::vec3(sh.x * P, sh.y * P, 0.0f);
        shiftErr = maxKeepNaN(shiftErr, double(glm::length(d)) / h);
      }
    }
  }
  r.gpuMilliseconds = msSince(g0);
  r.gpuTiming = "3 G-buffers (GPU) and their CPU face distances";
  r.metrics = {
      Metric{"periodicity.lookup_mismatched", double(bad), 0, "points",
             fmt::format("lookup(p) ≠ lookup(p + (i, j)·P), i, j ∈ [−3, 3], {} points ({} with a negative coordinate); "
                         "{} within 1e-4 h of a face excluded",
                         tested, negative, skipped)},
      Metric{"periodicity.gpu_ids_mismatched", double(gpuBad), 0, "rays",
             fmt::format("GPU G-buffer ids of the camera moved by (2, −1)·P and (−3, 1)·P vs unmoved, {}² rays; {} "
                         "rays with a sample within 1e-4 h of a face excluded",
                         kRays, gpuExcluded)},
      Metric{"periodicity.gpu_point_shift_err", shiftErr, 1e-4, "h",
             "hit points of the moved camera minus the shift: float at |p| ≲ 5 P ≈ 320 h: ~3e-5 h"},
      nonFiniteMetric("gpu", nonFinitePoints(base), "GPU G-buffer points"),
  };
  r.finish();
  return r;
}

// ---- prt/vol/embree ----------------------------------------------------------
struct Agreement {
  double idPct = 0, fiberPct = 0, hitMissPct = 0, medianPointErr = 0, p90PointErr = 0;
  uint64_t bothHit = 0;
};
Agreement agree(const VolSetup& s, const std::vector<VolHit>& vol, const std::vector<VolHit>& truth) {
  const size_t S = s.block.segments.size();
  uint64_t same = 0, sameFiber = 0, hitMiss = 0, hitEither = 0;
  std::vector<double> errs;
  for (size_t i = 0; i < vol.size(); ++i) {
    const bool hv = vol[i].id != 0, ht = truth[i].id != 0;
    if (hv == ht) ++hitMiss;
    if (!hv && !ht) continue;
    ++hitEither;
    if (!(hv && ht)) continue;
    const uint32_t blockId = (truth[i].id - 1) % uint32_t(S);
    if (vol[i].id - 1 == blockId) ++same;
    if (s.block.segments[vol[i].id - 1].fiber == s.block.segments[blockId].fiber) ++sameFiber;
    errs.push_back(double(glm::length(vol[i].point - truth[i].point)) / double(s.layout.origin.w));
  }
  Agreement a;
  a.bothHit = errs.size();
  a.idPct = 100.0 * double(same) / double(std::max<uint64_t>(1, hitEither));
  a.fiberPct = 100.0 * double(sameFiber) / double(std::max<uint64_t>(1, hitEither));
  a.hitMissPct = 100.0 * double(hitMiss) / double(vol.size());
  if (!errs.empty()) {
    std::sort(errs.begin(), errs.end());
    a.medianPointErr = errs[errs.size() / 2];
    a.p90PointErr = errs[errs.size() * 9 / 10];
  }
  return a;
}

// The exact traversal of the volume (Amanatides & Woo 1987), written here in
// double with its own floor-mod: the first non-empty voxel the ray enters in
// the slab, the limit of the sampler as N → ∞ (notes §8.5). Returns its id.
uint32_t ddaFirstId(const VolSetup& s, glm::dvec3 o, glm::dvec3 d) {
  const VolParams& L = s.layout;
  const double h = L.origin.w, zLo = L.origin.z, zHi = zLo + double(L.dims.z) * h;
  if (d.z == 0.0) return 0;
  const double ta = (zLo - o.z) / d.z, tb = (zHi - o.z) / d.z;
  const double t0 = std::max(0.0, std::min(ta, tb)), t1 = std::max(ta, tb);
  if (t0 > t1) return 0;
  const glm::dvec3 org(L.origin.x, L.origin.y, L.origin.z);
  const glm::dvec3 c = (o + t0 * d - org) / h;
  glm::ivec3 v(int(std::floor(c.x)), int(std::floor(c.y)), int(std::floor(c.z)));
  glm::ivec3 step;
  glm::dvec3 tMax, tDelta;
  for (int a = 0; a < 3; ++a) {
    step[a] = d[a] > 0 ? 1 : -1;
    tDelta[a] = d[a] == 0 ? 1e300 : h / std::abs(d[a]);
    const double boundary = (d[a] > 0 ? v[a] + 1 : v[a]) * h + org[a];
    tMax[a] = d[a] == 0 ? 1e300 : t0 + (boundary - (o[a] + t0 * d[a])) / d[a];
  }
  const int nx = int(L.dims.x), ny = int(L.dims.y), nz = int(L.dims.z);
  double t = t0;
  for (int it = 0; it < 100000 && t <= t1; ++it) {
    if (v.z >= 0 && v.z < nz) {
      const size_t i = (size_t(v.z) * ny + size_t(((v.y % ny) + ny) % ny)) * nx + size_t(((v.x % nx) + nx) % nx);
      if (s.cpu.ids[i] != 0) return s.cpu.ids[i];
    }
    const int a = tMax.x < tMax.y ? (tMax.x < tMax.z ? 0 : 2) : (tMax.y < tMax.z ? 1 : 2);
    t = tMax[a];
    tMax[a] += tDelta[a];
    v[a] += step[a];
  }
  return 0;
}

// False colour of a block segment id (0: black).
glm::uvec3 idColour(uint32_t id) {
  if (id == 0) return {0, 0, 0};
  uint32_t x = id * 2654435761u;
  x ^= x >> 15;
  x *= 2246822519u;
  x ^= x >> 13;
  return {64u + (x & 0xBFu), 64u + ((x >> 8) & 0xBFu), 64u + ((x >> 16) & 0xBFu)};
}

CaseResult runEmbreeCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  VolSetup& s = setup(ctx);
  const auto t0 = Clock::now();
  const VolParams base = testRays(s, kSamples);
  const std::vector<VolHit> truth = s.truth->firstHits(base, 1e30f);
  // The fill at the true hit, independent of the sampling: the voxel that
  // holds Embree's hit point must be non-empty (it holds a point of the
  // capsule), and its id is the fill's answer there.
  uint64_t truthHits = 0, truthVoxelEmpty = 0, truthVoxelId = 0;
  {
    const uint32_t S = uint32_t(s.block.segments.size());
    const double h = s.layout.origin.w;
    for (const VolHit& t : truth) {
      if (t.id == 0) continue;
      ++truthHits;
      // The voxel of the hit point, computed here in double: floor-mod by hand.
      glm::ivec3 v;
      for (int a = 0; a < 3; ++a) v[a] = int(std::floor((double(t.point[a]) - double(s.layout.origin[a])) / h));
      const int nx = int(s.layout.dims.x), ny = int(s.layout.dims.y);
      if (v.z < 0 || v.z >= int(s.layout.dims.z)) {
        ++truthVoxelEmpty;
        continue;
      }
      const size_t i = (size_t(v.z) * ny + size_t(((v.y % ny) + ny) % ny)) * nx + size_t(((v.x % nx) + nx) % nx);
      if (s.cpu.ids[i] == 0) ++truthVoxelEmpty;
      else if (s.cpu.ids[i] == (t.id - 1) % S + 1) ++truthVoxelId;
    }
  }
  const int counts[] = {32, 64, 128, 1024};
  std::vector<uint32_t> dda(truth.size());
  for (uint32_t y = 0; y < uint32_t(kRays); ++y)
    for (uint32_t x = 0; x < uint32_t(kRays); ++x)
      dda[size_t(y) * kRays + x] = ddaFirstId(s, glm::dvec3(ftVolRayOrigin(base, x, y)), glm::dvec3(ftVolRayDirection(base, x, y)));
  std::vector<Agreement> a;
  std::vector<double> ddaDisagree;
  std::vector<VolHit> g64;
  for (int n : counts) {
    std::vector<float> face;
    const std::vector<VolHit> v = sampleVolumeCpu(s.cpu, testRays(s, n), &face);
    a.push_back(agree(s, v, truth));
    uint64_t differ = 0;
    for (size_t i = 0; i < v.size(); ++i) differ += v[i].id != dda[i];
    ddaDisagree.push_back(100.0 * double(differ) / double(v.size()));
    if (n == 64) g64 = v;
  }
  r.cpuMilliseconds = msSince(t0);
  uint64_t truthNonFinite = nonFinitePoints(truth);
  uint64_t ddaIncreases = 0;
  for (size_t i = 1; i < a.size(); ++i)
    if (ddaDisagree[i] > ddaDisagree[i - 1]) ++ddaIncreases;
  // The GPU's G-buffer beside the truth (the picture of docs/exemplar-volume.md),
  // zoomed to [−P/4, P/4]² (4 pixels a voxel: the voxels' blocks show).
  if (ctx.options().images) {
    gpuVolume(ctx);
    const VolParams zoom = testRays(s, kSamples, glm::vec2(0.0f), 0.25f);
    VolParams zoomCapsule = zoom;
    zoomCapsule.camDir.w = float(FT_VOL_IDS_CAPSULE);
    const std::vector<VolHit> gpu = ctx.gpu<ExemplarVolumeGpu>().sample(zoom);
    const std::vector<VolHit> gpuCapsule = ctx.gpu<ExemplarVolumeGpu>().sample(zoomCapsule);
    const std::vector<VolHit> truth = s.truth->firstHits(zoom, 1e30f);
    const int scale = 2, gap = 4, pw = kRays * scale, panels = 5;
    RgbaImage img;
    img.width = panels * pw + (panels - 1) * gap;
    img.height = pw;
    img.pixels.assign(size_t(img.width) * img.height * 4, 255);
    const uint32_t S = uint32_t(s.block.segments.size());
    const auto agreement = [](uint32_t id, uint32_t tid) {
      return id == tid ? (tid == 0 ? glm::uvec3(0) : glm::uvec3(200)) : glm::uvec3(220, 30, 30);
    };
    for (int panel = 0; panel < panels; ++panel)
      for (int y = 0; y < pw; ++y)
        for (int x = 0; x < pw; ++x) {
          const size_t i = size_t(y / scale) * kRays + size_t(x / scale);
          const uint32_t tid = truth[i].id == 0 ? 0 : (truth[i].id - 1) % S + 1;
          glm::uvec3 c;
          if (panel == 0) c = idColour(gpu[i].id);
          else if (panel == 1) c = idColour(gpuCapsule[i].id);
          else if (panel == 2) c = idColour(tid);
          else if (panel == 3) c = agreement(gpu[i].id, tid);
          else c = agreement(gpuCapsule[i].id, tid);
          uint8_t* px = &img.pixels[(size_t(y) * img.width + size_t(panel * (pw + gap) + x)) * 4];
          px[0] = uint8_t(c.x), px[1] = uint8_t(c.y), px[2] = uint8_t(c.z), px[3] = 255;
        }
    r.images.push_back(ctx.saveImage(img, "prt-volume-ids"));
    r.imageCaptions.push_back(fmt::format(
        "segment ids, false colour: (a) GPU G-buffer, midpoint ids, {} samples; (b) GPU G-buffer, capsule ids; (c) "
        "Embree first hit on the 7 × 7 tiled capsules (block id); (d), (e) grey: (a), (b) name Embree's segment, red: "
        "another, black: both miss — {}² orthographic rays over [−P/4, P/4]², 35° off the normal",
        kSamples, kRays));
  }
  std::string trend;
  for (size_t i = 0; i < a.size(); ++i)
    trend += fmt::format("{}N = {}: id {:.2f}%, fiber {:.2f}%, hit/miss {:.2f}%, median |Δx| {:.2f} h, ≠ DDA {:.2f}%",
                         i ? "; " : "", counts[i], a[i].idPct, a[i].fiberPct, a[i].hitMissPct, a[i].medianPointErr,
                         ddaDisagree[i]);
  r.details = trend;
  // Gates on the measured figures of the CI exemplar (docs/exemplar-volume.md)
  // at N = 64, each with a few points of room for a different Embree / TBB
  // build: a regression of the fill or the sampler costs more.
  const Agreement& m = a[1];
  r.metrics = {
      Metric{"embree.truth_voxel_empty", double(truthVoxelEmpty), 0, "rays",
             fmt::format("Embree hits ({} of {}²) whose point lies in an empty voxel (index in double, written "
                         "here): the fill is conservative, so none (a hit point within 1e-5 h of a face may fall "
                         "outside by rounding; none seen)",
                         truthHits, kRays)},
      Metric{"embree.truth_voxel_id_pct", 100.0 * double(truthVoxelId) / double(std::max<uint64_t>(1, truthHits)), 100.0,
             "%", "the voxel at Embree's hit holds the segment hit (the nearest-midpoint fill alone, no sampling)",
             false},
      Metric{"dda.disagree_pct_1024", ddaDisagree.back(), kDdaLimitPct, "%",
             "rays whose N = 1024 sampler id ≠ the exact traversal's (written here): only voxel corners clipped by "
             "less than a step (~0.08 h) are skipped, and the rate falls ∝ step (34, 17, 9.1 % at N = 32, 64, "
             "128 → ~1.1 % expected); measured 1.25 %"},
      Metric{"dda.trend_increases", double(ddaIncreases), 0, "count",
             "the sampler converges to the exact traversal (notes §8.5): its disagreement never grows from N = 32 "
             "to 64, 128, 1024"},
      Metric{"embree.id_disagree_pct", 100.0 - m.idPct, kIdDisagreePct, "%",
             fmt::format("rays (hit by either) whose volume id ≠ Embree's first-hit segment, N = {}; measured 65.6 %: "
                         "the conservative fill is ~3.6× the fibers' cross-section, so the ray meets a neighbour's "
                         "fringe voxel before the true surface (the fill alone, at the true hit: 77 % right)",
                         kSamples)},
      Metric{"embree.fiber_disagree_pct", 100.0 - m.fiberPct, kFiberDisagreePct, "%",
             "the same for the fiber of the segment: measured 62.3 %"},
      Metric{"embree.hitmiss_disagree_pct", 100.0 - m.hitMissPct, kHitMissPct, "%",
             "rays that hit in one and miss in the other: measured 4.3 % (fat voxels catch rays that pass between "
             "fibers)"},
      Metric{"embree.point_median_h", m.medianPointErr, kPointMedianH, "h",
             "median distance of the G-buffer point to Embree's hit, N = 64: measured 2.04 h (fringe ≤ 1.7 h + "
             "part of a 1.3 h step)"},
      Metric{"embree.id_trend", a[0].idPct - a[2].idPct, 100.0, "points",
             fmt::format("id agreement at N = 32 minus N = 128 (004 Fig. 13: more samples, closer to path tracing; "
                         "here the reverse, the exact traversal of a fat volume stops earlier): {}",
                         trend),
             false},
      nonFiniteMetric("cpu", nonFinitePoints(g64) + truthNonFinite, "CPU G-buffer and Embree points"),
  };
  r.finish();
  return r;
}

// ---- prt/vol/capsule ---------------------------------------------------------
CaseResult runCapsuleCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r = start(name);
  VolSetup& s = setup(ctx);
  gpuVolume(ctx);
  VolParams ortho = testRays(s, kSamples);
  ortho.camDir.w = float(FT_VOL_IDS_CAPSULE);
  const VolParams pinhole = pinholeRays(s, kSamples, FT_VOL_IDS_CAPSULE);
  std::vector<VolHit> cpu, gpu, truth, midpoint;
  std::vector<float> gap;
  ExemplarVolumeGpu& g = ctx.gpu<ExemplarVolumeGpu>();
  for (const VolParams* rays : {const_cast<const VolParams*>(&ortho), &pinhole}) {
    const auto t0 = Clock::now();
    std::vector<float> f;
    const std::vector<VolHit> c = sampleVolumeCpu(s.cpu, *rays, &f);
    r.cpuMilliseconds += msSince(t0);
    const auto g0 = Clock::now();
    const std::vector<VolHit> h = g.sample(*rays);
    r.gpuMilliseconds += msSince(g0);
    VolParams mid = *rays;
    mid.camDir.w = float(FT_VOL_IDS_MIDPOINT);
    const std::vector<VolHit> m = sampleVolumeCpu(s.cpu, mid);
    const std::vector<VolHit> t = s.truth->firstHits(*rays, 1e30f);
    cpu.insert(cpu.end(), c.begin(), c.end());
    gpu.insert(gpu.end(), h.begin(), h.end());
    gap.insert(gap.end(), f.begin(), f.end());
    midpoint.insert(midpoint.end(), m.begin(), m.end());
    truth.insert(truth.end(), t.begin(), t.end());
  }
  r.gpuTiming = "wall clock of 2 capsule-id dispatches + read-backs";
  // GPU vs CPU.
  uint64_t mismatched = 0, excluded = 0;
  double pointErr = 0.0;
  size_t firstBad = cpu.size();
  for (size_t i = 0; i < cpu.size(); ++i) {
    if (double(gap[i]) < kCapsuleTieMargin) {
      ++excluded;
      continue;
    }
    if (cpu[i].id != gpu[i].id) {
      ++mismatched;
      if (firstBad == cpu.size()) firstBad = i;
      continue;
    }
    if (cpu[i].id != 0)
      pointErr = maxKeepNaN(pointErr, double(glm::length(cpu[i].point - gpu[i].point)) / double(s.layout.origin.w));
  }
  // Against Embree (no code of common/: round linear curves of the 7 × 7 tiling).
  const Agreement a = agree(s, cpu, truth), am = agree(s, midpoint, truth);
  uint64_t hitsCpu = 0, hitsTruth = 0, hitsMid = 0;
  for (size_t i = 0; i < cpu.size(); ++i) hitsCpu += cpu[i].id != 0, hitsTruth += truth[i].id != 0, hitsMid += midpoint[i].id != 0;
  const double coverage = 100.0 * (double(hitsCpu) / double(std::max<uint64_t>(1, hitsTruth)) - 1.0);
  const double coverageMid = 100.0 * (double(hitsMid) / double(std::max<uint64_t>(1, hitsTruth)) - 1.0);
  r.details = fmt::format(
      "capsule ids: same segment {:.2f} %, same fiber {:.2f} %, hit/miss {:.3f} %, |Δx| median {:.2e} h, p90 {:.2e} h, "
      "coverage {:+.2f} % vs Embree; midpoint ids (N = {}): {:.2f} %, {:.2f} %, {:.2f} %, {:.2f} h, {:.2f} h, {:+.2f} %",
      a.idPct, a.fiberPct, a.hitMissPct, a.medianPointErr, a.p90PointErr, coverage, kSamples, am.idPct, am.fiberPct,
      am.hitMissPct, am.medianPointErr, am.p90PointErr, coverageMid);
  if (firstBad < cpu.size())
    r.details += fmt::format("; first mismatch: {} camera, pixel ({}, {}): cpu id {} gpu id {}",
                             firstBad < size_t(kRays) * kRays ? "orthographic" : "pinhole", firstBad % kRays,
                             firstBad / kRays % kRays, cpu[firstBad].id, gpu[firstBad].id);
  r.metrics = {
      Metric{"capsule.ids_mismatched", double(mismatched), 0, "rays",
             fmt::format("GPU vs CPU capsule ids, orthographic and pinhole cameras, {}² rays each; {} rays whose hit "
                         "and another capsule's entry are within {} h along the ray excluded (ties float decides)",
                         kRays, excluded, kCapsuleTieMargin)},
      Metric{"capsule.points_max_abs", pointErr, kCapsulePointsMaxH, "h",
             "GPU vs CPU hit points (same ids): the same float root, FMA contraction apart (a grazing ray's small "
             "discriminant amplifies it); measured " +
                 fmt::format("{:.1e}", kCapsulePointsMeasured) + " h"},
      Metric{"capsule.id_disagree_pct", 100.0 - a.idPct, kCapsuleIdDisagreePct, "%",
             fmt::format("rays (hit by either) whose capsule id ≠ Embree's first-hit segment; measured {:.2f} % "
                         "(all on the same fiber: the shared end sphere at a joint of two consecutive segments is hit "
                         "at the same t by both, and Embree and we break the tie differently); the midpoint ids: {:.1f} %",
                         kCapsuleIdMeasured, 100.0 - am.idPct)},
      Metric{"capsule.fiber_disagree_pct", 100.0 - a.fiberPct, kCapsuleFiberDisagreePct, "%",
             fmt::format("the same for the fiber of the segment: measured 0 % (midpoint ids: {:.1f} %)", 100.0 - am.fiberPct)},
      Metric{"capsule.hitmiss_disagree_pct", 100.0 - a.hitMissPct, kCapsuleHitMissPct, "%",
             fmt::format("rays hit in one and missed in the other (silhouettes; measured 0 of 2 × 128²); midpoint ids: "
                         "{:.2f} %",
                         100.0 - am.hitMissPct)},
      Metric{"capsule.coverage_excess_abs_pct", std::abs(coverage), kCapsuleCoveragePct, "%",
             fmt::format("|rays hit / Embree's rays hit − 1|: {:+.3f} %, measured 0 (midpoint ids: {:+.1f} %, the "
                         "conservative fill)",
                         coverage, coverageMid)},
      Metric{"capsule.point_median_h", a.medianPointErr, kCapsulePointMedianH, "h",
             "median distance of the hit point to Embree's (rays both hit): the same surface in float; measured 0 "
             "(bit-equal on most rays)"},
      Metric{"capsule.point_p90_h", a.p90PointErr, kCapsulePointP90H, "h",
             "90th percentile of the same: measured 1.9e-5 h (float at |p| ≲ 200 h); the exit root of a fiber is ~r ≈ "
             "0.5 h away"},
      nonFiniteMetric("cpu", nonFinitePoints(cpu), "CPU capsule G-buffer points"),
      nonFiniteMetric("gpu", nonFinitePoints(gpu), "GPU capsule G-buffer points"),
  };
  r.finish();
  return r;
}

}  // namespace

void addExemplarVolumeCases(ValidationContext&, std::vector<ValidationCase>& out) {
  out.push_back({"prt/vol/idvolume", [](ValidationContext& c) { return runIdVolumeCase(c, "prt/vol/idvolume"); }});
  out.push_back({"prt/vol/sampler", [](ValidationContext& c) { return runSamplerCase(c, "prt/vol/sampler"); }});
  out.push_back(
      {"prt/vol/periodicity", [](ValidationContext& c) { return runPeriodicityCase(c, "prt/vol/periodicity"); }});
  out.push_back({"prt/vol/embree", [](ValidationContext& c) { return runEmbreeCase(c, "prt/vol/embree"); }});
  out.push_back({"prt/vol/capsule", [](ValidationContext& c) { return runCapsuleCase(c, "prt/vol/capsule"); }});
}

}  // namespace ft
