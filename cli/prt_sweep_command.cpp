// prt_sweep_command.cpp — `fibertwin prt-sweep` and `fibertwin prt-ms-probe`
// (cli/prt_sweep_command.h). Rendering, path tracing and the IIRTF bakes are
// reference/prt_frame.h's; this file only chooses configurations and reports.
#include "cli/prt_sweep_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <ostream>

#include "bake/iirtf_bake.h"
#include "cli/prt_frame_command.h"
#include "scene/input_error.h"

namespace ft {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr const char* kChannel[3] = {"r", "g", "b"};
using Clock = std::chrono::steady_clock;

// Mean of one channel over all pixels (004 Fig. 13's average intensity, per channel).
double channelAverage(const PrtFrameImage& im, int ch) {
  double s = 0.0;
  for (const glm::vec3& c : im.rgb) s += double(c[ch]);
  return im.rgb.empty() ? 0.0 : s / double(im.rgb.size());
}

glm::vec3 capDirection(int i, int n, double zMin, double turn) {
  const double z = zMin + (1.0 - zMin) * (double(i) + 0.5) / double(n);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = double(i) * kPi * (3.0 - std::sqrt(5.0)) + turn;
  return glm::normalize(glm::vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
}

void addFrameOptions(CLI::App* c, PrtFrameSettings& f) {
  c->add_option("--yarn", f.exemplar.yarn, "yarn preset of the plain-weave block")->capture_default_str();
  c->add_option("--fibers-per-ply", f.exemplar.fibersPerPly, "fibers per ply (0: the preset's)")->capture_default_str();
  c->add_option("--width", f.width)->capture_default_str();
  c->add_option("--height", f.height)->capture_default_str();
  c->add_option("--tiles", f.tiles, "N x N copies of the block")->capture_default_str();
  c->add_option("--volume-samples", f.volumeSamples, "samples per eye ray in the exemplar volume (004 §5.1)")->capture_default_str();
  c->add_option("--svf-size", f.svfSize, "visibility image size (004: 128)")->capture_default_str();
  c->add_option("--bands", f.bands, "SH bands L + 1 of multiple scattering")->capture_default_str();
  c->add_option("--cell-factor", f.cellFactor, "IIRTF cell side in mean free paths")->capture_default_str();
  c->add_option("--paths-per-cell", f.pathsPerCell, "IIRTF paths per cell (004: 50,000)")->capture_default_str();
  c->add_option("--ms-noise-cut", f.msNoiseCut,
                "noise-aware truncation of A_C: drop a cell's SH band pairs whose relative noise exceeds this (0: off)")
      ->capture_default_str();
  c->add_option("--spp", f.ptSamples, "path-traced samples per pixel")->capture_default_str();
  c->add_option("--max-depth", f.maxDepth, "scattering events per path")->capture_default_str();
  c->add_option("--seed", f.seed)->capture_default_str();
  c->add_flag("--embree-gbuffer", f.embreeGBuffer, "experiment: PRT shading at the capsules' Embree first hits");
}

void writeJson(const std::string& path, const nlohmann::ordered_json& j) {
  std::ofstream f(path);
  if (!f) throw InputError(fmt::format("--json: cannot write '{}'", path));
  f << j.dump(1) << '\n';
  if (!f) throw InputError(fmt::format("--json: writing '{}' failed", path));
}
}  // namespace

std::vector<PrtFrameView> prtSweepConfigurations(int views, int lights, const std::vector<float>& lambdas) {
  if (views < 1 || lights < 1 || lambdas.empty())
    throw InputError(fmt::format("prt-sweep: --views {}, --lights {}, {} λ (≥ 1 each)", views, lights, lambdas.size()));
  std::vector<PrtFrameView> out;
  for (int v = 0; v < views; ++v)
    for (int l = 0; l < lights; ++l)
      for (float lambda : lambdas) {
        PrtFrameView c;
        c.wo = capDirection(v, views, 0.25, 0.0);
        c.light = capDirection(l, lights, 0.15, 1.0);
        c.lambda = lambda;
        checkPrtFrameView(c);  // names a negative λ
        out.push_back(c);
      }
  return out;
}

CLI::App* addPrtSweepCommand(CLI::App& app, PrtSweepCommandOptions& o) {
  CLI::App* c = app.add_subcommand(
      "prt-sweep", "004 Fig. 13's protocol: the tiled flat exemplar under views x lights x lambda (directional, SG "
                   "lights), PRT against path tracing; per configuration and channel the average intensities, per "
                   "fabric the RMSE over the sweep; JSON/CSV (docs/prt-frame.md)");
  o.frame.width = o.frame.height = 64;
  o.frame.ptSamples = 128;
  addFrameOptions(c, o.frame);
  c->add_option("--fabrics", o.fabrics, "BCSDF presets (data/fabric-bcsdf.tsv), one sweep each")->delimiter(',')->capture_default_str();
  c->add_option("--views", o.views, "view directions (Fibonacci cap, z >= 0.25)")->capture_default_str();
  c->add_option("--lights", o.lights, "light directions / SG axes (Fibonacci cap, z >= 0.15)")->capture_default_str();
  c->add_option("--lambdas", o.lambdas, "light kinds: 0 = directional, > 0 = SG light of that sharpness")
      ->delimiter(',')->capture_default_str();
  c->add_option("--alt-noise-cut", o.altNoiseCut,
                "also render each configuration's PRT with this --ms-noise-cut (0: none) against the same path tracing")
      ->capture_default_str();
  c->add_option("--limit", o.limit, "only the first N configurations of each fabric (0: all)")->capture_default_str();
  c->add_option("--json", o.json, "write every configuration and the summary as JSON");
  c->add_option("--csv", o.csv, "write one row per configuration and channel as CSV");
  return c;
}

int runPrtSweepCommand(const PrtSweepCommandOptions& o, std::ostream& out) {
  std::vector<PrtFrameView> configs = prtSweepConfigurations(o.views, o.lights, o.lambdas);
  if (o.limit < 0) throw InputError(fmt::format("--limit: {} (≥ 0)", o.limit));
  if (o.limit > 0 && size_t(o.limit) < configs.size()) configs.resize(size_t(o.limit));
  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    if (!csv) throw InputError(fmt::format("--csv: cannot write '{}'", o.csv));
    csv << "fabric,config,view_x,view_y,view_z,light_x,light_y,light_z,lambda,channel,average_prt,average_pt,"
           "pt_std_error,single_prt,multi_prt\n";
  }
  nlohmann::ordered_json j;
  j["protocol"] = "Khungurn et al. 2017 (004) §6.3, Fig. 13: RMSE of per-image average intensities, PRT vs path tracing";
  j["settings"] = {{"width", o.frame.width}, {"height", o.frame.height}, {"spp", o.frame.ptSamples},
                   {"fibers_per_ply", o.frame.exemplar.fibersPerPly}, {"tiles", o.frame.tiles},
                   {"bands", o.frame.bands}, {"cell_factor", o.frame.cellFactor},
                   {"paths_per_cell", o.frame.pathsPerCell}, {"svf_size", o.frame.svfSize},
                   {"ms_noise_cut", o.frame.msNoiseCut}, {"embree_gbuffer", o.frame.embreeGBuffer},
                   {"views", o.views}, {"lights", o.lights}, {"lambdas", o.lambdas}, {"seed", o.frame.seed}};
  bool finite = true;
  for (const std::string& fabric : o.fabrics) {
    PrtFrameSettings fs = o.frame;
    fs.fabric = fabric;
    const auto t0 = Clock::now();
    PrtFrameScene scene(fs);
    const bool alt = o.altNoiseCut >= 0.0;
    double sq[3] = {}, sqRel[3] = {}, sumRel = 0.0, prtSeconds = 0.0, ptSeconds = 0.0;
    double sqAlt[3] = {}, sqRelAlt[3] = {}, sumRelAlt = 0.0;
    nlohmann::ordered_json rows = nlohmann::json::array();
    for (size_t c = 0; c < configs.size(); ++c) {
      const PrtFrameView& v = configs[c];
      const PrtFrameParts prt = scene.renderPrt(v);
      const PrtFrameImage pt = scene.renderPathTraced(v, fs.ptSamples, fs.maxDepth);
      PrtFrameParts prtAlt;
      if (alt) {
        scene.setMsNoiseCut(o.altNoiseCut);
        prtAlt = scene.renderPrt(v);
        scene.setMsNoiseCut(fs.msNoiseCut);
      }
      prtSeconds += prt.total.seconds, ptSeconds += pt.seconds;
      nlohmann::ordered_json row = {{"config", c},
                                    {"view", {v.wo.x, v.wo.y, v.wo.z}},
                                    {"light", {v.light.x, v.light.y, v.light.z}},
                                    {"lambda", v.lambda},
                                    {"pt_std_error", pt.averageStdError}};
      std::string line = fmt::format("{} {:3d}/{} view ({:.2f},{:.2f},{:.2f}) light ({:.2f},{:.2f},{:.2f}) λ {:g}:", fabric,
                                     c + 1, configs.size(), v.wo.x, v.wo.y, v.wo.z, v.light.x, v.light.y, v.light.z, v.lambda);
      for (int ch = 0; ch < 3; ++ch) {
        const double a = channelAverage(prt.total, ch), b = channelAverage(pt, ch);
        finite = finite && std::isfinite(a) && std::isfinite(b);
        sq[ch] += (a - b) * (a - b);
        const double rel = (a - b) / std::max(1e-30, std::abs(b));
        sqRel[ch] += rel * rel;
        sumRel += rel / 3.0;
        const char* name = kChannel[ch];
        row[fmt::format("average_prt_{}", name)] = a;
        row[fmt::format("average_pt_{}", name)] = b;
        line += fmt::format(" {} {:.5f}/{:.5f}", name, a, b);
        if (alt) {
          const double c2 = channelAverage(prtAlt.total, ch), relAlt = (c2 - b) / std::max(1e-30, std::abs(b));
          finite = finite && std::isfinite(c2);
          sqAlt[ch] += (c2 - b) * (c2 - b), sqRelAlt[ch] += relAlt * relAlt, sumRelAlt += relAlt / 3.0;
          row[fmt::format("average_prt_alt_{}", name)] = c2;
          line += fmt::format(" (alt {:.5f})", c2);
        }
        if (csv.is_open())
          csv << fmt::format("{},{},{},{},{},{},{},{},{},{},{:.9g},{:.9g},{:.6g},{:.9g},{:.9g}\n", fabric, c, v.wo.x, v.wo.y,
                             v.wo.z, v.light.x, v.light.y, v.light.z, v.lambda, name, a, b, pt.averageStdError,
                             channelAverage(prt.single, ch), channelAverage(prt.multi, ch));
      }
      row["average_single_prt"] = prt.single.average();
      row["average_multi_prt"] = prt.multi.average();
      rows.push_back(row);
      out << line << fmt::format(" (PRT {:.3f} s, PT {:.2f} s)\n", prt.total.seconds, pt.seconds) << std::flush;
    }
    const double n = double(configs.size());
    nlohmann::ordered_json summary;
    std::string line = fmt::format("{}: {} configurations, RMSE of the average intensity (PRT vs path tracing) per channel:",
                                   fabric, configs.size());
    for (int ch = 0; ch < 3; ++ch) {
      const char* name = kChannel[ch];
      summary[fmt::format("rmse_{}", name)] = std::sqrt(sq[ch] / n);
      summary[fmt::format("rmse_rel_{}", name)] = std::sqrt(sqRel[ch] / n);
      line += fmt::format(" {} {:.5f} (relative {:.3f})", name, std::sqrt(sq[ch] / n), std::sqrt(sqRel[ch] / n));
    }
    summary["mean_rel_error"] = sumRel / n;
    if (alt) {
      line += fmt::format("; mean relative error {:+.3f}\n  with --ms-noise-cut {:g}:", sumRel / n, o.altNoiseCut);
      for (int ch = 0; ch < 3; ++ch) {
        summary[fmt::format("alt_rmse_{}", kChannel[ch])] = std::sqrt(sqAlt[ch] / n);
        summary[fmt::format("alt_rmse_rel_{}", kChannel[ch])] = std::sqrt(sqRelAlt[ch] / n);
        line += fmt::format(" {} {:.5f} (relative {:.3f})", kChannel[ch], std::sqrt(sqAlt[ch] / n), std::sqrt(sqRelAlt[ch] / n));
      }
      summary["alt_noise_cut"] = o.altNoiseCut;
      summary["alt_mean_rel_error"] = sumRelAlt / n;
      sumRel = sumRelAlt;  // printed last on the line below
    }
    summary["prt_frame_seconds"] = prtSeconds;
    summary["path_traced_seconds"] = ptSeconds;
    summary["bake_seconds"] = scene.bakeSeconds();
    summary["wall_seconds"] = std::chrono::duration<double>(Clock::now() - t0).count();
    out << line << fmt::format("; mean relative error {:+.3f}; PRT frames {:.1f} s, path tracing {:.1f} s, bakes {:.1f} s\n",
                               sumRel / n, prtSeconds, ptSeconds, scene.bakeSeconds());
    j["fabrics"][fabric] = {{"summary", summary}, {"configurations", rows}};
  }
  if (!o.json.empty()) writeJson(o.json, j);
  return finite ? 0 : 1;
}

CLI::App* addPrtMsProbeCommand(CLI::App& app, PrtMsProbeCommandOptions& o) {
  CLI::App* c = app.add_subcommand(
      "prt-ms-probe", "noise or bias of PRT multiple scattering on one configuration: L~multi per SH order over "
                      "several IIRTF seeds, the bake's relative noise per band, and the SH-free transfer at the hit "
                      "point, the segment midpoint and the cell average (docs/prt-multiple-scattering.md)");
  o.frame.width = o.frame.height = 48;
  o.frame.embreeGBuffer = true;  // only L~multi differs from the path tracer's first hits
  addFrameOptions(c, o.frame);
  c->add_option("--fabric", o.frame.fabric, "BCSDF preset")->capture_default_str();
  c->add_option("--view", o.view, "direction towards the eye x,y,z")->capture_default_str();
  c->add_option("--light", o.light, "direction towards the light x,y,z")->capture_default_str();
  c->add_option("--lambda", o.lambda, "0: directional; > 0: SG light")->capture_default_str();
  c->add_option("--seeds", o.seeds, "IIRTF bakes with seeds --seed, --seed + 1, ...")->capture_default_str();
  c->add_option("--transfer-spp", o.transferSpp, "samples per pixel of the SH-free estimates")->capture_default_str();
  c->add_option("--json", o.json, "write the figures as JSON");
  return c;
}

int runPrtMsProbeCommand(const PrtMsProbeCommandOptions& o, std::ostream& out) {
  PrtFrameView view;
  view.wo = parseDirection("--view", o.view);
  view.light = parseDirection("--light", o.light);
  view.lambda = o.lambda;
  checkPrtFrameView(view);
  if (o.seeds < 1 || o.transferSpp < 1)
    throw InputError(fmt::format("prt-ms-probe: --seeds {}, --transfer-spp {} (≥ 1 each)", o.seeds, o.transferSpp));
  PrtFrameScene scene(o.frame);
  nlohmann::ordered_json j;
  j["view"] = {view.wo.x, view.wo.y, view.wo.z};
  j["light"] = {view.light.x, view.light.y, view.light.z};
  j["lambda"] = view.lambda;
  j["cells"] = scene.cellCount();
  j["mean_free_path"] = scene.meanFreePath();
  out << fmt::format("{} segments, {} IIRTF cells (cell factor {:g}, ℓ = {:.5g}), {} paths per cell, noise cut {:g}\n",
                     scene.block().segments.size(), scene.cellCount(), o.frame.cellFactor, scene.meanFreePath(),
                     o.frame.pathsPerCell, o.frame.msNoiseCut);
  using O = PrtFrameScene::TransferOrigin;
  for (auto [origin, name] : {std::pair{O::Hit, "hit point (path-traced indirect)"}, std::pair{O::Midpoint, "segment midpoint"},
                              std::pair{O::Cell, "cell average"}}) {
    const PrtFrameImage im = scene.renderTransfer(view, o.transferSpp, origin);
    const double scale = im.covered ? double(im.rgb.size()) / double(im.covered) : 0.0;
    out << fmt::format("SH-free transfer at the {}: {:.6f} ± {:.6f} per covered pixel ({} px, {:.1f} s)\n", name,
                       im.coveredAverage(), im.averageStdError * scale, im.covered, im.seconds);
    j["transfer"][name] = {{"covered_average", im.coveredAverage()}, {"std_error", im.averageStdError * scale}};
  }
  std::vector<std::vector<double>> perL(FT_SH_BANDS);
  for (int s = 0; s < o.seeds; ++s) {
    scene.reseedIirtf(o.frame.seed + uint32_t(s));
    std::string line = fmt::format("seed {}: L~multi per covered pixel", o.frame.seed + uint32_t(s));
    for (int bands = 1; bands <= FT_SH_BANDS; ++bands) {
      scene.setBands(bands);
      const PrtFrameParts p = scene.renderPrt(view);
      perL[size_t(bands - 1)].push_back(p.multi.coveredAverage());
      line += fmt::format(" L={} {:.5f}", bands - 1, p.multi.coveredAverage());
    }
    std::vector<float> a, e;
    scene.bakedTransfer(a, e);
    const IirtfNoiseByBand noise = iirtfNoiseByBand(a, e);
    line += "; relative noise of A_C by band";
    for (int l = 0; l < FT_SH_BANDS; ++l) line += fmt::format(" {:.3f}", noise.band[size_t(l)]);
    out << line << '\n' << std::flush;
    j["seeds"].push_back({{"seed", o.frame.seed + uint32_t(s)}, {"relative_noise_by_band", noise.band},
                          {"relative_noise_by_band_pair", noise.pair}});
  }
  std::string line = "mean ± sd over seeds:";
  for (int l = 0; l < FT_SH_BANDS; ++l) {
    const std::vector<double>& v = perL[size_t(l)];
    double m = 0.0, q = 0.0;
    for (double x : v) m += x / double(v.size());
    for (double x : v) q += (x - m) * (x - m);
    const double sd = v.size() > 1 ? std::sqrt(q / double(v.size() - 1)) : 0.0;
    line += fmt::format(" L={} {:.5f} ± {:.5f}", l, m, sd);
    j["multi_by_order"].push_back({{"L", l}, {"mean", m}, {"sd_over_seeds", sd}, {"values", v}});
  }
  out << line << '\n';
  if (!o.json.empty()) writeJson(o.json, j);
  return 0;
}

}  // namespace ft
