#include "scene/default_scene.h"

#include <cmath>

namespace ft {

YarnModel makeDefaultScene() {
  YarnModel m;
  m.name = "default-scene";
  // Control points about one yarn radius apart, like the real BCC models
  // (reference-data §1); units are centimetres like the presets.
  const float spacing = 0.03f;
  const float pitch = 0.2f;   // distance between neighbouring yarns
  const int yarns = 4;
  const float extent = pitch * yarns;
  const int n = static_cast<int>(extent / spacing);
  for (int i = 0; i < yarns; ++i) {  // weft along x and warp along z, interlaced
    YarnCurve weft, warp;
    for (int k = 0; k <= n; ++k) {
      float u = k * spacing;
      float phase = static_cast<float>(M_PI) * u / pitch;
      weft.points.push_back({u, 0.04f * std::sin(phase + i * static_cast<float>(M_PI)), (i + 0.5f) * pitch});
      warp.points.push_back({(i + 0.5f) * pitch, -0.04f * std::sin(phase + i * static_cast<float>(M_PI)), u});
    }
    m.curves.push_back(weft);
    m.curves.push_back(warp);
  }
  {  // A closed, tilted loop above the patch.
    YarnCurve loop;
    loop.closed = true;
    const int count = 60;
    const float r = 0.25f;
    for (int k = 0; k < count; ++k) {
      float a = 2.0f * static_cast<float>(M_PI) * k / count;
      loop.points.push_back({0.4f + r * std::cos(a), 0.35f + 0.3f * r * std::sin(a) + 0.05f * std::sin(3.0f * a),
                             0.4f + r * std::sin(a)});
    }
    m.curves.push_back(loop);
  }
  {  // A straight vertical piece: the tangent is parallel to the y axis.
    YarnCurve post;
    for (int k = 0; k < 16; ++k) post.points.push_back({-0.15f, k * spacing, -0.15f});
    m.curves.push_back(post);
  }
  {  // An open cubic Bézier curve: a C1 S-shaped helix, built from Hermite data
     // (B1 = P_k + T_k h/3, B2 = P_k+1 - T_k+1 h/3) so tangents match at knots.
    YarnCurve s;
    s.basis = FT_BASIS_BEZIER;
    auto point = [](float u) {
      return glm::vec3(0.9f * u, 0.2f + 0.12f * std::sin(6.0f * u), -0.3f + 0.08f * std::cos(4.0f * u));
    };
    auto tangent = [](float u) {
      return glm::vec3(0.9f, 0.72f * std::cos(6.0f * u), -0.32f * std::sin(4.0f * u));
    };
    const int segments = 24;
    const float h = 1.0f / segments;
    for (int k = 0; k < segments; ++k) {
      const float u0 = k * h, u1 = (k + 1) * h;
      if (k == 0) s.points.push_back(point(u0));
      s.points.push_back(point(u0) + tangent(u0) * (h / 3.0f));
      s.points.push_back(point(u1) - tangent(u1) * (h / 3.0f));
      s.points.push_back(point(u1));
    }
    m.curves.push_back(s);
  }
  return m;
}

}  // namespace ft
