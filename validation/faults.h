// faults.h — realistic shader bugs that `--inject` builds into the GPU side
// (as preprocessor defines of the shared headers / shaders). Each must make
// at least one validation case fail; tests/fault_injection_test.cpp checks it.
#pragma once
#include <string_view>

namespace ft {

struct Fault {
  const char* name;         // --inject value
  const char* define;       // preprocessor symbol seen by the shaders
  const char* description;
  const char* caughtBy;     // metric expected to fail
};

inline constexpr Fault kFaults[] = {
    {"ply-angle-sign", "FT_FAULT_PLY_ANGLE_SIGN", "ply twist angle sign flipped (common/fiber_geometry.h)",
     "position.max_abs"},
    {"ellipse-swap", "FT_FAULT_ELLIPSE_SWAP", "ply ellipse axes e_N and e_B swapped", "position.max_abs"},
    {"fiber-index", "FT_FAULT_FIBER_INDEX", "fiber table read one row off (gpu/shaders/fiber_resources.glsl)",
     "position.max_abs"},
    {"length-ignored", "FT_FAULT_LENGTH_IGNORED", "length coordinate ignored: twist restarts every segment",
     "position.max_abs"},
    {"lod-inverted", "FT_FAULT_LOD_INVERTED", "LoD comparison of eq. 4 inverted", "decisions.mismatched"},
    {"hair-period", "FT_FAULT_HAIR_PERIOD", "random draw keyed by the wrong period: hair/loop periods misassigned",
     "ids.mismatched"},
    {"cull-margin", "FT_FAULT_CULL_MARGIN", "frustum test forgets the fibers' reach beyond the yarn axis",
     "decisions.mismatched"},
    {"rmf-one-reflection", "FT_FAULT_RMF_ONE_REFLECTION",
     "frame propagation skips the second reflection of the double-reflection method (common/yarn_frame.h)",
     "normal.max_angle"},
};

inline const Fault* findFault(std::string_view name) {
  for (const Fault& f : kFaults)
    if (name == f.name) return &f;
  return nullptr;
}

}  // namespace ft
