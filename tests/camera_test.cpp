// camera_test.cpp — the named views of render/trace do not depend on the
// resolution (issue 14, deliverable 10), and the explicit camera (--eye,
// --target, --fov) is checked and framed. Expected values are written here
// from the definitions (pinhole projection, 1/16 of the frame height), not
// taken from scene/camera.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "scene/camera.h"
#include "scene/default_scene.h"
#include "scene/input_error.h"
#include "scene/yarn_fibers.h"
#include "scene/yarn_preset.h"
#include "scene/yarn_radius.h"

namespace ft {
namespace {

// Pixel position of p through a camera, written from the pinhole model:
// x_px = W/2 + f·(p·right)/(p·forward), y likewise, f = H / (2 tan(fovy/2)).
glm::dvec2 pixelOf(const Camera& c, glm::vec3 p) {
  const glm::dvec3 fwd = glm::normalize(glm::dvec3(c.target) - glm::dvec3(c.eye));
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(c.up)));
  const glm::dvec3 up = glm::cross(right, fwd);
  const glm::dvec3 q = glm::dvec3(p) - glm::dvec3(c.eye);
  const double f = c.height / (2.0 * std::tan(c.fovyDegrees * M_PI / 360.0));
  const double z = glm::dot(q, fwd);
  return {0.5 * c.width + f * glm::dot(q, right) / z, 0.5 * c.height + f * glm::dot(q, up) / z};
}

TEST(Camera, NamedViewsFrameTheSameAtEveryResolution) {
  const YarnModel model = makeDefaultScene();
  const FittedFibers fibers = fitFibers(findYarnPreset("cotton1"), model, FiberOptions{});
  for (const char* name : {"frame", "closeup", "near", "mid", "far"}) {
    SCOPED_TRACE(name);
    const Camera small = namedViewCamera(name, model, fibers.params, {0.3f, 0.5f, 1.0f}, 640, 480);
    const Camera large = namedViewCamera(name, model, fibers.params, {0.3f, 0.5f, 1.0f}, 1280, 960);
    EXPECT_EQ(small.width, 640);
    EXPECT_EQ(large.height, 960);
    // Every control point lands at the same fraction of the frame.
    double worst = 0.0;
    for (const YarnCurve& c : model.curves)
      for (const glm::vec3& p : c.points) {
        const glm::dvec2 a = pixelOf(small, p) / glm::dvec2(640, 480), b = pixelOf(large, p) / glm::dvec2(1280, 960);
        worst = std::max(worst, glm::length(a - b));
      }
    EXPECT_LT(worst, 1e-6) << "framing moved between 640x480 and 1280x960 (fraction of the frame)";
  }
}

// The renderer's per-view culling choice (boxInView): a box is in view when
// every corner lies in front of the eye and projects within `slack` times the
// half-image of the centre (pinhole, written here); the frame view has the
// whole model in view at slack 2, the close-up not even at 4.
TEST(Camera, BoxInViewIsEveryCornerNearTheImage) {
  const YarnModel model = makeDefaultScene();
  const FittedFibers fibers = fitFibers(findYarnPreset("cotton1"), model, FiberOptions{});
  glm::vec3 lo(3e38f), hi(-3e38f);
  for (const YarnCurve& c : model.curves)
    for (const glm::vec3& p : c.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  for (const char* name : {"frame", "closeup", "near", "mid", "far"})
    for (float slack : {1.0f, 2.0f, 4.0f}) {
      SCOPED_TRACE(std::string(name) + " slack " + std::to_string(slack));
      const Camera cam = namedViewCamera(name, model, fibers.params, {0.3f, 0.5f, 1.0f}, 1280, 960);
      bool inside = true;
      for (int c = 0; c < 8; ++c) {
        const glm::vec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
        const glm::dvec2 px = pixelOf(cam, p) - glm::dvec2(640, 480);
        const double depth = glm::dot(glm::dvec3(p - cam.eye), glm::normalize(glm::dvec3(cam.target - cam.eye)));
        inside = inside && depth > 0.0 && std::abs(px.x) <= slack * 640 && std::abs(px.y) <= slack * 480;
      }
      EXPECT_EQ(boxInView(makeViewParams(cam, 1.0f, true, true), lo, hi, slack), inside);
      if (std::string(name) == "frame" && slack == 2.0f) {
        EXPECT_TRUE(inside);
      }
      if (std::string(name) == "closeup") {
        EXPECT_FALSE(inside);
      }
    }
}

TEST(Camera, CloseupSegmentSpansOneSixteenthOfTheHeight) {
  const YarnModel model = makeDefaultScene();
  const FittedFibers fibers = fitFibers(findYarnPreset("cotton1"), model, FiberOptions{});
  std::vector<float> spacing;
  for (const YarnCurve& c : model.curves)
    for (size_t i = 0; i + 1 < c.points.size(); ++i) spacing.push_back(glm::distance(c.points[i], c.points[i + 1]));
  std::nth_element(spacing.begin(), spacing.begin() + spacing.size() / 2, spacing.end());
  const double median = spacing[spacing.size() / 2];
  for (int h : {240, 480, 960, 1440}) {
    const Camera c = namedViewCamera("closeup", model, fibers.params, {0, 0, 1}, h * 4 / 3, h);
    // A segment of median length, across the view at the target's depth.
    const double dist = glm::distance(glm::dvec3(c.eye), glm::dvec3(c.target));
    const double f = h / (2.0 * std::tan(c.fovyDegrees * M_PI / 360.0));
    EXPECT_NEAR(median * f / dist, h / 16.0, 1e-3 * h) << "height " << h;
  }
  // At the named height it is the close-up the harness and README always had.
  const Camera named = namedViewCamera("closeup", model, fibers.params, {0, 0, 1}, 1280, 960);
  const Camera old = closeupCamera(model, 1280, 960, 60.0f);
  EXPECT_EQ(named.eye, old.eye);
  EXPECT_EQ(named.target, old.target);
}

TEST(Camera, ExplicitCameraReplacesTheNamedView) {
  const YarnModel model = makeDefaultScene();
  CameraOverride o;
  o.eye = glm::vec3(0.1f, 2.0f, 0.3f);
  o.target = glm::vec3(0.1f, 0.0f, 0.3f);  // straight down: the up vector must change
  o.fovyDegrees = 25.0f;
  const Camera c = applyCameraOverride(Camera{}, o, model);
  EXPECT_EQ(c.eye, *o.eye);
  EXPECT_EQ(c.target, *o.target);
  EXPECT_EQ(c.fovyDegrees, 25.0f);
  // The target is the image centre; the planes hold every control point.
  const glm::dvec2 centre = pixelOf(c, *o.target + glm::vec3(0.0f, -1e-3f, 0.0f));
  EXPECT_NEAR(centre.x, c.width / 2.0, 1e-6);
  EXPECT_NEAR(centre.y, c.height / 2.0, 1e-6);
  const glm::mat4 vp = c.projection() * c.view();
  for (const YarnCurve& curve : model.curves)
    for (const glm::vec3& p : curve.points) {
      const glm::vec4 clip = vp * glm::vec4(p, 1.0f);
      ASSERT_TRUE(std::isfinite(clip.z) && std::isfinite(clip.w));
      EXPECT_GT(clip.z, -clip.w);
      EXPECT_LT(clip.z, clip.w);
    }
  // Only the given fields change.
  CameraOverride fovOnly;
  fovOnly.fovyDegrees = 10.0f;
  Camera base;
  base.eye = {1, 2, 3};
  const Camera d = applyCameraOverride(base, fovOnly, model);
  EXPECT_EQ(d.eye, base.eye);
  EXPECT_EQ(d.target, base.target);
  EXPECT_EQ(d.fovyDegrees, 10.0f);
}

void expectRefused(const CameraOverride& o, const std::vector<std::string>& parts) {
  try {
    applyCameraOverride(Camera{}, o, makeDefaultScene());
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    for (const std::string& s : parts) EXPECT_NE(what.find(s), std::string::npos) << "missing '" << s << "': " << what;
  }
}

TEST(Camera, ExplicitCameraRefusesBadValues) {
  const float nan = std::nanf(""), inf = INFINITY;
  CameraOverride o;
  o.eye = glm::vec3(nan, 0.0f, 1.0f);
  expectRefused(o, {"--eye", "nan"});
  o = {};
  o.target = glm::vec3(0.0f, inf, 1.0f);
  expectRefused(o, {"--target", "inf"});
  o = {};
  o.eye = o.target = glm::vec3(1.0f, 2.0f, 3.0f);
  expectRefused(o, {"--eye", "--target", "1,2,3", "at the target"});
  o = {};
  o.target = Camera{}.eye;  // the default eye: equal once combined
  expectRefused(o, {"at the target"});
  for (float fov : {0.0f, 180.0f, -5.0f, 200.0f, nan, inf}) {
    o = {};
    o.fovyDegrees = fov;
    expectRefused(o, {"--fov", "(0, 180)"});
  }
  EXPECT_THROW(namedViewCamera("nosuch", makeDefaultScene(), YarnParams{}, {0, 0, 1}, 64, 48), InputError);
}

}  // namespace
}  // namespace ft
