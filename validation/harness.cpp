#include "validation/harness.h"

#include <chrono>
#include <fmt/format.h>
#include <fstream>
#include <ostream>

#include "reference/fiber_reference.h"
#include "scene/bcc_reader.h"
#include "scene/default_scene.h"
#include "scene/input_error.h"
#include "validation/faults.h"
#include "validation/report.h"

namespace ft {

void CaseResult::finish() {
  pass = error.empty();
  for (const Metric& m : metrics) pass = pass && m.pass();
}

ValidationContext::ValidationContext(HarnessOptions options) : options_(std::move(options)) {
  model_ = options_.model ? readBcc(*options_.model) : makeDefaultScene();
  // The presets of the run, each with the --set overrides (checked here).
  if (options_.yarns.empty())
    for (const YarnPreset& p : builtinYarnPresets()) presets_.push_back(overrideYarnPreset(p, options_.presetOverrides));
  else
    for (const std::string& y : options_.yarns)
      presets_.push_back(overrideYarnPreset(findYarnPreset(y), options_.presetOverrides));
  applyCameraOverride(Camera{}, options_.camera, model_);  // bad --eye/--target/--fov fail before any GL work
  buffers_ = buildYarnBuffers(model_);
  // Bad names and options fail here, before any GL work.
  for (const YarnPreset* preset : presets()) checkFiberOptions(*preset, options_.fiber);
  if (options_.fiber.yarnRadius != 0.0f) {
    yarnRadius_ = fitYarnPreset(*presets().front(), model_, options_.fiber.yarnRadius).radius;  // checks the value
    yarnRadiusSource_ = "--yarn-radius";
  } else if (const YarnRadiusEstimate e = estimateYarnRadius(model_); e.found) {
    yarnRadius_ = e.radius;
    yarnRadiusSource_ = "estimated from the model";
  } else {
    yarnRadius_ = 0.0;  // each preset at its own scale
    yarnRadiusSource_ = "no yarn passes near another: each preset at its own scale";
  }
  std::vector<std::string>& defines = defines_;
  if (!options_.inject.empty()) {
    const Fault* f = findFault(options_.inject);
    if (!f) {
      std::string names;
      for (const Fault& k : kFaults) names += std::string(names.empty() ? "" : ", ") + k.name;
      throw InputError(fmt::format("--inject: unknown fault '{}' (known: {})", options_.inject, names));
    }
    defines.push_back(f->define);
  }
  context_ = GlContext::create(options_.backend);
  std::filesystem::create_directories(options_.reportDir / "images");
  // Last: nothing below throws, so the destructor always switches it off again.
  if (const Fault* f = options_.inject.empty() ? nullptr : findFault(options_.inject); f && f->shared)
    setSharedFault(f->define, true);
}

ValidationContext::~ValidationContext() {
  if (const Fault* f = options_.inject.empty() ? nullptr : findFault(options_.inject); f && f->shared)
    setSharedFault(f->define, false);
}

const FiberSetup& ValidationContext::fiberSetup(const YarnPreset& preset) {
  return cached(CacheKey<FiberSetup>{"preset/" + preset.name}, [&]() -> FiberSetup {
    return fitFibers(preset, yarnRadius_, yarnRadiusSource_, options_.fiber);
  });
}

const FittedFibers& ValidationContext::fittedFibers(const YarnPreset& preset) {
  return cached(CacheKey<FittedFibers>{"shading/fitted/" + preset.name},
                [&] { return fitFibers(preset, yarnRadius_, yarnRadiusSource_, options_.fiber); });
}

const FiberSetup& ValidationContext::allFiberSetup(const YarnPreset& preset) {
  return cached(CacheKey<FiberSetup>{"preset-all-fibers/" + preset.name}, [&]() -> FiberSetup {
    FiberOptions all = options_.fiber;
    all.allFibers = true;
    return fitFibers(preset, yarnRadius_, yarnRadiusSource_, all);
  });
}

const std::vector<FrameNormal>& ValidationContext::cpuFrames() {
  return cached(CacheKey<std::vector<FrameNormal>>{"frames"}, [&] { return computeKnotFramesCpu(buffers_); });
}

std::string ValidationContext::modelLabel() const {
  return options_.model ? options_.model->stem().string() : std::string("default");
}

std::vector<const YarnPreset*> ValidationContext::presets() const {
  std::vector<const YarnPreset*> out;
  for (const YarnPreset& p : presets_) out.push_back(&p);
  return out;
}

std::string ValidationContext::saveImage(const RgbaImage& image, const std::string& stem) {
  std::string file = stem;
  for (char& c : file)
    if (c == '/') c = '_';
  file = "images/" + file + ".png";
  writePng(options_.reportDir / file, image);
  return file;
}

void addPresetCases(ValidationContext& ctx, std::vector<ValidationCase>& out, const std::string& prefix,
                    std::initializer_list<std::pair<const char*, PresetCaseRun>> kinds) {
  for (const YarnPreset* preset : ctx.presets())
    for (const auto& [kind, run] : kinds) {
      const std::string name = prefix + "/" + kind + "/" + preset->name;
      out.push_back({name, [run = run, preset, name](ValidationContext& c) { return run(c, *preset, name); }});
    }
}

std::regex parseFilter(const std::string& filter) {
  try {
    return std::regex(filter.empty() ? std::string(".*") : filter);
  } catch (const std::regex_error& e) {
    throw InputError(fmt::format("--filter: '{}' is not a valid regular expression ({})", filter, e.what()));
  }
}

RunSummary runValidation(const HarnessOptions& options, std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::regex filter = parseFilter(options.filter);  // before any GL work
  ValidationContext ctx(options);
  std::vector<ValidationCase> cases;
#define FT_SUITE(Name) add##Name##Cases(ctx, cases);
#include "validation/suites.inc"  // every validation/<alg>_cases.cpp, in file-name order
#undef FT_SUITE

  RunSummary summary;
  const GlInfo& gl = ctx.gl();
  log << fmt::format("fibertwin validate: {} on {} ({}, {}), model {}, yarn radius {:.4g} ({}){}\n", gl.version,
                     gl.renderer, gl.vendor, gl.backend, ctx.modelLabel(), ctx.yarnRadius(), ctx.yarnRadiusSource(),
                     options.inject.empty() ? "" : ", injected fault " + options.inject);
  for (ValidationCase& c : cases) {
    if (!std::regex_search(c.name, filter)) continue;
    CaseResult r;
    const auto caseStart = std::chrono::steady_clock::now();
    try {
      r = c.run(ctx);
    } catch (const std::exception& e) {
      r = CaseResult{};
      r.name = c.name;
      r.error = e.what();
      r.finish();
    }
    // Lazy shared set-ups (contexts, bakes) land on the first case that needs them.
    r.wallMilliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - caseStart).count();
    std::string failed;
    for (const Metric& m : r.metrics)
      if (!m.pass()) failed += fmt::format(" {}={:.3g}>{:.3g}", m.name, m.value, m.tolerance);
    log << fmt::format("  {:<4} {:<58} cpu {:8.1f} ms  gpu {:8.1f} ms  wall {:8.1f} ms{}{}\n", r.pass ? "ok" : "FAIL",
                       r.name, r.cpuMilliseconds, r.gpuMilliseconds, r.wallMilliseconds, failed, r.error.empty() ? "" : "  error: " + r.error);
    summary.results.push_back(std::move(r));
  }
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  summary.allPassed = !summary.results.empty();
  size_t passed = 0;
  for (const CaseResult& r : summary.results) {
    summary.allPassed = summary.allPassed && r.pass;
    passed += r.pass;
  }
  summary.yarnRadius = ctx.yarnRadius();
  summary.yarnRadiusSource = ctx.yarnRadiusSource();
  writeReport(options, ctx.gl(), ctx.modelLabel(), summary);
  log << fmt::format("{} passed, {} failed ({:.1f} s); report: {}\n", passed, summary.results.size() - passed,
                     summary.seconds, (options.reportDir / "index.html").string());
  if (summary.results.empty()) log << "no case matched the filter\n";
  return summary;
}

}  // namespace ft
