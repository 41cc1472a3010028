#include "scene/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

namespace ft {

glm::mat4 Camera::view() const { return glm::lookAt(eye, target, up); }

glm::mat4 Camera::projection() const {
  return glm::perspective(glm::radians(fovyDegrees), static_cast<float>(width) / static_cast<float>(height), zNear,
                          zFar);
}

float Camera::pixelsPerUnitAtDepth1() const {
  return static_cast<float>(height) / (2.0f * std::tan(glm::radians(fovyDegrees) * 0.5f));
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
