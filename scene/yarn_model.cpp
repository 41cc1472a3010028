#include "scene/yarn_model.h"

#include <cmath>
#include <stdexcept>
#include <fmt/format.h>

#include "scene/input_error.h"

namespace ft {

YarnBuffers buildYarnBuffers(const YarnModel& model) {
  YarnBuffers out;
  for (size_t c = 0; c < model.curves.size(); ++c) {
    const YarnCurve& curve = model.curves[c];
    const size_t n = curve.points.size();
    auto fail = [&](const std::string& what) {
      throw InputError(fmt::format("{}: curve {}: {}", model.name, c, what));
    };
    if (curve.basis == FT_BASIS_BEZIER) {
      if (curve.closed) fail("closed Bézier curves are not supported");
      if (n < 4 || (n - 1) % 3 != 0) fail(fmt::format("a Bézier curve needs 3k+1 >= 4 points, has {}", n));
    } else if (curve.basis != FT_BASIS_CATMULL_ROM) {
      fail(fmt::format("unknown basis {}", curve.basis));
    }
    if (!curve.closed && n < 2) fail(fmt::format("an open curve needs >= 2 points, has {}", n));
    if (curve.closed && n < 3) fail(fmt::format("a closed curve needs >= 3 points, has {}", n));
    if (out.points.size() + n > 0xFFFFFFF0u) fail("too many control points in the model");
    for (size_t i = 0; i < n; ++i) {
      const glm::vec3& p = curve.points[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail(fmt::format("point {} is not finite ({}, {}, {})", i, p.x, p.y, p.z));
      for (int k = 0; k < 3; ++k)
        if (std::abs(p[k]) > kMaxCoordinate)
          fail(fmt::format("point {}: coordinate {} is {} (beyond ±{:g}, too large for float32 frames)", i, "xyz"[k],
                           p[k], kMaxCoordinate));
    }
    CurveInfo info{};
    info.firstPoint = static_cast<uint32_t>(out.points.size());
    info.pointCount = static_cast<uint32_t>(n);
    info.closed = curve.closed ? 1u : 0u;
    info.basis = curve.basis;
    info.firstSegment = static_cast<uint32_t>(out.segments.size());
    info.frameBase = out.knotCount;
    // Length coordinate: arc length of the control polygon, accumulated in
    // double and fixed here for the life of the model (§5).
    double s = 0.0;
    for (size_t i = 0; i < n; ++i) {
      if (i > 0) {
        double d = glm::distance(glm::dvec3(curve.points[i - 1]), glm::dvec3(curve.points[i]));
        if (!(d > 0.0)) fail(fmt::format("points {} and {} coincide", i - 1, i));
        if (d < kMinPointSpacing)
          fail(fmt::format("point {} is {:g} from point {} (spacing below {:g}, too small for float32 frames)", i, d,
                           i - 1, kMinPointSpacing));
        s += d;
      }
      out.points.push_back(ControlPoint{glm::vec4(curve.points[i], static_cast<float>(s))});
    }
    if (curve.closed) {
      double d = glm::distance(glm::dvec3(curve.points[n - 1]), glm::dvec3(curve.points[0]));
      if (!(d > 0.0)) fail(fmt::format("points {} and 0 coincide (closed curve)", n - 1));
      if (d < kMinPointSpacing)
        fail(fmt::format("point {} is {:g} from point 0 (closed curve; spacing below {:g}, too small for float32 "
                         "frames)", n - 1, d, kMinPointSpacing));
      s += d;
    }
    info.totalLength = static_cast<float>(s);
    const uint32_t segments = ftCurveSegmentCount(info);
    for (uint32_t k = 0; k < segments; ++k) out.segments.push_back(SegmentRef{static_cast<uint32_t>(c), k});
    out.knotCount += ftCurveKnotCount(info);
    out.curves.push_back(info);
  }
  if (out.segments.empty()) throw InputError(fmt::format("{}: the model has no curve segments", model.name));
  return out;
}

void adoptLengthCoordinates(YarnBuffers& frame, const YarnBuffers& rest) {
  if (frame.points.size() != rest.points.size() || frame.curves.size() != rest.curves.size())
    throw std::invalid_argument(fmt::format("adoptLengthCoordinates: {} points in {} curves, rest has {} in {}",
                                            frame.points.size(), frame.curves.size(), rest.points.size(),
                                            rest.curves.size()));
  for (size_t c = 0; c < frame.curves.size(); ++c) {
    if (frame.curves[c].pointCount != rest.curves[c].pointCount || frame.curves[c].closed != rest.curves[c].closed)
      throw std::invalid_argument(fmt::format("adoptLengthCoordinates: curve {} differs from the rest state", c));
    frame.curves[c].totalLength = rest.curves[c].totalLength;
  }
  for (size_t i = 0; i < frame.points.size(); ++i) frame.points[i].positionLength.w = rest.points[i].positionLength.w;
}

Bounds modelBounds(const YarnModel& model) {
  Bounds b{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
  for (const YarnCurve& c : model.curves)
    for (const glm::vec3& p : c.points) {
      b.lo = glm::min(b.lo, p);
      b.hi = glm::max(b.hi, p);
    }
  return b;
}

}  // namespace ft
