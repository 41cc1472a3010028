// fiber_gpu.h — the GPU side of procedural fiber generation: both paths of
// issue "spine" (000_cc9bd0fbd0e08a03.txt §3, §5), fed only by the yarn
// control points with their length coordinates, the curve/segment tables and
// the fiber-coordinate table.
//   * tessellation: instanced isoline patches, TCS decides LoD/culling, TES
//     evaluates fibers, GS expands lines to camera-facing strips;
//   * compute: decide → scan → owners → yarn samples → generate into a vertex
//     + index buffer and an indirect draw command; LoD and culling decided on
//     the GPU.
// Both can hand their vertices back (transform feedback / buffer read-back).
// Drawing them (targets, shading) is gpu/fiber_renderer.h's.
#pragma once
#include <epoxy/gl.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "common/fiber_vertex.h"
#include "common/view_params.h"
#include "common/yarn_buffers.h"
#include "common/yarn_params.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"
#include "scene/fiber_input.h"

namespace ft {

// The two ways the GPU makes fiber geometry (000 §5): compute kernels that
// write a vertex + index buffer drawn with an indirect draw, or tessellation
// stages that evaluate the fibers while they are drawn.
enum class FiberPath { Compute, Tessellation };

// The stages of a draw program that bring a path's fibers to the geometry
// stage (gpu/fiber_renderer.h appends the strip geometry and fragment stages).
struct FiberDrawStages {
  std::vector<std::string> files;
  std::vector<std::string> defines;
};

class FiberGpu {
 public:
  // `defines` are injected into every shader (fault injection uses them);
  // limits (GL_MAX_TESS_GEN_LEVEL, work-group counts) come from `gl`.
  // GL objects are RAII owners (gpu/gl_objects.h): destroy before the context.
  FiberGpu(const GlInfo& gl, std::vector<std::string> defines = {});
  ~FiberGpu();
  FiberGpu(const FiberGpu&) = delete;
  FiberGpu& operator=(const FiberGpu&) = delete;

  // Uploads the procedural input and computes the knot frames on the GPU.
  void setModel(const YarnBuffers& yarn, std::span<const FiberCoord> fiberTable);
  // Changes with every setModel, unique across FiberGpu objects: what a
  // renderer keys view-independent results (the yarn shadow map) on.
  uint64_t modelVersion() const { return modelVersion_; }
  void setParams(const YarnParams& params, const ViewParams& view);
  // Segments to generate, in order; empty = every segment.
  void setSegmentList(std::span<const uint32_t> segments);
  size_t segmentListSize() const { return listCount_; }
  size_t inputBytes() const { return inputBytes_; }

  std::vector<FrameNormal> readFrames() const;

  // Compute path. generate() only dispatches; the read-backs synchronize.
  void generateCompute();
  std::vector<SegmentDecision> readDecisions() const;
  std::vector<FiberVertex> readComputeVertices() const;
  // The line-strip index buffer the indirect draw reads (DrawElementsCommand::count entries).
  std::vector<uint32_t> readComputeIndices() const;
  DrawElementsCommand readDrawCommand() const;

  // Tessellation path, captured with transform feedback and rasterizer
  // discard: two FiberVertex per isoline segment, in the driver's order.
  // Returns the number of line segments written.
  size_t captureTessellation();
  std::vector<FiberVertex> readTessellationLines() const;
  // Upper bound of line segments a tessellation capture can write (buffer size).
  size_t tessellationCapacity() const;
  // Isolines per patch for the current params (GL_MAX_TESS_GEN_LEVEL, or less
  // on llvmpipe, see kLlvmpipeMaxPatchVertices in fiber_gpu.cpp).
  uint32_t linesPerPatch() const;

  // For a renderer: the vertex (and tessellation) stages of `path`'s draw
  // program; the buffers and uniforms they read, bound; the draw of the fibers
  // with `program` (built from drawStages(path) + the renderer's stages).
  // Compute: generateCompute() first (prepareDraw does it).
  FiberDrawStages drawStages(FiberPath path) const;
  void prepareDraw(FiberPath path);
  void draw(FiberPath path, GLuint program);
  // The compute path's draw with another index buffer of the same layout
  // (indexCapacity() indices, e.g. a copy with some restarts added).
  void drawComputeIndices(GLuint program, GLuint indexBuffer);
  size_t indexCapacity() const { return indexCapacity_; }
  // An arbitrary vertex stream in canonical strip order (e.g. the CPU's) in
  // place of the compute path's buffers: the same draw as FiberPath::Compute.
  void drawVertices(std::span<const FiberVertex> vertices, std::span<const SegmentDecision> decisions, GLuint program);
  const YarnParams& params() const { return params_; }
  // The view of the last setParams (the renderer's per-view culling choice).
  const ViewParams& view() const { return view_; }
  // For the yarn shadow map's depth pass (FiberRenderer, common/shadow_map.h):
  // the model's yarn segments, its control points' bounds, and the yarn
  // buffers bound at their slots.
  size_t segmentCount() const { return segmentCount_; }
  glm::vec3 boundsMin() const { return boundsMin_; }
  glm::vec3 boundsMax() const { return boundsMax_; }
  void bindYarn() const { bindCommon(); }

 private:
  void decideAndScan();  // passes 1-2: decisions, offsets and totals of the listed segments
  void ensureComputeCapacity();
  // A flattened dispatch of `items` invocations in groups of `groupSize` (x, then y rows).
  void dispatchFlat(GLuint program, size_t items, size_t groupSize, const char* what);
  void bindCommon() const;
  void drawCompute(GLuint program, GLuint indexBuffer = 0);
  void drawTessellation(GLuint program);

  std::vector<std::string> defines_;
  int maxTessGenLevel_ = 64;
  int maxPatchVertices_ = 0;  // 0: no limit
  int maxGroupsX_ = 65535;  // flat dispatches fill x rows of at most this many groups, then y
  int maxGroupsY_ = 65535;
  int maxGroupsZ_ = 65535;
  Program framesProgram_, decideProgram_, ownersProgram_, samplesProgram_, scanProgram_, generateProgram_;
  Program tessCaptureProgram_;
  VertexArray vao_;
  Framebuffer captureFbo_;  // attachment-less: surfaceless contexts have no default framebuffer
  Buffer yarnUbo_, viewUbo_;
  Buffer points_, curves_, segments_, frames_, table_, list_;
  Buffer frameCarry_;  // per curve: the normal carried between frame chunks, the holonomy
  Buffer decisions_, offsets_, samples_, stripOwners_, sampleOwners_, vertices_, indices_, draw_, xfb_;
  glm::vec3 boundsMin_{0.0f}, boundsMax_{0.0f};
  size_t curveCount_ = 0, segmentCount_ = 0, knotCount_ = 0, listCount_ = 0, inputBytes_ = 0;
  uint64_t modelVersion_ = 0;
  size_t pendingStrips_ = 0, pendingSamples_ = 0, sampleCapacity_ = 0, stripCapacity_ = 0, vertexCapacity_ = 0, indexCapacity_ = 0, xfbCapacityLines_ = 0, xfbLines_ = 0;
  YarnParams params_{};
  ViewParams view_{};
};

}  // namespace ft
