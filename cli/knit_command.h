// knit_command.h — `fibertwin knit`: stitch mesh (file, frames or built-in
// patch) + deformation → knot-based optimized yarn curves (BCC) and, unless
// switched off, the shaded frame of `render` (or image sequence: EXR + PNG),
// optionally each frame's path-traced all-fiber reference
// (docs/knit-rendering.md).
#pragma once
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "cli/render_command.h"
#include "gpu/gl_context.h"
#include "knit/knit_problem.h"
#include "scene/yarn_fibers.h"

namespace ft {

struct KnitCommandOptions {
  std::vector<std::filesystem::path> meshes;  // none: built-in; one: rest state; several: frames
  std::string pattern = "stockinette";        // built-in: stockinette or ribbing
  int rows = 20, cols = 20;
  std::string deformation = "stretch-course=1.4";
  int frames = 1;                             // > 1: animate the deformation from rest
  std::string solver = "gpu";                 // gpu or cpu
  KnitOptions knit;
  std::filesystem::path bcc = "knit.bcc";
  std::filesystem::path image = "knit.exr";   // empty: no image; .exr: EXR + PNG beside it; .png: PNG only
  bool preview = false;                       // the old preview style (PNG) instead of the shaded frame
  std::string path = "compute";               // compute or tessellation
  bool occlusionCull = true;
  Lighting lighting;                          // as `render` (--fabric, --light, ...)
  DisplayMapping display;                     // PNG: --exposure, --tonemap
  AppearanceOptions appearance;               // 000 §4's approximations, as `render`
  std::filesystem::path reference;            // empty: none; else each frame's path-traced all-fiber reference
  TraceSettings trace;                        // how the reference is traced (--spp, --multiple-scattering, ...)
  int width = 1280, height = 960;
  std::string yarn = "cotton1";
  std::vector<std::string> presetOverrides;    // --set name=value over the yarn preset
  FiberOptions fiber;
  GlBackend backend = GlBackend::Auto;
};

// Returns the process exit status; throws InputError for bad input.
int runKnitCommand(const KnitCommandOptions& options, std::ostream& log);

// "<stem>_<index, 3 digits><ext>" for frame sequences.
std::filesystem::path frameFileName(const std::filesystem::path& path, int index);

}  // namespace ft
