// fiber_input.h — everything fiber generation reads, as plain host arrays.
// The GPU paths upload exactly these arrays; the CPU reference reads them.
#pragma once
#include <vector>

#include "common/fiber_vertex.h"
#include "common/view_params.h"
#include "common/yarn_buffers.h"
#include "common/yarn_params.h"
#include "scene/yarn_model.h"

namespace ft {

struct FiberInput {
  const YarnBuffers* yarn = nullptr;
  const std::vector<FiberCoord>* fiberTable = nullptr;
  YarnParams params{};
  ViewParams view{};
};

// What a generator produced, in canonical order (common/fiber_generation.h).
struct FiberGeometry {
  std::vector<uint32_t> segments;           // which segments were processed, in order
  std::vector<SegmentDecision> decisions;   // one per processed segment
  std::vector<FiberVertex> vertices;
};

}  // namespace ft
