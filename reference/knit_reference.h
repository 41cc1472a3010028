// knit_reference.h — the CPU reference of the knot-based yarn optimization
// (001_dce8d4d1f783b802.txt §3.2, §5.2): common/knit_solver.h in double
// precision, TBB over stitches.
#pragma once
#include <array>
#include <glm/glm.hpp>
#include <vector>

#include "knit/knit_problem.h"

namespace ft {

struct KnitSolution {
  std::vector<glm::dvec3> framePoints;  // tile * 14 + i, face frame (x, y in plane, z normal)
  std::vector<glm::dvec3> worldPoints;  // the same, world space
  // Eq. 3 energy per tile before each iteration and after the last (iterations + 1 values).
  std::vector<std::array<double, FT_KNIT_MAX_ITERATIONS + 1>> energy;
  std::vector<glm::dvec4> theta;  // final (θ_L, θ_R, l_L, l_R)
  std::vector<uint32_t> steps;    // iterations that changed Θ (a singular system skips one)
};

KnitSolution solveKnitCpu(const KnitSetup& setup);
// The same into `solution`, reusing its storage when it already has the
// setup's size (an animation solving frame after frame).
void solveKnitCpu(const KnitSetup& setup, KnitSolution& solution);
// The same in float (ft::knit32): the GPU's arithmetic on the CPU, to tell
// float rounding from an algorithmic difference.
KnitSolution solveKnitCpuFloat(const KnitSetup& setup);

}  // namespace ft
