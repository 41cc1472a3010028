// prt_multiple_scattering.cpp — CPU reference of 004 §4.2, §4.3, §5.3.1
// (reference/prt_multiple_scattering.h).
#include "reference/prt_multiple_scattering.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/fiber_shading.h"
#include "reference/bcsdf_sampling.h"
#include "reference/numbers.h"
#include "scene/input_error.h"

namespace ft {

namespace {
constexpr int kJ = FT_SH_COEFFS;
}  // namespace

// ---- tables ---------------------------------------------------------------------

std::vector<double> prtMsPhiCpu(const FabricParams& p, int nTheta, int nPhi) {
  if (nTheta < 2 || nPhi < 2) throw InputError(fmt::format("C_S quadrature: {} θ_i and {} φ nodes (≥ 2 each)", nTheta, nPhi));
  std::vector<double> phi(size_t(2) * size_t(nTheta) * kJ, 0.0);
  tbb::parallel_for(0, nTheta, [&](int i) {
    const double th = prtMsThetaINode(i, nTheta);
    double r[kJ] = {}, tt[kJ] = {};
    const double dphi = 2.0 * kPi / nPhi;
    for (int k = 0; k < nPhi; ++k) {
      const double ph = prtMsPhiNode(k, nPhi);
      const ShCoeffs y = shEval(prtMsOmegaOSpaceDirection(th, ph));
      const double ntt = prtMsAzimuthTT(p, ph);
      for (int j = 0; j < kJ; ++j) r[j] += y.c[j] * dphi, tt[j] += y.c[j] * ntt * dphi;
    }
    for (int j = 0; j < kJ; ++j) {
      phi[(size_t(0) * nTheta + size_t(i)) * kJ + size_t(j)] = r[j];
      phi[(size_t(1) * nTheta + size_t(i)) * kJ + size_t(j)] = tt[j];
    }
  });
  return phi;
}

PrtMsTables prtMsTablesCpu(const FabricParams& p, int nTheta, int nPhi) {
  const std::vector<double> phi = prtMsPhiCpu(p, nTheta, nPhi);
  PrtMsTables t;
  t.cs.assign(size_t(t.thetaO) * kJ * 3, 0.0);
  tbb::parallel_for(0, t.thetaO, [&](int o) {
    const double thetaO = prtMsThetaONode(o, t.thetaO);
    double acc[kJ][3] = {};
    const double dtheta = kPi / nTheta;
    for (int i = 0; i < nTheta; ++i) {
      const double th = prtMsThetaINode(i, nTheta);
      const double c2 = std::cos(th) * std::cos(th) * dtheta;
      const glm::vec3 r = prtMsLobeR(p, th, thetaO), tt = prtMsLobeTT(p, th, thetaO);
      const double* pr = &phi[size_t(i) * kJ];
      const double* pt = &phi[(size_t(nTheta) + size_t(i)) * kJ];
      for (int j = 0; j < kJ; ++j)
        for (int ch = 0; ch < 3; ++ch) acc[j][ch] += c2 * (double(r[ch]) * pr[j] + double(tt[ch]) * pt[j]);
    }
    for (int j = 0; j < kJ; ++j)
      for (int ch = 0; ch < 3; ++ch) t.cs[(size_t(o) * kJ + size_t(j)) * 3 + size_t(ch)] = acc[j][ch];
  });
  t.cg.assign(size_t(t.lambdaNodes) * FT_SH_BANDS, 0.0);
  for (int k = 0; k < t.lambdaNodes; ++k) {
    const PrtMsZonal z = prtMsZonalSg(double(k) / double(t.lambdaNodes - 1));
    for (int l = 0; l < FT_SH_BANDS; ++l) t.cg[size_t(k) * FT_SH_BANDS + size_t(l)] = z.c[l];
  }
  return t;
}

// ---- the scene ------------------------------------------------------------------

struct IirtfScene::Impl {
  std::vector<ExemplarSegment> segments;
  glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
  std::vector<glm::vec4> points;
  std::vector<uint32_t> firstVertex, fiber;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

IirtfScene::IirtfScene(std::span<const ExemplarSegment> tiled) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.segments.assign(tiled.begin(), tiled.end());
  for (size_t k = 0; k < tiled.size(); ++k) {
    const ExemplarSegment& s = tiled[k];
    const bool finite = std::isfinite(s.a.x) && std::isfinite(s.a.y) && std::isfinite(s.a.z) &&
                        std::isfinite(s.b.x) && std::isfinite(s.b.y) && std::isfinite(s.b.z) && std::isfinite(s.radius);
    if (!finite || !(s.radius > 0.0f) || glm::distance(s.a, s.b) <= 0.0f)
      throw InputError(fmt::format("segment {}: ({}, {}, {}) – ({}, {}, {}), radius {}: needs finite distinct "
                                   "endpoints and a radius > 0",
                                   k, s.a.x, s.a.y, s.a.z, s.b.x, s.b.y, s.b.z, s.radius));
    m.points.emplace_back(s.a, s.radius);
    m.points.emplace_back(s.b, s.radius);
    m.firstVertex.push_back(uint32_t(2 * k));
    m.fiber.push_back(s.fiber);
    m.lo = glm::min(m.lo, glm::min(s.a, s.b) - s.radius);
    m.hi = glm::max(m.hi, glm::max(s.a, s.b) + s.radius);
  }
  m.device = rtcNewDevice(nullptr);
  if (!m.device) throw std::runtime_error("Embree: rtcNewDevice failed");
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  if (!tiled.empty()) {
    RTCGeometry geom = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, m.points.data(), 0,
                               sizeof(glm::vec4), m.points.size());
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, m.firstVertex.data(), 0,
                               sizeof(uint32_t), m.firstVertex.size());
    rtcCommitGeometry(geom);
    rtcAttachGeometry(m.scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(m.scene);
  if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the IIRTF scene failed");
}
IirtfScene::~IirtfScene() = default;
IirtfScene::IirtfScene(IirtfScene&&) noexcept = default;
IirtfScene& IirtfScene::operator=(IirtfScene&&) noexcept = default;
const std::vector<ExemplarSegment>& IirtfScene::segments() const { return impl_->segments; }

bool IirtfScene::entersThroughSide(glm::vec3 p, glm::vec3 w0) const {
  if (!(w0.z > 0.0f)) return true;
  const float t = std::max(0.0f, (impl_->hi.z - p.z) / w0.z);
  const glm::vec3 q = p + t * w0;
  return q.x < impl_->lo.x || q.x > impl_->hi.x || q.y < impl_->lo.y || q.y > impl_->hi.y;
}

namespace {
struct IgnoreFiberContext {
  RTCIntersectContext embree;  // first: Embree hands its address back to the filter
  const uint32_t* fiber;
  uint32_t ignore;
};
void ignoreFiber(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const IgnoreFiberContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 && c->fiber[RTCHitN_primID(args->hit, args->N, i)] == c->ignore) args->valid[i] = 0;
}
RTCRay makeRay(glm::vec3 o, glm::vec3 d) {
  RTCRay r{};
  r.org_x = o.x, r.org_y = o.y, r.org_z = o.z;
  r.dir_x = d.x, r.dir_y = d.y, r.dir_z = d.z;
  r.tnear = 0.0f;
  r.tfar = std::numeric_limits<float>::infinity();
  r.mask = ~0u;
  return r;
}
}  // namespace

bool IirtfScene::intersect(glm::vec3 org, glm::vec3 dir, uint32_t ignore, Hit& hit) const {
  IgnoreFiberContext ctx;
  rtcInitIntersectContext(&ctx.embree);
  ctx.embree.filter = ignoreFiber;
  ctx.fiber = impl_->fiber.data();
  ctx.ignore = ignore;
  RTCRayHit rh{};
  rh.ray = makeRay(org, dir);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx.embree, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.t = rh.ray.tfar;
  hit.segment = rh.hit.primID;
  glm::vec3 n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  const float len = glm::length(n);
  n = len > 0.0f ? n / len : -dir;
  if (glm::dot(n, dir) > 0.0f) n = -n;
  hit.normal = n;
  return true;
}

bool IirtfScene::occluded(glm::vec3 org, glm::vec3 dir, uint32_t ignore) const {
  IgnoreFiberContext ctx;
  rtcInitIntersectContext(&ctx.embree);
  ctx.embree.filter = ignoreFiber;
  ctx.fiber = impl_->fiber.data();
  ctx.ignore = ignore;
  RTCRay ray = makeRay(org, dir);
  rtcOccluded1(impl_->scene, &ctx.embree, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar to −∞ on a hit
}

// ---- settings, cells, ℓ ---------------------------------------------------------

void checkIirtfSettings(const IirtfSettings& s) {
  if (s.tiles < 1 || s.tiles > 31 || s.tiles % 2 == 0) throw InputError(fmt::format("--tiles: {} (odd, 1..31)", s.tiles));
  if (!(s.cellFactor > 0.0) || !std::isfinite(s.cellFactor) || s.cellFactor > 1e3)
    throw InputError(fmt::format("--cell-factor: {} (> 0)", s.cellFactor));
  if (!(s.cellSize >= 0.0) || !std::isfinite(s.cellSize)) throw InputError(fmt::format("--cell-size: {} (≥ 0)", s.cellSize));
  if (s.pathsPerCell < 1 || s.pathsPerCell > 100000000)
    throw InputError(fmt::format("--paths: {} (1..1e8)", s.pathsPerCell));
  if (s.maxDepth < 1 || s.maxDepth > 1024) throw InputError(fmt::format("--max-depth: {} (1..1024)", s.maxDepth));
  if (!(s.albedo >= 0.0) || s.albedo > 1.0) throw InputError(fmt::format("--albedo: {} (0..1)", s.albedo));
  if (s.ellPaths < 1 || s.ellPaths > 10000000) throw InputError(fmt::format("--ell-paths: {} (≥ 1)", s.ellPaths));
}

IirtfCells makeIirtfCells(const Exemplar& block, double target) {
  if (!(target > 0.0) || !std::isfinite(target)) throw InputError(fmt::format("cell side {}: must be > 0", target));
  IirtfCells c;
  double zlo = std::numeric_limits<double>::infinity(), zhi = -zlo;
  for (const ExemplarSegment& s : block.segments) zlo = std::min(zlo, double(s.mid().z)), zhi = std::max(zhi, double(s.mid().z));
  if (block.segments.empty()) zlo = zhi = 0.0;
  const double P = block.period, H = std::max(zhi - zlo, 1e-9);
  auto count = [&](double extent) { return std::clamp(int(std::lround(extent / target)), 1, 64); };
  c.nx = count(P), c.ny = count(P), c.nz = count(H);
  c.origin = glm::dvec3(0.0, 0.0, zlo);
  c.side = glm::dvec3(P / c.nx, P / c.ny, H / c.nz);
  c.members.resize(size_t(c.nx) * size_t(c.ny) * size_t(c.nz));
  for (size_t k = 0; k < block.segments.size(); ++k) {
    const glm::dvec3 m = glm::dvec3(block.segments[k].mid()) - c.origin;
    // Midpoints a little outside [0, P) (fibers reach past the block edge) go to the nearest cell.
    const int ix = std::clamp(int(std::floor(m.x / c.side.x)), 0, c.nx - 1);
    const int iy = std::clamp(int(std::floor(m.y / c.side.y)), 0, c.ny - 1);
    const int iz = std::clamp(int(std::floor(m.z / c.side.z)), 0, c.nz - 1);
    const uint32_t cell = uint32_t((iz * c.ny + iy) * c.nx + ix);
    c.cellOf.push_back(cell);
    c.members[cell].push_back(uint32_t(k));
  }
  return c;
}

namespace {

ShadingParams unitLight(const FabricParams& fabric, glm::vec3 w0) {
  ShadingParams s{};
  s.fabric = fabric;
  s.lightDirection[0] = vec4(w0, 0.0f);
  s.lightIrradiance[0] = vec4(1.0f, 1.0f, 1.0f, 0.0f);
  s.flags = uvec4(1u, FT_SHADING_KHUNGURN, 0u, 0u);
  return s;
}

glm::vec3 tangentOf(const ExemplarSegment& s) { return glm::normalize(s.b - s.a); }

// The common walk: from a fiber hit, NEE to ω0 and BCSDF continuation.
// `onScatter(distance)` sees each continuation that hits a fiber.
template <class OnScatter>
glm::dvec3 walk(const IirtfScene& scene, const ShadingParams& light, double albedo, int maxDepth, glm::vec3 p,
                glm::vec3 wo, IirtfScene::Hit hit, RandomStream& rng, uint64_t& rays, bool nee, OnScatter&& onScatter) {
  const std::vector<ExemplarSegment>& segs = scene.segments();
  const glm::vec3 w0 = glm::vec3(light.lightDirection[0]);
  glm::dvec3 L(0.0), throughput(1.0);
  for (int depth = 0; depth < maxDepth; ++depth) {
    const ExemplarSegment& seg = segs[hit.segment];
    const glm::vec3 t = tangentOf(seg);
    if (nee) {
      ++rays;
      if (!scene.entersThroughSide(p, w0) && !scene.occluded(p, w0, seg.fiber))
        L += throughput * albedo * glm::dvec3(ftFiberDirect(light, 0, t, hit.normal, wo));
    }
    const FiberScatter sc(light, t, hit.normal, wo);
    if (!sc.scatters()) break;
    const glm::vec3 wi = sc.sample(rng);
    throughput *= albedo * glm::dvec3(sc.weight(wi));
    if (depth + 1 >= 3) {  // Russian roulette after 3 scattering events
      const double q = std::min(0.95, std::max({throughput.x, throughput.y, throughput.z}));
      if (!(q > 0.0) || double(rng.next()) >= q) break;
      throughput /= q;
    }
    if (!(throughput.x + throughput.y + throughput.z > 0.0)) break;
    ++rays;
    IirtfScene::Hit next;
    if (!scene.intersect(p, wi, seg.fiber, next)) break;  // escapes: only the delta light, which NEE covers
    onScatter(double(next.t));
    p = p + next.t * wi;
    wo = -wi;
    hit = next;
  }
  return L;
}

}  // namespace

MeanFreePath estimateMeanFreePath(const IirtfScene& scene, const Exemplar& block, int tiles, const FabricParams& fabric,
                                  const IirtfSettings& s) {
  (void)tiles;
  double ztop = -std::numeric_limits<double>::infinity();
  for (const ExemplarSegment& seg : block.segments) ztop = std::max({ztop, double(seg.a.z), double(seg.b.z)});
  MeanFreePath r;
  double total = 0.0;
  const ShadingParams light = unitLight(fabric, glm::vec3(0, 0, 1));
  for (int i = 0; i < s.ellPaths; ++i) {
    RandomStream rng(0xFFFFFFFFu, uint32_t(i), s.seed);  // stream id past any segment index
    const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next(), u3 = rng.next();
    glm::dvec3 w0, w1;
    iirtfDirections(u0, u1, 0.5, 0.5, w0, w1);
    const glm::vec3 start(float(u2 * block.period), float(u3 * block.period), float(ztop + block.reach));
    const glm::vec3 dir = -glm::vec3(w0);
    IirtfScene::Hit hit;
    ++r.rays;
    if (!scene.intersect(start, dir, 0xFFFFFFFFu, hit)) continue;
    walk(scene, light, 1.0, s.maxDepth, start + hit.t * dir, -dir, hit, rng, r.rays, false, [&](double d) {
      total += d;
      ++r.distances;
    });
  }
  r.ell = r.distances ? total / double(r.distances) : 0.0;
  return r;
}

void iirtfDirections(double u0, double u1, double u2, double u3, glm::dvec3& w0, glm::dvec3& w1) {
  const double z0 = u0, r0 = std::sqrt(std::max(0.0, 1.0 - z0 * z0)), p0 = 2.0 * kPi * u1;
  w0 = glm::dvec3(r0 * std::cos(p0), r0 * std::sin(p0), z0);
  const double z1 = 1.0 - 2.0 * u2, r1 = std::sqrt(std::max(0.0, 1.0 - z1 * z1)), p1 = 2.0 * kPi * u3;
  w1 = glm::dvec3(r1 * std::cos(p1), r1 * std::sin(p1), z1);
}

void iirtfAccumulate(std::span<double> sum, glm::dvec3 T, glm::dvec3 w0, glm::dvec3 w1, std::span<double> sumSq) {
  if (T.x == 0.0 && T.y == 0.0 && T.z == 0.0) return;
  const ShCoeffs y0 = shEval(w0), y1 = shEval(w1);
  const double inv = (2.0 * kPi) * (4.0 * kPi);  // 1 / (p(ω0) p(ω1))
  const bool second = !sumSq.empty();
  for (int ch = 0; ch < 3; ++ch) {
    const double t = T[ch] * inv;
    double* row = &sum[size_t(ch) * kJ * kJ];
    double* rowSq = second ? &sumSq[size_t(ch) * kJ * kJ] : nullptr;
    for (int j1 = 0; j1 < kJ; ++j1) {
      const double a = t * y1.c[j1];
      for (int j0 = 0; j0 < kJ; ++j0) {
        const double term = a * y0.c[j0];
        row[j1 * kJ + j0] += term;
        if (second) rowSq[j1 * kJ + j0] += term * term;
      }
    }
  }
}

glm::dvec3 iirtfPathRadiance(const IirtfScene& scene, const FabricParams& fabric, double albedo, int maxDepth,
                             glm::vec3 x, uint32_t ownFiber, glm::vec3 w0, glm::vec3 w1, uint32_t stream, uint32_t path,
                             uint32_t seed, uint64_t& rays) {
  RandomStream rng(stream, path, seed ^ 0x9E3779B9u);  // the walk's numbers; the directions used (stream, path, seed)
  IirtfScene::Hit hit;
  ++rays;
  if (!scene.intersect(x, w1, ownFiber, hit)) return glm::dvec3(0.0);  // no fiber point on the path: not in T
  return walk(scene, unitLight(fabric, w0), albedo, maxDepth, x + hit.t * w1, -w1, hit, rng, rays, true, [](double) {});
}

namespace {

// Paths [first, first + count) of block segment k, summed in path order.
void segmentRange(const IirtfScene& scene, const Exemplar& block, int tiles, const FabricParams& fabric,
                  const IirtfSettings& s, uint32_t k, uint32_t first, uint32_t count, std::span<double> sum,
                  std::span<double> sumSq, uint64_t& rays) {
  const size_t S = block.segments.size();
  const ExemplarSegment& own = scene.segments()[centreCopy(tiles) * S + k];
  const glm::vec3 x = own.mid();
  for (uint32_t i = first; i < first + count; ++i) {
    RandomStream rng(k, i, s.seed);
    const double u0 = rng.next(), u1 = rng.next(), u2 = rng.next(), u3 = rng.next();
    glm::dvec3 w0, w1;
    iirtfDirections(u0, u1, u2, u3, w0, w1);
    const glm::dvec3 T = iirtfPathRadiance(scene, fabric, s.albedo, s.maxDepth, x, own.fiber, glm::vec3(w0),
                                           glm::vec3(w1), k, i, s.seed, rays);
    iirtfAccumulate(sum, T, w0, w1, sumSq);
  }
}

constexpr uint32_t kPathBlock = 256;  // paths per task: the sums' grouping, fixed whatever the threads

// Σ over paths [0, n) of segment k as blocks of kPathBlock summed in order.
struct SegmentTask {
  uint32_t k, first, count;
};

}  // namespace

std::vector<double> iirtfSegmentSum(const IirtfScene& scene, const Exemplar& block, int tiles, const FabricParams& fabric,
                                    const IirtfSettings& s, uint32_t k, int paths, uint64_t& rays) {
  IirtfCell c = iirtfCellCpu(scene, block, tiles, fabric, [&] {
    IirtfSettings one = s;
    one.pathsPerCell = paths;
    return one;
  }(), std::vector<uint32_t>{k});
  for (double& v : c.a) v *= double(c.paths);
  rays += c.rays;
  return c.a;
}

IirtfCell iirtfCellCpu(const IirtfScene& scene, const Exemplar& block, int tiles, const FabricParams& fabric,
                       const IirtfSettings& s, const std::vector<uint32_t>& members) {
  IirtfCell cell;
  cell.a.assign(kIirtfMatrixSize, 0.0);
  cell.stdError.assign(kIirtfMatrixSize, 0.0);
  if (members.empty()) return cell;
  const size_t C = members.size();
  const uint32_t perSegment = uint32_t((size_t(s.pathsPerCell) + C - 1) / C);
  std::vector<SegmentTask> tasks;
  for (uint32_t k : members) {
    if (k >= block.segments.size()) throw std::out_of_range(fmt::format("IIRTF cell: segment {} of {}", k, block.segments.size()));
    for (uint32_t f = 0; f < perSegment; f += kPathBlock) tasks.push_back({k, f, std::min(kPathBlock, perSegment - f)});
  }
  std::vector<std::vector<double>> sums(tasks.size()), sumsSq(tasks.size());
  std::vector<uint64_t> rays(tasks.size(), 0);
  tbb::parallel_for(size_t(0), tasks.size(), [&](size_t t) {
    sums[t].assign(kIirtfMatrixSize, 0.0);
    sumsSq[t].assign(kIirtfMatrixSize, 0.0);
    segmentRange(scene, block, tiles, fabric, s, tasks[t].k, tasks[t].first, tasks[t].count, sums[t], sumsSq[t],
                 rays[t]);
  });
  // 004 §4.2c: (1/|C|) T Y Y / (p(k) p(ω0) p(ω1)) with p(k) = 1/|C|, averaged over the paths.
  // The variance: per segment (the tasks of a segment are consecutive) when it has ≥ 2 paths.
  const double n = double(perSegment);
  std::vector<double> segSum(kIirtfMatrixSize), segSq(kIirtfMatrixSize), pooledSq(kIirtfMatrixSize, 0.0);
  for (size_t t = 0; t < tasks.size();) {
    std::fill(segSum.begin(), segSum.end(), 0.0);
    std::fill(segSq.begin(), segSq.end(), 0.0);
    const uint32_t k = tasks[t].k;
    for (; t < tasks.size() && tasks[t].k == k; ++t) {
      for (size_t i = 0; i < kIirtfMatrixSize; ++i)
        cell.a[i] += sums[t][i], segSum[i] += sums[t][i], segSq[i] += sumsSq[t][i];  // a: task order, as before
      cell.rays += rays[t];
    }
    for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
      pooledSq[i] += segSq[i];
      if (perSegment >= 2) cell.stdError[i] += std::max(0.0, segSq[i] - segSum[i] * segSum[i] / n) / ((n - 1.0) * n);
    }
  }
  cell.paths = uint64_t(perSegment) * C;
  const double N = double(cell.paths);
  for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
    if (perSegment >= 2) {
      cell.stdError[i] = std::sqrt(cell.stdError[i]) / (FT_FAULT_MS_STDERR_CELL_COUNT_ON ? 1.0 : double(C));
    } else if (cell.paths >= 2) {
      const double mean = cell.a[i] / N;
      cell.stdError[i] = std::sqrt(std::max(0.0, pooledSq[i] - N * mean * mean) / ((N - 1.0) * N));
    } else {
      cell.stdError[i] = std::numeric_limits<double>::infinity();
    }
  }
  for (double& v : cell.a) v /= N;
  return cell;
}

int prtMsNoiseCut(IirtfCell& cell, double cut) {
  if (cell.a.size() != kIirtfMatrixSize || cell.stdError.size() != kIirtfMatrixSize)
    throw std::invalid_argument(fmt::format("prtMsNoiseCut: {} entries, {} standard errors", cell.a.size(), cell.stdError.size()));
  double se2[FT_SH_BANDS] = {}, a2[FT_SH_BANDS] = {};
  for (size_t i = 0; i < kIirtfMatrixSize; ++i) {
    const int l = iirtfEntryBand(i);
    se2[l] += cell.stdError[i] * cell.stdError[i], a2[l] += cell.a[i] * cell.a[i];
  }
  int keep = 1;
  while (keep < FT_SH_BANDS && !(se2[keep] > cut * cut * a2[keep])) ++keep;
  for (size_t i = 0; i < kIirtfMatrixSize; ++i)
    if (iirtfEntryBand(i) >= keep) cell.a[i] = 0.0;
  return keep;
}

glm::dvec3 prtMsRadianceCpu(const PrtMsTables& tables, std::span<const double> a, int bands, const PrtMsQuery& q) {
  if (a.size() != kIirtfMatrixSize || bands < 1 || bands > FT_SH_BANDS)
    throw std::invalid_argument(fmt::format("prtMsRadianceCpu: {} matrix values, {} bands", a.size(), bands));
  const int J = bands * bands;
  const glm::dvec3 lg = prtMsCgLookup(std::max(0.0, double(q.light.w)), tables.lambdaNodes);
  PrtMsZonal g;
  for (int l = 0; l < FT_SH_BANDS; ++l)
    g.c[l] = glm::mix(tables.cg[size_t(lg.x) * FT_SH_BANDS + size_t(l)], tables.cg[size_t(lg.y) * FT_SH_BANDS + size_t(l)], lg.z);
  const ShCoeffs cd = prtMsLightCoeffs(shEval(glm::dvec3(q.light.x, q.light.y, q.light.z)), g, q.light.w > 0.0f, bands);
  const size_t plane = size_t(kJ) * kJ;
  ShCoeffs3 cT;
  for (int j = 0; j < kJ; ++j) cT.c[j] = glm::dvec3(0.0);
  for (int j1 = 0; j1 < J; ++j1)
    for (int j0 = 0; j0 < J; ++j0) {
      const size_t at = size_t(j1) * kJ + size_t(j0);
      cT.c[j1] += glm::dvec3(a[at], a[at + plane], a[at + 2 * plane]) * cd.c[j0];
    }
  const glm::dvec3 t(q.tangent.x, q.tangent.y, q.tangent.z), wo(q.wo.x, q.wo.y, q.wo.z);
  const ShCoeffs3 c = shRotate3(prtMsOmegaORotation(t, wo, bands), cT, bands);
  const glm::dvec3 lk = prtMsCsLookup(prtMsThetaO(t, wo), tables.thetaO);
  glm::dvec3 L(0.0);
  for (int j = 0; j < J; ++j) {
    const double* s0 = &tables.cs[(size_t(lk.x) * kJ + size_t(j)) * 3];
    const double* s1 = &tables.cs[(size_t(lk.y) * kJ + size_t(j)) * 3];
    L += glm::mix(glm::dvec3(s0[0], s0[1], s0[2]), glm::dvec3(s1[0], s1[1], s1[2]), lk.z) * c.c[j];
  }
  return L;
}

// ---- V̄_glo ----------------------------------------------------------------------

std::vector<double> prtMsVgloFilterCpu(std::span<const double> v, int width, int height, double texel, double sigma) {
  if (width < 1 || height < 1 || v.size() != size_t(width) * size_t(height))
    throw InputError(fmt::format("V_glo grid: {} values for {} × {} texels", v.size(), width, height));
  if (!(texel > 0.0) || !std::isfinite(texel)) throw InputError(fmt::format("V_glo grid: texel side {} (> 0)", texel));
  if (!(sigma > 0.0) || !std::isfinite(sigma)) throw InputError(fmt::format("V_glo: σ_glo {} (> 0)", sigma));
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw InputError(fmt::format("V_glo grid: texel ({}, {}) is {}", i % size_t(width), i / size_t(width), v[i]));
  const double s = prtMsVgloSigmaTexels(sigma, texel);
  const int r = prtMsVgloRadius(s);
  std::vector<double> k(size_t(2 * r + 1));
  for (int d = -r; d <= r; ++d) k[size_t(d + r)] = prtMsVgloWeight(d, s);
  // One axis: normalised by the weights inside the grid (A is the grid, 004's ∫_A K).
  auto pass = [&](const std::vector<double>& in, bool alongX) {
    std::vector<double> out(in.size());
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const int c = alongX ? x : y, n = alongX ? width : height;
        double num = 0.0, den = 0.0;
        for (int d = std::max(-r, -c); d <= std::min(r, n - 1 - c); ++d) {
          const size_t at = alongX ? size_t(y) * size_t(width) + size_t(x + d) : size_t(y + d) * size_t(width) + size_t(x);
          num += k[size_t(d + r)] * in[at];
          den += k[size_t(d + r)];
        }
        out[size_t(y) * size_t(width) + size_t(x)] = num / den;
      }
    return out;
  };
  return pass(pass(std::vector<double>(v.begin(), v.end()), true), false);
}

double prtMsVgloSampleCpu(const std::function<double(glm::dvec2)>& vGlo, glm::dvec2 x, double sigma, int samples,
                          uint32_t stream, uint32_t seed) {
  if (!(sigma > 0.0) || !std::isfinite(sigma) || samples < 1)
    throw InputError(fmt::format("V̄_glo sampling: σ_glo {}, {} samples (σ > 0, ≥ 1 sample)", sigma, samples));
  RandomStream rng(stream, 0u, seed);
  double sum = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double u1 = 1.0 - double(rng.next()), u2 = rng.next();  // u1 ∈ (0, 1]
    const double rad = sigma * std::sqrt(-2.0 * std::log(u1));
    sum += vGlo(x + rad * glm::dvec2(std::cos(2.0 * kPi * u2), std::sin(2.0 * kPi * u2)));
  }
  return sum / double(samples);
}

}  // namespace ft
