// ambient_occlusion_bake.h — the file `fibertwin bake ambient-occlusion`
// writes (bake/ambient_occlusion_bake.cpp, docs/bakes.md): one JSON header
// line, then the n × n AO texels as little-endian float32, texel (i, j) at
// j·n + i (common/ambient_occlusion.h conventions, ψ = 0).
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

namespace ft {

inline constexpr const char* kAoTextureFormat = "fibertwin-ao-texture";

struct AoTextureFile {
  nlohmann::json header;  // format, version, yarn, overrides, resolution, directions, kappa, ..., cubic
  std::vector<float> ao;  // resolution² texels
};

// Throws InputError naming the file for anything that is not such a file.
AoTextureFile readAoTextureFile(const std::filesystem::path& path);

}  // namespace ft
