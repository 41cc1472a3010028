// harness.h — the cross-check harness: a registry of cases, each running a
// CPU reference and a GPU path and comparing them with named metrics against
// tolerances declared beside the case. Adding an algorithm = adding its
// validation/<alg>_cases.cpp defining add<Alg>Cases (validation/CMakeLists.txt
// generates the suite list from the file names).
#pragma once
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <typeindex>
#include <utility>
#include <vector>

#include "gpu/fiber_gpu.h"
#include "gpu/fiber_renderer.h"
#include "gpu/gl_context.h"
#include "scene/camera.h"
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
  std::vector<std::string> presetOverrides;    // --set name=value, applied to every preset
  CameraOverride camera;                       // --eye/--target/--fov: the closeup/* cases' camera
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

// A key of the per-run result cache: the value's type is part of the key, so
// a case can never read a result as another type.
template <class T>
struct CacheKey {
  std::string name;
};

// Shared state of one run: GL context, GPU programs (built with the injected
// fault), the model, cached CPU results.
class ValidationContext {
 public:
  explicit ValidationContext(HarnessOptions options);
  ~ValidationContext();  // switches a shared fault's CPU side off again
  const HarnessOptions& options() const { return options_; }
  const GlInfo& gl() const { return context_->info(); }
  // The injected fault's define, for other GPU programs built in a case.
  const std::vector<std::string>& defines() const { return defines_; }
  // The GPU side of an algorithm (FiberGpu, BcsdfGpu, KnitGpu, ...), built on
  // first use with the injected fault: any class constructible from
  // (const GlInfo&, const std::vector<std::string>& defines), one per run.
  template <class Gpu>
  Gpu& gpu() {
    return cached(CacheKey<Gpu>{"gpu"}, [&] { return Gpu(context_->info(), defines_); });
  }
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
  // The same fit with the fitted preset itself (FittedFibers::fit.preset: the
  // ply-density field the appearance bakes of 000 §4 read), built once per preset.
  const FittedFibers& fittedFibers(const YarnPreset& preset);
  // The same preset as the all-fiber reference (FiberOptions::allFibers:
  // every fiber of the preset explicit, no core; pair it with LoD off), with
  // the run's other fiber options, built once per preset.
  const FiberSetup& allFiberSetup(const YarnPreset& preset);
  // The CPU reference's knot frames of the model, computed once.
  const std::vector<FrameNormal>& cpuFrames();
  // Results shared by cases (e.g. one CPU reference for both GPU paths):
  // make() runs on the first request of `key` and its result is kept for the
  // run; make may return T or a type convertible to it.
  template <class T, class Make>
  T& cached(const CacheKey<T>& key, Make&& make) {
    std::unique_ptr<Entry>& slot = cache_[{std::type_index(typeid(T)), key.name}];
    if (!slot) slot = std::make_unique<Holder<T>>(std::forward<Make>(make));
    return static_cast<Holder<T>&>(*slot).value;
  }
  // The value under `key` if a case has made it, else nullptr.
  template <class T>
  T* findCached(const CacheKey<T>& key) {
    auto it = cache_.find({std::type_index(typeid(T)), key.name});
    return it == cache_.end() ? nullptr : &static_cast<Holder<T>&>(*it->second).value;
  }

 private:
  struct Entry {
    virtual ~Entry() = default;
  };
  template <class T>
  struct Holder final : Entry {
    // Built in place from make()'s result, so T need not be movable (GPU classes are not).
    template <class Make>
    explicit Holder(Make&& make) : value(std::forward<Make>(make)()) {}
    T value;
  };

  HarnessOptions options_;
  YarnModel model_;
  YarnBuffers buffers_;
  std::vector<YarnPreset> presets_;  // built once; cases keep pointers to them
  double yarnRadius_ = 0.0;
  std::string yarnRadiusSource_;
  std::vector<std::string> defines_;
  std::unique_ptr<GlContext> context_;
  // GPU objects and results, destroyed before the context (declared after it).
  std::map<std::pair<std::type_index, std::string>, std::unique_ptr<Entry>> cache_;
};

// One case per yarn preset of the run and per kind: `<prefix>/<kind>/<preset>`,
// run(ctx, preset, name) — the shape of every suite that checks a bake per preset.
using PresetCaseRun = CaseResult (*)(ValidationContext&, const YarnPreset&, const std::string&);
void addPresetCases(ValidationContext& ctx, std::vector<ValidationCase>& out, const std::string& prefix,
                    std::initializer_list<std::pair<const char*, PresetCaseRun>> kinds);

// Case factories, one per validation/<alg>_cases.cpp (the generated list).
#define FT_SUITE(Name) void add##Name##Cases(ValidationContext& ctx, std::vector<ValidationCase>& out);
#include "validation/suites.inc"
#undef FT_SUITE

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
