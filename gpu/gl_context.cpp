#include "gpu/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <vector>

#ifdef FT_WITH_OSMESA
#include <GL/osmesa.h>  // after epoxy/gl.h: its GL/gl.h include is then a no-op
#endif

namespace ft {
namespace {

bool debugRequested() {
  const char* v = std::getenv("FT_GL_DEBUG");
  if (v && *v) return std::atoi(v) != 0;
#ifdef NDEBUG
  return false;
#else
  return true;
#endif
}

bool hasToken(const char* list, const char* token) {
  if (!list) return false;
  std::size_t n = std::strlen(token);
  for (const char* p = list; (p = std::strstr(p, token)) != nullptr; p += n) {
    bool startOk = p == list || p[-1] == ' ';
    bool endOk = p[n] == '\0' || p[n] == ' ';
    if (startOk && endOk) return true;
  }
  return false;
}

std::string containsSoftwareName(const std::string& renderer) {
  for (const char* name : {"llvmpipe", "softpipe", "swrast", "lavapipe", "Software Rasterizer"})
    if (renderer.find(name) != std::string::npos) return name;
  return {};
}

// ---------------------------------------------------------------------------------------------------
// EGL

const char* eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    case EGL_BAD_DEVICE_EXT: return "EGL_BAD_DEVICE_EXT";
    default: return "unknown EGL error";
  }
}

[[noreturn]] void throwEgl(const std::string& step) {
  EGLint e = eglGetError();
  std::ostringstream s;
  s << "EGL: " << step << " failed: " << eglErrorName(e) << " (0x" << std::hex << e << ")";
  throw std::runtime_error(s.str());
}

struct EglClient {
  const char* extensions = nullptr;  // client extensions (EGL_NO_DISPLAY), may be null
  PFNEGLGETPLATFORMDISPLAYEXTPROC getPlatformDisplay = nullptr;
  PFNEGLQUERYDEVICESEXTPROC queryDevices = nullptr;
  PFNEGLQUERYDEVICESTRINGEXTPROC queryDeviceString = nullptr;

  static const EglClient& get() {
    static const EglClient client = [] {
      EglClient c;
      c.extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
      if (!c.extensions) eglGetError();  // EGL_BAD_DISPLAY without EGL_EXT_client_extensions
      if (hasToken(c.extensions, "EGL_EXT_platform_base"))
        c.getPlatformDisplay =
            reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
      if (hasToken(c.extensions, "EGL_EXT_device_enumeration") ||
          hasToken(c.extensions, "EGL_EXT_device_base"))
        c.queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
      if (hasToken(c.extensions, "EGL_EXT_device_query") || hasToken(c.extensions, "EGL_EXT_device_base"))
        c.queryDeviceString =
            reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
      return c;
    }();
    return client;
  }
  bool has(const char* ext) const { return hasToken(extensions, ext); }
};

// eglInitialize is not reference counted and eglTerminate kills every context on
// the display, and eglGetPlatformDisplay returns the same display for the same
// arguments: count users ourselves so two GlContexts can coexist.
std::mutex gDisplayMutex;
std::map<EGLDisplay, int> gDisplayUsers;

void acquireDisplay(EGLDisplay dpy, const std::string& what) {
  std::lock_guard lock(gDisplayMutex);
  if (gDisplayUsers[dpy]++ > 0) return;
  EGLint major = 0, minor = 0;
  if (!eglInitialize(dpy, &major, &minor)) {
    gDisplayUsers.erase(dpy);
    throwEgl("eglInitialize(" + what + ")");
  }
}

void releaseDisplay(EGLDisplay dpy) {
  std::lock_guard lock(gDisplayMutex);
  if (--gDisplayUsers[dpy] > 0) return;
  gDisplayUsers.erase(dpy);
  eglTerminate(dpy);
}

class EglContext final : public GlContext {
 public:
  // Takes a display from eglGetPlatformDisplayEXT; `what` names it in errors.
  EglContext(GlBackend backend, EGLDisplay dpy, const std::string& what) : GlContext(backend), dpy_(dpy) {
    acquireDisplay(dpy_, what);
    try {
      create(what);
    } catch (...) {
      destroy();
      throw;
    }
  }
  ~EglContext() override { destroy(); }

  void makeCurrent() override {
    if (!eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_)) throwEgl("eglMakeCurrent");
  }

 private:
  void create(const std::string& what) {
    const char* ext = eglQueryString(dpy_, EGL_EXTENSIONS);
    if (!ext) throwEgl("eglQueryString(EGL_EXTENSIONS) on " + what);
    if (!hasToken(ext, "EGL_KHR_surfaceless_context"))
      throw std::runtime_error("EGL: " + what + " lacks EGL_KHR_surfaceless_context");
    if (!hasToken(ext, "EGL_KHR_create_context"))
      throw std::runtime_error("EGL: " + what +
                               " lacks EGL_KHR_create_context (needed for a 4.5 core context)");
    if (!eglBindAPI(EGL_OPENGL_API)) throwEgl("eglBindAPI(EGL_OPENGL_API) on " + what);

    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasToken(ext, "EGL_KHR_no_config_context") && !hasToken(ext, "EGL_MESA_configless_context")) {
      const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint count = 0;
      if (!eglChooseConfig(dpy_, attribs, &config, 1, &count)) throwEgl("eglChooseConfig on " + what);
      if (count == 0) throw std::runtime_error("EGL: no OpenGL-renderable config on " + what);
    }
    bool debug = debugRequested();
    const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION_KHR,
                                     4,
                                     EGL_CONTEXT_MINOR_VERSION_KHR,
                                     5,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR,
                                     EGL_CONTEXT_FLAGS_KHR,
                                     debug ? EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR : 0,
                                     EGL_NONE};
    ctx_ = eglCreateContext(dpy_, config, EGL_NO_CONTEXT, contextAttribs);
    if (ctx_ == EGL_NO_CONTEXT) throwEgl("eglCreateContext(OpenGL 4.5 core) on " + what);
    if (!eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_))
      throwEgl("eglMakeCurrent(no surface) on " + what);
    initializeCurrent(backend() == GlBackend::EglDevice ? "egl-device" : "egl-surfaceless", debug);
  }

  void destroy() {
    if (ctx_ != EGL_NO_CONTEXT) {
      if (eglGetCurrentContext() == ctx_)
        eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(dpy_, ctx_);
      ctx_ = EGL_NO_CONTEXT;
    }
    if (dpy_ != EGL_NO_DISPLAY) {
      releaseDisplay(dpy_);
      dpy_ = EGL_NO_DISPLAY;
    }
  }

  EGLDisplay dpy_;
  EGLContext ctx_ = EGL_NO_CONTEXT;
};

std::unique_ptr<GlContext> createSurfaceless() {
  const EglClient& egl = EglClient::get();
  if (!egl.has("EGL_MESA_platform_surfaceless") || !egl.getPlatformDisplay)
    throw std::runtime_error(
        "EGL: client extensions lack EGL_MESA_platform_surfaceless / EGL_EXT_platform_base");
  EGLDisplay dpy = egl.getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (dpy == EGL_NO_DISPLAY) throwEgl("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
  return std::make_unique<EglContext>(GlBackend::EglSurfaceless, dpy, "the surfaceless display");
}

std::vector<EGLDeviceEXT> eglDevices() {
  const EglClient& egl = EglClient::get();
  if (!egl.queryDevices || !egl.getPlatformDisplay || !egl.has("EGL_EXT_platform_device"))
    throw std::runtime_error(
        "EGL: client extensions lack EGL_EXT_device_enumeration / EGL_EXT_platform_device");
  EGLint count = 0;
  if (!egl.queryDevices(0, nullptr, &count)) throwEgl("eglQueryDevicesEXT(count)");
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
  if (count > 0 && !egl.queryDevices(count, devices.data(), &count)) throwEgl("eglQueryDevicesEXT");
  devices.resize(static_cast<std::size_t>(count));
  return devices;
}

bool isSoftwareDevice(EGLDeviceEXT device) {
  const EglClient& egl = EglClient::get();
  if (!egl.queryDeviceString) return false;
  const char* ext = egl.queryDeviceString(device, EGL_EXTENSIONS);
  if (!ext) eglGetError();
  return hasToken(ext, "EGL_MESA_device_software");
}

// The first device (optionally: the first hardware device) that gives a 4.5 core context.
std::unique_ptr<GlContext> createDevice(bool hardwareOnly, std::string& errors) {
  std::vector<EGLDeviceEXT> devices = eglDevices();
  for (std::size_t i = 0; i < devices.size(); ++i) {
    if (hardwareOnly && isSoftwareDevice(devices[i])) continue;
    std::string what = "EGL device " + std::to_string(i);
    try {
      EGLDisplay dpy = EglClient::get().getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
      if (dpy == EGL_NO_DISPLAY)
        throwEgl("eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device " + std::to_string(i) + ")");
      auto ctx = std::make_unique<EglContext>(GlBackend::EglDevice, dpy, what);
      if (hardwareOnly && ctx->info().isSoftware) {
        errors += "\n  " + what + ": software renderer " + ctx->info().renderer;
        continue;
      }
      return ctx;
    } catch (const std::exception& e) { errors += "\n  " + what + ": " + e.what(); }
  }
  if (devices.empty()) errors += "\n  eglQueryDevicesEXT found no devices";
  return nullptr;
}

// ---------------------------------------------------------------------------------------------------
// OSMesa

#ifdef FT_WITH_OSMESA

// libepoxy cannot resolve GL functions for an OSMesa context (it asks GLX or EGL),
// so the OSMesa backend overwrites epoxy's global dispatch pointers with
// OSMesaGetProcAddress results for every function in gl_functions.inc, and puts
// the previous values back when the last OSMesa context goes away.
using GlProc = void (*)();
struct GlFunctionSlot {
  const char* name;
  GlProc (*get)();
  void (*set)(GlProc);
};
const GlFunctionSlot kGlFunctionSlots[] = {
#define FT_GL_FUNCTION(name)                                     \
  {#name, [] { return reinterpret_cast<GlProc>(epoxy_##name); }, \
   [](GlProc p) { epoxy_##name = reinterpret_cast<decltype(epoxy_##name)>(p); }},
#include "gpu/gl_functions.inc"
#undef FT_GL_FUNCTION
};

std::mutex gOsMesaMutex;
int gOsMesaUsers = 0;
std::vector<GlProc> gSavedPointers;

void installOsMesaDispatch() {
  std::lock_guard lock(gOsMesaMutex);
  if (gOsMesaUsers++ > 0) return;
  std::vector<GlProc> resolved;
  std::string missing;
  for (const GlFunctionSlot& slot : kGlFunctionSlots) {
    GlProc p = OSMesaGetProcAddress(slot.name);
    if (!p) missing += std::string(" ") + slot.name;
    resolved.push_back(p);
  }
  if (!missing.empty()) {
    --gOsMesaUsers;
    throw std::runtime_error("OSMesa: OSMesaGetProcAddress returned null for:" + missing);
  }
  gSavedPointers.clear();
  for (std::size_t i = 0; i < std::size(kGlFunctionSlots); ++i) {
    gSavedPointers.push_back(kGlFunctionSlots[i].get());
    kGlFunctionSlots[i].set(resolved[i]);
  }
}

void restoreEpoxyDispatch() {
  std::lock_guard lock(gOsMesaMutex);
  if (--gOsMesaUsers > 0) return;
  for (std::size_t i = 0; i < std::size(kGlFunctionSlots); ++i) kGlFunctionSlots[i].set(gSavedPointers[i]);
}

class OsMesaContext final : public GlContext {
 public:
  OsMesaContext() : GlContext(GlBackend::OSMesa), buffer_(kSize * kSize * 4) {
    bool debug = debugRequested();
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_STENCIL_BITS,
                           8,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           4,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           5,
                           0};
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx_) throw std::runtime_error("OSMesa: OSMesaCreateContextAttribs(OpenGL 4.5 core) failed");
    try {
      makeCurrent();
      installOsMesaDispatch();
      dispatchInstalled_ = true;
      initializeCurrent("osmesa", debug);
    } catch (...) {
      destroy();
      throw;
    }
  }
  ~OsMesaContext() override { destroy(); }

  void makeCurrent() override {
    // A small default framebuffer: OSMesa needs one; the project renders into FBOs.
    if (!OSMesaMakeCurrent(ctx_, buffer_.data(), GL_UNSIGNED_BYTE, kSize, kSize))
      throw std::runtime_error("OSMesa: OSMesaMakeCurrent failed");
  }

 private:
  static constexpr int kSize = 16;
  void destroy() {
    if (dispatchInstalled_) restoreEpoxyDispatch();
    dispatchInstalled_ = false;
    if (ctx_) {
      if (OSMesaGetCurrentContext() == ctx_) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
      OSMesaDestroyContext(ctx_);
      ctx_ = nullptr;
    }
  }

  OSMesaContext ctx_ = nullptr;
  std::vector<unsigned char> buffer_;
  bool dispatchInstalled_ = false;
};

std::unique_ptr<GlContext> createOsMesa() { return std::make_unique<OsMesaContext>(); }

#else

std::unique_ptr<GlContext> createOsMesa() {
  throw std::runtime_error("OSMesa backend not built (configure with FT_WITH_OSMESA=ON and libosmesa6-dev)");
}

#endif

}  // namespace

// -----------------------------------------------------------------------------------------------------

std::optional<GlBackend> parseGlBackend(std::string_view name) {
  if (name == "auto") return GlBackend::Auto;
  if (name == "surfaceless") return GlBackend::EglSurfaceless;
  if (name == "device") return GlBackend::EglDevice;
  if (name == "osmesa") return GlBackend::OSMesa;
  return std::nullopt;
}

const char* glBackendName(GlBackend backend) {
  switch (backend) {
    case GlBackend::Auto: return "auto";
    case GlBackend::EglSurfaceless: return "surfaceless";
    case GlBackend::EglDevice: return "device";
    case GlBackend::OSMesa: return "osmesa";
  }
  return "?";
}

GlBackend glBackendFromEnv() {
  const char* v = std::getenv("FT_GL_BACKEND");
  if (!v || !*v) return GlBackend::Auto;
  if (auto b = parseGlBackend(v)) return *b;
  throw std::runtime_error(std::string("FT_GL_BACKEND=") + v +
                           ": expected auto, surfaceless, device or osmesa");
}

bool hasGlExtension(const char* name) {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    const char* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
    if (e && std::strcmp(e, name) == 0) return true;
  }
  return false;
}

void GlContext::initializeCurrent(const char* backendName, bool debug) {
  auto str = [](GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
  };
  GlInfo& i = info_;
  i.backend = backendName;
  i.vendor = str(GL_VENDOR);
  i.renderer = str(GL_RENDERER);
  i.version = str(GL_VERSION);
  i.glslVersion = str(GL_SHADING_LANGUAGE_VERSION);
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 45)
    throw std::runtime_error(std::string(backendName) + ": got OpenGL " + i.version + " (" + i.renderer +
                             "), need 4.5 core");
  glGetIntegerv(GL_MAX_TESS_GEN_LEVEL, &i.maxTessGenLevel);
  for (GLuint k = 0; k < 3; ++k) {
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, k, &i.maxComputeWorkGroupCount[k]);
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_SIZE, k, &i.maxComputeWorkGroupSize[k]);
  }
  glGetIntegerv(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, &i.maxComputeInvocations);
  glGetIntegerv(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, &i.maxComputeSharedMemorySize);
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &i.maxShaderStorageBufferBindings);
  i.isSoftware = !containsSoftwareName(i.renderer).empty();
  // llvmpipe builds GL_TIME_ELAPSED from CPU timestamps (~1 ns for an empty query).
  i.timerQueriesMeaningful = !i.isSoftware;
  if (debug) {
    enableGlDebugOutput();
    i.debugOutput = true;
  }
  glCheck("GlContext initialization");
}

std::unique_ptr<GlContext> GlContext::create(GlBackend backend) {
  switch (backend) {
    case GlBackend::EglSurfaceless: return createSurfaceless();
    case GlBackend::EglDevice: {
      std::string errors;
      if (auto ctx = createDevice(false, errors)) return ctx;
      throw std::runtime_error("EGL device backend: no device gave an OpenGL 4.5 core context:" + errors);
    }
    case GlBackend::OSMesa: return createOsMesa();
    case GlBackend::Auto: break;
  }
  // Auto: hardware first. On a machine with both Mesa and a vendor driver (glvnd),
  // surfaceless may be llvmpipe even though a GPU exists, so try hardware devices first.
  std::string errors;
  const EglClient& egl = EglClient::get();
  bool haveDevices = egl.queryDevices && egl.has("EGL_EXT_platform_device");
  if (haveDevices) {
    try {
      if (auto ctx = createDevice(true, errors)) return ctx;
    } catch (const std::exception& e) { errors += std::string("\n  ") + e.what(); }
  }
  try {
    return createSurfaceless();
  } catch (const std::exception& e) { errors += std::string("\n  surfaceless: ") + e.what(); }
  if (haveDevices) {
    try {
      if (auto ctx = createDevice(false, errors)) return ctx;
    } catch (const std::exception& e) { errors += std::string("\n  ") + e.what(); }
  }
#ifdef FT_WITH_OSMESA
  try {
    return createOsMesa();
  } catch (const std::exception& e) { errors += std::string("\n  osmesa: ") + e.what(); }
#endif
  throw std::runtime_error("GlContext: no backend gave an OpenGL 4.5 core context:" + errors);
}

}  // namespace ft
