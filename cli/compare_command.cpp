#include "cli/compare_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <array>
#include <fstream>
#include <map>
#include <ostream>
#include <stdexcept>
#include <string>

#include "image/image_io.h"
#include "image/image_metrics.h"

namespace ft {
namespace {

const std::map<std::string, FlipToneMapper> kToneMappers = {
    {"aces", FlipToneMapper::Aces}, {"hable", FlipToneMapper::Hable}, {"reinhard", FlipToneMapper::Reinhard}};

struct LoadedImage {
  ImageRgbaF linear;  // rgb linear: PNG decoded from sRGB as the FLIP tool does, EXR as stored
  bool exr = false;
};

// By content, not by name: PNG and OpenEXR start with fixed magic bytes.
LoadedImage load(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path))
    throw std::invalid_argument(path.string() + ": is a directory, not an image");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::invalid_argument(path.string() + ": cannot open");
  std::array<unsigned char, 4> magic{};
  file.read(reinterpret_cast<char*>(magic.data()), magic.size());
  constexpr std::array<unsigned char, 4> png = {0x89, 'P', 'N', 'G'}, exr = {0x76, 0x2f, 0x31, 0x01};
  LoadedImage loaded;
  if (magic == exr) {
    loaded.linear = readExr(path);
    loaded.exr = true;
  } else if (magic == png) {
    loaded.linear = readPng(path);
    for (size_t i = 0; i < loaded.linear.pixels.size(); ++i)
      if (i % 4 != 3) loaded.linear.pixels[i] = srgbToLinear(loaded.linear.pixels[i]);
  } else {
    throw std::invalid_argument(path.string() + ": neither a PNG nor an OpenEXR file");
  }
  return loaded;
}

nlohmann::json pooledJson(const FlipPooled& p) {
  return {{"pixels", p.count},
          {"mean", p.mean},
          {"mean_double", p.meanDouble},
          {"weighted_median", p.weightedMedian},
          {"weighted_quartile_1", p.weightedQuartile1},
          {"weighted_quartile_3", p.weightedQuartile3},
          {"min", p.min},
          {"max", p.max},
          {"histogram", p.histogram},
          {"histogram_weighted_percentiles",
           {{"0.25", p.histogramWeighted25}, {"0.50", p.histogramWeighted50}, {"0.75", p.histogramWeighted75}}}};
}

}  // namespace

CLI::App* addCompareCommand(CLI::App& app, CompareCommandOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "compare", "FLIP, RMSE and relative MSE of two images (PNG: LDR-FLIP on sRGB-decoded values; OpenEXR: HDR-FLIP)");
  cmd->add_option("reference", o.reference, "reference image (PNG or OpenEXR)")->required();
  cmd->add_option("test", o.test, "test image, same size")->required();
  cmd->add_option("--ppd", o.ppd,
                  "pixels per degree of visual angle (default: 0.7 m from a 0.7 m wide 3840-pixel display)")
      ->capture_default_str();
  auto* hdr = cmd->add_flag("--hdr", o.hdr, "HDR-FLIP even for PNG input");
  cmd->add_flag("--ldr", o.ldr, "LDR-FLIP even for OpenEXR input (linear values clamped to [0, 1])")->excludes(hdr);
  cmd->add_option("--tonemapper", o.toneMapper, "HDR-FLIP tone curve: aces, hable or reinhard")
      ->check(CLI::IsMember(kToneMappers))
      ->capture_default_str();
  cmd->add_option("--start-exposure", o.startExposure, "HDR-FLIP: first exposure, stops (default: from the reference)");
  cmd->add_option("--stop-exposure", o.stopExposure, "HDR-FLIP: last exposure, stops (default: from the reference)");
  cmd->add_option("--exposures", o.exposures, "HDR-FLIP: number of exposures (default: one per stop, at least 2)");
  cmd->add_option("--error-map", o.errorMap, "write the FLIP error map as a magma-coloured PNG");
  cmd->add_option("--json", o.json, "write every number as JSON");
  return cmd;
}

int runCompareCommand(const CompareCommandOptions& o, std::ostream& out) {
  const LoadedImage ref = load(o.reference), test = load(o.test);
  if (ref.linear.width != test.linear.width || ref.linear.height != test.linear.height)
    throw std::invalid_argument(fmt::format("{} is {}x{} but {} is {}x{}", o.reference.string(), ref.linear.width,
                                            ref.linear.height, o.test.string(), test.linear.width, test.linear.height));
  const ImageMetrics metrics = compareImages(ref.linear, test.linear);
  for (const auto& [path, count] : {std::pair{&o.reference, metrics.nonFiniteReference},
                                    std::pair{&o.test, metrics.nonFiniteTest}})
    if (count) throw std::invalid_argument(fmt::format("{}: {} non-finite rgb value(s)", path->string(), count));

  const bool hdr = o.hdr || ((ref.exr || test.exr) && !o.ldr);
  FlipOptions flip;
  flip.ppd = o.ppd;
  flip.toneMapper = kToneMappers.at(o.toneMapper);
  flip.startExposure = o.startExposure, flip.stopExposure = o.stopExposure, flip.exposureCount = o.exposures;
  const FlipResult r = hdr ? flipHdr(ref.linear, test.linear, flip) : flipLdr(ref.linear, test.linear, flip);
  const FlipPooled& p = r.pooled;

  out << fmt::format("reference: {}\ntest: {}\n{}-FLIP, {}x{} pixels, {:.4f} pixels per degree\n", o.reference.string(),
                     o.test.string(), hdr ? "HDR" : "LDR", r.width, r.height, o.ppd);
  if (hdr)
    out << fmt::format("Tone mapper: {}\nStart exposure: {:.4f}\nStop exposure: {:.4f}\nNumber of exposures: {}\n",
                       o.toneMapper, r.startExposure, r.stopExposure, r.exposureCount);
  out << fmt::format(
      "Mean: {:.6f}\nWeighted median: {:.6f}\n1st weighted quartile: {:.6f}\n3rd weighted quartile: {:.6f}\n"
      "Min: {:.6f}\nMax: {:.6f}\nRMSE: {:.6g}\nrelMSE: {:.6g} (epsilon {})\n",
      p.mean, p.weightedMedian, p.weightedQuartile1, p.weightedQuartile3, p.min, p.max, metrics.rmse, metrics.relMse,
      kRelMseEpsilon);

  if (!o.errorMap.empty()) {
    writePngRgba8(o.errorMap, r.width, r.height, magmaRgba8(r.errorMap));
    out << "error map: " << o.errorMap.string() << "\n";
  }
  if (!o.json.empty()) {
    nlohmann::json j = {{"reference", o.reference.string()},
                        {"test", o.test.string()},
                        {"width", r.width},
                        {"height", r.height},
                        {"flip", hdr ? "hdr" : "ldr"},
                        {"ppd", o.ppd},
                        {"pooled", pooledJson(p)},
                        {"rmse", metrics.rmse},
                        {"rel_mse", metrics.relMse},
                        {"rel_mse_epsilon", kRelMseEpsilon}};
    if (hdr)
      j["hdr"] = {{"tone_mapper", o.toneMapper},
                  {"start_exposure", r.startExposure},
                  {"stop_exposure", r.stopExposure},
                  {"exposures", r.exposureCount}};
    std::ofstream file(o.json);
    file << j.dump(2) << "\n";
    if (!file) throw std::runtime_error("cannot write " + o.json.string());
    out << "json: " << o.json.string() << "\n";
  }
  return 0;
}

}  // namespace ft
