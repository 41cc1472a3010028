// iirtf_bake.h — the file `fibertwin bake iirtf` writes (bake/iirtf_bake.cpp,
// docs/prt-multiple-scattering.md "File"): one JSON header line, then
// little-endian sections:
//   cell_of   S × uint32: the cell of block segment k (its midpoint's)
//   cells     C × (uint32 segments, uint32 paths)
//   transfer  C × 3 × 36 × 36 float32: A_C per cell, [channel][j1][j0]
//             (004 §4.2a's a[j0, j1] at row j1, column j0: c_T = A_C c_d)
//   stderr    C × 3 × 36 × 36 float32: the standard error of each transfer
//             entry from the same paths (version 2; IirtfCell::stdError)
// Version 1 files (no stderr section) read with stdError empty: no noise
// estimate, which readers must treat as unknown, not as zero.
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
  std::vector<float> stdError;         // C × 3 × 36 × 36 (version 2), empty for version 1
  int version = 0;
};

// Relative noise of a set of IIRTF matrices per SH band pair: for bands
// (l1, l0) the root of Σ SE² over Σ a² of the entries with j1 in band l1 and
// j0 in band l0, summed over every matrix and channel ([l1][l0], row major,
// FT_SH_BANDS²), and per band l the same over the entries with
// max(l1, l0) = l. 0/0 (an all-zero block) gives 0.
struct IirtfNoiseByBand {
  std::vector<double> pair;  // FT_SH_BANDS × FT_SH_BANDS
  std::vector<double> band;  // FT_SH_BANDS
};
IirtfNoiseByBand iirtfNoiseByBand(const std::vector<float>& transfer, const std::vector<float>& stdError);

// Throws InputError naming the file and the field (or section and item) for
// anything that is not such a file: header, sizes, a cell id ≥ C, non-finite values.
IirtfFile readIirtfFile(const std::filesystem::path& path);

}  // namespace ft
