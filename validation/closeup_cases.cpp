// closeup_cases.cpp — checks of what a person sees, on each GPU path's own
// output rather than against the CPU:
//   closeup/<model>/<yarn>/<path>: at a close-up camera (a yarn segment spans
//     ~60 px, fibers under a pixel), every drawn fiber polyline against the
//     exact fiber curve: the chord error in pixels and the kink at every
//     vertex, knots between segments included.
//   strip-width/<path>: one straight fiber of known width, rendered; its
//     drawn width measured in pixels.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <map>
#include <span>
#include <unordered_map>

#include "common/fiber_generation.h"
#include "common/lod.h"
#include "reference/fiber_reference.h"
#include "scene/camera.h"
#include "gpu/fiber_renderer.h"
#include "validation/case_support.h"
#include "validation/harness.h"
#include "validation/vertex_compare.h"

namespace ft {

namespace {

using Clock = std::chrono::steady_clock;

// Chord error: the subdivision rule (common/lod.h) aims at
// kDefaultChordErrorPx = 0.25 px from an upper bound of the curve's second
// derivative; half a pixel is where a drawn line starts to cover other pixel
// centres than the curve does.
constexpr double kChordTolerancePx = 0.5;
// Kink: the distance of a polyline vertex from the line through the
// midpoints of its two chords. For a curve sampled with chord error ε it is
// 2ε (a circle: (ℓ/2)·sin(θ/2) = ℓ²/(4R) = 2·ℓ²/(8R)), so twice the chord
// tolerance; a segment drawn as one straight line shows there as a kink.
constexpr double kKinkTolerancePx = 2.0 * kChordTolerancePx;

struct ProjectedPoint {
  glm::dvec2 px;
  bool visible = false;  // in front of the camera and inside the image (+ a margin)
};

ProjectedPoint project(const ViewParams& v, int width, int height, const glm::vec3& p) {
  const glm::dvec4 clip = glm::dmat4(v.viewProj) * glm::dvec4(glm::dvec3(p), 1.0);
  ProjectedPoint out;
  if (clip.w <= 1e-9) return out;
  out.px = glm::dvec2((clip.x / clip.w * 0.5 + 0.5) * width, (clip.y / clip.w * 0.5 + 0.5) * height);
  const double margin = 0.25 * std::max(width, height);
  out.visible = clip.z >= -clip.w && out.px.x > -margin && out.px.x < width + margin && out.px.y > -margin &&
                out.px.y < height + margin;
  return out;
}

double pointSegmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

double pointLineDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
  const glm::dvec2 ab = b - a;
  const double len = glm::length(ab);
  if (len <= 0.0) return glm::length(p - a);
  return std::abs(ab.x * (p.y - a.y) - ab.y * (p.x - a.x)) / len;
}

bool hairBreak(const uvec4& a, const uvec4& b) {
  const bool periodChange = (a.w >> 16u) != (b.w >> 16u);
  return periodChange && ((a.w & 0xFFu) == FT_FIBER_HAIR || (b.w & 0xFFu) == FT_FIBER_HAIR);
}

// Model cusps (issue 14, deliverable 11): a back-track p[i+1] == p[i-1]
// makes the curve turn back on itself — exactly at knot i (zero tangent), and
// nearly again at knot i+1, where it leaves p[i+1] towards p[i+2] after
// arriving from p[i]. There the centre line's radius of curvature falls below
// the distance of the fibers from it (to 0 at knot i), so each fiber, an
// offset of the centre line, folds into a corner of the model itself: no
// sampling density removes it, and like a hair's free end it is reported
// apart. The region: on the segments the back-track's points shape (i-1, i,
// i+1), the stretches where the radius of curvature is below the fibers'
// reach (YarnParams::boundRadius). Everywhere else, including the rest of
// those segments, the metric stays strict. Written from the control points
// alone (not common/).
class CuspRegions {
 public:
  static constexpr int kSteps = 256;  // the region to 1/256 of a segment
  CuspRegions(const YarnBuffers& y, double reach) : folded_(y.segments.size()) {
    for (const CurveInfo& c : y.curves) {
      if (c.basis != FT_BASIS_CATMULL_ROM) continue;
      const int n = int(c.pointCount), segments = c.closed ? n : n - 1;
      auto point = [&](int k) -> glm::dvec3 {  // wrapped, or reflected at open ends
        auto at = [&](int i) { return glm::dvec3(glm::vec3(y.points[c.firstPoint + uint32_t(i)].positionLength)); };
        if (c.closed) return at(((k % n) + n) % n);
        if (k < 0) return 2.0 * at(0) - at(1);
        if (k >= n) return 2.0 * at(n - 1) - at(n - 2);
        return at(k);
      };
      // Radius of curvature |C'|³ / |C' × C''| of uniform Catmull-Rom segment k at t.
      auto radius = [&](int k, double t) {
        const glm::dvec3 p0 = point(k - 1), p1 = point(k), p2 = point(k + 1), p3 = point(k + 2);
        const glm::dvec3 a = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3, b = -p0 + 3.0 * p1 - 3.0 * p2 + p3;
        const glm::dvec3 d1 = 0.5 * ((p2 - p0) + 2.0 * a * t + 3.0 * b * t * t), d2 = 0.5 * (2.0 * a + 6.0 * b * t);
        const double cross = glm::length(glm::cross(d1, d2)), speed = glm::length(d1);
        return cross > 0.0 ? speed * speed * speed / cross : std::numeric_limits<double>::infinity();
      };
      for (int k = 0; k < n; ++k) {
        if (!c.closed && (k == 0 || k + 1 == n)) continue;  // open ends are reflected, never cusps
        if (point(k + 1) != point(k - 1)) continue;
        ++cusps_;
        for (int sgm = k - 1; sgm <= k + 1; ++sgm) {
          if (!c.closed && (sgm < 0 || sgm >= segments)) continue;
          std::vector<bool>& f = folded_[c.firstSegment + uint32_t((sgm + segments) % segments)];
          if (f.empty()) f.assign(kSteps + 1, false);
          for (int i = 0; i <= kSteps; ++i)
            if (radius((sgm + segments) % segments, double(i) / kSteps) < reach) f[size_t(i)] = true;
        }
      }
    }
  }
  // Whether the part [t0, t1] of segment `sgm` lies on a fold.
  bool folded(uint32_t sgm, double t0, double t1) const {
    const std::vector<bool>& f = folded_[sgm];
    if (f.empty()) return false;
    for (int i = int(std::floor(t0 * kSteps)); i <= int(std::ceil(t1 * kSteps)); ++i)
      if (i >= 0 && i <= kSteps && f[size_t(i)]) return true;
    return false;
  }
  uint32_t count() const { return cusps_; }

 private:
  std::vector<std::vector<bool>> folded_;  // per segment: radius < reach at t = i / kSteps (empty: not shaped by a cusp)
  uint32_t cusps_ = 0;
};

// One drawn fiber piece: a strip of one segment, vertices by index.
struct Strip {
  uint32_t segment = 0;
  uint32_t plyFiber = 0;
  std::map<uint32_t, FiberVertex> vertices;
};

CaseResult runCloseupCase(ValidationContext& ctx, const YarnPreset& preset, bool tessellation,
                          const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "closeup";
  r.path = tessellation ? "tessellation" : "compute";
  const HarnessOptions& o = ctx.options();
  const FiberSetup& s = ctx.fiberSetup(preset);
  const YarnParams& p = s.params;
  const int width = o.lodWidth, height = o.lodHeight;
  // --eye/--target/--fov, when given, replace the close-up view.
  const Camera camera = applyCameraOverride(closeupCamera(ctx.model(), width, height), o.camera, ctx.model());
  // ω^LoD at twice the fiber's width at the target, so λ of eq. 4 is about
  // ½ there: fewer fibers are drawn, and their smoothness must not suffer
  // (the subdivisions follow the screen, not λ).
  const ViewParams probe = makeViewParams(camera, 1.0f, true, true);
  const float lodThreshold = 2.0f * ftScreenWidthsAt(p, probe, camera.target).x;
  const ViewParams view = makeViewParams(camera, lodThreshold, true, true);
  const YarnBuffers& y = ctx.buffers();
  const std::vector<FrameNormal>& frames = ctx.cpuFrames();

  // The segments the camera sees (the CPU's culling decision; the
  // cross-check cases compare decisions), nearest first, up to the budget.
  const auto t0 = Clock::now();
  std::vector<std::pair<float, uint32_t>> visible;
  for (uint32_t sgm = 0; sgm < y.segments.size(); ++sgm) {
    const YarnSegment seg = loadSegmentCpu(y, frames, sgm);
    if (ftDecideSegment(p, view, seg).culled) continue;
    visible.push_back({glm::distance(ftBezierPoint(seg, 0.5f), camera.target), sgm});
  }
  std::sort(visible.begin(), visible.end());
  if (visible.size() > o.tessSegmentBudget) visible.resize(o.tessSegmentBudget);
  std::vector<uint32_t> list;
  for (const auto& [dist, sgm] : visible) list.push_back(sgm);
  std::sort(list.begin(), list.end());
  r.cpuMilliseconds = msSince(t0);
  if (list.empty()) throw std::runtime_error("the close-up camera sees no segment");

  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  gpu.setModel(y, s.table);
  gpu.setParams(p, view);
  gpu.setSegmentList(list);
  const auto t1 = Clock::now();
  std::vector<FiberVertex> vertices;
  if (tessellation) {
    gpu.captureTessellation();
    vertices = gpu.readTessellationLines();
  } else {
    gpu.generateCompute();
    vertices = gpu.readComputeVertices();
  }
  r.gpuMilliseconds = msSince(t1);
  r.gpuTiming = "glFinish+steady_clock (includes read-back)";
  // A NaN vertex projects nowhere and would silently drop out of the maxima.
  std::string firstNonFinite;
  const uint64_t gpuNonFinite = countNonFinite(vertices, &firstNonFinite);
  uint64_t exactNonFinite = 0;

  // Polylines of the GPU's own vertices.
  std::map<std::pair<uint32_t, uint32_t>, Strip> strips;  // (segment, ply|fiber)
  for (const FiberVertex& v : vertices) {
    Strip& st = strips[{v.id.y, v.id.z}];
    st.segment = v.id.y;
    st.plyFiber = v.id.z;
    st.vertices[(v.id.w >> 8u) & 0xFFu] = v;
  }

  const CuspRegions cusps(y, p.boundRadius);
  double chordCuspMax = 0.0, kinkCuspMax = 0.0;
  uint64_t cuspChords = 0, cuspJoints = 0;
  std::string cuspWorst;
  double chordHairMax = 0.0, chordMax = 0.0, kinkMax = 0.0, kinkKnotMax = 0.0, turnMax = 0.0, turnKnotMax = 0.0;
  uint64_t chords = 0, joints = 0, knotJoints = 0, subdivSum = 0, stripCount = 0, cappedStrips = 0;
  double lambdaSum = 0.0;
  uint32_t subdivMax = 0;
  std::string worst;
  std::map<uint32_t, SegmentDecision> decisions;
  for (uint32_t sgm : list) decisions[sgm] = ftDecideSegment(p, view, loadSegmentCpu(y, frames, sgm));
  for (const auto& [sgm, d] : decisions) lambdaSum += d.lambda;

  auto kinkAt = [&](const ProjectedPoint& a, const ProjectedPoint& b, const ProjectedPoint& c, double& turnDeg) {
    const glm::dvec2 u = b.px - a.px, w = c.px - b.px;
    const double lu = glm::length(u), lw = glm::length(w);
    turnDeg = (lu > 0.0 && lw > 0.0)
                  ? std::atan2(std::abs(u.x * w.y - u.y * w.x), glm::dot(u, w)) * 180.0 / M_PI
                  : 0.0;
    return pointLineDistance(b.px, 0.5 * (a.px + b.px), 0.5 * (b.px + c.px));
  };

  for (const auto& [key, st] : strips) {
    const uint32_t sgm = st.segment;
    const auto dit = decisions.find(sgm);
    if (dit == decisions.end()) throw std::runtime_error(fmt::format("GPU drew segment {} outside the list", sgm));
    const uint32_t ply = st.plyFiber >> 16u, fiber = st.plyFiber & 0xFFFFu;
    const bool core = fiber == FT_CORE_FIBER_ID;
    const uint32_t slot = core ? 0u : p.fiberCount - fiber;
    // The path's own lines (what it drew): vertices 0..m at t = j/m (the
    // subdivisions for a regular fiber, the core's own coreLines for the core,
    // whose chords must meet the same target by the core's own bound).
    SegmentDecision d = dit->second;
    const uint32_t m = static_cast<uint32_t>(st.vertices.size()) - 1u;
    if (st.vertices.rbegin()->first != m || m == 0)
      throw std::runtime_error(fmt::format("segment {} fiber {:#x}: vertex indices are not 0..n", sgm, st.plyFiber));
    (core ? d.coreLines : d.subdivisions) = m;
    subdivSum += m;
    subdivMax = std::max(subdivMax, m);
    ++stripCount;
    // A segment at the --subdivisions cap (one that passes right by the
    // camera) cannot meet the chord target: counted, not measured.
    if (d.subdivisions >= p.maxSubdivisions) {
      ++cappedStrips;
      continue;
    }
    const YarnSegment seg = loadSegmentCpu(y, frames, sgm);
    const uint32_t curve = y.segments[sgm].curve;
    const TwistRates rates = ftTwistRates(p, y.curves[curve]);
    const FiberCoord fc = core ? FiberCoord{0.0f, 0.0f} : s.table[fiber];
    SegmentDecision d4 = d;
    d4.subdivisions = 4u * d.subdivisions;
    d4.coreLines = 4u * d.coreLines;  // vertex 4j + q is the quarter point q of chord j

    // The chords and vertices that touch a cusp knot of the model.
    auto cuspChord = [&](uint32_t j) { return cusps.folded(sgm, double(j) / m, double(j + 1u) / m); };
    auto cuspVertex = [&](uint32_t j) { return cuspChord(j - 1u) || cuspChord(j); };
    std::vector<ProjectedPoint> proj(m + 1u);
    for (uint32_t j = 0; j <= m; ++j)
      proj[j] = project(view, width, height, glm::vec3(st.vertices.at(j).position));

    // Chord error against the exact curve at the quarter points of each
    // chord: the shared vertex function at 4× the subdivisions (a pure
    // function of t, so these are points of the same curve).
    for (uint32_t j = 0; j < m; ++j) {
      const FiberVertex &a = st.vertices.at(j), &b = st.vertices.at(j + 1);
      if (hairBreak(a.id, b.id) || !proj[j].visible || !proj[j + 1].visible) continue;
      // A hair's free end and the point where it rejoins its period are
      // corners of the model itself (000 §3.1 as fiber_geometry.h builds it):
      // reported apart, since no sampling density removes a corner.
      const bool hair = (a.id.w & 0xFFu) == FT_FIBER_HAIR || (b.id.w & 0xFFu) == FT_FIBER_HAIR;
      ++chords;
      cuspChords += cuspChord(j) ? 1u : 0u;
      for (uint32_t q = 1; q < 4; ++q) {
        const FiberVertex e = ftFiberVertex(p, rates, seg, d4, curve, sgm, ply, slot, fc, 4u * j + q);
        if (countNonFinite(std::span<const FiberVertex>(&e, 1)) != 0) {
          ++exactNonFinite;
          continue;
        }
        if (hairBreak(a.id, e.id) || hairBreak(e.id, b.id)) continue;  // the free end of a hair lies inside
        const ProjectedPoint pe = project(view, width, height, glm::vec3(e.position));
        if (!pe.visible) continue;
        const double err = pointSegmentDistance(pe.px, proj[j].px, proj[j + 1].px);
        if (hair) {
          chordHairMax = maxKeepNaN(chordHairMax, err);
        } else if (cuspChord(j)) {
          if (err > chordCuspMax)
            cuspWorst = fmt::format("at a model cusp (reported apart): segment {} chord {}/{}: {:.3f} px\n", sgm, j, m, err);
          chordCuspMax = maxKeepNaN(chordCuspMax, err);
        } else if (!(err <= chordMax)) {
          chordMax = maxKeepNaN(chordMax, err);
          worst = fmt::format("chord: segment {} ply {} fiber {} type {} chord {}/{}: {:.3f} px\n", sgm, ply, fiber,
                              a.id.w & 0xFFu, j, m, err);
        }
      }
    }
    // Kinks at the interior vertices, and at the knot joining this strip's
    // last vertex to the next segment's first (same curve, same fiber).
    for (uint32_t j = 1; j < m; ++j) {
      const FiberVertex &a = st.vertices.at(j - 1), &b = st.vertices.at(j), &c = st.vertices.at(j + 1);
      if (hairBreak(a.id, b.id) || hairBreak(b.id, c.id)) continue;
      if (((a.id.w | b.id.w | c.id.w) & 0xFFu) == FT_FIBER_HAIR || (b.id.w & 0xFFu) == FT_FIBER_HAIR) continue;
      if (!proj[j - 1].visible || !proj[j].visible || !proj[j + 1].visible) continue;
      double turn = 0.0;
      const double k = kinkAt(proj[j - 1], proj[j], proj[j + 1], turn);
      ++joints;
      if (cuspVertex(j)) {
        ++cuspJoints;
        kinkCuspMax = maxKeepNaN(kinkCuspMax, k);
        continue;
      }
      turnMax = maxKeepNaN(turnMax, turn);
      if (!(k <= kinkMax)) {
        kinkMax = maxKeepNaN(kinkMax, k);
        if (k > kKinkTolerancePx)
          worst += fmt::format("kink: segment {} ply {} fiber {} vertex {}: {:.3f} px, {:.1f}°\n", sgm, ply, fiber, j, k, turn);
      }
    }
    const CurveInfo& ci = y.curves[curve];
    const uint32_t local = y.segments[sgm].local, count = ftCurveSegmentCount(ci);
    if (local + 1u < count || ci.closed) {
      const uint32_t next = ci.firstSegment + (local + 1u) % count;
      const auto nit = strips.find({next, st.plyFiber});
      if (nit != strips.end() && nit->second.vertices.size() >= 2 &&
          nit->second.vertices.size() <= p.maxSubdivisions) {
        const FiberVertex &a = st.vertices.at(m - 1), &b = st.vertices.at(m);
        const FiberVertex &c = nit->second.vertices.at(1);
        const ProjectedPoint pc = project(view, width, height, glm::vec3(c.position));
        const bool hair = (a.id.w & 0xFFu) == FT_FIBER_HAIR || (b.id.w & 0xFFu) == FT_FIBER_HAIR ||
                          (c.id.w & 0xFFu) == FT_FIBER_HAIR;
        if (!hair && !hairBreak(a.id, b.id) && !hairBreak(b.id, nit->second.vertices.at(0).id) &&
            !hairBreak(nit->second.vertices.at(0).id, c.id) && proj[m - 1].visible &&
            proj[m].visible && pc.visible) {
          double turn = 0.0;
          const double k = kinkAt(proj[m - 1], proj[m], pc, turn);
          ++knotJoints;
          if (cusps.folded(sgm, 1.0, 1.0) || cusps.folded(next, 0.0, 0.0)) {  // a knot on a fold
            ++cuspJoints;
            kinkCuspMax = maxKeepNaN(kinkCuspMax, k);
            continue;
          }
          turnKnotMax = maxKeepNaN(turnKnotMax, turn);
          kinkKnotMax = maxKeepNaN(kinkKnotMax, k);
          if (!(k <= kinkMax)) {
            kinkMax = maxKeepNaN(kinkMax, k);
            if (k > kKinkTolerancePx)
              worst += fmt::format("kink at knot: segment {} → {} ply {} fiber {} types {} {} {}: {:.3f} px, {:.1f}°, "
                                   "subdivisions {} / {}\n",
                                   sgm, next, ply, fiber, a.id.w & 0xFFu, b.id.w & 0xFFu, c.id.w & 0xFFu, k, turn,
                                   m, nit->second.vertices.size() - 1);
          }
        }
      }
    }
  }
  if (chords == 0) throw std::runtime_error("no visible chord to measure");

  r.metrics = {
      nonFiniteMetric("gpu", gpuNonFinite, "drawn vertex positions and widths"),
      nonFiniteMetric("cpu", exactNonFinite, "points of the exact curve"),
      Metric{"chord.max_px", chordMax, kChordTolerancePx, "pixels",
             "the subdivision rule aims at 0.25 px; half a pixel is where a line covers other pixel centres "
             "than the curve",
             true},
      Metric{"kink.max_px", kinkMax, kKinkTolerancePx, "pixels",
             "a vertex's distance from the line through its chords' midpoints: 2× the chord error on a "
             "well-sampled curve, far more where a segment is drawn too straight (knots included)",
             true},
      Metric{"chord.hair_max_px", chordHairMax, 0.0, "pixels",
             "hair chords: the free end and the rejoining point are corners of the model", false},
      Metric{"chord.cusp_max_px", chordCuspMax, 0.0, "pixels",
             "chords that touch a cusp of the model (p[i+1] == p[i-1]): the yarn reverses there, a corner of the "
             "curve itself",
             false},
      Metric{"kink.cusp_max_px", kinkCuspMax, 0.0, "pixels", "the same for vertices next to a cusp knot", false},
      Metric{"cusp.chords", double(cuspChords), 0.0, "count", "chords measured apart at model cusps", false},
      Metric{"cusp.joints", double(cuspJoints), 0.0, "count", "vertices measured apart at model cusps", false},
      Metric{"kink.knot_max_px", kinkKnotMax, kKinkTolerancePx, "pixels", "the same, at knots only", false},
      Metric{"turning.max_deg", turnMax, 0.0, "degrees", "largest screen-space turn between chords inside segments",
             false},
      Metric{"turning.knot_max_deg", turnKnotMax, 0.0, "degrees", "the same across knots", false},
      Metric{"chords", double(chords), 0.0, "count", "visible chords measured", false},
      Metric{"joints", double(joints + knotJoints), 0.0, "count", "vertices whose kink was measured", false},
      Metric{"subdivisions.mean", double(subdivSum) / double(std::max<uint64_t>(stripCount, 1)), 0.0, "count",
             "line segments per fiber per yarn segment drawn at this camera", false},
      Metric{"subdivisions.max", double(subdivMax), 0.0, "count", "the most drawn along one yarn segment", false},
      Metric{"lambda.mean", lambdaSum / double(decisions.size()), 0.0, "λ",
             "eq. 4 at ω^LoD = twice the fiber's width at the target: fewer fibers, equally smooth", false},
      Metric{"strips.capped", double(cappedStrips), 0.0, "count",
             "strips at the --subdivisions cap (segments passing by the camera): not measured", false},
      Metric{"segments.listed", double(list.size()), 0.0, "count", "segments the camera sees (up to the budget)",
             false},
  };
  worst += cuspWorst;
  if (o.camera.any())
    worst = fmt::format("explicit camera: eye {},{},{} target {},{},{} fov {}°\n", camera.eye.x, camera.eye.y,
                        camera.eye.z, camera.target.x, camera.target.y, camera.target.z, camera.fovyDegrees) +
            worst;
  r.details = firstNonFinite.empty() ? worst : firstNonFinite + "\n" + worst;
  r.finish();
  if (o.images && (!r.pass || &preset == ctx.presets().front())) {
    RgbaImage img = ctx.gpu<FiberRenderer>().preview(gpu, tessellation ? FiberPath::Tessellation : FiberPath::Compute,
                                                     o.imageWidth * 2, o.imageHeight * 2);
    r.images.push_back(ctx.saveImage(img, name));
  }
  return r;
}

// One straight fiber along x, seen from the side: its strip must cover
// 2·w·(pixels per unit) rows.
CaseResult runStripWidthCase(ValidationContext& ctx, bool tessellation, const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "strip-width";
  r.path = tessellation ? "tessellation" : "compute";
  YarnModel model;
  model.name = "straight fiber";
  YarnCurve c;
  for (int i = 0; i <= 16; ++i) c.points.push_back({-1.6f + 0.2f * i, 0.0f, 0.0f});  // beyond the image
  model.curves.push_back(c);
  const YarnBuffers buffers = buildYarnBuffers(model);

  Camera cam;
  cam.width = 320;
  cam.height = 240;
  cam.eye = {0.0f, 0.0f, 2.0f};
  cam.target = {0.0f, 0.0f, 0.0f};
  cam.zNear = 0.1f;
  cam.zFar = 10.0f;
  const double expectedPx = 12.0;
  const double ppu = cam.pixelsPerUnitAtDepth1() / 2.0;  // at depth 2

  // Only the core fiber, on the yarn axis, of half-width w: one ply at the
  // centre, no regular fibers, LoD off (λ = 1: core half-width = e_B·coreRadius).
  YarnParams p{};
  p.plyCount = 1;
  p.fiberCount = 1;
  p.regularFibers = 0;
  p.maxSubdivisions = 4;
  p.plyRadius = 0.0f;
  p.ellipseN = p.ellipseB = 1.0f;
  p.fiberRadius = 0.001f;
  p.plyTurnsPerLength = p.fiberTurnsPerLength = 1.0f;
  p.plyTwistSign = p.fiberTwistSign = 1.0f;
  p.migrationS = 1.0f;
  p.rhoMin = p.rhoMax = 1.0f;
  p.coreRadius = static_cast<float>(0.5 * expectedPx / ppu);
  p.boundRadius = p.coreRadius;
  const std::vector<FiberCoord> table(1, FiberCoord{0.5f, 0.0f});

  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  gpu.setModel(buffers, table);
  gpu.setParams(p, makeViewParams(cam, 1.0f, false, true));
  gpu.setSegmentList({});
  const auto t0 = Clock::now();
  const RenderStyle style;
  const RgbaImage img = ctx.gpu<FiberRenderer>().preview(gpu, tessellation ? FiberPath::Tessellation : FiberPath::Compute,
                                                         cam.width, cam.height, style);
  r.gpuMilliseconds = msSince(t0);
  r.gpuTiming = "glFinish+steady_clock (includes generation)";

  // Covered rows per column over the middle half of the image, against the
  // background.
  const glm::ivec3 bg = glm::ivec3(glm::round(style.background * 255.0f));
  double sum = 0.0, worst = 0.0;
  int columns = 0;
  for (int x = cam.width / 4; x < 3 * cam.width / 4; ++x) {
    int covered = 0;
    for (int yy = 0; yy < cam.height; ++yy) {
      const uint8_t* px = &img.pixels[(static_cast<size_t>(yy) * cam.width + x) * 4];
      const int diff = std::max({std::abs(px[0] - bg.x), std::abs(px[1] - bg.y), std::abs(px[2] - bg.z)});
      covered += diff > 8;
    }
    sum += covered;
    worst = std::max(worst, std::abs(covered - expectedPx));
    ++columns;
  }
  const double mean = sum / columns;
  r.metrics = {
      Metric{"width.error_px", std::abs(mean - expectedPx), 1.0, "pixels",
             "mean covered rows per column vs 2·w·(pixels per unit) = 12 px; each edge snaps to the nearest pixel "
             "centre (±½ px)",
             true},
      Metric{"width.worst_column_px", worst, 1.0, "pixels", "the same, the worst column", true},
      Metric{"width.mean_px", mean, 0.0, "pixels", "drawn width", false},
  };
  r.finish();
  if (ctx.options().images) r.images.push_back(ctx.saveImage(img, name));
  return r;
}

}  // namespace

void addCloseupCases(ValidationContext& ctx, std::vector<ValidationCase>& out) {
  const YarnPreset* preset = ctx.presets().front();
  for (bool tess : {true, false}) {
    const std::string path = tess ? "tessellation" : "compute";
    const std::string name = fmt::format("closeup/{}/{}/{}", ctx.modelLabel(), preset->name, path);
    out.push_back({name, [preset, tess, name](ValidationContext& c) { return runCloseupCase(c, *preset, tess, name); }});
    const std::string wname = "strip-width/" + path;
    out.push_back({wname, [tess, wname](ValidationContext& c) { return runStripWidthCase(c, tess, wname); }});
  }
}

}  // namespace ft
