#include "gpu/fiber_gpu.h"

#include <algorithm>
#include <atomic>
#include <fmt/format.h>
#include <stdexcept>

#include "common/constants.h"
#include "common/fiber_generation.h"
#include "gpu/shader_library.h"

namespace ft {

namespace {

Buffer makeBuffer(size_t bytes, const void* data = nullptr) {
  // Never empty (binding a zero-size buffer is an error); upload only the
  // caller's bytes (ASan caught a 16-byte read of an 8-byte table).
  Buffer b = Buffer::createMutable(std::max<size_t>(bytes, 16));
  if (data && bytes) b.update(data, bytes);
  return b;
}

// The old buffer is deleted by the move assignment.
void replaceBuffer(Buffer& b, size_t bytes, const void* data = nullptr) { b = makeBuffer(bytes, data); }

template <class T>
std::vector<T> readBack(GLuint buffer, size_t count) {
  std::vector<T> out(count);
  if (count) glGetNamedBufferSubData(buffer, 0, static_cast<GLsizeiptr>(count * sizeof(T)), out.data());
  return out;
}

void setUint(GLuint program, const char* name, uint32_t value) {
  GLint loc = glGetUniformLocation(program, name);
  if (loc >= 0) glProgramUniform1ui(program, loc, value);
}

uint32_t checkedGroups(size_t items, size_t groupSize, int limit, const char* what) {
  const size_t groups = (items + groupSize - 1) / groupSize;
  if (groups > static_cast<size_t>(limit))
    throw std::runtime_error(fmt::format("{}: {} work groups exceed GL_MAX_COMPUTE_WORK_GROUP_COUNT ({})", what,
                                         groups, limit));
  return static_cast<uint32_t>(groups);
}

}  // namespace

// llvmpipe (Mesa 22.3) loses or misplaces tessellation output when one patch
// emits more than ~316 isoline vertices (measured: 315 correct, 318 and 320
// wrong; tests/fiber_gpu_test.cpp InstancedPatches... catches it). On
// llvmpipe a patch emits at most this many, and more instances make up for it.
constexpr int kLlvmpipeMaxPatchVertices = 256;

FiberGpu::FiberGpu(const GlInfo& gl, std::vector<std::string> defines)
    : defines_(std::move(defines)),
      maxTessGenLevel_(std::min(gl.maxTessGenLevel, 64)),
      maxPatchVertices_(gl.renderer.find("llvmpipe") != std::string::npos ? kLlvmpipeMaxPatchVertices : 0),
      maxGroupsX_(std::clamp(gl.maxComputeWorkGroupCount[0], 1, 65535)),
      maxGroupsY_(gl.maxComputeWorkGroupCount[1]),
      maxGroupsZ_(gl.maxComputeWorkGroupCount[2]) {
  framesProgram_ = Program(buildProgram({"shaders/yarn_frames.comp.glsl"}, defines_));
  decideProgram_ = Program(buildProgram({"shaders/fiber_decide.comp.glsl"}, defines_));
  scanProgram_ = Program(buildProgram({"shaders/fiber_scan.comp.glsl"}, defines_));
  ownersProgram_ = Program(buildProgram({"shaders/fiber_owners.comp.glsl"}, defines_));
  samplesProgram_ = Program(buildProgram({"shaders/fiber_samples.comp.glsl"}, defines_));
  generateProgram_ = Program(buildProgram({"shaders/fiber_generate.comp.glsl"}, defines_));
  const std::vector<std::string> tess = {"shaders/fiber_tess.vert.glsl", "shaders/fiber_tess.tesc.glsl",
                                         "shaders/fiber_tess.tese.glsl"};
  tessCaptureProgram_ = Program(buildProgram(tess, defines_, {"fiberPosition", "fiberId"}));
  vao_ = VertexArray::create();
  captureFbo_ = Framebuffer::create();
  glNamedFramebufferParameteri(captureFbo_.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, 1);
  glNamedFramebufferParameteri(captureFbo_.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, 1);
  yarnUbo_ = makeBuffer(sizeof(YarnParams));
  viewUbo_ = makeBuffer(sizeof(ViewParams));
  draw_ = makeBuffer(sizeof(DrawElementsCommand));
}

void FiberGpu::bindCommon() const {
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_YARN_PARAMS, yarnUbo_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_VIEW_PARAMS, viewUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_CONTROL_POINTS, points_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_CURVES, curves_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SEGMENTS, segments_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FRAMES, frames_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FIBER_TABLE, table_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SEGMENT_LIST, list_.id());
  if (decisions_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_DECISIONS, decisions_.id());
  if (offsets_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_OFFSETS, offsets_.id());
  if (samples_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SAMPLES, samples_.id());
  if (stripOwners_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_STRIP_OWNERS, stripOwners_.id());
  if (sampleOwners_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SAMPLE_OWNERS, sampleOwners_.id());
  if (vertices_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_VERTICES, vertices_.id());
  if (indices_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_INDICES, indices_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_DRAW_COMMAND, draw_.id());
}

void FiberGpu::setModel(const YarnBuffers& yarn, std::span<const FiberCoord> fiberTable) {
  static std::atomic<uint64_t> versions{0};
  modelVersion_ = ++versions;
  replaceBuffer(points_, yarn.points.size() * sizeof(ControlPoint), yarn.points.data());
  replaceBuffer(curves_, yarn.curves.size() * sizeof(CurveInfo), yarn.curves.data());
  replaceBuffer(segments_, yarn.segments.size() * sizeof(SegmentRef), yarn.segments.data());
  replaceBuffer(table_, fiberTable.size_bytes(), fiberTable.data());
  replaceBuffer(frames_, yarn.knotCount * sizeof(FrameNormal));
  replaceBuffer(frameCarry_, yarn.curves.size() * sizeof(glm::vec4));
  curveCount_ = yarn.curves.size();
  segmentCount_ = yarn.segments.size();
  boundsMin_ = glm::vec3(0.0f);
  boundsMax_ = glm::vec3(0.0f);
  for (size_t k = 0; k < yarn.points.size(); ++k) {
    const glm::vec3 p(yarn.points[k].positionLength);
    boundsMin_ = k == 0 ? p : glm::min(boundsMin_, p);
    boundsMax_ = k == 0 ? p : glm::max(boundsMax_, p);
  }
  knotCount_ = yarn.knotCount;
  inputBytes_ = yarn.byteSize() + fiberTable.size_bytes();
  setSegmentList({});

  bindCommon();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FRAME_CARRY, frameCarry_.id());
  glUseProgram(framesProgram_.id());
  // One dispatch per FT_FRAME_CHUNK knots of the longest curve (gallivm ends a
  // loop after 65,535 iterations), then the closed-loop correction.
  uint32_t longest = 0;
  bool anyClosed = false;
  for (const CurveInfo& c : yarn.curves) {
    longest = std::max(longest, ftCurveSegmentCount(c));
    anyClosed = anyClosed || c.closed != 0u;
  }
  const uint32_t chunks = (longest + FT_FRAME_CHUNK - 1) / FT_FRAME_CHUNK;
  setUint(framesProgram_.id(), "mode", 0u);
  setUint(framesProgram_.id(), "itemCount", static_cast<uint32_t>(curveCount_));
  for (uint32_t chunk = 0; chunk < chunks; ++chunk) {
    setUint(framesProgram_.id(), "chunk", chunk);
    dispatchFlat(framesProgram_.id(), curveCount_, FT_WG_FRAMES, "yarn_frames");
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  if (anyClosed) {
    setUint(framesProgram_.id(), "mode", 1u);
    setUint(framesProgram_.id(), "itemCount", static_cast<uint32_t>(segmentCount_));
    dispatchFlat(framesProgram_.id(), segmentCount_, FT_WG_FRAMES, "yarn_frames (closed loops)");
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void FiberGpu::setParams(const YarnParams& params, const ViewParams& view) {
  params_ = params;
  view_ = view;
  yarnUbo_.update(&params, sizeof(YarnParams));
  viewUbo_.update(&view, sizeof(ViewParams));
}

void FiberGpu::setSegmentList(std::span<const uint32_t> segments) {
  std::vector<uint32_t> all;
  if (segments.empty()) {
    all.resize(segmentCount_);
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
    segments = all;
  }
  for (uint32_t s : segments)
    if (s >= segmentCount_)
      throw std::runtime_error(fmt::format("segment list: segment {} out of range ({} segments)", s, segmentCount_));
  listCount_ = segments.size();
  replaceBuffer(list_, segments.size_bytes(), segments.data());
  replaceBuffer(decisions_, listCount_ * sizeof(SegmentDecision));
  replaceBuffer(offsets_, listCount_ * sizeof(glm::uvec4));
}

std::vector<FrameNormal> FiberGpu::readFrames() const { return readBack<FrameNormal>(frames_.id(), knotCount_); }

void FiberGpu::decideAndScan() {
  bindCommon();
  glUseProgram(decideProgram_.id());
  setUint(decideProgram_.id(), "listCount", static_cast<uint32_t>(listCount_));
  dispatchFlat(decideProgram_.id(), listCount_, FT_WG_DECIDE, "fiber_decide");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(scanProgram_.id());
  setUint(scanProgram_.id(), "listCount", static_cast<uint32_t>(listCount_));
  glDispatchCompute(1, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

void FiberGpu::generateCompute() {
  decideAndScan();
  // The only CPU–GPU sync of the path: the totals size the output buffers.
  ensureComputeCapacity();
  bindCommon();
  glUseProgram(ownersProgram_.id());
  setUint(ownersProgram_.id(), "listCount", static_cast<uint32_t>(listCount_));
  dispatchFlat(ownersProgram_.id(), listCount_, FT_WG_DECIDE, "fiber_owners");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(samplesProgram_.id());
  setUint(samplesProgram_.id(), "listCount", static_cast<uint32_t>(listCount_));
  setUint(samplesProgram_.id(), "sampleTotal", static_cast<uint32_t>(pendingSamples_));
  dispatchFlat(samplesProgram_.id(), pendingSamples_, FT_WG_SAMPLES, "fiber_samples");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(generateProgram_.id());
  setUint(generateProgram_.id(), "listCount", static_cast<uint32_t>(listCount_));
  setUint(generateProgram_.id(), "stripTotal", static_cast<uint32_t>(pendingStrips_));
  dispatchFlat(generateProgram_.id(), pendingStrips_, FT_WG_GENERATE, "fiber_generate");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void FiberGpu::dispatchFlat(GLuint program, size_t items, size_t groupSize, const char* what) {
  if (items == 0) return;
  const size_t groups = (items + groupSize - 1) / groupSize;
  const uint32_t groupsX = static_cast<uint32_t>(std::min<size_t>(groups, static_cast<size_t>(maxGroupsX_)));
  const uint32_t groupsY = checkedGroups(groups, groupsX, maxGroupsY_, what);
  setUint(program, "groupsX", groupsX);
  glDispatchCompute(groupsX, groupsY, 1);
}

void FiberGpu::ensureComputeCapacity() {
  const DrawElementsCommand cmd = readDrawCommand();
  pendingStrips_ = cmd.stripTotal;
  pendingSamples_ = cmd.sampleTotal;
  if (cmd.sampleTotal > sampleCapacity_ || !samples_) {
    sampleCapacity_ = std::max<size_t>(cmd.sampleTotal, sampleCapacity_ * 3 / 2);
    replaceBuffer(samples_, sampleCapacity_ * sizeof(YarnSample));
    replaceBuffer(sampleOwners_, sampleCapacity_ * sizeof(uint32_t));
  }
  if (cmd.stripTotal > stripCapacity_ || !stripOwners_) {
    stripCapacity_ = std::max<size_t>(cmd.stripTotal, stripCapacity_ * 3 / 2);
    replaceBuffer(stripOwners_, stripCapacity_ * sizeof(uint32_t));
  }
  if (cmd.vertexTotal > vertexCapacity_ || !vertices_) {
    vertexCapacity_ = std::max<size_t>(cmd.vertexTotal, vertexCapacity_ * 3 / 2);
    replaceBuffer(vertices_, vertexCapacity_ * sizeof(FiberVertex));
  }
  if (cmd.count > indexCapacity_ || !indices_) {
    indexCapacity_ = std::max<size_t>(cmd.count, indexCapacity_ * 3 / 2);
    replaceBuffer(indices_, indexCapacity_ * sizeof(uint32_t));
  }
}

std::vector<SegmentDecision> FiberGpu::readDecisions() const {
  return readBack<SegmentDecision>(decisions_.id(), listCount_);
}

DrawElementsCommand FiberGpu::readDrawCommand() const {
  DrawElementsCommand cmd{};
  glGetNamedBufferSubData(draw_.id(), 0, sizeof(cmd), &cmd);
  return cmd;
}

std::vector<FiberVertex> FiberGpu::readComputeVertices() const {
  return readBack<FiberVertex>(vertices_.id(), readDrawCommand().vertexTotal);
}

std::vector<uint32_t> FiberGpu::readComputeIndices() const {
  return readBack<uint32_t>(indices_.id(), readDrawCommand().count);
}

size_t FiberGpu::tessellationCapacity() const { return xfbCapacityLines_; }

uint32_t FiberGpu::linesPerPatch() const {
  int lines = maxTessGenLevel_;
  if (maxPatchVertices_ > 0)
    lines = std::min(lines, maxPatchVertices_ / static_cast<int>(params_.maxSubdivisions + 1));
  return static_cast<uint32_t>(std::max(lines, 1));
}

size_t FiberGpu::captureTessellation() {
  // Size the capture from the GPU's own decisions (decide + scan passes); an
  // overflow is still detected below by comparing the two primitive queries.
  decideAndScan();
  // Every isoline has `subdivisions` lines, the core's too (its vertices past
  // the last repeat it: fiber_tess.tese.glsl).
  const std::vector<SegmentDecision> decisions = readDecisions();
  size_t lines = 0;
  for (size_t i = 0; i < listCount_; ++i)
    if (!decisions[i].culled)
      lines += size_t(params_.plyCount) * (1u + decisions[i].regularCount) * decisions[i].subdivisions;
  if (lines > xfbCapacityLines_ || !xfb_) {
    xfbCapacityLines_ = std::max<size_t>(lines, 1);
    replaceBuffer(xfb_, xfbCapacityLines_ * 2 * sizeof(FiberVertex));
  }

  bindCommon();
  glUseProgram(tessCaptureProgram_.id());
  setUint(tessCaptureProgram_.id(), "linesPerPatch", linesPerPatch());
  glBindVertexArray(vao_.id());
  glPatchParameteri(GL_PATCH_VERTICES, 4);
  const uint32_t slots = params_.plyCount * (1u + params_.regularFibers);
  const uint32_t instances = (slots + linesPerPatch() - 1) / linesPerPatch();
  // One transform-feedback session per (instance block, chunk of segments),
  // each into its own buffer range after what the previous ones wrote:
  //  * llvmpipe (Mesa 22.3) misplaces output when a tessellated draw with
  //    several instances, or several draws, append within one session (part of
  //    the first block is overwritten; tests/fiber_gpu_test.cpp
  //    InstancedPatches... catches it);
  //  * its capture time grows quadratically with the lines one draw writes
  //    (600 full-detail segments: 2.4 s in one draw), so draws are cut into
  //    chunks of about kCaptureLinesPerDraw lines; a trailing range that
  //    emits nothing in this instance block is not drawn.
  // Rendering uses one instanced draw with the same shaders.
  constexpr size_t kCaptureLinesPerDraw = 16384;
  // Chunk boundaries from the GPU's own decisions (lines each listed segment
  // emits in each instance block).
  const uint32_t perPatch = linesPerPatch();
  glBindFramebuffer(GL_FRAMEBUFFER, captureFbo_.id());
  glEnable(GL_RASTERIZER_DISCARD);
  const Query primitivesGenerated = Query::create(GL_PRIMITIVES_GENERATED);
  const Query primitivesWritten = Query::create(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
  size_t written = 0, generated = 0;
  const size_t lineBytes = 2 * sizeof(FiberVertex);
  auto drawChunk = [&](size_t first, size_t count) {
    const size_t room = xfbCapacityLines_ > written ? xfbCapacityLines_ - written : 0;
    if (room == 0)  // still draw, to count what overflowed
      glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, 0, xfb_.id(), 0, static_cast<GLsizeiptr>(lineBytes));
    else
      glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, 0, xfb_.id(), static_cast<GLintptr>(written * lineBytes),
                        static_cast<GLsizeiptr>(room * lineBytes));
    glBeginQuery(GL_PRIMITIVES_GENERATED, primitivesGenerated.id());
    glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, primitivesWritten.id());
    glBeginTransformFeedback(GL_LINES);
    glDrawArrays(GL_PATCHES, static_cast<GLint>(4 * first), static_cast<GLsizei>(4 * count));
    glEndTransformFeedback();
    glEndQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
    glEndQuery(GL_PRIMITIVES_GENERATED);
    GLuint g = 0, w = 0;
    glGetQueryObjectuiv(primitivesGenerated.id(), GL_QUERY_RESULT, &g);
    glGetQueryObjectuiv(primitivesWritten.id(), GL_QUERY_RESULT, &w);
    generated += g;
    written += room == 0 ? 0 : w;
  };
  for (uint32_t k = 0; k < instances; ++k) {
    setUint(tessCaptureProgram_.id(), "instanceOffset", k);
    size_t first = 0, lines = 0;
    for (size_t i = 0; i < listCount_; ++i) {
      const SegmentDecision& d = decisions[i];
      const uint32_t slots = d.culled ? 0u : params_.plyCount * (1u + d.regularCount);
      const uint32_t begin = k * perPatch;
      const size_t mine = slots > begin ? std::min(slots - begin, perPatch) * size_t(d.subdivisions) : 0;
      if (lines > 0 && lines + mine > kCaptureLinesPerDraw) {
        drawChunk(first, i - first);
        first = i;
        lines = 0;
      }
      lines += mine;
    }
    if (lines > 0) drawChunk(first, listCount_ - first);
  }
  glDisable(GL_RASTERIZER_DISCARD);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (generated != written)
    throw std::runtime_error(fmt::format("tessellation capture overflow: {} lines generated, {} written (buffer "
                                         "sized for {} from the GPU decisions)",
                                         generated, written, xfbCapacityLines_));
  xfbLines_ = written;
  return xfbLines_;
}

std::vector<FiberVertex> FiberGpu::readTessellationLines() const { return readBack<FiberVertex>(xfb_.id(), 2 * xfbLines_); }

FiberGpu::~FiberGpu() = default;

FiberDrawStages FiberGpu::drawStages(FiberPath path) const {
  if (path == FiberPath::Compute) return {{"shaders/fiber_strip.vert.glsl"}, {}};
  // The evaluation stage also gives the strip tangent when it feeds a draw.
  return {{"shaders/fiber_tess.vert.glsl", "shaders/fiber_tess.tesc.glsl", "shaders/fiber_tess.tese.glsl"},
          {"FT_STRIP_TANGENTS"}};
}

void FiberGpu::prepareDraw(FiberPath path) {
  if (path == FiberPath::Compute) generateCompute();
  bindCommon();
  glBindVertexArray(vao_.id());
}

void FiberGpu::draw(FiberPath path, GLuint program) {
  glUseProgram(program);
  if (path == FiberPath::Compute) drawCompute(program);
  else drawTessellation(program);
}

void FiberGpu::drawComputeIndices(GLuint program, GLuint indexBuffer) {
  glUseProgram(program);
  drawCompute(program, indexBuffer);
}

void FiberGpu::drawCompute(GLuint program, GLuint indexBuffer) {
  setUint(program, "vertexTotal", readDrawCommand().vertexTotal);
  setUint(program, "listCount", static_cast<uint32_t>(listCount_));  // the yarn frame of each vertex
  glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer != 0 ? indexBuffer : indices_.id());
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, draw_.id());
  glDrawElementsIndirect(GL_LINE_STRIP, GL_UNSIGNED_INT, nullptr);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glDisable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
}

void FiberGpu::drawTessellation(GLuint program) {
  setUint(program, "linesPerPatch", linesPerPatch());
  setUint(program, "instanceOffset", 0u);
  glPatchParameteri(GL_PATCH_VERTICES, 4);
  const uint32_t slots = params_.plyCount * (1u + params_.regularFibers);
  const GLsizei instances = static_cast<GLsizei>((slots + linesPerPatch() - 1) / linesPerPatch());
  glDrawArraysInstanced(GL_PATCHES, 0, static_cast<GLsizei>(4 * listCount_), instances);
}

void FiberGpu::drawVertices(std::span<const FiberVertex> vertices, std::span<const SegmentDecision> decisions,
                            GLuint program) {
  // Rebuild the strip indices of a canonical-order stream on the host.
  std::vector<uint32_t> indices;
  size_t base = 0;
  for (const SegmentDecision& d : decisions) {
    if (d.culled) continue;
    for (uint32_t ply = 0; ply < params_.plyCount; ++ply)
      for (uint32_t slot = 0; slot < ftSlotsPerPly(d); ++slot) {
        for (uint32_t v = 0; v < ftStripVertexCount(d, slot); ++v) indices.push_back(static_cast<uint32_t>(base++));
        indices.push_back(FT_RESTART_INDEX);
      }
  }
  if (base != vertices.size())
    throw std::runtime_error(fmt::format("drawVertices: decisions describe {} vertices, stream has {}", base,
                                         vertices.size()));
  const Buffer vbo = makeBuffer(vertices.size_bytes(), vertices.data());
  const Buffer ibo = makeBuffer(indices.size() * sizeof(uint32_t), indices.data());
  bindCommon();
  glBindVertexArray(vao_.id());
  glUseProgram(program);
  setUint(program, "vertexTotal", static_cast<uint32_t>(vertices.size()));
  setUint(program, "listCount", 0u);  // a foreign stream: no yarn samples of its own
  vbo.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_VERTICES);
  glEnable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo.id());
  glDrawElements(GL_LINE_STRIP, static_cast<GLsizei>(indices.size()), GL_UNSIGNED_INT, nullptr);
  glDisable(GL_PRIMITIVE_RESTART_FIXED_INDEX);
  if (vertices_) vertices_.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_VERTICES);  // the compute path's again
}

}  // namespace ft
