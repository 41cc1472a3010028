// metrics.h — named comparison metrics with the tolerance declared by the
// case that uses them, and the results a case reports.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace ft {

struct Metric {
  std::string name;           // e.g. "position.max_abs"
  double value = 0.0;
  double tolerance = 0.0;     // pass iff value <= tolerance
  std::string unit;           // "world units", "count", ...
  std::string justification;  // why this tolerance, in meaningful units
  bool gating = true;         // informational metrics do not decide pass/fail
  // A NaN or Inf value fails (NaN <= x is false anyway; Inf <= Inf is not).
  bool pass() const { return !gating || (std::isfinite(value) && value <= tolerance); }
};

// max for error metrics: a NaN operand wins. std::max(a, NaN) returns a, so a
// running maximum over NaN errors would silently read as a pass.
inline double maxKeepNaN(double a, double b) {
  return std::isnan(a) || std::isnan(b) ? std::numeric_limits<double>::quiet_NaN() : std::max(a, b);
}

// nonfinite.cpu / nonfinite.gpu: how many NaN/Inf values one side produced.
// Every case reports both, gating, tolerance 0: a NaN on both sides agrees
// with itself, so the CPU–GPU comparison cannot see it.
inline Metric nonFiniteMetric(const char* side, uint64_t count, const std::string& what) {
  return Metric{std::string("nonfinite.") + side, double(count), 0.0, "count",
                what + " that are NaN or Inf: never allowed", true};
}

// log10 histogram of per-vertex errors: bins [1e-10,1e-9), ..., [1e-1, inf); bin 0 also holds exact zeros.
struct ErrorHistogram {
  double firstDecade = -10.0;
  std::vector<uint64_t> counts = std::vector<uint64_t>(10, 0);
  void add(double error);
};

struct CaseResult {
  std::string name;
  std::string group;           // "fiber", "frames", ...
  std::string path;            // "tessellation", "compute", "" for CPU-only checks
  bool pass = false;
  std::string error;           // an exception while running the case: always a failure
  std::vector<Metric> metrics;
  ErrorHistogram histogram;
  std::string histogramMetric;  // the metric whose per-item values `histogram` bins (its tolerance is drawn)
  double cpuMilliseconds = 0.0;
  double gpuMilliseconds = 0.0;
  std::string gpuTiming;       // how gpuMilliseconds was measured
  double wallMilliseconds = 0.0;  // the whole case as the harness saw it: set-up, bakes, images included
  std::vector<std::string> images;  // file names relative to the report folder
  std::vector<std::string> imageCaptions;  // one per image; empty: "CPU reference", then "GPU <path>"
  std::string details;         // first mismatches, for a person reading the report
  void finish();               // pass := no error and every gating metric passes
};

}  // namespace ft
