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
  {  // An open cubic Bézier S-curve (3 segments).
    YarnCurve s;
    s.basis = FT_BASIS_BEZIER;
    s.points = {{0.0f, 0.2f, -0.3f}, {0.15f, 0.35f, -0.3f}, {0.25f, 0.05f, -0.3f}, {0.4f, 0.2f, -0.3f},
                {0.55f, 0.35f, -0.3f}, {0.65f, 0.05f, -0.3f}, {0.8f, 0.2f, -0.3f},
                {0.9f, 0.3f, -0.25f}, {0.95f, 0.3f, -0.1f}, {1.0f, 0.2f, 0.0f}};
    m.curves.push_back(s);
  }
  return m;
}

}  // namespace ft
