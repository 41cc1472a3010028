// Independent oracles for the knot-based yarn optimization
// (001_dce8d4d1f783b802.txt, §3.2 eq. 1–6): the CPU reference's output points,
// measured with formulas written here. Nothing from common/knit_solver.h is
// called: the knot points are rebuilt from Θ by eq. 1–2, the constraints of
// eq. 4 are checked on the world points, and the eq. 3 energy is recomputed
// from the output points with eq. 5–6 (docs/fiber-oracles.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "knit/knit_problem.h"
#include "reference/knit_reference.h"

namespace ft {
namespace {

constexpr double kWAngle = 1.0, kWLength = 100.0;  // §6 of the paper: w_angle = 1, w_length = 100

// The tile's control points as the knot model names them (knit_stitch.h's
// figure): for each knot point, the knot (0 = L, 1 = R) and its signs along d
// (contact c0 +1 / c1 −1), along b (p0 +1 / p1 −1) and along the face normal.
struct KnotPoint {
  int index, knot;
  double sd, sb, sn;
};
constexpr KnotPoint kKnotPoints[] = {
    {1, 0, -1, 0, -1}, {2, 0, 0, 1, 0},  {3, 0, 1, 0, 1},   {4, 0, -1, 0, 1},   {5, 0, 0, -1, 0},  {6, 0, 1, 0, -1},
    {8, 1, 1, 0, -1},  {9, 1, 0, 1, 0},  {10, 1, -1, 0, 1}, {11, 1, 1, 0, 1},   {12, 1, 0, -1, 0}, {13, 1, -1, 0, -1},
};
// Per knot: tile indices of c0+, c0−, c1+, c1−, p0, p1.
constexpr int kKnots[2][6] = {{3, 6, 4, 1, 2, 5}, {11, 8, 10, 13, 9, 12}};
// The three yarn pieces through a tile, halo points 14..20 included (knit_stitch.h).
const std::vector<std::vector<int>> kChains = {{14, 0, 1, 2, 3, 15}, {16, 4, 5, 6, 7, 8, 9, 10, 17}, {18, 11, 12, 13, 19, 20}};

// The 21 points of tile t in its face frame: 0..13 from `framePoints`, the
// halo (fixed) from the problem.
std::vector<glm::dvec3> tilePoints(const KnitSetup& s, const std::vector<glm::dvec3>& framePoints, uint32_t t) {
  std::vector<glm::dvec3> p(21);
  for (int i = 0; i < 14; ++i) p[i] = framePoints[t * 14 + i];
  for (int h = 14; h < 21; ++h) {
    const auto& pr = s.problems[t];
    p[h] = glm::dvec3(pr.fixedXY[h - 12].x, pr.fixedXY[h - 12].y, pr.fixedH[h - 12]);
  }
  return p;
}

// Eq. 5 and 6 measures of a tile's chains: segment lengths and the cosines at interior points.
struct Measures {
  std::vector<double> length, cosine;
};
Measures measure(const std::vector<glm::dvec3>& p) {
  Measures m;
  for (const auto& chain : kChains) {
    for (size_t k = 0; k + 1 < chain.size(); ++k) m.length.push_back(glm::length(p[chain[k + 1]] - p[chain[k]]));
    for (size_t k = 0; k + 2 < chain.size(); ++k) {
      const glm::dvec3 e = p[chain[k + 1]] - p[chain[k]], f = p[chain[k + 2]] - p[chain[k + 1]];
      m.cosine.push_back(glm::dot(e, f) / (glm::length(e) * glm::length(f)));
    }
  }
  return m;
}

// Eq. 3 with eq. 5–6: w_angle Σ (cos − cos₀)² + w_length Σ (|e| − |e₀|)².
double energy(const Measures& m, const Measures& rest, double wAngle, double wLength) {
  double angle = 0.0, length = 0.0;
  for (size_t i = 0; i < m.cosine.size(); ++i) angle += (m.cosine[i] - rest.cosine[i]) * (m.cosine[i] - rest.cosine[i]);
  for (size_t i = 0; i < m.length.size(); ++i) length += (m.length[i] - rest.length[i]) * (m.length[i] - rest.length[i]);
  return wAngle * angle + wLength * length;
}

// Eq. 1–2: the knot points of tile t for parameters Θ = (θ_L, θ_R, l_L, l_R), in the face frame.
std::vector<glm::dvec3> pointsFromTheta(const KnitSetup& s, const std::vector<glm::dvec3>& framePoints, uint32_t t,
                                        glm::dvec4 theta) {
  std::vector<glm::dvec3> p = tilePoints(s, framePoints, t);
  const auto& pr = s.problems[t];
  for (const KnotPoint& k : kKnotPoints) {
    const double angle = theta[k.knot], half = theta[2 + k.knot];
    const glm::dvec2 d(std::cos(angle), std::sin(angle));
    const glm::dvec2 b(d.y, -d.x);  // b = d × n, n = +z of the face frame
    const glm::dvec2 xy = glm::dvec2(pr.knot[k.knot]) + k.sd * half * d + k.sb * pr.radius * b;
    p[k.index] = glm::dvec3(xy, k.sn * pr.radius * pr.side);
  }
  return p;
}

struct Solved {
  KnitSetup rest, deformed;
  KnitSolution restSolution, solution;
};
Solved solve(Deformation d, const StitchMesh& restMesh, double wLength = kWLength) {
  KnitOptions o;
  o.wAngle = kWAngle;
  o.wLength = wLength;
  Solved s{buildKnitSetup(restMesh, restMesh, o), buildKnitSetup(restMesh, deform(restMesh, d), o), {}, {}};
  s.restSolution = solveKnitCpu(s.rest);
  s.solution = solveKnitCpu(s.deformed);
  return s;
}

// The rest template: knot segments of length √(l0² + 2) r (c and p points a
// half-length l0 along d, r along b and r along the normal apart), contacts
// 2 l0 r apart, knots 2κ stitch widths apart, zero energy.
TEST(OracleKnit, RestTemplateSegmentLengths) {
  const StitchMesh mesh = makeStockinette(4, 5);
  const Solved s = solve({Deformation::None, 0.0}, mesh);
  const KnitOptions& o = s.rest.options;
  const double r = o.yarnRadius, l0 = o.tile.halfLength * r;
  const double knotSegment = std::sqrt(l0 * l0 + 2.0 * r * r);
  double worstSegment = 0.0, worstContact = 0.0, worstSpacing = 0.0, worstEnergy = 0.0;
  for (uint32_t t = 0; t < s.rest.stitchCount; ++t) {
    const glm::dvec3* w = &s.restSolution.worldPoints[t * 14];
    for (const auto& [a, b] : {std::pair{1, 2}, {2, 3}, {4, 5}, {5, 6}, {8, 9}, {9, 10}, {11, 12}, {12, 13}})
      worstSegment = std::max(worstSegment, std::abs(glm::length(w[b] - w[a]) - knotSegment) / r);
    glm::dvec3 centre[2];
    for (int k = 0; k < 2; ++k) {
      const int* q = kKnots[k];
      const glm::dvec3 c0 = 0.5 * (w[q[0]] + w[q[1]]), c1 = 0.5 * (w[q[2]] + w[q[3]]);
      worstContact = std::max(worstContact, std::abs(glm::length(c0 - c1) - 2.0 * l0) / r);
      centre[k] = 0.5 * (w[q[4]] + w[q[5]]);
    }
    worstSpacing = std::max(worstSpacing, std::abs(glm::length(centre[1] - centre[0]) -
                                                   2.0 * o.tile.knotOffset * kDefaultStitchWidth) / r);
    const Measures m = measure(tilePoints(s.rest, s.restSolution.framePoints, t));
    worstEnergy = std::max(worstEnergy, energy(m, m, kWAngle, kWLength));
    for (int it = 0; it <= o.iterations; ++it) worstEnergy = std::max(worstEnergy, s.restSolution.energy[t][it]);
  }
  std::printf("rest template: knot segments vs sqrt(l0^2 + 2) r: %.2e r, contacts 2 l0: %.2e r, knot spacing "
              "2 kappa w: %.2e r, energy %.2e\n",
              worstSegment, worstContact, worstSpacing, worstEnergy);
  EXPECT_LT(worstSegment, 1e-9);
  EXPECT_LT(worstContact, 1e-9);
  EXPECT_LT(worstSpacing, 1e-9);
  EXPECT_LT(worstEnergy, 1e-20);
}

// Eq. 4 on the optimized world points: contact and control midpoints at the
// knot, |p0 − p1| = 2r, d ⟂ b, p in the face plane, c± offset by ±r along the normal.
void expectEquation4(const Solved& s, const char* what) {
  const double r = s.deformed.options.yarnRadius;
  double midpoint = 0.0, control = 0.0, perpendicular = 0.0, plane = 0.0, normal = 0.0;
  for (uint32_t t = 0; t < s.deformed.stitchCount; ++t) {
    const glm::dvec3* w = &s.solution.worldPoints[t * 14];
    const glm::dvec3 n = glm::normalize(s.deformed.frames[t].n);
    for (int k = 0; k < 2; ++k) {
      const int* q = kKnots[k];
      const glm::dvec3 x = 0.5 * (w[q[4]] + w[q[5]]);  // the knot, centred on p0, p1
      const glm::dvec3 c0 = 0.5 * (w[q[0]] + w[q[1]]), c1 = 0.5 * (w[q[2]] + w[q[3]]);
      midpoint = std::max(midpoint, glm::length(0.5 * (c0 + c1) - x) / r);
      control = std::max(control, std::abs(glm::length(w[q[4]] - w[q[5]]) - 2.0 * r) / r);
      perpendicular = std::max(perpendicular, std::abs(glm::dot(x - w[q[4]], c0 - x)) /
                                                  (glm::length(x - w[q[4]]) * glm::length(c0 - x)));
      plane = std::max({plane, std::abs(glm::dot(w[q[4]] - x, n)) / r, std::abs(glm::dot(c0 - x, n)) / r});
      // c0+ − c0− and c1+ − c1− are 2r along ±n (the template's side).
      normal = std::max(normal, glm::length(glm::cross(w[q[0]] - w[q[1]], n)) / r);
      normal = std::max(normal, std::abs(std::abs(glm::dot(w[q[0]] - w[q[1]], n)) - 2.0 * r) / r);
      normal = std::max(normal, std::abs(std::abs(glm::dot(w[q[2]] - w[q[3]], n)) - 2.0 * r) / r);
    }
  }
  std::printf("%s: eq. 4 midpoints %.2e r, |p0 - p1| - 2r %.2e r, d.b %.2e, off-plane %.2e r, normal offsets %.2e r\n",
              what, midpoint, control, perpendicular, plane, normal);
  EXPECT_LT(midpoint, 1e-9) << what;
  EXPECT_LT(control, 1e-9) << what;
  EXPECT_LT(perpendicular, 1e-9) << what;
  EXPECT_LT(plane, 1e-9) << what;
  EXPECT_LT(normal, 1e-9) << what;
}

TEST(OracleKnit, ContactConstraintsOfEquation4) {
  const StitchMesh mesh = makeStockinette(5, 6);
  expectEquation4(solve({Deformation::StretchCourse, 1.4}, mesh), "stretch-course 1.4");
  expectEquation4(solve({Deformation::Shear, 20.0}, mesh), "shear 20");
  expectEquation4(solve({Deformation::StretchWale, 1.3}, makeLacePatch(5, 7)), "lace, stretch-wale 1.3");
}

// Eq. 3 recomputed from the output points (rest values measured on the rest
// solve's points) against the energy the solver reports, before and after;
// the output points against eq. 1–2 rebuilt from the reported Θ; and the
// optimum: the recomputed energy rises along every Θ direction nearby.
void expectEnergies(const Solved& s, const char* what) {
  const int iterations = s.deformed.options.iterations;
  double worstReported = 0.0, worstInitial = 0.0, worstPoints = 0.0, sumBefore = 0.0, sumAfter = 0.0;
  const std::vector<glm::dvec3> initial = initialKnitPoints(s.deformed);
  for (uint32_t t = 0; t < s.deformed.tileCount(); ++t) {
    const Measures rest = measure(tilePoints(s.rest, s.restSolution.framePoints, t));
    const double after = energy(measure(tilePoints(s.deformed, s.solution.framePoints, t)), rest, kWAngle, kWLength);
    const double before = energy(measure(tilePoints(s.deformed, initial, t)), rest, kWAngle, kWLength);
    const double scale = std::max(before, 1e-12);
    worstReported = std::max(worstReported, std::abs(s.solution.energy[t][iterations] - after) / scale);
    worstInitial = std::max(worstInitial, std::abs(s.solution.energy[t][0] - before) / scale);
    sumBefore += before, sumAfter += after;
    const std::vector<glm::dvec3> rebuilt = pointsFromTheta(s.deformed, s.solution.framePoints, t, s.solution.theta[t]);
    for (int i = 0; i < 14; ++i)
      worstPoints = std::max(worstPoints, glm::length(rebuilt[i] - s.solution.framePoints[t * 14 + i]) /
                                              s.deformed.options.yarnRadius);
  }
  std::printf("%s: eq. 3 recomputed vs reported: after %.2e, before %.2e (relative); total %.4g -> %.4g; points vs "
              "eq. 1-2 from theta %.2e r\n",
              what, worstReported, worstInitial, sumBefore, sumAfter, worstPoints);
  EXPECT_LT(worstReported, 1e-9) << what << ": final energy";
  EXPECT_LT(worstInitial, 1e-9) << what << ": initial energy";
  EXPECT_LT(worstPoints, 1e-9) << what << ": points vs eq. 1–2";
  EXPECT_LT(sumAfter, sumBefore) << what << ": the optimization lowers eq. 3";
}

TEST(OracleKnit, EnergyRecomputedFromThePoints) {
  const StitchMesh mesh = makeStockinette(5, 6);
  expectEnergies(solve({Deformation::StretchCourse, 1.4}, mesh), "stretch-course 1.4");
  expectEnergies(solve({Deformation::Shear, 20.0}, mesh), "shear 20");
}

// The reported optimum is a minimum of the independently computed eq. 3: no
// small step of Θ lowers it by more than the Gauss–Newton tolerance left
// after three iterations (relative 1e-3 of the energy removed).
TEST(OracleKnit, SolutionIsAMinimumOfTheRecomputedEnergy) {
  const StitchMesh mesh = makeStockinette(4, 4);
  const Solved s = solve({Deformation::StretchCourse, 1.4}, mesh);
  const std::vector<glm::dvec3> initial = initialKnitPoints(s.deformed);
  double worstGain = 0.0;
  for (uint32_t t = 0; t < s.deformed.stitchCount; ++t) {
    const Measures rest = measure(tilePoints(s.rest, s.restSolution.framePoints, t));
    auto E = [&](glm::dvec4 theta) {
      return energy(measure(pointsFromTheta(s.deformed, s.solution.framePoints, t, theta)), rest, kWAngle, kWLength);
    };
    const glm::dvec4 theta = s.solution.theta[t];
    const double e = E(theta);
    const double removed = energy(measure(tilePoints(s.deformed, initial, t)), rest, kWAngle, kWLength) - e;
    const double r = s.deformed.options.yarnRadius;
    const glm::dvec4 steps(1e-3, 1e-3, 1e-3 * r, 1e-3 * r);
    for (int k = 0; k < 4; ++k)
      for (double sign : {-1.0, 1.0}) {
        glm::dvec4 q = theta;
        q[k] += sign * steps[k];
        worstGain = std::max(worstGain, (e - E(q)) / std::max(removed, 1e-12));
      }
  }
  std::printf("optimum: best energy gain of a small step, relative to the energy removed: %.2e\n", worstGain);
  EXPECT_LT(worstGain, 1e-3);
}

}  // namespace
}  // namespace ft
