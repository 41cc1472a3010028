// compute_dispatch.h — what every compute kernel's host code does: set
// uniforms by name, and run a program over a flat range of items. A range
// larger than 65,535 groups fills x rows of 65,535 groups, then y; the shader
// recovers the item index from `groupsX` (shaders/flat_dispatch.glsl).
#pragma once
#include <epoxy/gl.h>

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>

namespace ft {

// Uniforms a program does not have (optimised out) are skipped.
void setUniform(GLuint program, const char* name, uint32_t value);
void setUniform(GLuint program, const char* name, float value);
void setUniform(GLuint program, const char* name, glm::vec2 value);
void setUniform(GLuint program, const char* name, glm::vec3 value);
void setUniform(GLuint program, const char* name, glm::uvec2 value);

// Uses `program`, sets `groupsX` and `itemCount`, dispatches ⌈items/groupSize⌉
// groups, checks GL errors (naming `what`) and puts up a barrier for storage
// buffers and read-backs. std::runtime_error naming `what` when the groups
// exceed maxGroupsY rows. No items: nothing.
void dispatchFlat(GLuint program, size_t items, uint32_t groupSize, int maxGroupsY, const char* what);

}  // namespace ft
