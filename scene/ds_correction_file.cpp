#include "scene/ds_correction_file.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "scene/input_error.h"

namespace ft {

namespace {

constexpr const char* kFormat = "fibertwin-ds-correction-1";

template <class T>
void writeFloats(std::ofstream& f, const std::vector<T>& v) {
  f.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(T)));
}

}  // namespace

void writeDsCorrection(const std::filesystem::path& path, const DsCorrectionTextures& t, const std::string& settingsJson) {
  nlohmann::ordered_json h;
  h["format"] = kFormat;
  h["size"] = {t.layout.size.x, t.layout.size.y, t.layout.size.z, t.layout.size.w};
  h["period"] = t.layout.yarn.x;
  h["half_width"] = t.layout.yarn.y;
  h["settings"] = nlohmann::json::parse(settingsJson);
  h["mean_xi"] = t.meanXi;
  h["error_uncorrected"] = t.errorUncorrected;
  h["error_corrected"] = t.errorCorrected;
  h["total_error_corrected"] = t.totalCorrected;
  h["arrays"] = "xi_M, xi_N, psi_M, psi_N as float32 rgba, then coverage as float32, little-endian";
  std::ofstream f(path, std::ios::binary);
  if (!f) throw InputError(fmt::format("{}: cannot open for writing", path.string()));
  f << h.dump() << '\n';
  writeFloats(f, t.xiM);
  writeFloats(f, t.xiN);
  writeFloats(f, t.psiM);
  writeFloats(f, t.psiN);
  writeFloats(f, t.coverage);
  if (!f) throw InputError(fmt::format("{}: write failed", path.string()));
}

DsCorrectionTextures readDsCorrection(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(fmt::format("{}: cannot open", path.string()));
  std::string line;
  std::getline(f, line);
  nlohmann::json h;
  try {
    h = nlohmann::json::parse(line);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: header is not JSON ({})", path.string(), e.what()));
  }
  if (h.value("format", "") != kFormat) throw InputError(fmt::format("{}: format is not {}", path.string(), kFormat));
  DsCorrectionTextures t;
  const auto size = h.at("size");
  for (int k = 0; k < 4; ++k) {
    const long v = size.at(k).get<long>();
    if (v < 1 || v > 4096) throw InputError(fmt::format("{}: size[{}] = {} is outside [1, 4096]", path.string(), k, v));
    t.layout.size[k] = uint32_t(v);
  }
  t.layout.yarn = glm::vec4(h.at("period").get<float>(), h.at("half_width").get<float>(), 0.0f, 0.0f);
  const size_t texels = size_t(t.layout.size.x) * t.layout.size.y;
  const auto read = [&](auto& v, size_t n, const char* name) {
    v.resize(n);
    f.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(v[0])));
    if (!f) throw InputError(fmt::format("{}: {} is truncated", path.string(), name));
    const float* p = reinterpret_cast<const float*>(v.data());
    for (size_t k = 0; k < n * sizeof(v[0]) / sizeof(float); ++k)
      if (!std::isfinite(p[k])) throw InputError(fmt::format("{}: {} value {} is not finite", path.string(), name, k));
  };
  read(t.xiM, texels * t.layout.size.z, "xi_M");
  read(t.xiN, texels * t.layout.size.w, "xi_N");
  read(t.psiM, texels * t.layout.size.z, "psi_M");
  read(t.psiN, texels * t.layout.size.w, "psi_N");
  read(t.coverage, texels, "coverage");
  t.meanXi = h.value("mean_xi", std::vector<double>{});
  t.errorUncorrected = h.value("error_uncorrected", std::vector<double>{});
  t.errorCorrected = h.value("error_corrected", std::vector<double>{});
  t.totalCorrected = h.value("total_error_corrected", std::vector<double>{});
  if (h.contains("settings") && h["settings"].is_object()) {
    const auto& s = h["settings"];
    if (s.contains("yarn") && s["yarn"].is_string()) t.yarn = s["yarn"].get<std::string>();
    if (s.contains("fabric") && s["fabric"].is_string()) t.fabric = s["fabric"].get<std::string>();
    if (s.contains("set") && s["set"].is_array())
      for (const auto& x : s["set"])
        if (x.is_string()) t.presetOverrides.push_back(x.get<std::string>());
  }
  return t;
}

}  // namespace ft
