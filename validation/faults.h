// faults.h — realistic shader bugs that `--inject` builds into the GPU side
// (as preprocessor defines of the shared headers / shaders). Each must make
// at least one validation case fail; tests/fault_injection_test.cpp checks it.
// The faults themselves are listed once, in validation/faults.def.
#pragma once
#include <string_view>

namespace ft {

struct Fault {
  const char* name;         // --inject value
  const char* define;       // preprocessor symbol seen by the shaders
  const char* description;
  const char* caughtBy;     // metric expected to fail
  const char* paths;        // CaseResult::path values that must each fail a case, comma-separated
  const char* filter;       // the cases that can see it (regex; "" = all), to keep fault runs short
};

inline constexpr Fault kFaults[] = {
#define FT_FAULT(name, define, caughtBy, paths, filter, description) {name, #define, description, caughtBy, paths, filter},
#include "validation/faults.def"
#undef FT_FAULT
};

inline const Fault* findFault(std::string_view name) {
  for (const Fault& f : kFaults)
    if (name == f.name) return &f;
  return nullptr;
}

}  // namespace ft
