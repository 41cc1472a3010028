// report.h — report.json (machine-readable: every case, metric, tolerance,
// verdict, timing, and the GL renderer) and index.html (for a person: a
// pass/fail table, error histograms and thumbnails of both sides).
#pragma once
#include <filesystem>

#include "gpu/fiber_renderer.h"
#include "gpu/gl_context.h"
#include "validation/harness.h"

namespace ft {

void writePng(const std::filesystem::path& path, const RgbaImage& image);
void writeReport(const HarnessOptions& options, const GlInfo& gl, const std::string& model, const RunSummary& run);

}  // namespace ft
