// flyaway_oracle.h — expectations for the flyaway cases
// (validation/flyaway_cases.cpp) that share no code with common/: the
// distributions that 001 §4.4 eq. 12–13 and the preset's parameters imply,
// measured on the generated curves (KS distances, moments, Poisson counts),
// and an orthographic raster of the curves written again here, in double,
// for the textures and their seams. Nothing here includes common/.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace ft::oracle {

// The model's inputs as plain numbers (world units, radians).
struct FlyawayModel {
  double zeMu = 0, zeSigma = 0, r0Mu = 0, r0Sigma = 0, reMu = 0, reSigma = 0, peMu = 0, peSigma = 0;
  double rootOffset = 0;  // R_0 = rootOffset + r_0
  double alpha = 1;       // eq. 13
  double noise = 0;       // σ_n of the random walk (fraction of a step)
  double densityPerLength = 0;
  double period = 0, zReach = 0, margin = 0;
  // the raster
  double halfWidth = 0, bodyRadius = 0, lineHalfWidth = 0;
  int width = 0, height = 0;
};

// One pattern's curves as the side produced them: for each slot of each set
// (0 = boundary B, 1–3 = interior I_k) the points (x, y, z), empty when the
// slot is absent; `kept` the side's own flag.
struct FlyawayCurve {
  int pattern = 0, set = 0;
  std::vector<double> xyz;  // 3 per point
  bool kept = false;
};

struct StatResult {
  std::string name;
  double value = 0, tolerance = 0;
  std::string why;
};

// Eq. 12–13 statistics of noise-free curves (σ_n = 0): R_0, R_e, z_e, θ_e
// (KS against N(μ, σ) clamped at ±3σ), θ_0 and z_0 (KS against uniform),
// eq. 13's shape at t = ½ and the linearity of θ and z, the Poisson counts of
// candidates and of kept curves per pattern. `patterns`: how many were drawn.
std::vector<StatResult> flyawayStatistics(const FlyawayModel& m, const std::vector<FlyawayCurve>& curves, int patterns,
                                          std::string& details);

// The random walk: with the same draws, noisy minus clean curves' step
// increments over the clean step length are iid U[−√3 σ_n, √3 σ_n]³.
std::vector<StatResult> flyawayNoiseStatistics(const FlyawayModel& m, const std::vector<FlyawayCurve>& clean,
                                               const std::vector<FlyawayCurve>& noisy);

// One texel of the oracle's raster: covered, tangent (t_u, t_v, t_w) with t_u ≥ 0.
struct OracleTexel {
  bool covered = false;
  double t[3] = {0, 0, 0};
};

// Pattern 0's kept curves (decided here from the points) of layer k drawn
// over columns with centres z_c (any z, so a window may span two layers of a
// concatenation: `layerAt(z)` is given by `layers`, one per period starting at
// z = 0). Returns [row][column].
std::vector<OracleTexel> flyawayRaster(const FlyawayModel& m, const std::vector<FlyawayCurve>& curves,
                                       const std::vector<int>& layers, const std::vector<double>& columnZ);

// Decodes a packed RGBA8 texel (r in the low byte).
OracleTexel decodeFlyawayTexel(uint32_t rgba);

double angleBetweenDeg(const double a[3], const double b[3]);

}  // namespace ft::oracle
