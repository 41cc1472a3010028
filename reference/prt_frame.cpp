// prt_frame.cpp — the PRT frame of 004 §5 and its path-traced reference
// (reference/prt_frame.h; docs/prt-frame.md).
#include "reference/prt_frame.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/prt_frame.h"
#include "image/flip.h"
#include "reference/bcsdf_sampling.h"
#include "reference/numbers.h"
#include "reference/prt_single_scattering.h"
#include "scene/fabric.h"
#include "scene/input_error.h"

namespace ft {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
constexpr uint32_t kNoFiber = 0xFFFFFFFFu;
bool finiteUnit(glm::vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::abs(glm::length(v) - 1.0f) < 1e-3f;
}
// A Monte Carlo pixel: its mean radiance from the sum L and Σ intensity² of `samples` draws, and
// the variance of its mean intensity (for PrtFrameImage::averageStdError).
void storePixel(PrtFrameImage& im, std::vector<double>& variance, size_t i, glm::dvec3 L, double sq, int samples) {
  im.rgb[i] = glm::vec3(L / double(samples));
  const double mean = (L.x + L.y + L.z) / 3.0 / double(samples);
  if (samples > 1) variance[i] = std::max(0.0, sq / double(samples) - mean * mean) / double(samples - 1);
}
void finishImage(PrtFrameImage& im, const std::vector<uint8_t>& hit, const std::vector<double>& variance,
                 Clock::time_point t0) {
  im.covered = uint64_t(std::count(hit.begin(), hit.end(), uint8_t(1)));
  double v = 0.0;
  for (double x : variance) v += x;
  im.averageStdError = std::sqrt(v) / double(im.rgb.size());
  im.seconds = secondsSince(t0);
}
}  // namespace

void checkPrtFrameSettings(const PrtFrameSettings& s) {
  auto need = [](bool ok, const char* option, double value) {
    if (!ok) throw InputError(fmt::format("prt frame: {} {} is out of range", option, value));
  };
  need(s.tiles >= 3 && s.tiles <= 15, "--tiles (3..15)", s.tiles);
  need(s.width >= 1 && s.width <= 4096, "--width (1..4096)", s.width);
  need(s.height >= 1 && s.height <= 4096, "--height (1..4096)", s.height);
  need(s.volumeSamples >= 1 && s.volumeSamples <= int(FT_VOL_MAX_SAMPLES), "--volume-samples (1..4096)", s.volumeSamples);
  need(s.volumeIds == FT_VOL_IDS_MIDPOINT || s.volumeIds == FT_VOL_IDS_CAPSULE, "--volume-ids (0 midpoint, 1 capsule)",
       s.volumeIds);
  need(s.voxelsPerDiameter >= 1 && s.voxelsPerDiameter <= 4, "--voxels-per-diameter (1..4)", s.voxelsPerDiameter);
  need(s.svfSize >= 8 && s.svfSize <= 512 && s.svfSize % 2 == 0, "--svf-size (even, 8..512)", s.svfSize);
  need(s.bands >= 1 && s.bands <= FT_SH_BANDS, "--bands (1..FT_SH_BANDS)", s.bands);
  need(std::isfinite(s.cellFactor) && s.cellFactor > 0.0, "--cell-factor (> 0)", s.cellFactor);
  need(s.pathsPerCell >= 1, "--paths-per-cell (≥ 1)", s.pathsPerCell);
  need(std::isfinite(s.msNoiseCut) && s.msNoiseCut >= 0.0, "--ms-noise-cut (≥ 0)", s.msNoiseCut);
  need(s.ellPaths >= 1, "--ell-paths (≥ 1)", s.ellPaths);
  need(s.msThetaINodes >= 2 && s.msPhiNodes >= 2, "C_S nodes (≥ 2)", std::min(s.msThetaINodes, s.msPhiNodes));
  need(s.ptSamples >= 1, "--spp (≥ 1)", s.ptSamples);
  need(s.maxDepth >= 1, "--max-depth (≥ 1)", s.maxDepth);
}

void checkPrtFrameView(const PrtFrameView& v) {
  if (!finiteUnit(v.wo))
    throw InputError(fmt::format("prt frame: view direction ({}, {}, {}) is not a finite unit vector", v.wo.x, v.wo.y, v.wo.z));
  if (!(v.wo.z > 0.05f)) throw InputError(fmt::format("prt frame: view direction z = {} (the eye must be above the fabric, z > 0.05)", v.wo.z));
  if (!finiteUnit(v.light))
    throw InputError(fmt::format("prt frame: light direction ({}, {}, {}) is not a finite unit vector", v.light.x, v.light.y, v.light.z));
  if (!(std::isfinite(v.lambda) && v.lambda >= 0.0f)) throw InputError(fmt::format("prt frame: light lambda {} (finite, ≥ 0)", v.lambda));
}

double PrtFrameImage::average() const {
  if (rgb.empty()) return 0.0;
  double s = 0.0;
  for (const glm::vec3& c : rgb) s += (double(c.x) + double(c.y) + double(c.z)) / 3.0;
  return s / double(rgb.size());
}

glm::dvec3 sampleSgDirection(glm::dvec3 xi, double lambda, double u0, double u1) {
  const double c = std::clamp(1.0 + std::log1p(-u0 * -std::expm1(-2.0 * lambda)) / lambda, -1.0, 1.0);
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c)), phi = 2.0 * kPi * u1;
  const glm::dvec3 a = std::abs(xi.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(a, xi)), v = glm::cross(xi, u);
  return glm::normalize(c * xi + s * (std::cos(phi) * u + std::sin(phi) * v));
}

struct PrtFrameScene::Impl {
  PrtFrameSettings s;
  FabricParams fabric{};
  Exemplar block;
  std::vector<ExemplarSegment> tiled;
  std::unique_ptr<IirtfScene> scene;
  std::unique_ptr<SvfScene> svf;
  ExemplarVolume volume;
  PrtMsTables tables;
  std::vector<double> ssTable;
  MeanFreePath ell;
  IirtfCells cells;
  std::vector<std::vector<double>> transfer;  // per cell, empty until baked
  std::vector<std::vector<double>> stdError;  // per cell, with transfer
  std::vector<std::vector<double>> uncut;     // per cell, A_C before msNoiseCut (setMsNoiseCut cuts it again)
  uint32_t iirtfSeed = 0;                     // s.seed until reseedIirtf
  std::vector<std::vector<float>> ssdf;       // per block segment, empty until baked
  std::vector<float> angle;                   // R_k per block segment
  PrtSsSegments sosg;                         // weights of every block segment (zeros until baked)
  double zTop = 0.0, zBottom = 0.0;
  double bakeSeconds = 0.0;
  size_t svfBaked = 0, cellsBaked = 0;

  void bakeFor(const std::vector<VolHit>& hits) {
    const auto t0 = Clock::now();
    std::vector<uint32_t> segs, cellList;
    std::vector<uint8_t> wantSeg(block.segments.size(), 0), wantCell(cells.count(), 0);
    for (const VolHit& h : hits) {
      if (h.id == 0) continue;
      const uint32_t k = h.id - 1;
      if (ssdf[k].empty() && !wantSeg[k]) wantSeg[k] = 1, segs.push_back(k);
      const uint32_t c = cells.cellOf[k];
      if (transfer[c].empty() && !wantCell[c]) wantCell[c] = 1, cellList.push_back(c);
    }
    SvfSettings vs;
    vs.width = vs.height = s.svfSize;
    vs.seed = s.seed;
    const int Q = sosg.axes;
    tbb::parallel_for(size_t(0), segs.size(), [&](size_t i) {
      const uint32_t k = segs[i];
      SvfSegment sv = svfSegmentCpu(*svf, block, s.tiles, k, vs);
      ssdf[k] = std::move(sv.ssdf);
      angle[k] = sv.angle;
      std::copy(sv.weights.begin(), sv.weights.end(), sosg.weights.begin() + long(size_t(k) * size_t(Q)));
    });
    IirtfSettings is;
    is.tiles = s.tiles;
    is.pathsPerCell = s.pathsPerCell;
    is.maxDepth = s.maxDepth;
    is.seed = iirtfSeed;
    for (uint32_t c : cellList) {
      IirtfCell cell = iirtfCellCpu(*scene, block, s.tiles, fabric, is, cells.members[c]);
      uncut[c] = cell.a;
      if (s.msNoiseCut > 0.0) prtMsNoiseCut(cell, s.msNoiseCut);
      transfer[c] = std::move(cell.a);
      stdError[c] = std::move(cell.stdError);
    }
    svfBaked += segs.size();
    cellsBaked += cellList.size();
    bakeSeconds += secondsSince(t0);
  }
};

PrtFrameScene::PrtFrameScene(const PrtFrameSettings& settings) : impl_(std::make_unique<Impl>()) {
  checkPrtFrameSettings(settings);
  const auto t0 = Clock::now();
  Impl& m = *impl_;
  m.s = settings;
  m.fabric = findFabricPreset(settings.fabric).params();
  m.block = makePlainWeaveExemplar(settings.exemplar);
  m.tiled = tileExemplar(m.block, settings.tiles);
  m.scene = std::make_unique<IirtfScene>(m.tiled);
  m.svf = std::make_unique<SvfScene>(m.tiled);
  float rMax = 0.0f;
  for (const ExemplarSegment& g : m.block.segments) rMax = std::max(rMax, g.radius);
  const VolParams layout = makeVolumeLayout(
      m.block, std::max(1, int(std::lround(m.block.period / (2.0f * rMax)))) * settings.voxelsPerDiameter);
  m.volume = buildExemplarVolumeCpu(m.block, layout, buildVolumeCandidates(m.block, layout));
  m.tables = prtMsTablesCpu(m.fabric, settings.msThetaINodes, settings.msPhiNodes);
  m.ssTable = bakePrtSsTableCpu(std::span<const FabricParams>(&m.fabric, 1));
  IirtfSettings is;
  is.tiles = settings.tiles;
  is.ellPaths = settings.ellPaths;
  is.maxDepth = settings.maxDepth;
  is.seed = settings.seed;
  m.ell = estimateMeanFreePath(*m.scene, m.block, settings.tiles, m.fabric, is);
  // ℓ̃ = factor ℓ; no scattering measured (ℓ = 0): one cell per half period.
  m.cells = makeIirtfCells(m.block, m.ell.ell > 0.0 ? settings.cellFactor * m.ell.ell : m.block.period / 2.0);
  m.transfer.assign(m.cells.count(), {});
  m.stdError.assign(m.cells.count(), {});
  m.uncut.assign(m.cells.count(), {});
  m.iirtfSeed = settings.seed;
  const size_t S = m.block.segments.size();
  m.ssdf.assign(S, {});
  m.angle.assign(S, 0.0f);
  m.sosg.weights.assign(S * size_t(m.sosg.axes), 0.0f);
  m.zTop = -1e30, m.zBottom = 1e30;
  for (const ExemplarSegment& g : m.block.segments)
    m.zTop = std::max({m.zTop, double(g.a.z), double(g.b.z)}), m.zBottom = std::min({m.zBottom, double(g.a.z), double(g.b.z)});
  m.bakeSeconds = secondsSince(t0);
}
PrtFrameScene::~PrtFrameScene() = default;
PrtFrameScene::PrtFrameScene(PrtFrameScene&&) noexcept = default;
PrtFrameScene& PrtFrameScene::operator=(PrtFrameScene&&) noexcept = default;
const PrtFrameSettings& PrtFrameScene::settings() const { return impl_->s; }
const Exemplar& PrtFrameScene::block() const { return impl_->block; }
double PrtFrameScene::bakeSeconds() const { return impl_->bakeSeconds; }
double PrtFrameScene::meanFreePath() const { return impl_->ell.ell; }
size_t PrtFrameScene::cellCount() const { return impl_->cells.count(); }
size_t PrtFrameScene::svfBaked() const { return impl_->svfBaked; }
size_t PrtFrameScene::cellsBaked() const { return impl_->cellsBaked; }

PrtFrameData PrtFrameScene::gpuData() const {
  const Impl& m = *impl_;
  PrtFrameData d;
  d.fabric = m.fabric;
  d.layout = m.volume.layout;
  d.segments = volumeSegments(m.block);
  d.candidates = buildVolumeCandidates(m.block, d.layout);
  d.svfSize = m.s.svfSize;
  d.axes = m.sosg.axes;
  d.lambdaSvf = m.sosg.lambdaSvf;
  const size_t S = m.block.segments.size(), n2 = size_t(m.s.svfSize) * size_t(m.s.svfSize);
  d.ssdf.assign(S * n2, 0.0f);
  d.segmentData.resize(S);
  for (size_t k = 0; k < S; ++k) {
    if (!m.ssdf[k].empty()) std::copy(m.ssdf[k].begin(), m.ssdf[k].end(), d.ssdf.begin() + long(k * n2));
    d.segmentData[k] = glm::vec4(m.angle[k], float(m.cells.cellOf[k]), 0.0f, 0.0f);
  }
  d.weights = m.sosg.weights;
  d.transfer.assign(m.cells.count() * kIirtfMatrixSize, 0.0f);
  for (size_t c = 0; c < m.cells.count(); ++c)
    for (size_t j = 0; j < m.transfer[c].size(); ++j) d.transfer[c * kIirtfMatrixSize + j] = float(m.transfer[c][j]);
  return d;
}

void PrtFrameScene::setBands(int bands) {
  if (bands < 1 || bands > FT_SH_BANDS) throw InputError(fmt::format("prt frame: --bands {} (1..{})", bands, FT_SH_BANDS));
  impl_->s.bands = bands;
}

void PrtFrameScene::reseedIirtf(uint32_t seed) {
  Impl& m = *impl_;
  m.iirtfSeed = seed;
  m.transfer.assign(m.cells.count(), {});
  m.stdError.assign(m.cells.count(), {});
  m.uncut.assign(m.cells.count(), {});
}

void PrtFrameScene::setMsNoiseCut(double cut) {
  Impl& m = *impl_;
  if (!(std::isfinite(cut) && cut >= 0.0)) throw InputError(fmt::format("prt frame: --ms-noise-cut {} (≥ 0)", cut));
  m.s.msNoiseCut = cut;
  for (size_t c = 0; c < m.transfer.size(); ++c) {
    if (m.uncut[c].empty()) continue;
    IirtfCell cell;
    cell.a = m.uncut[c];
    cell.stdError = m.stdError[c];
    if (cut > 0.0) prtMsNoiseCut(cell, cut);
    m.transfer[c] = std::move(cell.a);
  }
}

void PrtFrameScene::bakedTransfer(std::vector<float>& transfer, std::vector<float>& stdError) const {
  transfer.clear(), stdError.clear();
  for (size_t c = 0; c < impl_->transfer.size(); ++c) {
    transfer.insert(transfer.end(), impl_->transfer[c].begin(), impl_->transfer[c].end());
    stdError.insert(stdError.end(), impl_->stdError[c].begin(), impl_->stdError[c].end());
  }
}

PrtFrameImage PrtFrameScene::renderTransfer(const PrtFrameView& view, int samples, TransferOrigin origin) const {
  if (samples < 1) throw InputError(fmt::format("prt frame: transfer probe with {} samples", samples));
  const Impl& m = *impl_;
  const VolParams rp = rays(view);
  const auto t0 = Clock::now();
  const int W = m.s.width, H = m.s.height;
  const size_t S = m.block.segments.size();
  PrtFrameImage im;
  im.width = W, im.height = H;
  im.rgb.assign(size_t(W) * size_t(H), glm::vec3(0.0f));
  std::vector<uint8_t> hit(im.rgb.size(), 0);
  std::vector<double> variance(im.rgb.size(), 0.0);  // of the pixel's mean intensity
  ShadingParams light{};
  light.fabric = m.fabric;
  light.lightIrradiance[0] = vec4(1.0f);
  light.flags = uvec4(1u, FT_SHADING_KHUNGURN, 0u, 0u);
  tbb::parallel_for(size_t(0), im.rgb.size(), [&](size_t i) {
    const uint32_t x = uint32_t(i % size_t(W)), y = uint32_t(i / size_t(W));
    const glm::vec3 org = ftVolRayOrigin(rp, x, y), dir = ftVolRayDirection(rp, x, y);
    IirtfScene::Hit first;
    if (!m.scene->intersect(org, dir, kNoFiber, first)) return;
    hit[i] = 1;
    const ExemplarSegment& g = m.scene->segments()[first.segment];
    const glm::vec3 t = glm::normalize(g.b - g.a), p = org + first.t * dir;
    const std::vector<uint32_t>& members = m.cells.members[m.cells.cellOf[first.segment % S]];
    glm::dvec3 L(0.0);
    double sq = 0.0;
    uint64_t rays = 0;
    for (int j = 0; j < samples; ++j) {
      RandomStream rng(uint32_t(i), uint32_t(j), m.s.seed ^ 0x7452u);
      glm::vec3 w0 = view.light;
      if (view.lambda > 0.0f) {
        const double u0 = rng.next(), u1 = rng.next();
        w0 = glm::vec3(sampleSgDirection(glm::dvec3(view.light), double(view.lambda), u0, u1));
      }
      light.lightDirection[0] = vec4(w0, 0.0f);
      const FiberScatter sc(light, t, first.normal, -dir);
      if (!sc.scatters()) break;
      const glm::vec3 wi = sc.sample(rng);
      glm::vec3 from = p;
      uint32_t fiber = g.fiber;
      if (origin != TransferOrigin::Hit) {
        const uint32_t k = origin == TransferOrigin::Midpoint
                               ? uint32_t(first.segment % S)
                               : members[std::min(members.size() - 1, size_t(double(rng.next()) * double(members.size())))];
        const ExemplarSegment& own = m.scene->segments()[centreCopy(m.s.tiles) * S + k];
        from = own.mid(), fiber = own.fiber;
      }
      const glm::dvec3 v = glm::dvec3(sc.weight(wi)) * iirtfPathRadiance(*m.scene, m.fabric, 1.0, m.s.maxDepth, from,
                                                                         fiber, w0, wi, uint32_t(i), uint32_t(j),
                                                                         m.s.seed ^ 0x7453u, rays);
      L += v;
      sq += std::pow((v.x + v.y + v.z) / 3.0, 2);
    }
    storePixel(im, variance, i, L, sq, samples);
  });
  finishImage(im, hit, variance, t0);
  return im;
}

VolParams PrtFrameScene::rays(const PrtFrameView& view) const {
  checkPrtFrameView(view);
  const Impl& m = *impl_;
  const float P = m.block.period;
  const glm::vec3 centre(0.5f * P, 0.5f * P, float(0.5 * (m.zTop + m.zBottom)));
  VolCamera cam;
  cam.type = FT_VOL_CAMERA_ORTHO;
  cam.direction = -view.wo;
  cam.up = std::abs(view.wo.z) > 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
  // The image rectangle above the fabric: its lowest corner clears the top by a reach.
  const float dist = float((0.75 * P + (m.zTop - m.zBottom) + m.block.reach) / view.wo.z);
  cam.position = centre + dist * view.wo;
  cam.halfWidth = cam.halfHeight = 0.5f * P;
  VolParams p = m.volume.layout;
  setVolumeRays(p, cam, m.s.width, m.s.height, m.s.volumeSamples, m.s.volumeIds);
  return p;
}

PrtFrameParts PrtFrameScene::renderPrt(const PrtFrameView& view) {
  Impl& m = *impl_;
  const VolParams rp = rays(view);
  const auto gbufferOf = [&] {
    if (!m.s.embreeGBuffer) return sampleVolumeCpu(m.volume, rp);  // 004 §5.1 (or the capsule ids)
    std::vector<VolHit> g(size_t(m.s.width) * size_t(m.s.height), VolHit{});
    tbb::parallel_for(size_t(0), g.size(), [&](size_t i) {
      const uint32_t x = uint32_t(i % size_t(m.s.width)), y = uint32_t(i / size_t(m.s.width));
      IirtfScene::Hit h;
      if (m.scene->intersect(ftVolRayOrigin(rp, x, y), ftVolRayDirection(rp, x, y), kNoFiber, h))
        g[i].id = uint32_t(h.segment % m.block.segments.size()) + 1u;
    });
    return g;
  };
  m.bakeFor(gbufferOf());
  const auto t0 = Clock::now();  // the frame: G-buffer again (the bakes above needed its ids), shading, composition
  const std::vector<VolHit> gbuffer = gbufferOf();
  const int W = m.s.width, H = m.s.height, n = m.s.svfSize;
  const size_t N = size_t(W) * size_t(H);
  std::vector<size_t> pixels;
  std::vector<PrtSsRequest> requests;
  std::vector<PrtMsQuery> queries;
  for (size_t i = 0; i < N; ++i) {
    if (gbuffer[i].id == 0) continue;
    const uint32_t k = gbuffer[i].id - 1;
    const ExemplarSegment& g = m.block.segments[k];
    const PrtFramePixel px = ftPrtFrameRequests(
        k, ftVolRayDirection(rp, uint32_t(i % size_t(W)), uint32_t(i / size_t(W))), g.a, g.b,
        m.ssdf[k][size_t(ftPrtFrameSvfPixel(view.light, n, n))], m.angle[k], m.cells.cellOf[k],
        vec4(view.light, view.lambda));
    requests.push_back(PrtSsRequest{px.ssTangent, px.ssOutgoing, px.ssLight, px.ssSegment});
    queries.push_back(PrtMsQuery{px.msWo, px.msTangent, px.msLight, px.msCell});
    pixels.push_back(i);
  }
  const std::vector<glm::dvec3> single =
      evaluatePrtSsCpu(std::span<const FabricParams>(&m.fabric, 1), m.ssTable, requests, m.sosg);
  std::vector<glm::dvec3> multi(queries.size());
  tbb::parallel_for(size_t(0), queries.size(), [&](size_t j) {
    multi[j] = prtMsRadianceCpu(m.tables, m.transfer[queries[j].cell.x], m.s.bands, queries[j]);
  });
  PrtFrameParts out;
  for (PrtFrameImage* im : {&out.total, &out.single, &out.multi}) {
    im->width = W, im->height = H;
    im->rgb.assign(N, glm::vec3(0.0f));
    im->covered = pixels.size();
  }
  for (size_t j = 0; j < pixels.size(); ++j) {
    const glm::vec3 ss(single[j]), ms(multi[j]);
    out.total.rgb[pixels[j]] = ftPrtFrameCompose(ss, ms, 1.0f);
    out.single.rgb[pixels[j]] = ss;
    out.multi.rgb[pixels[j]] = ms;
  }
  out.total.seconds = out.single.seconds = out.multi.seconds = secondsSince(t0);
  out.ids.resize(N);
  for (size_t i = 0; i < N; ++i) out.ids[i] = gbuffer[i].id;
  return out;
}

PrtFrameImage PrtFrameScene::renderPathTraced(const PrtFrameView& view, int samples, int maxDepth) const {
  if (samples < 1 || maxDepth < 1) throw InputError(fmt::format("prt frame: path tracing with {} samples, depth {}", samples, maxDepth));
  const Impl& m = *impl_;
  const VolParams rp = rays(view);
  const auto t0 = Clock::now();
  const int W = m.s.width, H = m.s.height;
  PrtFrameImage im;
  im.width = W, im.height = H;
  im.rgb.assign(size_t(W) * size_t(H), glm::vec3(0.0f));
  std::vector<uint8_t> hit(im.rgb.size(), 0);
  std::vector<double> variance(im.rgb.size(), 0.0);  // of the pixel's mean intensity
  const glm::dvec3 xi(view.light);
  tbb::parallel_for(size_t(0), im.rgb.size(), [&](size_t i) {
    const uint32_t x = uint32_t(i % size_t(W)), y = uint32_t(i / size_t(W));
    const glm::vec3 org = ftVolRayOrigin(rp, x, y), dir = ftVolRayDirection(rp, x, y);
    IirtfScene::Hit first;
    if (!m.scene->intersect(org, dir, kNoFiber, first)) return;
    hit[i] = 1;
    glm::dvec3 L(0.0);
    double sq = 0.0;
    uint64_t rays = 0;
    for (int j = 0; j < samples; ++j) {
      glm::vec3 w0 = view.light;
      if (view.lambda > 0.0f) {  // the SG light: ω0 ~ G/M, the estimator's weight is 1
        RandomStream rng(uint32_t(i), uint32_t(j), m.s.seed ^ 0x5347u);
        const double u0 = rng.next(), u1 = rng.next();
        w0 = glm::vec3(sampleSgDirection(xi, double(view.lambda), u0, u1));
      }
      const glm::dvec3 v = iirtfPathRadiance(*m.scene, m.fabric, 1.0, maxDepth, org, kNoFiber, w0, dir, uint32_t(i),
                                             uint32_t(j), m.s.seed ^ 0x50544652u, rays);
      L += v;
      sq += std::pow((v.x + v.y + v.z) / 3.0, 2);
    }
    storePixel(im, variance, i, L, sq, samples);
  });
  finishImage(im, hit, variance, t0);
  return im;
}

ImageRgbaF toImage(const PrtFrameImage& image) {
  ImageRgbaF out(image.width, image.height);
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    float* px = out.pixels.data() + 4 * i;
    px[0] = image.rgb[i].x, px[1] = image.rgb[i].y, px[2] = image.rgb[i].z, px[3] = 1.0f;
  }
  return out;
}

PrtFrameComparison comparePrtFrame(const PrtFrameImage& prt, const PrtFrameImage& reference, bool flip) {
  if (prt.width != reference.width || prt.height != reference.height || prt.rgb.size() != reference.rgb.size())
    throw InputError(fmt::format("prt frame: images of {}x{} and {}x{} compared", prt.width, prt.height, reference.width,
                                 reference.height));
  PrtFrameComparison c;
  double sq = 0.0;
  for (size_t i = 0; i < prt.rgb.size(); ++i) {
    for (int ch = 0; ch < 3; ++ch)
      c.nonFinite += uint64_t(!std::isfinite(prt.rgb[i][ch])) + uint64_t(!std::isfinite(reference.rgb[i][ch]));
    const double a = (double(prt.rgb[i].x) + prt.rgb[i].y + prt.rgb[i].z) / 3.0;
    const double b = (double(reference.rgb[i].x) + reference.rgb[i].y + reference.rgb[i].z) / 3.0;
    sq += (a - b) * (a - b);
  }
  c.averagePrt = prt.average();
  c.averageReference = reference.average();
  c.averageRelError = std::abs(c.averagePrt - c.averageReference) / std::max(1e-30, std::abs(c.averageReference));
  c.coveredPrt = prt.coveredAverage();
  c.coveredReference = reference.coveredAverage();
  c.pixelRmse = prt.rgb.empty() ? 0.0 : std::sqrt(sq / double(prt.rgb.size()));
  if (flip && c.nonFinite == 0 && c.averageReference > 0.0) c.flipMean = flipHdr(toImage(reference), toImage(prt)).pooled.meanDouble;
  return c;
}

}  // namespace ft
