// fidelity_xi.cpp — see fidelity_xi.h.
#include "validation/fidelity_xi.h"

#include <fmt/format.h>

#include <vector>

#include "reference/ds_correction.h"
#include "validation/case_support.h"

namespace ft {

std::filesystem::path fidelityXiFile(ValidationContext& ctx, const YarnPreset& preset, const std::string& fabric) {
  return ctx.cached(CacheKey<std::filesystem::path>{"shading/fidelity-xi/" + preset.name + "/" + fabric}, [&] {
    DsCorrectionSettings st;
    st.yarn = preset.name;
    st.presetOverrides = ctx.options().presetOverrides;
    st.fabric = fabric;
    st.height = 8;
    st.thetaSamples = 4;
    st.phiSamples = 4;
    st.pixelsPerTexel = 2;
    st.samplesPerPixel = 16;
    st.periods = 3;
    const DsCorrectionScene scene(st);
    std::vector<DsDirectionSums> sums;
    for (int d = 0; d < scene.directionCount(); ++d) sums.push_back(scene.trace(d));
    const DsCorrectionTextures t = factorDsCorrection(scene.layout(), sums, 16.0 * 2 * 2);
    const ScratchDirectory& dir = ctx.cached(CacheKey<ScratchDirectory>{"scratch/ds-fidelity"},
                                             [] { return ScratchDirectory("fibertwin-ds-fidelity"); });
    const std::filesystem::path file = dir.path() / (preset.name + "-" + fabric + ".bin");
    writeDsCorrection(file, t, fmt::format(R"({{"yarn": "{}", "fabric": "{}"}})", preset.name, fabric));
    return file;
  });
}

}  // namespace ft
