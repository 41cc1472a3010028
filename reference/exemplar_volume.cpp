// exemplar_volume.cpp — CPU reference of 004 §5.1 (reference/exemplar_volume.h).
#include "reference/exemplar_volume.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "reference/segment_visibility.h"
#include "scene/input_error.h"

namespace ft {

VolParams makeVolumeLayout(const Exemplar& block, int voxelsPerPeriod, int cellVoxels) {
  if (block.segments.empty()) throw InputError("exemplar volume: the block has no segments");
  if (!(block.period > 0.0f) || !std::isfinite(block.period))
    throw InputError(fmt::format("exemplar volume: period {} (a finite number > 0)", block.period));
  if (cellVoxels < 1 || cellVoxels > 64)
    throw InputError(fmt::format("exemplar volume: {} voxels per candidate cell (1..64)", cellVoxels));
  const float P = block.period;
  float rMax = 0.0f, zLo = std::numeric_limits<float>::infinity(), zHi = -zLo;
  for (size_t k = 0; k < block.segments.size(); ++k) {
    const ExemplarSegment& s = block.segments[k];
    checkExemplarSegment(s, k, false);
    // The 8 translates by ±P are the only neighbours the build looks at.
    for (const glm::vec3& e : {s.a, s.b})
      if (e.x < -P + s.radius || e.x > 2.0f * P - s.radius || e.y < -P + s.radius || e.y > 2.0f * P - s.radius)
        throw InputError(fmt::format("exemplar volume: segment {} reaches ({}, {}), beyond one period P = {} of "
                                     "the block",
                                     k, e.x, e.y, P));
    rMax = std::max(rMax, s.radius);
    zLo = std::min({zLo, s.a.z - s.radius, s.b.z - s.radius});
    zHi = std::max({zHi, s.a.z + s.radius, s.b.z + s.radius});
  }
  const int n = voxelsPerPeriod > 0 ? voxelsPerPeriod : std::max(1, int(std::lround(P / (2.0f * rMax))));
  const float h = P / float(n);
  // One empty voxel below and above the fibers: samples there read "empty".
  const float z0 = zLo - h;
  const int nz = int(std::ceil((zHi - z0) / h)) + 1;
  if (n > 512 || nz > 512)
    throw InputError(fmt::format("exemplar volume: {} × {} × {} voxels (at most 512 a side): voxel size {} for "
                                 "period {}",
                                 n, n, nz, h, P));
  VolParams p{};
  p.origin = glm::vec4(0.0f, 0.0f, z0, h);
  p.dims = glm::uvec4(uint32_t(n), uint32_t(n), uint32_t(nz), uint32_t(block.segments.size()));
  const uint32_t B = uint32_t(cellVoxels);
  p.grid = glm::uvec4((p.dims.x + B - 1) / B, (p.dims.y + B - 1) / B, (p.dims.z + B - 1) / B, B);
  return p;
}

std::vector<VolSegment> volumeSegments(const Exemplar& block) {
  std::vector<VolSegment> out;
  out.reserve(block.segments.size());
  for (const ExemplarSegment& s : block.segments)
    out.push_back({glm::vec4(s.a, s.radius), glm::vec4(s.b, float(s.fiber))});
  return out;
}

VolumeCandidates buildVolumeCandidates(const Exemplar& block, const VolParams& p) {
  const glm::ivec3 n(p.dims.x, p.dims.y, p.dims.z), cells(p.grid.x, p.grid.y, p.grid.z);
  const int B = int(p.grid.w);
  const glm::vec3 o(p.origin);
  const float h = p.origin.w;
  std::vector<std::vector<uint32_t>> lists(size_t(cells.x) * cells.y * cells.z);
  for (size_t k = 0; k < block.segments.size(); ++k) {
    const ExemplarSegment& s = block.segments[k];
    for (uint32_t c = 0; c < FT_VOL_COPIES; ++c) {
      const glm::vec3 off = ftVolCopyOffset(c, block.period);
      const glm::vec3 lo = glm::min(s.a, s.b) + off - s.radius, hi = glm::max(s.a, s.b) + off + s.radius;
      // Voxels whose box the grown bounding box reaches, one voxel of slack
      // each side (float), clipped to the volume.
      glm::ivec3 v0 = glm::ivec3(glm::floor((lo - o) / h)) - 1, v1 = glm::ivec3(glm::floor((hi - o) / h)) + 1;
      v0 = glm::max(v0, glm::ivec3(0));
      v1 = glm::min(v1, n - 1);
      if (v0.x > v1.x || v0.y > v1.y || v0.z > v1.z) continue;
      const glm::ivec3 c0 = v0 / B, c1 = v1 / B;
      for (int z = c0.z; z <= c1.z; ++z)
        for (int y = c0.y; y <= c1.y; ++y)
          for (int x = c0.x; x <= c1.x; ++x)
            lists[(size_t(z) * cells.y + size_t(y)) * cells.x + size_t(x)].push_back(uint32_t(k) * FT_VOL_COPIES + c);
    }
  }
  VolumeCandidates out;
  out.start.reserve(lists.size() + 1);
  for (const auto& l : lists) {
    out.start.push_back(uint32_t(out.entries.size()));
    out.entries.insert(out.entries.end(), l.begin(), l.end());
    out.maxPerCell = std::max(out.maxPerCell, uint32_t(l.size()));
  }
  out.start.push_back(uint32_t(out.entries.size()));
  return out;
}

ExemplarVolume buildExemplarVolumeCpu(const Exemplar& block, const VolParams& p, const VolumeCandidates& cand) {
  ExemplarVolume vol;
  vol.layout = p;
  const size_t count = size_t(p.dims.x) * p.dims.y * p.dims.z;
  if (cand.start.size() != size_t(p.grid.x) * p.grid.y * p.grid.z + 1)
    throw std::invalid_argument("buildExemplarVolumeCpu: candidate lists of another layout");
  vol.ids.assign(count, 0u);
  vol.tieGap.assign(count, std::numeric_limits<float>::infinity());
  const std::vector<VolSegment> segs = volumeSegments(block);
  const float h = p.origin.w, P = ftVolPeriod(p);
  const uint32_t B = p.grid.w;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const glm::ivec3 v = ftVolVoxelOfIndex(uint32_t(i), p.dims);
      const glm::vec3 centre = ftVolVoxelCentre(v, p.origin);
      const glm::vec3 lo = centre - 0.5f * h, hi = centre + 0.5f * h;
      const size_t cell = (size_t(v.z) / B * p.grid.y + size_t(v.y) / B) * p.grid.x + size_t(v.x) / B;
      uint32_t best = 0;
      float bestKey = std::numeric_limits<float>::infinity(), secondKey = bestKey;
      for (uint32_t e = cand.start[cell]; e < cand.start[cell + 1]; ++e) {
        const uint32_t k = cand.entries[e] / FT_VOL_COPIES, c = cand.entries[e] % FT_VOL_COPIES;
        const glm::vec3 off = ftVolCopyOffset(c, P);
        const glm::vec3 a = glm::vec3(segs[k].a) + off, b = glm::vec3(segs[k].b) + off;
        if (!ftVolSegmentTouchesBox(a, b, segs[k].a.w, lo, hi)) continue;
        const float key = ftVolMidpointKey(centre, a, b);
        if (best == k + 1) {
          bestKey = std::min(bestKey, key);
          continue;
        }
        if (key < bestKey || (key == bestKey && k + 1 < best)) {
          if (best != 0) secondKey = bestKey;
          best = k + 1;
          bestKey = key;
        } else {
          secondKey = std::min(secondKey, key);
        }
      }
      vol.ids[i] = best;
      if (best != 0 && std::isfinite(secondKey))
        vol.tieGap[i] = (std::sqrt(secondKey) - std::sqrt(bestKey)) / h;
    }
  });
  vol.segments = segs;
  vol.candidates = cand;
  return vol;
}

uint32_t parseVolumeIds(const std::string& name) {
  if (name == "midpoint") return FT_VOL_IDS_MIDPOINT;
  if (name == "capsule") return FT_VOL_IDS_CAPSULE;
  throw InputError(fmt::format("volume ids '{}': midpoint or capsule", name));
}

const char* volumeIdsName(uint32_t ids) { return ids == FT_VOL_IDS_CAPSULE ? "capsule" : "midpoint"; }

void setVolumeRays(VolParams& p, const VolCamera& cam, int width, int height, int samples, uint32_t ids) {
  if (ids != FT_VOL_IDS_MIDPOINT && ids != FT_VOL_IDS_CAPSULE)
    throw std::invalid_argument(fmt::format("exemplar volume rays: id mode {} (0 midpoint, 1 capsule)", ids));
  if (width < 1 || height < 1 || width > 8192 || height > 8192 || samples < 1 || samples > int(FT_VOL_MAX_SAMPLES))
    throw std::invalid_argument(fmt::format("exemplar volume rays: {} × {} pixels, {} samples (1..{})", width,
                                            height, samples, FT_VOL_MAX_SAMPLES));
  const float len = glm::length(cam.direction);
  if (!(len > 0.0f) || !std::isfinite(len)) throw std::invalid_argument("exemplar volume rays: camera direction");
  const glm::vec3 f = cam.direction / len;
  glm::vec3 right = glm::cross(f, cam.up);
  if (!(glm::length(right) > 1e-6f)) throw std::invalid_argument("exemplar volume rays: camera up ∥ direction");
  right = glm::normalize(right);
  const glm::vec3 up = glm::cross(right, f);
  p.ray = glm::uvec4(uint32_t(width), uint32_t(height), uint32_t(samples), 0u);
  p.camPos = glm::vec4(cam.position, float(cam.type));
  p.camRight = glm::vec4(right, cam.halfWidth);
  p.camUp = glm::vec4(up, cam.halfHeight);
  p.camDir = glm::vec4(f, float(ids));
}

namespace {

// Every eye ray of `p` that crosses the volume's slab, in parallel over rows:
// f(pixel, origin, direction, [t_in, t_out]). Rays that miss the slab are left alone.
template <class F>
void forEachSlabRay(const VolParams& p, F&& f) {
  const float zLo = p.origin.z, zHi = p.origin.z + float(p.dims.z) * p.origin.w;
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, p.ray.y), [&](const tbb::blocked_range<uint32_t>& rows) {
    for (uint32_t y = rows.begin(); y != rows.end(); ++y)
      for (uint32_t x = 0; x < p.ray.x; ++x) {
        const glm::vec3 o = ftVolRayOrigin(p, x, y), d = ftVolRayDirection(p, x, y);
        const glm::vec2 t = ftVolSlabInterval(o, d, zLo, zHi);
        if (t.x <= t.y) f(size_t(y) * p.ray.x + x, o, d, t);
      }
  });
}

// The capsule ids (common/exemplar_volume.h "capsule ids"): the cell walk,
// in each cell the exact test of its candidates in the frame shifted by the
// cell's whole periods, the nearest hit once the walk has passed it.
void sampleCapsules(const ExemplarVolume& vol, const VolParams& p, std::vector<VolHit>& out,
                    std::vector<float>* tieGap) {
  const VolumeCandidates& cand = vol.candidates;
  if (vol.segments.size() != p.dims.w || cand.start.size() != size_t(p.grid.x) * p.grid.y * p.grid.z + 1)
    throw std::invalid_argument("sampleVolumeCpu: capsule ids need the volume's segments and candidate lists");
  const int nx = int(p.dims.x), ny = int(p.dims.y), nz = int(p.dims.z);
  const float P = ftVolPeriod(p), h = p.origin.w;
  forEachSlabRay(p, [&](size_t pix, glm::vec3 o, glm::vec3 d, glm::vec2 t) {
    float best = -1.0f, gap = std::numeric_limits<float>::infinity();
    uint32_t bestId = 0;
    std::vector<float> entries;  // the candidates' entries, for the tie gap
    VolWalk w = ftVolWalkBegin(o, d, t.x, p);
    for (uint32_t step = 0; step < FT_VOL_MAX_STEPS; ++step, w = ftVolWalkNext(o, d, w, p)) {
      if (w.v.z < 0 || w.v.z >= nz || w.t > t.y || (best >= 0.0f && w.t > best)) break;
      const glm::ivec3 wv(ftVolWrap(w.v.x, nx), ftVolWrap(w.v.y, ny), w.v.z);
      const int cell = int(ftVolCellOf(wv, p)), sx = ftVolPeriodsOf(w.v.x, nx), sy = ftVolPeriodsOf(w.v.y, ny);
      const glm::vec3 os = o - glm::vec3(float(sx) * P, float(sy) * P, 0.0f);
      for (uint32_t e = cand.start[size_t(cell)]; e < cand.start[size_t(cell) + 1]; ++e) {
        const uint32_t k = cand.entries[e] / FT_VOL_COPIES, c = cand.entries[e] % FT_VOL_COPIES;
        const glm::vec3 off = ftVolCopyOffset(c, P);
        const VolSegment& s = vol.segments[k];
        const float th = ftVolRayCapsule(os, d, glm::vec3(s.a) + off, glm::vec3(s.b) + off, s.a.w);
        if (th < 0.0f) continue;
        if (tieGap) entries.push_back(th), entries.push_back(float(k));
        if (best < 0.0f || th < best || (th == best && k + 1 < bestId)) best = th, bestId = k + 1;
      }
    }
    if (bestId == 0) return;
    out[pix] = VolHit{o + best * d, bestId};
    if (tieGap) {
      for (size_t i = 0; i < entries.size(); i += 2)
        if (uint32_t(entries[i + 1]) + 1 != bestId) gap = std::min(gap, std::abs(entries[i] - best) / h);
      (*tieGap)[pix] = gap;
    }
  });
}

}  // namespace

std::vector<VolHit> sampleVolumeCpu(const ExemplarVolume& vol, const VolParams& rays, std::vector<float>* faceDistance) {
  VolParams p = vol.layout;
  p.ray = rays.ray;
  p.camPos = rays.camPos;
  p.camRight = rays.camRight;
  p.camUp = rays.camUp;
  p.camDir = rays.camDir;
  const uint32_t W = p.ray.x, H = p.ray.y, N = p.ray.z;
  std::vector<VolHit> out(size_t(W) * H, VolHit{glm::vec3(0.0f), 0u});
  if (faceDistance) faceDistance->assign(out.size(), std::numeric_limits<float>::infinity());
  if (ftVolIdMode(p) == FT_VOL_IDS_CAPSULE) {
    sampleCapsules(vol, p, out, faceDistance);
    return out;
  }
  forEachSlabRay(p, [&](size_t pix, glm::vec3 o, glm::vec3 d, glm::vec2 t) {
    float face = std::numeric_limits<float>::infinity();
    for (uint32_t i = 0; i < N; ++i) {
      const float ti = ftVolSampleT(t.x, t.y, i, N);
      const glm::vec3 q = o + ti * d;
      face = std::min(face, ftVolFaceDistance(q, p.origin));
      const int idx = ftVolSampleIndex(o, d, ti, p);
      if (idx >= 0 && vol.ids[size_t(idx)] != 0u) {
        out[pix] = VolHit{q, vol.ids[size_t(idx)]};
        break;
      }
    }
    if (faceDistance) (*faceDistance)[pix] = face;
  });
  return out;
}

struct VolumeTruth::Impl {
  SvfScene scene;
};

VolumeTruth::VolumeTruth(std::span<const ExemplarSegment> segments)
    : impl_(std::make_unique<Impl>(Impl{SvfScene(segments)})) {}
VolumeTruth::~VolumeTruth() = default;
VolumeTruth::VolumeTruth(VolumeTruth&&) noexcept = default;
VolumeTruth& VolumeTruth::operator=(VolumeTruth&&) noexcept = default;

std::vector<VolHit> VolumeTruth::firstHits(const VolParams& p, float tFar) const {
  const uint32_t W = p.ray.x, H = p.ray.y;
  std::vector<VolHit> out(size_t(W) * H, VolHit{glm::vec3(0.0f), 0u});
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, H), [&](const tbb::blocked_range<uint32_t>& rows) {
    for (uint32_t y = rows.begin(); y != rows.end(); ++y)
      for (uint32_t x = 0; x < W; ++x) {
        const glm::vec3 o = ftVolRayOrigin(p, x, y), d = ftVolRayDirection(p, x, y);
        const auto [k, t] = impl_->scene.firstHit(o, d, tFar);
        if (k >= 0) out[size_t(y) * W + x] = VolHit{o + t * d, uint32_t(k) + 1u};
      }
  });
  return out;
}

}  // namespace ft
