// prt_multiple_scattering_gpu.h — the GPU twin of local multiple scattering of
// 004 §4.3 and §5.3.1 (common/prt_multiple_scattering.h,
// prt_multiple_scattering.comp.glsl; docs/prt-multiple-scattering.md): the
// tables C_S and C_G baked in float, L̃^multi per query from given A_C
// matrices and tables, and an SH probe (Y and its rotation) for the identity
// checks; the estimator of 004 §4.2c summed over CPU-produced samples
// (prt_ms_accumulate.comp.glsl) and V̄_glo of §5.3.2 (prt_ms_visibility.comp.glsl).
// The IIRTF path tracing stays on the CPU (Embree). Every call uploads,
// dispatches and reads back.
#pragma once
#include <epoxy/gl.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/prt_multiple_scattering.h"
#include "gpu/gl_context.h"
#include "gpu/gl_objects.h"

namespace ft {

struct PrtMsGpuTables {
  int thetaO = FT_MS_THETA_O, lambdaNodes = FT_MS_LAMBDA_NODES;
  std::vector<float> phi;  // [2][θ_i][36] (pass 0)
  std::vector<float> cs;   // [θ_o][36][rgb]
  std::vector<float> cg;   // [λ node][6]
};

class PrtMultipleScatteringGpu {
 public:
  // defines: extra preprocessor symbols (fault injection, validation/faults.h).
  // std::runtime_error when the driver has fewer than FT_UBO_PRT_MS + 1
  // uniform-buffer bindings or FT_SSBO_PRT_MS_TABLES + 1 storage bindings.
  explicit PrtMultipleScatteringGpu(const GlInfo& gl, const std::vector<std::string>& defines = {});

  PrtMsGpuTables tables(const FabricParams& fabric, int thetaINodes = FT_MS_THETA_I_NODES,
                        int phiNodes = FT_MS_PHI_NODES);
  // rgb L̃^multi per query; transfer = cells × kIirtf matrix floats ([cell][ch][j1][j0]);
  // cs = [θ_o][36][rgb] (thetaO rows), cg = [λ][6].
  std::vector<glm::vec3> evaluate(std::span<const PrtMsQuery> queries, std::span<const float> transfer, int bands,
                                  std::span<const float> cs, int thetaO, std::span<const float> cg, int lambdaNodes);
  // Per direction ω and rotation rows (rx, ry; rz = rx × ry): Y(ω) then M(R) Y(ω), 72 floats.
  std::vector<float> shProbe(std::span<const glm::vec3> directions, std::span<const glm::vec3> rx,
                             std::span<const glm::vec3> ry);
  int uniformBufferBindings() const { return uboBindings_; }
  // C_S as float[θ_o][36][4] (rgb, 0) then C_G as float[λ][6]: the layout of FT_SSBO_PRT_MS_TABLES
  // for the per-frame steps (shaders/prt_ms_frame.glsl), here and in the PRT frame renderer.
  static std::vector<float> packFrameTables(std::span<const float> cs, int thetaO, std::span<const float> cg);
  static std::vector<float> packFrameTables(const PrtMsGpuTables& t) { return packFrameTables(t.cs, t.thetaO, t.cg); }
  // V̄_glo (004 §5.3.2): the normalised separable Gaussian filter of a V_glo grid (row-major,
  // width × height, texel side and σ_glo in fabric units), prt_ms_visibility.comp.glsl (its
  // own small program, built on first use). std::invalid_argument for mismatched sizes.
  // The IIRTF estimator of 004 §4.2c accumulated on the GPU over CPU-produced samples (ω0 on the
  // upper hemisphere, ω1 on the sphere, T): A = (1/N) Σ T Y(ω1) Y(ω0)ᵀ / (p(ω0) p(ω1)), [ch][j1][j0]
  // (kIirtf matrix layout), float sums per chunk of FT_MS_ACC_CHUNK samples added in order in double
  // here. prt_ms_accumulate.comp.glsl, its own program built on first use.
  std::vector<double> accumulateIirtf(std::span<const PrtMsSample> samples);
  std::vector<float> vgloFilter(std::span<const float> v, int width, int height, float texel, float sigma);

 private:
  Buffer params(uint32_t mode, uint32_t count, uint32_t bands, uint32_t thetaI, uint32_t phi, uint32_t thetaO,
                uint32_t lambdas, uint32_t cells, const FabricParams& fabric);
  int maxGroupsY_ = 65535;
  int uboBindings_ = 0;
  Program program_;
  Program vgloProgram_;
  Program accumulateProgram_;
  std::vector<std::string> defines_;
};

}  // namespace ft
