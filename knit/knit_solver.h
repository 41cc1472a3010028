// knit_solver.h — the C++ instances of common/knit_solver.h: ft::knit64
// (double, the CPU reference) and ft::knit32 (float, the GPU's arithmetic on
// the CPU, for telling precision from algorithm when the two sides differ).
#pragma once
#include <glm/glm.hpp>

#include "common/prelude.h"

namespace ft::knit64 {
typedef double kreal;
typedef glm::dvec2 kvec2;
typedef glm::dvec3 kvec3;
typedef glm::dvec4 kvec4;
#define KR(x) kreal(x)
#include "common/knit_solver.h"  // NOLINT(bugprone-suspicious-include): precision-generic body
#undef KR
}  // namespace ft::knit64

namespace ft::knit32 {
typedef float kreal;
typedef glm::vec2 kvec2;
typedef glm::vec3 kvec3;
typedef glm::vec4 kvec4;
#define KR(x) kreal(x)
#include "common/knit_solver.h"  // NOLINT(bugprone-suspicious-include)
#undef KR
}  // namespace ft::knit32
