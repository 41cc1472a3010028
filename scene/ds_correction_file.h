// ds_correction_file.h — the file of the dual-scattering correction bake
// (001 §4.3 eq. 9–11; docs/ds-correction.md): the textures of
// common/ds_correction.h with what the bake measured, written by
// `fibertwin bake ds-correction` (reference/ds_correction.h) and read by the
// bake's checks and by the shaded frame (scene/shading_inputs.h: both GPU and
// CPU sides, hence here in scene/).
#pragma once
#include <filesystem>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "common/ds_correction.h"

namespace ft {

// The baked textures (common/ds_correction.h) and what the bake measured.
struct DsCorrectionTextures {
  DsCorrectionLayout layout{};
  std::vector<glm::vec4> xiM, xiN, psiM, psiN;  // rgb per texel, w = 0
  std::vector<float> coverage;                   // per (u, v) texel: fraction of its samples that hit a fiber
  // Per direction d (a · N_φ + b), over the covered texels: the image's ξ
  // (Σ L_* / Σ Ψ̄ ḡ: how far plain dual scattering under- or overestimates
  // the yarn's radiance), and the relative L1 error against L_* of the prediction
  // without correction (Ψ̄ ḡ) and with the factored correction read back
  // through ftXiLookup at the texel centres (the runtime's ξ_M ξ_N Ψ_M Ψ_N ḡ).
  std::vector<double> meanXi, errorUncorrected, errorCorrected;
  // |Σ runtime − Σ L_*| / Σ L_* over the covered texels: the image's total.
  std::vector<double> totalCorrected;
  // From the header's "settings" (empty when absent): what the bake was made for.
  std::string yarn, fabric;
  std::vector<std::string> presetOverrides;  // settings.set
};

// The bake's file: one JSON line (format, layout, settings, the per-direction
// figures), then the five arrays as little-endian float32 (xiM, xiN, psiM,
// psiN as rgba, coverage). Reading checks sizes and finiteness and throws
// InputError naming the file and the field.
void writeDsCorrection(const std::filesystem::path& path, const DsCorrectionTextures& t, const std::string& settingsJson);
DsCorrectionTextures readDsCorrection(const std::filesystem::path& path);

}  // namespace ft
