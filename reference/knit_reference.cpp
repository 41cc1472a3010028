#include "reference/knit_reference.h"

#include <tbb/parallel_for.h>

namespace ft {
namespace {

knit32::KnitProblem toFloat(const knit64::KnitProblem& p) {
  knit32::KnitProblem q;
  for (int j = 0; j < 2; ++j) q.knot[j] = glm::vec2(p.knot[j]);
  q.theta0 = glm::vec4(p.theta0);
  for (int i = 0; i < FT_KNIT_FIXED_POINTS; ++i) {
    q.fixedXY[i] = glm::vec2(p.fixedXY[i]);
    q.fixedH[i] = float(p.fixedH[i]);
  }
  for (int i = 0; i < FT_KNIT_LENGTH_RESIDUALS; ++i) q.restLength[i] = float(p.restLength[i]);
  for (int i = 0; i < FT_KNIT_ANGLE_RESIDUALS; ++i) q.restCosine[i] = float(p.restCosine[i]);
  q.radius = float(p.radius);
  q.side = float(p.side);
  return q;
}

// Sizes `out` for the setup (no reallocation when it already fits, as from
// the previous frame of an animation) and solves every tile into it.
template <class SolveTile>
void solveAll(const KnitSetup& s, KnitSolution& out, SolveTile solveTile) {
  const uint32_t n = s.tileCount();
  out.framePoints.resize(size_t(n) * FT_KNIT_TILE_POINTS);
  out.worldPoints.resize(out.framePoints.size());
  out.energy.resize(n);
  out.theta.resize(n);
  out.steps.resize(n);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 64), [&](const tbb::blocked_range<uint32_t>& range) {
    for (uint32_t t = range.begin(); t != range.end(); ++t) {
      solveTile(t, out);
      for (size_t i = size_t(t) * FT_KNIT_TILE_POINTS; i < size_t(t + 1) * FT_KNIT_TILE_POINTS; ++i)
        out.worldPoints[i] = s.frames[t].toWorld(out.framePoints[i]);
    }
  });
}

}  // namespace

void solveKnitCpu(const KnitSetup& s, KnitSolution& solution) {
  const KnitOptions& o = s.options;
  solveAll(s, solution, [&](uint32_t t, KnitSolution& out) {
    const knit64::KnitTileResult r =
        knit64::knitSolveTile(s.problems[t], o.wAngle, o.wLength, static_cast<uint32_t>(o.iterations));
    for (int i = 0; i < FT_KNIT_TILE_POINTS; ++i) out.framePoints[size_t(t) * FT_KNIT_TILE_POINTS + i] = r.p[i];
    for (int k = 0; k <= FT_KNIT_MAX_ITERATIONS; ++k) out.energy[t][k] = r.energy[k];
    out.theta[t] = r.theta;
    out.steps[t] = r.steps;
  });
}

KnitSolution solveKnitCpu(const KnitSetup& s) {
  KnitSolution out;
  solveKnitCpu(s, out);
  return out;
}

KnitSolution solveKnitCpuFloat(const KnitSetup& s) {
  const KnitOptions& o = s.options;
  KnitSolution solution;
  solveAll(s, solution, [&](uint32_t t, KnitSolution& out) {
    const knit32::KnitTileResult r = knit32::knitSolveTile(toFloat(s.problems[t]), float(o.wAngle),
                                                           float(o.wLength), static_cast<uint32_t>(o.iterations));
    for (int i = 0; i < FT_KNIT_TILE_POINTS; ++i)
      out.framePoints[size_t(t) * FT_KNIT_TILE_POINTS + i] = glm::dvec3(r.p[i]);
    for (int k = 0; k <= FT_KNIT_MAX_ITERATIONS; ++k) out.energy[t][k] = r.energy[k];
    out.theta[t] = glm::dvec4(r.theta);
    out.steps[t] = r.steps;
  });
  return solution;
}

}  // namespace ft
