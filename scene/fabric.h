// fabric.h — the fiber scattering presets of data/fabric-bcsdf.tsv (the
// Khungurn-model fits 000 §4.3 uses; columns C_R, C_TT per RGB channel, β_R,
// β_TT, γ_TT in degrees). Embedded at build time, so `--fabric silk` needs
// no file.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "common/bcsdf.h"

namespace ft {

struct FabricPreset {
  std::string name;
  double colorR[3] = {0, 0, 0};   // C_R per channel, [0, 1]
  double colorTT[3] = {0, 0, 0};  // C_TT per channel, [0, 1]
  double betaRDegrees = 0.0;      // longitudinal width of R
  double betaTTDegrees = 0.0;     // longitudinal width of TT
  double gammaTTDegrees = 0.0;    // azimuthal width of TT (κ = γ^−2, γ in radians)

  FabricParams params() const;    // the std140 block, angles in radians
};

// Parses a fabric table (tab-separated, header row with the column names of
// data/fabric-bcsdf.tsv, any column order). InputError names `sourceName`,
// the line, the column and the value for: missing or duplicate columns, wrong
// field counts, non-numeric or non-finite numbers, colours outside [0, 1],
// lobe widths outside (0, 90] degrees.
std::vector<FabricPreset> parseFabricPresets(std::string_view text, std::string_view sourceName);

// The five fabrics built into the program.
const std::vector<FabricPreset>& builtinFabricPresets();

// By name; InputError lists the known names.
const FabricPreset& findFabricPreset(std::string_view name);

}  // namespace ft
