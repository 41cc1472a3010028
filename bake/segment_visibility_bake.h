// segment_visibility_bake.h — the file `fibertwin bake segment-visibility`
// writes (bake/segment_visibility_bake.cpp, docs/segment-visibility.md "File"):
// one JSON header line, then little-endian sections:
//   segments  S × 32 bytes: float32 a.xyz, b.xyz, radius; uint32 fiber id
//   svf       S × (1 + Q + C) float32: R_k angle, w_k,1..Q, SSDF PCA coefficients 1..C
//   mean      W·H float32: the PCA mean SSDF (radians)
//   basis     C × W·H float32: the principal directions (unit)
//   images    S × ⌈W·H/8⌉ bytes: the binary visibility images, pixel p at
//             byte p/8, bit p%8 (1 = visible), pixel p = y·W + x (common/segment_visibility.h)
#pragma once
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

namespace ft {

inline constexpr const char* kSvfFileFormat = "fibertwin-segment-visibility";

struct SvfFile {
  nlohmann::json header;
  size_t segments = 0;
  int width = 0, height = 0, axes = 0, components = 0;
  std::vector<float> segmentTable;  // S × 7: a.xyz, b.xyz, radius
  std::vector<uint32_t> fiber;      // S
  std::vector<float> angle;         // S
  std::vector<float> weights;       // S × Q
  std::vector<float> coefficients;  // S × C
  std::vector<float> mean;          // W·H
  std::vector<float> basis;         // C × W·H
  std::vector<uint8_t> images;      // S × W·H, 0/1 (unpacked)
};

// Throws InputError naming the file and the field (or byte offset) for
// anything that is not such a file: header, sizes, non-finite values,
// negative weights, a fiber id ≥ the header's "fibers".
SvfFile readSegmentVisibilityFile(const std::filesystem::path& path);

}  // namespace ft
