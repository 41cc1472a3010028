#include "scene/yarn_fibers.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "common/constants.h"
#include "common/rng.h"
#include "scene/input_error.h"

namespace ft {

namespace {
// Expected flyaways (loops + hairs) per cell at most: at least half the cells
// of a fiber stay regular migration (000_cc9bd0fbd0e08a03.txt §3.1).
constexpr double kMaxFlyawaysPerCell = 0.5;
}  // namespace

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

uint32_t regularFibersOf(const YarnPreset& preset, const FiberOptions& options) {
  return options.allFibers ? static_cast<uint32_t>(preset.fiberNum) : options.regularFibersPerPly;
}

void checkFiberOptions(const YarnPreset& preset, const FiberOptions& options) {
  if (!options.allFibers && options.regularFibersPerPly > static_cast<uint32_t>(preset.fiberNum))
    throw InputError(fmt::format("--fibers-per-ply: {} exceeds the {} fibers per ply of yarn '{}'",
                                 options.regularFibersPerPly, preset.fiberNum, preset.name));
  if (options.maxSubdivisions < 1 || options.maxSubdivisions > FT_MAX_SUBDIVISIONS)
    throw InputError(fmt::format("--subdivisions: {} is outside [1, {}]", options.maxSubdivisions,
                                 FT_MAX_SUBDIVISIONS));
  if (options.migrationPhase != FT_MIGRATION_PHASE_INDEPENDENT && options.migrationPhase != FT_MIGRATION_PHASE_FIBER_ANGLE)
    throw InputError(fmt::format("--migration-phase: unknown value {}", options.migrationPhase));
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
  p.regularFibers = regularFibersOf(preset, options);
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
  uint32_t cells = 1;
  if (p.regularFibers > 0 && periodsPerLength > 0.0) {
    const double perPeriodLoop = preset.loopDensity / (p.regularFibers * periodsPerLength);
    const double perPeriodHair = preset.hairDensity / (p.regularFibers * periodsPerLength);
    const double wanted = std::max(1.0, std::ceil((perPeriodLoop + perPeriodHair) / kMaxFlyawaysPerCell));
    if (!(wanted <= 4096.0))
      throw InputError(fmt::format("yarn preset {}: {} flyaway cells per migration period (at most 4096)",
                                   preset.name, wanted));
    cells = static_cast<uint32_t>(wanted);
    pLoop = perPeriodLoop / cells;
    pHair = perPeriodHair / cells;
  }
  p.flyawayCells = cells;
  p.migrationPhase = options.migrationPhase;
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

  // Largest distance any fiber point can reach (normal draws are clamped to
  // mu ± 3σ in common/rng.h).
  // Loops and hairs are world distances from the ply centre (r1; r0 + re).
  auto maxAbs = [](NormalParam n) { return std::abs(n.mu) + 3.0 * n.sigma; };
  const double regularMax = std::max(preset.ellipseLong, preset.ellipseShort) * preset.rhoMax;
  const double loopMax = maxAbs(preset.loopR1);
  const double hairMax = maxAbs(preset.hairR0) + maxAbs(preset.hairRe);
  const double reach = preset.yarnRadius / 2.0 + std::max({regularMax, loopMax, hairMax});
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
