// faults.h — realistic shader bugs that `--inject` builds into the GPU side
// (as preprocessor defines of the shared headers / shaders). Each must make
// at least one validation case fail; tests/fault_injection_test.cpp checks it.
#pragma once
#include <string_view>

#include "common/yarn_frame.h"

namespace ft {

struct Fault {
  const char* name;         // --inject value
  const char* define;       // preprocessor symbol seen by the shaders
  const char* description;
  const char* caughtBy;     // metric expected to fail
  const char* paths;        // CaseResult::path values that must each fail a case, comma-separated
  const char* filter;       // the cases that can see it (regex; "" = all), to keep fault runs short
  const char* model = nullptr;  // BCC (path from the repository root) the fault shows on; nullptr: built-in scene
  bool shared = false;          // lives in common/: planted on the CPU side too (at run time), not only the GPU's
};

inline constexpr const char* kFiberPaths = "tessellation,compute";

inline constexpr Fault kFaults[] = {
    {"ply-angle-sign", "FT_FAULT_PLY_ANGLE_SIGN", "ply twist angle sign flipped (common/fiber_geometry.h)",
     "position.max_abs", kFiberPaths, "^(fiber|frames)/"},
    {"ellipse-swap", "FT_FAULT_ELLIPSE_SWAP", "ply ellipse axes e_N and e_B swapped", "position.max_abs", kFiberPaths, "^(fiber|frames)/"},
    {"fiber-index", "FT_FAULT_FIBER_INDEX", "fiber table read one row off (gpu/shaders/fiber_resources.glsl)",
     "position.max_abs", kFiberPaths, "^(fiber|frames)/"},
    {"length-ignored", "FT_FAULT_LENGTH_IGNORED", "length coordinate ignored: twist restarts every segment",
     "position.max_abs", kFiberPaths, "^(fiber|frames)/"},
    {"lod-inverted", "FT_FAULT_LOD_INVERTED", "LoD comparison of eq. 4 inverted", "decisions.mismatched", kFiberPaths, "^(fiber|frames)/"},
    {"hair-period", "FT_FAULT_HAIR_PERIOD", "random draw keyed by the wrong period: hair/loop periods misassigned",
     "ids.mismatched", kFiberPaths, "^(fiber|frames)/"},
    {"cull-margin", "FT_FAULT_CULL_MARGIN", "frustum test forgets the fibers' reach beyond the yarn axis",
     "decisions.mismatched", kFiberPaths, "^(fiber|frames)/"},
    {"rmf-one-reflection", "FT_FAULT_RMF_ONE_REFLECTION",
     "frame propagation skips the second reflection of the double-reflection method (common/yarn_frame.h)",
     "normal.max_angle", kFiberPaths, "^(fiber|frames)/"},
    {"knit-jacobian-swap", "FT_FAULT_KNIT_JACOBIAN_SWAP",
     "Gauss-Newton Jacobian columns of theta_L and l_L swapped (common/knit_solver.h)", "points.max_abs", "knit",
     "^knit/"},
    {"knit-length-weight", "FT_FAULT_KNIT_LENGTH_WEIGHT",
     "eq. 6 residual scaled by w_length instead of its square root (common/knit_solver.h)", "points.max_abs", "knit",
     "^knit/"},
    {"knit-constraint-dropped", "FT_FAULT_KNIT_CONSTRAINT_DROPPED",
     "p0/p1 keep the interpolated contact direction: eq. 4 perpendicularity dropped (common/knit_solver.h)",
     "gpu.perpendicularity", "knit", "^knit/"},
    {"knit-coupling-dropped", "FT_FAULT_KNIT_COUPLING_DROPPED",
     "normal equations lose the block that couples the two knots (the angle at the apex; common/knit_solver.h)",
     "points.max_abs", "knit", "^knit/"},
    {"knit-no-safeguard", "FT_FAULT_KNIT_NO_SAFEGUARD",
     "Gauss-Newton steps taken even when they raise eq. 3 (common/knit_solver.h)", "gpu.energy_rises", "knit",
     "^knit/"},
    {"closure-axis", "FT_FAULT_CLOSURE_AXIS",
     "GPU closed-loop frame pass rotates about tangent - tangentIn at every knot: NaN off cusps "
     "(gpu/shaders/yarn_frames.comp.glsl)",
     "nonfinite.gpu", kFiberPaths, "^(fiber|frames)/"},
    {"tangent-fallback", "FT_FAULT_TANGENT_FALLBACK",
     "zero-tangent fallback dropped on both sides: NaN frames after a back-track (common/yarn_frame.h)",
     "nonfinite.cpu", kFiberPaths, "^(fiber|frames)/", "tests/edge_corpus/edges.bcc", true},
};

// Switches a shared fault's CPU side (the GPU side is the define); the
// harness turns it on for its run and off again when the run ends.
inline void setSharedFault(std::string_view define, bool on) {
  if (define == "FT_FAULT_TANGENT_FALLBACK") ftFaultTangentFallback = on;
}

inline const Fault* findFault(std::string_view name) {
  for (const Fault& f : kFaults)
    if (name == f.name) return &f;
  return nullptr;
}

}  // namespace ft
