// exemplar_volume.h — the CPU reference of the exemplar volume and eye-ray
// casting of Khungurn et al. 2017 (004) §5.1 (common/exemplar_volume.h for
// the conventions; docs/exemplar-volume.md):
//   * makeVolumeLayout: the grid of the periodic block (h = P / n, n =
//     round(P / 2r_f) unless given), the slab in z, the candidate grid;
//   * buildVolumeCandidates: per cell of the uniform candidate grid (B³
//     voxels), the (segment, copy) pairs whose grown bounding box reaches it;
//   * buildExemplarVolumeCpu: per voxel, brute force over its cell's
//     candidates: the conservative capsule–box test, the nearest midpoint;
//   * sampleVolumeCpu: the scalar ray sampler → G-buffer (id, flat point):
//     004's nearest midpoint at the first non-empty sample, or the first exact
//     capsule hit among the candidates of the cells crossed;
//   * VolumeTruth: Embree first hits against the real capsules (round linear
//     curves) of the tiled exemplar.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/exemplar_volume.h"
#include "reference/exemplar.h"

namespace ft {

// Throws InputError naming the value for a block without segments, a
// non-finite or non-positive radius / period, or a grid beyond 512³.
// voxelsPerPeriod ≤ 0: round(P / 2r_f) with r_f the block's largest radius.
VolParams makeVolumeLayout(const Exemplar& block, int voxelsPerPeriod = 0, int cellVoxels = 4);

// The segment table of the GPU (a: endpoint + radius, b: endpoint + fiber).
std::vector<VolSegment> volumeSegments(const Exemplar& block);

struct VolumeCandidates {
  std::vector<uint32_t> start;    // cells + 1 offsets into entries (cell = (cz·cy + cy)·cx + cx)
  std::vector<uint32_t> entries;  // segment · 9 + copy (common/exemplar_volume.h ftVolCopyOffset)
  uint32_t maxPerCell = 0;
};
VolumeCandidates buildVolumeCandidates(const Exemplar& block, const VolParams& layout);

struct ExemplarVolume {
  VolParams layout{};
  std::vector<uint32_t> ids;  // nx·ny·nz, 0 = empty, else 1 + block segment index
  // Per voxel: second-nearest minus nearest midpoint distance among the
  // touching capsules with a different id (+∞ when fewer than two), in units
  // of h: voxels with a gap below ~1e-6 are ties that float rounding decides.
  std::vector<float> tieGap;
  // What the capsule ids need (buildExemplarVolumeCpu copies them): the
  // block's segment table and the candidate lists of the layout.
  std::vector<VolSegment> segments;
  VolumeCandidates candidates;
};
// TBB over voxels.
ExemplarVolume buildExemplarVolumeCpu(const Exemplar& block, const VolParams& layout,
                                      const VolumeCandidates& candidates);

// The camera of the G-buffer (fills VolParams' cam* and ray fields).
struct VolCamera {
  uint32_t type = FT_VOL_CAMERA_ORTHO;
  glm::vec3 position{0.0f};  // ortho: centre of the image rectangle; pinhole: the eye
  glm::vec3 direction{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};  // projected to ⊥ direction
  float halfWidth = 1.0f;          // ortho: length; pinhole: tan(fov_x / 2)
  float halfHeight = 1.0f;
};
// Writes the camera, (width, height, samples) and the id (FT_VOL_IDS_*, in
// camDir.w) into layout. Throws std::invalid_argument for sizes ≤ 0, samples
// outside 1 … FT_VOL_MAX_SAMPLES, an unknown id or a degenerate camera.
void setVolumeRays(VolParams& layout, const VolCamera& camera, int width, int height, int samples,
                   uint32_t ids = FT_VOL_IDS_MIDPOINT);

// "midpoint" / "capsule" ↔ FT_VOL_IDS_*; parseVolumeIds throws InputError naming the value.
uint32_t parseVolumeIds(const std::string& name);
const char* volumeIdsName(uint32_t ids);

// The scalar sampler: per pixel (row-major), by rays.camDir.w's id: the first
// non-empty sample (FT_VOL_IDS_MIDPOINT) or the first capsule hit
// (FT_VOL_IDS_CAPSULE: exact point, N unused; throws std::invalid_argument
// when the volume has no candidates).
// faceDistance (optional, per pixel): midpoint ids: the smallest distance to
// a voxel face, in units of h, over the samples read (all of them on a miss);
// capsule ids: the smallest |t − t'| / h between the hit and another
// candidate's entry (+∞ for none: ties between capsules, e.g. at the joint of
// two segments of a fiber, are decided by float rounding).
std::vector<VolHit> sampleVolumeCpu(const ExemplarVolume& volume, const VolParams& rays,
                                    std::vector<float>* faceDistance = nullptr);

// The truth: Embree first hits on the capsules of `segments` (the tiled
// exemplar). Ids: 1 + index into `segments`, 0 = miss.
class VolumeTruth {
 public:
  // Throws InputError naming the segment for bad geometry, std::runtime_error when Embree fails.
  explicit VolumeTruth(std::span<const ExemplarSegment> segments);
  ~VolumeTruth();
  VolumeTruth(VolumeTruth&&) noexcept;
  VolumeTruth& operator=(VolumeTruth&&) noexcept;
  // The rays of `rays` (camera fields), each as far as t = tFar.
  std::vector<VolHit> firstHits(const VolParams& rays, float tFar) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ft
