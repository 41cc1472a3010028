// fiber_trace.h — the Embree 3 fiber ray tracer: the image-level ground truth
// of the shaded GPU render (docs/ground-truth.md). It traces the very fiber
// lines the GPU draws as strips (gpu/fiber_gpu.cpp drawVertices,
// fiber_strip.geom.glsl) as round tubes of radius position.w, through the
// GPU's pinhole camera, and shades them with common/fiber_shading.h
// (000 §4.3; notes-rendering §0.2, A4).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "common/fiber_shading.h"
#include "common/yarn_params.h"
#include "image/image.h"
#include "scene/camera.h"
#include "scene/fiber_input.h"

namespace ft {

struct TraceOptions;
struct TraceResult;
class EnvironmentSampler;
struct TraceSample;

// Unit tangent of every vertex of a canonical-order vertex stream, by the
// rule of gpu/shaders/fiber_strip_tangent.glsl: the central difference
// p₊₁ − p₋₁ where both neighbours exist, else the second-order one-sided
// difference (4p₊₁ − 3p₀ − p₊₂ or 3p₀ − 4p₋₁ + p₋₂), else the first-order
// one; neighbours are vertices of the same segment and fiber with
// consecutive vertex indices and no hair free end between them.
// Zero where the difference vanishes (the GPU then uses the line's chord).
std::vector<glm::vec3> fiberStripTangents(std::span<const FiberVertex> vertices);

// The fibers of one FiberGeometry as an Embree scene of round linear curves
// (RAII over the RTCDevice and RTCScene; movable, not copyable). The drawn
// lines are those of the GPU: per non-culled decision,
// plyCount·(1 + regularCount) strips of ftStripVertexCount vertices, a line
// between consecutive vertices of a strip unless it crosses a hair's period
// change (fiber_strip.geom.glsl) or has zero length. Each line is one curve
// segment from position.xyz with radius position.w; consecutive lines of a
// strip are joined (Embree's neighbour flags), a strip's ends are round caps.
// The geometry is copied: `geometry` may be freed after construction.
class FiberTraceScene {
 public:
  // Throws std::invalid_argument when the decisions do not describe the
  // vertex stream, std::runtime_error when Embree fails.
  FiberTraceScene(const FiberGeometry& geometry, const YarnParams& params);
  ~FiberTraceScene();
  FiberTraceScene(FiberTraceScene&&) noexcept;
  FiberTraceScene& operator=(FiberTraceScene&&) noexcept;

  size_t segmentCount() const;
  size_t fiberCount() const;  // distinct (yarn, ply, fiber)

  // Distinct fibers along p + τω, τ > 0 (ω a unit vector), up to `cap`,
  // ignoring the fiber of the sample's strip where it is "itself" (as shadow
  // rays do, traceFibers): the n of dual scattering's T_f = d_f ā_f^n
  // (notes-rendering A6–A7). A fiber crossed twice (a helix met on both sides)
  // counts once.
  uint32_t fibersCrossed(glm::vec3 p, glm::vec3 w, uint32_t fromStrip, uint32_t cap = 64) const;
  // Memory held: this scene's arrays (capacity) + every byte Embree has
  // allocated for it (BVH, build buffers still held), counted by Embree's
  // memory monitor.
  size_t bytes() const;
  size_t embreeBytes() const;

  struct Impl;  // opaque: the Embree handles and the per-segment arrays

 private:
  std::unique_ptr<Impl> impl_;
  friend TraceResult traceFibers(const FiberTraceScene&, const Camera&, const ShadingParams&,
                                 std::span<const glm::vec3>, const TraceOptions&);
};

struct TraceOptions {
  int samplesPerPixel = 4;          // stratified jittered (a k×k grid when square, Latin hypercube otherwise)
  // Fixed sample positions in the pixel ([0, 1]², y down), e.g. the GPU's
  // multisample pattern for the shading comparison (validation/
  // shading_cases.cpp); when given, samplesPerPixel must equal their count.
  std::vector<glm::vec2> samplePositions;
  bool shadows = true;              // trace V_i towards each light (else V_i = 1)
  // Each directional light as a cone of this half-angle (radians, [0, 60°];
  // 0: a single direction): the shadow ray of a sample goes along a direction
  // uniform over the cone (soft shadows; `trace --light-angular-radius`, the
  // reference of the frame's PCSS, docs/soft-shadows.md).
  double lightAngularRadius = 0.0;
  bool multipleScattering = false;  // path tracing (modes in traceFibers)
  int maxDepth = 16;                // scattering events per path (multipleScattering)
  bool russianRoulette = true;      // after 3 scattering events; off: every path runs until it escapes or maxDepth
  uint32_t seed = 1;
  std::function<void(double fraction)> progress;  // called from worker threads, one call at a time
  // Called at every camera sample that hits a fiber, once its radiance is
  // known, on the worker thread that renders the pixel (all samples of one
  // pixel run on one thread, in order, so per-pixel sums need no lock): for
  // bakes that gather more than the image (reference/ds_correction.cpp).
  std::function<void(const TraceSample&)> onHit;
  // An environment map lighting the fibers in place of the uniform ambient
  // (`trace --env`; reference/environment_sampling.h): sampled directly,
  // with MIS (power heuristic) against the BCSDF sampling. Not owned.
  const EnvironmentSampler* environment = nullptr;
};

// What TraceOptions::onHit sees.
struct TraceSample {
  uint32_t pixel;      // y · width + x
  glm::vec3 position;  // the hit
  glm::vec3 tangent;   // unit, as shaded
  glm::vec3 normal;    // unit, facing the camera ray
  glm::vec3 wo;        // towards the camera
  glm::vec3 radiance;  // the sample's shaded value (already finite)
  uint32_t strip;      // for FiberTraceScene::fibersCrossed
  uint32_t fiberType;  // FT_FIBER_*
};

struct TraceStats {
  uint64_t cameraRays = 0;
  uint64_t shadowRays = 0;
  uint64_t bounceRays = 0;      // path continuations (multipleScattering)
  uint64_t hitSamples = 0;      // camera samples that hit a fiber
  uint64_t truncatedPaths = 0;  // paths stopped by maxDepth (their remaining energy is lost)
  uint64_t nonFinite = 0;       // samples whose radiance was not finite: left out (black) and counted
  uint64_t rays() const { return cameraRays + shadowRays + bounceRays; }
};

struct TraceResult {
  ImageRgbaF image;  // linear rgb, alpha = fraction of the samples that hit a fiber; row 0 at the top
  TraceStats stats;  // stats.nonFinite > 0 is a failure of the render
  // Per pixel: 1 when every camera sample hit the same fiber strip (one fiber
  // in one yarn segment), 0 at any edge — a silhouette against the background
  // or one fiber's outline over another.
  std::vector<uint8_t> singleStrip;
  // Per pixel: the FT_FIBER_* type hit by most of its camera samples (the
  // first in FT_FIBER_* order on a tie), kNoFiberType where none hit. Lets a
  // comparison pool pixels by fiber type (validation/shading_cases.cpp).
  std::vector<uint8_t> fiberType;
};
inline constexpr uint8_t kNoFiberType = 255;

// Renders `scene` through `camera` (the GPU's: the inverse of projection() ·
// view() maps each pixel sample to a ray from the near to the far plane;
// pixel (x, y) covers [x, x+1] × [y, y+1] with row 0 at the top, as the GPU's
// read-back image). A sample that hits nothing sees s.background; a pixel's
// rgb is the mean over its samples (the background weighted by the misses),
// its alpha the fraction of samples that hit. At a hit: t = the two vertex
// tangents (fiberStripTangents) mixed linearly by the curve parameter and
// normalised, n = the tube's geometric normal facing the ray, ω_o = −ray.
//  * Direct (multipleScattering off): L = Σ_i ftFiberDirect(s, i, t, n, ω_o) V_i
//    + ftFiberAmbient(s, A(θ_o)), A from `ambientTable` (FT_AMBIENT_TABLE_SIZE
//    texels, ftAmbientLookup and a linear mix). V_i = 1 without shadows; with
//    them a ray from the hit towards light i that ignores the hit's own fiber
//    (the far-field BCSDF already accounts for the light crossing it): in
//    the yarn segment it leaves and its two neighbours, and closer than that
//    segment's fiber length; the same fiber further along its yarn occludes.
//  * Multiple scattering: a path tracer. At every fiber hit, next-event
//    estimation to each light (shadow rays as above when options.shadows),
//    then a continuation drawn from FiberScatter (bcsdf_sampling.h) that
//    ignores the fiber it leaves likewise; Russian roulette after 3 scattering events,
//    at most maxDepth of them; an escaping continuation sees the uniform
//    environment s.ambient. The ambient table is not used (may be empty).
//  * With options.environment (the map replaces s.ambient in both modes):
//    at every fiber hit one sample of the map (EnvironmentSampler, p_e) and
//    one of the BCSDF (FiberScatter, p_b; in path mode the continuation
//    itself), each weighted by the power heuristic p²/(p_e² + p_b²), the map
//    seen where a ray escapes. Direct mode: the map's sample is occluded by
//    the fibers when options.shadows (as the lights are), else not.
// Deterministic: every number of sample k of pixel p comes from
// RandomStream(p, k, seed), so the image does not depend on the thread count.
// TBB over 16×16 tiles. Throws std::invalid_argument on bad options, light
// counts or table sizes.
TraceResult traceFibers(const FiberTraceScene& scene, const Camera& camera, const ShadingParams& s,
                        std::span<const glm::vec3> ambientTable, const TraceOptions& options);

}  // namespace ft
