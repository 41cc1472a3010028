// exemplar_volume_test.cpp — the index math of the exemplar volume of 004
// §5.1 (common/exemplar_volume.h) against formulas written here: floor-mod
// wrap, voxel coordinates and centres, sample centres along a ray, the slab
// interval, the conservative capsule–box test; a small volume built through
// the candidate grid equal to all-pairs brute force; the scalar sampler on a
// one-voxel volume; the capsule ids (ray–capsule entry against a double
// root search, the whole walk against brute force over the tiled capsules);
// bad input. CPU vs GPU and the Embree truth live in the
// harness (validation/exemplar_volume_cases.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "common/exemplar_volume.h"
#include "reference/exemplar.h"
#include "reference/exemplar_volume.h"
#include "scene/input_error.h"
#include "validation/draw_order.h"

namespace ft {
namespace {

int floorMod(int i, int n) { return int(((long long)i % n + n) % n); }

TEST(ExemplarVolume, WrapIsFloorMod) {
  for (int n : {1, 3, 7, 64, 100})
    for (int i = -400; i <= 400; ++i) ASSERT_EQ(ftVolWrap(i, n), floorMod(i, n)) << "i " << i << " n " << n;
}

VolParams smallLayout() {
  VolParams p{};
  p.origin = glm::vec4(0.0f, 0.0f, -0.5f, 0.125f);  // h = 1/8 (exact in float)
  p.dims = glm::uvec4(8, 8, 8, 1);
  p.grid = glm::uvec4(2, 2, 2, 4);
  return p;
}

TEST(ExemplarVolume, VoxelIndexWrapsXYAndClipsZ) {
  const VolParams p = smallLayout();
  const double h = 0.125;
  for (int z = -2; z < 10; ++z)
    for (int y = -20; y < 20; y += 3)
      for (int x = -20; x < 20; ++x) {
        // The centre of voxel (x, y, z): exact in float.
        const glm::vec3 c(float((x + 0.5) * h), float((y + 0.5) * h), float(-0.5 + (z + 0.5) * h));
        const glm::ivec3 v = ftVolVoxelCoord(c, p.origin);
        ASSERT_EQ(v, glm::ivec3(x, y, z));
        const int expected = z < 0 || z >= 8 ? -1 : (z * 8 + floorMod(y, 8)) * 8 + floorMod(x, 8);
        ASSERT_EQ(ftVolIndex(v, p.dims), expected) << x << " " << y << " " << z;
        if (expected >= 0) {
          ASSERT_EQ(ftVolVoxelOfIndex(uint32_t(expected), p.dims), glm::ivec3(floorMod(x, 8), floorMod(y, 8), z));
          // The centre of the wrapped voxel is the point moved by whole periods.
          const glm::vec3 w = ftVolVoxelCentre(ftVolVoxelOfIndex(uint32_t(expected), p.dims), p.origin);
          EXPECT_NEAR(double(w.x), (floorMod(x, 8) + 0.5) * h, 1e-7);
          EXPECT_NEAR(double(w.y), (floorMod(y, 8) + 0.5) * h, 1e-7);
          EXPECT_NEAR(double(w.z), -0.5 + (z + 0.5) * h, 1e-7);
        }
      }
  // Just below zero: voxel −1, wrapped to n − 1.
  EXPECT_EQ(ftVolIndex(ftVolVoxelCoord(glm::vec3(-1e-4f, 0.01f, 0.0f), p.origin), p.dims), 4 * 64 + 0 * 8 + 7);
  EXPECT_EQ(ftVolPeriod(p), 1.0f);
}

TEST(ExemplarVolume, SampleCentresSpanTheSegment) {
  for (uint32_t n : {1u, 2u, 32u, 64u, 128u}) {
    const double t0 = 0.37, t1 = 2.91, step = (t1 - t0) / n;
    double sum = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
      const double t = ftVolSampleT(float(t0), float(t1), i, n);
      EXPECT_NEAR(t, t0 + (i + 0.5) * step, 1e-6) << n << " " << i;
      EXPECT_GT(t, t0);
      EXPECT_LT(t, t1);
      sum += t;
    }
    EXPECT_NEAR(sum / n, 0.5 * (t0 + t1), 1e-6);  // symmetric about the middle
  }
}

TEST(ExemplarVolume, SlabInterval) {
  const glm::vec3 o(0.3f, -0.2f, 2.0f), d = glm::normalize(glm::vec3(0.5f, 0.1f, -1.0f));
  const glm::vec2 t = ftVolSlabInterval(o, d, -0.5f, 0.5f);
  EXPECT_NEAR(double(t.x), (2.0 - 0.5) / -double(d.z), 1e-5);
  EXPECT_NEAR(double(t.y), (2.0 + 0.5) / -double(d.z), 1e-5);
  // Starting inside: from t = 0; horizontal: no segment; pointing away: empty.
  EXPECT_EQ(ftVolSlabInterval(glm::vec3(0.0f), d, -0.5f, 0.5f).x, 0.0f);
  const glm::vec2 hz = ftVolSlabInterval(o, glm::vec3(1.0f, 0.0f, 0.0f), -0.5f, 0.5f);
  EXPECT_GT(hz.x, hz.y);
  const glm::vec2 away = ftVolSlabInterval(o, -d, -0.5f, 0.5f);
  EXPECT_GT(away.x, away.y);
}

// Distance from a point to a box, and from a segment to a box by dense
// sampling (an upper bound within the sampling step).
double pointBoxDistance(glm::dvec3 p, glm::dvec3 lo, glm::dvec3 hi) {
  return glm::length(glm::max(glm::max(lo - p, p - hi), glm::dvec3(0.0)));
}
double segmentBoxDistance(glm::dvec3 a, glm::dvec3 b, glm::dvec3 lo, glm::dvec3 hi, int steps) {
  double best = 1e30;
  for (int i = 0; i <= steps; ++i) best = std::min(best, pointBoxDistance(a + (b - a) * (double(i) / steps), lo, hi));
  return best;
}

TEST(ExemplarVolume, CapsuleBoxTestIsConservativeAndBounded) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  const glm::vec3 lo(-0.5f), hi(0.5f);
  int touching = 0;
  for (int k = 0; k < 6000; ++k) {
    const glm::vec3 a = drawVec3<glm::vec3>(u, rng), b = drawVec3<glm::vec3>(u, rng);
    const float r = 0.25f;
    const bool t = ftVolSegmentTouchesBox(a, b, r, lo, hi);
    const double len = glm::length(glm::dvec3(b - a));
    const double d = segmentBoxDistance(a, b, lo, hi, 4000);
    // Sampling overestimates the distance by at most half a step.
    if (d + 0.5 * len / 4000 < r - 1e-6) {
      ASSERT_TRUE(t) << "missed a capsule at distance " << d;
    }
    // The grown box reaches at most √3 r from the box (its corners).
    if (t) {
      ++touching;
      ASSERT_LE(d - 0.5 * len / 4000, std::sqrt(3.0) * r + 1e-5);
    }
  }
  EXPECT_GT(touching, 300);
  // Axis-parallel segments (a zero direction component) on either side of a face.
  EXPECT_TRUE(ftVolSegmentTouchesBox(glm::vec3(0.74f, -2, 0), glm::vec3(0.74f, 2, 0), 0.25f, lo, hi));
  EXPECT_FALSE(ftVolSegmentTouchesBox(glm::vec3(0.76f, -2, 0), glm::vec3(0.76f, 2, 0), 0.25f, lo, hi));
}

// A tiny block: 5 segments in a unit period, some across the block's edges.
Exemplar tinyBlock() {
  Exemplar e;
  e.period = 1.0f;
  const float r = 0.05f;
  e.segments = {
      {glm::vec3(0.1f, 0.2f, 0.0f), glm::vec3(0.6f, 0.25f, 0.05f), r, 0},
      {glm::vec3(0.6f, 0.25f, 0.05f), glm::vec3(1.15f, 0.3f, 0.0f), r, 0},   // across x = P
      {glm::vec3(0.5f, -0.1f, -0.05f), glm::vec3(0.45f, 0.4f, 0.0f), r, 1},  // across y = 0
      {glm::vec3(0.45f, 0.4f, 0.0f), glm::vec3(0.4f, 0.9f, 0.05f), r, 1},
      {glm::vec3(0.8f, 0.7f, 0.1f), glm::vec3(0.82f, 0.72f, -0.1f), 0.07f, 2},
  };
  e.fibers = 3;
  return e;
}

TEST(ExemplarVolume, CandidateGridEqualsAllPairs) {
  const Exemplar e = tinyBlock();
  const VolParams p = makeVolumeLayout(e, 20, 3);
  EXPECT_EQ(p.dims.x, 20u);
  EXPECT_FLOAT_EQ(p.origin.w, 0.05f);
  const ExemplarVolume v = buildExemplarVolumeCpu(e, p, buildVolumeCandidates(e, p));
  const float P = ftVolPeriod(p), h = p.origin.w;
  size_t nonEmpty = 0;
  for (uint32_t i = 0; i < v.ids.size(); ++i) {
    const glm::ivec3 vx = ftVolVoxelOfIndex(i, p.dims);
    const glm::vec3 c = ftVolVoxelCentre(vx, p.origin);
    uint32_t best = 0;
    float bestKey = std::numeric_limits<float>::infinity();
    for (uint32_t k = 0; k < e.segments.size(); ++k)
      for (int cy = -1; cy <= 1; ++cy)
        for (int cx = -1; cx <= 1; ++cx) {
          const glm::vec3 off(float(cx) * P, float(cy) * P, 0.0f);
          const ExemplarSegment& s = e.segments[k];
          if (!ftVolSegmentTouchesBox(s.a + off, s.b + off, s.radius, c - 0.5f * h, c + 0.5f * h)) continue;
          const float key = ftVolMidpointKey(c, s.a + off, s.b + off);
          if (key < bestKey || (key == bestKey && k + 1 < best)) best = k + 1, bestKey = key;
        }
    ASSERT_EQ(v.ids[i], best) << "voxel " << vx.x << " " << vx.y << " " << vx.z;
    nonEmpty += best != 0;
  }
  EXPECT_GT(nonEmpty, 100u);
  // Periodic: the voxel column at x = 0 holds the part of segment 1 beyond x = P.
  const int idx = ftVolIndex(ftVolVoxelCoord(glm::vec3(0.12f, 0.3f, 0.0f), p.origin), p.dims);
  ASSERT_GE(idx, 0);
  EXPECT_EQ(v.ids[size_t(idx)], 2u);
}

TEST(ExemplarVolume, SamplerFindsTheOneVoxel) {
  ExemplarVolume v;
  v.layout = smallLayout();
  v.ids.assign(512, 0u);
  v.ids[size_t((3 * 8 + 5) * 8 + 2)] = 42u;  // voxel (2, 5, 3): x ∈ [0.25, 0.375), y ∈ [0.625, 0.75), z ∈ [−0.125, 0)
  VolParams rays = v.layout;
  VolCamera cam;
  cam.type = FT_VOL_CAMERA_ORTHO;
  cam.direction = glm::vec3(0.0f, 0.0f, -1.0f);
  cam.up = glm::vec3(0.0f, 1.0f, 0.0f);
  // One pixel per voxel column over the periodic block moved by −P in x.
  cam.position = glm::vec3(-0.5f, 0.5f, 3.0f);
  cam.halfWidth = cam.halfHeight = 0.5f;
  setVolumeRays(rays, cam, 8, 8, 64);
  std::vector<float> face;
  const std::vector<VolHit> g = sampleVolumeCpu(v, rays, &face);
  int hits = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const VolHit& hit = g[size_t(y) * 8 + x];
      if (hit.id == 0) continue;
      ++hits;
      EXPECT_EQ(hit.id, 42u);
      EXPECT_EQ(x, 2);      // x = −1 + (2 + ½)/8 wraps to voxel 2
      EXPECT_EQ(y, 7 - 5);  // row 0 at the top: y = 1 − (row + ½)/8
      // Slab z ∈ [−0.5, 0.5], 64 sample centres of step 1/64 from the top:
      // the first inside z < 0 is z = 0.5 − (32 + ½)/64.
      EXPECT_NEAR(double(hit.point.z), 0.5 - 32.5 / 64.0, 1e-6);
      EXPECT_NEAR(double(hit.point.x), -1.0 + 2.5 / 8.0, 1e-6);
    }
  EXPECT_EQ(hits, 1);
  for (float f : face) EXPECT_GT(f, 0.0f);
}

// ---- capsule ids ---------------------------------------------------------------
// The entry of a ray into a capsule in double, written here: the smallest root
// of dist(o + t d, segment) = r by sphere tracing (no quadratics).
double entryBySphereTracing(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b, double r,
                       double tMax) {
  auto dist = [&](double t) {
    const glm::dvec3 p = o + t * d, ab = b - a;
    const double u = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    return glm::length(p - (a + u * ab)) - r;
  };
  // Sphere tracing: dist is 1-Lipschitz in t (|d| = 1), so a step of dist(t) never passes the surface.
  double t = 0.0;
  for (int i = 0; i < 1000000 && t < tMax; ++i) {
    const double f = dist(t);
    if (f < 1e-10) return t;
    t += f;
  }
  return -1.0;
}

TEST(ExemplarVolume, RayCapsuleEntryMatchesSphereTracing) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int hits = 0, misses = 0;
  for (int i = 0; i < 300; ++i) {
    const glm::vec3 a = drawVec3<glm::vec3>(u, rng), b = a + 0.6f * drawVec3<glm::vec3>(u, rng);
    const float r = 0.05f + 0.2f * std::abs(u(rng));
    // Rays from 3 units away aimed near the capsule (some hit, some pass).
    const glm::vec3 target = 0.5f * (a + b) + 0.4f * drawVec3<glm::vec3>(u, rng);
    const glm::vec3 o = target + 3.0f * glm::normalize(drawVec3<glm::vec3>(u, rng));
    const glm::vec3 d = glm::normalize(target - o);
    const float t = ftVolRayCapsule(o, d, a, b, r);
    const double tr = entryBySphereTracing(glm::dvec3(o), glm::dvec3(d), glm::dvec3(a), glm::dvec3(b), r, 8.0);
    if (tr < 0.0) {
      ++misses;
      EXPECT_LT(t, 0.0f) << "ray " << i;
    } else {
      ++hits;
      EXPECT_NEAR(double(t), tr, 1e-4) << "ray " << i;  // float roots; a grazing entry's small discriminant amplifies
    }
  }
  EXPECT_GT(hits, 50);
  EXPECT_GT(misses, 50);
  // Along the axis: the end sphere; a ray starting beyond the capsule: none.
  EXPECT_NEAR(ftVolRayCapsule(glm::vec3(-2, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), 0.25f), 1.75f,
              1e-6f);
  EXPECT_LT(ftVolRayCapsule(glm::vec3(3, 0, 0), glm::vec3(1, 0, 0), glm::vec3(0, 0, 0), glm::vec3(1, 0, 0), 0.25f), 0.0f);
}

// Brute force in double over the tiled capsules (all copies within ±4 P),
// the entry by the quadratics written here (lateral + end spheres).
struct Brute {
  uint32_t id = 0;
  double t = -1.0, gap = 1e300;
  double graze = 1e300;  // min over capsules of |distance(ray line, axis) − r|: a silhouette
};
Brute bruteFirstHit(const Exemplar& e, const glm::dvec3& o, const glm::dvec3& d) {
  std::vector<std::pair<double, uint32_t>> all;
  double graze = 1e300;
  for (uint32_t k = 0; k < e.segments.size(); ++k)
    for (int ty = -4; ty <= 4; ++ty)
      for (int tx = -4; tx <= 4; ++tx) {
        const glm::dvec3 off(tx * double(e.period), ty * double(e.period), 0.0);
        const glm::dvec3 a = glm::dvec3(e.segments[k].a) + off, b = glm::dvec3(e.segments[k].b) + off;
        const double r = e.segments[k].radius;
        {  // the line–segment distance: |(a − o)⊥ + u (b − a)⊥| minimised over u ∈ [0, 1] (⊥ to d)
          const glm::dvec3 w = (a - o) - glm::dot(a - o, d) * d, ab = (b - a) - glm::dot(b - a, d) * d;
          const double uu = glm::dot(ab, ab) > 0.0 ? std::clamp(-glm::dot(w, ab) / glm::dot(ab, ab), 0.0, 1.0) : 0.0;
          graze = std::min(graze, std::abs(glm::length(w + uu * ab) - r));
        }
        double best = -1.0;
        auto keep = [&](double t) {
          if (t >= 0.0 && (best < 0.0 || t < best)) best = t;
        };
        for (const glm::dvec3& c : {a, b}) {  // spheres: |o + t d − c|² = r²
          const glm::dvec3 oc = o - c;
          const double B = glm::dot(oc, d), C = glm::dot(oc, oc) - r * r, D = B * B - C;
          if (D >= 0.0) keep(-B - std::sqrt(D));
        }
        const glm::dvec3 ax = glm::normalize(b - a), oa = o - a;  // cylinder
        const glm::dvec3 dp = d - glm::dot(d, ax) * ax, op = oa - glm::dot(oa, ax) * ax;
        const double A = glm::dot(dp, dp), B = glm::dot(dp, op), C = glm::dot(op, op) - r * r, D = B * B - A * C;
        if (A > 0.0 && D >= 0.0) {
          const double t = (-B - std::sqrt(D)) / A, y = glm::dot(oa + t * d, ax);
          if (y >= 0.0 && y <= glm::length(b - a)) keep(t);
        }
        if (best >= 0.0) all.push_back({best, k + 1});
      }
  Brute out;
  out.graze = graze;
  if (all.empty()) return out;
  std::sort(all.begin(), all.end());
  out.t = all[0].first;
  out.id = all[0].second;
  for (size_t i = 1; i < all.size(); ++i)
    if (all[i].second != out.id) {
      out.gap = all[i].first - out.t;
      break;
    }
  return out;
}

TEST(ExemplarVolume, CapsuleIdsEqualBruteForce) {
  const Exemplar e = tinyBlock();
  // 20 voxels a period in cells of 3: the last cell of each row is partial.
  const VolParams p = makeVolumeLayout(e, 20, 3);
  const ExemplarVolume v = buildExemplarVolumeCpu(e, p, buildVolumeCandidates(e, p));
  const float h = p.origin.w;
  int compared = 0, hits = 0, skipped = 0;
  for (int camera = 0; camera < 2; ++camera) {
    VolCamera cam;
    if (camera == 0) {  // orthographic, 40° off the normal over [−1.5, 1.5]²
      cam.type = FT_VOL_CAMERA_ORTHO;
      cam.direction = glm::vec3(0.55f, -0.3f, -0.78f);
      cam.up = glm::vec3(0.0f, 0.0f, 1.0f);
      cam.position = glm::vec3(0.2f, 0.1f, 0.0f) - 2.0f * cam.direction;
      cam.halfWidth = cam.halfHeight = 1.5f;
    } else {  // pinhole above the block
      cam.type = FT_VOL_CAMERA_PINHOLE;
      cam.direction = glm::vec3(0.3f, 0.2f, -1.0f);
      cam.up = glm::vec3(0.0f, 0.0f, 1.0f);
      cam.position = glm::vec3(0.0f, 0.0f, 0.8f);
      cam.halfWidth = cam.halfHeight = 1.0f;
    }
    VolParams rays = v.layout;
    setVolumeRays(rays, cam, 48, 48, 1, FT_VOL_IDS_CAPSULE);
    const std::vector<VolHit> g = sampleVolumeCpu(v, rays);
    for (uint32_t y = 0; y < 48; ++y)
      for (uint32_t x = 0; x < 48; ++x) {
        const glm::vec3 o = ftVolRayOrigin(rays, x, y), d = ftVolRayDirection(rays, x, y);
        const Brute b = bruteFirstHit(e, glm::dvec3(o), glm::dvec3(d));
        const VolHit& hit = g[size_t(y) * 48 + x];
        // A tie (a joint: either id is right) or a silhouette within float of the surface (hit or miss).
        if (b.gap < 1e-4 * h || b.graze < 1e-4 * h) {
          ++skipped;
          continue;
        }
        ++compared;
        ASSERT_EQ(hit.id, b.id) << "camera " << camera << " pixel " << x << " " << y;
        if (b.id == 0) continue;
        ++hits;
        const glm::dvec3 q = glm::dvec3(o) + b.t * glm::dvec3(d);
        // float: o + t d at |p| ≲ 3 P, and a grazing entry's small discriminant amplifies the rounding
        EXPECT_LT(glm::length(glm::dvec3(hit.point) - q), 1e-3 * h) << "camera " << camera << " pixel " << x << " " << y;
      }
  }
  EXPECT_GT(compared, 4000);
  EXPECT_GT(hits, 500);
  EXPECT_LT(skipped, 50);
}

TEST(ExemplarVolume, CapsuleIdsNeedCandidatesAndNamedModes) {
  ExemplarVolume v;  // ids only: no segment table, no candidates
  v.layout = smallLayout();
  v.ids.assign(512, 0u);
  VolParams rays = v.layout;
  VolCamera cam;
  setVolumeRays(rays, cam, 4, 4, 8, FT_VOL_IDS_CAPSULE);
  EXPECT_THROW(sampleVolumeCpu(v, rays), std::invalid_argument);
  EXPECT_THROW(setVolumeRays(rays, cam, 4, 4, 8, 7u), std::invalid_argument);
  EXPECT_EQ(parseVolumeIds("capsule"), FT_VOL_IDS_CAPSULE);
  EXPECT_EQ(parseVolumeIds("midpoint"), FT_VOL_IDS_MIDPOINT);
  try {
    parseVolumeIds("nearest");
    FAIL() << "no throw";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("nearest"), std::string::npos);
  }
}

TEST(ExemplarVolume, CameraRays) {
  VolParams p = smallLayout();
  VolCamera cam;
  cam.type = FT_VOL_CAMERA_PINHOLE;
  cam.position = glm::vec3(0.1f, 0.2f, 3.0f);
  cam.direction = glm::vec3(0.0f, 0.0f, -2.0f);  // not unit: normalised
  cam.up = glm::vec3(0.0f, 1.0f, 0.0f);
  cam.halfWidth = 0.5f;
  cam.halfHeight = 0.25f;
  setVolumeRays(p, cam, 4, 2, 8);
  for (uint32_t y = 0; y < 2; ++y)
    for (uint32_t x = 0; x < 4; ++x) {
      // Pixel centre on the image plane at distance 1: right = +x, up = +y, row 0 at the top.
      const double sx = (x + 0.5) / 2.0 - 1.0, sy = 1.0 - (y + 0.5);
      const glm::dvec3 d = glm::normalize(glm::dvec3(0.5 * sx, 0.25 * sy, -1.0));
      const glm::vec3 o = ftVolRayOrigin(p, x, y), e = ftVolRayDirection(p, x, y);
      EXPECT_EQ(o, cam.position);
      EXPECT_NEAR(double(e.x), d.x, 1e-6);
      EXPECT_NEAR(double(e.y), d.y, 1e-6);
      EXPECT_NEAR(double(e.z), d.z, 1e-6);
    }
  cam.type = FT_VOL_CAMERA_ORTHO;
  setVolumeRays(p, cam, 4, 2, 8);
  for (uint32_t y = 0; y < 2; ++y)
    for (uint32_t x = 0; x < 4; ++x) {
      const double sx = (x + 0.5) / 2.0 - 1.0, sy = 1.0 - (y + 0.5);
      const glm::vec3 o = ftVolRayOrigin(p, x, y);
      EXPECT_NEAR(double(o.x), 0.1 + 0.5 * sx, 1e-6);
      EXPECT_NEAR(double(o.y), 0.2 + 0.25 * sy, 1e-6);
      EXPECT_NEAR(double(o.z), 3.0, 1e-6);
      EXPECT_EQ(ftVolRayDirection(p, x, y), glm::vec3(0.0f, 0.0f, -1.0f));
    }
}

TEST(ExemplarVolume, BadInputIsNamed) {
  Exemplar empty;
  empty.period = 1.0f;
  EXPECT_THROW(makeVolumeLayout(empty), InputError);
  Exemplar far = tinyBlock();
  far.segments[3].b = glm::vec3(0.4f, 2.5f, 0.0f);
  try {
    makeVolumeLayout(far);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("segment 3"), std::string::npos) << e.what();
  }
  Exemplar nan = tinyBlock();
  nan.segments[1].radius = std::nanf("");
  EXPECT_THROW(makeVolumeLayout(nan), InputError);
  VolParams p = smallLayout();
  VolCamera cam;
  EXPECT_THROW(setVolumeRays(p, cam, 8, 8, 0), std::invalid_argument);
  cam.up = cam.direction;
  EXPECT_THROW(setVolumeRays(p, cam, 8, 8, 8), std::invalid_argument);
}

}  // namespace
}  // namespace ft
