// compare_command.h — `fibertwin compare REFERENCE TEST`: FLIP (LDR-FLIP
// for PNG pairs, HDR-FLIP when either file is OpenEXR), RMSE and relative MSE
// of two images of the same size; optionally the magma error map as PNG and
// every number as JSON (docs/flip.md).
#pragma once
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>

#include "image/flip.h"

namespace CLI {
class App;
}

namespace ft {

struct CompareCommandOptions {
  std::filesystem::path reference, test;
  double ppd = FlipOptions{}.ppd;
  bool hdr = false, ldr = false;  // force a FLIP variant (default: HDR iff either file is OpenEXR)
  std::string toneMapper = "aces";  // HDR-FLIP: aces, hable or reinhard
  std::optional<float> startExposure, stopExposure;
  std::optional<int> exposures;
  std::filesystem::path errorMap, json;  // empty: not written
};

// Registers `compare` and its options on `app`; parsing fills `options`.
CLI::App* addCompareCommand(CLI::App& app, CompareCommandOptions& options);

// Prints the pooled FLIP numbers (six decimals, the tool's labels), RMSE and
// relative MSE; returns the exit status. Unreadable files, different sizes
// and non-finite values throw std::invalid_argument naming the file(s).
int runCompareCommand(const CompareCommandOptions& options, std::ostream& out);

}  // namespace ft
