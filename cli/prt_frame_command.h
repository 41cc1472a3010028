// prt_frame_command.h — `fibertwin prt-frame`: the tiled flat exemplar
// rendered by the fabric PRT of Khungurn et al. 2017 (004 §5) and by the
// Embree path tracer with the same fibers, BCSDF, camera and light; writes
// both (EXR + PNG) and prints 004 Fig. 13's average intensities, the images'
// RMSE and FLIP, and the times (docs/prt-frame.md). --gpu: the PRT image by
// the GPU frame (the bakes stay on the CPU), the CPU frame's difference printed.
#pragma once
#include <iosfwd>
#include <string>

#include "reference/prt_frame.h"

namespace CLI {
class App;
}

namespace ft {

struct PrtFrameCommandOptions {
  PrtFrameSettings frame;
  std::string view = "0.3,-0.2,0.93";   // towards the eye (normalised)
  std::string light = "0.5,0.3,0.81";   // towards the light (normalised)
  float lambda = 0.0f;                  // 0: directional, else an SG light
  std::string out = "prt-frame";        // writes <out>_prt.{exr,png}, <out>_pt.{exr,png}
  float exposure = 0.0f;                // PNG exposure in stops
  bool noReference = false;
  std::string volumeIds;                // "" : the settings' default; midpoint | capsule
  bool gpu = false;                     // the PRT image by the GPU frame (gpu/prt_frame_gpu.h PrtFrameRendererGpu)
};

// "x,y,z" → the unit vector; InputError naming the option for anything else or zero.
glm::vec3 parseDirection(const std::string& option, const std::string& text);

CLI::App* addPrtFrameCommand(CLI::App& app, PrtFrameCommandOptions& options);
// Returns the exit status; throws InputError for bad input.
int runPrtFrameCommand(const PrtFrameCommandOptions& options, std::ostream& out);

}  // namespace ft
