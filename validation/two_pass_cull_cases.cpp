// two_pass_cull_cases.cpp — two-pass culling (common/occlusion_cull.h
// ftLineKey, FiberRenderer::setTwoPassCull) draws what one pass draws.
//
// shading/two-pass-cull/<view>/<path>: the harness model's shaded frame with
// every approximation of 000 §4 on, drawn four times by a renderer with
// two-pass culling: a first frame (which marks the lines it saw), the same
// view again (two-pass from its own lines), the view turned by kTurnDegrees
// about the target and back (each two-pass from the other view's lines: the
// frames of a moving camera). Each is compared with the same view drawn
// without any culling, sample by sample:
//  * the depth buffers must be equal at every sample. The depth test keeps
//    the nearest of what is drawn, whatever the order, so a line the second
//    draw dropped but which would have won a sample shows here; no tolerance.
//  * the colours must be equal at every pixel of the repeated view (the first
//    draw holds every line that won a sample of the one-pass frame before, in
//    the one pass's order). After a turn a sample where a line of the second
//    draw ties with one of the first at its 24-bit depth goes to the first
//    instead of to the earlier in the one pass's order (and the next frame's
//    marks carry that choice on): differing pixels are reported, and allowed
//    only where the depth is equal (which the first check ensures).
//  * in the repeated view the first draw left the frame's own depth, so the
//    pyramid's level 0 must be, at every pixel, the deepest of the frame's
//    four samples (GL's depth buffer, not the pyramid kernel).
//  * every covered sample's line (its key, read back from the frame) is
//    marked for the next frame's first draw, in the first, repeated and
//    turned frames: what makes the pyramid check's premise true. (Two lines
//    can leave bit-identical hit records, and the compaction groups samples
//    by record: marking each group's first line missed 5 samples' lines of
//    the glove.)
// The repeated view's frame alone cannot show a wrong pyramid (nothing
// visible is left for its second draw), hence that check and the turns. It
// is not vacuous: every frame after the
// first must be two-pass, and the second draw must drop some of its lines
// (the pipeline statistics count the triangles). Planted faults: the
// pyramid kept from the previous frame (`two-pass-stale-pyramid`), the
// depth cleared between the draws (`two-pass-depth-cleared`), the pyramid
// kernel run before its layout is bound (`two-pass-pyramid-layout`), the
// compute path's prefilter taking a line's far side (`two-pass-box-far`),
// the marks of each pixel's first line only (`two-pass-mark-first`), and,
// on the glove's close-up, the geometry stage's box of a line's rectangle
// where it draws the larger triangle (`occlusion-box-rectangle`).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>
#include <vector>

#include "validation/case_support.h"
#include "validation/harness_frame.h"

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

// How far the camera turns between the first frame and the moved one: a
// drag of an interactive orbit between two frames (the bench's orbit takes 2°).
constexpr float kTurnDegrees = 3.0f;

struct DrawnFrame {
  ImageRgbaF image;
  std::vector<float> depth;
  FrameTimings timings;
  // The covered samples whose line the compaction did not mark for the next
  // frame's first draw (-1: not read back).
  long long unmarkedSamples = -1;
};

DrawnFrame drawFrame(FiberRenderer& renderer, FiberGpu& gpu, FiberPath path) {
  DrawnFrame f;
  renderer.draw(gpu, path, kFrameWidth, kFrameHeight, &f.timings);
  f.image = renderer.read();
  f.depth = renderer.readFrameSampleDepths();
  const std::vector<uint32_t> lines = renderer.readFrameSampleLines(), marks = renderer.readVisibleLines();
  if (!lines.empty() && !marks.empty()) {
    f.unmarkedSamples = 0;
    for (uint32_t line : lines) {
      if (line == 0) continue;  // no fiber
      const uint32_t key = line - 1;
      f.unmarkedSamples += key / 32 >= marks.size() || ((marks[key / 32] >> (key % 32)) & 1u) == 0;
    }
  }
  return f;
}

struct FrameDifference {
  size_t pixels = 0, depthSamples = 0, nonFinite = 0;
  double maxAbs = 0.0;  // the largest difference of a colour channel
};

FrameDifference compareFrames(const DrawnFrame& a, const DrawnFrame& b) {
  FrameDifference d;
  for (size_t i = 0; i < a.image.pixels.size() && i < b.image.pixels.size(); ++i)
    if (!std::isfinite(a.image.pixels[i]) || !std::isfinite(b.image.pixels[i])) ++d.nonFinite;
  for (size_t p = 0; p < a.image.pixelCount(); ++p) {
    bool differs = false;
    for (int c = 0; c < 4; ++c) {
      const double x = a.image.pixels[4 * p + c], y = b.image.pixels[4 * p + c];
      differs = differs || x != y;
      if (std::isfinite(x - y)) d.maxAbs = std::max(d.maxAbs, std::abs(x - y));
    }
    d.pixels += differs;
  }
  if (a.depth.size() != b.depth.size()) {
    d.depthSamples = std::max(a.depth.size(), b.depth.size());
    return d;
  }
  for (size_t s = 0; s < a.depth.size(); ++s) {
    if (!std::isfinite(a.depth[s]) || !std::isfinite(b.depth[s])) ++d.nonFinite;
    d.depthSamples += a.depth[s] != b.depth[s];
  }
  return d;
}

CaseResult runTwoPassCull(ValidationContext& ctx, const std::string& view, bool tessellation) {
  CaseResult r;
  const char* pathName = tessellation ? "tessellation" : "compute";
  r.name = fmt::format("shading/two-pass-cull/{}/{}", view, pathName);
  r.group = "shading";
  r.path = pathName;
  const auto t0 = Clock::now();
  const AppearanceOptions everything;  // core texture, self-shadow, AO fit, shadow map: the defaults
  const FiberPath path = prepareHarnessFrame(ctx, view, tessellation, everything, kFrameWidth, kFrameHeight);
  FiberGpu& gpu = ctx.gpu<FiberGpu>();
  // A renderer of its own: its first pyramid is the two-pass one (the shared
  // renderer's earlier frames would leave one behind, and hide a pyramid
  // built from a stale layout, as one was).
  FiberRenderer renderer(ctx.gl(), ctx.defines());
  renderer.setShading(ctx.gpu<FiberRenderer>().shading());
  const ViewParams still = gpu.view();
  const Camera camera =
      namedViewCamera(view, ctx.model(), gpu.params(), glm::vec3(0.3f, 0.5f, 1.0f), kFrameWidth, kFrameHeight);
  Camera turnedCamera = camera;
  const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(kTurnDegrees), glm::normalize(camera.up));
  turnedCamera.eye = camera.target + glm::vec3(turn * glm::vec4(camera.eye - camera.target, 0.0f));
  const ViewParams turned = makeViewParams(turnedCamera, ctx.options().lodThresholdPx, true, true);

  // Two-pass: a first frame, the same view again, the turned view, back.
  renderer.setOcclusionCull(FiberRenderer::OcclusionCull::Auto);
  renderer.setTwoPassCull(true);
  renderer.forgetVisibility();
  const DrawnFrame first = drawFrame(renderer, gpu, path);
  const DrawnFrame again = drawFrame(renderer, gpu, path);
  const std::vector<float> pyramid = renderer.readPyramidLevel0();
  gpu.setParams(gpu.params(), turned);
  const DrawnFrame moved = drawFrame(renderer, gpu, path);
  gpu.setParams(gpu.params(), still);
  const DrawnFrame back = drawFrame(renderer, gpu, path);
  // One pass, nothing culled: the same two views.
  renderer.setOcclusionCull(FiberRenderer::OcclusionCull::Off);
  const DrawnFrame stillAll = drawFrame(renderer, gpu, path);
  gpu.setParams(gpu.params(), turned);
  const DrawnFrame movedAll = drawFrame(renderer, gpu, path);
  gpu.setParams(gpu.params(), still);
  renderer.setOcclusionCull(FiberRenderer::OcclusionCull::Auto);
  renderer.setTwoPassCull(false);
  r.gpuMilliseconds = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  r.gpuTiming = "steady_clock: bakes + 6 frames with read-back";

  const FrameDifference firstDiff = compareFrames(first, stillAll), againDiff = compareFrames(again, stillAll),
                        movedDiff = compareFrames(moved, movedAll), backDiff = compareFrames(back, stillAll);
  const bool depthsRead = !stillAll.depth.empty() && !movedAll.depth.empty();
  const bool twoPass = !first.timings.twoPass && moved.timings.twoPass && back.timings.twoPass && again.timings.twoPass;
  // The repeated view's pyramid against the deepest of each pixel's samples.
  size_t pyramidDiffering = 0;
  const size_t pixels = size_t(kFrameWidth) * kFrameHeight;
  const bool pyramidRead = pyramid.size() == pixels && again.depth.size() == 4 * pixels;
  for (size_t p = 0; pyramidRead && p < pixels; ++p) {
    float deepest = 0.0f;
    for (size_t s = 0; s < 4; ++s) deepest = std::max(deepest, again.depth[4 * p + s]);
    pyramidDiffering += !(pyramid[p] == deepest);
  }
  // The second draw's share of the lines it dropped: its triangles are the
  // frame's less the first draw's, against the one pass's.
  const auto secondDrawKept = [&](const DrawnFrame& f, const DrawnFrame& all) {
    const double second = double(f.timings.shadePrimitives) - double(f.timings.firstDrawPrimitives);
    const double rest = double(all.timings.shadePrimitives) - double(f.timings.firstDrawPrimitives);
    return rest > 0.0 ? second / rest : 1.0;
  };
  const bool counted = stillAll.timings.shadePrimitives > 0;
  const double keptStill = secondDrawKept(again, stillAll), keptMoved = secondDrawKept(moved, movedAll);
  r.metrics = {
      Metric{"nonfinite.gpu", double(firstDiff.nonFinite + againDiff.nonFinite + movedDiff.nonFinite + backDiff.nonFinite),
             0.0, "count",
             "NaN/Inf are failures (colours and depths)"},
      Metric{"depths.unread", depthsRead ? 0.0 : 1.0, 0.0, "count", "the frames' per-sample depths were read back"},
      Metric{"two_pass.unused", twoPass ? 0.0 : 1.0, 0.0, "count",
             "the first frame is one pass, the three after it two-pass (else the check is vacuous)"},
      Metric{"marks.unmarked_samples",
             double(first.unmarkedSamples < 0 || again.unmarkedSamples < 0 || moved.unmarkedSamples < 0
                        ? pixels * 4
                        : first.unmarkedSamples + again.unmarkedSamples + moved.unmarkedSamples),
             0.0, "count",
             "covered samples of the first, repeated and turned frames whose line (key, read from the frame) the "
             "compaction left unmarked: the next frame's first draw would not hold it"},
      Metric{"first.pixels_differing", double(firstDiff.pixels + firstDiff.depthSamples), 0.0, "count",
             "the first frame (the per-view occluder choice) against one pass without culling"},
      Metric{"still.depth_samples_differing", double(againDiff.depthSamples), 0.0, "count",
             "two-pass from the same view's lines: the depth buffer at every sample as without culling"},
      Metric{"still.pixels_differing", double(againDiff.pixels), 0.0, "count",
             "two-pass from the same view's lines: the first draw holds every line that wins a sample, in "
             "the one pass's order, so the frames agree bit for bit"},
      Metric{"still.pyramid_texels_differing", pyramidRead ? double(pyramidDiffering) : double(pixels), 0.0, "count",
             "the repeated view's pyramid level 0 at each pixel: the deepest of the frame's four samples"},
      Metric{"moved.depth_samples_differing", double(movedDiff.depthSamples + backDiff.depthSamples), 0.0, "count",
             fmt::format("two-pass after the camera turned {}° and back: nothing that would win a sample was "
                         "dropped (the depth test keeps the nearest, whatever the order)",
                         kTurnDegrees)},
      Metric{"moved.pixels_differing", double(movedDiff.pixels + backDiff.pixels), 0.0, "count",
             "pixels where a tie at a sample's 24-bit depth went to the line drawn first (the depth is equal)",
             false},
      Metric{"moved.value_max_abs", std::max(movedDiff.maxAbs, backDiff.maxAbs), 0.0, "radiance",
             "at those pixels, the largest difference of a channel (the two lines' shading at one point)", false},
      Metric{"lines.uncounted", counted ? 0.0 : 1.0, 0.0, "count",
             "the driver counts the geometry stage's triangles (else the share below is unknown)"},
      Metric{"second_draw.kept_still", keptStill, 0.9, "fraction",
             "of the lines the first draw left, the share the second draw still drew (the repeated view); at most "
             "0.9, else the culling does nothing"},
      Metric{"second_draw.kept_moved", keptMoved, 0.0, "fraction", "the same after the turn", false},
  };
  r.details = fmt::format(
      "repeated: {} pixels, {} depth samples, {} pyramid texels differ; turned {}° and back: {} pixels (at most "
      "{:.3g} in a channel), {} depth samples differ; triangles: "
      "one pass {} / {}, two-pass first draw {} / {}, both {} / {} (repeated / turned)",
      againDiff.pixels, againDiff.depthSamples, pyramidDiffering, kTurnDegrees, movedDiff.pixels + backDiff.pixels,
      std::max(movedDiff.maxAbs, backDiff.maxAbs), movedDiff.depthSamples + backDiff.depthSamples,
      stillAll.timings.shadePrimitives, movedAll.timings.shadePrimitives, again.timings.firstDrawPrimitives,
      moved.timings.firstDrawPrimitives, again.timings.shadePrimitives, moved.timings.shadePrimitives);
  r.finish();
  return r;
}

}  // namespace

void addTwoPassCullCases(ValidationContext& /*ctx*/, std::vector<ValidationCase>& out) {
  for (const char* view : {"closeup", "frame"})
    for (bool tessellation : {false, true})
      out.push_back({fmt::format("shading/two-pass-cull/{}/{}", view, tessellation ? "tessellation" : "compute"),
                     [view = std::string(view), tessellation](ValidationContext& c) {
                       return runTwoPassCull(c, view, tessellation);
                     }});
}

}  // namespace ft
