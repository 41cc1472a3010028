// fiber_reference.h — the scalar CPU reference for procedural fiber
// generation (000_cc9bd0fbd0e08a03.txt §2.2, §3.1–3.3, §5): the same
// common/ functions the shaders call, run with TBB over yarn segments.
#pragma once
#include <span>
#include <vector>

#include "common/yarn_frame.h"
#include "scene/fiber_input.h"

namespace ft {

// Rotation-minimizing knot normals of every curve (common/yarn_frame.h),
// TBB over curves.
std::vector<FrameNormal> computeKnotFramesCpu(const YarnBuffers& yarn);

// Knot k of curve c (0 <= k <= segments), as the frame propagation sees it.
Knot knotCpu(const YarnBuffers& yarn, const CurveInfo& c, uint32_t k);

// Segment `segment` in Bézier form with its knot normals filled in.
YarnSegment loadSegmentCpu(const YarnBuffers& yarn, std::span<const FrameNormal> frames, uint32_t segment);

// Generates the fibers of the listed segments (all segments when empty).
FiberGeometry generateFibersCpu(const FiberInput& input, std::span<const FrameNormal> frames,
                                std::span<const uint32_t> segments = {});

}  // namespace ft
