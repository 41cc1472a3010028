// flyaway.h — CPU reference of the flyaway curves and their three seamless
// textures (001 §4.4, eq. 12–13; common/flyaway.h, docs/flyaways.md): scalar
// C++, TBB over slots and rows. gpu/flyaway_gpu.h is the twin.
#pragma once
#include "scene/flyaway_input.h"

namespace ft {

// Planted fault of the CPU side only (validation/faults.def, setSharedFault).
inline bool ftFaultFlyawayCpuVFlip = false;
#define FT_FAULT_FLYAWAY_CPU_V_FLIP_ON ::ft::ftFaultFlyawayCpuVFlip

// Every slot of every pattern: the shared generator run in C++.
FlyawayCurves generateFlyawaysCpu(const FlyawayParams& params);

// The three layers of pattern 0: per texel the nearest drawn segment of B
// (twice, at z and z + P) and I_k, dropped when behind the regular fibers.
FlyawayTextures bakeFlyawaysCpu(const FlyawayCurves& curves);

}  // namespace ft
