// yarn_preset.h — fitted procedural-yarn parameters (Zhao, Luan & Bala 2016),
// one row of data/yarn-presets.tsv; column meanings in the shared
// reference-data §2. The table is embedded in the program at build time, so
// `--yarn cotton1` needs no file.
#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace ft {

struct NormalParam {
  double mu = 0.0;
  double sigma = 0.0;
};

struct YarnPreset {
  std::string name;
  int plyNum = 0;             // ply_num
  int fiberNum = 0;           // fiber_num (per ply)
  bool yarnClockWise = false; // yarn_clock_wise
  bool fiberClockWise = false;// fiber_clock_wise
  double yarnAlpha = 0.0;     // yarn_alpha: ply twist pitch length
  double alpha = 0.0;         // alpha: fiber twist pitch length
  double yarnRadius = 0.0;    // yarn_radius
  double ellipseLong = 0.0;   // ellipse_long  (e_B)
  double ellipseShort = 0.0;  // ellipse_short (e_N)
  double epsilon = 0.0;       // fiber density p(R) parameters
  double beta = 0.0;
  double rMax = 0.0;          // R_max
  double sI = 0.0;            // s_i: migration rate (s of eq. 2)
  double rhoMin = 0.0;
  double rhoMax = 0.0;
  double hairDensity = 0.0;   // hair fibers per unit length
  NormalParam hairZe, hairR0, hairRe, hairPe;
  double loopDensity = 0.0;   // loop fibers per unit length
  NormalParam loopR1;
};

// Parses a presets table (tab-separated, header row with the column names of
// data/yarn-presets.tsv, any column order). Throws InputError naming
// `sourceName`, the line, the column and the offending value for: missing or
// duplicate columns, wrong field counts, non-numeric or non-finite numbers,
// and out-of-range values (ply_num 1..8, fiber_num 1..4096, pitches/radii > 0,
// 0 <= rho_min <= rho_max, densities and sigmas >= 0, ...).
std::vector<YarnPreset> parseYarnPresets(std::string_view text, std::string_view sourceName);

// The nine presets built into the program (data/yarn-presets.tsv).
const std::vector<YarnPreset>& builtinYarnPresets();

// Looks a built-in preset up by name; InputError lists the known names.
const YarnPreset& findYarnPreset(std::string_view name);

// `base` with columns overridden from "name=value" texts (`--set ply_num=4`;
// the names are the columns of data/yarn-presets.tsv, later ones win), parsed
// and range-checked exactly as parseYarnPresets does, cross-column checks
// included. InputError naming --set, the parameter and the value.
YarnPreset overrideYarnPreset(const YarnPreset& base, const std::vector<std::string>& assignments);

}  // namespace ft
