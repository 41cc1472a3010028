// faults.h — realistic shader bugs that `--inject` builds into the GPU side
// (as preprocessor defines of the shared headers / shaders). Each must make
// at least one validation case fail; tests/fault_injection_test.cpp checks it.
// The faults themselves are listed once, in validation/faults.def.
#pragma once
#include <string_view>

#include "common/ambient_occlusion.h"
#include "common/bcsdf.h"
#include "common/core_texture.h"
#include "common/ds_correction.h"
#include "common/dual_scattering.h"
#include "common/exemplar_volume.h"
#include "common/fiber_shading.h"
#include "common/flyaway.h"
#include "common/lod.h"
#include "common/pcss.h"
#include "common/prt_multiple_scattering.h"
#include "common/prt_frame.h"
#include "common/prt_single_scattering.h"
#include "common/segment_visibility.h"
#include "common/sh.h"
#include "common/self_shadow.h"
#include "common/shadow_map.h"
#include "common/srbf.h"
#include "common/srbf_bcsdf.h"
#include "common/srbf_lighting.h"
#include "common/yarn_frame.h"
#include "knit/knit_render.h"
#include "reference/ds_correction.h"
#include "reference/flyaway.h"
#include "reference/prt_multiple_scattering.h"
#include "reference/segment_visibility.h"

namespace ft {

struct Fault {
  const char* name;         // --inject value
  const char* define;       // preprocessor symbol seen by the shaders
  const char* description;
  const char* caughtBy;     // metric expected to fail
  const char* paths;        // CaseResult::path values that must each fail a case, comma-separated
  const char* filter;       // the cases that can see it (regex; "" = all), to keep fault runs short
  const char* model;        // BCC (path from the repository root) the fault shows on; nullptr: built-in scene
  bool shared;              // lives in common/: planted on the CPU side too (at run time), not only the GPU's
  bool* cpuSwitch;          // shared: the CPU side's run-time switch, <DEFINE>_ON of its header; else nullptr
};

inline constexpr Fault kFaults[] = {
// A shared fault's header defines <DEFINE>_ON as its C++ switch variable.
#define FT_FAULT_CPU_SWITCH_true(define) &(define##_ON)
#define FT_FAULT_CPU_SWITCH_false(define) nullptr
#define FT_FAULT(name, define, caughtBy, paths, filter, model, shared, description) \
  {name, #define, description, caughtBy, paths, filter, (model)[0] ? (model) : nullptr, shared,       \
   FT_FAULT_CPU_SWITCH_##shared(define)},
#include "validation/faults.def"
#undef FT_FAULT
#undef FT_FAULT_CPU_SWITCH_true
#undef FT_FAULT_CPU_SWITCH_false
};

// Switches a shared fault's CPU side (the GPU side is the define); the
// harness turns it on for its run and off again when the run ends.
inline void setSharedFault(std::string_view define, bool on) {
  for (const Fault& f : kFaults)
    if (f.cpuSwitch && define == f.define) *f.cpuSwitch = on;
}

inline const Fault* findFault(std::string_view name) {
  for (const Fault& f : kFaults)
    if (name == f.name) return &f;
  return nullptr;
}

}  // namespace ft
