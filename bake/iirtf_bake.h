// iirtf_bake.h — the file `fibertwin bake iirtf` writes (bake/iirtf_bake.cpp,
// docs/prt-multiple-scattering.md "File"): one JSON header line, then
// little-endian sections:
//   cell_of   S × uint32: the cell of block segment k (its midpoint's)
//   cells     C × (uint32 segments, uint32 paths)
//   transfer  C × 3 × 36 × 36 float32: A_C per cell, [channel][j1][j0]
//             (004 §4.2a's a[j0, j1] at row j1, column j0: c_T = A_C c_d)
#pragma once
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

namespace ft {

inline constexpr const char* kIirtfFileFormat = "fibertwin-iirtf";

struct IirtfFile {
  nlohmann::json header;
  size_t segments = 0, cells = 0;
  int bands = 0;
  std::vector<uint32_t> cellOf;        // S
  std::vector<uint32_t> cellSegments;  // C
  std::vector<uint32_t> cellPaths;     // C
  std::vector<float> transfer;         // C × 3 × 36 × 36
};

// Throws InputError naming the file and the field (or section and item) for
// anything that is not such a file: header, sizes, a cell id ≥ C, non-finite values.
IirtfFile readIirtfFile(const std::filesystem::path& path);

}  // namespace ft
