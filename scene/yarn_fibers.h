// yarn_fibers.h — turns a fitted yarn preset into what the generators read:
// the YarnParams block and the fiber-coordinate table sorted by R_i
// (000_cc9bd0fbd0e08a03.txt §5).
#pragma once
#include <cstdint>
#include <vector>

#include "common/yarn_buffers.h"
#include "common/yarn_params.h"
#include "scene/yarn_preset.h"

namespace ft {

struct FiberOptions {
  uint32_t regularFibersPerPly = 20;  // outermost fibers drawn individually; the rest form the core (§3.2)
  uint32_t maxSubdivisions = 32;      // cap on line segments per fiber per yarn segment (the screen decides, lod.h)
  float fiberRadius = 0.0008f;        // drawn fiber half-width at the preset's own scale (8 µm if units are cm)
  uint32_t seed = 1;
  float yarnRadius = 0.0f;            // yarn radius to fit the preset to; 0: estimated from the model (yarn_radius.h)
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
// length of ply; each regular fiber has preset.sI/alpha migration periods per
// unit length, so a period is a loop with probability 1 - exp(-λ_loop),
// λ_loop = loop_density·alpha / (regular fibers·s_i) (Poisson: at least one
// loop in the period), likewise hair; both are scaled down together if they
// would sum past 1. Throws InputError for options out of range.
YarnParams makeYarnParams(const YarnPreset& preset, const std::vector<FiberCoord>& table,
                          const FiberOptions& options);

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
