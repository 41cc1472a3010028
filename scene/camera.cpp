#include "scene/camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <limits>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/input_error.h"

namespace ft {

glm::mat4 Camera::view() const { return glm::lookAt(eye, target, up); }

glm::mat4 Camera::projection() const {
  return glm::perspective(glm::radians(fovyDegrees), static_cast<float>(width) / static_cast<float>(height), zNear,
                          zFar);
}

float Camera::pixelsPerUnitAtDepth1() const {
  return static_cast<float>(height) / (2.0f * std::tan(glm::radians(fovyDegrees) * 0.5f));
}

bool boxInView(const ViewParams& view, glm::vec3 lo, glm::vec3 hi, float slack) {
  for (int c = 0; c < 8; ++c) {
    const glm::vec4 clip = view.viewProj * glm::vec4((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z, 1.0f);
    if (!(clip.w > 0.0f) || std::abs(clip.x) > slack * clip.w || std::abs(clip.y) > slack * clip.w) return false;
  }
  return true;
}

ViewParams makeViewParams(const Camera& camera, float lodThresholdPx, bool lodEnabled, bool cullEnabled,
                          float chordErrorPx) {
  ViewParams v{};
  v.viewProj = camera.projection() * camera.view();
  // Gribb–Hartmann plane extraction: rows of viewProj combined; normalized so
  // plane distances are in world units (the culling margin is in world units).
  const glm::mat4 m = glm::transpose(v.viewProj);  // m[i] = row i
  const glm::vec4 planes[6] = {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2], m[3] - m[2]};
  for (int i = 0; i < 6; ++i) v.frustumPlanes[i] = planes[i] / glm::length(glm::vec3(planes[i]));
  v.cameraPos = glm::vec4(camera.eye, camera.pixelsPerUnitAtDepth1());
  v.lodThresholdPx = lodThresholdPx;
  v.lodEnabled = lodEnabled ? 1u : 0u;
  v.cullEnabled = cullEnabled ? 1u : 0u;
  v.chordErrorPx = chordErrorPx;
  return v;
}

Camera frameModel(const YarnModel& model, glm::vec3 viewDir, int width, int height) {
  const Bounds b = modelBounds(model);
  const glm::vec3 center = 0.5f * (b.lo + b.hi);
  const float radius = std::max(0.5f * glm::length(b.hi - b.lo), 1e-3f);
  Camera c;
  c.width = width;
  c.height = height;
  c.target = center;
  const glm::vec3 back = glm::normalize(viewDir);  // from the target towards the eye
  if (std::abs(glm::dot(back, c.up)) > 0.99f) c.up = glm::vec3(0.0f, 0.0f, 1.0f);
  // The nearest distance at which every control point lies inside the
  // frustum, plus 4% of margin; at most the bounding sphere's distance.
  const glm::vec3 right = glm::normalize(glm::cross(c.up, back));
  const glm::vec3 up = glm::cross(back, right);
  const double tanY = std::tan(glm::radians(c.fovyDegrees) * 0.5);
  const double tanX = tanY * width / height;
  double distance = 0.0;
  for (const YarnCurve& curve : model.curves)
    for (const glm::vec3& p : curve.points) {
      const glm::dvec3 q(p - center);
      const double z = glm::dot(q, glm::dvec3(back));
      distance = std::max({distance, z + std::abs(glm::dot(q, glm::dvec3(right))) / tanX,
                           z + std::abs(glm::dot(q, glm::dvec3(up))) / tanY});
    }
  const float sphere = radius / std::sin(glm::radians(c.fovyDegrees) * 0.5f);
  const float d = std::min(sphere, static_cast<float>(distance * 1.04));
  c.eye = center + back * d;
  c.zNear = std::max(d - radius, d * 1e-3f);
  c.zFar = d + radius;
  return c;
}

const char* lodDistanceName(LodDistance d) {
  switch (d) {
    case LodDistance::Near: return "near";
    case LodDistance::Mid: return "mid";
    case LodDistance::Far: return "far";
  }
  return "?";
}

namespace {
glm::vec3 controlPointNearCentre(const YarnModel& model) {
  const Bounds b = modelBounds(model);
  const glm::vec3 center = 0.5f * (b.lo + b.hi);
  glm::vec3 target = center;
  float best = std::numeric_limits<float>::max();
  for (const YarnCurve& c : model.curves)
    for (const glm::vec3& p : c.points)
      if (float d = glm::distance(p, center); d < best) best = d, target = p;
  return target;
}
}  // namespace

Camera closeupCamera(const YarnModel& model, int width, int height, float segmentPixels) {
  std::vector<float> spacing;
  for (const YarnCurve& c : model.curves)
    for (size_t i = 0; i + 1 < c.points.size(); ++i) spacing.push_back(glm::distance(c.points[i], c.points[i + 1]));
  float median = 1.0f;
  if (!spacing.empty()) {
    std::nth_element(spacing.begin(), spacing.begin() + spacing.size() / 2, spacing.end());
    median = spacing[spacing.size() / 2];
  }
  Camera c;
  c.width = width;
  c.height = height;
  const float d = median * c.pixelsPerUnitAtDepth1() / segmentPixels;
  const Bounds b = modelBounds(model);
  c.target = controlPointNearCentre(model);
  c.eye = c.target + glm::normalize(glm::vec3(0.3f, 0.5f, 1.0f)) * d;
  c.zNear = d * 0.01f;
  c.zFar = d + glm::length(b.hi - b.lo) + 1.0f;
  return c;
}

Camera lodCamera(const YarnModel& model, const YarnParams& params, LodDistance distance, float lodThresholdPx,
                 int width, int height) {
  const Bounds b = modelBounds(model);
  const glm::vec3 target = controlPointNearCentre(model);

  Camera c;
  c.width = width;
  c.height = height;
  const float pixels = c.pixelsPerUnitAtDepth1();
  const float fiberWidth = 2.0f * params.fiberRadius;
  const float plyWidth = 2.0f * params.ellipseB * params.rhoMax;
  float d = 1.0f;
  switch (distance) {
    case LodDistance::Near: d = fiberWidth * pixels / (1.5f * lodThresholdPx); break;
    case LodDistance::Mid: d = std::sqrt(fiberWidth * plyWidth) * pixels / lodThresholdPx; break;
    case LodDistance::Far: d = plyWidth * pixels / (0.5f * lodThresholdPx); break;
  }
  const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, 0.5f, 1.0f));
  c.target = target;
  c.eye = target + dir * d;
  const float radius = 0.5f * glm::length(b.hi - b.lo);
  c.zNear = d * 0.01f;
  c.zFar = d + 2.0f * radius + 1.0f;
  return c;
}

}  // namespace ft

namespace ft {

Camera namedViewCamera(std::string_view distance, const YarnModel& model, const YarnParams& params,
                       glm::vec3 viewDir, int width, int height) {
  // Made at kNamedViewHeight with the requested aspect ratio, then resized.
  const int h = kNamedViewHeight;
  const int w = std::max(1, static_cast<int>(std::lround(double(width) * h / std::max(height, 1))));
  Camera c;
  if (distance == "frame") c = frameModel(model, viewDir, w, h);
  else if (distance == "near") c = lodCamera(model, params, LodDistance::Near, 1.0f, w, h);
  else if (distance == "mid") c = lodCamera(model, params, LodDistance::Mid, 1.0f, w, h);
  else if (distance == "far") c = lodCamera(model, params, LodDistance::Far, 1.0f, w, h);
  else if (distance == "closeup") c = closeupCamera(model, w, h, kCloseupSegmentPixelsAtNamedHeight);
  else
    throw InputError("--distance: '" + std::string(distance) + "' is not frame, closeup, near, mid or far");
  c.width = width;
  c.height = height;
  return c;
}

namespace {
std::string pointText(glm::vec3 v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%g,%g,%g", v.x, v.y, v.z);
  return buf;
}
}  // namespace

Camera applyCameraOverride(Camera c, const CameraOverride& o, const YarnModel& model) {
  if (!o.any()) return c;
  auto finite = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (o.eye && !finite(*o.eye)) throw InputError("--eye: '" + pointText(*o.eye) + "' is not a finite point x,y,z");
  if (o.target && !finite(*o.target))
    throw InputError("--target: '" + pointText(*o.target) + "' is not a finite point x,y,z");
  if (o.fovyDegrees && !(std::isfinite(*o.fovyDegrees) && *o.fovyDegrees > 0.0f && *o.fovyDegrees < 180.0f)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", *o.fovyDegrees);
    throw InputError(std::string("--fov: ") + buf + " is not a vertical field of view in (0, 180) degrees");
  }
  if (o.eye) c.eye = *o.eye;
  if (o.target) c.target = *o.target;
  if (o.fovyDegrees) c.fovyDegrees = *o.fovyDegrees;
  const glm::dvec3 dir = glm::dvec3(c.target) - glm::dvec3(c.eye);
  const double len = glm::length(dir);
  // An eye within float rounding of the target gives lookAt no direction.
  if (!(len > 1e-6 * std::max({1.0, glm::length(glm::dvec3(c.eye)), glm::length(glm::dvec3(c.target))})))
    throw InputError("--eye " + pointText(c.eye) + " and --target " + pointText(c.target) +
                     ": the eye is at the target, so there is no view direction");
  c.up = glm::vec3(0.0f, 1.0f, 0.0f);
  if (std::abs(glm::dot(dir / len, glm::dvec3(c.up))) > 0.99) c.up = glm::vec3(0.0f, 0.0f, 1.0f);
  // Planes around the model's bounding sphere (control points, plus half
  // again for the fibers around them); the near plane never closer than
  // 1e-4 of the far one (24-bit depth).
  const Bounds b = modelBounds(model);
  const double radius = 1.5 * std::max(0.5 * glm::length(glm::dvec3(b.hi - b.lo)), 1e-3);
  const double d = glm::length(glm::dvec3(c.eye) - 0.5 * glm::dvec3(b.lo + b.hi));
  c.zFar = static_cast<float>(d + radius);
  c.zNear = static_cast<float>(std::max(d - radius, 1e-4 * c.zFar));
  return c;
}

}  // namespace ft
