// test_data.h — where tests find the repository's data files (data/).
// FT_SOURCE_DIR is set by ctest (cmake/FibertwinModules.cmake); a test run
// from the repository root works without it. A missing file is a failure,
// never a skip: the data ships with the repository.
#pragma once
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace ft::test {

inline std::filesystem::path repoDataFile(const std::string& relative) {
  const char* src = std::getenv("FT_SOURCE_DIR");
  const std::filesystem::path p = std::filesystem::path(src ? src : ".") / "data" / relative;
  if (!std::filesystem::exists(p))
    throw std::runtime_error(p.string() + " not found (run from the repository root or set FT_SOURCE_DIR)");
  return p;
}

inline std::filesystem::path yarnModel(const char* name) { return repoDataFile(std::string("yarn-models/") + name); }

}  // namespace ft::test
