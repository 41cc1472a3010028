// prt_sweep_command.h — two user commands around the fabric PRT frame of
// Khungurn et al. 2017 (004; reference/prt_frame.h, docs/prt-frame.md):
//   * `fibertwin prt-sweep`: 004 Fig. 13's protocol (§6.3): the flat tiled
//     exemplar under a sweep of views × lights × λ (directional and SG lights)
//     for one or more fabrics, each configuration rendered by the PRT and by
//     the path tracer; per configuration and channel the average intensities,
//     and per fabric the RMSE over the sweep; JSON and CSV.
//   * `fibertwin prt-ms-probe`: noise or bias of multiple scattering on one
//     configuration (docs/prt-multiple-scattering.md, "Noise or bias"):
//     L̃^multi per SH order over several IIRTF seeds, the bake's relative
//     noise per band (its standard errors), and the SH-free estimates at the
//     hit point, the segment midpoint and the cell average.
#pragma once
#include <iosfwd>
#include <string>
#include <vector>

#include "reference/prt_frame.h"

namespace CLI {
class App;
}

namespace ft {

struct PrtSweepCommandOptions {
  PrtFrameSettings frame;
  std::vector<std::string> fabrics{"fleece"};
  int views = 41, lights = 4;             // 41 × 4 × 3 λ = 492 configurations (004 Fig. 13's count)
  std::vector<float> lambdas{0.0f, 30.0f, 150.0f};  // 0: directional
  int limit = 0;                          // > 0: only the first configurations (a reduced sweep)
  double altNoiseCut = -1.0;              // ≥ 0: each configuration's PRT also with this --ms-noise-cut (same path tracing)
  std::string json, csv;
};
CLI::App* addPrtSweepCommand(CLI::App& app, PrtSweepCommandOptions& options);
int runPrtSweepCommand(const PrtSweepCommandOptions& options, std::ostream& out);

struct PrtMsProbeCommandOptions {
  PrtFrameSettings frame;
  std::string view = "0.3,-0.2,0.93", light = "0.5,0.3,0.81";  // docs/prt-frame.md's "back" configuration
  float lambda = 0.0f;
  int seeds = 4;        // IIRTF bakes with seeds seed, seed + 1, ...
  int transferSpp = 64; // samples per pixel of the SH-free estimates
  std::string json;
};
CLI::App* addPrtMsProbeCommand(CLI::App& app, PrtMsProbeCommandOptions& options);
int runPrtMsProbeCommand(const PrtMsProbeCommandOptions& options, std::ostream& out);

// The configurations of `prt-sweep`: views on the cap z ∈ [0.25, 1], lights on z ∈ [0.15, 1]
// (Fibonacci spirals, the lights' turned by 1 radian against the views'), each view with every
// light and λ, in that order.
std::vector<PrtFrameView> prtSweepConfigurations(int views, int lights, const std::vector<float>& lambdas);

}  // namespace ft
