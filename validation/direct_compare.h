// direct_compare.h — shading/direct's comparison of a shaded GPU frame (no
// approximation of 000 §4) with its Embree twin, for other suites that draw
// the same kind of frame (knit/appearance/*). Defined in shading_cases.cpp,
// where its tolerances are stated and measured.
#pragma once
#include <cstddef>
#include <string>

#include "image/flip.h"
#include "image/image.h"
#include "reference/fiber_trace.h"
#include "validation/harness.h"

namespace ft {

struct DirectComparison {
  size_t interior = 0, covered = 0;  // pixels compared by FLIP; pixels either side covers
  std::string pools;                 // "core N px +bias, ..." for the details line
  FlipResult flip;                   // the interior LDR-FLIP (its error map for the report)
};

// Appends to r.metrics: non-finite values on both sides, the LDR-FLIP over
// interior pixels (every sample of the pixel and its 8 neighbours on one
// fiber strip, both sides), the coverage error against the 16-sample
// `truth16`, and the pooled relative bias over every covered pixel by what it
// shows (core, regular, loop, hair, silhouette). `truth` is traced at the
// rasteriser's own sample positions (FiberRenderer::samplePositions), direct
// light, no shadows.
DirectComparison compareWithDirectTruth(CaseResult& r, const ImageRgbaF& gpu, const TraceResult& truth,
                                        const TraceResult& truth16);

// The fidelity rows' colour figure (informational): (mean B / mean R) of the
// frame over the reference's, over the pixels both cover (> 1: the frame is
// bluer); NaN when a mean is 0.
Metric blueOverRedMetric(const ImageRgbaF& frame, const ImageRgbaF& truth);

}  // namespace ft
