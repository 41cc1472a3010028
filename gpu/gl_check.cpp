#include "gpu/gl_check.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace ft {
namespace {

// Messages from the debug callback. The callback runs on the thread that made
// the GL call (synchronous output), and must not throw through the driver, so
// it only records; glCheck throws.
thread_local std::string tPendingDebugErrors;
constexpr std::size_t kMaxPending = 16 * 1024;

const char* debugTypeName(GLenum type) {
  switch (type) {
    case GL_DEBUG_TYPE_ERROR: return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined behavior";
    case GL_DEBUG_TYPE_PORTABILITY: return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE: return "performance";
    default: return "other";
  }
}

void GLAPIENTRY debugCallback(GLenum /*source*/, GLenum type, GLuint id, GLenum severity, GLsizei length,
                              const GLchar* message, const void* /*user*/) {
  std::string text(message,
                   length >= 0 ? static_cast<std::size_t>(length) : std::char_traits<char>::length(message));
  if (type == GL_DEBUG_TYPE_ERROR) {
    if (tPendingDebugErrors.size() < kMaxPending) tPendingDebugErrors += "\n  debug: " + text;
    return;
  }
  // Everything else only matters when someone is looking: FT_GL_DEBUG=2.
  static const bool verbose = [] {
    const char* v = std::getenv("FT_GL_DEBUG");
    return v && std::atoi(v) >= 2;
  }();
  if (verbose || severity == GL_DEBUG_SEVERITY_HIGH)
    std::fprintf(stderr, "[gl %s #%u] %s\n", debugTypeName(type), id, text.c_str());
}

}  // namespace

std::string glErrorName(GLenum error) {
  switch (error) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
    default: {
      char buf[32];
      std::snprintf(buf, sizeof buf, "GL error 0x%04X", error);
      return buf;
    }
  }
}

void glCheck(const char* what) {
  std::string errors;
  // glGetError can queue several flags; a lost context repeats forever, hence the cap.
  for (int i = 0; i < 8; ++i) {
    GLenum e = glGetError();
    if (e == GL_NO_ERROR) break;
    errors += (errors.empty() ? "" : ", ") + glErrorName(e);
  }
  if (errors.empty() && tPendingDebugErrors.empty()) return;
  std::string message = std::string(what) + ": " + (errors.empty() ? "GL debug error" : errors);
  message += tPendingDebugErrors;
  tPendingDebugErrors.clear();
  throw GlError(message);
}

void enableGlDebugOutput() {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
  glDebugMessageCallback(debugCallback, nullptr);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
}

}  // namespace ft
