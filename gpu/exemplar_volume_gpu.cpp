#include "gpu/exemplar_volume_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "gpu/compute_dispatch.h"
#include "gpu/gl_check.h"
#include "gpu/shader_library.h"

namespace ft {

ExemplarVolumeGpu::ExemplarVolumeGpu(const GlInfo& gl, const std::vector<std::string>& defines)
    : maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {
  GLint ubos = 0;
  glGetIntegerv(GL_MAX_UNIFORM_BUFFER_BINDINGS, &ubos);
  if (ubos <= FT_UBO_PRT_VOL)
    throw std::runtime_error(fmt::format("ExemplarVolumeGpu: UBO binding {} needs more than the context's {} "
                                         "bindings",
                                         FT_UBO_PRT_VOL, ubos));
  build_ = Program(buildProgram({"shaders/exemplar_volume_build.comp.glsl"}, defines));
  sample_ = Program(buildProgram({"shaders/exemplar_volume_sample.comp.glsl"}, defines));
}

void ExemplarVolumeGpu::build(const VolParams& p, std::span<const VolSegment> segments,
                              std::span<const uint32_t> start, std::span<const uint32_t> entries) {
  const size_t cells = size_t(p.grid.x) * p.grid.y * p.grid.z;
  const size_t voxels = size_t(p.dims.x) * p.dims.y * p.dims.z;
  if (voxels == 0 || p.grid.w == 0 || start.size() != cells + 1 || segments.size() != p.dims.w ||
      start.back() != entries.size() || !(p.origin.w > 0.0f))
    throw std::invalid_argument(fmt::format("ExemplarVolumeGpu::build: {} voxels, {} cells ({} offsets, {} "
                                            "entries), {} segments for {}",
                                            voxels, cells, start.size(), entries.size(), segments.size(), p.dims.w));
  for (uint32_t e : entries)
    if (e / FT_VOL_COPIES >= segments.size())
      throw std::invalid_argument(fmt::format("ExemplarVolumeGpu::build: candidate entry {} names segment {} of {}",
                                              e, e / FT_VOL_COPIES, segments.size()));
  layout_ = p;
  std::vector<uint32_t> cand(start.begin(), start.end());
  cand.insert(cand.end(), entries.begin(), entries.end());
  const Buffer u = Buffer::create(sizeof(VolParams), &p);
  const Buffer segs = Buffer::create(segments.size() * sizeof(VolSegment), segments.data());
  const Buffer c = Buffer::create(cand.size() * 4, cand.data());
  // The ids (written by the build), then the candidate lists and the segment
  // table for the capsule ids (common/exemplar_volume.h ftVolCandidateBase).
  std::vector<uint32_t> all(voxels, 0u);
  all.insert(all.end(), cand.begin(), cand.end());
  const size_t segBase = all.size();
  all.resize(segBase + segments.size() * (sizeof(VolSegment) / 4));
  std::memcpy(all.data() + segBase, segments.data(), segments.size() * sizeof(VolSegment));
  ids_ = Buffer::create(all.size() * 4, all.data());
  u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_VOL);
  segs.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_VOL_SEGMENTS);
  c.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_REQUESTS);
  ids_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_VOL_IDS);
  dispatchFlat(build_.id(), voxels, FT_WG_PRT_VOL, maxGroupsY_, "exemplar_volume_build");
}

std::vector<uint32_t> ExemplarVolumeGpu::ids() const {
  return readBuffer<uint32_t>(ids_.id(), size_t(layout_.dims.x) * layout_.dims.y * layout_.dims.z);
}

const Buffer& ExemplarVolumeGpu::sampleNoReadback(const VolParams& rays) {
  if (ids_.id() == 0) throw std::logic_error("ExemplarVolumeGpu::sample before build");
  if (rays.ray.x == 0 || rays.ray.y == 0 || rays.ray.z == 0 || rays.ray.z > FT_VOL_MAX_SAMPLES ||
      (ftVolIdMode(rays) != FT_VOL_IDS_MIDPOINT && ftVolIdMode(rays) != FT_VOL_IDS_CAPSULE))
    throw std::invalid_argument(fmt::format("ExemplarVolumeGpu::sample: {} × {} rays, {} samples (1..{}), ids {}",
                                            rays.ray.x, rays.ray.y, rays.ray.z, FT_VOL_MAX_SAMPLES, rays.camDir.w));
  VolParams p = layout_;
  p.ray = rays.ray;
  p.camPos = rays.camPos;
  p.camRight = rays.camRight;
  p.camUp = rays.camUp;
  p.camDir = rays.camDir;
  const size_t pixels = size_t(p.ray.x) * p.ray.y;
  if (gbuffer_.id() == 0 || gbuffer_.size() != pixels * sizeof(VolHit)) gbuffer_ = Buffer::create(pixels * sizeof(VolHit));
  const Buffer u = Buffer::create(sizeof(VolParams), &p);
  u.bindBase(GL_UNIFORM_BUFFER, FT_UBO_PRT_VOL);
  ids_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_VOL_IDS);
  gbuffer_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PRT_RESULTS);
  dispatchFlat(sample_.id(), pixels, FT_WG_PRT_VOL, maxGroupsY_, "exemplar_volume_sample");
  return gbuffer_;
}

std::vector<VolHit> ExemplarVolumeGpu::sample(const VolParams& rays) {
  sampleNoReadback(rays);
  return readBuffer<VolHit>(gbuffer_.id(), size_t(rays.ray.x) * rays.ray.y);
}

}  // namespace ft
