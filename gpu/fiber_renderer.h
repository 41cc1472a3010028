// fiber_renderer.h — draws the fibers a FiberGpu generates: it owns the
// multisample targets, the strip geometry and fragment stages (capsule
// impostors, fiber_strip.geom/frag.glsl) and the shading inputs
// (scene/shading_inputs.h) bound at the "shading inputs" slots of
// common/constants.h. FiberGpu owns generation; this owns the frame.
#pragma once
#include <epoxy/gl.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "common/fiber_vertex.h"
#include "common/occlusion_cull.h"
#include "common/pcss.h"
#include "common/srbf.h"
#include "gpu/fiber_gpu.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"
#include "image/image.h"
#include "scene/shading_inputs.h"

namespace ft {

struct RgbaImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;  // RGBA8, row 0 at the top
};

// The unshaded preview: one colour, a headlight-style Lambert term.
struct RenderStyle {
  glm::vec3 baseColor{0.85f, 0.78f, 0.62f};
  glm::vec3 background{0.08f, 0.08f, 0.1f};
  glm::vec3 lightDir{0.3f, 0.8f, 0.5f};
};

// Where a shaded frame's time goes (draw(..., &timings)): each phase ends with
// glFinish and is timed on the CPU's steady clock (llvmpipe's timer queries
// are CPU timestamps anyway, docs/llvmpipe-notes.md).
struct FrameTimings {
  double shadowMapMs = 0;   // the yarn shadow map's depth pass and copy (0 when off, or kept from an earlier frame)
  double generateMs = 0;    // fiber generation (compute path; the tessellation path generates while drawing)
  double depthMs = 0;       // the depth pre-pass (capsule coverage and depth only)
  double shadeMs = 0;       // the shaded pass over the visible capsules (deferred: the visibility pass)
  double deferredMs = 0;    // deferred shading: the compaction and the shading of the list into the target
  // CPU time of the process (all threads, processCpuMs) in the occluder pass,
  // the shaded (visibility) pass and the whole frame: the work, less
  // sensitive than wall time to other jobs on a shared machine.
  double depthCpuMs = 0, shadeCpuMs = 0, totalCpuMs = 0;
  // The visibility (or shaded) pass's pipeline statistics: triangles out of
  // the geometry stage (two per line, one for a short, thin line) and
  // fragment-shader invocations (llvmpipe counts one per
  // pixel of every 4 x 4 block a primitive touches, covered or not: the
  // work its fragment stage does). 0 where the driver has no such query.
  uint64_t shadePrimitives = 0, shadeFragmentInvocations = 0;
  // Two-pass culling (FiberRenderer::setTwoPassCull): whether this frame
  // was, and the triangles of its first draw (included in shadePrimitives).
  bool twoPass = false;
  uint64_t firstDrawPrimitives = 0;
  double firstDrawMs = 0, firstDrawCpuMs = 0;  // the first draw's share of shadeMs and shadeCpuMs
  double totalMs() const { return shadowMapMs + generateMs + depthMs + shadeMs + deferredMs; }
};

class FiberRenderer {
 public:
  // `defines` are injected into every shader (fault injection); they must be
  // those the FiberGpu it draws was built with.
  explicit FiberRenderer(const GlInfo& gl, std::vector<std::string> defines = {});
  ~FiberRenderer();
  FiberRenderer(const FiberRenderer&) = delete;
  FiberRenderer& operator=(const FiberRenderer&) = delete;

  // Shaded frames (000 §4.3, common/fiber_shading.h): linear HDR radiance,
  // alpha = the fraction of the pixel the fibers cover (4× multisampling,
  // capsules tested per sample). Checks the inputs (checkShadingInputs).
  void setShading(const ShadingInputs& inputs);
  const ShadingInputs& shading() const { return inputs_; }
  // One shaded frame into the kept float target, without the read-back: what
  // a frame costs (the benches time this); read() then returns it.
  // With `timings`, each phase is finished and timed (slower: no overlap).
  void draw(FiberGpu& fibers, FiberPath path, int width, int height, FrameTimings* timings = nullptr);
  // Exact occlusion culling of shaded frames (common/occlusion_cull.h): an
  // occluder pass and its depth pyramid let hidden lines and fragments skip
  // the shading. The frame is the same either way, so whether to cull is a
  // matter of time only, chosen per view by default (Auto,
  // docs/shaded-frame.md): off when the model's bounds lie wholly inside the
  // view frustum (the whole glove: thin yarns, occluders over 16 % of the
  // image, the pass costs more than it saves), on otherwise (the close-up:
  // 63 %, it halves the frame).
  enum class OcclusionCull { Off, On, Auto };
  void setOcclusionCull(bool on) { occlusionCull_ = on ? OcclusionCull::On : OcclusionCull::Off; }
  void setOcclusionCull(OcclusionCull mode) { occlusionCull_ = mode; }
  OcclusionCull occlusionCull() const { return occlusionCull_; }
  // Whether a frame of `fibers`' current view culls (the Auto choice resolved).
  bool cullsView(const FiberGpu& fibers) const;
  // The share of the last culled frame's pixels that an occluder covers at
  // every sample (pyramid level 0 below the far plane); 0 before one.
  double occludedFraction() const;
  // Window depths per sample (width × height × 4, rows bottom-up, a pixel's
  // samples together) of the last culled frame's occluder pass, and of the
  // last shaded frame's depth buffer: what the visibility pass drew. The
  // culling is exact only if no occluder sample is nearer than the frame's
  // depth there (validation/occlusion_cull_cases.cpp compares them). Empty
  // before such a frame.
  std::vector<float> readOccluderSampleDepths() const;
  std::vector<float> readFrameSampleDepths() const;
  // Level 0 of the last culled frame's depth pyramid (width × height, rows
  // bottom-up): the occluders', or of a two-pass frame the first draw's
  // max depth per pixel. Empty before such a frame.
  std::vector<float> readPyramidLevel0() const;
  // The last deferred frame's line key + 1 (0: no fiber) per sample, laid out
  // as readFrameSampleDepths, and the marks its compaction set (bit k: a
  // sample's line had key k): two-pass culling's next first draw takes the
  // marked lines, so every key of the first must be marked. Empty before
  // such a frame.
  std::vector<uint32_t> readFrameSampleLines() const;
  std::vector<uint32_t> readVisibleLines() const;
  // Two-pass culling (common/occlusion_cull.h ftLineKey; off by default, so
  // that a frame depends on its inputs only: `render` and the bench turn it
  // on; for deferred frames with occlusion culling not Off): a frame after another of
  // the same model and size first draws the lines that won a sample of that
  // frame, builds the pyramid from the depth they leave, and then draws the
  // others against it, instead of the occluder pass. The depth buffer is the
  // same as without; the colour too, but where two lines tie at a sample's
  // depth (the first drawn wins; docs/shaded-frame.md "Two-pass culling").
  void setTwoPassCull(bool on) { twoPass_ = on; }
  bool twoPassCull() const { return twoPass_; }
  // Forgets what the last frame saw: the next frame draws as a first frame.
  void forgetVisibility() { visibleKept_ = false; }
  // Whether the next draw() of `fibers` at width × height is two-pass.
  bool drawsTwoPass(const FiberGpu& fibers, int width, int height) const;
  // Deferred shading (on by default; docs/shaded-frame.md): a visibility pass
  // writes each fragment's hit instead of shading it, a compute pass lists
  // each pixel's distinct hits, and only those are shaded (the forward pass's
  // shadeFiber) and written to their samples. Off: the forward pass, which
  // shades every fragment that reaches the fragment stage. The frame is the
  // same either way (shading/deferred/*).
  void setDeferred(bool on) { deferred_ = on; }
  bool deferred() const { return deferred_; }
  // Entries (distinct hits) the last deferred frame shaded; 0 before one.
  size_t deferredEntries() const { return deferredEntries_; }
  ImageRgbaF read() const;
  ImageRgbaF render(FiberGpu& fibers, FiberPath path, int width, int height);
  // The shaded target's multisample positions in the pixel ([0, 1]², y down
  // as the read-back image), as GL reports them (after a draw()).
  std::vector<glm::vec2> samplePositions() const;

  // The yarn shadow map (000 §4.1, common/shadow_map.h): every yarn segment
  // of `fibers`' model as FT_SHADOW_MAP_SUBSEGMENTS capsules of radius W
  // (shading().density.supportRadius), the far side stored, one N × N
  // DEPTH32F layer per light of shading(), orthographic, fitted to the
  // model's bounds. draw() calls it when FT_APPEARANCE_SHADOW_MAP is set; the
  // harness and the bench call it directly. Then shadowMapParams() and
  // readShadowMap() (float[lights][N][N], rows bottom-up) describe the map.
  // The map does not depend on the camera: draw() redraws it only when the
  // shading inputs (lights, W, N) or `fibers`' model changed since it was
  // drawn (FiberGpu::modelVersion), so a camera move keeps it.
  void drawShadowMap(FiberGpu& fibers);
  const ShadowMapParams& shadowMapParams() const { return shadowParams_; }
  std::vector<float> readShadowMap() const;

  // Soft yarn shadows by PCSS (001 §4.5 eq. 17, common/pcss.h,
  // docs/soft-shadows.md). The SRBF lobes' maps: one yarn-level depth pass
  // (the shadow map's tubes and box, orthographic) from each lobe axis μ_j
  // whose lobe holds at least FT_PCSS_LOBE_MIN_SHARE of the environment's
  // energy, `size`² texels per layer; the other lobes get no map (T̃_j = 1).
  // draw() calls it when shading().lobeShadowEnvironment is set, and redraws
  // only when the inputs or the model changed (as the light maps); the
  // harness calls it directly. pcssParams() then describes the lobe layers
  // and readLobeShadowMaps() returns them (float[layers][N][N]).
  void drawLobeShadowMaps(FiberGpu& fibers, const SrbfEnvironment& env, uint32_t size);
  const PcssParams& pcssParams() const { return pcssParams_; }
  std::vector<float> readLobeShadowMaps() const;
  // The GPU's PCSS T̃ at points (pcss_lookup.comp.glsl, the frame's functions):
  // request (p, i) with i a light of the shadow map (lobes false; tan α from
  // shading().lightTanAlpha) or a lobe j of the lobe maps (lobes true).
  std::vector<float> pcssLookup(std::span<const glm::vec4> requests, bool lobes);

  // Unshaded RGBA8 previews (harness thumbnails, `render --preview`): the
  // path's own fibers, or an arbitrary vertex stream in canonical strip order
  // (e.g. the CPU reference's) drawn as the compute path draws its buffers.
  RgbaImage preview(FiberGpu& fibers, FiberPath path, int width, int height, const RenderStyle& style = {});
  RgbaImage previewVertices(FiberGpu& fibers, std::span<const FiberVertex> vertices,
                            std::span<const SegmentDecision> decisions, int width, int height,
                            const RenderStyle& style = {});

 private:
  // computeIndices: on the compute path, the index buffer to draw instead of the fibers' own.
  void drawCounted(FiberGpu& fibers, FiberPath path, GLuint prog, FrameTimings* timings, GLuint computeIndices = 0);
  // Built on first use per path and pass (common/occlusion_cull.h).
  // ShadedDualScattering: the shaded pass with FT_FRAME_DUAL_SCATTERING, so
  // that frames without it do not pay for it (llvmpipe runs every branch).
  // ShadedEnvironment(+DualScattering): with FT_FRAME_ENVIRONMENT (SRBF
  // environment lighting, 001 §4.5), likewise only when on.
  enum class StripPass {
    Shaded,
    PlainOccluders,
    CoreOccluders,
    ShadedDualScattering,
    ShadedEnvironment,
    ShadedDualScatteringEnvironment,
    Visibility  // deferred shading's visibility pass (FT_VISIBILITY_PASS)
  };
  // pcss: the shaded passes with FT_FRAME_PCSS (soft shadows, the lobe maps).
  // occlusionTest: the shaded passes with FT_OCCLUSION_TEST (the geometry and
  // fragment stages' tests against the occluders' depth pyramid), for the
  // frames that draw occluders; without, the tests are compiled out, since
  // llvmpipe runs them anyway (7 % of the whole glove's visibility pass).
  GLuint program(const FiberGpu& fibers, FiberPath path, StripPass pass = StripPass::Shaded, bool pcss = false,
                 bool occlusionTest = false);
  void uploadPcss();
  void bindShading() const;
  // The occluder pass and its depth pyramid into occlusionTexels_; binds the
  // pyramid for the shaded pass.
  void drawOccluders(FiberGpu& fibers, FiberPath path, int width, int height);
  void bindOcclusion(bool enabled);
  // The pyramid's layout and texels for a width × height target; then the
  // pyramid of a 4× multisampled depth texture, bound for the shaded pass.
  void ensurePyramid(int width, int height);
  void buildPyramid(GLuint multisampleDepthTexture);

  std::vector<std::string> defines_;
  Program programs_[2][7][2][2];  // [path][StripPass][FT_FRAME_PCSS][FT_OCCLUSION_TEST]
  // Deferred shading: the visibility pass into the hit records, then these.
  void drawDeferred(FiberGpu& fibers, FiberPath path, bool ds, bool env, bool pcss, bool cull, bool twoPass,
                    FrameTimings* timings);
  // Two-pass culling: the lines seen by the last frame and by this one
  // (FT_SSBO_VISIBLE_LINES bit sets of 2^visibleBits_ marks, swapped after
  // each deferred frame), and what the kept one belongs to.
  bool twoPass_ = false, visibleKept_ = false;
  Buffer visibleLines_[2];
  int visibleNow_ = 0;
  uint64_t visibleModel_ = 0;
  uint32_t visibleBits_ = 0;
  GLuint twoPassIndices(FiberGpu& fibers, FiberPath path, uint32_t which, uint32_t bits);
  Program twoPassLinesProgram_;
  Buffer twoPassIndices_;
  size_t twoPassIndexCapacity_ = 0;
  bool deferred_ = true;
  size_t deferredEntries_ = 0;
  Program compactTilesProgram_, compactProgram_;
  Program shadeProgram_[2][2][2];  // [FT_FRAME_DUAL_SCATTERING][FT_FRAME_ENVIRONMENT][FT_FRAME_PCSS]
  std::unique_ptr<struct DeferredTarget> deferredTarget_;
  // Occlusion culling: the occluder depth (4× multisampled texture), the pyramid.
  OcclusionCull occlusionCull_ = OcclusionCull::Auto;
  Program pyramidProgram_;
  mutable Program sampleDepthProgram_;  // sample_depth_read.comp.glsl (harness read-back)
  mutable Program sampleLineProgram_;   // the same for the line keys (FT_SAMPLE_READ_UINT)
  std::vector<float> readSampleDepths(GLuint multisampleDepthTexture, int width, int height) const;
  Texture occluderDepth_;
  Framebuffer occluderFbo_;
  int occluderWidth_ = 0, occluderHeight_ = 0, pyramidWidth_ = 0, pyramidHeight_ = 0;
  Buffer occlusionUbo_, occlusionTexels_;
  OcclusionPyramid pyramid_{};
  Buffer shadingUbo_, ambientTable_, lobeNormTable_, selfShadowUbo_, selfShadowTexels_;
  Buffer coreTextureUbo_, coreTex0_, coreTex1_;  // 000 §3.2 core-fiber texture
  Buffer aoUbo_, aoTexels_;  // ambient occlusion (000 §4.2)
  // Dual scattering (001 §4.1, §4.3): the DS table, the ξ layout, the four ξ textures.
  Buffer dsTable_, xiUbo_, xiM_, xiN_, psiM_, psiN_;
  // SRBF environment lighting (001 §4.5): the fit + table dimensions, the I_M table.
  Buffer srbfUbo_, srbfTable_;
  // Flyaways (001 §4.4): the third pass's program, block and texels (docs/flyaways.md).
  void drawFlyaways(FiberGpu& fibers);
  Program flyawayProgram_;
  VertexArray flyawayVao_;
  Buffer flyawayUbo_, flyawayTexels_;
  // Yarn shadow map: depth pass program, target, and the depth copied to an SSBO for the frame.
  Program shadowProgram_;
  Texture shadowDepth_;
  Framebuffer shadowFbo_;
  VertexArray shadowVao_;
  Buffer shadowUbo_, shadowTexels_;
  ShadowMapParams shadowParams_{};
  // What the stored map was drawn from: FiberGpu::modelVersion and the
  // setShading count; 0: none.
  uint64_t shadowModel_ = 0, shadowInputs_ = 0, inputsVersion_ = 0;
  bool faultShadowMapStale_ = false;
  bool faultFlyawayNoDepthTest_ = false;  // planted: the flyaway pass without the depth test
  bool faultTwoPassStalePyramid_ = false;  // planted: the second draw tested against the last frame's pyramid
  bool faultTwoPassDepthCleared_ = false;  // planted: the depth cleared between the two draws
  bool faultTwoPassPyramidLayout_ = false;  // planted: the pyramid built before its layout is bound
  uint32_t shadowSize_ = 0, shadowLayers_ = 0;
  // Soft shadows (common/pcss.h): the lobe maps' depth array and its SSBO
  // copy, PcssParams, the GPU lookup; what the lobe maps were drawn from.
  Texture lobeDepth_;
  Buffer pcssUbo_, lobeTexels_;
  PcssParams pcssParams_{};
  Program pcssLookupProgram_;
  uint64_t lobeModel_ = 0, lobeInputs_ = 0;
  uint32_t lobeSize_ = 0, lobeLayers_ = 0;
  int maxGroupsY_ = 65535;
  ShadingInputs inputs_;
  std::unique_ptr<struct MultisampleTarget> shadedTarget_;  // kept between shaded frames
};

}  // namespace ft
