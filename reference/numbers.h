// numbers.h — π in double for the CPU reference's .cpp files (common/'s FT_PI
// is a float, shared with GLSL). One definition, so that the files of a
// library can be compiled together (unity builds, scripts/test.sh).
#pragma once
#include <numbers>

namespace ft {

inline constexpr double kPi = std::numbers::pi;

}  // namespace ft
