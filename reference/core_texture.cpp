#include "reference/core_texture.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ft {

namespace {

CoreTexture emptyTexture(const CoreTextureParams& c) {
  CoreTexture t;
  t.columns = c.columns;
  t.height = c.height;
  t.tex0.assign(size_t(c.columns) * c.height, glm::vec4(0.0f));
  t.tex1.assign(size_t(c.columns) * c.height, glm::vec4(0.0f));
  return t;
}

struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

}  // namespace

CoreTexture bakeCoreTextureEmbree(const CoreTextureInput& input) {
  const CoreTextureParams& c = input.params;
  CoreTexture out = emptyTexture(c);
  // Segments that a ray with z ∈ [0, α] can meet (z within r_f of a segment),
  // plus one on each side: the texture's ± α copies (notes A1) are the helix
  // itself continued past θ = 0 and 2π.
  const double dz = double(c.alpha) / c.segmentsPerTwist;
  const int kMin = int(std::floor(-double(c.fiberRadius) / dz)) - 1;
  const int kMax = int(std::floor((double(c.alpha) + c.fiberRadius) / dz)) + 1;
  const int perFiber = kMax - kMin + 1;  // segments
  const float step = ftCoreTwistStep(c);
  std::vector<glm::vec4> points;
  std::vector<uint32_t> first;
  points.reserve(input.fibers.size() * size_t(perFiber + 1));
  for (const glm::vec4& f : input.fibers) {
    const uint32_t base = uint32_t(points.size());
    for (int k = kMin; k <= kMax + 1; ++k) points.push_back(glm::vec4(ftCoreHelixPoint(c, f, float(k) * step), c.fiberRadius));
    for (int s = 0; s < perFiber; ++s) first.push_back(base + uint32_t(s));
  }

  EmbreeScene e;
  e.device = rtcNewDevice(nullptr);
  if (!e.device) throw std::runtime_error("core texture: Embree rtcNewDevice failed");
  e.scene = rtcNewScene(e.device);
  RTCGeometry geom = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, points.data(), 0, sizeof(glm::vec4),
                             points.size());
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, first.data(), 0, sizeof(uint32_t),
                             first.size());
  rtcCommitGeometry(geom);
  rtcAttachGeometry(e.scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(e.scene);
  if (rtcGetDeviceError(e.device) != RTC_ERROR_NONE) throw std::runtime_error("core texture: Embree scene build failed");

  tbb::parallel_for(uint32_t(0), c.height, [&](uint32_t j) {
    RTCIntersectContext ctx;
    for (uint32_t i = 0; i < c.columns; ++i) {
      rtcInitIntersectContext(&ctx);
      const glm::vec3 o = ftCoreTexelOrigin(c, i, j);
      RTCRayHit rh{};
      rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
      rh.ray.dir_x = -1.0f, rh.ray.dir_y = 0.0f, rh.ray.dir_z = 0.0f;
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = 2.0f * c.rayStart + c.fiberRadius;  // through the whole core
      rh.ray.mask = ~0u;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(e.scene, &ctx, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      const uint32_t fiber = rh.hit.primID / uint32_t(perFiber);
      const int k = kMin + int(rh.hit.primID % uint32_t(perFiber));
      const float theta0 = (float(k) + std::clamp(rh.hit.u, 0.0f, 1.0f)) * step;
      const glm::vec3 p = o + glm::vec3(-rh.ray.tfar, 0.0f, 0.0f);
      const CoreTexel t = ftCoreTexelAt(c, input.fibers[fiber], p, theta0);
      out.tex0[size_t(j) * c.columns + i] = t.tex0;
      out.tex1[size_t(j) * c.columns + i] = t.tex1;
    }
  });
  return out;
}

CoreTexture bakeCoreTextureCapsules(const CoreTextureInput& input) {
  const CoreTextureParams& c = input.params;
  CoreTexture out = emptyTexture(c);
  tbb::parallel_for(uint32_t(0), c.height, [&](uint32_t j) {
    for (uint32_t i = 0; i < c.columns; ++i) {
      const glm::vec3 o = ftCoreTexelOrigin(c, i, j);
      glm::vec3 best(0.0f);
      uint32_t bestFiber = 0;
      for (uint32_t f = 0; f < input.fibers.size(); ++f) {
        const glm::vec3 hit = ftCoreFiberCapsuleHit(c, input.fibers[f], o);
        if (hit.z != 0.0f && (best.z == 0.0f || hit.x > best.x)) best = hit, bestFiber = f;
      }
      if (best.z == 0.0f) continue;
      const CoreTexel t = ftCoreTexelAt(c, input.fibers[bestFiber], glm::vec3(best.x, o.y, o.z), best.y);
      out.tex0[size_t(j) * c.columns + i] = t.tex0;
      out.tex1[size_t(j) * c.columns + i] = t.tex1;
    }
  });
  return out;
}

}  // namespace ft
