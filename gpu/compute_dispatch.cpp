#include "gpu/compute_dispatch.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "gpu/gl_check.h"

namespace ft {

void setUniform(GLuint program, const char* name, uint32_t value) {
  const GLint loc = glGetUniformLocation(program, name);
  if (loc >= 0) glProgramUniform1ui(program, loc, value);
}

void setUniform(GLuint program, const char* name, float value) {
  const GLint loc = glGetUniformLocation(program, name);
  if (loc >= 0) glProgramUniform1f(program, loc, value);
}

void setUniform(GLuint program, const char* name, glm::vec2 value) {
  const GLint loc = glGetUniformLocation(program, name);
  if (loc >= 0) glProgramUniform2f(program, loc, value.x, value.y);
}

void setUniform(GLuint program, const char* name, glm::vec3 value) {
  const GLint loc = glGetUniformLocation(program, name);
  if (loc >= 0) glProgramUniform3f(program, loc, value.x, value.y, value.z);
}

void setUniform(GLuint program, const char* name, glm::uvec2 value) {
  const GLint loc = glGetUniformLocation(program, name);
  if (loc >= 0) glProgramUniform2ui(program, loc, value.x, value.y);
}

void dispatchFlat(GLuint program, size_t items, uint32_t groupSize, int maxGroupsY, const char* what) {
  if (items == 0) return;
  const size_t groups = (items + groupSize - 1) / groupSize;
  const uint32_t groupsX = static_cast<uint32_t>(std::min<size_t>(groups, 65535));
  const size_t groupsY = (groups + groupsX - 1) / groupsX;
  if (groupsY > static_cast<size_t>(maxGroupsY))
    throw std::runtime_error(fmt::format("{}: {} work groups exceed the GL limit", what, groups));
  glUseProgram(program);
  setUniform(program, "groupsX", groupsX);
  setUniform(program, "itemCount", static_cast<uint32_t>(items));
  glDispatchCompute(groupsX, static_cast<GLuint>(groupsY), 1);
  glCheck(what);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

}  // namespace ft
