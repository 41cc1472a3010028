// Shared C++/GLSL layouts (reference-data §6): for every struct in the common/
// headers that crosses the API, GL's view of the compiled probe program
// (gpu/shaders/layout_probe.comp.glsl) must match C++ offsetof/sizeof member by
// member, every member must be listed here (GL's active-member count), and a
// round trip through the GPU must preserve the bytes.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "common/ambient_occlusion.h"
#include "common/constants.h"
#include "common/core_texture.h"
#include "common/exemplar_volume.h"
#include "common/fiber_shading.h"
#include "common/fiber_vertex.h"
#include "common/flyaway.h"
#include "common/knit_stitch.h"
#include "common/occlusion_cull.h"
#include "common/segment_visibility.h"
#include "common/pcss.h"
#include "common/prt_frame.h"
#include "common/prt_single_scattering.h"
#include "common/shadow_map.h"
#include "common/srbf.h"
#include "common/view_params.h"
#include "common/yarn_buffers.h"
#include "common/yarn_params.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"
#include "gpu/shader_library.h"

namespace ft {
namespace {

// Every member, padding included, in declaration order; keep in step with common/
// (a renamed member breaks the build here, a new one fails MemberCountMatches, a
// wrong offset or size fails OffsetsMatch).
// clang-format off
#define FT_YARN_PARAMS_MEMBERS(X) \
  X(plyCount) X(fiberCount) X(regularFibers) X(maxSubdivisions) X(plyRadius) X(ellipseN) X(ellipseB) \
  X(fiberRadius) X(plyTurnsPerLength) X(fiberTurnsPerLength) X(plyTwistSign) X(fiberTwistSign) \
  X(migrationS) X(rhoMin) X(rhoMax) X(coreRadius) X(loopProbability) X(hairProbability) X(loopR1Mu) \
  X(loopR1Sigma) X(hairZeMu) X(hairZeSigma) X(hairR0Mu) X(hairR0Sigma) X(hairReMu) X(hairReSigma) \
  X(hairPeMu) X(hairPeSigma) X(boundRadius) X(seed) X(flyawayCells) X(migrationPhase)
#define FT_VIEW_PARAMS_MEMBERS(X) \
  X(viewProj) X(frustumPlanes) X(cameraPos) X(lodThresholdPx) X(lodEnabled) X(cullEnabled) X(chordErrorPx)
#define FT_CONTROL_POINT_MEMBERS(X) X(positionLength)
#define FT_CURVE_INFO_MEMBERS(X) \
  X(firstPoint) X(pointCount) X(closed) X(firstSegment) X(totalLength) X(basis) X(frameBase) X(pad0)
#define FT_SEGMENT_REF_MEMBERS(X) X(curve) X(local)
#define FT_FRAME_NORMAL_MEMBERS(X) X(normal)
#define FT_FIBER_COORD_MEMBERS(X) X(radius) X(thetaTurns)
#define FT_FIBER_VERTEX_MEMBERS(X) X(position) X(id)
#define FT_SEGMENT_DECISION_MEMBERS(X) \
  X(lambda) X(coreHalfWidth) X(regularCount) X(subdivisions) X(culled) X(vertexCount) X(coreHalfWidthEnd) \
  X(coreLines)
#define FT_DRAW_ELEMENTS_COMMAND_MEMBERS(X) \
  X(count) X(instanceCount) X(firstIndex) X(baseVertex) X(baseInstance) X(vertexTotal) X(stripTotal) \
  X(sampleTotal)
#define FT_YARN_SAMPLE_MEMBERS(X) X(centerLength) X(tangent) X(normal) X(binormal)
#define FT_KNIT_STITCH_GPU_MEMBERS(X) \
  X(origin) X(e1) X(e2) X(normal) X(knots) X(theta0) X(fixedXY) X(fixedH) X(restLength) X(restCosine) X(misc)
#define FT_KNIT_SOLVE_PARAMS_MEMBERS(X) X(wAngle) X(wLength) X(iterations) X(stitchCount)
#define FT_KNIT_ENERGY_GPU_MEMBERS(X) X(energy) X(steps) X(pad0) X(pad1)
#define FT_SHADING_PARAMS_MEMBERS(X) \
  X(fabric.colorR) X(fabric.colorTT) X(fabric.lobes) X(lightDirection) X(lightIrradiance) X(ambient) X(diffuse) \
  X(simple) X(flags) X(background)
#define FT_CORE_TEXTURE_PARAMS_MEMBERS(X) \
  X(width) X(height) X(columns) X(coreFibers) X(segmentsPerTwist) X(uOffset) X(alpha) X(coreHalfWidth) \
  X(fiberRadius) X(twistSign) X(migrationS) X(rhoMin) X(rhoMax) X(plyScale) X(rayStart) X(pad0)
#define FT_AO_PARAMS_MEMBERS(X) \
  X(density.plyCount) X(density.fiberCount) X(density.plyRadius) X(density.ellipseN) X(density.ellipseB) \
  X(density.epsilon) X(density.beta) X(density.rMax) X(density.normalization) X(density.plyTwistSign) \
  X(density.supportRadius) X(density.pad0) X(cubic) X(resolution) X(directions) X(directionMode) X(seed) \
  X(halfWidth) X(kappa) X(densityResolution) X(marchStep)
#define FT_SHADOW_MAP_PARAMS_MEMBERS(X) X(lightX) X(lightY) X(lightZ) X(extent) X(tube) X(count)
#define FT_OCCLUSION_PYRAMID_MEMBERS(X) X(size) X(level)
#define FT_SVF_PARAMS_MEMBERS(X) \
  X(width) X(height) X(axes) X(segments) X(seed) X(components) X(firstSegment) X(mode) X(lambda) X(pad0) X(pad1) X(pad2)
#define FT_SRBF_ENVIRONMENT_MEMBERS(X) \
  X(lobes[0].axisLambda) X(lobes[0].weight) X(lobes[1].axisLambda) X(lobes[1].weight) X(lobes[2].axisLambda) X(lobes[2].weight) X(lobes[3].axisLambda) X(lobes[3].weight) \
   X(lobes[4].axisLambda) X(lobes[4].weight) X(lobes[5].axisLambda) X(lobes[5].weight) X(lobes[6].axisLambda) X(lobes[6].weight) X(lobes[7].axisLambda) X(lobes[7].weight) \
   X(lobes[8].axisLambda) X(lobes[8].weight) X(lobes[9].axisLambda) X(lobes[9].weight) X(lobes[10].axisLambda) X(lobes[10].weight) X(lobes[11].axisLambda) X(lobes[11].weight) \
   X(lobes[12].axisLambda) X(lobes[12].weight) X(lobes[13].axisLambda) X(lobes[13].weight) X(lobes[14].axisLambda) X(lobes[14].weight) X(lobes[15].axisLambda) X(lobes[15].weight) \
  X(constant)
#define FT_FLYAWAY_PARAMS_MEMBERS(X) \
  X(width) X(height) X(maxPerSet) X(patterns) X(period) X(halfWidth) X(bodyRadius) X(lineHalfWidth) X(zeMu) X(zeSigma) \
  X(r0Mu) X(r0Sigma) X(reMu) X(reSigma) X(peMu) X(peSigma) X(rootOffset) X(alpha) X(noise) X(zReach) \
  X(margin) X(poissonThresholdB) X(poissonThresholdI) X(chunksB) X(chunksI) X(seed) X(pad0) X(pad1)
#define FT_PRT_FRAME_GPU_PARAMS_MEMBERS(X) \
  X(light) X(sizes) X(ms) X(offsets) X(flags) X(svf) X(fabric.colorR) X(fabric.colorTT) X(fabric.lobes)
#define FT_PRT_SS_FABRIC_MEMBERS(X, i) X(fabrics[i].colorR) X(fabrics[i].colorTT) X(fabrics[i].lobes)
#define FT_PRT_SS_PARAMS_MEMBERS(X) \
  FT_PRT_SS_FABRIC_MEMBERS(X, 0) FT_PRT_SS_FABRIC_MEMBERS(X, 1) FT_PRT_SS_FABRIC_MEMBERS(X, 2) FT_PRT_SS_FABRIC_MEMBERS(X, 3) \
  FT_PRT_SS_FABRIC_MEMBERS(X, 4) FT_PRT_SS_FABRIC_MEMBERS(X, 5) FT_PRT_SS_FABRIC_MEMBERS(X, 6) FT_PRT_SS_FABRIC_MEMBERS(X, 7) \
  X(count) X(mode) X(fabricCount) X(axes) X(lambdaSvf) X(tableSize) X(pad0) X(pad1)
#define FT_PCSS_PARAMS_MEMBERS(X) X(lightTanAlpha) X(lobeX) X(lobeY) X(lobeZ) X(lobeCone) X(extent) X(count)
#define FT_VOL_PARAMS_MEMBERS(X) X(origin) X(dims) X(grid) X(ray) X(camPos) X(camRight) X(camUp) X(camDir)
// clang-format on

struct Member {
  const char* name;
  std::size_t offset;
  std::size_t size;
};
// Expanded where `S` names the struct.
#define FT_MEMBER(m) Member{#m, offsetof(S, m), sizeof(S::m)},

// How the probe shader exposes one struct.
struct StructCase {
  const char* cppName;
  std::size_t size;
  std::vector<Member> members;
  bool uniform;        // std140 uniform block with one struct member, else std430 SSBO `{ T data[]; }`
  const char* block;   // block name
  std::string prefix;  // resource-name prefix of the members
  GLuint binding;
};

// Uniform structs sit in `uniform <block> { T <instance>; }`, storage structs in
// `buffer <T>Buf { T data[]; }`; `S` is the struct for FT_MEMBER.
#define FT_UNIFORM_CASE(T, LIST, block, instance, binding)                                   \
  [] {                                                                                       \
    using S = T;                                                                             \
    return StructCase{#T, sizeof(S), {LIST(FT_MEMBER)}, true, block, instance ".", binding}; \
  }()
#define FT_STORAGE_CASE(T, LIST, binding)                                                             \
  [] {                                                                                                \
    using S = T;                                                                                      \
    return StructCase{#T, sizeof(S), {LIST(FT_MEMBER)}, false, #T "Buf", #T "Buf.data[0].", binding}; \
  }()

std::vector<StructCase> structCases() {
  return {
      FT_UNIFORM_CASE(YarnParams, FT_YARN_PARAMS_MEMBERS, "YarnBlock", "yarn", FT_UBO_YARN_PARAMS),
      FT_UNIFORM_CASE(ViewParams, FT_VIEW_PARAMS_MEMBERS, "ViewBlock", "view", FT_UBO_VIEW_PARAMS),
      FT_STORAGE_CASE(ControlPoint, FT_CONTROL_POINT_MEMBERS, FT_SSBO_CONTROL_POINTS),
      FT_STORAGE_CASE(CurveInfo, FT_CURVE_INFO_MEMBERS, FT_SSBO_CURVES),
      FT_STORAGE_CASE(SegmentRef, FT_SEGMENT_REF_MEMBERS, FT_SSBO_SEGMENTS),
      FT_STORAGE_CASE(FrameNormal, FT_FRAME_NORMAL_MEMBERS, FT_SSBO_FRAMES),
      FT_STORAGE_CASE(FiberCoord, FT_FIBER_COORD_MEMBERS, FT_SSBO_FIBER_TABLE),
      FT_STORAGE_CASE(FiberVertex, FT_FIBER_VERTEX_MEMBERS, FT_SSBO_VERTICES),
      FT_STORAGE_CASE(SegmentDecision, FT_SEGMENT_DECISION_MEMBERS, FT_SSBO_DECISIONS),
      FT_STORAGE_CASE(DrawElementsCommand, FT_DRAW_ELEMENTS_COMMAND_MEMBERS, FT_SSBO_DRAW_COMMAND),
      FT_STORAGE_CASE(YarnSample, FT_YARN_SAMPLE_MEMBERS, FT_SSBO_SAMPLES),
      FT_UNIFORM_CASE(KnitSolveParams, FT_KNIT_SOLVE_PARAMS_MEMBERS, "KnitParamsBlock", "knit", FT_UBO_KNIT_PARAMS),
      FT_STORAGE_CASE(KnitStitchGpu, FT_KNIT_STITCH_GPU_MEMBERS, FT_SSBO_KNIT_STITCHES),
      FT_STORAGE_CASE(KnitEnergyGpu, FT_KNIT_ENERGY_GPU_MEMBERS, FT_SSBO_KNIT_ENERGY),
      FT_UNIFORM_CASE(ShadingParams, FT_SHADING_PARAMS_MEMBERS, "ShadingBlock", "shading", FT_UBO_SHADING),
      FT_UNIFORM_CASE(CoreTextureParams, FT_CORE_TEXTURE_PARAMS_MEMBERS, "CoreTextureBlock", "core",
                      FT_UBO_CORE_TEXTURE),
      FT_UNIFORM_CASE(AmbientOcclusionParams, FT_AO_PARAMS_MEMBERS, "AoBlock", "ao", FT_UBO_AMBIENT_OCCLUSION),
      FT_UNIFORM_CASE(ShadowMapParams, FT_SHADOW_MAP_PARAMS_MEMBERS, "ShadowMapBlock", "shadowMapParams",
                      FT_UBO_SHADOW_MAP),
      FT_UNIFORM_CASE(OcclusionPyramid, FT_OCCLUSION_PYRAMID_MEMBERS, "OcclusionBlock", "pyramid", FT_UBO_OCCLUSION),
      FT_UNIFORM_CASE(SrbfEnvironment, FT_SRBF_ENVIRONMENT_MEMBERS, "SrbfBlock", "srbf", FT_UBO_SRBF),
      FT_UNIFORM_CASE(FlyawayParams, FT_FLYAWAY_PARAMS_MEMBERS, "FlyawayBlock", "fly", FT_UBO_FLYAWAY),
      FT_UNIFORM_CASE(SvfParams, FT_SVF_PARAMS_MEMBERS, "SvfBlock", "svf", FT_UBO_SVF),
      FT_UNIFORM_CASE(PcssParams, FT_PCSS_PARAMS_MEMBERS, "PcssBlock", "pcss", FT_UBO_PCSS),
      FT_UNIFORM_CASE(VolParams, FT_VOL_PARAMS_MEMBERS, "VolBlock", "vol", FT_UBO_PRT_VOL),
      FT_UNIFORM_CASE(PrtSsParams, FT_PRT_SS_PARAMS_MEMBERS, "PrtSsBlock", "prtSs", FT_UBO_PRT_SS),
      FT_UNIFORM_CASE(PrtFrameGpuParams, FT_PRT_FRAME_GPU_PARAMS_MEMBERS, "PrtFrameGpuBlock", "prtFrame",
                      FT_UBO_PRT_FRAME_GPU),
  };
}

// Bytes of one GL type as a C++ member holding it (glm types are tightly packed).
std::size_t glTypeSize(GLint type) {
  switch (type) {
    case GL_FLOAT:
    case GL_INT:
    case GL_UNSIGNED_INT:
    case GL_BOOL: return 4;
    case GL_FLOAT_VEC2:
    case GL_INT_VEC2:
    case GL_UNSIGNED_INT_VEC2: return 8;
    case GL_FLOAT_VEC3:
    case GL_INT_VEC3:
    case GL_UNSIGNED_INT_VEC3: return 12;
    case GL_FLOAT_VEC4:
    case GL_INT_VEC4:
    case GL_UNSIGNED_INT_VEC4: return 16;
    case GL_FLOAT_MAT4: return 64;
    default: return 0;
  }
}

class SharedLayoutTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ctx_ = GlContext::create(glBackendFromEnv());
    program_ = Program(buildProgram({"shaders/layout_probe.comp.glsl"}, {}));
  }
  void TearDown() override {
    program_.reset();
    ctx_.reset();
  }
  GLenum memberInterface(const StructCase& s) const { return s.uniform ? GL_UNIFORM : GL_BUFFER_VARIABLE; }
  GLenum blockInterface(const StructCase& s) const {
    return s.uniform ? GL_UNIFORM_BLOCK : GL_SHADER_STORAGE_BLOCK;
  }
  GLint property(GLenum interface, GLuint index, GLenum prop) const {
    GLint value = -1;
    glGetProgramResourceiv(program_.id(), interface, index, 1, &prop, 1, nullptr, &value);
    return value;
  }
  // Sets *name to GL's canonical resource name: "member[0]" for arrays (lookups
  // accept the bare name, and Mesa even matches "[0]" on non-arrays).
  GLuint memberIndex(const StructCase& s, const Member& m, std::string* name) const {
    *name = s.prefix + m.name;
    GLuint index = glGetProgramResourceIndex(program_.id(), memberInterface(s), name->c_str());
    if (index != GL_INVALID_INDEX) {
      char buf[256] = {};
      glGetProgramResourceName(program_.id(), memberInterface(s), index, sizeof buf, nullptr, buf);
      *name = buf;
    }
    return index;
  }

  std::unique_ptr<GlContext> ctx_;
  Program program_;
};

TEST_F(SharedLayoutTest, MembersCoverTheStructWithoutImplicitPadding) {
  // Padding must be named (reference-data §6); then member sizes add up to sizeof.
  for (const StructCase& s : structCases()) {
    std::size_t sum = 0, end = 0;
    for (const Member& m : s.members) {
      EXPECT_EQ(m.offset, end) << s.cppName << "." << m.name << ": unnamed padding or list out of order";
      end = m.offset + m.size;
      sum += m.size;
    }
    EXPECT_EQ(sum, s.size) << s.cppName;
  }
}

TEST_F(SharedLayoutTest, MemberCountMatches) {
  for (const StructCase& s : structCases()) {
    GLuint block = glGetProgramResourceIndex(program_.id(), blockInterface(s), s.block);
    ASSERT_NE(block, GL_INVALID_INDEX) << s.block << " is not active in the probe";
    EXPECT_EQ(property(blockInterface(s), block, GL_NUM_ACTIVE_VARIABLES),
              static_cast<GLint>(s.members.size()))
        << s.cppName << ": GL sees a different member count than the C++ list";
    EXPECT_EQ(property(blockInterface(s), block, GL_BUFFER_BINDING), static_cast<GLint>(s.binding))
        << s.block;
    if (s.uniform) {
      EXPECT_EQ(property(blockInterface(s), block, GL_BUFFER_DATA_SIZE), static_cast<GLint>(s.size))
          << s.cppName;
    }
  }
  glCheck("MemberCountMatches");
}

TEST_F(SharedLayoutTest, OffsetsMatch) {
  for (const StructCase& s : structCases()) {
    GLuint block = glGetProgramResourceIndex(program_.id(), blockInterface(s), s.block);
    for (const Member& m : s.members) {
      std::string name;
      GLuint index = memberIndex(s, m, &name);
      ASSERT_NE(index, GL_INVALID_INDEX) << s.cppName << "." << m.name << ": no GL resource " << name;
      GLenum iface = memberInterface(s);
      const std::string where = std::string(s.cppName) + "." + m.name + " (" + name + ")";
      EXPECT_EQ(property(iface, index, GL_BLOCK_INDEX), static_cast<GLint>(block)) << where;
      EXPECT_EQ(property(iface, index, GL_OFFSET), static_cast<GLint>(m.offset)) << where;
      GLint arraySize = property(iface, index, GL_ARRAY_SIZE);
      GLint type = property(iface, index, GL_TYPE);
      if (name.back() == ']') {
        // An array member: the whole array must occupy exactly the C++ member.
        EXPECT_EQ(static_cast<std::size_t>(arraySize * property(iface, index, GL_ARRAY_STRIDE)), m.size)
            << where;
        EXPECT_EQ(static_cast<std::size_t>(arraySize) * glTypeSize(type), m.size) << where;
      } else {
        EXPECT_EQ(glTypeSize(type), m.size) << where << " GL type 0x" << std::hex << type;
      }
      if (type == GL_FLOAT_MAT4) {
        EXPECT_EQ(property(iface, index, GL_MATRIX_STRIDE), 16) << where;
        EXPECT_EQ(property(iface, index, GL_IS_ROW_MAJOR), 0) << where;  // GLM is column-major
      }
      if (!s.uniform) {
        EXPECT_EQ(property(iface, index, GL_TOP_LEVEL_ARRAY_STRIDE), static_cast<GLint>(s.size)) << where;
      }
    }
  }
  glCheck("OffsetsMatch");
}

// Fills every 32-bit word with a distinct normal float (valid as float and uint,
// so no NaN canonicalization can alter the bytes on the way).
template <class T>
T pattern(float base) {
  static_assert(sizeof(T) % 4 == 0);
  T value;
  float words[sizeof(T) / 4];
  for (std::size_t i = 0; i < sizeof(T) / 4; ++i) words[i] = base + static_cast<float>(i) * 0.25f;
  std::memcpy(&value, words, sizeof(T));
  return value;
}

template <class T>
void expectSameBytes(const T& a, const T& b, const char* what) {
  EXPECT_EQ(std::memcmp(&a, &b, sizeof(T)), 0) << what << " changed on the way through the GPU";
}

TEST_F(SharedLayoutTest, BytesSurviveTheGpu) {
  YarnParams yarn = pattern<YarnParams>(1.0f);
  ViewParams view = pattern<ViewParams>(100.0f);
  Buffer yarnUbo = Buffer::create(sizeof yarn, &yarn);
  Buffer viewUbo = Buffer::create(sizeof view, &view);
  yarnUbo.bindBase(GL_UNIFORM_BUFFER, FT_UBO_YARN_PARAMS);
  viewUbo.bindBase(GL_UNIFORM_BUFFER, FT_UBO_VIEW_PARAMS);
  Buffer copy = Buffer::create(sizeof yarn + sizeof view);
  copy.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_LAYOUT_PROBE);

  // Two elements per storage buffer: the probe copies element 0 over element 1.
  std::vector<Buffer> ssbos;
  auto add = [&](auto element, GLuint binding) {
    decltype(element) two[2] = {element, {}};
    std::memset(&two[1], 0, sizeof two[1]);
    ssbos.push_back(Buffer::create(sizeof two, two));
    ssbos.back().bindBase(GL_SHADER_STORAGE_BUFFER, binding);
  };
  add(pattern<ControlPoint>(200.0f), FT_SSBO_CONTROL_POINTS);
  add(pattern<CurveInfo>(300.0f), FT_SSBO_CURVES);
  add(pattern<SegmentRef>(400.0f), FT_SSBO_SEGMENTS);
  add(pattern<FrameNormal>(500.0f), FT_SSBO_FRAMES);
  add(pattern<FiberCoord>(600.0f), FT_SSBO_FIBER_TABLE);
  add(pattern<FiberVertex>(700.0f), FT_SSBO_VERTICES);
  add(pattern<SegmentDecision>(800.0f), FT_SSBO_DECISIONS);
  add(pattern<DrawElementsCommand>(900.0f), FT_SSBO_DRAW_COMMAND);
  add(pattern<YarnSample>(1000.0f), FT_SSBO_SAMPLES);
  add(pattern<KnitStitchGpu>(1100.0f), FT_SSBO_KNIT_STITCHES);
  add(pattern<KnitEnergyGpu>(1300.0f), FT_SSBO_KNIT_ENERGY);
  KnitSolveParams knit = pattern<KnitSolveParams>(1200.0f);
  Buffer knitUbo = Buffer::create(sizeof knit, &knit);
  knitUbo.bindBase(GL_UNIFORM_BUFFER, FT_UBO_KNIT_PARAMS);
  Buffer knitCopy = Buffer::create(sizeof knit);
  knitCopy.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_KNIT_POINTS);

  ShadingParams shading = pattern<ShadingParams>(1400.0f);
  Buffer shadingUbo = Buffer::create(sizeof shading, &shading);
  shadingUbo.bindBase(GL_UNIFORM_BUFFER, FT_UBO_SHADING);
  Buffer shadingCopy = Buffer::create(sizeof shading);
  shadingCopy.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_AMBIENT_TABLE);

  CoreTextureParams core = pattern<CoreTextureParams>(1500.0f);
  Buffer coreUbo = Buffer::create(sizeof core, &core);
  coreUbo.bindBase(GL_UNIFORM_BUFFER, FT_UBO_CORE_TEXTURE);
  Buffer coreCopy = Buffer::create(sizeof core);
  coreCopy.bindBase(GL_SHADER_STORAGE_BUFFER, FT_SSBO_CORE_TEX0);

  glUseProgram(program_.id());
  glDispatchCompute(1, 1, 1);
  glCheck("layout probe dispatch");

  auto check = [&](std::size_t k, auto element, const char* what) {
    using T = decltype(element);
    std::vector<T> out = readBuffer<T>(ssbos[k].id(), 2);
    expectSameBytes(out[0], out[1], what);
    expectSameBytes(element, out[1], what);
  };
  check(0, pattern<ControlPoint>(200.0f), "ControlPoint");
  check(1, pattern<CurveInfo>(300.0f), "CurveInfo");
  check(2, pattern<SegmentRef>(400.0f), "SegmentRef");
  check(3, pattern<FrameNormal>(500.0f), "FrameNormal");
  check(4, pattern<FiberCoord>(600.0f), "FiberCoord");
  check(5, pattern<FiberVertex>(700.0f), "FiberVertex");
  check(6, pattern<SegmentDecision>(800.0f), "SegmentDecision");
  check(7, pattern<DrawElementsCommand>(900.0f), "DrawElementsCommand");
  check(8, pattern<YarnSample>(1000.0f), "YarnSample");
  check(9, pattern<KnitStitchGpu>(1100.0f), "KnitStitchGpu");
  check(10, pattern<KnitEnergyGpu>(1300.0f), "KnitEnergyGpu");
  expectSameBytes(knit, readBuffer<KnitSolveParams>(knitCopy.id(), 1)[0], "KnitSolveParams (uniform block)");
  expectSameBytes(shading, readBuffer<ShadingParams>(shadingCopy.id(), 1)[0], "ShadingParams (uniform block)");
  expectSameBytes(core, readBuffer<CoreTextureParams>(coreCopy.id(), 1)[0], "CoreTextureParams (uniform block)");

  // std140 uniform → std430 storage copy: both layouts equal the C++ one for these structs.
  std::vector<YarnParams> yarnBack = readBuffer<YarnParams>(copy.id(), 1);
  std::vector<ViewParams> viewBack = readBuffer<ViewParams>(copy.id(), 1, sizeof(YarnParams));
  expectSameBytes(yarn, yarnBack[0], "YarnParams (uniform block)");
  expectSameBytes(view, viewBack[0], "ViewParams (uniform block)");
}

}  // namespace
}  // namespace ft
