// Unit tests of the shared fiber math in common/ (compiled as C++ here; the
// GPU compiles the same text). Each tolerance says why.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/fiber_generation.h"
#include "common/lod.h"
#include "common/yarn_frame.h"
#include "reference/fiber_reference.h"
#include "scene/bcc_reader.h"
#include "scene/camera.h"
#include "scene/default_scene.h"
#include "scene/yarn_fibers.h"
#include "tests/test_data.h"
#include "validation/draw_order.h"

namespace ft {
namespace {

struct SceneData {
  YarnModel model;
  YarnBuffers buffers;
  std::vector<FrameNormal> frames;
  explicit SceneData(YarnModel m) : model(std::move(m)), buffers(buildYarnBuffers(model)), frames(computeKnotFramesCpu(buffers)) {}
};

const SceneData& defaultSetup() {
  static const SceneData s(makeDefaultScene());
  return s;
}

YarnParams paramsFor(const char* yarn, std::vector<FiberCoord>* tableOut = nullptr) {
  const YarnPreset& p = findYarnPreset(yarn);
  FiberSetup fibers = makeFiberSetup(p, FiberOptions{});
  if (tableOut) *tableOut = std::move(fibers.table);
  return fibers.params;
}

TEST(YarnCurve, CatmullRomToBezierMatchesDirectEvaluation) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int trial = 0; trial < 100; ++trial) {
    vec3 p[4];
    for (vec3& q : p) q = drawVec3<vec3>(u, rng);
    CurveInfo c{0, 4, 0, 0, 1.0f, FT_BASIS_CATMULL_ROM, 0, 0};
    SegmentIndices idx = ftSegmentIndices(c, 1);
    ASSERT_EQ(idx.i0, 0u);
    ASSERT_EQ(idx.i3, 3u);
    YarnSegment seg = ftMakeSegment(c, 1, idx, vec4(p[0], 0), vec4(p[1], 0), vec4(p[2], 0), vec4(p[3], 0));
    for (float t = 0.0f; t <= 1.0f; t += 0.125f) {
      // Two float evaluations of one cubic with |p| <= 1: agree to ~1e-6.
      EXPECT_LT(glm::length(ftBezierPoint(seg, t) - ftCatmullRomPoint(p[0], p[1], p[2], p[3], t)), 2e-6f);
    }
  }
}

TEST(YarnCurve, OpenEndsReflectAndClosedCurvesWrap) {
  CurveInfo open{10, 5, 0, 0, 1.0f, FT_BASIS_CATMULL_ROM, 0, 0};
  EXPECT_EQ(ftCurveSegmentCount(open), 4u);
  SegmentIndices first = ftSegmentIndices(open, 0), last = ftSegmentIndices(open, 3);
  EXPECT_EQ(first.reflectStart, 1u);
  EXPECT_EQ(first.i1, 10u);
  EXPECT_EQ(last.reflectEnd, 1u);
  EXPECT_EQ(last.i2, 14u);
  CurveInfo closed{10, 5, 1, 0, 1.0f, FT_BASIS_CATMULL_ROM, 0, 0};
  EXPECT_EQ(ftCurveSegmentCount(closed), 5u);
  SegmentIndices wrap = ftSegmentIndices(closed, 4);
  EXPECT_EQ(wrap.i0, 13u);
  EXPECT_EQ(wrap.i1, 14u);
  EXPECT_EQ(wrap.i2, 10u);
  EXPECT_EQ(wrap.i3, 11u);
  // Reflection keeps the end tangent along the chord.
  YarnSegment s = ftMakeSegment(open, 0, first, vec4(0), vec4(0, 0, 0, 0), vec4(1, 0, 0, 1), vec4(2, 1, 0, 2));
  vec3 d = ftBezierDerivative(s, 0.0f);
  EXPECT_NEAR(d.y, 0.0f, 1e-7f);
  EXPECT_NEAR(d.z, 0.0f, 1e-7f);
}

// Frame along every segment: unit, ⟂ T, right-handed, and continuous at knots.
TEST(YarnFrame, OrthonormalAndContinuousAtKnots) {
  const SceneData& s = defaultSetup();
  for (size_t ci = 0; ci < s.buffers.curves.size(); ++ci) {
    const CurveInfo& c = s.buffers.curves[ci];
    for (uint32_t k = 0; k < ftCurveSegmentCount(c); ++k) {
      const YarnSegment seg = loadSegmentCpu(s.buffers, s.frames, c.firstSegment + k);
      for (float t = 0.0f; t <= 1.0f; t += 0.25f) {
        YarnFrame f = ftYarnFrameAt(seg, t);
        EXPECT_NEAR(glm::length(f.N), 1.0f, 1e-5f);  // a few ulps from sqrt-normalize
        EXPECT_NEAR(glm::dot(f.N, f.T), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(glm::cross(f.T, f.N), f.B), 1.0f, 1e-5f);
      }
      const bool hasNext = k + 1 < ftCurveSegmentCount(c);
      if (hasNext || c.closed) {
        const YarnSegment next = loadSegmentCpu(s.buffers, s.frames, c.firstSegment + (hasNext ? k + 1 : 0));
        YarnFrame a = ftYarnFrameAt(seg, 1.0f), b = ftYarnFrameAt(next, 0.0f);
        // Same knot, same normal; tangents equal up to float rounding of two
        // algebraically equal Bézier differences: 1e-4 rad is far below one
        // twist step (~10°).
        EXPECT_LT(glm::length(a.N - b.N), 1e-4f) << "curve " << ci << " knot " << k + 1;
        EXPECT_LT(glm::length(a.center - b.center), 1e-6f);
      }
    }
  }
}

// A rotation-minimizing frame does not rotate about a straight yarn, even
// when it points straight up (where an up-vector frame is undefined).
TEST(YarnFrame, StraightVerticalYarnHasConstantFrame) {
  YarnModel m;
  m.name = "vertical";
  YarnCurve c;
  for (int i = 0; i < 20; ++i) c.points.push_back(vec3(0.0f, 0.03f * i, 0.0f));
  m.curves.push_back(c);
  SceneData s(m);
  for (const FrameNormal& n : s.frames) EXPECT_LT(glm::length(vec3(n.normal) - vec3(s.frames[0].normal)), 1e-6f);
}

// On a planar curve the RMF normal keeps a constant angle to the plane.
TEST(YarnFrame, PlanarCurveNormalKeepsItsAngleToThePlane) {
  YarnModel m;
  m.name = "planar";
  YarnCurve c;
  for (int i = 0; i < 80; ++i) {
    float a = 0.05f * i;
    c.points.push_back(vec3(std::cos(a) * (1.0f + 0.3f * a), 0.0f, std::sin(a) * (1.0f + 0.3f * a)));
  }
  m.curves.push_back(c);
  SceneData s(m);
  const float first = glm::dot(vec3(s.frames[0].normal), vec3(0, 1, 0));
  for (const FrameNormal& n : s.frames) EXPECT_NEAR(glm::dot(vec3(n.normal), vec3(0, 1, 0)), first, 1e-4f);
}

// On the real models the frame never flips: between consecutive knots the
// normal turns by no more than the tangent's total turning along the segment
// (a rotation-minimizing frame has N' = -(T'·N) T, so |N'| <= |T'|) plus the
// closed-loop holonomy share, at most π·Δs/L. A fixed-up-vector frame fails
// this near vertical yarn, a Frenet frame at every inflection.
TEST(YarnFrame, RealModelsNormalsTurnNoMoreThanTangents) {
  for (const char* name : {"glove.bcc", "fiber.bcc"}) {
    const std::filesystem::path path = ft::test::yarnModel(name);
    const SceneData s(readBcc(path));
    size_t checked = 0;
    for (const CurveInfo& c : s.buffers.curves) {
      const uint32_t segments = ftCurveSegmentCount(c);
      for (uint32_t k = 0; k < segments; ++k) {
        const YarnSegment seg = loadSegmentCpu(s.buffers, s.frames, c.firstSegment + k);
        double tangentTurn = 0.0;  // total turning of T, sampled finely enough for these short segments
        for (int i = 0; i < 32; ++i) {
          const vec3 t0 = ftNormalize(ftBezierDerivative(seg, i / 32.0f));
          const vec3 t1 = ftNormalize(ftBezierDerivative(seg, (i + 1) / 32.0f));
          tangentTurn += std::acos(std::clamp(double(glm::dot(t0, t1)), -1.0, 1.0));
        }
        const double normalTurn =
            std::acos(std::clamp(double(glm::dot(vec3(seg.n0), vec3(seg.n1))), -1.0, 1.0));
        const double holonomyShare = c.closed ? M_PI * (seg.s1 - seg.s0) / c.totalLength : 0.0;
        // 1e-3 rad: float rounding of the propagation over up to 19,730 knots.
        // Double reflection is rotation-minimizing to 4th order, not exactly
        // (Wang et al. 2008): its normal may turn a few percent more than the
        // exact bound (worst seen: 1.03× on fiber.bcc). A flip (π) or a spin
        // unrelated to T breaks 1.1× by orders of magnitude.
        ASSERT_LE(normalTurn, 1.1 * tangentTurn + holonomyShare + 1e-4) << name << " segment " << c.firstSegment + k;
        ++checked;
      }
    }
    EXPECT_GT(checked, 10000u) << name;
  }
}

// Fibers are continuous from one segment into the next, including across the
// seam of a closed yarn (whole-turn twist rates).
TEST(FiberGeometry, FibersAreContinuousAcrossSegmentsAndSeams) {
  const SceneData& s = defaultSetup();
  std::vector<FiberCoord> table;
  const YarnParams p = paramsFor("cotton1", &table);
  SegmentDecision d{1.0f, 0.01f, p.regularFibers, 4, 0, 0, 0, 4};  // 4 lines for the fibers and the cores
  for (size_t ci = 0; ci < s.buffers.curves.size(); ++ci) {
    const CurveInfo& c = s.buffers.curves[ci];
    const TwistRates r = ftTwistRates(p, c);
    const uint32_t n = ftCurveSegmentCount(c);
    for (uint32_t k = 0; k < n; ++k) {
      if (k + 1 == n && !c.closed) break;
      const uint32_t a = c.firstSegment + k, b = c.firstSegment + (k + 1) % n;
      const YarnSegment sa = loadSegmentCpu(s.buffers, s.frames, a), sb = loadSegmentCpu(s.buffers, s.frames, b);
      for (uint32_t ply = 0; ply < p.plyCount; ++ply)
        for (uint32_t slot = 0; slot <= p.regularFibers; ++slot) {
          const FiberCoord fc = slot ? table[ftSlotFiber(p, slot)] : FiberCoord{0, 0};
          FiberVertex end = ftFiberVertex(p, r, sa, d, uint(ci), a, ply, slot, fc, 4);
          FiberVertex start = ftFiberVertex(p, r, sb, d, uint(ci), b, ply, slot, fc, 0);
          const bool hair = (end.id.w & 0xFFu) == FT_FIBER_HAIR || (start.id.w & 0xFFu) == FT_FIBER_HAIR;
          if (hair && (end.id.w >> 16) != (start.id.w >> 16)) continue;  // a hair's free end at a period start
          // Same length coordinate up to one rounding of s0 + 1·(s1 - s0):
          // 1e-3 of a fiber radius.
          EXPECT_LT(glm::length(vec3(end.position) - vec3(start.position)), 1e-3f * p.fiberRadius)
              << "curve " << ci << " segments " << a << "→" << b << " ply " << ply << " slot " << slot;
        }
    }
  }
}

// Closed curves round each rate to the NEAREST whole number of turns over
// the loop (fiber_geometry.h): the pitch changes by at most half a turn. The
// seam test above holds for any whole number (rounding down too), so this
// one checks the number itself against round() written here, over loop
// lengths whose fractional turn count sweeps [0, 1) (issue 14, deliverable 12).
TEST(FiberGeometry, ClosedCurvesRoundTwistToTheNearestWholeTurn) {
  const YarnParams p = paramsFor("cotton1");
  int checked = 0, roundedUp = 0;
  for (int i = 0; i < 200; ++i) {
    CurveInfo c{};
    c.closed = 1u;
    c.totalLength = 3.0f + 0.0137f * float(i);
    const TwistRates r = ftTwistRates(p, c);
    const double L = c.totalLength;
    const struct { const char* what; double rate, rounded; } rates[] = {
        {"ply", p.plyTurnsPerLength, r.ply},
        {"fiber", p.fiberTurnsPerLength, r.fiber},
        {"migration", double(p.fiberTurnsPerLength) * p.migrationS, r.migration}};
    for (const auto& x : rates) {
      const double expected = std::max(1.0, std::round(double(float(x.rate)) * L));
      // 1e-5 turns: one float rounding of turns / L times L.
      EXPECT_NEAR(x.rounded * L, expected, 1e-5 * expected) << x.what << " over loop length " << L;
      roundedUp += expected > x.rate * L ? 1 : 0;
      ++checked;
    }
    EXPECT_EQ(r.migrationPeriods, uint32_t(std::max(1.0, std::round(double(float(rates[2].rate)) * L))))
        << "loop length " << L;
  }
  EXPECT_GT(roundedUp, checked / 4) << "the sweep must include loops whose turn count rounds up";
  // An open curve keeps the preset's rates.
  CurveInfo open{};
  open.totalLength = 5.0f;
  const TwistRates r = ftTwistRates(p, open);
  EXPECT_EQ(r.ply, p.plyTurnsPerLength);
  EXPECT_EQ(r.migrationPeriods, 0u);
}

// The random draws of one flyaway cell are independent of each other, of
// the neighbouring period and of the neighbouring fiber (rng.h: one stream
// per draw). Each normal deviate is recovered from the cell (means far from 0
// so abs() never folds), and every pair of features from different draws —
// deviates, their squares (a uniform reused inside Box-Muller shows there),
// the type and free-end bits — must be uncorrelated: |ρ| < 5/√N, by chance
// with probability < 1e-6 per pair (issue 14, deliverable 12).
TEST(FiberGeometry, PerPeriodRandomDrawsAreIndependent) {
  YarnParams p = paramsFor("cotton1");
  p.loopProbability = 0.0f;
  p.hairProbability = 0.5f;
  p.flyawayCells = 1u;
  const TwistRates r{1.0f, 1.0f, 1.0f, 0u};
  p.hairZeMu = 0.4f, p.hairZeSigma = 0.1f;  // span = ze · migration · cells stays inside (1e-3, 0.95)
  p.hairR0Mu = p.hairReMu = p.hairPeMu = 5.0f;
  p.hairR0Sigma = p.hairReSigma = p.hairPeSigma = 1.0f;
  const int periods = 8000, fibers = 4;
  // Per cell: the four deviates (draw), their squares, type and end bits.
  struct Cell { double z[4]; double hair, atEnd; };
  std::vector<Cell> cells(size_t(periods) * fibers);
  for (int f = 0; f < fibers; ++f)
    for (int k = 0; k < periods; ++k) {
      const FiberPeriod fp = ftFiberPeriod(p, r, 3u, 1u, uint32_t(f + 1), uint32_t(k));
      Cell& c = cells[size_t(f) * periods + k];
      c.z[0] = (fp.hairSpan - p.hairZeMu) / p.hairZeSigma;
      c.z[1] = fp.hairRoot - p.hairR0Mu;
      c.z[2] = fp.hairEnd - fp.hairRoot - p.hairReMu;
      c.z[3] = fp.hairAngle - p.hairPeMu;
      c.hair = fp.type == FT_FIBER_HAIR ? 1.0 : 0.0;
      c.atEnd = fp.hairAtEnd;
    }
  // Feature f of a cell and the draw it comes from (pairs of one draw are skipped).
  const char* names[10] = {"ze", "r0", "re", "pe", "ze²", "r0²", "re²", "pe²", "type", "at-end"};
  const int draw[10] = {0, 1, 2, 3, 0, 1, 2, 3, 4, 5};
  auto feature = [](const Cell& c, int f) {
    return f < 4 ? c.z[f] : f < 8 ? c.z[f - 4] * c.z[f - 4] : f == 8 ? c.hair : c.atEnd;
  };
  auto correlation = [&](auto pairOf, size_t count, int fa, int fb) {
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (size_t i = 0; i < count; ++i) {
      const auto [a, b] = pairOf(i);
      const double x = feature(*a, fa), y = feature(*b, fb);
      sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y;
    }
    const double n = double(count), cov = sab / n - sa / n * sb / n;
    return cov / std::sqrt((saa / n - sa / n * sa / n) * (sbb / n - sb / n * sb / n));
  };
  const size_t n = cells.size();
  const double limit = 5.0 / std::sqrt(double(periods * (fibers - 1)));
  for (int fa = 0; fa < 10; ++fa)
    for (int fb = 0; fb < 10; ++fb) {
      // Same cell, different draws.
      if (draw[fa] < draw[fb]) {
        const double rho = correlation([&](size_t i) { return std::pair{&cells[i], &cells[i]}; }, n, fa, fb);
        EXPECT_LT(std::abs(rho), 5.0 / std::sqrt(double(n))) << names[fa] << " vs " << names[fb] << " in one cell";
      }
      // The next period of the same fiber, and the same period of the next fiber: any two features.
      const double rhoPeriod = correlation(
          [&](size_t i) {
            const size_t f = i / (periods - 1), k = i % (periods - 1);
            return std::pair{&cells[f * periods + k], &cells[f * periods + k + 1]};
          },
          size_t(fibers) * (periods - 1), fa, fb);
      EXPECT_LT(std::abs(rhoPeriod), limit) << names[fa] << " vs the next period's " << names[fb];
      const double rhoFiber = correlation(
          [&](size_t i) { return std::pair{&cells[i], &cells[i + periods]}; }, size_t(fibers - 1) * periods, fa, fb);
      EXPECT_LT(std::abs(rhoFiber), limit) << names[fa] << " vs the next fiber's " << names[fb];
    }
  // The type draw still follows its probability (the features are live).
  double hairs = 0;
  for (const Cell& c : cells) hairs += c.hair;
  EXPECT_NEAR(hairs / double(n), 0.5, 5.0 * 0.5 / std::sqrt(double(n)));
}

// The frustum test keeps a segment unless ALL four Bézier points lie more than
// the bound radius behind one plane (lod.h). Built here plane by plane and
// point by point: three points far outside, the fourth just inside the margin
// band (kept) or just beyond it (culled) — so a margin dropped or changed for
// any single point shows (issue 14, deliverable 12).
TEST(Lod, CullingMarginHoldsForEachBezierPointAndPlane) {
  Camera cam;
  cam.eye = {0.0f, 0.0f, 5.0f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.zNear = 1.0f;
  cam.zFar = 9.0f;
  const ViewParams v = makeViewParams(cam, 1.0f, false, true);
  const float margin = 0.05f;
  const glm::vec3 inside(0.0f, 0.0f, 0.0f);  // depth 5, the frustum's middle
  int kept = 0, culled = 0;
  for (int plane = 0; plane < 6; ++plane) {
    const glm::vec3 n = glm::vec3(v.frustumPlanes[plane]);
    const float w = v.frustumPlanes[plane].w;
    // The point at signed distance `d` from the plane, moved from `inside` along its normal.
    auto at = [&](float d) { return inside + n * (d - (glm::dot(n, inside) + w)); };
    for (int k = 0; k < 4; ++k) {
      for (float near : {-0.5f * margin, -0.9f * margin, -1.1f * margin, -1.5f * margin}) {
        YarnSegment seg{};
        glm::vec4* b[4] = {&seg.b0, &seg.b1, &seg.b2, &seg.b3};
        for (int j = 0; j < 4; ++j) *b[j] = glm::vec4(at(j == k ? near : -3.0f * margin), 1.0f);
        const bool expectCulled = near < -margin;
        EXPECT_EQ(ftSegmentOutsideFrustum(v, seg, margin), expectCulled)
            << "plane " << plane << ", Bézier point " << k << " at " << near / margin << " margins";
        (expectCulled ? culled : kept) += 1;
      }
    }
  }
  EXPECT_EQ(kept, 48);
  EXPECT_EQ(culled, 48);
}

// Every fiber point stays within boundRadius of the yarn centre curve (the
// frustum test relies on it), for all presets and all fiber types.
TEST(FiberGeometry, FibersStayWithinTheBoundRadius) {
  const SceneData& s = defaultSetup();
  for (const YarnPreset& preset : builtinYarnPresets()) {
    std::vector<FiberCoord> table;
    const YarnParams p = paramsFor(preset.name.c_str(), &table);
    SegmentDecision d{1.0f, 0.0f, p.regularFibers, 8, 0, 0, 0, 0};
    double worst = 0.0;
    for (uint32_t seg = 0; seg < s.buffers.segments.size(); seg += 3) {
      const YarnSegment ys = loadSegmentCpu(s.buffers, s.frames, seg);
      const TwistRates r = ftTwistRates(p, s.buffers.curves[s.buffers.segments[seg].curve]);
      for (uint32_t ply = 0; ply < p.plyCount; ++ply)
        for (uint32_t slot = 1; slot <= p.regularFibers; ++slot)
          for (uint32_t v = 0; v <= 8; ++v) {
            FiberVertex fv = ftFiberVertex(p, r, ys, d, 0, seg, ply, slot, table[ftSlotFiber(p, slot)], v);
            const vec3 c = ftBezierPoint(ys, float(v) / 8.0f);
            worst = std::max(worst, double(glm::length(vec3(fv.position) - c)) + fv.position.w);
          }
    }
    EXPECT_LE(worst, p.boundRadius) << preset.name;
    EXPECT_GT(worst, 0.3 * p.boundRadius) << preset.name << ": the bound is far from tight";
  }
}

// Loop and hair periods occur with the probabilities YarnParams states
// (binomial, 5σ: fails by chance with probability < 1e-6).
TEST(FiberGeometry, PeriodTypeFrequenciesMatchTheirProbabilities) {
  const YarnParams p = paramsFor("cotton1");
  TwistRates r{p.plyTurnsPerLength, p.fiberTurnsPerLength, p.fiberTurnsPerLength * p.migrationS, 0u};
  const int n = 40000;
  int loops = 0, hairs = 0;
  for (int i = 0; i < n; ++i) {
    FiberCoord fc{0.9f, 0.0f};
    const float s = (float(i % 400) + 0.25f) / r.migration;  // period i%400 of fiber i/400
    FiberPeriod fp = ftFiberPeriod(p, r, 3u, 0u, uint(i / 400), ftPeriodPhase(p, r, s, fc.thetaTurns).index);
    loops += fp.type == FT_FIBER_LOOP;
    hairs += fp.type == FT_FIBER_HAIR;
  }
  auto check = [&](int count, double prob, const char* what) {
    const double mean = n * prob, sigma = std::sqrt(n * prob * (1.0 - prob));
    EXPECT_NEAR(count, mean, 5.0 * sigma) << what;
  };
  check(loops, p.loopProbability, "loops");
  check(hairs, p.hairProbability, "hairs");
}

// Eq. 4: λ is 1 and 0 on its outer branches and continuous where they meet
// the middle one.
TEST(Lod, LambdaFollowsEquation4AndIsContinuous) {
  const float fiber = 0.05f, ply = 1.5f;
  EXPECT_EQ(ftLodLambda(fiber, ply, 0.04f), 1.0f);
  EXPECT_EQ(ftLodLambda(fiber, ply, 2.0f), 0.0f);
  EXPECT_NEAR(ftLodLambda(fiber, ply, fiber * 1.0001f), 1.0f, 1e-3f);
  EXPECT_NEAR(ftLodLambda(fiber, ply, ply * 0.9999f), 0.0f, 1e-3f);
  float previous = 1.0f;
  for (float w = fiber; w <= ply; w *= 1.05f) {
    const float l = ftLodLambda(fiber, ply, w);
    EXPECT_LE(l, previous + 1e-7f);  // monotonic: a coarser threshold never adds detail
    previous = l;
  }
}

// Eq. 4's middle branch at interior points, against values worked out by
// hand from the printed formula λ = (ω_f/ω_L)·(ω_p − ω_L)/(ω_p − ω_f):
//   ω_f = 0.5, ω_p = 4.5, ω_L = 1:   0.5 · 3.5/4 = 0.4375
//   ω_f = 0.5, ω_p = 4.5, ω_L = 2.5: 0.2 · 2/4   = 0.1
//   ω_f = 1,   ω_p = 3,   ω_L = 2:   0.5 · 1/2   = 0.25
// (the endpoints alone cannot tell a wrong exponent or a swapped ratio).
TEST(Lod, LambdaInteriorValuesByHand) {
  EXPECT_NEAR(ftLodLambda(0.5f, 4.5f, 1.0f), 0.4375f, 1e-6f);
  EXPECT_NEAR(ftLodLambda(0.5f, 4.5f, 2.5f), 0.1f, 1e-6f);
  EXPECT_NEAR(ftLodLambda(1.0f, 3.0f, 2.0f), 0.25f, 1e-6f);
}

// A straight segment along x from the origin, 0.375 long, its Bézier points
// at binary fractions (the centre term of the subdivision bound is exactly 0).
YarnSegment straightSegment(float s0) {
  YarnSegment seg{};
  seg.b0 = vec4(0.0f, 0.0f, 0.0f, 1.0f);
  seg.b1 = vec4(0.125f, 0.0f, 0.0f, 1.0f);
  seg.b2 = vec4(0.25f, 0.0f, 0.0f, 1.0f);
  seg.b3 = vec4(0.375f, 0.0f, 0.0f, 1.0f);
  seg.s0 = s0;
  seg.s1 = s0 + 0.375f;
  return seg;
}

// Eq. 4's count: n = λ² n_max to the nearest whole fiber, so a view where
// λ² n_max < ½ draws no regular fiber (the core has grown to the ply), and
// none where λ = 0. Swept over distances that take λ from 1 to 0; λ is
// checked against eq. 4 by hand above, the rounding here.
TEST(Lod, RegularCountIsEquation4RoundedToNearest) {
  YarnParams p{};
  p.plyCount = 3;
  p.maxSubdivisions = 64;
  p.regularFibers = 20;
  p.fiberRadius = 0.002f;
  p.ellipseB = 0.02f;
  p.rhoMax = 1.0f;
  const YarnSegment seg = straightSegment(0.0f);
  int zeroWithLambda = 0, belowHalf = 0;
  for (float z = 0.5f; z < 400.0f; z *= 1.03f) {
    Camera cam;
    cam.eye = {0.1875f, 0.0f, z};
    cam.target = {0.1875f, 0.0f, 0.0f};
    const SegmentDecision d = ftDecideSegment(p, makeViewParams(cam, 1.0f, true, false, 0.25f), seg);
    const double n = double(d.lambda) * d.lambda * p.regularFibers;
    if (std::abs(n - std::floor(n) - 0.5) < 1e-4) continue;  // on a rounding boundary
    EXPECT_EQ(d.regularCount, uint32_t(std::floor(n + 0.5))) << "z " << z << " λ² n_max " << n;
    if (d.lambda > 0.0f && n < 0.5) {
      ++belowHalf;
      if (d.regularCount == 0u) ++zeroWithLambda;
    }
  }
  EXPECT_GT(belowHalf, 0);  // the sweep reaches λ > 0 with fewer than half a fiber
  EXPECT_EQ(zeroWithLambda, belowHalf);
}

// The subdivision bound of docs/pictures.md, evaluated here in double from
// its written form, on a straight and a bent segment seen from 5 units:
//   n = sqrt(|x''| · ppu / (8 ε)),
//   |x''| ≤ 6 max|b_i − 2b_{i+1} + b_{i+2}| + R_ply (ω_ply + Θ)² + R_fib (ω_ply + ω_fib + Θ)² + A_mig ω_mig²,
// ω = 2π · turns per length · Δs, Θ the control polygon's turning,
// R_fib = max(e_N, e_B)·ρ_max, A_mig = ½(ρ_max − ρ_min)·R_fib.
TEST(Lod, SubdivisionBoundAsDocumented) {
  YarnParams p{};
  p.plyCount = 2;
  p.maxSubdivisions = 64;
  p.plyRadius = 0.02f;
  p.ellipseN = 0.015f;
  p.ellipseB = 0.02f;
  p.rhoMin = 0.8f;
  p.rhoMax = 1.0f;
  p.plyTurnsPerLength = 2.0f;
  p.fiberTurnsPerLength = 3.0f;
  p.migrationS = 1.5f;
  Camera cam;
  cam.eye = {0.1f, 0.1f, 5.0f};
  cam.target = {0.1f, 0.1f, 0.0f};
  const ViewParams v = makeViewParams(cam, 1.0f, false, false, 0.25f);
  const double ppu = cam.pixelsPerUnitAtDepth1() / 5.0;
  auto expected = [&](double centre, double turning, double ds) {
    const double wPly = 2.0 * M_PI * 2.0 * ds, wFib = 2.0 * M_PI * 3.0 * ds, wMig = 1.5 * wFib;
    const double rFib = 0.02 * 1.0, aMig = 0.5 * (1.0 - 0.8) * rFib;
    const double accel = centre + 0.02 * (wPly + turning) * (wPly + turning) +
                         rFib * (wPly + wFib + turning) * (wPly + wFib + turning) + aMig * wMig * wMig;
    return std::sqrt(accel * ppu / (8.0 * 0.25));
  };
  const YarnSegment straight = straightSegment(1.0f);
  EXPECT_NEAR(ftSubdivisionEstimate(p, v, straight) / expected(0.0, 0.0, 0.375), 1.0, 1e-5);
  // Bent by 45° at b1 and at b2: |b0 − 2b1 + b2| = |b1 − 2b2 + b3| = 0.1, Θ = π/2.
  YarnSegment bent{};
  bent.b0 = vec4(1.0f, 0.5f, 0.0f, 1.0f);  // away from the origin: b1 − b0 ≠ b1 + b0
  bent.b1 = vec4(1.1f, 0.5f, 0.0f, 1.0f);
  bent.b2 = vec4(1.2f, 0.6f, 0.0f, 1.0f);
  bent.b3 = vec4(1.2f, 0.7f, 0.0f, 1.0f);
  bent.s0 = 0.0f;
  bent.s1 = 0.25f;
  EXPECT_NEAR(ftSubdivisionEstimate(p, v, bent) / expected(0.6, M_PI / 2.0, 0.25), 1.0, 1e-5);
  // Twice the distance: half the pixels per unit, 1/√2 the subdivisions.
  Camera far = cam;
  far.eye.z = 10.0f;
  EXPECT_NEAR(ftSubdivisionEstimate(p, makeViewParams(far, 1.0f, false, false, 0.25f), bent) /
                  ftSubdivisionEstimate(p, v, bent),
              1.0 / std::sqrt(2.0), 1e-5);
  // ε = 0: always the cap.
  EXPECT_EQ(ftSubdivisionEstimate(p, makeViewParams(cam, 1.0f, false, false, 0.0f), bent), 64.0f);

  // The core strip runs along the ply centre: the bound without the fiber
  // terms, |x''| ≤ |c''| + R_ply (ω_ply + Θ)².
  auto expectedCore = [&](double centre, double turning, double ds) {
    const double wPly = 2.0 * M_PI * 2.0 * ds;
    return std::sqrt((centre + 0.02 * (wPly + turning) * (wPly + turning)) * ppu / (8.0 * 0.25));
  };
  EXPECT_NEAR(ftCoreSubdivisionEstimate(p, v, straight) / expectedCore(0.0, 0.0, 0.375), 1.0, 1e-5);
  EXPECT_NEAR(ftCoreSubdivisionEstimate(p, v, bent) / expectedCore(0.6, M_PI / 2.0, 0.25), 1.0, 1e-5);
  EXPECT_EQ(ftCoreSubdivisionEstimate(p, makeViewParams(cam, 1.0f, false, false, 0.0f), bent), 64.0f);
  // The decision draws the core with ⌈its own bound⌉ lines, at least 1 and
  // never more than the fibers' subdivisions.
  p.fiberCount = 8;
  p.regularFibers = 4;
  for (const YarnSegment& seg : {straight, bent})
    for (float z : {2.0f, 5.0f, 40.0f}) {
      Camera c = cam;
      c.eye.z = z;
      const ViewParams w = makeViewParams(c, 1.0f, false, false, 0.25f);
      const SegmentDecision d = ftDecideSegment(p, w, seg);
      const double core = std::ceil(double(ftCoreSubdivisionEstimate(p, w, seg)));
      EXPECT_EQ(d.coreLines, uint32_t(std::clamp(core, 1.0, double(d.subdivisions)))) << z;
      EXPECT_GE(d.coreLines, 1u);
      EXPECT_LE(d.coreLines, d.subdivisions);
      EXPECT_EQ(d.vertexCount, p.plyCount * ((d.coreLines + 1u) + d.regularCount * (d.subdivisions + 1u)));
    }
}

// Culling is conservative: no fiber point of a culled segment is inside the
// view frustum.
TEST(Lod, CulledSegmentsHaveNoVisibleFiberPoint) {
  const SceneData& s = defaultSetup();
  std::vector<FiberCoord> table;
  const YarnParams p = paramsFor("rayon1", &table);
  int culledSegments = 0;
  for (LodDistance dist : {LodDistance::Near, LodDistance::Mid}) {
    const Camera cam = lodCamera(s.model, p, dist, 1.0f, 640, 480);
    const ViewParams v = makeViewParams(cam, 1.0f, true, true);
    for (uint32_t seg = 0; seg < s.buffers.segments.size(); ++seg) {
      const YarnSegment ys = loadSegmentCpu(s.buffers, s.frames, seg);
      if (!ftSegmentOutsideFrustum(v, ys, p.boundRadius)) continue;
      ++culledSegments;
      SegmentDecision d{1.0f, p.ellipseB, p.regularFibers, 8, 0, 0, 0, 0};
      const TwistRates r = ftTwistRates(p, s.buffers.curves[s.buffers.segments[seg].curve]);
      for (uint32_t ply = 0; ply < p.plyCount; ++ply)
        for (uint32_t slot = 0; slot <= p.regularFibers; ++slot)
          for (uint32_t k = 0; k <= 8; ++k) {
            const FiberCoord fc = slot ? table[ftSlotFiber(p, slot)] : FiberCoord{0, 0};
            const vec3 q = vec3(ftFiberVertex(p, r, ys, d, 0, seg, ply, slot, fc, k).position);
            bool inside = true;
            for (const vec4& pl : v.frustumPlanes) inside = inside && glm::dot(vec3(pl), q) + pl.w >= 0.0f;
            EXPECT_FALSE(inside) << "segment " << seg << " was culled but a fiber point is visible";
          }
    }
  }
  EXPECT_GT(culledSegments, 10) << "the test views cull too little to test anything";
}

// Fiber-table rows: sorted by R, inside the unit disk, θ in [0, 1).
TEST(FiberTable, SortedInsideTheDiskAndDeterministic) {
  for (const YarnPreset& preset : builtinYarnPresets()) {
    const std::vector<FiberCoord> a = makeFiberTable(preset, 1), b = makeFiberTable(preset, 1);
    ASSERT_EQ(a.size(), static_cast<size_t>(preset.fiberNum));
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].radius, b[i].radius);
      EXPECT_GE(a[i].radius, 0.0f);
      EXPECT_LE(a[i].radius, preset.rMax);
      EXPECT_GE(a[i].thetaTurns, 0.0f);
      EXPECT_LT(a[i].thetaTurns, 1.0f);
      if (i) {
        EXPECT_LE(a[i - 1].radius, a[i].radius);
      }
    }
  }
}

}  // namespace
}  // namespace ft
