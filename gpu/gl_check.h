// gl_check.h — GL error checking that throws. glGetError alone says little, so
// when KHR_debug output is on (debug builds, or FT_GL_DEBUG=1) the driver's
// error messages since the last check are appended to the exception text.
#pragma once
#include <epoxy/gl.h>

#include <stdexcept>
#include <string>

namespace ft {

class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "GL_INVALID_OPERATION" etc.; "GL error 0x...." for unknown codes.
std::string glErrorName(GLenum error);

// Throws GlError("<what>: GL_INVALID_VALUE ...") when glGetError reports an
// error or the debug callback recorded one since the last call; clears both.
void glCheck(const char* what);

// Turns on synchronous KHR_debug output routed into glCheck. Called by
// GlContext when debug output is enabled; safe to call on any 4.3+ context.
void enableGlDebugOutput();

}  // namespace ft
