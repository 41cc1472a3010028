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

// Checks the model (every curve evaluable: enough points, finite, no
// coincident consecutive points) and flattens it. Throws InputError naming
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
