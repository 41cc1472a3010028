// ambient_occlusion.h (reference) — the CPU side of the yarn ambient occlusion
// of Wu & Yuksel 2019 (000) §4.2 (common/ambient_occlusion.h, notes-rendering
// A3): the texture bake with the exact line integral of the ply density (the
// same stratified directions as the GPU twin), a converged variant (many
// equally spaced directions), and the distance-based cubic fit to the
// texture's radial average.
#pragma once
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "common/ambient_occlusion.h"
#include "scene/ambient_occlusion_setup.h"  // AoSettings, makeAoParams, the cubic fit

namespace ft {

struct AoBakeCpu {
  std::vector<float> ao;     // n × n, texel j·n + i (common/ambient_occlusion.h)
  std::vector<float> sigma;  // the estimator's standard deviation per texel, from the strata (see .cpp)
};

// AO at every texel centre (ψ = 0; the jitter keyed by the texel index):
// ftAoExact, one TBB task per row.
AoBakeCpu bakeAmbientOcclusionCpu(const AmbientOcclusionParams& p);
// AO at points (x, y, ψ); point k's jitter is keyed by `sampleIds[k]` when
// given (e.g. the texel index, to reproduce texels), else by k.
AoBakeCpu ambientOcclusionAtCpu(const AmbientOcclusionParams& p, std::span<const glm::vec3> pointsPsi,
                                std::span<const uint32_t> sampleIds = {});

}  // namespace ft
