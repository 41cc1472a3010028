#include "reference/shadow_map_reference.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <limits>
#include <unordered_map>
#include <stdexcept>

#include "common/yarn_curve.h"

namespace ft {

ShadowTubes shadowTubes(const YarnBuffers& yarn, float radius) {
  ShadowTubes t;
  t.radius = radius;
  for (const SegmentRef& ref : yarn.segments) {
    const CurveInfo& c = yarn.curves[ref.curve];
    const SegmentIndices idx = ftSegmentIndices(c, ref.local);
    const auto& p = yarn.points;
    const YarnSegment s = ftMakeSegment(c, ref.local, idx, p[idx.i0].positionLength, p[idx.i1].positionLength,
                                        p[idx.i2].positionLength, p[idx.i3].positionLength);
    std::vector<glm::vec3> line;
    for (uint32_t k = 0; k <= FT_SHADOW_MAP_SUBSEGMENTS; ++k)
      line.push_back(ftBezierPoint(s, float(k) / float(FT_SHADOW_MAP_SUBSEGMENTS)));
    t.lines.push_back(std::move(line));
  }
  return t;
}

struct ShadowMapReference::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<glm::vec4> vertices;  // two per capsule: xyz, w radius (no shared vertices: every capsule has both balls)
  std::vector<uint32_t> firstVertex;
  float radius = 0.0f;
  float cell = 1.0f;
  std::unordered_map<int64_t, std::vector<uint32_t>> grid;  // cell → capsules whose bounds touch it
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

struct OccludeContext {
  RTCIntersectContext embree;  // first: Embree hands its address back to the filter
  const ShadowMapReference::Impl* impl;
  glm::vec3 point;
};

int64_t cellKey(glm::ivec3 c) {
  return (int64_t(c.x) & 0x1FFFFF) | ((int64_t(c.y) & 0x1FFFFF) << 21) | ((int64_t(c.z) & 0x1FFFFF) << 42);
}

double distanceToSegment(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
  const glm::dvec3 d = b - a;
  const double len2 = glm::dot(d, d);
  const double t = len2 > 0.0 ? glm::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * d));
}

// A capsule that contains the ray's origin does not occlude it (the far side is stored).
void skipContaining(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const OccludeContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const uint32_t v = c->impl->firstVertex[RTCHitN_primID(args->hit, args->N, i)];
    const double dist = distanceToSegment(glm::dvec3(c->point), glm::dvec3(glm::vec3(c->impl->vertices[v])),
                                          glm::dvec3(glm::vec3(c->impl->vertices[v + 1])));
    if (dist <= double(c->impl->radius)) args->valid[i] = 0;
  }
}

}  // namespace

ShadowMapReference::ShadowMapReference(const ShadowTubes& tubes) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.radius = tubes.radius;
  for (const auto& line : tubes.lines)
    for (size_t k = 0; k + 1 < line.size(); ++k) {
      m.firstVertex.push_back(uint32_t(m.vertices.size()));
      m.vertices.emplace_back(line[k], tubes.radius);
      m.vertices.emplace_back(line[k + 1], tubes.radius);
    }
  m.cell = std::max(2.0f * tubes.radius, 1e-6f);
  for (uint32_t prim = 0; prim < m.firstVertex.size(); ++prim) {
    const glm::vec3 a(m.vertices[m.firstVertex[prim]]), b(m.vertices[m.firstVertex[prim] + 1]);
    const glm::ivec3 lo(glm::floor((glm::min(a, b) - tubes.radius) / m.cell));
    const glm::ivec3 hi(glm::floor((glm::max(a, b) + tubes.radius) / m.cell));
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) m.grid[cellKey({x, y, z})].push_back(prim);
  }
  m.firstVertex.resize(m.firstVertex.size() + 4, 0u);  // Embree reads index buffers 16 bytes at a time
  m.vertices.resize(m.vertices.size() + 1, glm::vec4(0.0f));
  m.device = rtcNewDevice(nullptr);
  if (!m.device) throw std::runtime_error("Embree: rtcNewDevice failed (shadow-map reference)");
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  const size_t capsules = m.firstVertex.size() - 4;
  if (capsules > 0) {
    RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, m.vertices.data(), 0,
                               sizeof(glm::vec4), m.vertices.size() - 1);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, m.firstVertex.data(), 0, sizeof(uint32_t),
                               capsules);
    rtcCommitGeometry(g);
    rtcAttachGeometry(m.scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(m.scene);
  if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: building the shadow-map reference scene failed");
}

ShadowMapReference::~ShadowMapReference() = default;

size_t ShadowMapReference::capsuleCount() const { return impl_->firstVertex.size() - 4; }

// Whether x lies strictly inside some capsule (the union of the tubes): the
// capsules listed in x's grid cell (cells of 2R, each capsule listed in every
// cell its bounds touch).
static bool insideTubes(const ShadowMapReference::Impl& m, glm::vec3 x) {
  const glm::ivec3 c(glm::floor(x / m.cell));
  auto it = m.grid.find(cellKey(c));
  if (it == m.grid.end()) return false;
  for (uint32_t prim : it->second) {
    const uint32_t v = m.firstVertex[prim];
    if (distanceToSegment(glm::dvec3(x), glm::dvec3(glm::vec3(m.vertices[v])), glm::dvec3(glm::vec3(m.vertices[v + 1]))) <
        double(m.radius))
      return true;
  }
  return false;
}

// The light is blocked when the ray, having left the tube region it starts
// in (if any), enters a tube again: the mesh tube of notes A5 with its back
// faces stored. Each step finds the first capsule entry beyond `cur` that is
// not a capsule containing `cur`; an entry from inside another capsule is
// still inside the region (continue from there), an entry from outside every
// capsule is an occluder.
float ShadowMapReference::visibility(glm::vec3 p, glm::vec3 toLight) const {
  const glm::vec3 w = glm::normalize(toLight);
  const float eps = 1e-3f * impl_->radius;
  glm::vec3 cur = p;
  for (int step = 0; step < 4096; ++step) {
    OccludeContext ctx;
    rtcInitIntersectContext(&ctx.embree);
    ctx.embree.filter = skipContaining;
    ctx.impl = impl_.get();
    ctx.point = cur;
    RTCRayHit rh{};
    rh.ray.org_x = cur.x, rh.ray.org_y = cur.y, rh.ray.org_z = cur.z;
    rh.ray.dir_x = w.x, rh.ray.dir_y = w.y, rh.ray.dir_z = w.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &ctx.embree, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 1.0f;
    const glm::vec3 hit = cur + rh.ray.tfar * w;
    if (!insideTubes(*impl_, hit - eps * w)) return 0.0f;
    cur = hit + eps * w;
  }
  throw std::runtime_error("ShadowMapReference: more than 4096 capsule entries along one ray");
}

std::vector<float> ShadowMapReference::visibility(std::span<const glm::vec3> points, glm::vec3 toLight) const {
  std::vector<float> out(points.size());
  tbb::parallel_for(size_t(0), points.size(), [&](size_t i) { out[i] = visibility(points[i], toLight); });
  return out;
}

float shadowMapLookup(const ShadowMapParams& m, std::span<const float> texels, int light, glm::vec3 p) {
  const vec3 c = ftShadowNdcToMap(ftShadowNdc(m, ftShadowLightSpace(m, light, p)));
  const ivec4 t = ftShadowTexel(m, c);
  if (t.w < 0) return 1.0f;
  const auto verdict = [&](int x, int y) {
    const uint32_t k = ftShadowMapIndex(m, light, x, y);
    if (k >= texels.size()) throw std::out_of_range(fmt::format("shadowMapLookup: texel {} of {}", k, texels.size()));
    return ftShadowVisibility(c.z, texels[k]);
  };
  if (m.count.z != FT_SHADOW_FILTER_PCF) return verdict(t.x, t.y);
  const int n = int(m.count.y);
  const vec4 f = ftShadowPcfFootprint(c, n);
  const int x0 = ftShadowPcfTexel(f.x, 0, n), x1 = ftShadowPcfTexel(f.x, 1, n);
  const int y0 = ftShadowPcfTexel(f.y, 0, n), y1 = ftShadowPcfTexel(f.y, 1, n);
  return ftShadowPcfCombine(f, verdict(x0, y0), verdict(x1, y0), verdict(x0, y1), verdict(x1, y1));
}

}  // namespace ft
