// harness.h — the cross-check harness: a registry of cases, each running a
// CPU reference and a GPU path and comparing them with named metrics against
// tolerances declared beside the case. Adding an algorithm = one
// `add...Cases` function and one line in harness.cpp.
#pragma once
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "gpu/bcsdf_gpu.h"
#include "gpu/fiber_gpu.h"
#include "gpu/knit_gpu.h"
#include "gpu/gl_context.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_model.h"
#include "scene/yarn_preset.h"
#include "scene/yarn_radius.h"
#include "validation/metrics.h"

namespace ft {

struct HarnessOptions {
  std::optional<std::filesystem::path> model;  // BCC file; default: the built-in scene
  std::vector<std::string> yarns;              // preset names; empty: all
  std::string filter;                          // regex on case names; empty: all
  std::string inject;                          // fault name (faults.def); empty: none
  std::string commandLine;                     // as typed, for the report
  std::filesystem::path reportDir = "fibertwin-report";
  GlBackend backend = GlBackend::Auto;
  FiberOptions fiber;
  int lodWidth = 640, lodHeight = 480;         // the view the LoD decisions are made for
  float lodThresholdPx = 1.0f;                 // ω^LoD
  int imageWidth = 256, imageHeight = 192;     // report thumbnails
  bool images = true;
  size_t tessSegmentBudget = 1500;             // tessellation cases on bigger models use a fixed subset
};

class ValidationContext;

struct ValidationCase {
  std::string name;
  std::function<CaseResult(ValidationContext&)> run;
};

// Shared state of one run: GL context, GPU programs (built with the injected
// fault), the model, cached CPU results.
class ValidationContext {
 public:
  explicit ValidationContext(HarnessOptions options);
  ~ValidationContext();  // switches a shared fault's CPU side off again
  const HarnessOptions& options() const { return options_; }
  const GlInfo& gl() const { return context_->info(); }
  FiberGpu& fiberGpu() { return *fiberGpu_; }
  // The injected fault's define, for other GPU programs built in a case.
  const std::vector<std::string>& defines() const { return defines_; }
  // Built on first use, with the same injected fault.
  KnitGpu& knitGpu();
  BcsdfGpu& bcsdfGpu();
  const YarnModel& model() const { return model_; }
  const YarnBuffers& buffers() const { return buffers_; }
  std::string modelLabel() const;
  // The yarn radius every preset is fitted to (--yarn-radius, else estimated
  // from the model once), and where it came from.
  double yarnRadius() const { return yarnRadius_; }
  const std::string& yarnRadiusSource() const { return yarnRadiusSource_; }
  std::vector<const YarnPreset*> presets() const;
  // Writes an image into the report folder, returns its relative name.
  std::string saveImage(const RgbaImage& image, const std::string& stem);
  // The preset fitted to yarnRadius() with its fiber table and YarnParams
  // (scene/yarn_radius.h), built once per preset.
  const FiberSetup& fiberSetup(const YarnPreset& preset);
  // The CPU reference's knot frames of the model, computed once.
  const std::vector<FrameNormal>& cpuFrames();
  // Per-key cache for CPU results shared by cases (e.g. both GPU paths).
  std::map<std::string, std::shared_ptr<void>>& cache() { return cache_; }

 private:
  HarnessOptions options_;
  std::unique_ptr<GlContext> context_;
  std::vector<std::string> defines_;
  std::unique_ptr<FiberGpu> fiberGpu_;
  std::unique_ptr<KnitGpu> knitGpu_;
  std::unique_ptr<BcsdfGpu> bcsdfGpu_;
  YarnModel model_;
  YarnBuffers buffers_;
  double yarnRadius_ = 0.0;
  std::string yarnRadiusSource_;
  std::map<std::string, std::shared_ptr<void>> cache_;
};

// Case factories, one per algorithm.
void addFiberCases(ValidationContext& ctx, std::vector<ValidationCase>& out);
void addCloseupCases(ValidationContext& ctx, std::vector<ValidationCase>& out);
void addKnitCases(ValidationContext& ctx, std::vector<ValidationCase>& out);
void addBcsdfCases(ValidationContext& ctx, std::vector<ValidationCase>& out);
void addShadingCases(ValidationContext& ctx, std::vector<ValidationCase>& out);
void addAmbientOcclusionCases(ValidationContext& ctx, std::vector<ValidationCase>& out);

struct RunSummary {
  std::vector<CaseResult> results;
  double yarnRadius = 0.0;        // the radius every preset was fitted to (0: each at its own scale)
  std::string yarnRadiusSource;
  bool allPassed = false;
  double seconds = 0.0;
};

// The --filter regex (ECMAScript); InputError naming the option if invalid.
std::regex parseFilter(const std::string& filter);

// Runs every case whose name matches the filter; writes report.json and
// index.html into options.reportDir.
RunSummary runValidation(const HarnessOptions& options, std::ostream& log);

}  // namespace ft
