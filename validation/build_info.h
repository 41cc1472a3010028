// build_info.h — what `fibertwin --version` and the report say about the
// build: the CMake project() version and the git commit HEAD was at when CMake
// configured (validation/CMakeLists.txt re-configures when HEAD moves).
#pragma once
#include <string>

namespace ft {

const char* buildVersion();  // e.g. "0.1.0"
const char* buildCommit();   // abbreviated hash, or "unknown" outside a git checkout
std::string versionLine();   // "fibertwin 0.1.0 (commit 0123456789ab)"

}  // namespace ft
