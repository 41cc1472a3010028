// The shared knit solver (common/knit_solver.h) and the CPU reference: the
// analytic Jacobian against finite differences, the template at rest, the
// Gauss–Newton descent, eq. 4 by construction, yarn assembly and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "knit/knit_problem.h"
#include "knit/knit_solver.h"
#include "reference/fiber_reference.h"
#include "reference/knit_reference.h"
#include "scene/input_error.h"

namespace ft {
namespace {

KnitSetup stretched(int rows, int cols, Deformation d, KnitOptions o = {}) {
  const StitchMesh rest = makeStockinette(rows, cols);
  return buildKnitSetup(rest, deform(rest, d), o);
}

double totalEnergy(const KnitSetup& s, bool initial) {
  double e = 0;
  for (const auto& p : s.problems) {
    const glm::dvec4 t = initial ? p.theta0 : p.theta0;
    e += knit64::knitEnergy(p, t, s.options.wAngle, s.options.wLength);
  }
  return e;
}

// The finite-difference checks below: four tiles of a sheared 3×3 patch at a
// Θ off the interpolated one, and central differences with step h along Θ_k.
constexpr uint32_t kProbeTiles[] = {0u, 4u, 8u, 10u};
constexpr double kStep = 1e-6;
glm::dvec4 probeTheta(const knit64::KnitProblem& p) { return p.theta0 + glm::dvec4(0.05, -0.03, 0.01, 0.004); }
glm::dvec4 stepped(glm::dvec4 theta, int k, double h) {
  theta[k] += h;
  return theta;
}

// The Jacobian rows of knitNormalEquations are checked through g = Σ J r =
// ∇E / 2 against central differences of E (eq. 3); tolerance: the difference
// quotient's truncation error, O(h²) relative with h = 1e-6.
TEST(KnitSolver, GradientMatchesFiniteDifferences) {
  const KnitSetup s = stretched(3, 3, {Deformation::Shear, 25.0});
  const KnitOptions& o = s.options;
  for (uint32_t t : kProbeTiles) {
    const knit64::KnitProblem& p = s.problems[t];
    const glm::dvec4 theta = probeTheta(p);
    const auto ne = knit64::knitNormalEquations(p, theta, o.wAngle, o.wLength);
    for (int k = 0; k < 4; ++k) {
      const double fd = (knit64::knitEnergy(p, stepped(theta, k, kStep), o.wAngle, o.wLength) -
                         knit64::knitEnergy(p, stepped(theta, k, -kStep), o.wAngle, o.wLength)) /
                        (2 * kStep);
      EXPECT_NEAR(2 * ne.g[k], fd, 1e-6 * std::max(1.0, std::abs(fd))) << "tile " << t << " parameter " << k;
    }
  }
}

// The dense 4×4 A of the block normal equations, in Θ order.
glm::dmat4 denseNormalMatrix(const knit64::KnitNormalEquations& ne) {
  glm::dmat4 a(0.0);  // a[column][row]
  const double LL[3] = {ne.LL.x, ne.LL.y, ne.LL.z}, RR[3] = {ne.RR.x, ne.RR.y, ne.RR.z};
  auto set = [&](int i, int j, double v) { a[i][j] = a[j][i] = v; };
  set(0, 0, LL[0]), set(0, 2, LL[1]), set(2, 2, LL[2]);  // θ_L, l_L
  set(1, 1, RR[0]), set(1, 3, RR[1]), set(3, 3, RR[2]);  // θ_R, l_R
  set(0, 1, ne.LR.x), set(0, 3, ne.LR.y), set(2, 1, ne.LR.z), set(2, 3, ne.LR.w);
  return a;
}

// A = Σ J Jᵀ is assembled from per-knot blocks; checked entry by entry against
// JᵀJ with J from central differences of every residual, through knitMeasure
// (lengths and cosines: a path that shares no Jacobian code). Tolerance: the
// O(h²) truncation error of the differences, h = 1e-6, relative to |A|.
TEST(KnitSolver, NormalMatrixIsTheJacobianGramian) {
  const KnitSetup s = stretched(3, 3, {Deformation::Shear, 25.0});
  const KnitOptions& o = s.options;
  for (uint32_t t : kProbeTiles) {
    const knit64::KnitProblem& p = s.problems[t];
    const glm::dvec4 theta = probeTheta(p);
    const glm::dmat4 A = denseNormalMatrix(knit64::knitNormalEquations(p, theta, o.wAngle, o.wLength));
    double J[FT_KNIT_LENGTH_RESIDUALS + FT_KNIT_ANGLE_RESIDUALS][4];
    for (int k = 0; k < 4; ++k) {
      const auto ma = knit64::knitMeasure(p, stepped(theta, k, kStep));
      const auto mb = knit64::knitMeasure(p, stepped(theta, k, -kStep));
      for (int i = 0; i < FT_KNIT_LENGTH_RESIDUALS; ++i)
        J[i][k] = std::sqrt(o.wLength) * (ma.segment[i] - mb.segment[i]) / (2 * kStep);
      for (int i = 0; i < FT_KNIT_ANGLE_RESIDUALS; ++i)
        J[FT_KNIT_LENGTH_RESIDUALS + i][k] = std::sqrt(o.wAngle) * (ma.cosine[i] - mb.cosine[i]) / (2 * kStep);
    }
    double scale = 0;
    for (int i = 0; i < 4; ++i) scale = std::max(scale, std::abs(A[i][i]));
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        double jtj = 0;
        for (const auto& row : J) jtj += row[i] * row[j];
        EXPECT_NEAR(A[j][i], jtj, 1e-6 * scale) << "tile " << t << " A(" << i << "," << j << ")";
      }
  }
}

// The block L D Lᵀ solve against Gaussian elimination with partial pivoting on
// the dense A; tolerance: 1e-9 relative (A's condition number here is < 1e5).
TEST(KnitSolver, BlockSolveMatchesDenseElimination) {
  const KnitSetup s = stretched(3, 3, {Deformation::StretchCourse, 1.4});
  const KnitOptions& o = s.options;
  for (uint32_t t : {1u, 4u, 7u}) {
    const knit64::KnitProblem& p = s.problems[t];
    const auto ne = knit64::knitNormalEquations(p, p.theta0 + glm::dvec4(0.02, 0.01, -0.003, 0.002), o.wAngle,
                                                o.wLength);
    const glm::dvec4 rhs(0.3, -1.2, 0.7, 2.0);
    const knit64::KnitSolve4 x = knit64::knitSolveNormalEquations(ne, rhs);
    ASSERT_TRUE(x.ok) << t;
    double m[4][5];
    const glm::dmat4 A = denseNormalMatrix(ne);
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) m[i][j] = A[j][i];
      m[i][4] = rhs[i];
    }
    for (int c = 0; c < 4; ++c) {
      int piv = c;
      for (int r = c + 1; r < 4; ++r)
        if (std::abs(m[r][c]) > std::abs(m[piv][c])) piv = r;
      for (int j = 0; j < 5; ++j) std::swap(m[c][j], m[piv][j]);
      for (int r = c + 1; r < 4; ++r) {
        const double f = m[r][c] / m[c][c];
        for (int j = c; j < 5; ++j) m[r][j] -= f * m[c][j];
      }
    }
    double ref[4];
    for (int i = 3; i >= 0; --i) {
      double v = m[i][4];
      for (int j = i + 1; j < 4; ++j) v -= m[i][j] * ref[j];
      ref[i] = v / m[i][i];
    }
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(x.x[i], ref[i], 1e-9 * std::max(1.0, std::abs(ref[i]))) << t << " " << i;
  }
  // A parameter that no residual sees: the system is singular and no step is taken.
  knit64::KnitNormalEquations singular{};
  singular.LL = glm::dvec3(1, 0, 0);  // l_L unseen
  singular.RR = glm::dvec3(2, 0.1, 1);
  EXPECT_FALSE(knit64::knitSolveNormalEquations(singular, glm::dvec4(1)).ok);
}

TEST(KnitSolver, RestTemplateHasZeroEnergyAndStays) {
  const StitchMesh rest = makeStockinette(4, 5);
  const KnitSetup s = buildKnitSetup(rest, rest, {});
  EXPECT_LT(totalEnergy(s, true), 1e-20);
  const KnitSolution sol = solveKnitCpu(s);
  const std::vector<glm::dvec3> init = liftKnitPoints(s, initialKnitPoints(s));
  for (size_t i = 0; i < init.size(); ++i) ASSERT_LT(glm::length(sol.worldPoints[i] - init[i]), 1e-12) << i;
}

TEST(KnitSolver, EnergyDecreasesEveryIteration) {
  for (Deformation d : {Deformation{Deformation::StretchCourse, 1.4}, Deformation{Deformation::StretchWale, 1.6},
                        Deformation{Deformation::Shear, 30.0}}) {
    const KnitSetup s = stretched(6, 6, d);
    const KnitSolution sol = solveKnitCpu(s);
    double before = 0, after = 0;
    for (uint32_t t = 0; t < s.tileCount(); ++t) {
      for (int k = 0; k < 3; ++k) EXPECT_LE(sol.energy[t][k + 1], sol.energy[t][k] * (1 + 1e-12)) << t << " " << k;
      before += sol.energy[t][0];
      after += sol.energy[t][3];
    }
    EXPECT_LT(after, 0.9 * before) << deformationKindName(d.kind);
  }
}

TEST(KnitSolver, ConstraintsHoldByConstruction) {
  const KnitSetup s = stretched(4, 4, {Deformation::Shear, 30.0});
  const KnitSolution sol = solveKnitCpu(s);
  for (uint32_t t = 0; t < s.tileCount(); ++t) {
    const auto c = knitConstraintResiduals(s, t, &sol.worldPoints[size_t(t) * FT_KNIT_TILE_POINTS]);
    EXPECT_LT(c.midpointContact, 1e-12);
    EXPECT_LT(c.midpointControl, 1e-12);
    EXPECT_LT(c.controlDistance, 1e-12);
    EXPECT_LT(c.perpendicularity, 1e-12);
  }
}

// Under a course stretch the tile is mirror-symmetric about its centre line,
// so the solved tilts mirror each other: θ_R = π − θ_L, l_R = l_L.
TEST(KnitSolver, CourseStretchKeepsTheTileSymmetric) {
  const KnitSetup s = stretched(3, 3, {Deformation::StretchCourse, 1.4});
  const KnitSolution sol = solveKnitCpu(s);
  const glm::dvec4 t = sol.theta[4];  // the middle stitch
  EXPECT_NEAR(t.x + t.y, M_PI, 1e-9);
  EXPECT_NEAR(t.z, t.w, 1e-9);
}

// The harness's lengths case (validation/knit_cases.cpp) can fail: with the
// length energy of eq. 6 switched off, the optimized segments drift further
// from their rest lengths than plain interpolation leaves them.
double meanLengthDeviation(const KnitSetup& s, const KnitSolution* sol) {
  double sum = 0;
  int n = 0;
  for (uint32_t t = 0; t < s.stitchCount; ++t) {
    const auto& p = s.problems[t];
    const auto m = knit64::knitMeasure(p, sol ? sol->theta[t] : p.theta0);
    for (int i = 0; i < FT_KNIT_LENGTH_RESIDUALS; ++i, ++n) sum += std::abs(m.segment[i] / p.restLength[i] - 1);
  }
  return sum / n;
}

TEST(KnitSolver, LengthEnergyIsWhatKeepsSegmentLengths) {
  KnitOptions paper, noLength;
  noLength.wLength = 0;
  const KnitSetup a = stretched(6, 6, {Deformation::StretchCourse, 1.4}, paper);
  const KnitSetup b = stretched(6, 6, {Deformation::StretchCourse, 1.4}, noLength);
  const KnitSolution sa = solveKnitCpu(a), sb = solveKnitCpu(b);
  const double interpolated = meanLengthDeviation(a, nullptr);
  EXPECT_LT(meanLengthDeviation(a, &sa), interpolated);
  EXPECT_GT(meanLengthDeviation(b, &sb), interpolated);
}

TEST(KnitSolver, FloatInstanceTracksDouble) {
  const KnitSetup s = stretched(5, 5, {Deformation::Shear, 20.0});
  const KnitSolution d = solveKnitCpu(s), f = solveKnitCpuFloat(s);
  double worst = 0;
  for (size_t i = 0; i < d.worldPoints.size(); ++i)
    worst = std::max(worst, glm::length(d.worldPoints[i] - f.worldPoints[i]));
  // A thousandth of the yarn radius (0.05): see the knit cases in validation/.
  EXPECT_LT(worst, 5e-5);
}

TEST(KnitYarns, RowsAreContinuousAndCoverEveryTilePointOnce) {
  const int rows = 4, cols = 5;
  const KnitSetup s = stretched(rows, cols, {Deformation::StretchCourse, 1.2});
  ASSERT_EQ(s.stitchCount, uint32_t(rows * cols));
  ASSERT_EQ(s.tileCount(), uint32_t(rows * cols + cols));  // one ghost above each top stitch
  // rows yarns of 14 points per stitch, plus one cast-on yarn of 7 per stitch.
  ASSERT_EQ(s.yarns.size(), size_t(rows + 1));
  std::vector<int> uses(size_t(s.tileCount()) * FT_KNIT_TILE_POINTS, 0);
  for (int r = 0; r < rows; ++r) EXPECT_EQ(s.yarns[r].points.size(), size_t(14 * cols));
  EXPECT_EQ(s.yarns[rows].points.size(), size_t(7 * cols));
  for (const KnitYarn& y : s.yarns)
    for (uint32_t p : y.points) ++uses[p];
  for (uint32_t t = 0; t < s.stitchCount; ++t)
    for (int i = 0; i < 14; ++i) EXPECT_EQ(uses[t * 14 + i], 1) << "tile " << t << " point " << i;
  // Consecutive yarn points are never far apart: no jumps between stitches.
  const KnitSolution sol = solveKnitCpu(s);
  for (const KnitYarn& y : s.yarns)
    for (size_t i = 0; i + 1 < y.points.size(); ++i)
      EXPECT_LT(glm::length(sol.worldPoints[y.points[i + 1]] - sol.worldPoints[y.points[i]]), 0.4) << i;
  const YarnModel m = knitYarnModel(s, sol.worldPoints, true);
  EXPECT_EQ(m.curves[0].points.size(), size_t(14 * cols - 1) * FT_KNIT_UPSAMPLE + 1);
}

// The knit up-sampling (§5.2) must be the curve the fiber side draws through
// the same points: the BCC of `knit` (no up-sampling) loaded as Catmull-Rom
// segments (common/yarn_curve.h, ends reflected) evaluated at t = k/U gives
// the up-sampled vertices; open yarns start and end at their end points; and
// knitCatmullRom itself interpolates p1, p2 with tangents (p2 - p0)/2,
// (p3 - p1)/2 (checked here by finite differences). Issue 14, deliverable 12.
TEST(KnitYarns, UpsamplingIsTheFiberSidesCatmullRomThroughTheEndPoints) {
  const glm::dvec3 p0(0.1, 0.3, -0.2), p1(1.0, 0.0, 0.4), p2(1.7, 0.9, 0.1), p3(2.0, 2.1, -0.5);
  EXPECT_LT(glm::length(knit64::knitCatmullRom(p0, p1, p2, p3, 0.0) - p1), 1e-15);
  EXPECT_LT(glm::length(knit64::knitCatmullRom(p0, p1, p2, p3, 1.0) - p2), 1e-14);
  const double h = 1e-6;  // central difference: O(h²) truncation, 1e-9 relative
  const glm::dvec3 d0 = (knit64::knitCatmullRom(p0, p1, p2, p3, h) - knit64::knitCatmullRom(p0, p1, p2, p3, -h)) / (2 * h);
  const glm::dvec3 d1 = (knit64::knitCatmullRom(p0, p1, p2, p3, 1 + h) - knit64::knitCatmullRom(p0, p1, p2, p3, 1 - h)) / (2 * h);
  EXPECT_LT(glm::length(d0 - 0.5 * (p2 - p0)), 1e-8);
  EXPECT_LT(glm::length(d1 - 0.5 * (p3 - p1)), 1e-8);

  for (const KnitSetup& s : {stretched(3, 3, {Deformation::Shear, 20.0}),
                             buildKnitSetup(makeLacePatch(4, 6), makeLacePatch(4, 6), {})}) {
    const KnitSolution sol = solveKnitCpu(s);
    const YarnModel coarse = knitYarnModel(s, sol.worldPoints, false);
    const YarnModel fine = knitYarnModel(s, sol.worldPoints, true);
    const YarnBuffers y = buildYarnBuffers(coarse);
    const std::vector<FrameNormal> frames = computeKnotFramesCpu(y);
    int closed = 0, open = 0;
    for (size_t ci = 0; ci < coarse.curves.size(); ++ci) {
      const YarnCurve &cc = coarse.curves[ci], &fc = fine.curves[ci];
      const size_t n = cc.points.size(), segments = cc.closed ? n : n - 1;
      ASSERT_EQ(fc.points.size(), segments * FT_KNIT_UPSAMPLE + (cc.closed ? 0 : 1)) << s.name << " yarn " << ci;
      (cc.closed ? closed : open) += 1;
      if (!cc.closed) {  // the solver's own end points (float), not the coarse curve's
        EXPECT_EQ(fc.points.front(), glm::vec3(sol.worldPoints[s.yarns[ci].points.front()]))
            << s.name << " yarn " << ci << " start";
        EXPECT_EQ(fc.points.back(), glm::vec3(sol.worldPoints[s.yarns[ci].points.back()]))
            << s.name << " yarn " << ci << " end";
      }
      for (size_t i = 0; i < segments; ++i) {
        const YarnSegment seg = loadSegmentCpu(y, frames, y.curves[ci].firstSegment + uint32_t(i));
        for (int k = 0; k < FT_KNIT_UPSAMPLE; ++k) {
          const glm::vec3 q = ftBezierPoint(seg, float(k) / FT_KNIT_UPSAMPLE);
          const glm::vec3 v = fc.points[i * FT_KNIT_UPSAMPLE + k];
          // float32 Bézier evaluation of points a few units from the origin: 1e-5.
          ASSERT_LT(glm::length(v - q), 1e-5f * (1.0f + glm::length(q)))
              << s.name << " yarn " << ci << " segment " << i << " vertex " << k;
        }
      }
    }
    EXPECT_GT(open, 0) << s.name;
  }
}

// The solver at its largest iteration count (FT_KNIT_MAX_ITERATIONS, the
// most --iterations accepts) runs every iteration: k + 1 iterations are
// exactly one more from where k stopped, the energy after the last is the
// energy at the returned Θ, and the last iteration still moves some tiles
// (so a count capped one short would show). Issue 14, deliverable 12.
TEST(KnitSolver, MaximumIterationCountRunsEveryIteration) {
  const KnitSetup s = stretched(4, 4, {Deformation::Shear, 30.0});
  const double wA = s.options.wAngle, wL = s.options.wLength;
  const uint32_t maxIt = FT_KNIT_MAX_ITERATIONS;
  int movedInLast = 0;
  for (uint32_t t = 0; t < s.tileCount(); ++t) {
    const knit64::KnitProblem& pr = s.problems[t];
    for (uint32_t k = 0; k < maxIt; ++k) {
      const knit64::KnitTileResult a = knit64::knitSolveTile(pr, wA, wL, k + 1);
      const knit64::KnitTileResult b = knit64::knitSolveTile(pr, wA, wL, k);
      knit64::KnitProblem from = pr;
      from.theta0 = b.theta;
      const knit64::KnitTileResult c = knit64::knitSolveTile(from, wA, wL, 1);
      // Same arithmetic on the same Θ: equal to a few ulps.
      ASSERT_LT(glm::length(a.theta - c.theta), 1e-12 * (1.0 + glm::length(a.theta))) << "tile " << t << " k " << k;
      EXPECT_NEAR(a.energy[k + 1], c.energy[1], 1e-12 * (1.0 + c.energy[1])) << "tile " << t << " k " << k;
      EXPECT_NEAR(a.energy[k + 1], knit64::knitEnergy(pr, a.theta, wA, wL), 1e-12 * (1.0 + a.energy[k + 1]))
          << "tile " << t << ": energy after the last iteration is not the returned Θ's";
      if (k + 1 == maxIt && glm::length(a.theta - b.theta) > 1e-9 * (1.0 + glm::length(b.theta))) ++movedInLast;
    }
  }
  EXPECT_GT(movedInLast, 0) << "no tile moves in iteration " << maxIt << ": the test could not see a capped count";
}

// Every stitch type: pentagons split into two tiles, the yarn-over triangle on
// a half-width quad; yarns stay continuous and every point is used once.
TEST(KnitYarns, LacePatchWithEveryStitchTypeAssemblesContinuousYarns) {
  const StitchMesh rest = makeLacePatch(8, 10);
  int counts[5] = {0, 0, 0, 0, 0};
  for (const StitchFace& f : rest.faces) ++counts[int(f.type)];
  ASSERT_GT(counts[int(StitchType::Decrease)], 0);
  ASSERT_GT(counts[int(StitchType::Increase)], 0);
  ASSERT_GT(counts[int(StitchType::YarnOver)], 0);
  const KnitSetup s = buildKnitSetup(rest, deform(rest, {Deformation::StretchCourse, 1.3}), {});
  const KnitSolution sol = solveKnitCpu(s);
  std::vector<int> uses(size_t(s.tileCount()) * FT_KNIT_TILE_POINTS, 0);
  for (const KnitYarn& y : s.yarns)
    for (uint32_t p : y.points) ++uses[p];
  for (uint32_t t = 0; t < s.stitchCount; ++t) {
    for (int i : {0, 1, 2, 3, 11, 12, 13}) EXPECT_EQ(uses[t * 14 + i], 1) << "tile " << t << " red point " << i;
    for (int i = 4; i <= 10; ++i) EXPECT_LE(uses[t * 14 + i], 1) << "tile " << t << " green point " << i;
  }
  double longest = 0;
  for (const KnitYarn& y : s.yarns)
    for (size_t i = 0; i + 1 < y.points.size(); ++i)
      longest = std::max(longest, glm::length(sol.worldPoints[y.points[i + 1]] - sol.worldPoints[y.points[i]]));
  // No jumps across the patch: within 1.25 stretched stitch widths (0.5 × 1.3 × 1.25).
  EXPECT_LT(longest, 0.82);
  for (uint32_t t = 0; t < s.tileCount(); ++t) {
    for (int k = 0; k < 3; ++k) EXPECT_LE(sol.energy[t][k + 1], sol.energy[t][k] * (1 + 1e-12)) << t;
    for (int i = 0; i < 14; ++i) ASSERT_TRUE(std::isfinite(sol.worldPoints[t * 14 + i].x)) << t;
  }
}

// A sleeve: stockinette rolled into a tube (courses round the circumference,
// outward normals). Rows close on themselves: the row yarns are closed curves,
// and the solve stays finite and descending on curved faces.
StitchMesh makeTube(int rows, int cols) {
  StitchMesh m;
  m.name = "tube";
  const double radius = cols * 0.5 / (2 * M_PI);
  for (int r = 0; r <= rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double a = 2 * M_PI * c / cols;
      m.vertices.emplace_back(radius * std::cos(a), r * 0.45, -radius * std::sin(a));
    }
  for (uint32_t r = 0; r < uint32_t(rows); ++r)
    for (uint32_t c = 0; c < uint32_t(cols); ++c) {
      const uint32_t c1 = (c + 1) % cols, B = r * cols, T = B + cols;
      m.faces.push_back({{B + c, B + c1, T + c1, T + c, kNoVertex}, 4, StitchType::Knit, 0});
    }
  return m;
}

TEST(KnitYarns, TubeRowsAreClosedYarns) {
  const StitchMesh rest = makeTube(4, 24);
  validateStitchMesh(rest);
  const KnitSetup s = buildKnitSetup(rest, rest, {});
  ASSERT_EQ(s.yarns.size(), size_t(5));  // four rows and the cast-on, all round the tube
  for (const KnitYarn& y : s.yarns) EXPECT_TRUE(y.closed);
  const KnitSolution sol = solveKnitCpu(s);
  for (uint32_t t = 0; t < s.tileCount(); ++t) EXPECT_LT(sol.energy[t][3], 1e-6) << t;  // rest: nothing to do
  // Stretched along the circumference (radius × 1.3).
  StitchMesh wide = rest;
  for (glm::dvec3& v : wide.vertices) v.x *= 1.3, v.z *= 1.3;
  const KnitSetup w = buildKnitSetup(rest, wide, {});
  const KnitSolution ws = solveKnitCpu(w);
  double longest = 0;
  for (const KnitYarn& y : w.yarns)
    for (size_t i = 0; i < y.points.size(); ++i)
      longest = std::max(longest, glm::length(ws.worldPoints[y.points[(i + 1) % y.points.size()]] -
                                              ws.worldPoints[y.points[i]]));
  EXPECT_LT(longest, 0.5 * 1.3);  // no jump, including the seam where the yarn closes
  for (uint32_t t = 0; t < w.tileCount(); ++t)
    for (int k = 0; k < 3; ++k) EXPECT_LE(ws.energy[t][k + 1], ws.energy[t][k] * (1 + 1e-12)) << t;
}

// Animation keeps the rest state's length coordinates (the fibers' material
// coordinate), so the yarn models of every frame must line up point for point.
TEST(KnitYarns, FramesShareTheRestStateYarnLayout) {
  const StitchMesh rest = makeLacePatch(6, 8);
  const KnitSetup r = buildKnitSetup(rest, rest, {});
  const KnitSetup d = buildKnitSetup(rest, deform(rest, {Deformation::StretchWale, 1.5}), {});
  YarnBuffers restBuffers = buildYarnBuffers(knitYarnModel(r, liftKnitPoints(r, initialKnitPoints(r)), true));
  YarnBuffers frame = buildYarnBuffers(knitYarnModel(d, solveKnitCpu(d).worldPoints, true));
  const glm::vec4 p0 = frame.points[100].positionLength;
  adoptLengthCoordinates(frame, restBuffers);
  EXPECT_EQ(frame.points[100].positionLength.w, restBuffers.points[100].positionLength.w);
  EXPECT_EQ(glm::vec3(frame.points[100].positionLength), glm::vec3(p0));
  EXPECT_GT(p0.w, frame.points[100].positionLength.w);  // the stretched yarn is longer than its material
  YarnBuffers other = buildYarnBuffers(knitYarnModel(buildKnitSetup(makeStockinette(6, 8), makeStockinette(6, 8), {}),
                                                     solveKnitCpu(d).worldPoints, false));
  EXPECT_THROW(adoptLengthCoordinates(other, restBuffers), std::invalid_argument);
}

TEST(KnitSetupErrors, RejectsBadOptions) {
  KnitOptions o;
  o.beta = 1.5;
  const StitchMesh rest = makeStockinette(2, 2);
  EXPECT_THROW(buildKnitSetup(rest, rest, o), InputError);
  o = {};
  o.yarnRadius = std::nan("");
  EXPECT_THROW(buildKnitSetup(rest, rest, o), InputError);
}

TEST(KnitSetupErrors, DegenerateAndFlippedFacesAreErrors) {
  const StitchMesh rest = makeStockinette(3, 3);
  StitchMesh collapsed = rest;
  for (uint32_t v : {5u, 6u}) collapsed.vertices[v] = collapsed.vertices[1];  // face 1 to zero area
  EXPECT_THROW(buildKnitSetup(rest, collapsed, {}), InputError);
  StitchMesh flipped = rest;
  std::swap(flipped.vertices[5].x, flipped.vertices[6].x);
  flipped.vertices[5].x += 0.0;
  EXPECT_THROW(buildKnitSetup(rest, flipped, {}), InputError);
  StitchMesh nan = rest;
  nan.vertices[4].y = std::nan("");
  EXPECT_THROW(buildKnitSetup(rest, nan, {}), InputError);
}

}  // namespace
}  // namespace ft
