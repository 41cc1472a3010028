// camera.h — a pinhole camera and the ViewParams block it yields, plus the
// three standard LoD distances the harness and benchmarks use.
#pragma once
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

}  // namespace ft
