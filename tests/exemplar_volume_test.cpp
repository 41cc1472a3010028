// exemplar_volume_test.cpp — the index math of the exemplar volume of 004
// §5.1 (common/exemplar_volume.h) against formulas written here: floor-mod
// wrap, voxel coordinates and centres, sample centres along a ray, the slab
// interval, the conservative capsule–box test; a small volume built through
// the candidate grid equal to all-pairs brute force; the scalar sampler on a
// one-voxel volume; bad input. CPU vs GPU and the Embree truth live in the
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
    const glm::vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
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
