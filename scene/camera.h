// camera.h — a pinhole camera and the ViewParams block it yields, plus the
// three standard LoD distances the harness and benchmarks use.
#pragma once
#include <optional>
#include <string_view>

#include "common/view_params.h"
#include "common/yarn_params.h"
#include "scene/yarn_model.h"

namespace ft {

struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovyDegrees = 40.0f;
  int width = 640;
  int height = 480;
  float zNear = 0.01f;
  float zFar = 1000.0f;

  glm::mat4 view() const;
  glm::mat4 projection() const;
  float pixelsPerUnitAtDepth1() const;  // H / (2 tan(fovy/2))
};

// Default target chord error of fiber polylines on screen (common/lod.h):
// a quarter pixel keeps the drawn curve within the pixel that the exact
// curve covers, so no kink shows at any distance. 0 draws every segment
// with the --subdivisions cap (tests that need a fixed count).
inline constexpr float kDefaultChordErrorPx = 0.25f;

ViewParams makeViewParams(const Camera& camera, float lodThresholdPx, bool lodEnabled, bool cullEnabled,
                          float chordErrorPx = kDefaultChordErrorPx);

// Whether the box [lo, hi] is in view, give or take: every corner in front
// of the eye and projected within `slack` times the image's half-size of its
// centre (NDC |x|, |y| <= slack). FiberRenderer's per-view choice of
// occlusion culling uses slack 2 (the whole model in view: `--distance frame`
// fits the control points, whose box corners may lie a little outside;
// docs/shaded-frame.md).
bool boxInView(const ViewParams& view, glm::vec3 lo, glm::vec3 hi, float slack);

// Camera that frames the whole model from direction `viewDir` (from the target).
Camera frameModel(const YarnModel& model, glm::vec3 viewDir, int width, int height);

// LoD distances (§3.3, eq. 4), measured from a control point near the model
// centre, so each exercises one branch of eq. 4 for the segments near it:
//  near: ω^fiber = 1.5 ω^LoD  (λ = 1, full detail; most of the model is culled),
//  mid:  ω^LoD is the geometric mean of ω^fiber and ω^ply (0 < λ < 1),
//  far:  ω^ply = 0.5 ω^LoD   (λ = 0, core fibers only).
enum class LodDistance { Near, Mid, Far };

// Close-up: the camera looks at the control point nearest the model centre
// from the distance at which a typical yarn segment (the median distance of
// consecutive control points) spans `segmentPixels` on screen — near enough
// that a segment drawn as one straight line would show as a kink.
Camera closeupCamera(const YarnModel& model, int width, int height, float segmentPixels = 60.0f);
const char* lodDistanceName(LodDistance d);
Camera lodCamera(const YarnModel& model, const YarnParams& params, LodDistance distance, float lodThresholdPx,
                 int width, int height);

// The named views of `render` and `trace` (--distance frame, closeup, near,
// mid, far) are made at this frame height and then given the requested size,
// so the framing does not depend on the resolution (only the aspect ratio
// widens or narrows the view). The LoD branch each LoD distance names holds
// exactly at this height (the default 1280x960); at other heights the same
// picture is drawn with the LoD that its pixels ask for.
inline constexpr int kNamedViewHeight = 960;
// Close-up of the named views: a typical segment spans 60 px of 960, 1/16 of
// the frame height.
inline constexpr float kCloseupSegmentPixelsAtNamedHeight = 60.0f;
// InputError (naming --distance) for an unknown name.
Camera namedViewCamera(std::string_view distance, const YarnModel& model, const YarnParams& params,
                       glm::vec3 viewDir, int width, int height);

// An explicit camera (--eye, --target, --fov): each given value replaces the
// base camera's; near and far planes then follow the model's bounds.
struct CameraOverride {
  std::optional<glm::vec3> eye, target;
  std::optional<float> fovyDegrees;
  bool any() const { return eye || target || fovyDegrees; }
};
// InputError naming the option and value for a non-finite point, an eye at
// the target, or a field of view outside (0, 180) degrees.
Camera applyCameraOverride(Camera base, const CameraOverride& override, const YarnModel& model);

}  // namespace ft
