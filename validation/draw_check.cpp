#include "validation/draw_check.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace ft {

void checkBeforeDrawing(const std::string& model, const YarnBuffers& yarn, std::span<const FrameNormal> frames) {
  auto fail = [&](size_t curve, const std::string& what) {
    throw std::runtime_error(fmt::format("{}: yarn {}: {}; nothing drawn", model, curve, what));
  };
  if (frames.size() != yarn.knotCount)
    throw std::runtime_error(fmt::format("{}: {} knot frames for {} knots; nothing drawn", model, frames.size(),
                                         yarn.knotCount));
  for (size_t c = 0; c < yarn.curves.size(); ++c) {
    const CurveInfo& info = yarn.curves[c];
    if (!std::isfinite(info.totalLength) || !(info.totalLength > 0.0f))
      fail(c, fmt::format("length {} is not a positive finite number", info.totalLength));
    for (uint32_t i = 0; i < info.pointCount; ++i) {
      const glm::vec4 p = yarn.points[info.firstPoint + i].positionLength;
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w))
        fail(c, fmt::format("point {}: ({}, {}, {}), length coordinate {} is not finite", i, p.x, p.y, p.z, p.w));
    }
    for (uint32_t k = 0; k < ftCurveKnotCount(info); ++k) {
      const glm::vec3 n(frames[info.frameBase + k].normal);
      const float len = glm::length(n);
      // 1e-3: the frames are normalized with sqrt on both sides (a few ulps);
      // anything far from unit is a broken frame, not rounding.
      if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z) || !(std::abs(len - 1.0f) <= 1e-3f))
        fail(c, fmt::format("knot {}: frame normal ({}, {}, {}) is not a finite unit vector", k, n.x, n.y, n.z));
    }
  }
}

}  // namespace ft
