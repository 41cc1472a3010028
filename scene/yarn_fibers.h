// yarn_fibers.h — turns a fitted yarn preset into what the generators read:
// the YarnParams block and the fiber-coordinate table sorted by R_i
// (000_cc9bd0fbd0e08a03.txt §5).
#pragma once
#include <cstdint>
#include <vector>

#include "common/constants.h"
#include "common/yarn_buffers.h"
#include "common/yarn_params.h"
#include "scene/yarn_preset.h"

namespace ft {

struct FiberOptions {
  uint32_t regularFibersPerPly = 20;  // outermost fibers drawn individually; the rest form the core (§3.2)
  // The all-fiber reference (docs/ground-truth.md): every fiber of the preset
  // (fiber_num per ply) explicit, so no core (its radius is 0 and nothing
  // draws it); regularFibersPerPly is then ignored. Loop and hair fibers keep
  // the preset's densities per unit length. Pair with LoD off
  // (allFiberViewParams) so no fiber is dropped into the core.
  bool allFibers = false;
  uint32_t maxSubdivisions = 32;      // cap on line segments per fiber per yarn segment (the screen decides, lod.h)
  float fiberRadius = 0.0008f;        // drawn fiber half-width at the preset's own scale (8 µm if units are cm)
  uint32_t seed = 1;
  float yarnRadius = 0.0f;            // yarn radius to fit the preset to; 0: estimated from the model (yarn_radius.h)
  // Phase of eq. 2: FT_MIGRATION_PHASE_INDEPENDENT (a random phase per fiber, as
  // the presets were fitted) or FT_MIGRATION_PHASE_FIBER_ANGLE (θ_i, as eq. 2 of
  // 000_cc9bd0fbd0e08a03.txt writes it). common/fiber_geometry.h.
  uint32_t migrationPhase = FT_MIGRATION_PHASE_INDEPENDENT;
};

// Rejection-samples `preset.fiberNum` fiber positions in the unit ply disk with
// the density p(R) of reference-data §2, using the shared counter-based RNG
// (common/rng.h) so the table is the same on every machine; sorted by R then θ.
std::vector<FiberCoord> makeFiberTable(const YarnPreset& preset, uint32_t seed);

// Throws InputError (naming the option and value) when `options` cannot be
// used with `preset`. makeYarnParams checks the same; call this first to
// reject bad options before any other work.
void checkFiberOptions(const YarnPreset& preset, const FiberOptions& options);

// Fills YarnParams. Loop and hair fibers: the preset gives densities per unit
// length of ply (reference-data §2), shared by the regular fibers. Flyaways
// are tied to migration periods (000_cc9bd0fbd0e08a03.txt §3.1): each period
// of each regular fiber is cut into `flyawayCells` equal cells, as few as keep
// the expected flyaways per cell ≤ ½ (1 = the paper's one type per period),
// and a cell is a loop with probability λ_loop = loop_density / (regular
// fibers · cells per unit length), a hair with λ_hair likewise: the expected
// counts per unit length equal the preset densities exactly. Throws
// InputError for options out of range.
YarnParams makeYarnParams(const YarnPreset& preset, const std::vector<FiberCoord>& table,
                          const FiberOptions& options);

// The regular fibers per ply `options` asks for: fiber_num with allFibers.
uint32_t regularFibersOf(const YarnPreset& preset, const FiberOptions& options);

// What both generators read for one preset: the fiber table (seeded by
// options.seed) and the YarnParams made from it.
struct FiberSetup {
  std::vector<FiberCoord> table;
  YarnParams params{};
};

// The one path from a preset and options to the generators' inputs:
// makeFiberTable then makeYarnParams. Throws InputError like makeYarnParams.
FiberSetup makeFiberSetup(const YarnPreset& preset, const FiberOptions& options);

}  // namespace ft
