// occlusion_cull_cases.cpp — the shaded frame's occlusion culling
// (common/occlusion_cull.h, FiberRenderer::draw) changes nothing.
//
// shading/occlusion-cull/<view>/<path>: the harness model's shaded frame with
// every approximation of 000 §4 on (the core-fiber texture's holes are what
// the occluder pass must respect), rendered with and without the culling.
// The culling may only drop lines and fragments that would fail the depth
// test, so the two frames must agree bit for bit: no tolerance, no shared
// code with the culling in the check. It is not vacuous: the occluder pass
// must cover a share of the pixels (else nothing is ever culled), and the
// planted faults that make it cull a visible line (a near bound taken on the
// capsule's far side; occluders not pushed back) fail it.
//
// Bit-equal frames show that nothing visible was culled on this scene; they
// do not show that the occluders are right: a line is dropped only when it
// lies behind the deepest occluder sample over its whole rectangle, with a
// margin, so an occluder sample that claims a depth nearer than what the
// frame draws there stays harmless until the margins run out (two such
// errors hid that way from the start: docs/shaded-frame.md, "Wider occluders").
// So the case also compares, sample by sample, the occluder pass's depth
// with the unculled frame's depth buffer: the culling is exact when no
// occluder sample is nearer than the frame (a line that would win a sample
// is nearer there than the frame's depth, hence than the occluder's, so it
// is never dropped).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "validation/case_support.h"
#include "validation/harness_frame.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

// The occluder pass must occlude at least this share of the pixels for the
// equality to mean anything. Measured on the built-in scene at 320 × 240:
// 0.24 (close-up), 0.12 (frame, which leaves most of the image empty).
constexpr double kMinOccludedClose = 0.1, kMinOccludedFrame = 0.05;
// The frame's depth buffer is 24-bit fixed point (rounded to the nearest
// 1 / (2^24 − 1)), the occluder's 32-bit float: an occluder sample counts as
// nearer than the frame only below the frame's depth by more than one step.
constexpr double kDepthStep = 1.0 / 16777215.0;

CaseResult runOcclusionCull(ValidationContext& ctx, const std::string& view, bool tessellation) {
  CaseResult r;
  const char* pathName = tessellation ? "tessellation" : "compute";
  r.name = fmt::format("shading/occlusion-cull/{}/{}", view, pathName);
  r.group = "shading";
  r.path = pathName;
  const auto t0 = Clock::now();
  const AppearanceOptions everything;  // core texture, self-shadow, AO fit, shadow map: the defaults
  const FiberPath path = prepareHarnessFrame(ctx, view, tessellation, everything, kFrameWidth, kFrameHeight);
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  FiberRenderer& renderer = ctx.gpu<FiberRenderer>();
  renderer.setOcclusionCull(true);
  const ImageRgbaF culled = renderer.render(gpu, path, kFrameWidth, kFrameHeight);
  const double occluded = renderer.occludedFraction();
  const std::vector<float> occluderDepth = renderer.readOccluderSampleDepths();
  renderer.setOcclusionCull(false);
  const ImageRgbaF all = renderer.render(gpu, path, kFrameWidth, kFrameHeight);
  const std::vector<float> frameDepth = renderer.readFrameSampleDepths();
  r.gpuMilliseconds = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  r.gpuTiming = "steady_clock: bakes + 2 frames with read-back";

  size_t differing = 0, nonFinite = 0, covered = 0;
  double worst = 0.0;
  for (size_t p = 0; p < all.pixelCount(); ++p) {
    bool differs = false;
    for (int c = 0; c < 4; ++c) {
      const float a = all.pixels[4 * p + c], b = culled.pixels[4 * p + c];
      if (!std::isfinite(a) || !std::isfinite(b)) ++nonFinite;
      if (a != b) differs = true;
      worst = std::isnan(a - b) ? worst : std::max(worst, double(std::abs(a - b)));
    }
    differing += differs;
    covered += all.pixels[4 * p + 3] > 0.0f;
  }
  // Occluder samples nearer than the frame's depth (the sample-exact test of
  // the culling's premise), and how much nearer at worst, in window depth.
  size_t claimed = 0, nearer = 0, depthNonFinite = 0;
  double nearestBy = 0.0;
  const bool depthsRead = !occluderDepth.empty() && occluderDepth.size() == frameDepth.size();
  for (size_t s = 0; depthsRead && s < occluderDepth.size(); ++s) {
    const double o = occluderDepth[s], f = frameDepth[s];
    if (!std::isfinite(o) || !std::isfinite(f)) {
      ++depthNonFinite;
      continue;
    }
    claimed += o < 1.0;
    if (o < f - kDepthStep) {
      ++nearer;
      nearestBy = std::max(nearestBy, f - o);
    }
  }
  const double minOccluded = view == "closeup" ? kMinOccludedClose : kMinOccludedFrame;
  r.metrics = {
      Metric{"nonfinite.gpu", double(nonFinite + depthNonFinite), 0.0, "count", "NaN/Inf are failures (colours and depths)"},
      Metric{"depths.unread", depthsRead ? 0.0 : 1.0, 0.0, "count",
             "the per-sample depths of the occluders and of the frame were read back, at the same size"},
      Metric{"occluder.samples_nearer", double(nearer), 0.0, "count",
             "occluder samples nearer than the unculled frame's depth there by more than its 24-bit step: each "
             "could cull a line that is seen"},
      Metric{"occluder.nearer_max", nearestBy, 0.0, "window depth", "how much nearer, at worst", false},
      Metric{"occluder.samples_claimed", double(claimed), 0.0, "count", "samples with an occluder", false},
      Metric{"pixels.differing", double(differing), 0.0, "count",
             "culling drops only what the depth test would reject: the frames agree bit for bit"},
      Metric{"value.max_abs", worst, 0.0, "radiance", "the largest difference of a channel", false},
      Metric{"occluded.short", std::max(0.0, minOccluded - occluded), 0.0, "fraction",
             fmt::format("the occluder pass covers at least {:.2f} of the pixels (else the check is vacuous)", minOccluded)},
      Metric{"occluded.fraction", occluded, 0.0, "fraction", "pixels with an occluder (pyramid level 0 < 1)", false},
      Metric{"pixels.covered", double(covered), 0.0, "count", "pixels the frame covers", false},
  };
  r.details = fmt::format("{} of {} pixels differ; occluders over {:.3f} of the pixels; {} covered; {} of {} occluder "
                          "samples nearer than the frame",
                          differing, all.pixelCount(), occluded, covered, nearer, claimed);
  r.finish();
  return r;
}

}  // namespace

void addOcclusionCullCases(ValidationContext& /*ctx*/, std::vector<ValidationCase>& out) {
  for (const char* view : {"closeup", "frame"})
    for (bool tessellation : {false, true})
      out.push_back({fmt::format("shading/occlusion-cull/{}/{}", view, tessellation ? "tessellation" : "compute"),
                     [view = std::string(view), tessellation](ValidationContext& c) {
                       return runOcclusionCull(c, view, tessellation);
                     }});
}

}  // namespace ft
