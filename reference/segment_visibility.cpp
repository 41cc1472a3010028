// segment_visibility.cpp — CPU reference of 004 §4.1 (reference/segment_visibility.h).
#include "reference/segment_visibility.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "common/segment_visibility.h"
#include "scene/input_error.h"

namespace ft {

struct SvfScene::Impl {
  std::vector<glm::vec4> points;     // 2 per segment: (xyz, r)
  std::vector<uint32_t> firstVertex;  // 2k
  std::vector<uint32_t> fiber;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

SvfScene::SvfScene(std::span<const ExemplarSegment> segments) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.points.reserve(2 * segments.size());
  for (size_t k = 0; k < segments.size(); ++k) {
    const ExemplarSegment& s = segments[k];
    checkExemplarSegment(s, k);
    m.points.emplace_back(s.a, s.radius);
    m.points.emplace_back(s.b, s.radius);
    m.firstVertex.push_back(uint32_t(2 * k));
    m.fiber.push_back(s.fiber);
  }
  m.device = rtcNewDevice(nullptr);
  if (!m.device) throw std::runtime_error("Embree: rtcNewDevice failed");
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  if (!segments.empty()) {
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
  if (rtcGetDeviceError(m.device) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the SVF scene failed");
}

SvfScene::~SvfScene() = default;
SvfScene::SvfScene(SvfScene&&) noexcept = default;
SvfScene& SvfScene::operator=(SvfScene&&) noexcept = default;
size_t SvfScene::segmentCount() const { return impl_->fiber.size(); }

namespace {

struct OwnFiberContext {
  RTCIntersectContext embree;  // first: Embree hands its address back to the filter
  const uint32_t* fiber;
  uint32_t ownFiber, ownSegment;
};

// 004 §4.1a: only fibers other than k's own occlude.
void ignoreOwnFiber(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const OwnFiberContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    if (prim == c->ownSegment || (!ftFaultSvfOwnFiberOccludes && c->fiber[prim] == c->ownFiber)) args->valid[i] = 0;
  }
}

}  // namespace

std::vector<uint8_t> SvfScene::visibilityImage(glm::vec3 origin, uint32_t ownFiber, uint32_t ownSegment, int width,
                                               int height) const {
  std::vector<uint8_t> image(size_t(width) * size_t(height), 1);
  OwnFiberContext ctx;
  rtcInitIntersectContext(&ctx.embree);
  ctx.embree.filter = ignoreOwnFiber;
  ctx.fiber = impl_->fiber.data();
  ctx.ownFiber = ownFiber;
  ctx.ownSegment = ownSegment;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::vec3 w = ftSvfPixelDirection(x, y, width, height);
      RTCRay ray{};
      ray.org_x = origin.x, ray.org_y = origin.y, ray.org_z = origin.z;
      ray.dir_x = w.x, ray.dir_y = w.y, ray.dir_z = w.z;
      ray.tnear = 0.0f;
      ray.tfar = std::numeric_limits<float>::infinity();
      ray.mask = ~0u;
      rtcOccluded1(impl_->scene, &ctx.embree, &ray);
      image[size_t(y) * width + x] = ray.tfar >= 0.0f ? 1 : 0;  // Embree sets tfar to −∞ on a hit
    }
  return image;
}

std::pair<int64_t, float> SvfScene::firstHit(glm::vec3 origin, glm::vec3 direction, float tFar) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);  // no filter: every segment counts
  RTCRayHit rh{};
  rh.ray.org_x = origin.x, rh.ray.org_y = origin.y, rh.ray.org_z = origin.z;
  rh.ray.dir_x = direction.x, rh.ray.dir_y = direction.y, rh.ray.dir_z = direction.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = tFar;
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {-1, tFar};
  return {int64_t(rh.hit.primID), rh.ray.tfar};
}

std::vector<float> svfSsdfCpu(std::span<const uint8_t> image, int W, int H) {
  if (image.size() != size_t(W) * size_t(H)) throw std::invalid_argument("svfSsdfCpu: image size");
  // Boundary lists per value and row: pixels with a 4-neighbour of the other value.
  std::vector<std::vector<int>> boundary[2];
  boundary[0].resize(size_t(H));
  boundary[1].resize(size_t(H));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const uint8_t v = image[size_t(y) * W + x];
      for (int dir = 0; dir < 4; ++dir)
        if (image[size_t(ftSvfNeighbour(x, y, dir, W, H))] != v) {
          boundary[v ? 1 : 0][size_t(y)].push_back(x);
          break;
        }
    }
  std::vector<glm::vec3> dirs(image.size());
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) dirs[size_t(y) * W + x] = ftSvfPixelDirection(x, y, W, H);
  std::vector<float> out(image.size());
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const bool visible = image[size_t(y) * W + x] != 0;
      const glm::vec3 wp = dirs[size_t(y) * W + x];
      const std::vector<std::vector<int>>& rows = boundary[visible ? 0 : 1];
      float best = -1.0f;
      // Rows outward from y; a row |Δy| away is at least π|Δy|/H away (the
      // great-circle distance and the flat one are ≥ |Δθ|): stop past the best
      // (with 1e-6 slack for float). Same minimum as the GPU's full scan.
      for (int gap = 0; gap < H; ++gap) {
        if (best >= 0.0f && FT_PI * float(gap) / float(H) > ftSvfDistanceOfKey(best) + 1e-6f) break;
        for (int side = 0; side < (gap == 0 ? 1 : 2); ++side) {
          const int qy = side == 0 ? y - gap : y + gap;
          if (qy < 0 || qy >= H) continue;
          for (int qx : rows[size_t(qy)]) {
            const float key = ftSvfDistanceKey(wp, dirs[size_t(qy) * W + qx], x, y, qx, qy, W, H);
            if (best < 0.0f || key < best) best = key;
          }
        }
      }
      out[size_t(y) * W + x] = ftSvfSsdfFromKey(visible, best);
    }
  return out;
}

std::vector<int32_t> svfNearestAxesCpu(int W, int H, int axes, float angle) {
  std::vector<int32_t> out(size_t(W) * size_t(H / 2));
  for (int y = 0; y < H / 2; ++y)
    for (int x = 0; x < W; ++x) out[size_t(y) * W + x] = ftSvfNearestAxis(ftSvfPixelDirection(x, y, W, H), axes, angle);
  return out;
}

std::vector<float> svfWeightsCpu(std::span<const uint8_t> image, int W, int H, int axes, float angle) {
  const std::vector<int32_t> nearest = svfNearestAxesCpu(W, H, axes, angle);
  std::vector<float> w(size_t(axes), 0.0f);
  for (int y = 0; y < H / 2; ++y) {
    const float omega = ftSvfPixelSolidAngle(y, W, H);
    for (int x = 0; x < W; ++x)
      if (image[size_t(y) * W + x]) w[size_t(nearest[size_t(y) * W + x])] += omega;
  }
  return w;
}

std::vector<float> svfSgDecodeCpu(std::span<const float> weights, float angle, float lambda, int W, int H) {
  const int axes = int(weights.size());
  std::vector<glm::vec3> xi(static_cast<size_t>(axes));
  for (int q = 0; q < axes; ++q) xi[size_t(q)] = ftSvfAxis(q + 1, axes, angle);
  std::vector<float> out(size_t(W) * size_t(H));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const glm::vec3 w = ftSvfPixelDirection(x, y, W, H);
      float v = 0.0f;
      for (int q = 0; q < axes; ++q) v += ftSvfSgTerm(weights[size_t(q)], xi[size_t(q)], lambda, w);
      out[size_t(y) * W + x] = v;
    }
  return out;
}

void checkSvfSettings(const SvfSettings& s) {
  for (auto [name, v] : {std::pair<const char*, int>{"--width", s.width}, {"--height", s.height}})
    if (v < 4 || v > 1024 || v % 2 != 0) throw InputError(fmt::format("{}: {} (an even number of pixels, 4..1024)", name, v));
  if (s.axes < 1 || s.axes > FT_SVF_MAX_AXES)
    throw InputError(fmt::format("--axes: {} (1..{})", s.axes, FT_SVF_MAX_AXES));
  if (!(s.lambda > 0.0f) || !std::isfinite(s.lambda) || s.lambda > 1e4f)
    throw InputError(fmt::format("--lambda: {} (0 < λ ≤ 10⁴)", s.lambda));
}

SvfSegment svfSegmentCpu(const SvfScene& scene, const Exemplar& block, int tiles, uint32_t k, const SvfSettings& s) {
  const size_t copy = centreCopy(tiles);
  const ExemplarSegment& seg = block.segments.at(k);
  SvfSegment out;
  out.image = scene.visibilityImage(seg.mid(), uint32_t(copy) * block.fibers + seg.fiber,
                                    uint32_t(copy * block.segments.size() + k), s.width, s.height);
  out.ssdf = svfSsdfCpu(out.image, s.width, s.height);
  out.angle = ftSvfRotationAngle(k, s.seed);
  out.weights = svfWeightsCpu(out.image, s.width, s.height, s.axes, out.angle);
  return out;
}

SvfPca svfPcaCpu(std::span<const float> ssdf, size_t rows, int pixels, int components) {
  if (rows == 0 || pixels <= 0 || ssdf.size() != rows * size_t(pixels))
    throw std::invalid_argument(fmt::format("svfPcaCpu: {} values for {} rows × {} pixels", ssdf.size(), rows, pixels));
  using Mat = Eigen::MatrixXd;
  Mat X(Eigen::Index(rows), pixels);
  for (size_t r = 0; r < rows; ++r)
    for (int p = 0; p < pixels; ++p) X(Eigen::Index(r), p) = double(ssdf[r * size_t(pixels) + size_t(p)]);
  SvfPca pca;
  pca.pixels = pixels;
  const Eigen::RowVectorXd mean = X.colwise().mean();
  X.rowwise() -= mean;
  pca.mean.assign(mean.data(), mean.data() + pixels);
  pca.components = std::max(0, std::min({components, int(rows), pixels}));
  const int C = pca.components;
  pca.basis.assign(size_t(C) * size_t(pixels), 0.0);
  pca.eigenvalues.assign(size_t(C), 0.0);
  Mat basis(pixels, C);  // columns: unit principal directions
  if (size_t(pixels) >= rows) {
    // Gram form (rows ≤ pixels): X Xᵀ u = λ u, direction Xᵀu/√λ.
    const Mat G = X * X.transpose();
    Eigen::SelfAdjointEigenSolver<Mat> es(G);
    pca.totalVariance = G.trace();
    for (int c = 0; c < C; ++c) {
      const Eigen::Index i = Eigen::Index(rows) - 1 - c;  // ascending order: the largest last
      const double lambda = std::max(0.0, es.eigenvalues()(i));
      pca.eigenvalues[size_t(c)] = lambda;
      Eigen::VectorXd v = X.transpose() * es.eigenvectors().col(i);
      const double n = v.norm();
      // Centring leaves rank ≤ rows − 1: a null direction (λ ≈ 0) is rounding
      // noise, not orthogonal to the rest; it is left out (zero basis, zero coefficient).
      const double top = std::max(0.0, es.eigenvalues()(Eigen::Index(rows) - 1));
      basis.col(c) = n > 0.0 && lambda > 1e-10 * top ? Eigen::VectorXd(v / n) : Eigen::VectorXd::Zero(pixels);
    }
  } else {
    const Mat Cov = X.transpose() * X;
    Eigen::SelfAdjointEigenSolver<Mat> es(Cov);
    pca.totalVariance = Cov.trace();
    for (int c = 0; c < C; ++c) {
      const Eigen::Index i = Eigen::Index(pixels) - 1 - c;
      pca.eigenvalues[size_t(c)] = std::max(0.0, es.eigenvalues()(i));
      basis.col(c) = es.eigenvectors().col(i);
    }
  }
  for (int c = 0; c < C; ++c) {  // sign: largest |entry| positive (first on a tie), for a deterministic file
    if (basis.col(c).squaredNorm() == 0.0) continue;
    Eigen::Index at = 0;
    basis.col(c).cwiseAbs().maxCoeff(&at);
    if (basis(at, c) < 0.0) basis.col(c) = -basis.col(c);
    for (int p = 0; p < pixels; ++p) pca.basis[size_t(c) * size_t(pixels) + size_t(p)] = basis(p, c);
  }
  const Mat coef = X * basis;
  pca.coefficients.resize(rows * size_t(C));
  for (size_t r = 0; r < rows; ++r)
    for (int c = 0; c < C; ++c) pca.coefficients[r * size_t(C) + size_t(c)] = coef(Eigen::Index(r), c);
  return pca;
}

std::vector<double> svfPcaReconstruct(const SvfPca& pca, size_t row, int use) {
  use = std::clamp(use, 0, pca.components);
  std::vector<double> out = pca.mean;
  for (int c = 0; c < use; ++c) {
    const double a = pca.coefficients[row * size_t(pca.components) + size_t(c)];
    for (int p = 0; p < pca.pixels; ++p) out[size_t(p)] += a * pca.basis[size_t(c) * size_t(pca.pixels) + size_t(p)];
  }
  return out;
}

}  // namespace ft
