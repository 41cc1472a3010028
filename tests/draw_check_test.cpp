// What `render` and `knit` check before drawing (validation/draw_check.h):
// every NaN/Inf or non-unit frame, control point or length is refused with
// the yarn and the knot (or point) named. End-to-end through the program:
// tests/render_refuses_nan_test.sh.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "reference/fiber_reference.h"
#include "scene/default_scene.h"
#include "validation/draw_check.h"

namespace ft {
namespace {

std::string refusal(const YarnBuffers& y, const std::vector<FrameNormal>& f) {
  try {
    checkBeforeDrawing("model.bcc", y, f);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(DrawCheck, AcceptsTheReferenceFramesAndRefusesEachKindOfBadValue) {
  const YarnBuffers good = buildYarnBuffers(makeDefaultScene());
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(good);
  EXPECT_EQ(refusal(good, frames), "");

  const CurveInfo& c = good.curves[3];
  for (float bad : {NAN, INFINITY, 0.0f, 2.0f}) {
    std::vector<FrameNormal> f = frames;
    f[c.frameBase + 4].normal = glm::vec4(bad, 0.0f, 0.0f, 0.0f);
    const std::string what = refusal(good, f);
    EXPECT_NE(what.find("model.bcc: yarn 3: knot 4: frame normal"), std::string::npos) << bad << ": " << what;
  }
  YarnBuffers y = good;
  y.points[c.firstPoint + 2].positionLength.y = NAN;
  EXPECT_NE(refusal(y, frames).find("yarn 3: point 2"), std::string::npos) << refusal(y, frames);
  y = good;
  y.points[c.firstPoint + 2].positionLength.w = INFINITY;
  EXPECT_NE(refusal(y, frames).find("yarn 3: point 2"), std::string::npos) << refusal(y, frames);
  std::vector<FrameNormal> shortFrames(frames.begin(), frames.end() - 1);
  EXPECT_NE(refusal(good, shortFrames).find("knot frames"), std::string::npos);
}

}  // namespace
}  // namespace ft
