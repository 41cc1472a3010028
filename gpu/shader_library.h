// shader_library.h — the shaders and common/ headers embedded at build time,
// #include resolution, and program building with errors mapped back to the
// original file and line.
//
// Names: "shaders/<file>" for gpu/shaders/*.glsl, "common/<file>" for common/*.h.
// Lookups also accept "gpu/shaders/<file>" and, for stage files, a bare "<file>".
#pragma once
#include <epoxy/gl.h>

#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ft {

struct ShaderSource {
  std::string name;
  std::string text;
};

// A compile or link failure; what() names the stage file, the defines and the
// driver log with every "<source id>:<line>" replaced by "<file>:<line>".
class ShaderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::optional<ShaderSource> findShaderSource(std::string_view name);
// Every known name (embedded and registered), in id order.
std::vector<std::string> shaderSourceNames();
// The GLSL source-string number used in #line for this file (>= 1; 0 is the
// preamble), or -1 when unknown.
int shaderSourceId(std::string_view name);

// Adds (or replaces) an in-memory source, e.g. a deliberately broken shader in a test.
void registerShaderSourceForTest(std::string name, std::string text);

// GL stage enum from the suffix (.vert.glsl .tesc.glsl .tese.glsl .geom.glsl
// .frag.glsl .comp.glsl); 0 when there is none.
GLenum shaderStageFromName(std::string_view file);
// glslangValidator's stage name for the same suffixes ("comp", ...); "" when none.
const char* shaderStageShortName(std::string_view file);

// Complete shader text: "#version 450 core", a #define per entry ("NAME",
// "NAME VALUE" or "NAME=VALUE"), the #extension lines hoisted from the sources,
// common/prelude.h, then `file` with every #include "..." expanded once
// (relative to the including file, else from the repository root). Includes in
// branches that are certainly inactive (#ifdef __cplusplus, undefined FT_FAULT_*)
// are dropped. Every file gets `#line <id * 100000 + line> <id>` (id from
// shaderSourceId): Mesa drops the source number from most errors, so the id is in
// the line number too; mapShaderLog decodes it.
// Throws ShaderError for an unknown file or include.
std::string resolveShader(std::string_view file, const std::vector<std::string>& defines);

// Rewrites a driver or glslang log: Mesa "0:300012(5): error: x", NVIDIA
// "3(300012) : error x" and glslang "ERROR: 3:300012: x" (file id 3, line 12) become
// "common/lod.h:12:5: error: x", "common/lod.h:12: error x" and
// "ERROR: common/lod.h:12: x". Other lines pass unchanged.
std::string mapShaderLog(std::string_view log);

// Compiles and links one program from stage files (resolved as above). With
// xfbVaryings, glTransformFeedbackVaryings is set before linking. Returns the
// program name (wrap it in ft::Program); throws ShaderError on failure.
GLuint buildProgram(const std::vector<std::string>& stageFiles, const std::vector<std::string>& defines,
                    const std::vector<std::string>& xfbVaryings = {},
                    GLenum xfbMode = GL_INTERLEAVED_ATTRIBS);

}  // namespace ft
