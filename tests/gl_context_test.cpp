// GPU infrastructure: context creation (backend from FT_GL_BACKEND), GlInfo,
// the embedded shader library (#include, defines, error mapping), a compute
// smoke test, and GpuTimer.
#include "gpu/gl_context.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <string>
#include <vector>

#include "common/constants.h"
#include "gpu/gl_objects.h"
#include "gpu/gpu_timer.h"
#include "gpu/shader_library.h"

namespace ft {
namespace {

class GlTest : public ::testing::Test {
 protected:
  void SetUp() override { ctx_ = GlContext::create(glBackendFromEnv()); }
  void TearDown() override { ctx_.reset(); }
  std::unique_ptr<GlContext> ctx_;
};

// Runs smoke.comp.glsl on 0..n-1 and returns the buffer.
std::vector<std::uint32_t> runSmoke(std::size_t n, const std::vector<std::string>& defines) {
  std::vector<std::uint32_t> values(n);
  std::iota(values.begin(), values.end(), 0u);
  Buffer buffer = Buffer::fromVector(values);
  Program program(buildProgram({"shaders/smoke.comp.glsl"}, defines));
  glUseProgram(program.id());
  buffer.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  glDispatchCompute(static_cast<GLuint>((n + FT_WG_GENERATE - 1) / FT_WG_GENERATE), 1, 1);
  glCheck("smoke dispatch");
  return readBuffer<std::uint32_t>(buffer.id(), n);
}

void expectSmoke(const std::vector<std::uint32_t>& out, std::uint32_t add) {
  for (std::size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], i + add) << "element " << i;
}

TEST(GlBackendTest, ParsesNames) {
  EXPECT_EQ(parseGlBackend("auto"), GlBackend::Auto);
  EXPECT_EQ(parseGlBackend("surfaceless"), GlBackend::EglSurfaceless);
  EXPECT_EQ(parseGlBackend("device"), GlBackend::EglDevice);
  EXPECT_EQ(parseGlBackend("osmesa"), GlBackend::OSMesa);
  EXPECT_EQ(parseGlBackend("vulkan"), std::nullopt);
  for (GlBackend b : {GlBackend::Auto, GlBackend::EglSurfaceless, GlBackend::EglDevice, GlBackend::OSMesa})
    EXPECT_EQ(parseGlBackend(glBackendName(b)), b);
}

TEST_F(GlTest, InfoIsPopulated) {
  const GlInfo& info = ctx_->info();
  std::cout << "backend " << info.backend << ", " << info.vendor << " / " << info.renderer << " / "
            << info.version << " / GLSL " << info.glslVersion << ", max tess level " << info.maxTessGenLevel
            << "\n";
  EXPECT_FALSE(info.backend.empty());
  EXPECT_FALSE(info.vendor.empty());
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_FALSE(info.version.empty());
  EXPECT_FALSE(info.glslVersion.empty());
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  EXPECT_GE(major * 10 + minor, 45);
  EXPECT_GE(info.maxTessGenLevel, 32);  // OSMesa reports 32, EGL llvmpipe 64 (spec minimum 64)
  EXPECT_GE(info.maxComputeWorkGroupCount[0], 65535);
  EXPECT_GE(info.maxComputeWorkGroupSize[0], 1024);
  EXPECT_GE(info.maxComputeInvocations, 1024);
  EXPECT_GE(info.maxShaderStorageBufferBindings, 8);
  EXPECT_EQ(info.timerQueriesMeaningful, !info.isSoftware);
  if (info.renderer.find("llvmpipe") != std::string::npos) { EXPECT_TRUE(info.isSoftware); }
  const char* env = std::getenv("FT_GL_BACKEND");
  const std::string requested = env ? env : "";
  if (requested == "osmesa") {
    EXPECT_EQ(info.backend, "osmesa");
  } else if (requested == "surfaceless") {
    EXPECT_EQ(info.backend, "egl-surfaceless");
  } else if (requested == "device") {
    EXPECT_EQ(info.backend, "egl-device");
  }
}

TEST_F(GlTest, SmokeComputeAddsOne) { expectSmoke(runSmoke(1000, {}), 1); }

TEST_F(GlTest, SmokeComputeHonoursDefines) {
  expectSmoke(runSmoke(130, {"FT_SMOKE_ADD 5u"}), 5);
  expectSmoke(runSmoke(130, {"FT_SMOKE_ADD=7u"}), 7);
}

TEST_F(GlTest, GlCheckThrowsOnError) {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1u << 20, 0);  // index far beyond the limit
  EXPECT_THROW(glCheck("bad bind"), GlError);
  EXPECT_NO_THROW(glCheck("after"));  // the error was consumed
}

TEST(ShaderLibraryTest, EmbedsShadersAndCommonHeaders) {
  ASSERT_TRUE(findShaderSource("shaders/smoke.comp.glsl"));
  ASSERT_TRUE(findShaderSource("gpu/shaders/smoke.comp.glsl"));
  ASSERT_TRUE(findShaderSource("smoke.comp.glsl"));
  auto lod = findShaderSource("common/lod.h");
  ASSERT_TRUE(lod);
  EXPECT_NE(lod->text.find("FT_LOD_H"), std::string::npos);
  EXPECT_FALSE(findShaderSource("common/no_such_header.h"));
  EXPECT_GE(shaderSourceId("common/prelude.h"), 1);
  EXPECT_EQ(shaderSourceId("nope.glsl"), -1);
  EXPECT_EQ(shaderStageFromName("shaders/a.tesc.glsl"), static_cast<GLenum>(GL_TESS_CONTROL_SHADER));
  EXPECT_EQ(shaderStageFromName("common/lod.h"), 0u);
  EXPECT_STREQ(shaderStageShortName("x.tese.glsl"), "tese");
}

TEST(ShaderLibraryTest, ResolvesDefinesAndIncludesOnce) {
  registerShaderSourceForTest("shaders/test_once.comp.glsl",
                              "#version 450\n"
                              "#include \"../common/constants.h\"\n"
                              "#include \"common/constants.h\"\n"
                              "#extension GL_ARB_shader_ballot : enable\n"
                              "layout(local_size_x = 1) in;\n"
                              "void main() {}\n");
  std::string text = resolveShader("shaders/test_once.comp.glsl", {"A", "B 2", "C=3"});
  EXPECT_EQ(text.rfind("#version 450 core\n#define A\n#define B 2\n#define C 3\n", 0), 0u) << text;
  auto count = [&](const std::string& needle) {
    std::size_t n = 0;
    for (std::size_t p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("#define FT_CONSTANTS_H"), 1u);
  EXPECT_EQ(count("#define FT_PRELUDE_H"), 1u);
  EXPECT_EQ(count("#version"), 1u);
  // The extension moves above the first declaration (prelude's constants).
  EXPECT_LT(text.find("#extension GL_ARB_shader_ballot"), text.find("const float FT_PI"));
  auto lineDirective = [](const char* file, long line) {
    long id = shaderSourceId(file);
    return "#line " + std::to_string(id * 100000 + line) + " " + std::to_string(id) + "\n";
  };
  EXPECT_NE(text.find(lineDirective("common/constants.h", 1)), std::string::npos);
  EXPECT_NE(text.find(lineDirective("shaders/test_once.comp.glsl", 3)), std::string::npos);
}

TEST(ShaderLibraryTest, UnknownIncludeThrows) {
  registerShaderSourceForTest("shaders/test_missing.comp.glsl", "\n#include \"common/missing.h\"\n");
  try {
    resolveShader("shaders/test_missing.comp.glsl", {});
    FAIL() << "no exception";
  } catch (const ShaderError& e) {
    EXPECT_NE(std::string(e.what()).find("common/missing.h"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("shaders/test_missing.comp.glsl:2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(resolveShader("shaders/none.comp.glsl", {}), ShaderError);
}

TEST(ShaderLibraryTest, MapsDriverLogs) {
  const int lodId = shaderSourceId("common/lod.h");
  const std::string id = std::to_string(lodId), line = std::to_string(lodId * 100000 + 12);
  // Mesa drops the source number in most messages: the line number alone decides.
  EXPECT_EQ(mapShaderLog("0:" + line + "(3): error: x\n"), "common/lod.h:12:3: error: x\n");
  EXPECT_EQ(mapShaderLog(id + ":" + line + "(3): error: x\n"), "common/lod.h:12:3: error: x\n");
  EXPECT_EQ(mapShaderLog(id + "(" + line + ") : error C1008: x\n"), "common/lod.h:12: error C1008: x\n");
  EXPECT_EQ(mapShaderLog("ERROR: " + id + ":" + line + ": 'x' : undeclared\n"),
            "ERROR: common/lod.h:12: 'x' : undeclared\n");
  EXPECT_EQ(mapShaderLog(id + ":12(3): error: x\n"), "common/lod.h:12:3: error: x\n");  // plain #line N id
  EXPECT_EQ(mapShaderLog("0:1(1): error: y\n"), "<preamble>:1:1: error: y\n");
  EXPECT_EQ(mapShaderLog("unrelated line\n"), "unrelated line\n");
}

// Compile errors name the original file and line, through includes, after
// includes, and for headers included from the repository root.
TEST_F(GlTest, CompileErrorNamesOriginalFileAndLine) {
  registerShaderSourceForTest("shaders/test_broken_inc.glsl",
                              "// line 1\n"
                              "// line 2\n"
                              "float brokenHelper() { return undefined_symbol_in_include; }\n");
  registerShaderSourceForTest("shaders/test_broken_a.comp.glsl",
                              "layout(local_size_x = 1) in;\n"
                              "#include \"test_broken_inc.glsl\"\n"
                              "void main() {}\n");
  registerShaderSourceForTest("common/test_ok.h", "#include \"prelude.h\"\nconst float okValue = 1.0f;\n");
  registerShaderSourceForTest("shaders/test_broken_b.comp.glsl",
                              "layout(local_size_x = 1) in;\n"
                              "#include \"common/constants.h\"\n"
                              "#include \"common/test_ok.h\"\n"
                              "void main() {\n"
                              "  float y = okValue + undefined_symbol_in_main;\n"
                              "}\n");
  struct Case {
    const char* file;
    const char* expected;
  };
  for (const Case& c : {Case{"shaders/test_broken_a.comp.glsl", "shaders/test_broken_inc.glsl:3:"},
                        Case{"shaders/test_broken_b.comp.glsl", "shaders/test_broken_b.comp.glsl:5:"}}) {
    try {
      Program p(buildProgram({c.file}, {"FT_SOMETHING 1"}));
      ADD_FAILURE() << c.file << ": no exception";
    } catch (const ShaderError& e) {
      std::string what = e.what();
      EXPECT_NE(what.find(c.expected), std::string::npos) << what;
      EXPECT_NE(what.find(std::string("compiling ") + c.file), std::string::npos) << what;
      EXPECT_NE(what.find("FT_SOMETHING 1"), std::string::npos) << what;
    }
  }
}

TEST_F(GlTest, LinkErrorThrowsShaderError) {
  registerShaderSourceForTest("shaders/test_nomain.comp.glsl",
                              "layout(local_size_x = 1) in;\nvoid helper() {}\n");
  try {
    Program p(buildProgram({"shaders/test_nomain.comp.glsl"}, {}));
    FAIL() << "no exception";
  } catch (const ShaderError& e) {
    EXPECT_NE(std::string(e.what()).find("linking shaders/test_nomain.comp.glsl"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(buildProgram({"common/lod.h"}, {}), ShaderError);  // no stage suffix
}

TEST_F(GlTest, GpuTimerMeasures) {
  GpuTimer timer(ctx_->info());
  EXPECT_STREQ(timer.method(),
               ctx_->info().timerQueriesMeaningful ? "GL_TIME_ELAPSED" : "glFinish+steady_clock");
  timer.begin();
  expectSmoke(runSmoke(4096, {}), 1);
  double ms = timer.endMs();
  EXPECT_GE(ms, 0.0);
  EXPECT_THROW(timer.endMs(), std::logic_error);
  // Both methods work everywhere, even where the query's number means little.
  for (GpuTimer::Method m : {GpuTimer::Method::FinishClock, GpuTimer::Method::TimeElapsedQuery}) {
    GpuTimer t(ctx_->info(), m);
    t.begin();
    glFlush();
    EXPECT_GE(t.endMs(), 0.0) << t.method();
  }
}

#ifdef FT_WITH_OSMESA
// OSMesa regardless of FT_GL_BACKEND: exercises the epoxy dispatch rewrite
// (gl_functions.inc), then an EGL context must work again after it is restored.
TEST(GlOsMesaTest, SmokeComputeThenEglAgain) {
  {
    auto ctx = GlContext::create(GlBackend::OSMesa);
    EXPECT_EQ(ctx->info().backend, "osmesa");
    expectSmoke(runSmoke(1000, {}), 1);
    GpuTimer t(ctx->info(), GpuTimer::Method::TimeElapsedQuery);  // glGetQueryObjectui64v via OSMesa
    t.begin();
    t.endMs();
  }
  if (std::getenv("FT_GL_BACKEND") && std::string(std::getenv("FT_GL_BACKEND")) == "osmesa") return;
  auto ctx = GlContext::create(glBackendFromEnv());
  expectSmoke(runSmoke(100, {}), 1);
}
#endif

}  // namespace
}  // namespace ft
