// bench_flags.h — the benchmark programs' own `--name=value` flags, taken out
// of argv before benchmark::Initialize (which rejects flags it does not know).
#pragma once
#include <cstring>
#include <string>

namespace ft {

// Removes the first `--name=value` from argv and returns true with its value.
inline bool takeFlag(int& argc, char** argv, const char* name, std::string& value) {
  const std::string prefix = std::string("--") + name + "=";
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], prefix.c_str(), prefix.size()) == 0) {
      value = argv[i] + prefix.size();
      for (int j = i; j < argc - 1; ++j) argv[j] = argv[j + 1];
      --argc;
      return true;
    }
  }
  return false;
}

}  // namespace ft
