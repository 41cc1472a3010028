// case_support.h — small helpers the suite files of the harness used to
// repeat in their anonymous namespaces (validation/*_cases.cpp, the oracles):
// π, the frame cases' image size, the case timer, a count of non-finite
// values, a scratch directory. One definition each, so that the files of ft_validation can be
// compiled together (unity builds, scripts/test.sh). Included by
// validation/*.cpp only; π is std's, not common/'s FT_PI, since an oracle
// shares no code with common/.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <numbers>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

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

// A directory of the run's own under the system's temporary folder, for the
// files a case writes for a reader under test (synthetic ξ bakes), removed
// with its contents when the object goes: keep it in the context's cache
// (ValidationContext::cached) and it lives as long as the run.
class ScratchDirectory {
 public:
  explicit ScratchDirectory(const std::string& stem)
      : path_(std::filesystem::temp_directory_path() / (stem + "-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ignored;  // a destructor must not throw; what is left stays
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace ft
