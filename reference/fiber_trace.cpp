#include "reference/fiber_trace.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

#include "common/constants.h"
#include "common/fiber_generation.h"
#include "common/lod.h"
#include "reference/bcsdf_sampling.h"
#include "reference/environment_sampling.h"

namespace ft {

namespace {

// ftStripNeighbour of gpu/shaders/fiber_strip_tangent.glsl: b is `step`
// vertices after a on the same piece of the same fiber in the same segment.
bool stripNeighbour(const uvec4& a, const uvec4& b, int step) {
  if (a.y != b.y || a.z != b.z) return false;
  const int va = int((a.w >> 8u) & 0xFFu), vb = int((b.w >> 8u) & 0xFFu);
  if (vb - va != step) return false;
  const bool periodChange = (a.w >> 16u) != (b.w >> 16u);
  return !(periodChange && ((a.w & 0xFFu) == FT_FIBER_HAIR || (b.w & 0xFFu) == FT_FIBER_HAIR));
}

// fiber_strip.geom.glsl's rule for the line between two consecutive vertices
// of a strip: not across a hair's free end, not of zero length. A line of
// zero radius at both ends is not a tube: the core of the all-fiber
// reference (FiberOptions::allFibers), which has no core fibers left.
bool lineDrawn(const FiberVertex& a, const FiberVertex& b) {
  const bool periodChange = (a.id.w >> 16u) != (b.id.w >> 16u);
  if (periodChange && ((a.id.w & 0xFFu) == FT_FIBER_HAIR || (b.id.w & 0xFFu) == FT_FIBER_HAIR)) return false;
  if (!(a.position.w > 0.0f) && !(b.position.w > 0.0f)) return false;
  const vec3 chord = vec3(b.position) - vec3(a.position);
  return dot(chord, chord) > 0.0f;
}

const char* embreeErrorName(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
  }
}

}  // namespace

std::vector<glm::vec3> fiberStripTangents(std::span<const FiberVertex> v) {
  std::vector<vec3> out(v.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, v.size(), 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      // ftStripTangent: neighbours at −2, −1, +1, +2 (index k + 2).
      bool has[5];
      vec3 p[5];
      for (int k = -2; k <= 2; ++k) {
        const int64_t j = static_cast<int64_t>(i) + k;
        has[k + 2] = k != 0 && j >= 0 && j < static_cast<int64_t>(v.size()) && stripNeighbour(v[i].id, v[j].id, k);
        p[k + 2] = vec3(has[k + 2] ? v[j].position : v[i].position);
      }
      vec3 t(0.0f);
      if (has[1] && has[3])
        t = p[3] - p[1];
      else if (has[3])
        t = has[4] ? 4.0f * p[3] - 3.0f * p[2] - p[4] : p[3] - p[2];
      else if (has[1])
        t = has[0] ? 3.0f * p[2] - 4.0f * p[1] + p[0] : p[2] - p[1];
      const float len2 = dot(t, t);
      out[i] = len2 > 0.0f ? t / std::sqrt(len2) : vec3(0.0f);
    }
  });
  return out;
}

// A strip (one fiber in one yarn segment) with a drawn line.
struct StripInfo {
  uint32_t fiber;    // dense id of (yarn, ply, fiber)
  uint32_t segment;  // global yarn segment (consecutive along a curve)
  float length;      // of its drawn lines
  uint32_t type;     // FT_FIBER_* of its first vertex (a strip is one fiber type)
};

struct FiberTraceScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::atomic<int64_t> embreeBytes{0};
  std::vector<vec4> points;            // per vertex: xyz, w radius (Embree's vertex buffer)
  std::vector<vec3> tangents;          // per vertex: unit tangent, 0 = use the chord
  std::vector<uint32_t> firstVertex;   // per segment: its first vertex (Embree's index buffer, padded)
  std::vector<uint8_t> neighbours;     // per segment: RTC_CURVE_FLAG_NEIGHBOR_* (padded)
  std::vector<uint32_t> stripOf;       // per segment: its strip
  std::vector<StripInfo> strips;
  size_t segments = 0;
  size_t fibers = 0;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);  // after the scene: the monitor still counts its frees
  }

  void check(const char* what) const {
    if (const RTCError e = rtcGetDeviceError(device); e != RTC_ERROR_NONE)
      throw std::runtime_error(fmt::format("Embree: {} failed: {}", what, embreeErrorName(e)));
  }
};

namespace {

bool countEmbreeBytes(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
  return true;
}

// Calls line(first vertex, strip index) for every drawn line of the stream,
// strip by strip as gpu/fiber_gpu.cpp drawVertices cuts it.
template <class F>
void forEachLine(const FiberGeometry& g, const YarnParams& params, F&& line) {
  size_t base = 0, strip = 0;
  for (const SegmentDecision& d : g.decisions) {
    if (d.culled) continue;
    if (base + ftVertexCount(params, d) > g.vertices.size())
      throw std::invalid_argument(fmt::format("FiberTraceScene: the decisions describe more than the {} vertices",
                                              g.vertices.size()));
    for (uint32_t ply = 0; ply < params.plyCount; ++ply)
      for (uint32_t slot = 0; slot < ftSlotsPerPly(d); ++slot, ++strip) {
        const size_t n = ftStripVertexCount(d, slot);
        for (size_t i = base; i + 1 < base + n; ++i)
          if (lineDrawn(g.vertices[i], g.vertices[i + 1])) line(i, strip);
        base += n;
      }
  }
  if (base != g.vertices.size())
    throw std::invalid_argument(
        fmt::format("FiberTraceScene: the decisions describe {} vertices, the stream has {}", base, g.vertices.size()));
}

}  // namespace

FiberTraceScene::FiberTraceScene(const FiberGeometry& g, const YarnParams& params) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  if (g.vertices.size() > std::numeric_limits<uint32_t>::max())
    throw std::invalid_argument(fmt::format("FiberTraceScene: {} vertices exceed 32-bit indices", g.vertices.size()));
  forEachLine(g, params, [&](size_t, size_t) { ++m.segments; });
  // Embree reads index and flag buffers 16 bytes at a time: pad them.
  m.firstVertex.assign(m.segments + 4, 0u);
  m.neighbours.assign(m.segments + 16, 0u);
  m.stripOf.assign(m.segments, 0u);
  std::unordered_map<uint64_t, uint32_t> fiberIds;
  size_t at = 0, lastStrip = std::numeric_limits<size_t>::max();
  forEachLine(g, params, [&](size_t i, size_t strip) {
    if (strip != lastStrip) {
      const uvec4 id = g.vertices[i].id;  // yarn (x) and ply << 16 | fiber (z) name the fiber across segments
      const uint64_t key = (uint64_t(id.x) << 32) | id.z;
      m.strips.push_back({fiberIds.try_emplace(key, static_cast<uint32_t>(fiberIds.size())).first->second, id.y, 0.0f,
                          id.w & 0xFFu});
    } else if (m.firstVertex[at - 1] + 1 == i) {  // joined to the previous line of the strip
      m.neighbours[at - 1] |= RTC_CURVE_FLAG_NEIGHBOR_RIGHT;
      m.neighbours[at] |= RTC_CURVE_FLAG_NEIGHBOR_LEFT;
    }
    lastStrip = strip;
    m.strips.back().length += glm::distance(vec3(g.vertices[i].position), vec3(g.vertices[i + 1].position));
    m.firstVertex[at] = static_cast<uint32_t>(i);
    m.stripOf[at] = static_cast<uint32_t>(m.strips.size() - 1);
    ++at;
  });
  m.strips.shrink_to_fit();
  m.fibers = fiberIds.size();
  m.tangents = fiberStripTangents(g.vertices);
  m.points.resize(g.vertices.size());
  tbb::parallel_for(size_t(0), g.vertices.size(), [&](size_t i) { m.points[i] = g.vertices[i].position; });

  m.device = rtcNewDevice(nullptr);
  if (!m.device)
    throw std::runtime_error(
        fmt::format("Embree: rtcNewDevice failed: {}", embreeErrorName(rtcGetDeviceError(nullptr))));
  if (!rtcGetDeviceProperty(m.device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED) ||
      !rtcGetDeviceProperty(m.device, RTC_DEVICE_PROPERTY_CURVE_GEOMETRY_SUPPORTED))
    throw std::runtime_error("Embree: this build lacks filter functions or curves");
  rtcSetDeviceMemoryMonitorFunction(m.device, countEmbreeBytes, &m.embreeBytes);
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  if (m.segments > 0) {
    RTCGeometry geom = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, m.points.data(), 0, sizeof(vec4),
                               m.points.size());
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, m.firstVertex.data(), 0,
                               sizeof(uint32_t), m.segments);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, m.neighbours.data(), 0,
                               sizeof(uint8_t), m.segments);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(m.scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(m.scene);
  m.check("building the fiber scene");
}

FiberTraceScene::~FiberTraceScene() = default;
FiberTraceScene::FiberTraceScene(FiberTraceScene&&) noexcept = default;
FiberTraceScene& FiberTraceScene::operator=(FiberTraceScene&&) noexcept = default;

size_t FiberTraceScene::segmentCount() const { return impl_->segments; }
size_t FiberTraceScene::fiberCount() const { return impl_->fibers; }
size_t FiberTraceScene::embreeBytes() const {
  return static_cast<size_t>(std::max<int64_t>(0, impl_->embreeBytes.load()));
}
size_t FiberTraceScene::bytes() const {
  const Impl& m = *impl_;
  return m.points.capacity() * sizeof(vec4) + m.tangents.capacity() * sizeof(vec3) +
         m.firstVertex.capacity() * sizeof(uint32_t) + m.neighbours.capacity() +
         m.stripOf.capacity() * sizeof(uint32_t) + m.strips.capacity() * sizeof(StripInfo) + embreeBytes();
}

namespace {

constexpr uint32_t kNoStrip = ~0u;

// A direction uniform in solid angle over the cone of half-angle alpha about
// the unit axis a, from two uniform numbers: cos θ = 1 − u0 (1 − cos α),
// ψ = 2π u1 about a.
glm::vec3 coneDirection(glm::vec3 a, double alpha, double u0, double u1) {
  const double cosT = 1.0 - u0 * (1.0 - std::cos(alpha)), sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
  const double psi = 2.0 * 3.14159265358979323846 * u1;
  const glm::dvec3 ad(a);
  const glm::dvec3 helper = std::abs(ad.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 b1 = glm::normalize(glm::cross(ad, helper)), b2 = glm::cross(ad, b1);
  return glm::vec3(glm::normalize(cosT * ad + sinT * (std::cos(psi) * b1 + std::sin(psi) * b2)));
}

// An intersection context that makes Embree skip the fiber a ray leaves
// (context filter: the scene carries RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION).
struct FilterContext {
  RTCIntersectContext embree;  // first: Embree hands its address back to the filter
  const uint32_t* stripOf;
  const StripInfo* strips;
  StripInfo own;               // the strip the ray leaves
};

// The far-field BCSDF lets light through the fiber it scatters from (000
// §4.3), so a ray ignores that fiber where it is "itself": in the yarn segment
// it leaves and the two next to it (which also covers grazing rays that run
// inside the tube), and closer than the length of the strip it leaves (which
// also covers a closed curve's seam, where segment numbers jump). The same
// fiber further along its yarn (the next loop of a knit) still occludes.
void ignoreOwnFiber(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const FilterContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const StripInfo& h = c->strips[c->stripOf[RTCHitN_primID(args->hit, args->N, i)]];
    if (h.fiber != c->own.fiber) continue;
    const bool adjacent = h.segment + 1u >= c->own.segment && h.segment <= c->own.segment + 1u;
    // Embree sets tfar to this hit's distance before calling the filter.
    if (adjacent || RTCRayN_tfar(args->ray, args->N, i) < c->own.length) args->valid[i] = 0;
  }
}

struct FiberHit {
  vec3 position;
  vec3 t;  // unit tangent
  vec3 n;  // unit normal, facing the ray
  uint32_t strip;
};

// Everything one render reads, shared by all tiles.
struct Render {
  const FiberTraceScene::Impl* scene;
  const ShadingParams* s;
  std::span<const vec3> ambientTable;
  const TraceOptions* options;
  int lights;

  FilterContext leaving(uint32_t strip) const {
    FilterContext ctx;
    rtcInitIntersectContext(&ctx.embree);
    ctx.stripOf = scene->stripOf.data();
    ctx.strips = scene->strips.data();
    if (strip != kNoStrip) {
      ctx.embree.filter = ignoreOwnFiber;
      ctx.own = scene->strips[strip];
    }
    return ctx;
  }

  // First fiber hit along org + τ dir (dir a unit vector), τ ∈ [0, tfar],
  // ignoring the fiber of `fromStrip` (ignoreOwnFiber) unless it is kNoStrip.
  bool intersect(vec3 org, vec3 dir, float tfar, uint32_t fromStrip, FiberHit& out) const {
    FilterContext ctx = leaving(fromStrip);
    RTCRayHit rh{};
    rh.ray.org_x = org.x, rh.ray.org_y = org.y, rh.ray.org_z = org.z;
    rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = tfar;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene->scene, &ctx.embree, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

    const uint32_t v0 = scene->firstVertex[rh.hit.primID];
    const vec3 chord = normalize(vec3(scene->points[v0 + 1]) - vec3(scene->points[v0]));
    const vec3 t0 = scene->tangents[v0], t1 = scene->tangents[v0 + 1];
    // The strip's rule (fiber_strip.geom.glsl): a vertex without a tangent takes the chord.
    const vec3 t = mix(dot(t0, t0) > 0.0f ? t0 : chord, dot(t1, t1) > 0.0f ? t1 : chord,
                       std::clamp(rh.hit.u, 0.0f, 1.0f));
    out.t = dot(t, t) > 0.0f ? normalize(t) : chord;
    const vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    out.n = normalize(dot(ng, dir) > 0.0f ? -ng : ng);
    out.position = org + rh.ray.tfar * dir;
    out.strip = scene->stripOf[rh.hit.primID];
    return true;
  }

  // Whether no fiber but that of `fromStrip` lies along p + τ ω, τ > 0 (ω a unit vector).
  bool unoccluded(vec3 p, vec3 w, uint32_t fromStrip) const {
    FilterContext ctx = leaving(fromStrip);
    RTCRay ray{};
    ray.org_x = p.x, ray.org_y = p.y, ray.org_z = p.z;
    ray.dir_x = w.x, ray.dir_y = w.y, ray.dir_z = w.z;
    ray.tnear = 0.0f;
    ray.tfar = std::numeric_limits<float>::infinity();
    ray.mask = ~0u;
    rtcOccluded1(scene->scene, &ctx.embree, &ray);
    return ray.tfar >= 0.0f;  // Embree sets tfar to −∞ on a hit
  }

  // Σ_i ftFiberDirect(s, i, t, n, ω_o) V_i. With lightAngularRadius α > 0
  // each light is a cone of directions of half-angle α about its direction,
  // of uniform radiance: V_i is then one shadow ray along a direction drawn
  // uniformly in solid angle over the cone (cos θ uniform in [cos α, 1], ψ
  // uniform), an unbiased estimate of the visible fraction; the BCSDF stays
  // at the cone's axis, as the frame's PCSS only softens the visibility
  // (docs/soft-shadows.md).
  vec3 direct(const FiberHit& h, vec3 wo, RandomStream& rng, TraceStats& stats) const {
    vec3 sum(0.0f);
    for (int i = 0; i < lights; ++i) {
      const vec3 c = ftFiberDirect(*s, i, h.t, h.n, wo);
      if (c == vec3(0.0f)) continue;
      if (options->shadows) {
        ++stats.shadowRays;
        vec3 w = normalize(vec3(s->lightDirection[i]));
        if (options->lightAngularRadius > 0.0) w = coneDirection(w, options->lightAngularRadius, rng.next(), rng.next());
        if (!unoccluded(h.position, w, h.strip)) continue;
      }
      sum += c;
    }
    return sum;
  }

  // ftFiberAmbient with A(θ_o) from the table (ftAmbientLookup, linear mix).
  vec3 ambient(const FiberHit& h, vec3 wo) const {
    const float thetaO = std::asin(std::clamp(dot(wo, h.t), -1.0f, 1.0f));  // ftFiberAngles' θ_o
    const vec3 k = ftAmbientLookup(thetaO, FT_AMBIENT_TABLE_SIZE);
    return ftFiberAmbient(*s, mix(ambientTable[size_t(k.x)], ambientTable[size_t(k.y)], k.z));
  }

  // ---- Environment map (options->environment) ----
  // Solid-angle density of the BCSDF mixture at ω: its density per dθ dφ over cos θ_i.
  static double scatterPdf(const FiberScatter& scatter, vec3 t, vec3 w) {
    const double st = std::clamp(double(dot(w, t)), -1.0, 1.0);
    const double ct = std::sqrt(std::max(0.0, 1.0 - st * st));
    const double a = scatter.angularDensity(w);
    return ct > 1e-9 ? a / ct : (a > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  }
  static double powerWeight(double a, double b) {
    if (std::isinf(a)) return 1.0;
    if (std::isinf(b)) return 0.0;
    const double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
  }
  // h(ω) of fiber_shading.h per unit radiance from ω (the direct term of a
  // unit light from ω).
  vec3 response(const FiberHit& h, vec3 wo, vec3 w) const {
    ShadingParams unit = *s;
    unit.flags.x = 1u;
    unit.lightDirection[0] = vec4(w, 0.0f);
    unit.lightIrradiance[0] = vec4(1.0f, 1.0f, 1.0f, 0.0f);
    return ftFiberDirect(unit, 0, h.t, h.n, wo);
  }
  // The map's own sample at a hit, MIS-weighted against the BCSDF's
  // (`visible`: trace its visibility).
  vec3 environmentLight(const FiberHit& h, vec3 wo, const FiberScatter& scatter, RandomStream& rng, bool visible,
                        TraceStats& stats) const {
    const EnvironmentSampler& env = *options->environment;
    if (!env.samplable()) return vec3(0.0f);
    const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next();
    const EnvironmentSampler::Sample e = env.sample(u0, u1, u2);
    if (!(e.pdf > 0.0)) return vec3(0.0f);
    const vec3 w(e.w);
    const vec3 f = response(h, wo, w);
    if (f == vec3(0.0f)) return vec3(0.0f);
    if (visible) {
      ++stats.shadowRays;
      if (!unoccluded(h.position, w, h.strip)) return vec3(0.0f);
    }
    const double pb = scatter.scatters() ? scatterPdf(scatter, h.t, w) : 0.0;
    return e.radiance * f * float(powerWeight(e.pdf, pb) / e.pdf);
  }
  // The map seen along a BCSDF-sampled ω that escaped, MIS-weighted.
  vec3 environmentEscape(const FiberScatter& scatter, vec3 t, vec3 w) const {
    const EnvironmentSampler& env = *options->environment;
    const double pb = scatterPdf(scatter, t, w);
    return env.radiance(glm::dvec3(w)) * float(powerWeight(pb, env.pdf(glm::dvec3(w))));
  }
  // Direct mode: the map's sample plus one BCSDF sample (in place of the ambient term).
  vec3 environmentDirect(const FiberHit& h, vec3 wo, RandomStream& rng, TraceStats& stats) const {
    const FiberScatter scatter(*s, h.t, h.n, wo);
    vec3 sum = environmentLight(h, wo, scatter, rng, options->shadows, stats);
    if (!scatter.scatters()) return sum;
    const vec3 wi = scatter.sample(rng);
    const vec3 weight = scatter.weight(wi);
    if (weight == vec3(0.0f)) return sum;
    if (options->shadows) {
      ++stats.shadowRays;
      if (!unoccluded(h.position, wi, h.strip)) return sum;
    }
    return sum + weight * environmentEscape(scatter, h.t, wi);
  }

  // The path tracer (traceFibers, multiple scattering) from a camera hit.
  vec3 path(FiberHit h, vec3 wo, RandomStream& rng, TraceStats& stats) const {
    vec3 radiance(0.0f), throughput(1.0f);
    const bool env = options->environment != nullptr;
    for (int depth = 1;; ++depth) {
      radiance += throughput * direct(h, wo, rng, stats);
      if (env) radiance += throughput * environmentLight(h, wo, FiberScatter(*s, h.t, h.n, wo), rng, true, stats);
      if (depth == options->maxDepth) {
        ++stats.truncatedPaths;
        break;
      }
      const FiberScatter scatter(*s, h.t, h.n, wo);
      if (!scatter.scatters()) break;
      const vec3 wi = scatter.sample(rng);
      throughput *= scatter.weight(wi);
      if (throughput == vec3(0.0f)) break;
      if (options->russianRoulette && depth >= 3) {  // Russian roulette
        const float q = std::min(1.0f, std::max({throughput.x, throughput.y, throughput.z}));
        if (rng.next() >= q) break;
        throughput /= q;
      }
      ++stats.bounceRays;
      FiberHit next;
      if (!intersect(h.position, wi, std::numeric_limits<float>::infinity(), h.strip, next)) {
        if (env) radiance += throughput * environmentEscape(scatter, h.t, wi);  // the map, MIS-weighted
        else radiance += throughput * vec3(s->ambient);  // the uniform environment
        break;
      }
      h = next;
      wo = -wi;
    }
    return radiance;
  }
};

// Sample k of n in the unit pixel: a jittered g×g grid when n = g², a Latin
// hypercube (x stratum k, y stratum perm[k]) otherwise (empty perm: square).
glm::dvec2 pixelSample(int k, int n, int g, std::span<const int> perm, RandomStream& rng) {
  const double jx = rng.next(), jy = rng.next();
  if (perm.empty()) return {(k % g + jx) / g, (k / g + jy) / g};
  return {(k + jx) / n, (perm[k] + jy) / n};
}

constexpr int kTile = 16;
constexpr uint32_t kPermutationStream = ~0u;  // RandomStream sample index of a pixel's Latin-hypercube permutation

// Collects the distinct fibers a ray passes (rejecting every hit, so Embree
// goes on to the next), after ignoreOwnFiber's test.
struct CrossingContext {
  FilterContext filter;  // first: Embree hands its address back
  uint32_t fibers[64];
  uint32_t count, cap;
};

void collectFibers(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<CrossingContext*>(args->context);
  if (c->filter.own.fiber != ~0u) ignoreOwnFiber(args);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    args->valid[i] = 0;
    const uint32_t fiber = c->filter.strips[c->filter.stripOf[RTCHitN_primID(args->hit, args->N, i)]].fiber;
    if (c->count >= c->cap || std::find(c->fibers, c->fibers + c->count, fiber) != c->fibers + c->count) continue;
    c->fibers[c->count++] = fiber;
  }
}

}  // namespace

uint32_t FiberTraceScene::fibersCrossed(glm::vec3 p, glm::vec3 w, uint32_t fromStrip, uint32_t cap) const {
  CrossingContext c{};
  rtcInitIntersectContext(&c.filter.embree);
  c.filter.embree.filter = collectFibers;
  c.filter.stripOf = impl_->stripOf.data();
  c.filter.strips = impl_->strips.data();
  c.filter.own = fromStrip == kNoStrip ? StripInfo{~0u, 0, 0.0f, 0} : impl_->strips[fromStrip];
  c.cap = std::min<uint32_t>(cap, 64);
  RTCRay ray{};
  ray.org_x = p.x, ray.org_y = p.y, ray.org_z = p.z;
  ray.dir_x = w.x, ray.dir_y = w.y, ray.dir_z = w.z;
  ray.tnear = 0.0f;
  ray.tfar = std::numeric_limits<float>::infinity();
  ray.mask = ~0u;
  rtcOccluded1(impl_->scene, &c.filter.embree, &ray);
  return c.count;
}

TraceResult traceFibers(const FiberTraceScene& scene, const Camera& camera, const ShadingParams& s,
                        std::span<const glm::vec3> ambientTable, const TraceOptions& options) {
  if (options.samplesPerPixel < 1)
    throw std::invalid_argument(fmt::format("traceFibers: samplesPerPixel {} < 1", options.samplesPerPixel));
  if (!options.samplePositions.empty() && options.samplePositions.size() != size_t(options.samplesPerPixel))
    throw std::invalid_argument(fmt::format("traceFibers: {} sample positions for {} samples per pixel",
                                            options.samplePositions.size(), options.samplesPerPixel));
  if (options.multipleScattering && options.maxDepth < 1)
    throw std::invalid_argument(fmt::format("traceFibers: maxDepth {} < 1", options.maxDepth));
  if (!(options.lightAngularRadius >= 0.0 && options.lightAngularRadius <= 3.14159265358979323846 / 3.0))
    throw std::invalid_argument(
        fmt::format("traceFibers: lightAngularRadius {} rad outside [0, 60°]", options.lightAngularRadius));
  if (camera.width < 1 || camera.height < 1)
    throw std::invalid_argument(fmt::format("traceFibers: image {}x{}", camera.width, camera.height));
  if (s.flags.x > FT_MAX_LIGHTS)
    throw std::invalid_argument(fmt::format("traceFibers: {} lights, at most {}", s.flags.x, FT_MAX_LIGHTS));
  if (!options.multipleScattering && ambientTable.size() != FT_AMBIENT_TABLE_SIZE)
    throw std::invalid_argument(fmt::format("traceFibers: ambient table of {} texels, expected {}",
                                            ambientTable.size(), FT_AMBIENT_TABLE_SIZE));

  const Render render{scene.impl_.get(), &s, ambientTable, &options, static_cast<int>(s.flags.x)};
  const glm::dmat4 toWorld = glm::inverse(glm::dmat4(camera.projection()) * glm::dmat4(camera.view()));
  const int width = camera.width, height = camera.height, spp = options.samplesPerPixel;
  const vec3 background(s.background);

  TraceResult result{ImageRgbaF(width, height), {}, std::vector<uint8_t>(size_t(width) * height, 0),
                     std::vector<uint8_t>(size_t(width) * height, kNoFiberType)};
  const int tilesX = (width + kTile - 1) / kTile, tilesY = (height + kTile - 1) / kTile;
  std::atomic<uint64_t> totals[6] = {};
  int tilesDone = 0;  // guarded by progressMutex
  std::mutex progressMutex;

  const int grid = static_cast<int>(std::lround(std::sqrt(double(spp))));
  const bool square = grid * grid == spp;
  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 1), [&](const tbb::blocked_range<int>& tiles) {
    std::vector<int> perm(square ? 0 : spp);
    for (int tile = tiles.begin(); tile != tiles.end(); ++tile) {
      TraceStats stats;
      const int x0 = (tile % tilesX) * kTile, y0 = (tile / tilesX) * kTile;
      for (int y = y0; y < std::min(y0 + kTile, height); ++y)
        for (int x = x0; x < std::min(x0 + kTile, width); ++x) {
          const uint32_t pixel = static_cast<uint32_t>(y) * static_cast<uint32_t>(width) + static_cast<uint32_t>(x);
          if (!square) {
            std::iota(perm.begin(), perm.end(), 0);
            RandomStream shuffle(pixel, kPermutationStream, options.seed);
            for (int i = spp - 1; i > 0; --i) std::swap(perm[i], perm[static_cast<int>(shuffle.next() * (i + 1.0))]);
          }
          glm::dvec3 sum(0.0);
          int hits = 0;
          uint32_t firstStrip = kNoStrip;
          bool oneStrip = true;
          int typeCount[4] = {0, 0, 0, 0};
          for (int k = 0; k < spp; ++k) {
            RandomStream rng(pixel, static_cast<uint32_t>(k), options.seed);
            const glm::dvec2 j = options.samplePositions.empty() ? pixelSample(k, spp, grid, perm, rng)
                                                                 : glm::dvec2(options.samplePositions[k]);
            const glm::dvec2 ndc(2.0 * (x + j.x) / width - 1.0, 1.0 - 2.0 * (y + j.y) / height);
            const glm::dvec4 nearH = toWorld * glm::dvec4(ndc, -1.0, 1.0), farH = toWorld * glm::dvec4(ndc, 1.0, 1.0);
            const glm::dvec3 nearP = glm::dvec3(nearH) / nearH.w, span = glm::dvec3(farH) / farH.w - nearP;
            const double length = glm::length(span);
            const vec3 org(nearP), dir(span / length);
            ++stats.cameraRays;
            FiberHit h;
            if (!render.intersect(org, dir, static_cast<float>(length), kNoStrip, h)) {
              sum += glm::dvec3(background);
              continue;
            }
            ++hits;
            if (firstStrip == kNoStrip) firstStrip = h.strip;
            ++typeCount[std::min<uint32_t>(render.scene->strips[h.strip].type, 3u)];
            oneStrip = oneStrip && h.strip == firstStrip;
            const vec3 L = options.multipleScattering ? render.path(h, -dir, rng, stats)
                           : options.environment ? render.direct(h, -dir, rng, stats) + render.environmentDirect(h, -dir, rng, stats)
                                                 : render.direct(h, -dir, rng, stats) + render.ambient(h, -dir);
            if (!std::isfinite(L.x) || !std::isfinite(L.y) || !std::isfinite(L.z)) {
              ++stats.nonFinite;
              continue;
            }
            sum += glm::dvec3(L);
            if (options.onHit)
              options.onHit(TraceSample{pixel, h.position, h.t, h.n, -dir, L, h.strip,
                                        render.scene->strips[h.strip].type});
          }
          float* px = result.image.at(x, y);
          const glm::dvec3 mean = sum / double(spp);
          px[0] = static_cast<float>(mean.x);
          px[1] = static_cast<float>(mean.y);
          px[2] = static_cast<float>(mean.z);
          px[3] = static_cast<float>(double(hits) / spp);
          result.singleStrip[pixel] = hits == spp && oneStrip;
          if (hits > 0) result.fiberType[pixel] = static_cast<uint8_t>(std::max_element(typeCount, typeCount + 4) - typeCount);
          stats.hitSamples += static_cast<uint64_t>(hits);
        }
      const uint64_t counts[6] = {stats.cameraRays, stats.shadowRays,     stats.bounceRays,
                                  stats.hitSamples, stats.truncatedPaths, stats.nonFinite};
      for (int i = 0; i < 6; ++i) totals[i].fetch_add(counts[i], std::memory_order_relaxed);
      if (options.progress) {
        const std::lock_guard lock(progressMutex);
        options.progress(double(++tilesDone) / (tilesX * tilesY));
      }
    }
  });
  result.stats = {totals[0].load(), totals[1].load(), totals[2].load(),
                  totals[3].load(), totals[4].load(), totals[5].load()};
  return result;
}

}  // namespace ft
