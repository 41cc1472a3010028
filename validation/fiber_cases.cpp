// fiber_cases.cpp — cross-checks of procedural fiber generation
// (000_cc9bd0fbd0e08a03.txt §2.2, §3.1–3.3, §5): CPU reference against the
// tessellation and compute paths, for every yarn preset at three LoD
// distances, plus the knot frames both sides build.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <numeric>
#include <set>
#include <unordered_map>

#include "common/constants.h"
#include "common/lod.h"
#include "common/yarn_frame.h"
#include "reference/fiber_reference.h"
#include "scene/camera.h"
#include "gpu/fiber_renderer.h"
#include "validation/harness.h"
#include "gpu/gpu_timer.h"
#include "validation/case_support.h"
#include "validation/vertex_compare.h"

namespace ft {

namespace {

using Clock = std::chrono::steady_clock;

// ---- Tolerances, each with its reason ---------------------------------------

// Positions: both sides run the same float operations; transcendental
// functions (sin, cos, atan, log) and normalization may differ by a few ulps
// on the GPU, which moves a fiber by ~1e-7 of the yarn radius. 5% of a
// fiber's radius is invisible at any zoom that resolves the fiber; the cubic
// evaluation at large coordinates adds up to 16 ulps of the largest
// coordinate (a real GPU may contract to FMA where `precise` is absent).
double positionTolerance(const YarnParams& p, double maxCoordinate) {
  const double ulp = std::ldexp(1.0, std::ilogb(std::max(maxCoordinate, 1e-30)) - 23);
  return 0.05 * p.fiberRadius + 16.0 * ulp;
}
const char* kPositionWhy = "5% of the fiber radius plus 16 float ulps of the largest coordinate";

struct CpuRun {
  FiberGeometry geometry;
  double milliseconds = 0.0;
};

// The tessellation path is ~100× slower than compute on llvmpipe
// (reference-data §5): on big models its cases use a fixed subset — the
// segments nearest the LoD target plus an even stride over the rest.
std::vector<uint32_t> tessellationSubset(ValidationContext& ctx, const glm::vec3& target) {
  const YarnBuffers& y = ctx.buffers();
  const size_t n = y.segments.size(), budget = ctx.options().tessSegmentBudget;
  if (n <= budget) return {};
  std::vector<std::pair<float, uint32_t>> byDistance(n);
  for (uint32_t s = 0; s < n; ++s) {
    const CurveInfo& c = y.curves[y.segments[s].curve];
    const glm::vec3 p = glm::vec3(y.points[c.firstPoint + std::min(y.segments[s].local, c.pointCount - 1)].positionLength);
    byDistance[s] = {glm::distance(p, target), s};
  }
  const size_t nearest = budget * 3 / 4;
  std::nth_element(byDistance.begin(), byDistance.begin() + nearest, byDistance.end());
  std::set<uint32_t> chosen;
  for (size_t i = 0; i < nearest; ++i) chosen.insert(byDistance[i].second);
  const size_t stride = n / (budget - nearest);
  for (size_t s = 0; s < n && chosen.size() < budget; s += stride) chosen.insert(static_cast<uint32_t>(s));
  return {chosen.begin(), chosen.end()};
}

// The regular-fiber count of eq. 4 (000 §3.3), written here from the
// segment's control points and the camera, in double, without common/lod.h:
// ω^fiber and ω^ply at the Bézier midpoint, λ by the three branches,
// n = λ² n_max to the nearest whole fiber.
uint32_t eq4RegularCount(const YarnParams& p, const ViewParams& v, const YarnSegment& seg) {
  const glm::dvec3 mid = (glm::dvec3(glm::vec3(seg.b0)) + 3.0 * glm::dvec3(glm::vec3(seg.b1)) +
                          3.0 * glm::dvec3(glm::vec3(seg.b2)) + glm::dvec3(glm::vec3(seg.b3))) / 8.0;
  const double w = (glm::dmat4(v.viewProj) * glm::dvec4(mid, 1.0)).w;
  const double pixelsPerUnit = double(v.cameraPos.w) / std::max(w, 1e-6);
  const double fiber = 2.0 * p.fiberRadius * pixelsPerUnit, ply = 2.0 * double(p.ellipseB) * p.rhoMax * pixelsPerUnit;
  const double lod = v.lodThresholdPx;
  const double lambda = lod <= fiber ? 1.0 : ply <= lod ? 0.0 : (fiber / lod) * ((ply - lod) / (ply - fiber));
  const double n = std::floor(lambda * lambda * p.regularFibers + 0.5);
  if (!std::isfinite(n)) return UINT32_MAX;  // a non-finite segment or camera: counted as a mismatch, never cast
  return uint32_t(std::min(n, double(p.regularFibers)));
}

// A decision the two sides may legitimately round differently: the CPU's
// continuous quantity lies within a relative 1e-4 of a discrete boundary.
bool decisionAmbiguous(const YarnParams& p, const ViewParams& v, const YarnSegment& seg,
                       const SegmentDecision& d) {
  const double band = 1e-4;
  auto nearInteger = [&](double x) { return std::abs(x - std::round(x)) <= band * std::max(1.0, x); };
  // λ = 0 and λ = 1 come from the branches of eq. 4 (checked below), not from rounding.
  const double scale = static_cast<double>(d.lambda) * d.lambda;
  if (d.lambda > 0.0f && d.lambda < 1.0f &&
      nearInteger(scale * p.regularFibers + 0.5))  // the count rounds to nearest: boundaries at half-integers
    return true;
  const double subdiv = ftSubdivisionEstimate(p, v, seg);
  if (subdiv < p.maxSubdivisions && nearInteger(subdiv)) return true;
  const double coreSubdiv = ftCoreSubdivisionEstimate(p, v, seg);
  if (coreSubdiv < p.maxSubdivisions && nearInteger(coreSubdiv)) return true;
  const glm::vec2 w = ftScreenWidths(p, v, seg);
  auto near = [&](double a, double b) { return std::abs(a - b) <= band * std::max(std::abs(a), std::abs(b)); };
  if (near(v.lodThresholdPx, w.x) || near(v.lodThresholdPx, w.y)) return true;
  for (int i = 0; i < 6; ++i) {  // the plane test of ftSegmentOutsideFrustum, in double
    const glm::dvec4 pl(v.frustumPlanes[i]);
    double farthest = -INFINITY;
    for (const glm::vec4& b : {seg.b0, seg.b1, seg.b2, seg.b3})
      farthest = std::max(farthest, glm::dot(glm::dvec3(pl), glm::dvec3(glm::vec3(b))) + pl.w);
    if (std::abs(farthest + p.boundRadius) <= band * std::max(1.0, std::abs(farthest))) return true;
  }
  return false;
}

Metric exact(std::string name, double value, std::string why) {
  return Metric{std::move(name), value, 0.0, "count", std::move(why), true};
}

// What the compute path's indirect draw will read: its index buffer must be
// one run per fiber strip, each run the strip's vertices 0..n of one
// (segment, ply, fiber) in order, closed by the restart index, every strip
// exactly once. Returns the runs and strips that break it.
uint64_t malformedStrips(const std::vector<uint32_t>& indices, const std::vector<FiberVertex>& vertices,
                         std::string& notes) {
  uint64_t bad = 0;
  auto note = [&](const std::string& what) {
    if (bad++ < 3) notes += "indices: " + what + "\n";
  };
  std::set<std::pair<uint32_t, uint32_t>> strips, drawn;
  for (const FiberVertex& v : vertices) strips.insert({v.id.y, v.id.z});
  std::vector<uint32_t> run;
  for (size_t i = 0; i <= indices.size(); ++i) {
    if (i < indices.size() && indices[i] != FT_RESTART_INDEX) {
      run.push_back(indices[i]);
      continue;
    }
    if (i == indices.size() && run.empty()) break;
    if (run.empty()) {
      note(fmt::format("empty run at {}", i));
      continue;
    }
    if (i == indices.size()) note("the last run has no restart index");
    bool ok = run.size() >= 2;
    for (size_t k = 0; ok && k < run.size(); ++k) {
      ok = run[k] < vertices.size() && vertices[run[k]].id.y == vertices[run[0]].id.y &&
           vertices[run[k]].id.z == vertices[run[0]].id.z && ((vertices[run[k]].id.w >> 8u) & 0xFFu) == k;
    }
    if (!ok) {
      note(fmt::format("run ending at {} is not one strip's vertices 0..n", i));
    } else if (!drawn.insert({vertices[run[0]].id.y, vertices[run[0]].id.z}).second) {
      note(fmt::format("segment {} fiber {:#x} drawn twice", vertices[run[0]].id.y, vertices[run[0]].id.z));
    }
    run.clear();
  }
  for (const auto& st : strips)
    if (!drawn.count(st)) note(fmt::format("segment {} fiber {:#x} never drawn", st.first, st.second));
  return bad;
}

struct FiberCaseSpec {
  const YarnPreset* preset;
  LodDistance lod;
  bool tessellation;
};

CaseResult runFiberCase(ValidationContext& ctx, const FiberCaseSpec& spec, const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "fiber";
  r.path = spec.tessellation ? "tessellation" : "compute";
  const HarnessOptions& o = ctx.options();
  const FiberSetup& ps = ctx.fiberSetup(*spec.preset);
  const YarnParams& params = ps.params;
  const Camera camera = lodCamera(ctx.model(), params, spec.lod, o.lodThresholdPx, o.lodWidth, o.lodHeight);
  const ViewParams view = makeViewParams(camera, o.lodThresholdPx, true, true);
  const std::vector<uint32_t> list = spec.tessellation ? tessellationSubset(ctx, camera.target) : std::vector<uint32_t>{};

  // CPU reference (cached: both GPU paths compare with the same run when their lists agree).
  const std::string cpuKey = fmt::format("cpu/{}/{}/{}", spec.preset->name, lodDistanceName(spec.lod), list.size());
  const CpuRun& cpu = ctx.cached(CacheKey<CpuRun>{cpuKey}, [&] {
    CpuRun run;
    FiberInput input{&ctx.buffers(), &ps.table, params, view};
    const auto t0 = Clock::now();
    run.geometry = generateFibersCpu(input, ctx.cpuFrames(), list);
    run.milliseconds = msSince(t0);
    return run;
  });
  r.cpuMilliseconds = cpu.milliseconds;

  // GPU path.
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  gpu.setModel(ctx.buffers(), ps.table);
  gpu.setParams(params, view);
  gpu.setSegmentList(list);
  std::vector<FiberVertex> gpuVertices;
  std::vector<SegmentDecision> gpuDecisions;
  std::vector<uint32_t> gpuIndices;
  GpuTimer timer(ctx.gl());  // glFinish + clock on llvmpipe, timer queries on real GPUs
  timer.begin();
  if (spec.tessellation) {
    gpu.captureTessellation();
    r.gpuMilliseconds = timer.endMs();
    gpuVertices = gpu.readTessellationLines();
  } else {
    gpu.generateCompute();
    r.gpuMilliseconds = timer.endMs();
    gpuDecisions = gpu.readDecisions();
    gpuVertices = gpu.readComputeVertices();
    gpuIndices = gpu.readComputeIndices();
  }
  r.gpuTiming = timer.method();

  // Segments whose decision sits on a rounding boundary are left out of the
  // exact comparisons (and counted).
  std::unordered_map<uint32_t, size_t> listIndex;
  std::set<uint32_t> ambiguous;
  for (size_t i = 0; i < cpu.geometry.segments.size(); ++i) {
    const uint32_t s = cpu.geometry.segments[i];
    listIndex[s] = i;
    if (decisionAmbiguous(params, view, loadSegmentCpu(ctx.buffers(), ctx.cpuFrames(), s), cpu.geometry.decisions[i]))
      ambiguous.insert(s);
  }
  auto keep = [&](const FiberVertex& v) { return !ambiguous.count(v.id.y); };
  std::vector<FiberVertex> cpuKept, gpuKept;
  std::copy_if(cpu.geometry.vertices.begin(), cpu.geometry.vertices.end(), std::back_inserter(cpuKept), keep);
  std::copy_if(gpuVertices.begin(), gpuVertices.end(), std::back_inserter(gpuKept), keep);

  // Decisions: read directly on the compute path, derived from the emitted
  // vertices on the tessellation path (culled = nothing emitted).
  uint64_t decisionMismatch = 0, eq4Mismatch = 0, eq4Checked = 0;
  double lambdaMax = 0.0;
  std::string notes;
  auto noteDecision = [&](uint32_t s, const std::string& what) {
    if (decisionMismatch++ < 5) notes += fmt::format("segment {}: {}\n", s, what);
  };
  // The CPU's counts against eq. 4 written above (a count the two sides share
  // passes the cross-check whatever it is).
  for (size_t i = 0; i < cpu.geometry.segments.size(); ++i) {
    const uint32_t s = cpu.geometry.segments[i];
    const SegmentDecision& c = cpu.geometry.decisions[i];
    if (c.culled != 0u || ambiguous.count(s)) continue;
    ++eq4Checked;
    const uint32_t expected = eq4RegularCount(params, view, loadSegmentCpu(ctx.buffers(), ctx.cpuFrames(), s));
    if (c.regularCount != expected && eq4Mismatch++ < 5)
      notes += fmt::format("segment {}: {} regular fibers per ply, eq. 4 gives {}\n", s, c.regularCount, expected);
  }
  if (!spec.tessellation) {
    if (gpuDecisions.size() != cpu.geometry.decisions.size())
      throw std::runtime_error("compute path returned a decision count different from the segment list");
    for (size_t i = 0; i < gpuDecisions.size(); ++i) {
      const SegmentDecision &c = cpu.geometry.decisions[i], &g = gpuDecisions[i];
      lambdaMax = maxKeepNaN(lambdaMax, static_cast<double>(std::abs(c.lambda - g.lambda)));
      if (ambiguous.count(cpu.geometry.segments[i])) continue;
      // A culled segment draws nothing: its core lines are not a decision (off-screen,
      // behind the eye, the bound's pixels per unit is ill-conditioned).
      if (c.culled != g.culled || c.regularCount != g.regularCount || c.subdivisions != g.subdivisions ||
          (c.culled == 0u && c.coreLines != g.coreLines) || c.vertexCount != g.vertexCount)
        noteDecision(cpu.geometry.segments[i],
                     fmt::format("CPU culled {} fibers {} subdiv {} core {} / GPU culled {} fibers {} subdiv {} core {}",
                                 c.culled, c.regularCount, c.subdivisions, c.coreLines, g.culled, g.regularCount,
                                 g.subdivisions, g.coreLines));
    }
  } else {
    // The last vertex of the regular strands and of the core strands.
    struct Seen { std::set<uint32_t> strands; uint32_t maxVertex = 0, maxCoreVertex = 0; };
    std::unordered_map<uint32_t, Seen> seen;
    for (const FiberVertex& v : gpuVertices) {
      Seen& s = seen[v.id.y];
      s.strands.insert(v.id.z);
      uint32_t& m = (v.id.z & 0xFFFFu) == FT_CORE_FIBER_ID ? s.maxCoreVertex : s.maxVertex;
      m = std::max(m, (v.id.w >> 8) & 0xFFu);
    }
    for (size_t i = 0; i < cpu.geometry.segments.size(); ++i) {
      const uint32_t s = cpu.geometry.segments[i];
      if (ambiguous.count(s)) continue;
      const SegmentDecision& c = cpu.geometry.decisions[i];
      auto it = seen.find(s);
      const bool gpuCulled = it == seen.end();
      if (gpuCulled != (c.culled != 0u)) {
        noteDecision(s, fmt::format("CPU culled {} / GPU emitted {}", c.culled, gpuCulled ? "nothing" : "fibers"));
      } else if (!gpuCulled && (it->second.strands.size() != params.plyCount * (1u + c.regularCount) ||
                                (c.regularCount > 0u && it->second.maxVertex != c.subdivisions) ||
                                it->second.maxCoreVertex != c.coreLines)) {
        noteDecision(s, fmt::format("CPU {} strands × {} subdiv, cores {} / GPU {} strands × {} subdiv, cores {}",
                                    params.plyCount * (1u + c.regularCount), c.subdivisions, c.coreLines,
                                    it->second.strands.size(), it->second.maxVertex, it->second.maxCoreVertex));
      }
    }
    for (const auto& [s, unused] : seen)
      if (!listIndex.count(s)) noteDecision(s, "GPU emitted a segment that is not in the list");
  }

  double maxCoordinate = 0.0;
  for (const FiberVertex& v : cpuKept)
    maxCoordinate = std::max({maxCoordinate, std::abs(double(v.position.x)), std::abs(double(v.position.y)),
                              std::abs(double(v.position.z))});
  const StreamComparison cmp = compareStreams(cpuKept, gpuKept, params.boundRadius);
  // NaN/Inf on each side, over the whole streams (ambiguous segments included).
  std::string firstCpuNonFinite, firstGpuNonFinite;
  uint64_t cpuNonFinite = countNonFinite(cpu.geometry.vertices, &firstCpuNonFinite);
  uint64_t gpuNonFinite = countNonFinite(gpuVertices, &firstGpuNonFinite);
  for (const SegmentDecision& d : cpu.geometry.decisions) cpuNonFinite += !std::isfinite(d.lambda);
  for (const SegmentDecision& d : gpuDecisions) gpuNonFinite += !std::isfinite(d.lambda);
  const double posTol = positionTolerance(params, maxCoordinate);
  r.histogram = cmp.histogram;
  r.histogramMetric = "position.max_abs";
  r.metrics = {
      exact("vertices.count_difference", std::abs(double(cmp.gpuVertices) - double(cmp.cpuVertices)),
            "both sides generate the same vertices"),
      exact("fibers.count_difference", std::abs(double(cmp.gpuFibers) - double(cmp.cpuFibers)),
            "both sides generate the same fibers"),
      exact("vertices.missing", double(cmp.missing), "every CPU vertex exists on the GPU"),
      exact("vertices.extra", double(cmp.extra), "the GPU emits no vertex the CPU does not"),
      exact("vertices.duplicates_disagree", double(cmp.duplicateDisagree),
            "a vertex shared by two isoline segments is evaluated identically"),
      exact("ids.mismatched", double(cmp.idMismatch),
            "yarn, type and period tags come from exact integer/float operations"),
      exact("decisions.mismatched", double(decisionMismatch), "LoD counts and culling are discrete decisions"),
      exact("lod.count_vs_eq4", double(eq4Mismatch),
            "the CPU's regular fibers per ply against round(λ² n_max) of eq. 4 computed in the case (segments near a "
            "rounding boundary left out)"),
      Metric{"lod.segments_checked", double(eq4Checked), 0.0, "segments", "segments whose count eq. 4 judged", false},
      nonFiniteMetric("cpu", cpuNonFinite, "CPU vertex coordinates, widths and λ"),
      nonFiniteMetric("gpu", gpuNonFinite, "GPU vertex coordinates, widths and λ"),
      Metric{"position.max_abs", cmp.maxAbs, posTol, "world units", kPositionWhy, true},
      Metric{"position.rmse", cmp.rmse, 0.01 * params.fiberRadius, "world units",
             "1% of the fiber radius: typical error must be far below the worst case", true},
      Metric{"position.max_rel", cmp.maxRel, 1e-4, "fraction of max(|p|, yarn bound radius)",
             "100× the float resolution of the generating arithmetic (sin/cos ~1e-6)", true},
      Metric{"width.max_abs", cmp.maxWidthAbs, 1e-3 * params.fiberRadius, "world units",
             "strip widths are products of params and λ²: 0.1% of the fiber radius", true},
      Metric{"decisions.ambiguous", double(ambiguous.size()), 0.0, "segments",
             "decisions within 1e-4 (relative) of a rounding boundary; excluded from exact checks", false},
      Metric{"vertices.cpu", double(cmp.cpuVertices), 0.0, "count", "size of the comparison", false},
      Metric{"segments.listed", double(cpu.geometry.segments.size()), 0.0, "count", "segments generated", false},
  };
  if (!spec.tessellation)
    r.metrics.push_back(Metric{"lambda.max_abs", lambdaMax, 1e-5, "λ",
                               "λ² scales counts ≤ 4096 through ceil(): 1e-5 moves them by < 0.1", true});
  if (!spec.tessellation) {
    std::string indexNotes;
    const uint64_t malformed = malformedStrips(gpuIndices, gpuVertices, indexNotes);
    notes += indexNotes;
    r.metrics.push_back(exact("indices.malformed", double(malformed),
                              "the index buffer the draw reads holds every fiber strip once, vertices 0..n in order, "
                              "each run closed by a restart"));
  }
  r.details = notes + firstCpuNonFinite + firstGpuNonFinite + cmp.firstMismatches;
  r.finish();

  // Thumbnails: the CPU stream and the GPU path's own rendering, same camera.
  if (o.images && (!r.pass || spec.preset == ctx.presets().front())) {
    // Both images use the comparison's view and decisions (a thumbnail of
    // another aspect ratio would stretch).
    const std::string stem = name;
    FiberRenderer& renderer = ctx.gpu<FiberRenderer>();
    r.images.push_back(ctx.saveImage(renderer.previewVertices(gpu, cpu.geometry.vertices, cpu.geometry.decisions,
                                                              o.imageWidth, o.imageHeight),
                                     stem + "-cpu"));
    RgbaImage g = renderer.preview(gpu, spec.tessellation ? FiberPath::Tessellation : FiberPath::Compute,
                                   o.imageWidth, o.imageHeight);
    r.images.push_back(ctx.saveImage(g, stem + "-gpu"));
  }
  return r;
}

CaseResult runFramesCase(ValidationContext& ctx, const std::string& name) {
  CaseResult r;
  r.name = name;
  r.group = "frames";
  r.path = "compute";
  const auto t0 = Clock::now();
  const std::vector<FrameNormal>& cpu = ctx.cpuFrames();
  r.cpuMilliseconds = msSince(t0);
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  const std::vector<FiberCoord> table(1, FiberCoord{0.0f, 0.0f});
  const auto t1 = Clock::now();
  gpu.setModel(ctx.buffers(), table);
  const std::vector<FrameNormal> g = gpu.readFrames();
  r.gpuMilliseconds = msSince(t1);
  r.gpuTiming = "glFinish+steady_clock (includes upload)";
  if (g.size() != cpu.size()) throw std::runtime_error("GPU frame count differs from the CPU's");
  double maxAngle = 0.0, maxUnit = 0.0, maxOrtho = 0.0;
  uint64_t cpuNonFinite = 0, gpuNonFinite = 0, cusps = 0;
  std::string firstNonFinite;
  const YarnBuffers& y = ctx.buffers();
  for (size_t ci = 0; ci < y.curves.size(); ++ci) {
    const CurveInfo& c = y.curves[ci];
    for (uint32_t k = 0; k < ftCurveKnotCount(c); ++k) {
      const Knot knot = knotCpu(y, c, k);
      cusps += knot.cusp;
      const glm::dvec3 a(glm::vec3(cpu[c.frameBase + k].normal)), b(glm::vec3(g[c.frameBase + k].normal));
      const bool aBad = !std::isfinite(glm::dot(a, a)), bBad = !std::isfinite(glm::dot(b, b));
      cpuNonFinite += aBad;
      gpuNonFinite += bBad;
      if ((aBad || bBad) && firstNonFinite.empty())
        firstNonFinite = fmt::format("curve {} knot {}: CPU normal ({}, {}, {}), GPU normal ({}, {}, {})\n", ci, k, a.x,
                                     a.y, a.z, b.x, b.y, b.z);
      const double ang = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
      maxAngle = maxKeepNaN(maxAngle, ang);
      maxUnit = maxKeepNaN(maxUnit, std::abs(glm::length(b) - 1.0));
      maxOrtho = maxKeepNaN(maxOrtho, std::abs(glm::dot(b, glm::dvec3(ftKnotAxis(knot)))));
      r.histogram.add(ang);
      r.histogramMetric = "normal.max_angle";
    }
  }
  r.metrics = {
      Metric{"normal.max_angle", maxAngle, 1e-4, "radians",
             "1e-4 rad turns a ply by 1e-4 of its offset (~2e-6 units, <1% of a fiber radius) after "
             "propagation over thousands of knots",
             true},
      Metric{"normal.unit_error", maxUnit, 1e-5, "|n|-1", "normalized with sqrt on both sides: a few ulps", true},
      Metric{"normal.tangent_dot", maxOrtho, 1e-5, "|n·t|", "the normal is projected ⟂ the tangent: a few ulps",
             true},
      nonFiniteMetric("cpu", cpuNonFinite, "CPU knot normals"),
      nonFiniteMetric("gpu", gpuNonFinite, "GPU knot normals"),
      Metric{"knots", double(cpu.size()), 0.0, "count", "frames compared", false},
      Metric{"knots.cusps", double(cusps), 0.0, "count",
             "knots with a zero tangent (exact back-tracks): the fallback of common/yarn_frame.h", false},
  };
  r.details = firstNonFinite;
  r.finish();
  return r;
}

}  // namespace

void addFiberCases(ValidationContext& ctx, std::vector<ValidationCase>& out) {
  const std::string model = ctx.modelLabel();
  out.push_back({"frames/" + model, [name = "frames/" + model](ValidationContext& c) { return runFramesCase(c, name); }});
  for (const YarnPreset* preset : ctx.presets())
    for (LodDistance lod : {LodDistance::Near, LodDistance::Mid, LodDistance::Far})
      for (bool tess : {true, false}) {
        const std::string name = fmt::format("fiber/{}/{}/{}/{}", model, preset->name, lodDistanceName(lod),
                                             tess ? "tessellation" : "compute");
        FiberCaseSpec spec{preset, lod, tess};
        out.push_back({name, [spec, name](ValidationContext& c) { return runFiberCase(c, spec, name); }});
      }
}

}  // namespace ft
