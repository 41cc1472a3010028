// edge_corpus.h — the geometric edge-case corpus (issue 8): yarn curves that
// real exports contain or that push float32 to its limits. The committed files
// under tests/edge_corpus/ and the bad-*.bcc of tests/fuzz_corpus/bcc are
// written from these models (tests/edge_corpus_test.cpp checks they still
// match; FT_WRITE_EDGE_CORPUS=1 rewrites them).
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "scene/yarn_model.h"

namespace ft::test {

// A wavy open run of n points starting at `origin`, spacing about `step` along x.
inline std::vector<glm::vec3> wavyRun(glm::vec3 origin, int n, float step) {
  std::vector<glm::vec3> p;
  for (int i = 0; i < n; ++i)
    p.push_back(origin + glm::vec3(step * i, 0.02f * std::sin(1.3f * i), 0.015f * std::cos(0.7f * i)));
  return p;
}

inline YarnCurve openCurve(std::vector<glm::vec3> p) { return YarnCurve{std::move(p), false}; }
inline YarnCurve closedCurve(std::vector<glm::vec3> p) { return YarnCurve{std::move(p), true}; }

// Every curve at its own z so that the yarns do not overlap in the images.
// Back-tracks are exact: p[i+1] is a copy of p[i-1], so the Catmull-Rom
// derivative at knot i is exactly zero.
inline YarnModel edgeCorpus() {
  YarnModel m;
  m.name = "edges";
  auto lane = [](int i) { return glm::vec3(0.0f, 0.0f, 0.15f * i); };
  {  // 0: open, back-track in the middle (knot 5)
    std::vector<glm::vec3> p = wavyRun(lane(0), 6, 0.05f);
    p.push_back(p[4]);
    for (int i = 0; i < 5; ++i) p.push_back(p.back() + glm::vec3(-0.03f, 0.04f, 0.01f * std::sin(float(i))));
    m.curves.push_back(openCurve(p));
  }
  {  // 1: open, back-track at the start (knot 1: p2 == p0)
    std::vector<glm::vec3> p = {lane(1), lane(1) + glm::vec3(0.05f, 0.01f, 0.0f), lane(1)};
    for (int i = 1; i <= 6; ++i) p.push_back(lane(1) + glm::vec3(-0.05f * i, 0.02f * std::sin(float(i)), 0.01f));
    m.curves.push_back(openCurve(p));
  }
  {  // 2: open, back-track at the end (knot n-2: p[n-1] == p[n-3])
    std::vector<glm::vec3> p = wavyRun(lane(2), 7, 0.05f);
    p.push_back(p[p.size() - 2]);
    m.curves.push_back(openCurve(p));
  }
  {  // 3: open, two back-tracks in a row (knots 1 and 2: A B A B C ...)
    const glm::vec3 a = lane(3), b = lane(3) + glm::vec3(0.06f, 0.02f, 0.01f);
    std::vector<glm::vec3> p = {a, b, a, b, b + glm::vec3(0.05f, -0.03f, 0.0f), b + glm::vec3(0.1f, 0.0f, 0.02f)};
    m.curves.push_back(openCurve(p));
  }
  {  // 4: closed, back-track at knot 0 (p1 == p[n-1])
    std::vector<glm::vec3> p;
    const int n = 12;
    for (int i = 0; i < n - 1; ++i) {
      const float a = 6.2831853f * i / n;
      p.push_back(lane(4) + glm::vec3(0.5f + 0.1f * std::cos(a), 0.1f * std::sin(a), 0.02f * std::sin(2.0f * a)));
    }
    p.push_back(p[1]);
    m.curves.push_back(closedCurve(p));
  }
  {  // 5: closed, back-track at the last knot (p0 == p[n-2])
    std::vector<glm::vec3> p;
    const int n = 10;
    for (int i = 0; i < n - 1; ++i) {
      const float a = 6.2831853f * i / n;
      p.push_back(lane(5) + glm::vec3(0.9f + 0.1f * std::cos(a), 0.1f * std::sin(a), 0.03f * std::cos(3.0f * a)));
    }
    // q0..q9 with q8 := q0: the last knot's neighbours q8 and q0 (wrapped) are equal.
    p.insert(p.end() - 1, p[0]);
    m.curves.push_back(closedCurve(p));
  }
  {  // 6: closed, back-track in the middle, and a 4-point closed zigzag (cusps at knots 0 and 2)
    std::vector<glm::vec3> p;
    for (int i = 0; i < 8; ++i) {
      const float a = 6.2831853f * i / 8;
      p.push_back(lane(6) + glm::vec3(1.3f + 0.1f * std::cos(a), 0.1f * std::sin(a), 0.0f));
    }
    p.insert(p.begin() + 5, p[3]);  // q4 = p4, q5 = p3: knot 4 has neighbours q3 == q5
    m.curves.push_back(closedCurve(p));
    const glm::vec3 b = lane(6) + glm::vec3(1.7f, 0.0f, 0.0f);
    m.curves.push_back(closedCurve({b, b + glm::vec3(0.08f, 0.0f, 0.0f), b + glm::vec3(0.08f, 0.08f, 0.02f),
                                    b + glm::vec3(0.08f, 0.0f, 0.0f)}));
  }
  {  // 8: collinear: a straight run, then an exact back-track along the same line, then on
    std::vector<glm::vec3> p;
    for (int i = 0; i < 6; ++i) p.push_back(lane(8) + glm::vec3(0.05f * i, 0.0f, 0.0f));
    p.push_back(p[4]);
    p.push_back(p[3]);
    p.push_back(p[3] + glm::vec3(0.0f, 0.05f, 0.0f));
    m.curves.push_back(openCurve(p));
  }
  {  // 9: collinear, pointing straight up (+y) and straight down (-y): ftPerpendicular's branch point
    std::vector<glm::vec3> p;
    for (int i = 0; i < 5; ++i) p.push_back(lane(9) + glm::vec3(0.0f, 0.05f * i, 0.0f));
    p.push_back(p[3]);
    for (int i = 2; i >= 0; --i) p.push_back(lane(9) + glm::vec3(0.0f, 0.05f * i - 0.01f, 0.0f));
    m.curves.push_back(openCurve(p));
  }
  {  // 10: 1e-6 spacing: a dense stretch of 12 points inside a normal run
    std::vector<glm::vec3> p = wavyRun(lane(10), 4, 0.05f);
    const glm::vec3 at = p.back();
    for (int i = 1; i <= 12; ++i) p.push_back(at + glm::vec3(1e-6f * i, 0.5e-6f * (i % 2), 0.0f));
    for (int i = 1; i <= 4; ++i) p.push_back(p.back() + glm::vec3(0.05f, 0.01f * (i % 2), 0.0f));
    m.curves.push_back(openCurve(p));
  }
  {  // 11, 12: 2-point curves (one segment; both ends reflected), one of them vertical
    m.curves.push_back(openCurve({lane(11), lane(11) + glm::vec3(0.2f, 0.05f, 0.0f)}));
    m.curves.push_back(openCurve({lane(12), lane(12) + glm::vec3(0.0f, 0.2f, 0.0f)}));
  }
  {  // 13: a cusp whose one-sided tangents are less than 90° apart (the minimal-rotation
     // branch): long legs before and after a short back-and-forth (P3 == P1)
    const glm::vec3 b = lane(13) + glm::vec3(0.3f, 0.0f, 0.0f);
    m.curves.push_back(openCurve({b + glm::vec3(0.0f, 0.6f, 0.0f), b, b + glm::vec3(0.01f, 0.0f, 0.0f), b,
                                  b + glm::vec3(0.0f, -0.6f, 0.0f), b + glm::vec3(0.05f, -0.7f, 0.0f)}));
  }
  return m;
}

// A helix with an exact back-track in the middle (issue 14, deliverable 11):
// h0 .. h10, h9, h11 .. h20, so p[11] == p[9]: the curve turns back at knot
// 10 (zero tangent) and again, nearly, at knot 11 (from h9 on to h11). Those
// are corners of the curve itself, which closeup/* must report apart while
// staying strict everywhere else; the close-up camera looks at the control
// point nearest the model centre, next to them.
inline YarnModel helixCusp() {
  YarnModel m;
  m.name = "helix-cusp";
  std::vector<glm::vec3> h;
  for (int i = 0; i <= 20; ++i) {
    const float a = 0.7f * float(i);
    h.push_back(glm::vec3(0.15f * std::cos(a), 0.15f * std::sin(a), 0.06f * float(i)));
  }
  std::vector<glm::vec3> p(h.begin(), h.begin() + 11);
  p.push_back(h[9]);
  p.insert(p.end(), h.begin() + 11, h.end());
  m.curves.push_back(openCurve(p));
  return m;
}

// Segments a million units long (and short ones next to them): a separate
// model, since its scale sets the position tolerance of the whole model.
inline YarnModel longSegments() {
  YarnModel m;
  m.name = "long-segments";
  std::vector<glm::vec3> p;
  for (int i = 0; i < 8; ++i) p.push_back({1e6f * i, 2e5f * std::sin(float(i)), 1e5f * std::cos(1.7f * float(i))});
  m.curves.push_back(openCurve(p));
  std::vector<glm::vec3> q;
  for (int i = 0; i < 6; ++i) {
    const float a = 6.2831853f * i / 6;
    q.push_back({3e6f + 1e6f * std::cos(a), 2e6f, 1e6f * std::sin(a)});
  }
  q.push_back(q[4]);  // and a back-track at that scale
  m.curves.push_back(closedCurve(q));
  return m;
}

// Rejected by the reader: one coordinate of 1e30 (curve 1, point 2), points
// 1e-30 apart (curve 0, point 1), a one-point curve (curve 1).
inline YarnModel hugeCoordinate() {
  YarnModel m;
  m.name = "bad-huge-coordinate";
  m.curves.push_back(openCurve({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}));
  m.curves.push_back(openCurve({{0, 1, 0}, {1, 1, 0}, {1e30f, 1, 0}, {3, 1, 0}}));
  return m;
}

inline YarnModel tinySpacing() {
  YarnModel m;
  m.name = "bad-tiny-spacing";
  m.curves.push_back(openCurve({{0, 0, 0}, {1e-30f, 0, 0}, {1, 0, 0}}));
  return m;
}

inline YarnModel onePointCurve() {
  YarnModel m;
  m.name = "bad-one-point-curve";
  m.curves.push_back(openCurve({{0, 0, 0}, {1, 0, 0}}));
  m.curves.push_back(openCurve({{0, 1, 0}}));
  return m;
}

}  // namespace ft::test
