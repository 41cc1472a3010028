#include "gpu/fiber_renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "common/constants.h"
#include "common/flyaway.h"
#include "gpu/compute_dispatch.h"
#include "gpu/gpu_timer.h"
#include "gpu/shader_library.h"
#include "scene/camera.h"

namespace ft {
namespace {

Buffer makeBuffer(size_t bytes, const void* data) {
  Buffer b = Buffer::createMutable(std::max<size_t>(bytes, 16));  // never empty: binding one is an error
  if (data && bytes) b.update(data, bytes);
  return b;
}

}  // namespace

// A 4× multisampled colour + depth target and its single-sampled resolve.
struct MultisampleTarget {
  Framebuffer ms = Framebuffer::create(), resolve = Framebuffer::create();
  Renderbuffer resolveColor = Renderbuffer::create();
  Texture color;  // a texture, which deferred shading's kernel writes (FT_IMAGE_SHADED)
  Texture depth;  // a texture, which the two-pass culling's pyramid reads
  GLenum colorFormat;
  int width, height;

  MultisampleTarget(int w, int h, GLenum format) : colorFormat(format), width(w), height(h) {
    GLuint tex[2] = {0, 0};
    glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 2, tex);
    color = Texture(tex[0]);
    depth = Texture(tex[1]);
    glTextureStorage2DMultisample(tex[0], 4, colorFormat, w, h, GL_TRUE);
    glTextureStorage2DMultisample(tex[1], 4, GL_DEPTH_COMPONENT24, w, h, GL_TRUE);
    glNamedRenderbufferStorage(resolveColor.id(), colorFormat, w, h);
    glNamedFramebufferTexture(ms.id(), GL_COLOR_ATTACHMENT0, tex[0], 0);
    glNamedFramebufferTexture(ms.id(), GL_DEPTH_ATTACHMENT, tex[1], 0);
    glNamedFramebufferRenderbuffer(resolve.id(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolveColor.id());
  }
  void begin(glm::vec4 clear) const {
    glBindFramebuffer(GL_FRAMEBUFFER, ms.id());
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glClearColor(clear.x, clear.y, clear.z, clear.w);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
  void finish() const {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_DEPTH_TEST);
  }
  // Resolves and reads the colour back with row 0 at the top (GL's is the bottom).
  template <class T>
  std::vector<T> read(GLenum type) const {
    glBlitNamedFramebuffer(ms.id(), resolve.id(), 0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
    const size_t row = static_cast<size_t>(width) * 4;
    std::vector<T> rows(row * height), out(row * height);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve.id());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, type, rows.data());
    for (int y = 0; y < height; ++y)
      std::copy_n(rows.data() + static_cast<size_t>(height - 1 - y) * row, row, out.data() + static_cast<size_t>(y) * row);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    return out;
  }
};

// The compaction's tiles over a w × h target (fiber_compact_tiles.comp.glsl).
static size_t deferredTileCount(int w, int h) {
  return size_t((w + FT_DEFERRED_TILE - 1) / FT_DEFERRED_TILE) * ((h + FT_DEFERRED_TILE - 1) / FT_DEFERRED_TILE);
}

// Deferred shading's visibility target: FT_VISIBILITY_TARGETS 4× multisampled
// RGBA32F textures (the hit records, fiber_strip.frag.glsl ftPackHit) with the
// shaded target's depth, and the list of distinct hits (FT_SSBO_DEFERRED_LIST).
struct DeferredTarget {
  Framebuffer fbo = Framebuffer::create();
  Texture records[FT_VISIBILITY_TARGETS];
  Texture lines;  // R32UI: the hit's line key + 1 (two-pass culling), after the records
  Buffer list;
  int width, height;

  DeferredTarget(int w, int h, GLuint depth) : width(w), height(h) {
    GLenum buffers[FT_VISIBILITY_TARGETS + 1];
    for (int k = 0; k <= FT_VISIBILITY_TARGETS; ++k) {
      GLuint tex = 0;
      glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &tex);
      (k < FT_VISIBILITY_TARGETS ? records[k] : lines) = Texture(tex);
      glTextureStorage2DMultisample(tex, FT_DEFERRED_SAMPLES, k < FT_VISIBILITY_TARGETS ? GL_RGBA32F : GL_R32UI, w, h,
                                    GL_TRUE);
      glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0 + k, tex, 0);
      buffers[k] = GL_COLOR_ATTACHMENT0 + k;
    }
    glNamedFramebufferDrawBuffers(fbo.id(), FT_VISIBILITY_TARGETS + 1, buffers);
    glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth, 0);
    // A header, at most one entry per sample (16 bytes each), then the tiles (16 bytes each).
    list = makeBuffer(16 + (size_t(w) * h * FT_DEFERRED_SAMPLES + deferredTileCount(w, h)) * 16, nullptr);
  }
};

FiberRenderer::FiberRenderer(const GlInfo& gl, std::vector<std::string> defines)
    : defines_(std::move(defines)),
      // Planted fault (validation/faults.def) of the renderer's own C++: the map kept across setModel.
      faultShadowMapStale_(std::find(defines_.begin(), defines_.end(), "FT_FAULT_SHADOW_MAP_STALE") != defines_.end()),
      faultFlyawayNoDepthTest_(std::find(defines_.begin(), defines_.end(), "FT_FAULT_FRAME_FLYAWAY_NO_DEPTH_TEST") !=
                               defines_.end()),
      faultTwoPassStalePyramid_(std::find(defines_.begin(), defines_.end(), "FT_FAULT_TWO_PASS_STALE_PYRAMID") !=
                                defines_.end()),
      faultTwoPassDepthCleared_(std::find(defines_.begin(), defines_.end(), "FT_FAULT_TWO_PASS_DEPTH_CLEARED") !=
                                defines_.end()),
      faultTwoPassPyramidLayout_(std::find(defines_.begin(), defines_.end(), "FT_FAULT_TWO_PASS_PYRAMID_LAYOUT") !=
                                 defines_.end()),
      maxGroupsY_(gl.maxComputeWorkGroupCount[1]) {}

FiberRenderer::~FiberRenderer() = default;

GLuint FiberRenderer::program(const FiberGpu& fibers, FiberPath path, StripPass pass, bool pcss, bool occlusionTest) {
  const bool shadedPass = pass != StripPass::PlainOccluders && pass != StripPass::CoreOccluders;
  Program& p = programs_[path == FiberPath::Compute ? 0 : 1][int(pass)][pcss && shadedPass ? 1 : 0]
                        [occlusionTest && shadedPass ? 1 : 0];
  if (!p) {
    FiberDrawStages stages = fibers.drawStages(path);
    stages.files.push_back("shaders/fiber_strip.geom.glsl");
    stages.files.push_back("shaders/fiber_strip.frag.glsl");
    std::vector<std::string> defines = defines_;
    defines.insert(defines.end(), stages.defines.begin(), stages.defines.end());
    const bool ds = pass == StripPass::ShadedDualScattering || pass == StripPass::ShadedDualScatteringEnvironment;
    const bool env = pass == StripPass::ShadedEnvironment || pass == StripPass::ShadedDualScatteringEnvironment;
    if (ds) defines.push_back("FT_FRAME_DUAL_SCATTERING");
    if (env) defines.push_back("FT_FRAME_ENVIRONMENT");
    if (pass == StripPass::PlainOccluders || pass == StripPass::CoreOccluders) defines.push_back("FT_OCCLUDER_PASS");
    if (pass == StripPass::PlainOccluders) defines.push_back("FT_OCCLUDER_PLAIN");
    if (pass == StripPass::Visibility) defines.push_back("FT_VISIBILITY_PASS");
    if (pcss && shadedPass) defines.push_back("FT_FRAME_PCSS");  // soft shadows: compiled out otherwise (llvmpipe runs all code)
    if (occlusionTest && shadedPass) defines.push_back("FT_OCCLUSION_TEST");
    p = Program(buildProgram(stages.files, defines));
  }
  return p.id();
}

void FiberRenderer::setShading(const ShadingInputs& inputs) {
  checkShadingInputs(inputs);
  inputs_ = inputs;
  ++inputsVersion_;
  shadingUbo_ = makeBuffer(sizeof(ShadingParams), &inputs.params);
  std::vector<glm::vec4> texels;
  for (const glm::vec3& a : inputs.ambientTable) texels.emplace_back(a, 0.0f);
  ambientTable_ = makeBuffer(texels.size() * sizeof(glm::vec4), texels.data());
  lobeNormTable_ = makeBuffer(inputs.lobeNormTable.size() * sizeof(glm::vec2), inputs.lobeNormTable.data());
  // The self-shadow block as the bake kernels declare it (self_shadow_*.comp.glsl).
  struct SelfShadowBlock {
    SelfShadowParams shadow;
    YarnDensityParams density;
  } block{inputs.selfShadow, inputs.density};
  selfShadowUbo_ = makeBuffer(sizeof(block), &block);
  selfShadowTexels_ = makeBuffer(inputs.selfShadowTexels.size() * sizeof(float), inputs.selfShadowTexels.data());
  // The core-fiber texture (000 §3.2) at the core-texture slots its bake shares.
  coreTextureUbo_ = makeBuffer(sizeof(CoreTextureParams), &inputs.coreTexture);
  coreTex0_ = makeBuffer(inputs.coreTex0.size() * sizeof(glm::vec4), inputs.coreTex0.data());
  coreTex1_ = makeBuffer(inputs.coreTex1.size() * sizeof(glm::vec4), inputs.coreTex1.data());
  // Ambient occlusion (000 §4.2): its params (with the cubic) and texture.
  aoUbo_ = makeBuffer(sizeof(AmbientOcclusionParams), &inputs.aoParams);
  aoTexels_ = makeBuffer(inputs.aoTexels.size() * sizeof(float), inputs.aoTexels.data());
  // Dual scattering (001 §4.1, §4.3): empty buffers (16 bytes) when off.
  dsTable_ = makeBuffer(inputs.dsTable.size() * sizeof(glm::vec4), inputs.dsTable.data());
  xiUbo_ = makeBuffer(sizeof(DsCorrectionLayout), &inputs.dsCorrection);
  // ξ and Ψ log-encoded: the lookup interpolates logarithms (common/ds_correction.h).
  const auto encoded = [](const std::vector<glm::vec4>& t) {
    std::vector<glm::vec4> e(t.size());
    for (size_t k = 0; k < t.size(); ++k) e[k] = glm::vec4(ftXiEncode(glm::vec3(t[k])), 0.0f);
    return e;
  };
  const std::vector<glm::vec4> xiM = encoded(inputs.xiM), xiN = encoded(inputs.xiN), psiM = encoded(inputs.psiM),
                               psiN = encoded(inputs.psiN);
  xiM_ = makeBuffer(xiM.size() * sizeof(glm::vec4), xiM.data());
  xiN_ = makeBuffer(xiN.size() * sizeof(glm::vec4), xiN.data());
  psiM_ = makeBuffer(psiM.size() * sizeof(glm::vec4), psiM.data());
  psiN_ = makeBuffer(psiN.size() * sizeof(glm::vec4), psiN.data());
  // SRBF environment lighting (001 §4.5): the fit and the table's dimensions
  // in one block (FT_UBO_FRAME_SRBF), the table as vec4 texels.
  struct SrbfFrameBlock {
    SrbfEnvironment environment;
    glm::ivec4 dims;
  } srbf{inputs.environment, inputs.srbfTableDims};
  static_assert(sizeof(SrbfFrameBlock) == 544, "std140: SrbfEnvironment (528 B) then an ivec4");
  srbfUbo_ = makeBuffer(sizeof(srbf), &srbf);
  std::vector<glm::vec4> srbfTexels;
  srbfTexels.reserve(inputs.srbfTable.size());
  for (const glm::vec3& v : inputs.srbfTable) srbfTexels.emplace_back(v, 0.0f);
  srbfTable_ = makeBuffer(srbfTexels.size() * sizeof(glm::vec4), srbfTexels.data());
  // Flyaways (001 §4.4): the block and the three layers; 16 bytes when off.
  flyawayUbo_ = makeBuffer(sizeof(FlyawayParams), &inputs.flyaway);
  flyawayTexels_ = makeBuffer(inputs.flyawayTexels.size() * sizeof(uint32_t), inputs.flyawayTexels.data());
  // Soft shadows (common/pcss.h): the lights' cones now, the lobe maps when drawn.
  pcssParams_.lightTanAlpha = inputs.lightTanAlpha;
  if (!inputs.lobeShadowEnvironment) lobeLayers_ = 0;
  uploadPcss();
}

void FiberRenderer::uploadPcss() {
  if (!pcssUbo_) pcssUbo_ = makeBuffer(sizeof(PcssParams), nullptr);
  if (lobeLayers_ == 0)  // no lobe maps: every lobe reads T̃ = 1
    for (int j = 0; j < FT_PCSS_MAX_LOBES; ++j) pcssParams_.lobeCone[j] = glm::vec4(0.0f, -1.0f, 0.0f, 0.0f);
  pcssUbo_.update(&pcssParams_, sizeof(PcssParams));
  if (!lobeTexels_) lobeTexels_ = makeBuffer(16, nullptr);
}

// ---- Flyaways: the third pass (001 §4.4, §5.2; flyaway_strip.*.glsl) ----

void FiberRenderer::drawFlyaways(FiberGpu& fibers) {
  if (!flyawayProgram_)
    flyawayProgram_ = Program(buildProgram({"shaders/flyaway_strip.vert.glsl", "shaders/flyaway_strip.frag.glsl"}, defines_));
  if (!flyawayVao_) flyawayVao_ = VertexArray::create();
  // Into the shaded target, after the regular fibers: depth-tested against
  // them (LESS, as they were drawn) and writing depth among the flyaways.
  glUseProgram(flyawayProgram_.id());
  fibers.bindYarn();
  bindShading();
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_FLYAWAY, flyawayUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FLYAWAY_FRAME, flyawayTexels_.id());
  glBindVertexArray(flyawayVao_.id());
  if (faultFlyawayNoDepthTest_) glDisable(GL_DEPTH_TEST);  // planted (faults.def): drawn over nearer fibers
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(fibers.segmentCount() * FT_FLYAWAY_PIECES * 6));
  glEnable(GL_DEPTH_TEST);
  glBindVertexArray(0);
}

// ---- Yarn shadow map (000 §4.1 last paragraph; common/shadow_map.h) ----

void FiberRenderer::drawShadowMap(FiberGpu& fibers) {
  const uint32_t n = inputs_.shadowMapSize;
  if (!shadingUbo_ || n == 0) throw std::logic_error("FiberRenderer: drawShadowMap() needs shading inputs with the shadow map");
  const int lights = static_cast<int>(std::min<uint32_t>(inputs_.params.flags.x, FT_SHADOW_MAP_MAX_LIGHTS));
  const uint32_t layers = static_cast<uint32_t>(std::max(lights, 1));
  const float w = inputs_.density.supportRadius;
  // A sphere around the control points' bounds, padded by the tube and by the
  // Catmull-Rom overshoot (≤ 1/8 of a segment's chord; the pad takes W more):
  // the square and the depth range then hold every tube for any light.
  const glm::vec3 lo = fibers.boundsMin(), hi = fibers.boundsMax();
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = 0.5f * glm::length(hi - lo) * 1.05f + 2.0f * w;
  ShadowMapParams m{};
  for (int i = 0; i < lights; ++i) {
    const glm::vec3 z = -glm::normalize(glm::vec3(inputs_.params.lightDirection[i]));  // propagation
    const glm::vec3 helper = std::abs(z.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 x = glm::normalize(glm::cross(helper, z));
    const glm::vec3 y = glm::cross(z, x);
    m.lightX[i] = glm::vec4(x, -glm::dot(x, centre));
    m.lightY[i] = glm::vec4(y, -glm::dot(y, centre));
    m.lightZ[i] = glm::vec4(z, -glm::dot(z, centre));
  }
  m.extent = glm::vec4(radius, radius, 2.0f * radius / float(n), float(n));
  m.tube = glm::vec4(w, inputs_.density.plyRadius, FT_SHADOW_MAP_BIAS_TEXELS, 0.0f);
  m.count = glm::uvec4(uint32_t(lights), n, inputs_.shadowMapFilter, 0u);
  shadowParams_ = m;
  shadowModel_ = fibers.modelVersion();
  shadowInputs_ = inputsVersion_;
  if (!shadowUbo_) shadowUbo_ = makeBuffer(sizeof(ShadowMapParams), nullptr);
  shadowUbo_.update(&m, sizeof(m));

  if (!shadowProgram_)
    shadowProgram_ = Program(buildProgram(
        {"shaders/shadow_map.vert.glsl", "shaders/shadow_map.frag.glsl"}, defines_));
  if (!shadowVao_) shadowVao_ = VertexArray::create();
  if (!shadowFbo_) shadowFbo_ = Framebuffer::create();
  if (shadowSize_ != n || shadowLayers_ != layers) {
    GLuint tex = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &tex);
    shadowDepth_ = Texture(tex);
    glTextureStorage3D(tex, 1, GL_DEPTH_COMPONENT32F, GLsizei(n), GLsizei(n), GLsizei(layers));
    shadowTexels_ = makeBuffer(size_t(n) * n * layers * sizeof(float), nullptr);
    shadowSize_ = n;
    shadowLayers_ = layers;
  }
  GLint oldViewport[4];
  glGetIntegerv(GL_VIEWPORT, oldViewport);
  glNamedFramebufferDrawBuffer(shadowFbo_.id(), GL_NONE);
  glNamedFramebufferReadBuffer(shadowFbo_.id(), GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, shadowFbo_.id());
  glViewport(0, 0, GLsizei(n), GLsizei(n));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glUseProgram(shadowProgram_.id());
  fibers.bindYarn();
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_SHADOW_MAP, shadowUbo_.id());
  glBindVertexArray(shadowVao_.id());
  const GLint lightLoc = glGetUniformLocation(shadowProgram_.id(), "lightIndex");
  for (uint32_t i = 0; i < layers; ++i) {
    glNamedFramebufferTextureLayer(shadowFbo_.id(), GL_DEPTH_ATTACHMENT, shadowDepth_.id(), 0, GLint(i));
    glClear(GL_DEPTH_BUFFER_BIT);
    if (int(i) >= lights) continue;
    glProgramUniform1i(shadowProgram_.id(), lightLoc, GLint(i));
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(fibers.segmentCount() * FT_SHADOW_MAP_SUBSEGMENTS * 6));
  }
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDisable(GL_DEPTH_TEST);
  glViewport(oldViewport[0], oldViewport[1], oldViewport[2], oldViewport[3]);
  // The frame reads the map as an SSBO (a copy on the GPU, no read-back).
  glBindBuffer(GL_PIXEL_PACK_BUFFER, shadowTexels_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(shadowDepth_.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                    GLsizei(size_t(n) * n * layers * sizeof(float)), nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
}

std::vector<float> FiberRenderer::readShadowMap() const {
  if (!shadowTexels_) throw std::logic_error("FiberRenderer: readShadowMap() before drawShadowMap()");
  std::vector<float> out(size_t(shadowSize_) * shadowSize_ * shadowLayers_);
  glGetNamedBufferSubData(shadowTexels_.id(), 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
  return out;
}

// ---- Soft shadows: the SRBF lobes' maps (001 §4.5, common/pcss.h) ----

void FiberRenderer::drawLobeShadowMaps(FiberGpu& fibers, const SrbfEnvironment& env, uint32_t size) {
  if (size < 16 || size > 8192) throw std::invalid_argument(fmt::format("FiberRenderer: lobe shadow map size {}", size));
  // Which lobes get a map: those with ≥ FT_PCSS_LOBE_MIN_SHARE of Σ_j lum(W_j)·∫G_j dω
  // (∫G dω = 2π(1 − e^{−2λ})/λ, eq. 14); the others' T̃ = 1 costs < 1 % each.
  float energy[FT_PCSS_MAX_LOBES], total = 0.0f;
  for (int j = 0; j < FT_PCSS_MAX_LOBES; ++j) {
    const glm::vec4 w = env.lobes[j].weight;
    const float lambda = std::max(env.lobes[j].axisLambda.w, 1e-6f);
    const float lum = std::max(0.2126f * w.x + 0.7152f * w.y + 0.0722f * w.z, 0.0f);
    energy[j] = lum * 2.0f * 3.14159265f * (1.0f - std::exp(-2.0f * lambda)) / lambda;
    if (!std::isfinite(energy[j]) || !std::isfinite(lambda))
      throw std::invalid_argument(fmt::format("FiberRenderer: SRBF lobe {} has energy {} (λ {})", j, energy[j], lambda));
    total += energy[j];
  }
  const float w = inputs_.density.supportRadius;
  if (!(w > 0.0f)) throw std::logic_error("FiberRenderer: drawLobeShadowMaps() needs shading inputs with the tube radius W");
  const glm::vec3 lo = fibers.boundsMin(), hi = fibers.boundsMax();
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = 0.5f * glm::length(hi - lo) * 1.05f + 2.0f * w;  // the light maps' box (drawShadowMap)
  PcssParams& pc = pcssParams_;
  std::vector<int> lobeOfLayer;
  for (int j = 0; j < FT_PCSS_MAX_LOBES; ++j) {
    const glm::vec3 mu = glm::vec3(env.lobes[j].axisLambda);
    const float share = total > 0.0f ? energy[j] / total : 0.0f;
    const float alpha = ftPcssLobeAngle(env.lobes[j].axisLambda.w);
    const bool mapped = share >= FT_PCSS_LOBE_MIN_SHARE && glm::length(mu) > 0.5f;
    pc.lobeCone[j] = glm::vec4(std::tan(alpha), mapped ? float(lobeOfLayer.size()) : -1.0f, alpha, share);
    pc.lobeX[j] = pc.lobeY[j] = pc.lobeZ[j] = glm::vec4(0.0f);
    if (!mapped) continue;
    lobeOfLayer.push_back(j);
    const glm::vec3 z = -glm::normalize(mu);  // the lobe's propagation
    const glm::vec3 helper = std::abs(z.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 x = glm::normalize(glm::cross(helper, z));
    const glm::vec3 y = glm::cross(z, x);
    pc.lobeX[j] = glm::vec4(x, -glm::dot(x, centre));
    pc.lobeY[j] = glm::vec4(y, -glm::dot(y, centre));
    pc.lobeZ[j] = glm::vec4(z, -glm::dot(z, centre));
  }
  const uint32_t layers = uint32_t(std::max<size_t>(lobeOfLayer.size(), 1));
  pc.extent = glm::vec4(radius, radius, 2.0f * radius / float(size), float(size));
  pc.count = glm::uvec4(uint32_t(lobeOfLayer.size()), size, 0u, 0u);
  lobeModel_ = fibers.modelVersion();
  lobeInputs_ = inputsVersion_;

  if (!shadowProgram_)
    shadowProgram_ = Program(buildProgram({"shaders/shadow_map.vert.glsl", "shaders/shadow_map.frag.glsl"}, defines_));
  if (!shadowVao_) shadowVao_ = VertexArray::create();
  if (!shadowFbo_) shadowFbo_ = Framebuffer::create();
  if (lobeSize_ != size || lobeLayers_ != layers || !lobeDepth_) {
    GLuint tex = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &tex);
    lobeDepth_ = Texture(tex);
    glTextureStorage3D(tex, 1, GL_DEPTH_COMPONENT32F, GLsizei(size), GLsizei(size), GLsizei(layers));
    lobeTexels_ = makeBuffer(size_t(size) * size * layers * sizeof(float), nullptr);
    lobeSize_ = size;
  }
  lobeLayers_ = layers;
  // The shadow map's depth pass, four lobes per ShadowMapParams (its UBO's
  // light count), drawn into the lobe layers.
  Buffer groupUbo = makeBuffer(sizeof(ShadowMapParams), nullptr);
  GLint oldViewport[4];
  glGetIntegerv(GL_VIEWPORT, oldViewport);
  glNamedFramebufferDrawBuffer(shadowFbo_.id(), GL_NONE);
  glNamedFramebufferReadBuffer(shadowFbo_.id(), GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, shadowFbo_.id());
  glViewport(0, 0, GLsizei(size), GLsizei(size));
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glUseProgram(shadowProgram_.id());
  fibers.bindYarn();
  glBindVertexArray(shadowVao_.id());
  const GLint lightLoc = glGetUniformLocation(shadowProgram_.id(), "lightIndex");
  for (uint32_t layer = 0; layer < layers; ++layer) {
    glNamedFramebufferTextureLayer(shadowFbo_.id(), GL_DEPTH_ATTACHMENT, lobeDepth_.id(), 0, GLint(layer));
    glClear(GL_DEPTH_BUFFER_BIT);
    if (layer >= lobeOfLayer.size()) continue;
    const int j = lobeOfLayer[layer];
    ShadowMapParams m{};
    m.lightX[0] = pc.lobeX[j];
    m.lightY[0] = pc.lobeY[j];
    m.lightZ[0] = pc.lobeZ[j];
    m.extent = pc.extent;
    m.tube = glm::vec4(w, inputs_.density.plyRadius, FT_SHADOW_MAP_BIAS_TEXELS, 0.0f);
    m.count = glm::uvec4(1u, size, 0u, 0u);
    groupUbo.update(&m, sizeof(m));
    glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_SHADOW_MAP, groupUbo.id());
    glProgramUniform1i(shadowProgram_.id(), lightLoc, 0);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(fibers.segmentCount() * FT_SHADOW_MAP_SUBSEGMENTS * 6));
  }
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDisable(GL_DEPTH_TEST);
  glViewport(oldViewport[0], oldViewport[1], oldViewport[2], oldViewport[3]);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, lobeTexels_.id());
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(lobeDepth_.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(size_t(size) * size * layers * sizeof(float)),
                    nullptr);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  if (shadowUbo_) glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_SHADOW_MAP, shadowUbo_.id());
  uploadPcss();
}

std::vector<float> FiberRenderer::readLobeShadowMaps() const {
  if (lobeLayers_ == 0) throw std::logic_error("FiberRenderer: readLobeShadowMaps() before drawLobeShadowMaps()");
  std::vector<float> out(size_t(lobeSize_) * lobeSize_ * lobeLayers_);
  glGetNamedBufferSubData(lobeTexels_.id(), 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
  return out;
}

std::vector<float> FiberRenderer::pcssLookup(std::span<const glm::vec4> requests, bool lobes) {
  if (lobes ? lobeLayers_ == 0 : !shadowTexels_)
    throw std::logic_error("FiberRenderer: pcssLookup() before the maps it reads are drawn");
  if (!pcssLookupProgram_) pcssLookupProgram_ = Program(buildProgram({"shaders/pcss_lookup.comp.glsl"}, defines_));
  uploadPcss();
  const Buffer in = makeBuffer(requests.size() * sizeof(glm::vec4), requests.data());
  const Buffer out = makeBuffer(requests.size() * sizeof(float), nullptr);
  if (shadowUbo_) glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_SHADOW_MAP, shadowUbo_.id());
  if (shadowTexels_) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SHADOW_MAP, shadowTexels_.id());
  else glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SHADOW_MAP, lobeTexels_.id());  // unread
  if (!shadowUbo_) glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_SHADOW_MAP, pcssUbo_.id());  // unread (≥ its size)
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_PCSS, pcssUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PCSS_LOBE_MAPS, lobeTexels_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PCSS_REQUESTS, in.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PCSS_RESULTS, out.id());
  setUniform(pcssLookupProgram_.id(), "lobes", lobes ? 1u : 0u);
  dispatchFlat(pcssLookupProgram_.id(), requests.size(), FT_WG_PCSS, maxGroupsY_, "pcss_lookup");
  std::vector<float> result(requests.size());
  if (!result.empty()) glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(result.size() * sizeof(float)), result.data());
  return result;
}

void FiberRenderer::bindShading() const {
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_SHADING, shadingUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AMBIENT_TABLE, ambientTable_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_LOBE_NORM_TABLE, lobeNormTable_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_SELF_SHADOW, selfShadowUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SELF_SHADOW_TEXTURE, selfShadowTexels_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_CORE_TEXTURE, coreTextureUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_CORE_TEX0, coreTex0_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_CORE_TEX1, coreTex1_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_AMBIENT_OCCLUSION, aoUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AO_TEXTURE, aoTexels_.id());
  // Dual scattering: the ξ layout at the ξ group's UBO (bound here for each
  // shaded draw; the harness evaluator binds its own before each dispatch).
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FRAME_DS_TABLE, dsTable_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_XI, xiUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FRAME_XI_M, xiM_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FRAME_XI_N, xiN_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FRAME_PSI_M, psiM_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FRAME_PSI_N, psiN_.id());
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_FRAME_SRBF, srbfUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_FRAME_SRBF_TABLE, srbfTable_.id());
  if (shadowTexels_) {  // yarn shadow map (drawShadowMap)
    glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_SHADOW_MAP, shadowUbo_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SHADOW_MAP, shadowTexels_.id());
  }
  if (pcssUbo_) {  // soft shadows (common/pcss.h): the cones, the lobe maps (a 16-byte buffer without)
    glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_PCSS, pcssUbo_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_PCSS_LOBE_MAPS, lobeTexels_.id());
  }
}

// ---- Occlusion culling (common/occlusion_cull.h) ----

void FiberRenderer::bindOcclusion(bool enabled) {
  if (!occlusionUbo_) occlusionUbo_ = makeBuffer(sizeof(OcclusionPyramid), nullptr);
  if (!occlusionTexels_) occlusionTexels_ = makeBuffer(16, nullptr);
  OcclusionPyramid p = pyramid_;
  p.size.w = enabled ? 1u : 0u;
  occlusionUbo_.update(&p, sizeof(p));
  glBindBufferBase(GL_UNIFORM_BUFFER, FT_UBO_OCCLUSION, occlusionUbo_.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_OCCLUSION, occlusionTexels_.id());
}

void FiberRenderer::drawOccluders(FiberGpu& fibers, FiberPath path, int width, int height) {
  if (occluderWidth_ != width || occluderHeight_ != height) {
    GLuint tex = 0;
    glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &tex);
    occluderDepth_ = Texture(tex);
    glTextureStorage2DMultisample(tex, 4, GL_DEPTH_COMPONENT32F, width, height, GL_TRUE);  // the shaded target's samples
    occluderFbo_ = Framebuffer::create();
    glNamedFramebufferTexture(occluderFbo_.id(), GL_DEPTH_ATTACHMENT, tex, 0);
    glNamedFramebufferDrawBuffer(occluderFbo_.id(), GL_NONE);
    glNamedFramebufferReadBuffer(occluderFbo_.id(), GL_NONE);
    occluderWidth_ = width;
    occluderHeight_ = height;
  }
  ensurePyramid(width, height);
  bindOcclusion(false);
  glBindFramebuffer(GL_FRAMEBUFFER, occluderFbo_.id());
  glViewport(0, 0, width, height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  bindShading();  // the core-fiber texture's holes are not occluders
  // Plain lines first (no fragment work), then the textured core strips,
  // whose fragments look up the texture: two programs, so that neither pays
  // for the other's code (llvmpipe runs all of a fragment shader).
  const bool texturedCores = (inputs_.params.flags.w & FT_APPEARANCE_CORE_TEXTURE) != 0u;
  const GLuint plain = program(fibers, path, StripPass::PlainOccluders);
  setUniform(plain, "occluderTexturedCores", texturedCores ? 1u : 0u);
  fibers.draw(path, plain);
  if (texturedCores) {
    const GLuint cores = program(fibers, path, StripPass::CoreOccluders);
    setUniform(cores, "shaded", 1u);
    fibers.draw(path, cores);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDisable(GL_DEPTH_TEST);
  buildPyramid(occluderDepth_.id());
}

void FiberRenderer::ensurePyramid(int width, int height) {
  if (pyramidWidth_ == width && pyramidHeight_ == height) return;
  pyramid_ = ftOcclusionPyramidLayout(uint32_t(width), uint32_t(height));
  occlusionTexels_ = makeBuffer(size_t(ftOcclusionTexelCount(pyramid_)) * sizeof(float), nullptr);
  pyramidWidth_ = width;
  pyramidHeight_ = height;
}

void FiberRenderer::buildPyramid(GLuint multisampleDepthTexture) {
  // The layout, which the kernel reads (the culling's tests off until it is built).
  if (!faultTwoPassPyramidLayout_) bindOcclusion(false);
  if (!pyramidProgram_) pyramidProgram_ = Program(buildProgram({"shaders/occlusion_pyramid.comp.glsl"}, defines_));
  const GLuint pp = pyramidProgram_.id();
  glUseProgram(pp);
  glBindTextureUnit(FT_TEX_OCCLUDER_DEPTH, multisampleDepthTexture);
  setUniform(pp, "samples", 4u);
  glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  for (uint32_t k = 0; k < pyramid_.size.z; ++k) {
    setUniform(pp, "level", k);
    glDispatchCompute((pyramid_.level[k].y + FT_WG_OCCLUSION - 1) / FT_WG_OCCLUSION,
                      (pyramid_.level[k].z + FT_WG_OCCLUSION - 1) / FT_WG_OCCLUSION, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  glBindTextureUnit(FT_TEX_OCCLUDER_DEPTH, 0);
  bindOcclusion(true);
}

std::vector<float> FiberRenderer::readPyramidLevel0() const {
  if (pyramidWidth_ == 0) return {};
  std::vector<float> level0(size_t(pyramidWidth_) * pyramidHeight_);
  glGetNamedBufferSubData(occlusionTexels_.id(), 0, GLsizeiptr(level0.size() * sizeof(float)), level0.data());
  return level0;
}

double FiberRenderer::occludedFraction() const {
  if (pyramidWidth_ == 0) return 0.0;
  const std::vector<float> level0 = readPyramidLevel0();
  size_t occluded = 0;
  for (float d : level0) occluded += d < 1.0f;
  return double(occluded) / double(level0.size());
}

namespace {

// Copies a 4× multisampled texture, sample by sample (sample_depth_read.comp.glsl).
template <typename T>
std::vector<T> readSamples(GLuint prog, GLuint texture, int width, int height) {
  const size_t count = size_t(width) * height * 4;
  Buffer out = makeBuffer(count * sizeof(T), nullptr);
  glUseProgram(prog);
  glBindTextureUnit(FT_TEX_OCCLUDER_DEPTH, texture);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SAMPLE_DEPTHS, out.id());
  setUniform(prog, "width", uint32_t(width));
  setUniform(prog, "height", uint32_t(height));
  glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  glDispatchCompute((width + FT_WG_OCCLUSION - 1) / FT_WG_OCCLUSION, (height + FT_WG_OCCLUSION - 1) / FT_WG_OCCLUSION, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glBindTextureUnit(FT_TEX_OCCLUDER_DEPTH, 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_SAMPLE_DEPTHS, 0);
  std::vector<T> values(count);
  glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(count * sizeof(T)), values.data());
  return values;
}

}  // namespace

std::vector<float> FiberRenderer::readSampleDepths(GLuint texture, int width, int height) const {
  if (!sampleDepthProgram_)
    sampleDepthProgram_ = Program(buildProgram({"shaders/sample_depth_read.comp.glsl"}, defines_));
  return readSamples<float>(sampleDepthProgram_.id(), texture, width, height);
}

std::vector<uint32_t> FiberRenderer::readFrameSampleLines() const {
  if (!deferredTarget_) return {};
  if (!sampleLineProgram_) {
    std::vector<std::string> defines = defines_;
    defines.push_back("FT_SAMPLE_READ_UINT");
    sampleLineProgram_ = Program(buildProgram({"shaders/sample_depth_read.comp.glsl"}, defines));
  }
  return readSamples<uint32_t>(sampleLineProgram_.id(), deferredTarget_->lines.id(), deferredTarget_->width,
                               deferredTarget_->height);
}

std::vector<uint32_t> FiberRenderer::readVisibleLines() const {
  if (!visibleKept_) return {};
  const Buffer& kept = visibleLines_[1 - visibleNow_];
  std::vector<uint32_t> words((size_t(1) << visibleBits_) / 32);
  glGetNamedBufferSubData(kept.id(), 0, GLsizeiptr(words.size() * sizeof(uint32_t)), words.data());
  return words;
}

std::vector<float> FiberRenderer::readOccluderSampleDepths() const {
  if (occluderWidth_ == 0) return {};
  return readSampleDepths(occluderDepth_.id(), occluderWidth_, occluderHeight_);
}

std::vector<float> FiberRenderer::readFrameSampleDepths() const {
  if (!shadedTarget_) return {};
  return readSampleDepths(shadedTarget_->depth.id(), shadedTarget_->width, shadedTarget_->height);
}

namespace {

// The marks of two-pass culling for a width × height frame: a frame's lines
// that win a sample are at most its samples (4 per pixel), so 4 marks per
// sample keep a line unseen but marked through another's key below 1 in 4
// (0.5 % at the whole glove: 161 k lines seen, 2^25 marks, 4 MB).
uint32_t lineKeyBits(int width, int height) {
  const uint64_t samples = uint64_t(std::max(width, 1)) * uint64_t(std::max(height, 1)) * FT_DEFERRED_SAMPLES;
  uint32_t bits = 16;
  while (bits < 30 && (uint64_t(1) << bits) < 4 * samples) ++bits;
  return bits;
}

}  // namespace

bool FiberRenderer::drawsTwoPass(const FiberGpu& fibers, int width, int height) const {
  return deferred_ && twoPass_ && occlusionCull_ != OcclusionCull::Off && visibleKept_ &&
         visibleModel_ == fibers.modelVersion() && visibleBits_ == lineKeyBits(width, height);
}

bool FiberRenderer::cullsView(const FiberGpu& fibers) const {
  if (occlusionCull_ != OcclusionCull::Auto) return occlusionCull_ == OcclusionCull::On;
  // Auto: cull unless the whole model is in view (the control points' bounds
  // project within twice the image, scene/camera.h boxInView). Measured on the glove
  // at 1280 x 960 (docs/shaded-frame.md): whole view 16 % of the image behind
  // occluders, culling +17 % frame time; close-up 63 %, culling -36 %.
  return !boxInView(fibers.view(), fibers.boundsMin(), fibers.boundsMax(), 2.0f);
}

// The fibers drawn with `prog`; with `timings`, counting the geometry
// stage's primitives and the fragment-shader invocations where the driver
// has pipeline statistics (GL 4.6 or ARB_pipeline_statistics_query).
void FiberRenderer::drawCounted(FiberGpu& fibers, FiberPath path, GLuint prog, FrameTimings* timings,
                                GLuint computeIndices) {
  const auto drawFibers = [&] {
    if (computeIndices != 0 && path == FiberPath::Compute) fibers.drawComputeIndices(prog, computeIndices);
    else fibers.draw(path, prog);
  };
  const bool count =
      timings && (epoxy_gl_version() >= 46 || epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query"));
  if (!count) {
    drawFibers();
    return;
  }
  // glGenQueries: Mesa 22.3's glCreateQueries refuses these targets.
  GLuint ids[2] = {};
  glGenQueries(2, ids);
  Query primitives(ids[0]), fragments(ids[1]);
  glBeginQuery(GL_GEOMETRY_SHADER_PRIMITIVES_EMITTED_ARB, primitives.id());
  glBeginQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, fragments.id());
  drawFibers();
  glEndQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
  glEndQuery(GL_GEOMETRY_SHADER_PRIMITIVES_EMITTED_ARB);
  GLuint64 n = 0;
  glGetQueryObjectui64v(primitives.id(), GL_QUERY_RESULT, &n);
  timings->shadePrimitives += n;
  glGetQueryObjectui64v(fragments.id(), GL_QUERY_RESULT, &n);
  timings->shadeFragmentInvocations += n;
}

namespace {

// The strip-ray probe's inputs (FT_STRIP_RAY_PROBE, fiber_strip.frag.glsl),
// where the program has them: the bound multisample target's sample
// positions, as GL reports them, and the viewport.
void setRayProbeUniforms(GLuint prog, int width, int height) {
  if (glGetUniformLocation(prog, "probeViewport") < 0) return;
  GLint samples = 0;
  glGetIntegerv(GL_SAMPLES, &samples);
  for (GLint i = 0; i < std::min(samples, 4); ++i) {
    GLfloat p[2] = {0.5f, 0.5f};
    glGetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(i), p);
    setUniform(prog, fmt::format("probeSamplePositions[{}]", i).c_str(), glm::vec2(p[0], p[1]));
  }
  setUniform(prog, "probeViewport", glm::vec2(float(width), float(height)));
}

}  // namespace

void FiberRenderer::draw(FiberGpu& fibers, FiberPath path, int width, int height, FrameTimings* timings) {
  if (!shadingUbo_) throw std::logic_error("FiberRenderer: setShading() before a shaded frame");
  auto t = std::chrono::steady_clock::now();
  double cpu = timings ? processCpuMs() : 0.0, frameCpu = cpu;
  // Ends a phase: with `timings`, finishes it and adds its time to `ms`
  // (and its CPU time to `cpuMs`).
  double noCpu = 0;
  auto phase = [&](double& ms, double& cpuMs) {
    if (!timings) return;
    glFinish();
    const auto now = std::chrono::steady_clock::now();
    ms += std::chrono::duration<double, std::milli>(now - t).count();
    t = now;
    const double c = processCpuMs();
    cpuMs += c - cpu;
    cpu = c;
  };
  if (timings) *timings = FrameTimings{};
  double building = 0;
  const bool ds = (inputs_.params.flags.w & FT_APPEARANCE_DUAL_SCATTERING) != 0u;
  const bool env = (inputs_.params.flags.w & FT_APPEARANCE_ENVIRONMENT) != 0u;
  // Soft shadows or lobe maps: the PCSS variant of the shaded pass.
  const bool pcss = (inputs_.params.flags.w & FT_APPEARANCE_SOFT_SHADOWS) != 0u || inputs_.lobeShadowEnvironment.has_value();
  // Two-pass culling needs no occluder pass: the lines the last frame saw are its occluders.
  const bool twoPass = drawsTwoPass(fibers, width, height);
  const bool cull = !twoPass && cullsView(fibers);
  const GLuint prog = program(fibers, path,
                              ds ? (env ? StripPass::ShadedDualScatteringEnvironment : StripPass::ShadedDualScattering)
                                 : (env ? StripPass::ShadedEnvironment : StripPass::Shaded),
                              pcss, cull);
  phase(building, noCpu);  // a program's first build is not a phase of the frame
  frameCpu = cpu;
  if ((inputs_.params.flags.w & FT_APPEARANCE_SHADOW_MAP) != 0u &&
      ((shadowModel_ != fibers.modelVersion() && !faultShadowMapStale_) || shadowInputs_ != inputsVersion_ ||
       !shadowTexels_))
    drawShadowMap(fibers);
  if (inputs_.lobeShadowEnvironment &&
      (lobeModel_ != fibers.modelVersion() || lobeInputs_ != inputsVersion_ || lobeLayers_ == 0))
    drawLobeShadowMaps(fibers, *inputs_.lobeShadowEnvironment, inputs_.lobeShadowMapSize);
  if (timings) phase(timings->shadowMapMs, noCpu);
  fibers.prepareDraw(path);
  if (timings) phase(timings->generateMs, noCpu);
  if (cull) drawOccluders(fibers, path, width, height);
  else bindOcclusion(false);
  if (timings) phase(timings->depthMs, timings->depthCpuMs);
  // 32-bit float: the ground-truth comparison needs more than half's 11 bits.
  if (!shadedTarget_ || shadedTarget_->width != width || shadedTarget_->height != height)
    shadedTarget_ = std::make_unique<MultisampleTarget>(width, height, GL_RGBA32F);
  shadedTarget_->begin(glm::vec4(glm::vec3(inputs_.params.background), 0.0f));
  bindShading();
  if (deferred_) {
    drawDeferred(fibers, path, ds, env, pcss, cull, twoPass, timings);
    t = std::chrono::steady_clock::now();
    if (timings) cpu = processCpuMs();
  } else {
    setUniform(prog, "shaded", 1u);
    setRayProbeUniforms(prog, width, height);
    drawCounted(fibers, path, prog, timings);
    visibleKept_ = false;  // only the deferred frame marks what it saw
  }
  if ((inputs_.params.flags.w & FT_APPEARANCE_FLYAWAYS) != 0u) drawFlyaways(fibers);  // the third pass
  shadedTarget_->finish();
  if (timings) {
    phase(deferred_ ? timings->deferredMs : timings->shadeMs, deferred_ ? noCpu : timings->shadeCpuMs);
    timings->totalCpuMs = cpu - frameCpu;
  }
}

// Deferred shading (docs/shaded-frame.md): on llvmpipe every rasterised
// fragment costs the whole fragment shader (docs/llvmpipe-notes.md), so the
// shading moves out of it. Called with the shaded target bound and cleared;
// leaves it bound with the colour of every sample the fibers won written.
// The compute path's index buffer for draw `which` (1 or 2) of two-pass
// culling (two_pass_lines.comp.glsl); 0 on the tessellation path, whose
// geometry stage alone chooses. Needs the kept marks and, for the second
// draw, the pyramid bound.
GLuint FiberRenderer::twoPassIndices(FiberGpu& fibers, FiberPath path, uint32_t which, uint32_t bits) {
  if (path != FiberPath::Compute) return 0;
  const size_t count = fibers.readDrawCommand().count;
  if (twoPassIndexCapacity_ < fibers.indexCapacity() || !twoPassIndices_) {
    twoPassIndexCapacity_ = std::max<size_t>(fibers.indexCapacity(), 1);
    twoPassIndices_ = makeBuffer(twoPassIndexCapacity_ * sizeof(uint32_t), nullptr);
  }
  if (!twoPassLinesProgram_)
    twoPassLinesProgram_ = Program(buildProgram({"shaders/two_pass_lines.comp.glsl"}, defines_));
  const GLuint p = twoPassLinesProgram_.id();
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_TWO_PASS_INDICES, twoPassIndices_.id());
  setUniform(p, "twoPassDraw", which);
  setUniform(p, "lineKeyBits", bits);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  dispatchFlat(p, count, FT_WG_TWO_PASS, maxGroupsY_, "two_pass_lines");
  glMemoryBarrier(GL_ELEMENT_ARRAY_BARRIER_BIT);
  fibers.bindYarn();  // the strip owners at their slot again
  return twoPassIndices_.id();
}

void FiberRenderer::drawDeferred(FiberGpu& fibers, FiberPath path, bool ds, bool env, bool pcss, bool cull,
                                 bool twoPass, FrameTimings* timings) {
  const int width = shadedTarget_->width, height = shadedTarget_->height;
  if (!deferredTarget_ || deferredTarget_->width != width || deferredTarget_->height != height)
    deferredTarget_ = std::make_unique<DeferredTarget>(width, height, shadedTarget_->depth.id());
  DeferredTarget& dt = *deferredTarget_;
  auto t = std::chrono::steady_clock::now();
  const double cpu = timings ? processCpuMs() : 0.0;
  // 1. The visibility pass: the forward pass's casts, coverage, core texture
  // and depth, writing the hit records (0: no fiber) into the shared depth.
  glBindFramebuffer(GL_FRAMEBUFFER, dt.fbo.id());
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int k = 0; k < FT_VISIBILITY_TARGETS; ++k) glClearNamedFramebufferfv(dt.fbo.id(), GL_COLOR, k, zero);
  const GLuint zeroKey[4] = {0u, 0u, 0u, 0u};
  glClearNamedFramebufferuiv(dt.fbo.id(), GL_COLOR, FT_VISIBILITY_TARGETS, zeroKey);
  // Two-pass culling's bit sets: the kept one (read by the draws), this frame's (cleared, set by the compaction).
  const uint32_t bits = lineKeyBits(width, height);
  if (visibleBits_ != bits || !visibleLines_[0]) {
    for (Buffer& b : visibleLines_) b = makeBuffer((size_t(1) << bits) / 8, nullptr);
    visibleBits_ = bits;
    visibleKept_ = false;
  }
  const Buffer& seen = visibleLines_[1 - visibleNow_];
  const Buffer& seeing = visibleLines_[visibleNow_];
  glClearNamedBufferData(seeing.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_VISIBLE_LINES, seen.id());
  const auto visibilityDraw = [&](bool occlusionTest, uint32_t which) {
    const GLuint indices = which != FT_TWO_PASS_ALL ? twoPassIndices(fibers, path, which, bits) : 0;
    const GLuint vis = program(fibers, path, StripPass::Visibility, false, occlusionTest);
    setUniform(vis, "shaded", 1u);
    setUniform(vis, "twoPassDraw", which);
    setUniform(vis, "lineKeyBits", bits);
    drawCounted(fibers, path, vis, timings, indices);
  };
  if (twoPass) {
    // First the lines the last frame saw, then the pyramid of the depth they
    // left, then the other lines against it (common/occlusion_cull.h).
    visibilityDraw(false, FT_TWO_PASS_SEEN);
    if (timings) {
      glFinish();
      timings->twoPass = true;
      timings->firstDrawPrimitives = timings->shadePrimitives;
      timings->firstDrawMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
      timings->firstDrawCpuMs = processCpuMs() - cpu;
    }
    ensurePyramid(width, height);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!faultTwoPassStalePyramid_) buildPyramid(shadedTarget_->depth.id());
    else bindOcclusion(true);  // planted: whatever pyramid the last frame left
    glBindFramebuffer(GL_FRAMEBUFFER, dt.fbo.id());
    if (faultTwoPassDepthCleared_) glClear(GL_DEPTH_BUFFER_BIT);  // planted: the second draw on a fresh depth
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_VISIBLE_LINES, seen.id());
    visibilityDraw(true, FT_TWO_PASS_UNSEEN);
  } else {
    visibilityDraw(cull, 0u);
  }
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_VISIBLE_LINES, 0);
  auto afterVisibility = std::chrono::steady_clock::now();
  if (timings) {
    glFinish();
    afterVisibility = std::chrono::steady_clock::now();
    timings->shadeMs += std::chrono::duration<double, std::milli>(afterVisibility - t).count();
    timings->shadeCpuMs += processCpuMs() - cpu;
  }
  // 2. The compaction: each pixel's distinct records, one entry each, over
  // the tiles that hold a covered sample (listed first, one word per sample read).
  if (!compactProgram_) {
    compactTilesProgram_ = Program(buildProgram({"shaders/fiber_compact_tiles.comp.glsl"}, defines_));
    compactProgram_ = Program(buildProgram({"shaders/fiber_compact.comp.glsl"}, defines_));
  }
  const uint32_t header[4] = {0u, 0u, 0u, 0u};
  dt.list.update(header, sizeof(header));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_DEFERRED_LIST, dt.list.id());
  for (int k = 0; k < FT_VISIBILITY_TARGETS; ++k) glBindTextureUnit(FT_TEX_HIT_RECORD0 + k, dt.records[k].id());
  glBindTextureUnit(FT_TEX_HIT_LINE, dt.lines.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_VISIBLE_LINES, seeing.id());
  glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  const uint32_t tileBase = uint32_t(width) * uint32_t(height) * FT_DEFERRED_SAMPLES;
  const size_t allTiles = deferredTileCount(width, height);
  for (const Program* p : {&compactTilesProgram_, &compactProgram_}) {
    setUniform(p->id(), "size", glm::uvec2(width, height));
    setUniform(p->id(), "tileBase", tileBase);
  }
  dispatchFlat(compactTilesProgram_.id(), allTiles, FT_WG_DEFERRED_TILES, maxGroupsY_, "fiber_compact_tiles");
  uint32_t count[4] = {};
  glGetNamedBufferSubData(dt.list.id(), 0, sizeof(count), count);
  if (count[1] > allTiles)
    throw std::runtime_error(fmt::format("deferred shading: {} tiles listed of {}", count[1], allTiles));
  dispatchFlat(compactProgram_.id(), size_t(count[1]) * FT_WG_DEFERRED_COMPACT, FT_WG_DEFERRED_COMPACT, maxGroupsY_,
               "fiber_compact");
  glBindTextureUnit(FT_TEX_HIT_LINE, 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_VISIBLE_LINES, 0);
  visibleNow_ = 1 - visibleNow_;
  visibleKept_ = true;
  visibleModel_ = fibers.modelVersion();
  glGetNamedBufferSubData(dt.list.id(), 0, sizeof(count), count);
  const size_t capacity = size_t(width) * height * FT_DEFERRED_SAMPLES;
  if (count[0] > capacity)
    throw std::runtime_error(fmt::format("deferred shading: {} entries listed for {} samples", count[0], capacity));
  deferredEntries_ = count[0];
  // 3. The shading of the list: the forward pass's shadeFiber, in a compute
  // stage, each entry's colour stored to its samples of the shaded target
  // (cleared to the background; the depth stays the visibility pass's, for the flyaways).
  Program& shade = shadeProgram_[ds ? 1 : 0][env ? 1 : 0][pcss ? 1 : 0];
  if (!shade) {
    std::vector<std::string> defines = defines_;
    if (ds) defines.push_back("FT_FRAME_DUAL_SCATTERING");
    if (env) defines.push_back("FT_FRAME_ENVIRONMENT");
    if (pcss) defines.push_back("FT_FRAME_PCSS");
    shade = Program(buildProgram({"shaders/fiber_shade.comp.glsl"}, defines));
  }
  fibers.bindYarn();  // the view, the yarn parameters and the curves (still bound: made sure)
  glBindImageTexture(FT_IMAGE_SHADED, shadedTarget_->color.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                     shadedTarget_->colorFormat);
  dispatchFlat(shade.id(), deferredEntries_, FT_WG_DEFERRED_SHADE, maxGroupsY_, "fiber_shade");
  glBindImageTexture(FT_IMAGE_SHADED, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, shadedTarget_->colorFormat);
  for (int k = 0; k < FT_VISIBILITY_TARGETS; ++k) glBindTextureUnit(FT_TEX_HIT_RECORD0 + k, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, shadedTarget_->ms.id());
  // The flyaway pass blends over the stored colours, read() blits them.
  glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  if (timings) {  // the compaction's read-back waits for it: timed here, not by the caller
    glFinish();
    timings->deferredMs +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - afterVisibility).count();
  }
}

ImageRgbaF FiberRenderer::read() const {
  if (!shadedTarget_) throw std::logic_error("FiberRenderer: read() before draw()");
  ImageRgbaF img;
  img.width = shadedTarget_->width;
  img.height = shadedTarget_->height;
  img.pixels = shadedTarget_->read<float>(GL_FLOAT);
  return img;
}

ImageRgbaF FiberRenderer::render(FiberGpu& fibers, FiberPath path, int width, int height) {
  draw(fibers, path, width, height);
  return read();
}

std::vector<glm::vec2> FiberRenderer::samplePositions() const {
  if (!shadedTarget_) throw std::logic_error("FiberRenderer: samplePositions() before draw()");
  glBindFramebuffer(GL_FRAMEBUFFER, shadedTarget_->ms.id());
  GLint samples = 0;
  glGetIntegerv(GL_SAMPLES, &samples);
  std::vector<glm::vec2> out;
  for (GLint i = 0; i < samples; ++i) {
    GLfloat p[2] = {0.5f, 0.5f};
    glGetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(i), p);
    out.emplace_back(p[0], 1.0f - p[1]);  // GL's pixel y points up
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return out;
}

namespace {

void setPreviewUniforms(GLuint prog, const RenderStyle& style) {
  setUniform(prog, "shaded", 0u);
  setUniform(prog, "lightDir", style.lightDir);
  setUniform(prog, "baseColor", style.baseColor);
}

}  // namespace

RgbaImage FiberRenderer::preview(FiberGpu& fibers, FiberPath path, int width, int height, const RenderStyle& style) {
  const GLuint prog = program(fibers, path);
  fibers.prepareDraw(path);
  bindOcclusion(false);
  const MultisampleTarget target(width, height, GL_RGBA8);
  target.begin(glm::vec4(style.background, 1.0f));
  setPreviewUniforms(prog, style);
  fibers.draw(path, prog);
  target.finish();
  return RgbaImage{width, height, target.read<uint8_t>(GL_UNSIGNED_BYTE)};
}

RgbaImage FiberRenderer::previewVertices(FiberGpu& fibers, std::span<const FiberVertex> vertices,
                                         std::span<const SegmentDecision> decisions, int width, int height,
                                         const RenderStyle& style) {
  const GLuint prog = program(fibers, FiberPath::Compute);
  bindOcclusion(false);
  const MultisampleTarget target(width, height, GL_RGBA8);
  target.begin(glm::vec4(style.background, 1.0f));
  setPreviewUniforms(prog, style);
  fibers.drawVertices(vertices, decisions, prog);
  target.finish();
  return RgbaImage{width, height, target.read<uint8_t>(GL_UNSIGNED_BYTE)};
}

}  // namespace ft
