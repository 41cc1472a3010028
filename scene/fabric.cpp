// fabric.cpp — the fabric-presets table parser (data/fabric-bcsdf.tsv).
#include "scene/fabric.h"

#include <cmath>
#include <map>

#include "scene/input_error.h"
#include "scene/text_fields.h"

extern const char ftEmbeddedFabricPresets[];

namespace ft {

namespace {

constexpr const char* kColumns[] = {"name",    "C_R_r",   "C_R_g",      "C_R_b",       "C_TT_r",
                                    "C_TT_g",  "C_TT_b",  "beta_R_deg", "beta_TT_deg", "gamma_TT_deg"};

}  // namespace

FabricParams FabricPreset::params() const {
  const double rad = M_PI / 180.0;
  const double gamma = gammaTTDegrees * rad;
  FabricParams p{};
  p.colorR = vec4(float(colorR[0]), float(colorR[1]), float(colorR[2]), float(betaRDegrees * rad));
  p.colorTT = vec4(float(colorTT[0]), float(colorTT[1]), float(colorTT[2]), float(betaTTDegrees * rad));
  p.lobes = vec4(float(gamma), float(1.0 / (gamma * gamma)), 0.0f, 0.0f);
  return p;
}

std::vector<FabricPreset> parseFabricPresets(std::string_view text, std::string_view sourceName) {
  const std::string source(sourceName);
  std::vector<FabricPreset> out;
  std::map<std::string, size_t> index;
  size_t lineNo = 0, pos = 0;
  bool header = true;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    const auto fields = splitTabs(line);
    const auto fail = [&](const std::string& what) {
      throw InputError(source + ": line " + std::to_string(lineNo) + ": " + what);
    };
    if (header) {
      for (size_t i = 0; i < fields.size(); ++i)
        if (!index.emplace(std::string(fields[i]), i).second) fail("duplicate column '" + std::string(fields[i]) + "'");
      for (const char* c : kColumns)
        if (!index.count(c)) fail(std::string("missing column '") + c + "'");
      header = false;
      continue;
    }
    if (fields.size() != index.size())
      fail("expected " + std::to_string(index.size()) + " fields, found " + std::to_string(fields.size()));
    FabricPreset f;
    f.name = std::string(fields[index.at("name")]);
    if (f.name.empty()) fail("column 'name' is empty");
    const auto real = [&](const char* column, double lo, double hi, bool openLow) {
      const std::string_view v = fields[index.at(column)];
      const auto x = parseWholeReal(v);
      if (!x || !std::isfinite(*x)) fail(std::string("column '") + column + "': '" + std::string(v) + "' is not a finite number");
      if (*x > hi || *x < lo || (openLow && *x == lo))
        fail(std::string("column '") + column + "': " + std::string(v) + " is outside " + (openLow ? "(" : "[") +
             std::to_string(lo) + ", " + std::to_string(hi) + "]");
      return *x;
    };
    const char* rgb[2][3] = {{"C_R_r", "C_R_g", "C_R_b"}, {"C_TT_r", "C_TT_g", "C_TT_b"}};
    for (int c = 0; c < 3; ++c) {
      f.colorR[c] = real(rgb[0][c], 0.0, 1.0, false);
      f.colorTT[c] = real(rgb[1][c], 0.0, 1.0, false);
    }
    f.betaRDegrees = real("beta_R_deg", 0.0, 90.0, true);
    f.betaTTDegrees = real("beta_TT_deg", 0.0, 90.0, true);
    f.gammaTTDegrees = real("gamma_TT_deg", 0.0, 90.0, true);
    for (const FabricPreset& g : out)
      if (g.name == f.name) fail("duplicate fabric '" + f.name + "'");
    out.push_back(f);
  }
  if (header) throw InputError(source + ": no header row");
  return out;
}

const std::vector<FabricPreset>& builtinFabricPresets() {
  static const std::vector<FabricPreset> presets =
      parseFabricPresets(ftEmbeddedFabricPresets, "built-in fabric-bcsdf.tsv");
  return presets;
}

const FabricPreset& findFabricPreset(std::string_view name) {
  std::string known;
  for (const FabricPreset& f : builtinFabricPresets()) {
    if (f.name == name) return f;
    known += (known.empty() ? "" : ", ") + f.name;
  }
  throw InputError("built-in fabric-bcsdf.tsv: unknown fabric '" + std::string(name) + "' (known: " + known + ")");
}

}  // namespace ft
