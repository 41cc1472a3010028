#include "scene/yarn_fibers.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "common/constants.h"
#include "common/rng.h"
#include "scene/input_error.h"

namespace ft {

std::vector<FiberCoord> makeFiberTable(const YarnPreset& preset, uint32_t seed) {
  const double e = std::exp(1.0);
  auto density = [&](double r) {  // p(R) of reference-data §2
    return (1.0 - 2.0 * preset.epsilon) * std::pow((e - std::exp(r / preset.rMax)) / (e - 1.0), preset.beta) +
           preset.epsilon;
  };
  std::vector<FiberCoord> table;
  FiberRandomKey key{0xFFFFFFFFu, 0u, 0u, seed};  // yarn id reserved for the table
  for (uint32_t attempt = 0; table.size() < static_cast<size_t>(preset.fiberNum); ++attempt) {
    if (attempt > 1000000u * static_cast<uint32_t>(preset.fiberNum))
      throw InputError(fmt::format("yarn preset {}: fiber density p(R) rejects every sample", preset.name));
    key.period = attempt;
    glm::uvec4 bits = ftRandomBits(key, 0u);
    double x = 2.0 * ftUnitFloat(bits.x) - 1.0;
    double y = 2.0 * ftUnitFloat(bits.y) - 1.0;
    double r2 = x * x + y * y;
    if (r2 > 1.0) continue;  // uniform in the disk of radius R_max
    double r = std::sqrt(r2) * preset.rMax;
    if (ftUnitFloat(bits.z) >= density(r)) continue;
    double turns = std::atan2(y, x) / (2.0 * M_PI);
    if (turns < 0.0) turns += 1.0;
    table.push_back(FiberCoord{static_cast<float>(r), static_cast<float>(std::min(turns, 0x1.fffffep-1))});
  }
  std::sort(table.begin(), table.end(), [](const FiberCoord& a, const FiberCoord& b) {
    return a.radius != b.radius ? a.radius < b.radius : a.thetaTurns < b.thetaTurns;
  });
  return table;
}

void checkFiberOptions(const YarnPreset& preset, const FiberOptions& options) {
  if (options.regularFibersPerPly > static_cast<uint32_t>(preset.fiberNum))
    throw InputError(fmt::format("--fibers-per-ply: {} exceeds the {} fibers per ply of yarn '{}'",
                                 options.regularFibersPerPly, preset.fiberNum, preset.name));
  if (options.maxSubdivisions < 1 || options.maxSubdivisions > FT_MAX_SUBDIVISIONS)
    throw InputError(fmt::format("--subdivisions: {} is outside [1, {}]", options.maxSubdivisions,
                                 FT_MAX_SUBDIVISIONS));
  if (!(options.fiberRadius > 0.0f) || !std::isfinite(options.fiberRadius))
    throw InputError(fmt::format("--fiber-radius: {} must be a positive number", options.fiberRadius));
}

YarnParams makeYarnParams(const YarnPreset& preset, const std::vector<FiberCoord>& table,
                          const FiberOptions& options) {
  checkFiberOptions(preset, options);
  if (table.size() != static_cast<size_t>(preset.fiberNum))
    throw InputError(fmt::format("yarn preset {}: fiber table has {} rows, expected {}", preset.name,
                                 table.size(), preset.fiberNum));

  YarnParams p{};
  p.plyCount = static_cast<uint32_t>(preset.plyNum);
  p.fiberCount = static_cast<uint32_t>(preset.fiberNum);
  p.regularFibers = options.regularFibersPerPly;
  p.maxSubdivisions = options.maxSubdivisions;
  p.plyRadius = static_cast<float>(preset.yarnRadius / 2.0);
  p.ellipseN = static_cast<float>(preset.ellipseShort);
  p.ellipseB = static_cast<float>(preset.ellipseLong);
  p.fiberRadius = options.fiberRadius;
  p.plyTurnsPerLength = static_cast<float>(1.0 / preset.yarnAlpha);
  p.fiberTurnsPerLength = static_cast<float>(1.0 / preset.alpha);
  p.plyTwistSign = preset.yarnClockWise ? -1.0f : 1.0f;
  p.fiberTwistSign = preset.fiberClockWise ? -1.0f : 1.0f;
  p.migrationS = static_cast<float>(preset.sI);
  p.rhoMin = static_cast<float>(preset.rhoMin);
  p.rhoMax = static_cast<float>(preset.rhoMax);
  const uint32_t coreFibers = p.fiberCount - p.regularFibers;
  p.coreRadius = coreFibers > 0 ? table[coreFibers - 1].radius * p.rhoMax : 0.0f;

  const double periodsPerLength = preset.sI / preset.alpha;
  double pLoop = 0.0, pHair = 0.0;
  if (p.regularFibers > 0 && periodsPerLength > 0.0) {
    pLoop = 1.0 - std::exp(-preset.loopDensity / (p.regularFibers * periodsPerLength));
    pHair = 1.0 - std::exp(-preset.hairDensity / (p.regularFibers * periodsPerLength));
    if (pLoop + pHair > 1.0) {
      const double scale = 1.0 / (pLoop + pHair);
      pLoop *= scale;
      pHair *= scale;
    }
  }
  p.loopProbability = static_cast<float>(pLoop);
  p.hairProbability = static_cast<float>(pHair);
  p.loopR1Mu = static_cast<float>(preset.loopR1.mu);
  p.loopR1Sigma = static_cast<float>(preset.loopR1.sigma);
  p.hairZeMu = static_cast<float>(preset.hairZe.mu);
  p.hairZeSigma = static_cast<float>(preset.hairZe.sigma);
  p.hairR0Mu = static_cast<float>(preset.hairR0.mu);
  p.hairR0Sigma = static_cast<float>(preset.hairR0.sigma);
  p.hairReMu = static_cast<float>(preset.hairRe.mu);
  p.hairReSigma = static_cast<float>(preset.hairRe.sigma);
  p.hairPeMu = static_cast<float>(preset.hairPe.mu);
  p.hairPeSigma = static_cast<float>(preset.hairPe.sigma);

  // Largest fiber radius any period can reach (normal draws are clamped to
  // mu ± 3σ in common/rng.h), in ply-disk units, then in world units.
  auto maxAbs = [](NormalParam n) { return std::abs(n.mu) + 3.0 * n.sigma; };
  const double loopMax = preset.rhoMax + maxAbs(preset.loopR1) / preset.ellipseShort;
  const double hairMax = preset.rhoMax + (maxAbs(preset.hairR0) + maxAbs(preset.hairRe)) / preset.ellipseShort;
  const double rMax = std::max({preset.rhoMax, loopMax, hairMax});
  const double reach = preset.yarnRadius / 2.0 + std::max(preset.ellipseLong, preset.ellipseShort) * rMax;
  p.boundRadius = static_cast<float>(reach * 1.001 + options.fiberRadius);  // 0.1%: float rounding of the hull
  p.seed = options.seed;
  return p;
}

FiberSetup makeFiberSetup(const YarnPreset& preset, const FiberOptions& options) {
  checkFiberOptions(preset, options);
  FiberSetup s;
  s.table = makeFiberTable(preset, options.seed);
  s.params = makeYarnParams(preset, s.table, options);
  return s;
}

}  // namespace ft
