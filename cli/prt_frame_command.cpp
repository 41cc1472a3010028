// prt_frame_command.cpp — `fibertwin prt-frame` (cli/prt_frame_command.h).
#include "cli/prt_frame_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <utility>
#include <ostream>
#include <sstream>

#include "gpu/exemplar_volume_gpu.h"
#include "gpu/gl_context.h"
#include "gpu/prt_frame_gpu.h"
#include "gpu/prt_multiple_scattering_gpu.h"
#include "gpu/prt_single_scattering_gpu.h"
#include "image/image_io.h"
#include "scene/input_error.h"

namespace ft {

namespace {
// The frame by PrtFrameRendererGpu (the scene's bakes done by a CPU frame first): total,
// single and multiple as PrtFrameParts; seconds = one frame after a first (driver compile) one.
PrtFrameParts renderPrtGpu(PrtFrameScene& scene, const PrtFrameView& view, std::ostream& out) {
  const std::unique_ptr<GlContext> gl = GlContext::create(glBackendFromEnv());
  const PrtFrameSettings& s = scene.settings();
  PrtFrameParts parts;
  {
    ExemplarVolumeGpu vol(gl->info());
    PrtSingleScatteringGpu ss(gl->info());
    PrtMultipleScatteringGpu ms(gl->info());
    PrtFrameRendererGpu frame(gl->info());
    const PrtFrameData d = scene.gpuData();
    const std::vector<float> table = ss.bakeTable(std::span<const FabricParams>(&d.fabric, 1));
    const PrtMsGpuTables tables = ms.tables(d.fabric, s.msThetaINodes, s.msPhiNodes);
    vol.build(d.layout, d.segments, d.candidates.start, d.candidates.entries);
    const glm::vec4 light(view.light, view.lambda);
    const PrtFrameGpuInputs in = prtFrameGpuInputs(d, scene.rays(view), table, tables, s.bands, light);
    frame.upload(in);
    frame.render(vol, in.rays, light);  // the driver compiles on first use
    const auto t0 = std::chrono::steady_clock::now();
    const PrtFrameGpuImage im = frame.render(vol, in.rays, light, true);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::pair<PrtFrameImage*, const std::vector<glm::vec4>*> images[] = {
        {&parts.total, &im.total}, {&parts.single, &im.single}, {&parts.multi, &im.multi}};
    for (const auto& [dst, src] : images) {
      dst->width = im.width, dst->height = im.height, dst->seconds = seconds;
      dst->rgb.resize(src->size());
      for (size_t i = 0; i < src->size(); ++i) {
        dst->rgb[i] = glm::vec3((*src)[i]);
        dst->covered += uint64_t((*src)[i].w > 0.5f);
      }
    }
    out << fmt::format("GPU frame ({}): {:.3f} s\n", gl->info().renderer, seconds);
  }
  return parts;
}
}  // namespace

glm::vec3 parseDirection(const std::string& option, const std::string& text) {
  std::stringstream ss(text);
  glm::vec3 v(0.0f);
  char c1 = 0, c2 = 0;
  if (!(ss >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',' || !ss.eof() || !std::isfinite(v.x) ||
      !std::isfinite(v.y) || !std::isfinite(v.z) || glm::length(v) == 0.0f)
    throw InputError(fmt::format("{}: '{}' is not a non-zero vector x,y,z", option, text));
  return glm::normalize(v);
}

CLI::App* addPrtFrameCommand(CLI::App& app, PrtFrameCommandOptions& o) {
  CLI::App* c = app.add_subcommand(
      "prt-frame", "render the tiled flat exemplar by the fabric PRT (004 §5: volume G-buffer, single scattering by "
                   "SSDF / sums of SGs, multiple scattering by the IIRTF) and by the Embree path tracer; write both "
                   "(EXR + PNG) and print average intensities, RMSE, FLIP and times (docs/prt-frame.md)");
  PrtFrameSettings& f = o.frame;
  c->add_option("--fabric", f.fabric, "BCSDF preset (data/fabric-bcsdf.tsv)")->capture_default_str();
  c->add_option("--yarn", f.exemplar.yarn, "yarn preset of the plain-weave block")->capture_default_str();
  c->add_option("--fibers-per-ply", f.exemplar.fibersPerPly, "fibers per ply (0: the preset's)")->capture_default_str();
  c->add_option("--width", f.width)->capture_default_str();
  c->add_option("--height", f.height)->capture_default_str();
  c->add_option("--tiles", f.tiles, "N x N copies of the block")->capture_default_str();
  c->add_option("--view", o.view, "direction towards the eye x,y,z (orthographic, over the centre block)")->capture_default_str();
  c->add_option("--light", o.light, "direction towards the light x,y,z")->capture_default_str();
  c->add_option("--lambda", o.lambda, "0: directional light of unit irradiance; > 0: the SG light G/M of this sharpness")
      ->capture_default_str();
  c->add_option("--volume-samples", f.volumeSamples, "samples per eye ray in the exemplar volume (004 §5.1)")->capture_default_str();
  c->add_option("--volume-ids", o.volumeIds,
                "G-buffer ids: capsule (the first exact ray-capsule hit among the volume's candidates) or midpoint "
                "(004 §5.1: the nearest midpoint at the first non-empty sample); default: the settings' (" +
                    std::string(volumeIdsName(PrtFrameSettings{}.volumeIds)) + ")");
  c->add_option("--voxels-per-diameter", f.voxelsPerDiameter, "volume voxels per fiber diameter")->capture_default_str();
  c->add_option("--svf-size", f.svfSize, "visibility image size (004: 128)")->capture_default_str();
  c->add_option("--bands", f.bands, "SH bands L + 1 of multiple scattering")->capture_default_str();
  c->add_option("--cell-factor", f.cellFactor, "IIRTF cell side in mean free paths")->capture_default_str();
  c->add_option("--paths-per-cell", f.pathsPerCell, "IIRTF paths per cell (004: 50,000)")->capture_default_str();
  c->add_option("--ms-noise-cut", f.msNoiseCut,
                "noise-aware truncation of A_C: per cell, the SH order cut below the first band whose relative noise "
                "exceeds this (0: off; docs/prt-multiple-scattering.md)")
      ->capture_default_str();
  c->add_option("--spp", f.ptSamples, "path-traced samples per pixel")->capture_default_str();
  c->add_option("--max-depth", f.maxDepth, "scattering events per path")->capture_default_str();
  c->add_option("--seed", f.seed)->capture_default_str();
  c->add_option("--out", o.out, "output stem: <out>_prt.exr/.png, <out>_pt.exr/.png")->capture_default_str();
  c->add_option("--exposure", o.exposure, "PNG exposure in stops")->capture_default_str();
  c->add_flag("--embree-gbuffer", f.embreeGBuffer, "experiment: PRT shading at the capsules' Embree first hits, not the volume's ids");
  c->add_flag("--no-reference", o.noReference, "PRT only (no path tracing)");
  c->add_flag("--gpu", o.gpu, "the PRT image by the GPU frame (EGL/llvmpipe; bakes on the CPU); prints its difference "
                             "to the CPU frame");
  return c;
}

int runPrtFrameCommand(const PrtFrameCommandOptions& o, std::ostream& out) {
  PrtFrameView view;
  view.wo = parseDirection("--view", o.view);
  view.light = parseDirection("--light", o.light);
  view.lambda = o.lambda;
  checkPrtFrameView(view);
  if (!std::isfinite(o.exposure)) throw InputError("--exposure: not a finite number");
  PrtFrameSettings settings = o.frame;
  if (!o.volumeIds.empty()) settings.volumeIds = parseVolumeIds(o.volumeIds);
  PrtFrameScene scene(settings);
  const double setup = scene.bakeSeconds();
  PrtFrameParts prt = scene.renderPrt(view);  // with --gpu: the bakes, and the CPU frame to compare with
  if (o.gpu) {
    const PrtFrameParts cpu = std::move(prt);
    prt = renderPrtGpu(scene, view, out);
    double peak = 0.0, diff = 0.0;
    uint64_t idsDiffer = 0;
    for (size_t i = 0; i < cpu.total.rgb.size(); ++i)
      for (int ch = 0; ch < 3; ++ch) {
        peak = std::max(peak, double(cpu.total.rgb[i][ch]));
        diff = std::max(diff, std::abs(double(prt.total.rgb[i][ch]) - cpu.total.rgb[i][ch]));
      }
    for (size_t i = 0; i < cpu.total.rgb.size(); ++i)
      idsDiffer += uint64_t((cpu.total.rgb[i] != glm::vec3(0.0f)) != (prt.total.rgb[i] != glm::vec3(0.0f)));
    out << fmt::format("CPU frame {:.3f} s; max |GPU − CPU| / peak {:.3g} over all pixels (G-buffer ties included), "
                       "{} pixels lit on one side only\n",
                       cpu.total.seconds, peak > 0.0 ? diff / peak : 0.0, idsDiffer);
  }
  out << fmt::format("exemplar: {} ({} segments), {} tiles; mean free path {:.5g}, {} IIRTF cells\n", scene.block().label,
                     scene.block().segments.size(), o.frame.tiles, scene.meanFreePath(), scene.cellCount());
  out << fmt::format("bakes: {:.2f} s (setup {:.2f} s; visibility of {} segments, IIRTF of {} cells)\n", scene.bakeSeconds(),
                     setup, scene.svfBaked(), scene.cellsBaked());
  out << fmt::format("PRT{}: {}x{}, G-buffer ids {}, {} px covered, average {:.6g} (single {:.6g}, multiple {:.6g}), "
                     "frame {:.3f} s\n",
                     o.gpu ? " (GPU frame)" : "", prt.total.width, prt.total.height,
                     settings.embreeGBuffer ? "embree" : volumeIdsName(settings.volumeIds), prt.total.covered, prt.total.average(), prt.single.average(),
                     prt.multi.average(), prt.total.seconds);
  const DisplayMapping display{o.exposure, ToneMap::Aces};
  auto write = [&](const std::string& suffix, const PrtFrameImage& im) {
    const ImageRgbaF img = toImage(im);
    writeExr(o.out + suffix + ".exr", img);
    writePngTonemapped(o.out + suffix + ".png", img, display);
    out << fmt::format("wrote {0}{1}.exr, {0}{1}.png\n", o.out, suffix);
  };
  write("_prt", prt.total);
  if (o.noReference) return 0;
  const PrtFrameImage pt = scene.renderPathTraced(view, o.frame.ptSamples, o.frame.maxDepth);
  const PrtFrameComparison cmp = comparePrtFrame(prt.total, pt);
  const PrtFrameImage direct = scene.renderPathTraced(view, o.frame.ptSamples, 1);
  out << fmt::format("path traced: {} spp, {} px covered, average {:.6g} ± {:.2g} (direct {:.6g}), {:.3f} s\n",
                     o.frame.ptSamples, pt.covered, pt.average(), pt.averageStdError, direct.average(), pt.seconds);
  out << fmt::format("per covered pixel: PRT {:.6g} (single {:.6g}, multiple {:.6g}), path traced {:.6g} (direct {:.6g}, "
                     "indirect {:.6g})\n",
                     prt.total.coveredAverage(), prt.single.coveredAverage(), prt.multi.coveredAverage(),
                     pt.coveredAverage(), direct.coveredAverage(), pt.coveredAverage() - direct.coveredAverage());
  out << fmt::format("average intensity error {:.4f} (relative), pixel RMSE {:.4g}, HDR-FLIP mean {:.4f}, "
                     "time ratio path tracing / PRT frame {:.2f}\n",
                     cmp.averageRelError, cmp.pixelRmse, cmp.flipMean, pt.seconds / std::max(1e-9, prt.total.seconds));
  write("_pt", pt);
  return cmp.nonFinite == 0 ? 0 : 1;
}

}  // namespace ft
