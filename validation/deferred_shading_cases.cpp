// deferred_shading_cases.cpp — deferred shading of the frame
// (FiberRenderer::drawDeferred, docs/shaded-frame.md) changes nothing.
//
// shading/deferred/<view>/<path>: the harness model's shaded frame with every
// approximation of 000 §4 on (core texture, self-shadow, AO, shadow map),
// occlusion culling on, drawn by the forward pass (every fragment shaded in
// the fragment stage) and by deferred shading (a visibility pass writes each
// fragment's hit; each pixel's distinct hits are listed, shaded by the same
// shadeFiber in a compute stage and written to their samples). The deferred
// frame must be the forward one bit for bit: each sample gets the colour the
// forward pass gave the fragment that won it. No tolerance; the check shares
// no code with the deferred passes. shading/deferred/closeup/compute/extras
// does the same with dual scattering and soft shadows (two of the other
// compiled variants of shadeFiber; the SRBF environment's bake alone would
// make the case too long for CI).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "validation/case_support.h"
#include "validation/harness_frame.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

// Not vacuous: the frame must cover pixels, and some pixel must hold more
// than one distinct hit (an edge between fibers), where the compaction's
// grouping of samples matters. Measured on the built-in scene at 320 × 240:
// 31,294 covered pixels and 14,358 hits beyond one per pixel (close-up),
// 16,235 and 6,489 (frame).
constexpr double kMinCovered = 1000, kMinSplitPixels = 100;
// The colours agree within this share of their value, not bit for bit: the
// visibility pass and the shading kernel are other shaders than the forward
// pass, and Mesa's NIR lowers mix() and rewrites inexact sums by what else a
// shader computes, so the hit and the shading round differently in the last
// bits (the 1°-wide lobes of cotton amplify an ulp of the angles). Measured
// on these cases: at most 5.3e-6 (close-up), 5.2e-6 (frame), 5.4e-6 (extras).
constexpr double kRelativeBound = 1e-4;

CaseResult runDeferred(ValidationContext& ctx, const std::string& view, bool tessellation, bool extras) {
  CaseResult r;
  const char* pathName = tessellation ? "tessellation" : "compute";
  r.name = fmt::format("shading/deferred/{}/{}{}", view, pathName, extras ? "/extras" : "");
  r.group = "shading";
  r.path = pathName;
  const auto t0 = Clock::now();
  AppearanceOptions appearance;  // core texture, self-shadow, AO fit, shadow map: the defaults
  if (extras) {
    appearance.dualScattering = true;
    appearance.softShadows = true;
  }
  const FiberPath path = prepareHarnessFrame(ctx, view, tessellation, appearance, kFrameWidth, kFrameHeight);
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  FiberRenderer& renderer = ctx.gpu<FiberRenderer>();
  renderer.setDeferred(false);
  const ImageRgbaF forward = renderer.render(gpu, path, kFrameWidth, kFrameHeight);
  renderer.setDeferred(true);
  const ImageRgbaF deferred = renderer.render(gpu, path, kFrameWidth, kFrameHeight);
  const double hits = double(renderer.deferredEntries());
  r.gpuMilliseconds = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  r.gpuTiming = "steady_clock: bakes + 2 frames with read-back";

  size_t differing = 0, beyond = 0, alphaDiffering = 0, nonFinite = 0, covered = 0, partial = 0;
  double worst = 0.0, worstRel = 0.0;
  for (size_t p = 0; p < forward.pixelCount(); ++p) {
    bool differs = false, out = false;
    for (int c = 0; c < 4; ++c) {
      const float a = forward.pixels[4 * p + c], b = deferred.pixels[4 * p + c];
      if (!std::isfinite(a) || !std::isfinite(b)) ++nonFinite;
      if (a != b) differs = true;
      if (c == 3 && a != b) ++alphaDiffering;
      const double d = std::abs(double(a) - double(b)), scale = std::max(std::abs(double(a)), std::abs(double(b)));
      if (!(d <= kRelativeBound * scale)) out = true;  // NaN: out
      if (std::isfinite(d)) {
        worst = std::max(worst, d);
        if (scale > 0.0) worstRel = std::max(worstRel, d / scale);
      }
    }
    differing += differs;
    beyond += out;
    const float alpha = forward.pixels[4 * p + 3];
    covered += alpha > 0.0f;
    partial += alpha > 0.0f && alpha < 1.0f;
  }
  // Pixels with more than one distinct hit: at least the hits beyond one per covered pixel.
  const double split = hits - double(covered);
  r.metrics = {
      Metric{"nonfinite.gpu", double(nonFinite), 0.0, "count", "NaN/Inf are failures"},
      Metric{"pixels.differing", double(beyond), 0.0, "count",
             fmt::format("pixels with a channel off by more than {:.0e} of its value: each sample gets the colour the "
                         "forward pass gave the fragment that won it, up to float rounding of the same expressions "
                         "compiled in other shaders (docs/shaded-frame.md)",
                         kRelativeBound)},
      Metric{"alpha.differing", double(alphaDiffering), 0.0, "count",
             "coverage is the same code in the same stage: the alpha (samples covered) agrees bit for bit"},
      Metric{"pixels.not_identical", double(differing), 0.0, "count", "pixels not bit-identical", false},
      Metric{"value.max_abs", worst, 0.0, "radiance", "the largest difference of a channel", false},
      Metric{"value.max_rel", worstRel, 0.0, "fraction", "the largest difference of a channel over its value", false},
      Metric{"covered.short", std::max(0.0, kMinCovered - double(covered)), 0.0, "count",
             fmt::format("the frame covers at least {:.0f} pixels (else the check is vacuous)", kMinCovered)},
      Metric{"split.short", std::max(0.0, kMinSplitPixels - split), 0.0, "count",
             fmt::format("at least {:.0f} more hits than covered pixels (pixels split between fibers)", kMinSplitPixels)},
      Metric{"hits.shaded", hits, 0.0, "count", "distinct hits the deferred frame shaded", false},
      Metric{"pixels.covered", double(covered), 0.0, "count", "pixels the frame covers", false},
      Metric{"pixels.partial", double(partial), 0.0, "count", "pixels covered at some samples only", false},
  };
  r.details = fmt::format("{} of {} pixels not identical (max |Δ| {:.3g}, max relative {:.3g}), {} beyond the bound; "
                          "{} covered, {} partly; {} hits shaded",
                          differing, forward.pixelCount(), worst, worstRel, beyond, covered, partial, size_t(hits));
  r.finish();
  return r;
}

}  // namespace

void addDeferredShadingCases(ValidationContext& /*ctx*/, std::vector<ValidationCase>& out) {
  for (const char* view : {"closeup", "frame"})
    for (bool tessellation : {false, true})
      out.push_back({fmt::format("shading/deferred/{}/{}", view, tessellation ? "tessellation" : "compute"),
                     [view = std::string(view), tessellation](ValidationContext& c) {
                       return runDeferred(c, view, tessellation, false);
                     }});
  out.push_back({"shading/deferred/closeup/compute/extras",
                 [](ValidationContext& c) { return runDeferred(c, "closeup", false, true); }});
}

}  // namespace ft
