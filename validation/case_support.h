// case_support.h — small helpers the suite files of the harness used to
// repeat in their anonymous namespaces (validation/*_cases.cpp, the oracles):
// π, the frame cases' image size, the case timer, a count of non-finite
// values. One definition each, so that the files of ft_validation can be
// compiled together (unity builds, scripts/test.sh). Included by
// validation/*.cpp only; π is std's, not common/'s FT_PI, since an oracle
// shares no code with common/.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace ft {

inline constexpr double kPi = std::numbers::pi;

// The image size of the frame cases (shading/, strip/, knit/appearance/ ...):
// large enough for thousands of covered pixels, small enough for CI.
inline constexpr int kFrameWidth = 320, kFrameHeight = 240;

// Milliseconds since t0 (the per-case timings of report.json).
inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// How many values of v are NaN or ±Inf.
template <class T>
uint64_t nonFiniteCount(const std::vector<T>& v) {
  return uint64_t(std::count_if(v.begin(), v.end(), [](T x) { return !std::isfinite(double(x)); }));
}

}  // namespace ft
