// yarn_model.h — a yarn-level model (yarn centre curves) and its flattening
// into the buffers both generators consume (common/yarn_buffers.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/yarn_buffers.h"
#include "common/yarn_curve.h"

namespace ft {

struct YarnCurve {
  std::vector<glm::vec3> points;   // y-up world space (readers convert z-up files)
  bool closed = false;
  uint32_t basis = FT_BASIS_CATMULL_ROM;
};

struct YarnModel {
  std::string name;                // file path or "default-scene"
  std::vector<YarnCurve> curves;
};

struct YarnBuffers {
  std::vector<ControlPoint> points;   // xyz + length coordinate (fixed here, §5)
  std::vector<CurveInfo> curves;
  std::vector<SegmentRef> segments;
  uint32_t knotCount = 0;             // entries of the frame buffer
  // Bytes of procedural input a GPU path receives for the geometry.
  size_t byteSize() const {
    return points.size() * sizeof(ControlPoint) + curves.size() * sizeof(CurveInfo) +
           segments.size() * sizeof(SegmentRef);
  }
};

// Limits of what float32 frame and fiber arithmetic handles (README "Inputs
// and bad input"): squared differences of coordinates up to kMaxCoordinate
// (<= 12·1e36) stay below FLT_MAX (3.4e38) with room for the reflections'
// 2/c factors; consecutive points at least kMinPointSpacing apart keep their
// squared distance (>= 1e-24) and the tangent test's 1e-12 of it
// (common/yarn_frame.h) far above FLT_MIN (1.2e-38), where the GPU flushes
// denormals to zero and the CPU does not.
inline constexpr float kMaxCoordinate = 1e18f;
inline constexpr double kMinPointSpacing = 1e-12;

// Checks the model (every curve evaluable: enough points, finite, no
// coincident consecutive points, the limits above) and flattens it. Throws InputError naming
// model.name, the curve and the point.
YarnBuffers buildYarnBuffers(const YarnModel& model);

// Animation: gives `frame` the length coordinates (and curve lengths) of `rest`,
// a model with the same curves and point counts, so that the fibers stay on
// the same stretch of yarn material as it deforms (§5 fixes them at load).
// Throws std::invalid_argument when the two do not match.
void adoptLengthCoordinates(YarnBuffers& frame, const YarnBuffers& rest);

// Axis-aligned bounds of all control points.
struct Bounds {
  glm::vec3 lo{0.0f};
  glm::vec3 hi{0.0f};
};
Bounds modelBounds(const YarnModel& model);

}  // namespace ft
