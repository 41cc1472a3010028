// exemplar_volume_gpu.h — the GPU twin of the exemplar volume and eye-ray
// casting of 004 §5.1 (common/exemplar_volume.h; docs/exemplar-volume.md):
// build the segment-id volume from the block's segment table and the
// candidate lists of a uniform grid (exemplar_volume_build.comp.glsl), then
// cast eye rays by volume sampling into a G-buffer
// (exemplar_volume_sample.comp.glsl). The volume stays on the GPU between
// build() and sample(); its buffer carries, after the voxels' ids, the
// candidate lists and the segment table that the capsule ids test
// (common/exemplar_volume.h ftVolCandidateBase; llvmpipe has no free SSBO
// slot for them, and sample() then binds nothing beyond slots 64 and 40).
#pragma once
#include <epoxy/gl.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/exemplar_volume.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

class ExemplarVolumeGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, validation/faults.h).
  // Throws std::runtime_error when the context has fewer UBO bindings than FT_UBO_PRT_VOL needs.
  explicit ExemplarVolumeGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});

  // Builds the volume of `layout` (origin, dims, grid): segments = the block's
  // table, start = the cells + 1 offsets, entries = segment · 9 + copy.
  // Throws std::invalid_argument for inconsistent sizes.
  void build(const VolParams& layout, std::span<const VolSegment> segments, std::span<const uint32_t> start,
             std::span<const uint32_t> entries);
  // The built volume's ids (nx·ny·nz).
  std::vector<uint32_t> ids() const;
  // The G-buffer of the rays of `rays` (its ray and cam* fields; camDir.w the
  // id, FT_VOL_IDS_*) through the built volume, row-major.
  std::vector<VolHit> sample(const VolParams& rays);
  // Dispatch only, no read-back: the G-buffer (width × height VolHit) stays on
  // the GPU, owned by this object until the next call.
  const Buffer& sampleNoReadback(const VolParams& rays);

 private:
  int maxGroupsY_ = 65535;
  Program build_, sample_;
  VolParams layout_{};
  Buffer ids_, gbuffer_;
};

}  // namespace ft
