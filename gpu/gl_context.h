// gl_context.h — a headless OpenGL 4.5 core context: EGL surfaceless (Mesa),
// EGL device (NVIDIA/AMD headless), or OSMesa (Mesa < 25.1, built with
// FT_WITH_OSMESA). No window, surface or config: render into FBOs.
#pragma once
#include <epoxy/gl.h>

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "gpu/gl_check.h"

namespace ft {

enum class GlBackend { Auto, EglSurfaceless, EglDevice, OSMesa };

// "auto", "surfaceless", "device", "osmesa"; nullopt for anything else.
std::optional<GlBackend> parseGlBackend(std::string_view name);
// The inverse of parseGlBackend: "auto", "surfaceless", ...
const char* glBackendName(GlBackend backend);
// FT_GL_BACKEND, Auto when unset or empty; throws std::runtime_error on an unknown value.
GlBackend glBackendFromEnv();

struct GlInfo {
  std::string backend;      // the backend actually used: "egl-surfaceless", "egl-device", "osmesa"
  std::string vendor;       // GL_VENDOR
  std::string renderer;     // GL_RENDERER
  std::string version;      // GL_VERSION
  std::string glslVersion;  // GL_SHADING_LANGUAGE_VERSION
  int maxTessGenLevel = 0;
  int maxComputeWorkGroupCount[3] = {0, 0, 0};
  int maxComputeWorkGroupSize[3] = {0, 0, 0};
  int maxComputeInvocations = 0;
  int maxComputeSharedMemorySize = 0;
  int maxShaderStorageBufferBindings = 0;
  bool isSoftware = false;              // llvmpipe, softpipe, swrast, lavapipe
  bool timerQueriesMeaningful = false;  // false on software renderers: time with glFinish + clock
  bool debugOutput = false;             // KHR_debug output routed into glCheck
};

class GlContext {
 public:
  // Creates a context and makes it current on the calling thread. Throws
  // std::runtime_error naming the failing step (and the EGL error) otherwise.
  // Auto: an EGL device backed by hardware, else EGL surfaceless, else any
  // EGL device (software), else OSMesa when built in.
  // Debug output is on in builds without NDEBUG, or with FT_GL_DEBUG=1.
  static std::unique_ptr<GlContext> create(GlBackend backend = GlBackend::Auto);

  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes this context current on the calling thread (create() already did).
  virtual void makeCurrent() = 0;
  GlBackend backend() const { return backend_; }
  const GlInfo& info() const { return info_; }

 protected:
  explicit GlContext(GlBackend backend) : backend_(backend) {}
  // Fills info_, checks for 4.5 and turns on debug output; the context must be current.
  void initializeCurrent(const char* backendName, bool debug);

 private:
  GlBackend backend_;
  GlInfo info_;
};

// True when the current context lists the extension (glGetStringi; works under OSMesa,
// unlike epoxy_has_gl_extension).
bool hasGlExtension(const char* name);

}  // namespace ft
