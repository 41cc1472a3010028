// vertex_compare.h — compares a GPU fiber vertex stream with the CPU
// reference by vertex identity (yarn, segment, ply, fiber, vertex index), so
// the GPU may emit in any order (transform feedback follows the driver's).
#pragma once
#include <span>
#include <string>
#include <vector>

#include "common/fiber_vertex.h"
#include "common/yarn_params.h"
#include "validation/metrics.h"

namespace ft {

struct StreamComparison {
  uint64_t cpuVertices = 0, gpuVertices = 0;  // unique vertices
  uint64_t cpuFibers = 0, gpuFibers = 0;      // distinct (segment, ply, fiber) strips
  uint64_t missing = 0;                       // in CPU, not in GPU
  uint64_t extra = 0;                         // in GPU, not in CPU
  uint64_t idMismatch = 0;                    // same vertex, different yarn/type/period tag
  uint64_t duplicateDisagree = 0;             // a vertex emitted twice (line pairs) with different values
  double maxAbs = 0.0, maxRel = 0.0, rmse = 0.0, maxWidthAbs = 0.0;
  ErrorHistogram histogram;
  std::string firstMismatches;                // a few lines for the report
};

// `gpu` may contain each vertex more than once (isoline pairs); duplicates
// must agree exactly. `relativeFloor` is the magnitude below which the
// relative error is taken against the floor instead (avoids 0/0 near the
// origin).
StreamComparison compareStreams(std::span<const FiberVertex> cpu, std::span<const FiberVertex> gpu,
                                double relativeFloor);

uint64_t vertexKey(const FiberVertex& v);

// Vertices with a NaN/Inf position or width; `first` (if given) describes the first.
uint64_t countNonFinite(std::span<const FiberVertex> vertices, std::string* first = nullptr);

}  // namespace ft
