// The Embree ground truth (reference/fiber_trace.h, bcsdf_sampling.h) against
// expectations written out here, sharing no code with common/: the coverage
// of a tube from its silhouette, 000 §4.3 eq. 6 implemented from scratch
// (Gaussian M normalised by quadrature, von Mises N with std::cyl_bessel_i),
// shadows from the geometry of two cylinders, the white furnace
// (notes-rendering X6), the sampler's density by quadrature, determinism.
// Scenes are built by hand (straight fibers, a far camera with a narrow
// field of view), so every expected value has a closed form or a quadrature.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <vector>

#include "common/constants.h"
#include "reference/bcsdf_sampling.h"
#include "reference/environment_sampling.h"
#include "reference/fiber_reference.h"
#include "reference/fiber_trace.h"
#include "scene/camera.h"
#include "scene/default_scene.h"
#include "scene/fabric.h"
#include "scene/lighting.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_preset.h"

namespace ft {
namespace {

constexpr double kPi = std::numbers::pi;
using glm::dvec3;

double radians(double degrees) { return degrees * kPi / 180.0; }

// Composite Simpson on [a, b] with n (even) intervals.
template <class F>
double simpson(F&& f, double a, double b, int n) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return s * h / 3.0;
}

// ---- Hand-built fibers ---------------------------------------------------

struct Strip {
  std::vector<glm::vec3> points;
  float radius = 0.1f;
  uint32_t fiber = 0;                 // strips with the same fiber are one fiber (its segments)
  uint32_t type = FT_FIBER_MIGRATION;
  std::vector<uint32_t> periods;      // per vertex; empty: all 0
  int segment = -1;                   // global yarn segment; -1: the strip's index
};

// One yarn segment per strip, one ply without regular fibers: each decision
// holds exactly one strip (the cut of gpu/fiber_gpu.cpp drawVertices).
FiberGeometry makeGeometry(const std::vector<Strip>& strips) {
  FiberGeometry g;
  for (uint32_t s = 0; s < strips.size(); ++s) {
    const Strip& st = strips[s];
    SegmentDecision d{};
    d.subdivisions = static_cast<uint32_t>(st.points.size()) - 1;
    d.coreLines = d.subdivisions;  // the one strip is slot 0
    d.vertexCount = static_cast<uint32_t>(st.points.size());
    const uint32_t segment = st.segment < 0 ? s : static_cast<uint32_t>(st.segment);
    g.segments.push_back(segment);
    g.decisions.push_back(d);
    for (uint32_t v = 0; v < st.points.size(); ++v) {
      const uint32_t period = st.periods.empty() ? 0u : st.periods[v];
      FiberVertex fv{};
      fv.position = glm::vec4(st.points[v], st.radius);
      fv.id = glm::uvec4(0u, segment, st.fiber, st.type | (v << 8) | (period << 16));
      g.vertices.push_back(fv);
    }
  }
  return g;
}

YarnParams onePly() {
  YarnParams p{};
  p.plyCount = 1;
  return p;
}

// A straight fiber from a to b in lines of at most 8 radii, cut into strips
// (yarn segments) of 32 lines: Embree's float cone test loses accuracy on
// lines much longer than their radius (2000 radii: normals off by 1.5%).
std::vector<Strip> fiberLine(glm::vec3 a, glm::vec3 b, float radius, uint32_t fiber) {
  const int lines = std::max(1, static_cast<int>(std::ceil(glm::length(b - a) / (8.0f * radius))));
  std::vector<Strip> strips;
  for (int first = 0; first < lines; first += 32) {
    Strip s;
    s.radius = radius;
    s.fiber = fiber;
    for (int i = first; i <= std::min(first + 32, lines); ++i) s.points.push_back(glm::mix(a, b, float(i) / lines));
    strips.push_back(s);
  }
  return strips;
}

// A straight fiber through `c` along `dir`, 800 radii long.
std::vector<Strip> straight(glm::vec3 c, glm::vec3 dir, float radius, uint32_t fiber) {
  return fiberLine(c - 400.0f * radius * dir, c + 400.0f * radius * dir, radius, fiber);
}

std::vector<Strip> operator+(std::vector<Strip> a, const std::vector<Strip>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Looking down −z at `target` from `distance`, `viewHeight` world units tall
// at the target: nearly orthographic.
Camera farCamera(glm::vec3 target, float distance, float viewHeight, int width, int height) {
  Camera c;
  c.target = target;
  c.eye = target + glm::vec3(0.0f, 0.0f, distance);
  c.up = {0.0f, 1.0f, 0.0f};
  c.fovyDegrees = static_cast<float>(2.0 * std::atan(0.5 * viewHeight / distance) * 180.0 / kPi);
  c.width = width;
  c.height = height;
  c.zNear = 0.5f * distance;
  c.zFar = 2.0f * distance;
  return c;
}

// ---- The test's own pinhole camera and cylinders --------------------------

struct Ray {
  dvec3 o, d;
};

// Through (px, py) of the image, row 0 at the top: lookAt + perspective by hand.
Ray pixelRay(const Camera& c, double px, double py) {
  const dvec3 eye(c.eye), fwd = glm::normalize(dvec3(c.target) - eye);
  const dvec3 right = glm::normalize(glm::cross(fwd, dvec3(c.up))), up = glm::cross(right, fwd);
  const double ty = std::tan(radians(c.fovyDegrees) / 2.0), tx = ty * c.width / c.height;
  const double nx = 2.0 * px / c.width - 1.0, ny = 1.0 - 2.0 * py / c.height;
  return {eye, glm::normalize(fwd + nx * tx * right + ny * ty * up)};
}

struct Cylinder {
  dvec3 a;  // a point of the axis
  dvec3 u;  // unit axis
  double r;
};

std::optional<double> hit(const Ray& ray, const Cylinder& c) {
  const dvec3 oc = ray.o - c.a;
  const dvec3 dp = ray.d - glm::dot(ray.d, c.u) * c.u, op = oc - glm::dot(oc, c.u) * c.u;
  const double A = glm::dot(dp, dp), B = 2.0 * glm::dot(op, dp), C = glm::dot(op, op) - c.r * c.r;
  const double disc = B * B - 4.0 * A * C;
  if (disc < 0.0 || A == 0.0) return std::nullopt;
  const double t = (-B - std::sqrt(disc)) / (2.0 * A);
  if (t <= 0.0) return std::nullopt;
  return t;
}

dvec3 normalAt(const Cylinder& c, dvec3 p) {
  const dvec3 q = p - c.a;
  return glm::normalize(q - glm::dot(q, c.u) * c.u);
}

// ---- 000 §4.3 eq. 6 from scratch ----------------------------------------

struct Fabric {
  double cR[3], cTT[3];
  double betaR, betaTT, kappa;  // radians; κ = γ_TT^−2
};

Fabric fabricOf(const FabricPreset& p) {
  const double gamma = radians(p.gammaTTDegrees);
  return {{p.colorR[0], p.colorR[1], p.colorR[2]},
          {p.colorTT[0], p.colorTT[1], p.colorTT[2]},
          radians(p.betaRDegrees),
          radians(p.betaTTDegrees),
          1.0 / (gamma * gamma)};
}

FabricParams paramsOf(const Fabric& f) {
  FabricParams p{};
  p.colorR = glm::vec4(f.cR[0], f.cR[1], f.cR[2], f.betaR);
  p.colorTT = glm::vec4(f.cTT[0], f.cTT[1], f.cTT[2], f.betaTT);
  p.lobes = glm::vec4(1.0 / std::sqrt(f.kappa), f.kappa, 0.0, 0.0);
  return p;
}

double gauss(double x, double beta) { return std::exp(-0.5 * x * x / (beta * beta)) / (std::sqrt(2.0 * kPi) * beta); }

// Z(θ_i) = ∫_{−π/2}^{π/2} g(θ + θ_i; β) cos²θ dθ (the lobe is negligible beyond 10β).
double normZ(double thetaI, double beta) {
  const double lo = std::max(-kPi / 2, -thetaI - 10 * beta), hi = std::min(kPi / 2, -thetaI + 10 * beta);
  if (hi <= lo) return 0.0;
  return simpson([&](double t) { return gauss(t + thetaI, beta) * std::cos(t) * std::cos(t); }, lo, hi, 400);
}

double fresnel(double cR, double thetaI) { return cR + (1.0 - cR) * std::pow(1.0 - std::abs(std::cos(thetaI)), 5.0); }

double vonMisesTT(double phi, double kappa) {
  return std::exp(kappa * std::cos(phi - kPi)) / (2.0 * kPi * std::cyl_bessel_i(0.0, kappa));
}

double bcsdf(const Fabric& f, int ch, double thetaI, double thetaO, double phi) {
  const double F = fresnel(f.cR[ch], thetaI);
  const double mR = gauss(thetaO + thetaI, f.betaR) / normZ(thetaI, f.betaR);
  const double mTT = gauss(thetaO + thetaI, f.betaTT) / normZ(thetaI, f.betaTT);
  return F * mR / (2.0 * kPi) + (1.0 - F) * f.cTT[ch] * mTT * vonMisesTT(phi, f.kappa);
}

struct Angles {
  double thetaI, thetaO, phi;
};

Angles anglesOf(dvec3 t, dvec3 wi, dvec3 wo) {
  const double si = glm::dot(wi, t), so = glm::dot(wo, t);
  const dvec3 pi = wi - si * t, po = wo - so * t;
  return {std::asin(si), std::asin(so),
          std::acos(std::clamp(glm::dot(pi, po) / std::sqrt(glm::dot(pi, pi) * glm::dot(po, po)), -1.0, 1.0))};
}

// The single-scattering furnace of one fiber, L_amb ∫ f cos θ_i dω_i with
// dω = cos θ dθ dφ (000 eq. 8–10 with the F and C_TT of the TSV):
//   A(θ_o) = ∫ [F M_R ∫N_R dφ + (1 − F) C_TT M_TT ∫N_TT dφ] cos²θ_i dθ_i.
// The Z of every θ_i node is tabulated once per fabric.
class FurnaceIntegral {
 public:
  FurnaceIntegral(const Fabric& f, int channel) : f_(f), ch_(channel) {
    for (int i = 0; i <= kNodes; ++i) {
      const double t = node(i);
      zR_[i] = normZ(t, f.betaR);
      zTT_[i] = normZ(t, f.betaTT);
    }
    nTT_ = simpson([&](double phi) { return vonMisesTT(phi, f.kappa); }, 0.0, 2.0 * kPi, 2000);
  }
  double operator()(double thetaO) const {
    double s = 0.0;
    for (int i = 0; i <= kNodes; ++i) {
      const double t = node(i), F = fresnel(f_.cR[ch_], t), c2 = std::cos(t) * std::cos(t);
      const double r = zR_[i] > 0 ? gauss(thetaO + t, f_.betaR) / zR_[i] : 0.0;
      const double tt = zTT_[i] > 0 ? gauss(thetaO + t, f_.betaTT) / zTT_[i] : 0.0;
      s += (i == 0 || i == kNodes ? 1.0 : i % 2 ? 4.0 : 2.0) * (F * r + (1.0 - F) * f_.cTT[ch_] * tt * nTT_) * c2;
    }
    return s * (kPi / kNodes) / 3.0;
  }

 private:
  static constexpr int kNodes = 20000;  // h = 1.6e-4 rad: 0.009 of a 1° lobe
  static double node(int i) { return -kPi / 2 + kPi * i / kNodes; }
  Fabric f_;
  int ch_;
  std::array<double, kNodes + 1> zR_{}, zTT_{};
  double nTT_ = 0.0;
};

ShadingParams shading(const FabricParams& fabric) {
  ShadingParams s{};
  s.fabric = fabric;
  s.flags = glm::uvec4(0u, FT_SHADING_KHUNGURN, 0u, 0u);
  return s;
}

std::vector<glm::vec3> constantTable(glm::vec3 v) { return std::vector<glm::vec3>(FT_AMBIENT_TABLE_SIZE, v); }

// ---- Geometry -------------------------------------------------------------

// One straight fiber of radius r along x, 0.5 above the view's centre,
// starting at x = 0: each column right of the start covers the silhouette
// of an infinite cylinder, whose edges are the tangent planes through the
// eye that contain the x direction. In the y–z plane: the tangents from the
// eye to a circle of radius r at distance d, at angles atan(y0/D) ± asin(r/d).
TEST(FiberTrace, CoverageIsTheTubeSilhouette) {
  const float r = 0.2f, y0 = 0.5f, distance = 100.0f;
  const int size = 48;
  const Camera cam = farCamera({0, 0, 0}, distance, 3.5f, size, size);
  const FiberTraceScene scene(makeGeometry(fiberLine({0, y0, 0}, {80, y0, 0}, r, 0)), onePly());
  ASSERT_EQ(scene.segmentCount(), 50u);
  TraceOptions o;
  o.samplesPerPixel = 256;
  const TraceResult res = traceFibers(scene, cam, shading(paramsOf(fabricOf(findFabricPreset("cotton")))),
                                      constantTable(glm::vec3(0.5f)), o);
  EXPECT_EQ(res.stats.nonFinite, 0u);

  const double pixelsPerTan = size / (2.0 * std::tan(radians(cam.fovyDegrees) / 2.0));
  const double d = std::hypot(double(y0), double(distance));
  const double centre = std::atan(y0 / distance), half = std::asin(r / d);
  const double top = size / 2.0 - std::tan(centre + half) * pixelsPerTan;     // rows grow downwards
  const double bottom = size / 2.0 - std::tan(centre - half) * pixelsPerTan;
  ASSERT_GT(top, 1.0);
  ASSERT_LT(bottom, size / 2.0);  // above the centre: row 0 is the top
  // Columns clear of the round cap at x = 0 (r = 2.75 px).
  const double capPixels = r / (distance * std::tan(radians(cam.fovyDegrees) / 2.0)) * size / 2.0;
  for (int x = 0; x < size; ++x) {
    double column = 0.0;
    for (int y = 0; y < size; ++y) {
      const float a = res.image.at(x, y)[3];
      column += a;
      if (x < size / 2 - capPixels - 1) {
        EXPECT_EQ(a, 0.0f) << x << "," << y;  // left of the start
      } else if (x > size / 2 + capPixels + 1) {
        // 16×16 strata: an edge pixel is off by at most one stratum row (1/16).
        const double expected = std::clamp(std::min(y + 1.0, bottom) - std::max(double(y), top), 0.0, 1.0);
        if (expected == 0.0 || expected == 1.0) {
          EXPECT_EQ(a, expected) << x << "," << y;
        } else {
          EXPECT_NEAR(a, expected, 1.0 / 16 + 1e-6) << x << "," << y;
        }
      }
    }
    if (x > size / 2 + capPixels + 1) {
      EXPECT_NEAR(column, bottom - top, 2.0 / 16) << x;
    }
  }
}

// fiber_strip.geom.glsl: no line across a hair's period change (the hair's
// free end); a migration fiber's period change is drawn.
TEST(FiberTrace, HairFreeEndsAreNotJoined) {
  const std::vector<glm::vec3> row = {{-1.5f, 0, 0}, {-1.0f, 0, 0}, {-0.5f, 0, 0}, {0.5f, 0, 0}, {1.0f, 0, 0}};
  const std::vector<uint32_t> periods = {0, 0, 0, 1, 1};
  auto at = [&](float y) {
    std::vector<glm::vec3> p = row;
    for (glm::vec3& v : p) v.y = y;
    return p;
  };
  const FiberGeometry g = makeGeometry({{at(0.5f), 0.1f, 0, FT_FIBER_HAIR, periods},
                                        {at(-0.5f), 0.1f, 1, FT_FIBER_MIGRATION, periods}});
  const FiberTraceScene scene(g, onePly());
  EXPECT_EQ(scene.segmentCount(), 3u + 4u);
  const Camera cam = farCamera({0, 0, 0}, 100.0f, 2.0f, 40, 40);  // 20 px per unit
  TraceOptions o;
  o.samplesPerPixel = 16;
  const TraceResult res = traceFibers(scene, cam, shading(paramsOf(fabricOf(findFabricPreset("silk")))),
                                      constantTable(glm::vec3(0.5f)), o);
  // Row 10 is y = +0.5 (hair), row 30 is y = −0.5; the gap is x ∈ (−0.4, 0.4): columns 12..27.
  for (int x = 13; x <= 26; ++x) {
    EXPECT_EQ(res.image.at(x, 9)[3], 0.0f) << x;
    EXPECT_EQ(res.image.at(x, 10)[3], 0.0f) << x;
    EXPECT_EQ(res.image.at(x, 29)[3], 1.0f) << x;
    EXPECT_EQ(res.image.at(x, 30)[3], 1.0f) << x;
  }
  EXPECT_EQ(res.image.at(5, 10)[3], 1.0f);  // the hair itself is drawn
  EXPECT_EQ(res.image.at(33, 10)[3], 1.0f);
}

// The tangent rule of fiber_strip_tangent.glsl on a circle: the central
// difference p₊₁ − p₋₁ is parallel to the exact tangent; at a strip's ends
// the one-sided −3p₀ + 4p₁ − p₂ = R(4cosΔ − cos2Δ − 3, 4sinΔ − sin2Δ) is off
// by atan((4cosΔ − cos2Δ − 3)/(4sinΔ − sin2Δ)) = 0.0065 rad at Δ = 0.3
// (the first-order p₁ − p₀ would be off by Δ/2 = 0.15); a hair's free end
// cuts the strip into two such pieces.
TEST(FiberTrace, StripTangentsFollowTheGpuRule) {
  const double delta = 0.3, radius = 2.0;
  Strip s;
  s.type = FT_FIBER_HAIR;
  for (int k = 0; k < 8; ++k) {
    s.points.emplace_back(radius * std::cos(k * delta), radius * std::sin(k * delta), 0.0);
    s.periods.push_back(k < 4 ? 0u : 1u);
  }
  const FiberGeometry g = makeGeometry({s});
  const std::vector<glm::vec3> t = fiberStripTangents(g.vertices);
  const double endError = std::atan(std::abs(4 * std::cos(delta) - std::cos(2 * delta) - 3) /
                                    (4 * std::sin(delta) - std::sin(2 * delta)));
  for (int k = 0; k < 8; ++k) {
    const dvec3 exact(-std::sin(k * delta), std::cos(k * delta), 0.0);
    const double angle = std::atan2(glm::length(glm::cross(dvec3(t[k]), exact)), glm::dot(dvec3(t[k]), exact));
    const bool end = k == 0 || k == 3 || k == 4 || k == 7;  // the pieces are vertices 0..3 and 4..7
    if (end)
      EXPECT_NEAR(angle, endError, 1e-4) << k;
    else
      EXPECT_LT(angle, 1e-5) << k;
  }
}

// ---- Shading --------------------------------------------------------------

// A wide straight fiber (radius 50, seen from 1000 over 1.7 units) along x,
// one light, no shadows: each pixel is the mean over its footprint of
//   E [f cos θ_i + (k_d/π) max(0, n·ω_i)] + L_amb [A(θ_o) + k_d],
// f from eq. 6 above, n the cylinder's normal, and A read from a table that
// is linear in the texel index, so the lookup (texel centres at
// −π/2 + (k + ½)π/N, clamped) gives A(θ_o) = a + b·u exactly,
// u = (θ_o + π/2)/π·N − ½.
TEST(FiberTrace, DirectShadingMatchesEquation6) {
  const Camera cam = farCamera({0, 0, 0}, 1000.0f, 1.75f, 5, 5);
  const Cylinder cyl{{0, 0, 0}, {1, 0, 0}, 50.0};
  const FiberTraceScene scene(makeGeometry(straight({0, 0, 0}, {1, 0, 0}, 50.0f, 0)), onePly());
  const glm::dvec3 base(0.2, 0.5, 1.0), slope(0.01, 0.002, -0.005);
  std::vector<glm::vec3> table;
  for (int k = 0; k < FT_AMBIENT_TABLE_SIZE; ++k) table.emplace_back(base + slope * double(k));
  const double E[3] = {2.0, 1.5, 1.0}, kd[3] = {0.1, 0.2, 0.3}, Lamb[3] = {0.3, 0.2, 0.1};
  // Lights by (θ_i, φ) about t = x with φ measured from ω_o ≈ +z: in the R
  // lobe, at its flank, across TT, and to the side.
  const double lights[][2] = {{0.5, 40}, {-1.5, 10}, {-25, 160}, {10, 90}};
  for (const char* name : {"cotton", "silk"}) {
    const Fabric fabric = fabricOf(findFabricPreset(name));
    for (const auto& l : lights) {
      const double ti = radians(l[0]), ph = radians(l[1]);
      const dvec3 wi(std::sin(ti), -std::cos(ti) * std::sin(ph), std::cos(ti) * std::cos(ph));
      ShadingParams s = shading(paramsOf(fabric));
      s.flags.x = 1;
      s.lightDirection[0] = glm::vec4(glm::vec3(wi), 0.0f);
      s.lightIrradiance[0] = glm::vec4(E[0], E[1], E[2], 0.0f);
      s.diffuse = glm::vec4(kd[0], kd[1], kd[2], 0.0f);
      s.ambient = glm::vec4(Lamb[0], Lamb[1], Lamb[2], 0.0f);
      TraceOptions o;
      o.samplesPerPixel = 64;
      o.shadows = false;
      const TraceResult res = traceFibers(scene, cam, s, table, o);
      ASSERT_EQ(res.stats.nonFinite, 0u);
      // The centre pixel's footprint on 8×8 sub-pixel rays.
      double expected[3] = {0, 0, 0};
      for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
          const Ray ray = pixelRay(cam, 2 + (i + 0.5) / 8, 2 + (j + 0.5) / 8);
          const double tHit = hit(ray, cyl).value();
          const dvec3 n = normalAt(cyl, ray.o + tHit * ray.d), wo = -ray.d;
          const Angles a = anglesOf(cyl.u, wi, wo);
          const double u = std::clamp((a.thetaO + kPi / 2) / kPi * FT_AMBIENT_TABLE_SIZE - 0.5, 0.0,
                                      FT_AMBIENT_TABLE_SIZE - 1.0);
          for (int c = 0; c < 3; ++c) {
            const double f = bcsdf(fabric, c, a.thetaI, a.thetaO, a.phi);
            // The energy-conserving mix: the BCSDF carries 1 − k_d, the Lambertian lobe k_d.
            expected[c] += (E[c] * ((1.0 - kd[c]) * f * std::cos(a.thetaI) +
                                    kd[c] / kPi * std::max(0.0, glm::dot(n, wi))) +
                            Lamb[c] * ((1.0 - kd[c]) * (base[c] + slope[c] * u) + kd[c])) / 64.0;
          }
        }
      const float* px = res.image.at(2, 2);
      EXPECT_EQ(px[3], 1.0f);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(px[c], expected[c], 1e-3 * expected[c] + 1e-5)
            << name << " θ_i " << l[0] << "° φ " << l[1] << "° channel " << c;
    }
  }
}

// ---- Shadows --------------------------------------------------------------

// The shadow tests' scene: two parallel fibers along x, the lower (radius 1)
// at the origin, the upper (radius 0.15) at y = 2.5, z = 0.6; and their
// shading: black BCSDF (F = 0 at θ_i = 0), k_d = 1, one light of irradiance 1
// straight above (+y), so L = V max(0, n·ω_i)/π.
const Cylinder kLowerFiber{{0, 0, 0}, {1, 0, 0}, 1.0}, kUpperFiber{{0, 2.5, 0.6}, {1, 0, 0}, 0.15};
FiberTraceScene twoFiberScene() {
  return FiberTraceScene(
      makeGeometry(straight({0, 0, 0}, {1, 0, 0}, 1.0f, 0) + straight({0, 2.5f, 0.6f}, {1, 0, 0}, 0.15f, 1)), onePly());
}
// The points of the lower fiber seen through the 8 × 8 sub-rays of pixel
// (2, y) (those the upper fiber hides, or that miss, are left out).
std::vector<dvec3> lowerFootprint(const Camera& cam, int y) {
  std::vector<dvec3> points;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const Ray ray = pixelRay(cam, 2 + (i + 0.5) / 8, y + (j + 0.5) / 8);
      const std::optional<double> tl = hit(ray, kLowerFiber), tu = hit(ray, kUpperFiber);
      if (tl && !(tu && *tu < *tl)) points.push_back(ray.o + *tl * ray.d);
    }
  return points;
}
ShadingParams diffuseLightAbove() {
  Fabric black{{0, 0, 0}, {0, 0, 0}, radians(5), radians(10), 4.0};
  ShadingParams s = shading(paramsOf(black));
  s.flags.x = 1;
  s.lightDirection[0] = glm::vec4(0, 1, 0, 0);
  s.lightIrradiance[0] = glm::vec4(1, 1, 1, 0);
  s.diffuse = glm::vec4(1, 1, 1, 0);
  return s;
}

// Light straight above (+y) two parallel fibers along x: the lower one
// (radius 1 at the origin) is seen from +z; its visible point at height y is
// z = √(1 − y²), lit for y > 0 and shadowed where the vertical through it
// meets the upper fiber (radius 0.15 at y = 2.5, z = 0.6): |z − 0.6| < 0.15,
// i.e. y ∈ (0.661, 0.893). f vanishes there (C_R = C_TT = 0 and θ_i = 0 give
// F = 0), so L = V max(0, n·ω_i)/π with k_d = 1 and E = 1.
TEST(FiberTrace, ShadowsFallWhereTheUpperFiberBlocksTheLight) {
  const Cylinder &lower = kLowerFiber, &upper = kUpperFiber;
  const FiberTraceScene scene = twoFiberScene();
  const Camera cam = farCamera({0, 0.75f, 0}, 50.0f, 5.0f, 4, 200);  // 0.025 units per pixel at the target
  const ShadingParams s = diffuseLightAbove();
  TraceOptions o;
  o.samplesPerPixel = 64;
  const TraceResult res = traceFibers(scene, cam, s, constantTable(glm::vec3(0.0f)), o);
  ASSERT_EQ(res.stats.nonFinite, 0u);
  int shadowRows = 0, litRows = 0;
  for (int y = 0; y < cam.height; ++y) {
    // Classify the footprint of the column-2 pixel on 8×8 sub-rays.
    int onLower = 0, shadowed = 0, facing = 0;
    double expected = 0.0;
    for (const dvec3& p : lowerFootprint(cam, y)) {
      ++onLower;
      const bool blocked = hit({p, {0, 1, 0}}, upper).has_value();
      shadowed += blocked;
      facing += normalAt(lower, p).y > 0.0;
      if (!blocked) expected += std::max(0.0, normalAt(lower, p).y) / kPi / 64.0;
    }
    // Only footprints on the lower fiber with n·ω_i of one sign: elsewhere the
    // kink of max(0, n·ω_i) or an edge makes 64 jittered samples and 64
    // midpoints differ by more than the tolerance.
    if (onLower < 64 || (facing > 0 && facing < 64)) continue;
    const float v = res.image.at(2, y)[1];
    if (shadowed == 64) {
      ++shadowRows;
      EXPECT_EQ(v, 0.0f) << "row " << y << " is in the shadow";
    } else if (shadowed == 0) {
      if (expected > 0.0) ++litRows;
      EXPECT_NEAR(v, expected, 2e-3 * expected + 1e-5) << "row " << y;  // no self-shadowing
    }
  }
  EXPECT_GE(shadowRows, 8);  // (0.893 − 0.661)/0.025 = 9.3 rows
  EXPECT_GE(litRows, 10);
}

// The same two fibers under a cone light (TraceOptions::lightAngularRadius
// α = 0.05 rad about +y): at the lower fiber's visible point p the expected
// visibility is the fraction of the cone (uniform in solid angle) whose rays
// from p miss the upper fiber, by the test's own quadrature (midpoint rule,
// 96 × 192 cells in (cos θ, ψ), against the test's cylinder) tabulated over
// the height of p; the pixel's expectation averages V max(0, n·y)/π over an
// 8 × 8 footprint. One shadow ray per camera sample: the trace's value is a
// binomial estimate, within 5σ (σ from the expected V and 4096 samples:
// 0.6 % of the shade at V = ½) plus the footprint-midpoint and quadrature
// slack. The upper fiber subtends ±asin(0.15/d) ≈ ±5° > α from the lit rows:
// an umbra (exactly 0) between two penumbrae of ~2αd ≈ 0.17 units (~5 rows
// each at 0.025 units per pixel with 0.05 < V < 0.95). Directions drawn uniform in θ instead of
// in cos θ (the cone's centre over-weighted) miss by ~0.08 V mid-penumbra.
TEST(FiberTrace, ConeLightPenumbraIsTheVisibleFractionOfTheCone) {
  const Cylinder &lower = kLowerFiber, &upper = kUpperFiber;
  const FiberTraceScene scene = twoFiberScene();
  const Camera cam = farCamera({0, 0.75f, 0}, 50.0f, 5.0f, 4, 200);
  const ShadingParams s = diffuseLightAbove();
  const double alpha = 0.05;
  TraceOptions o;
  o.samplesPerPixel = 4096;
  o.lightAngularRadius = alpha;
  const TraceResult res = traceFibers(scene, cam, s, constantTable(glm::vec3(0.0f)), o);
  ASSERT_EQ(res.stats.nonFinite, 0u);
  // V(y) at p = (0, y, √(1 − y²)), y ∈ [0, 1], on 1001 heights.
  const int nCos = 96, nPsi = 192, nY = 1001;
  std::vector<double> table(nY);
  for (int k = 0; k < nY; ++k) {
    const double y = double(k) / (nY - 1);
    const dvec3 p(0.0, y, std::sqrt(std::max(0.0, 1.0 - y * y)));
    int visible = 0;
    for (int a = 0; a < nCos; ++a) {
      const double c = 1.0 - (a + 0.5) / nCos * (1.0 - std::cos(alpha)), sn = std::sqrt(1.0 - c * c);
      for (int b = 0; b < nPsi; ++b) {
        const double psi = 2.0 * kPi * (b + 0.5) / nPsi;
        visible += !hit({p, {sn * std::cos(psi), c, sn * std::sin(psi)}}, upper).has_value();
      }
    }
    table[k] = double(visible) / (nCos * nPsi);
  }
  const auto visibility = [&](double y) {
    const double f = std::clamp(y, 0.0, 1.0) * (nY - 1);
    const int k = std::min(int(f), nY - 2);
    return table[k] + (f - k) * (table[k + 1] - table[k]);
  };
  int penumbraRows = 0, umbraRows = 0, litRows = 0;
  for (int y = 0; y < cam.height; ++y) {
    int onLower = 0, facing = 0, umbra = 0;
    double expected = 0.0, vMean = 0.0, shadeMax = 0.0;
    for (const dvec3& p : lowerFootprint(cam, y)) {
      ++onLower;
      const double shade = std::max(0.0, normalAt(lower, p).y) / kPi;
      const double v = visibility(p.y);
      facing += normalAt(lower, p).y > 0.0;
      umbra += v == 0.0;
      expected += shade * v / 64.0;
      vMean += v / 64.0;
      shadeMax = std::max(shadeMax, shade);
    }
    if (onLower < 64 || (facing > 0 && facing < 64)) continue;
    const float got = res.image.at(2, y)[1];
    if (umbra == 64) {
      ++umbraRows;
      EXPECT_EQ(got, 0.0f) << "row " << y << " is in the umbra";
      continue;
    }
    const double sigma = shadeMax * std::sqrt(vMean * (1.0 - vMean) / o.samplesPerPixel);
    EXPECT_NEAR(got, expected, 5.0 * sigma + 4e-3 * expected + 1e-5) << "row " << y << ", V " << vMean;
    if (vMean > 0.05 && vMean < 0.95) ++penumbraRows;
    if (vMean == 1.0 && expected > 0.0) ++litRows;
  }
  EXPECT_GE(penumbraRows, 8);  // 10 with 0.05 < V < 0.95 (both edges)
  EXPECT_GE(umbraRows, 2);     // 3 whose whole footprint is in the umbra
  EXPECT_GE(litRows, 10);
}

// traceFibers refuses a cone wider than 60° or negative.
TEST(FiberTrace, RejectsABadLightAngularRadius) {
  const FiberTraceScene scene(makeGeometry(straight({0, 0, 0}, {1, 0, 0}, 1.0f, 0)), onePly());
  const Camera cam = farCamera({0, 0, 0}, 50.0f, 5.0f, 4, 4);
  ShadingParams s = shading(paramsOf(Fabric{{0, 0, 0}, {0, 0, 0}, radians(5), radians(10), 4.0}));
  for (double bad : {-0.1, 1.1, std::nan("")}) {
    TraceOptions o;
    o.lightAngularRadius = bad;
    EXPECT_THROW(traceFibers(scene, cam, s, constantTable(glm::vec3(0.0f)), o), std::invalid_argument) << bad;
  }
}

// A curved fiber (a circular arc over three yarn segments) never shadows
// itself: with the light behind it (only TT reaches the eye) or below it,
// shadow rays cross the fiber's own tube and its neighbouring segments, and
// the image must not change when shadows are switched on. Also when the
// segment numbers jump between the last two strips, as at a closed curve's
// seam.
TEST(FiberTrace, AFiberDoesNotShadowItself) {
  for (const int lastSegment : {2, 9}) {
    for (const glm::vec3 light : {glm::vec3(0.3f, 0.2f, -1.0f), glm::vec3(0.1f, -1.0f, 0.2f)}) {
      std::vector<Strip> strips;
      for (int seg = 0; seg < 3; ++seg) {
        Strip st;
        st.radius = 0.3f;
        st.fiber = 7;
        st.segment = seg == 2 ? lastSegment : seg;
        for (int v = 0; v <= 5; ++v) {
          const double a = 0.4 * (seg * 5 + v) / 5.0 - 0.6;
          st.points.emplace_back(3.0 * std::sin(a), 3.0 * std::cos(a) - 3.0, 0.0);
        }
        strips.push_back(st);
      }
      const FiberTraceScene scene(makeGeometry(strips), onePly());
      EXPECT_EQ(scene.fiberCount(), 1u);
      const Camera cam = farCamera({0, -0.3f, 0}, 200.0f, 2.0f, 48, 24);
      ShadingParams s = shading(findFabricPreset("cotton").params());
      s.flags.x = 1;
      s.lightDirection[0] = glm::vec4(glm::normalize(light), 0.0f);
      s.lightIrradiance[0] = glm::vec4(1, 1, 1, 0);
      s.diffuse = glm::vec4(0.2f, 0.2f, 0.2f, 0.0f);
      TraceOptions o;
      o.samplesPerPixel = 4;
      o.shadows = false;
      const TraceResult unshadowed = traceFibers(scene, cam, s, constantTable(glm::vec3(0.0f)), o);
      o.shadows = true;
      const TraceResult shadowed = traceFibers(scene, cam, s, constantTable(glm::vec3(0.0f)), o);
      EXPECT_GT(shadowed.stats.shadowRays, 0u);
      EXPECT_EQ(shadowed.image.pixels, unshadowed.image.pixels);
      float brightest = 0.0f;
      for (size_t i = 0; i < shadowed.image.pixelCount(); ++i)
        brightest = std::max(brightest, shadowed.image.pixels[4 * i]);
      EXPECT_GT(brightest, 0.0f);  // light reaches the eye: the images compared are not black
    }
  }
}

// The same fiber further along its yarn is an occluder like any other: a
// hairpin of radius 0.2 whose upper arm (yarn segments 3–4, 2 above) lies in
// the light's way to the lower arm (segments 0–1). Diffuse only (C_R = C_TT =
// 0, θ_i = 0: f = 0), E = k_d = 1: the lower arm's top is 1/π unshadowed.
TEST(FiberTrace, TheSameFiberFurtherAlongItsYarnCastsShadows) {
  std::vector<Strip> strips;
  auto arm = [&](float y, float x0, float x1) {
    Strip st;
    st.radius = 0.2f;
    st.fiber = 3;
    for (int v = 0; v <= 4; ++v) st.points.emplace_back(x0 + (x1 - x0) * v / 4.0f, y, 0.0f);
    strips.push_back(st);
  };
  arm(0.0f, -2.0f, -1.0f);
  arm(0.0f, -1.0f, 0.0f);
  Strip bend;  // segment 2: a half circle from (0, 0) up to (0, 2)
  bend.radius = 0.2f;
  bend.fiber = 3;
  for (int v = 0; v <= 8; ++v) {
    const double a = kPi * v / 8.0 - kPi / 2;
    bend.points.emplace_back(std::cos(a), 1.0 + std::sin(a), 0.0);
  }
  strips.push_back(bend);
  arm(2.0f, 0.0f, -1.0f);
  arm(2.0f, -1.0f, -2.0f);
  const FiberTraceScene scene(makeGeometry(strips), onePly());
  EXPECT_EQ(scene.fiberCount(), 1u);
  const Camera cam = farCamera({-1.5f, 1.0f, 0}, 100.0f, 4.0f, 32, 32);  // 8 px per unit
  const ShadingParams s = diffuseLightAbove();
  TraceOptions o;
  o.samplesPerPixel = 16;
  for (const bool shadows : {false, true}) {
    o.shadows = shadows;
    const TraceResult res = traceFibers(scene, cam, s, constantTable(glm::vec3(0.0f)), o);
    // Pixel (14, 23): x ∈ [−1.75, −1.625], y ∈ [0, 0.125], the lit top of
    // the lower arm (n·ω_i = y/0.2 ∈ [0, 0.6]) under the upper arm.
    const float v = res.image.at(14, 23)[1];
    EXPECT_EQ(res.image.at(14, 23)[3], 1.0f);
    if (shadows)
      EXPECT_EQ(v, 0.0f);
    else
      EXPECT_GT(v, 0.05f);
  }
}

// ---- The sampler ------------------------------------------------------------

// FiberScatter's density integrates to 1 over the sphere (∫∫ p cos θ dθ dφ),
// and its samples land in (θ_i, φ) cells as often as the density says.
TEST(FiberTrace, ScatterSamplesFollowTheirDensity) {
  struct Config {
    const char* fabric;
    double thetaO;  // ω_o's angle to the normal plane of t
    float kd;
    bool simple;
  };
  const Config configs[] = {{"cotton", 0.4, 0.3f, false}, {"silk", -1.2, 0.0f, false}, {"fleece", 1.5, 0.1f, false},
                            {"cotton", 0.2, 0.2f, true}};
  const glm::vec3 t(0, 0, 1), u(1, 0, 0), w = glm::cross(t, u);  // φ = 0 along u
  for (const Config& c : configs) {
    ShadingParams s = shading(findFabricPreset(c.fabric).params());
    s.diffuse = glm::vec4(c.kd, c.kd, c.kd, 0);
    if (c.simple) s.flags.y = FT_SHADING_SIMPLE, s.simple = glm::vec4(0.5f, radians(5), 0, 0);
    const glm::vec3 wo = float(std::sin(c.thetaO)) * t + float(std::cos(c.thetaO)) * u;
    const glm::vec3 n = glm::normalize(wo + glm::vec3(0, 0.3f, 0) - glm::dot(wo, t) * t);
    const FiberScatter scatter(s, t, n, wo);
    ASSERT_TRUE(scatter.scatters());
    auto dir = [&](double th, double ph) {
      return glm::vec3(float(std::sin(th)) * t + float(std::cos(th) * std::cos(ph)) * u +
                       float(std::cos(th) * std::sin(ph)) * w);
    };
    // θ cells with edges at −θ_o ± k·β/2 of each lobe, so narrow lobes are resolved.
    const FabricParams& f = s.fabric;
    std::vector<double> edges = {-kPi / 2, kPi / 2};
    for (double beta : {double(f.colorR.w), double(f.colorTT.w), c.simple ? 2 * radians(5) : 0.0})
      for (int k = -6; beta > 0 && k <= 6; ++k)
        if (const double e = -c.thetaO + k * beta / 2; std::abs(e) < kPi / 2) edges.push_back(e);
    std::sort(edges.begin(), edges.end());
    constexpr int kPhiCells = 8;
    std::vector<double> mass((edges.size() - 1) * kPhiCells);
    double total = 0.0;
    for (size_t i = 0; i + 1 < edges.size(); ++i)
      for (int j = 0; j < kPhiCells; ++j) {
        const double p0 = 2 * kPi * j / kPhiCells, p1 = 2 * kPi * (j + 1) / kPhiCells;
        mass[i * kPhiCells + j] = simpson(
            [&](double th) {
              return simpson([&](double ph) { return scatter.angularDensity(dir(th, ph)); }, p0, p1, 64);
            },
            edges[i], edges[i + 1], 64);
        total += mass[i * kPhiCells + j];
      }
    EXPECT_NEAR(total, 1.0, 2e-3) << c.fabric;
    constexpr int kSamples = 200000;
    std::vector<int> count(mass.size(), 0);
    for (uint32_t k = 0; k < kSamples; ++k) {
      RandomStream rng(k, 0, 9);
      const glm::vec3 wi = scatter.sample(rng);
      const double th = std::asin(std::clamp(double(glm::dot(wi, t)), -1.0, 1.0));
      double ph = std::atan2(double(glm::dot(wi, w)), double(glm::dot(wi, u)));
      if (ph < 0) ph += 2 * kPi;
      const size_t i = std::min<size_t>(std::upper_bound(edges.begin(), edges.end(), th) - edges.begin() - 1,
                                        edges.size() - 2);
      ++count[i * kPhiCells + std::min(kPhiCells - 1, int(ph / (2 * kPi) * kPhiCells))];
    }
    for (size_t k = 0; k < mass.size(); ++k) {
      const double expected = kSamples * mass[k] / total;
      EXPECT_NEAR(count[k], expected, 5.0 * std::sqrt(expected) + 2.0) << c.fabric << " cell " << k;
    }
  }
}

// ---- White furnace (notes-rendering X6) --------------------------------------

// Mean and standard deviation of the fully covered pixels' green channel.
struct PixelStats {
  double mean = 0, sigma = 0;
  std::vector<double> values;
};
PixelStats coveredPixels(const ImageRgbaF& img) {
  PixelStats p;
  for (size_t i = 0; i < img.pixelCount(); ++i)
    if (img.pixels[4 * i + 3] == 1.0f) p.values.push_back(img.pixels[4 * i + 1]);
  for (double v : p.values) p.mean += v / p.values.size();
  for (double v : p.values) p.sigma += (v - p.mean) * (v - p.mean) / (p.values.size() - 1);
  p.sigma = std::sqrt(p.sigma);
  return p;
}

ShadingParams furnace(const Fabric& f) {
  ShadingParams s = shading(paramsOf(f));
  s.ambient = glm::vec4(1, 1, 1, 0);
  s.background = glm::vec4(1, 1, 1, 0);
  return s;
}

// One fiber under a unit environment: continuations leave the fiber (their
// own fiber is ignored) and escape, so a pixel is the single-scattering
// furnace A(θ_o) of FurnaceIntegral. This BCSDF is normalised over θ_o for
// each θ_i (notes-rendering §0.2, B3: not reciprocal), so ∫ f cos θ_i dω_i
// is not 1: 1.017 at θ_o = 30° for the 10° R lobe below, 1.022 for the TT
// case; the tracer must find those values within 4σ (σ of a 64-sample
// pixel, over the pixels), which exercises the θ sampling, the von Mises
// and the lobe mixture, and their pdfs in dω = cos θ dθ dφ.
TEST(FiberTrace, FurnaceOfOneFiberIsItsAlbedoIntegral) {
  // The fiber tilted 30° towards the eye: θ_o ≈ 30° at every pixel.
  const glm::vec3 t(std::cos(radians(30)), 0.0f, std::sin(radians(30)));
  const FiberTraceScene scene(makeGeometry(straight({0, 0, 0}, t, 50.0f, 0)), onePly());
  const Camera cam = farCamera({0, 0, 0}, 1000.0f, 1.0f, 8, 8);
  const Fabric cases[] = {{{1, 1, 1}, {0, 0, 0}, radians(10), radians(10), 5.0},    // R only: F ≡ 1
                          {{0, 0, 0}, {1, 1, 1}, radians(4), radians(12), 4.0}};  // F + (1 − F)·1 = 1
  for (const Fabric& f : cases) {
    TraceOptions o;
    o.samplesPerPixel = 64;
    o.multipleScattering = true;
    o.maxDepth = 8;
    const TraceResult res = traceFibers(scene, cam, furnace(f), {}, o);
    ASSERT_EQ(res.stats.nonFinite, 0u);
    EXPECT_EQ(res.stats.bounceRays, res.stats.hitSamples);  // one bounce each, then the environment
    const FurnaceIntegral A(f, 1);
    const PixelStats px = coveredPixels(res.image);
    ASSERT_EQ(px.values.size(), 64u);
    std::vector<double> residual;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const Ray ray = pixelRay(cam, x + 0.5, y + 0.5);
        residual.push_back(res.image.at(x, y)[1] - A(std::asin(glm::dot(-ray.d, dvec3(t)))));
      }
    double mean = 0, var = 0;
    for (double r : residual) mean += r / residual.size();
    for (double r : residual) var += (r - mean) * (r - mean) / (residual.size() - 1);
    const double sigma = std::sqrt(var);
    ASSERT_GT(sigma, 0.0);
    for (double r : residual) EXPECT_LE(std::abs(r), 4 * sigma);
    EXPECT_LE(std::abs(mean), 4 * sigma / std::sqrt(residual.size()));
    EXPECT_GT(std::abs(A(radians(30)) - 1.0), 8 * sigma / std::sqrt(residual.size()));  // the check sees A ≠ 1
  }
}

// A slab of three layers of touching parallel fibers, seen across: paths
// bounce between fibers until they escape. With F ≡ 1 nothing is absorbed;
// the expected value of a path with k steps left, V_k, obeys
// V_k(θ_o) ≤ A(θ_o) max(1, sup V_k−1) with A the single-fiber furnace above,
// so V ≤ (1 + ε)^maxDepth where A ∈ [1, 1 + ε] for |θ| ≤ 30° (the 0.5° R
// lobe does not leave that range: θ_o ≈ 0 and each bounce moves θ by about
// β). Paths cut by maxDepth lose what they would have brought (≈ 1 each).
// So the mean of the covered pixels lies in [1 − cut fraction,
// (1 + ε)^maxDepth] up to 4σ. With C_R = 0.5 half of every bounce is
// absorbed: clearly below 1.
TEST(FiberTrace, FurnaceOfASlabConservesEnergy) {
  std::vector<Strip> strips;
  uint32_t id = 0;
  for (int layer = 0; layer < 3; ++layer)
    for (int k = -4; k <= 4; ++k)
      strips = strips + straight({0.0f, 2.0f * k + (layer % 2), -std::sqrt(3.0f) * layer}, {1, 0, 0}, 1.0f, id++);
  const FiberTraceScene scene(makeGeometry(strips), onePly());
  const Camera cam = farCamera({0, 0, 0}, 1000.0f, 8.0f, 16, 16);
  const int maxDepth = 64;
  for (const double cR : {1.0, 0.5}) {
    const Fabric f{{cR, cR, cR}, {0, 0, 0}, radians(0.5), radians(10), 4.0};
    TraceOptions o;
    o.samplesPerPixel = 64;
    o.multipleScattering = true;
    o.maxDepth = maxDepth;
    const TraceResult res = traceFibers(scene, cam, furnace(f), {}, o);
    ASSERT_EQ(res.stats.nonFinite, 0u);
    const PixelStats px = coveredPixels(res.image);
    ASSERT_EQ(px.values.size(), 256u);
    const double meanSigma = px.sigma / std::sqrt(px.values.size());
    if (cR == 1.0) {
      EXPECT_GT(res.stats.bounceRays, 2 * res.stats.hitSamples);  // multiple scattering happens
      const FurnaceIntegral A(f, 1);
      double lo = 1e9, hi = -1e9;
      for (int deg = 0; deg <= 30; ++deg) {
        lo = std::min(lo, A(radians(deg)));
        hi = std::max(hi, A(radians(deg)));
      }
      ASSERT_GE(lo, 1.0 - 1e-6);
      const double upper = std::pow(hi, maxDepth);
      const double cut = double(res.stats.truncatedPaths) / res.stats.hitSamples;
      EXPECT_LT(cut, 1e-3);
      EXPECT_GE(px.mean, 1.0 - cut - 4 * meanSigma);
      EXPECT_LE(px.mean, upper + 4 * meanSigma);
      for (double v : px.values) {  // a pixel may hold every cut path
        EXPECT_GE(v, 1.0 - double(res.stats.truncatedPaths) / o.samplesPerPixel - 4 * px.sigma);
        EXPECT_LE(v, upper + 4 * px.sigma);
      }
    } else {
      EXPECT_LT(px.mean, 0.75);
    }
  }
}

// The white furnace with the shipped defaults (scene/lighting.h: fabric
// cotton, k_d = 0.4; yarn cotton1 with its 20 regular fibers per ply and
// core, LoD on, as the harness) on the built-in scene, lights off, a unit
// environment: every bounce returns (1 − k_d) A(θ_o) + k_d of what it sees,
// so the mean radiance of the covered pixels must stay ≤ 1 however long the
// paths grow, and approach its limit. With k_d added on top of the BCSDF
// (000's wording) it was 2.0 at depth 8 and 264 at depth 32. Paths of depth
// 2d begin with the paths of depth d (the same random numbers: a path draws
// nothing at its last event), so m(2d) − m(d) ≥ 0 is exactly what bounces
// d+1..2d bring, and once d passes the typical path length it must shrink.
// The bound is 1 + 4σ of the mean (pixels are independent). Cotton absorbs
// almost nothing (C_TT = 0.999), so the limit is close to 1 (0.992 measured).
TEST(FiberTrace, WhiteFurnaceWithTheShippedDefaultsConvergesToAtMostOne) {
  const YarnModel model = makeDefaultScene();
  const YarnBuffers buffers = buildYarnBuffers(model);
  const FiberSetup fibers = makeFiberSetup(findYarnPreset("cotton1"), FiberOptions{});
  const Camera cam = closeupCamera(model, 64, 48);
  const FiberInput input{&buffers, &fibers.table, fibers.params, makeViewParams(cam, 1.0f, true, true)};
  const FiberTraceScene scene(generateFibersCpu(input, computeKnotFramesCpu(buffers)), fibers.params);
  ShadingParams s = makeShadingParams(Lighting{});
  ASSERT_EQ(s.diffuse.x, 0.4f);  // the default this test is about
  s.flags.x = 0;                 // no lights: the environment only
  s.ambient = glm::vec4(1, 1, 1, 0);
  s.background = glm::vec4(1, 1, 1, 0);
  const int depths[] = {4, 8, 16, 32, 64, 128};
  std::vector<double> mean, sigma;
  for (const int depth : depths) {
    TraceOptions o;
    o.samplesPerPixel = 4;
    o.multipleScattering = true;
    o.shadows = false;
    o.maxDepth = depth;
    const TraceResult res = traceFibers(scene, cam, s, {}, o);
    ASSERT_EQ(res.stats.nonFinite, 0u);
    const PixelStats px = coveredPixels(res.image);
    ASSERT_GT(px.values.size(), 500u);
    mean.push_back(px.mean);
    sigma.push_back(px.sigma / std::sqrt(double(px.values.size())));
    std::printf("furnace depth %2d: mean %.5f ± %.5f over %zu pixels, %.3g bounce rays, %llu paths cut\n", depth,
                px.mean, sigma.back(), px.values.size(), double(res.stats.bounceRays),
                static_cast<unsigned long long>(res.stats.truncatedPaths));
  }
  for (size_t k = 0; k < mean.size(); ++k) EXPECT_LE(mean[k], 1.0 + 4 * sigma[k]) << "depth " << depths[k];
  EXPECT_GT(mean.back(), 0.5);  // the furnace is lit: the check can fail
  for (size_t k = 1; k < mean.size(); ++k) EXPECT_GE(mean[k], mean[k - 1]) << "depth " << depths[k];
  // Cotton is nearly lossless and the close-up is yarn seen from above: paths
  // bounce tens of times before they escape, so the gains grow up to depth
  // 16 (measured +0.25 per doubling) and shrink from there (16 → 32: 0.18,
  // 32 → 64: 0.05) towards a limit just under 1.
  for (size_t k = 3; k < mean.size(); ++k)
    EXPECT_LT(mean[k] - mean[k - 1], mean[k - 1] - mean[k - 2]) << "depth " << depths[k];
  EXPECT_LT(mean.back() - mean[mean.size() - 2], 0.02) << "depth 64 → 128";
}

// The all-fiber reference (FiberOptions::allFibers, LoD off): every one of
// the preset's fiber_num fibers per ply is explicit and no core is drawn (its
// radius is 0), while the default setup shows core tubes. Checked through
// TraceResult::fiberType, which the shading cases pool by.
TEST(FiberTrace, AllFiberReferenceDrawsEveryFiberAndNoCore) {
  const YarnModel model = makeDefaultScene();
  const YarnBuffers buffers = buildYarnBuffers(model);
  const YarnPreset& preset = findYarnPreset("cotton1");
  FiberOptions all;
  all.allFibers = true;
  const FiberSetup every = makeFiberSetup(preset, all), usual = makeFiberSetup(preset, FiberOptions{});
  EXPECT_EQ(every.params.regularFibers, static_cast<uint32_t>(preset.fiberNum));
  EXPECT_EQ(every.params.coreRadius, 0.0f);
  EXPECT_EQ(usual.params.regularFibers, 20u);
  EXPECT_GT(usual.params.coreRadius, 0.0f);
  const Camera cam = closeupCamera(model, 96, 72);
  const auto frames = computeKnotFramesCpu(buffers);
  ShadingParams s = makeShadingParams(Lighting{});
  const std::vector<glm::vec3> table = constantTable(glm::vec3(0.5f));
  TraceOptions o;
  o.samplesPerPixel = 4;
  o.shadows = false;
  auto typeCounts = [&](const FiberSetup& f, bool lod, size_t& fibers) {
    const FiberInput input{&buffers, &f.table, f.params, makeViewParams(cam, 1.0f, lod, true)};
    const FiberTraceScene scene(generateFibersCpu(input, frames), f.params);
    fibers = scene.fiberCount();
    const TraceResult r = traceFibers(scene, cam, s, table, o);
    std::array<size_t, 5> n{};
    for (uint8_t t : r.fiberType) ++n[t == kNoFiberType ? 4 : t];
    return n;
  };
  size_t fibersAll = 0, fibersUsual = 0;
  const auto nAll = typeCounts(every, false, fibersAll), nUsual = typeCounts(usual, true, fibersUsual);
  EXPECT_EQ(nAll[FT_FIBER_CORE], 0u);
  EXPECT_GT(nAll[FT_FIBER_MIGRATION], 1000u);
  EXPECT_GT(nUsual[FT_FIBER_CORE], 1000u);
  // 75 fibers per ply against 20 + a core (hairs and loops are counted in their fibers).
  EXPECT_GT(fibersAll, 3 * fibersUsual);
}

// Russian roulette must not change the expected value, only the variance:
// the absorbing slab above (C_R = 0.5, so about half of every bounce is
// lost and roulette kills many paths), traced with and without it, depth 64
// (paths cut there carry < 0.5^60). The per-pixel differences of the two
// estimates (same seed, so correlated; their differences are independent
// across pixels) must average to 0 within 4σ. A roulette that forgot to
// divide the survivors by q reads −0.17 here; an upper bound alone
// (FurnaceOfASlabConservesEnergy) would not see it.
TEST(FiberTrace, RussianRouletteKeepsTheExpectedValue) {
  std::vector<Strip> strips;
  uint32_t id = 0;
  for (int layer = 0; layer < 3; ++layer)
    for (int k = -4; k <= 4; ++k)
      strips = strips + straight({0.0f, 2.0f * k + (layer % 2), -std::sqrt(3.0f) * layer}, {1, 0, 0}, 1.0f, id++);
  const FiberTraceScene scene(makeGeometry(strips), onePly());
  const Camera cam = farCamera({0, 0, 0}, 1000.0f, 8.0f, 16, 16);
  const Fabric f{{0.5, 0.5, 0.5}, {0.8, 0.8, 0.8}, radians(4), radians(10), 4.0};
  ShadingParams s = furnace(f);
  s.diffuse = glm::vec4(0.3f, 0.3f, 0.3f, 0.0f);
  TraceOptions o;
  o.samplesPerPixel = 64;
  o.multipleScattering = true;
  o.maxDepth = 64;
  const TraceResult with = traceFibers(scene, cam, s, {}, o);
  o.russianRoulette = false;
  const TraceResult without = traceFibers(scene, cam, s, {}, o);
  ASSERT_EQ(with.stats.nonFinite + without.stats.nonFinite, 0u);
  EXPECT_LT(with.stats.bounceRays, without.stats.bounceRays * 9 / 10);  // roulette does end paths
  std::vector<double> d;
  for (size_t i = 0; i < with.image.pixelCount(); ++i)
    if (with.image.pixels[4 * i + 3] == 1.0f) d.push_back(double(with.image.pixels[4 * i + 1]) - without.image.pixels[4 * i + 1]);
  ASSERT_EQ(d.size(), 256u);
  double mean = 0, var = 0;
  for (double v : d) mean += v / d.size();
  for (double v : d) var += (v - mean) * (v - mean) / (d.size() - 1);
  const double sigma = std::sqrt(var / d.size());
  std::printf("roulette: mean difference %.5f ± %.5f; bounce rays %.3g with, %.3g without\n", mean, sigma,
              double(with.stats.bounceRays), double(without.stats.bounceRays));
  EXPECT_LE(std::abs(mean), 4 * sigma);
  EXPECT_LT(sigma, 0.02);  // tight enough to see a biased roulette
}

// ---- Determinism --------------------------------------------------------------

// Generated fibers (the built-in scene, LoD on), path traced with shadows:
// the same seed gives the same image, on any number of threads; another
// seed does not.
TEST(FiberTrace, DeterministicForASeedOnAnyThreadCount) {
  const YarnModel model = makeDefaultScene();
  const YarnBuffers buffers = buildYarnBuffers(model);
  const FiberSetup fibers = makeFiberSetup(findYarnPreset("polyester1"), FiberOptions{});
  const Camera cam = frameModel(model, {0.3f, 0.5f, 1.0f}, 48, 36);
  const FiberInput input{&buffers, &fibers.table, fibers.params, makeViewParams(cam, 1.0f, true, true)};
  const FiberTraceScene scene(generateFibersCpu(input, computeKnotFramesCpu(buffers)), fibers.params);
  ShadingParams s = shading(findFabricPreset("polyester").params());
  s.flags.x = 2;
  s.lightDirection[0] = glm::vec4(glm::normalize(glm::vec3(0.2f, 1.0f, 0.5f)), 0);
  s.lightDirection[1] = glm::vec4(glm::normalize(glm::vec3(-0.7f, 0.3f, -0.2f)), 0);
  s.lightIrradiance[0] = glm::vec4(2, 2, 2, 0);
  s.lightIrradiance[1] = glm::vec4(0.5f, 0.6f, 0.7f, 0);
  s.ambient = glm::vec4(0.2f, 0.2f, 0.25f, 0);
  s.diffuse = glm::vec4(0.1f, 0.1f, 0.1f, 0);
  TraceOptions o;
  o.samplesPerPixel = 3;  // the Latin-hypercube path
  o.multipleScattering = true;
  o.maxDepth = 6;
  o.seed = 5;
  double lastProgress = 0.0;
  o.progress = [&](double f) {
    EXPECT_GE(f, lastProgress);
    lastProgress = f;
  };
  const TraceResult a = traceFibers(scene, cam, s, {}, o);
  EXPECT_EQ(lastProgress, 1.0);
  o.progress = nullptr;
  const TraceResult b = traceFibers(scene, cam, s, {}, o);
  TraceResult one;
  {
    const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = traceFibers(scene, cam, s, {}, o);
  }
  o.seed = 6;
  const TraceResult other = traceFibers(scene, cam, s, {}, o);
  EXPECT_EQ(a.stats.nonFinite, 0u);
  EXPECT_GT(a.stats.hitSamples, 0u);
  EXPECT_GT(a.stats.bounceRays, 0u);
  EXPECT_EQ(a.image.pixels, b.image.pixels);
  EXPECT_EQ(a.image.pixels, one.image.pixels);
  EXPECT_NE(a.image.pixels, other.image.pixels);
}

TEST(FiberTrace, RejectsBadInput) {
  const FiberTraceScene scene(makeGeometry(straight({0, 0, 0}, {1, 0, 0}, 1.0f, 0)), onePly());
  const Camera cam = farCamera({0, 0, 0}, 100.0f, 4.0f, 4, 4);
  const ShadingParams s = shading(findFabricPreset("cotton").params());
  TraceOptions o;
  EXPECT_THROW(traceFibers(scene, cam, s, {}, o), std::invalid_argument);  // direct mode needs the table
  o.samplesPerPixel = 0;
  EXPECT_THROW(traceFibers(scene, cam, s, constantTable(glm::vec3(0)), o), std::invalid_argument);
  FiberGeometry g = makeGeometry(straight({0, 0, 0}, {1, 0, 0}, 1.0f, 0));
  g.vertices.pop_back();
  EXPECT_THROW({ const FiberTraceScene bad(g, onePly()); }, std::invalid_argument);
}

// ---- trace --env: the environment map sampled directly (docs/srbf-lighting.md) ----

// A 32 × 16 map: random luminances over 3 decades, a zero row, one bright pixel.
ImageRgbaF testEnvironment() {
  ImageRgbaF m(32, 16);
  uint32_t h = 12345u;
  const auto next = [&] {
    h = h * 1664525u + 1013904223u;
    return (h >> 8) / double(1u << 24);
  };
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      const double v = y == 11 ? 0.0 : std::pow(10.0, 3.0 * next() - 2.0);
      float* p = m.at(x, y);
      p[0] = float(v * (0.5 + next())), p[1] = float(v), p[2] = float(v * (0.5 + next())), p[3] = 1.0f;
    }
  m.at(7, 3)[1] = 500.0f;
  return m;
}

// The density integrates to 1 (a quadrature over a grid 7× finer than the
// map, its own directions: the density is read back by direction), and the
// samples fall into the pixels in proportion to the density's mass there
// (each pixel's count within 5σ of its binomial expectation); a sample's pdf
// is pdf() at its direction; the zero row is never drawn.
TEST(FiberTraceEnvironment, SamplerDensityIntegratesToOneAndMatchesItsSamples) {
  const ImageRgbaF map = testEnvironment();
  const EnvironmentSampler env(map);
  ASSERT_TRUE(env.samplable());
  const int fw = 7 * 32, fh = 7 * 16;
  double integral = 0.0;
  for (int y = 0; y < fh; ++y) {
    const double t0 = kPi * y / fh, t1 = kPi * (y + 1) / fh, tm = 0.5 * (t0 + t1);
    const double dOmega = 2.0 * kPi / fw * (std::cos(t0) - std::cos(t1));
    for (int x = 0; x < fw; ++x) {
      const double phi = 2.0 * kPi * (x + 0.5) / fw - kPi;
      integral += env.pdf(dvec3(std::sin(tm) * std::cos(phi), std::cos(tm), std::sin(tm) * std::sin(phi))) * dOmega;
    }
  }
  EXPECT_NEAR(integral, 1.0, 1e-9);
  // Expected mass per pixel from the map itself: lum × the band area.
  std::vector<double> mass(32 * 16);
  double total = 0.0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) {
      const float* p = map.at(x, y);
      const double lum = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      mass[y * 32 + x] = lum * 2.0 * kPi / 32 * (std::cos(kPi * y / 16) - std::cos(kPi * (y + 1) / 16));
      total += mass[y * 32 + x];
    }
  const int n = 400000;
  std::vector<int> count(32 * 16, 0);
  uint32_t h = 777u;
  const auto next = [&] {
    h = h * 1664525u + 1013904223u;
    return (h >> 8) / double(1u << 24);
  };
  int pdfMismatch = 0;
  for (int i = 0; i < n; ++i) {
    const EnvironmentSampler::Sample s = env.sample(next(), next(), next());
    ASSERT_NEAR(glm::length(s.w), 1.0, 1e-12);
    const glm::ivec2 px = env.pixelOf(s.w);
    ++count[px.y * 32 + px.x];
    pdfMismatch += std::abs(env.pdf(s.w) - s.pdf) > 1e-12 * s.pdf;
  }
  EXPECT_LE(pdfMismatch, n / 10000);  // only a sample on a pixel border may read its neighbour
  double worstZ = 0.0;
  for (int k = 0; k < 32 * 16; ++k) {
    const double p = mass[k] / total, mean = n * p, sigma = std::sqrt(n * p * (1.0 - p));
    if (mass[k] == 0.0) {
      EXPECT_EQ(count[k], 0) << "pixel " << k;
      continue;
    }
    worstZ = std::max(worstZ, std::abs(count[k] - mean) / std::max(sigma, 1.0));
  }
  EXPECT_LE(worstZ, 5.0);
}

// Furnace: one fiber under a constant map of radiance 1 gives what the
// uniform ambient 1 gives — path traced, the single-scattering furnace A(θ_o)
// of FurnaceIntegral (as FurnaceOfOneFiberIsItsAlbedoIntegral), within 4σ; in
// direct mode without shadows, A(θ_o) as the ambient table holds it. No NaN.
TEST(FiberTraceEnvironment, ConstantMapIsTheUniformAmbient) {
  const glm::vec3 t(std::cos(radians(30)), 0.0f, std::sin(radians(30)));
  const FiberTraceScene scene(makeGeometry(straight({0, 0, 0}, t, 50.0f, 0)), onePly());
  const Camera cam = farCamera({0, 0, 0}, 1000.0f, 1.0f, 8, 8);
  const Fabric f{{1, 1, 1}, {0, 0, 0}, radians(10), radians(10), 5.0};  // R only: F ≡ 1
  ImageRgbaF ones(16, 8);
  for (float& v : ones.pixels) v = 1.0f;
  const EnvironmentSampler env(ones);
  const FurnaceIntegral A(f, 1);
  for (bool multiple : {true, false}) {
    TraceOptions o;
    o.samplesPerPixel = 576;  // the map's sample and the BCSDF's, MIS-weighted: noisier than the ambient furnace
    o.multipleScattering = multiple;
    o.shadows = false;
    o.maxDepth = 8;
    o.environment = &env;
    ShadingParams s = furnace(f);
    s.ambient = glm::vec4(0.0f);  // the map must bring it all
    const TraceResult res = traceFibers(scene, cam, s, constantTable(glm::vec3(0.0f)), o);
    ASSERT_EQ(res.stats.nonFinite, 0u);
    std::vector<double> residual;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        if (res.image.at(x, y)[3] != 1.0f) continue;
        const Ray ray = pixelRay(cam, x + 0.5, y + 0.5);
        residual.push_back(res.image.at(x, y)[1] - A(std::asin(glm::dot(-ray.d, dvec3(t)))));
      }
    ASSERT_EQ(residual.size(), 64u);
    double mean = 0, var = 0;
    for (double r : residual) mean += r / residual.size();
    for (double r : residual) var += (r - mean) * (r - mean) / (residual.size() - 1);
    const double sigma = std::sqrt(var);
    ASSERT_GT(sigma, 0.0);
    EXPECT_LE(std::abs(mean), 4 * sigma / std::sqrt(residual.size())) << (multiple ? "path traced" : "direct");
    EXPECT_GT(std::abs(A(radians(30)) - 1.0), 8 * sigma / std::sqrt(residual.size()));  // the check sees A ≠ 1
  }
}

// The shipped sky (a sun of λ = 800 over a dim sky) on a slab: NaN-free in
// both modes, with shadows, and brighter where the sun is sampled.
TEST(FiberTraceEnvironment, SkyIsFinite) {
  std::vector<Strip> strips;
  for (int k = -3; k <= 3; ++k) strips = strips + straight({0.0f, 2.0f * k, 0.0f}, {1, 0, 0}, 1.0f, uint32_t(k + 3));
  const FiberTraceScene scene(makeGeometry(strips), onePly());
  const Camera cam = farCamera({0, 0, 0}, 200.0f, 12.0f, 12, 12);
  ImageRgbaF sky(64, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      float* p = sky.at(x, y);
      p[0] = p[1] = p[2] = y < 16 ? 0.5f : 0.05f;
      p[3] = 1.0f;
    }
  for (int c = 0; c < 3; ++c) sky.at(40, 6)[c] = 2000.0f;
  const EnvironmentSampler env(sky);
  for (bool multiple : {false, true}) {
    TraceOptions o;
    o.samplesPerPixel = 4;
    o.multipleScattering = multiple;
    o.environment = &env;
    const TraceResult res =
        traceFibers(scene, cam, shading(findFabricPreset("cotton").params()), constantTable(glm::vec3(0.3f)), o);
    EXPECT_EQ(res.stats.nonFinite, 0u);
    for (float v : res.image.pixels) ASSERT_TRUE(std::isfinite(v));
  }
}

}  // namespace
}  // namespace ft
