#include "validation/case_support.h"
#include "validation/core_texture_oracle.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ft::oracle {
namespace {
}

// Eq. 1–2 of 000 §2.2 in a circular ply: R(θ) = R_i (R_min + (R_max − R_min)
// (1 − cos(2π f)) / 2), f = phase + θ / 2π + ½ for s = 1 (a period starts at
// R_min, as scene/yarn_fibers and common/fiber_geometry fix the phase), at the
// polar angle ±(θ_i + θ).
glm::dvec3 corePoint(const CoreHelixSet& set, const CoreHelix& f, double theta) {
  const double frac = f.phaseTurns + theta / (2.0 * kPi) + 0.5;
  const double r = set.scale * f.radius * (set.rhoMin + (set.rhoMax - set.rhoMin) * 0.5 * (1.0 - std::cos(2.0 * kPi * frac)));
  const double polar = set.clockSign * (2.0 * kPi * f.thetaTurns + theta);
  return {r * std::cos(polar), r * std::sin(polar), set.alpha * theta / (2.0 * kPi)};
}

glm::dvec3 coreTangent(const CoreHelixSet& set, const CoreHelix& f, double theta) {
  const double h = 1e-5;
  return glm::normalize(corePoint(set, f, theta + h) - corePoint(set, f, theta - h));
}

NearestCore nearestCorePoint(const CoreHelixSet& set, const glm::dvec3& p, double window) {
  NearestCore best;
  best.distance = std::numeric_limits<double>::infinity();
  const double centre = 2.0 * kPi * p.z / set.alpha;
  constexpr int kSamples = 16;
  const double rp = std::hypot(p.x, p.y);
  // Pass 1: coarse samples of every fiber that can come near p (the helix
  // stays between rLo and rHi from the axis); the minimum lies at most one
  // chord below the coarse minimum.
  struct Coarse {
    size_t fiber;
    double theta, distance, bound;
  };
  std::vector<Coarse> coarse;
  for (size_t i = 0; i < set.fibers.size(); ++i) {
    const CoreHelix& f = set.fibers[i];
    const double rLo = set.scale * f.radius * std::min(set.rhoMin, set.rhoMax);
    const double rHi = set.scale * f.radius * std::max(set.rhoMin, set.rhoMax);
    if (!coarse.empty() && std::max(rLo - rp, rp - rHi) > coarse.front().distance) continue;
    double bt = centre - window, bd = glm::length(corePoint(set, f, bt) - p), chord = 0.0;
    glm::dvec3 prev = corePoint(set, f, bt);
    for (int s = 1; s <= kSamples; ++s) {
      const double t = centre - window + 2.0 * window * s / kSamples;
      const glm::dvec3 q = corePoint(set, f, t);
      chord = std::max(chord, glm::length(q - prev));
      prev = q;
      const double d = glm::length(q - p);
      if (d < bd) bd = d, bt = t;
    }
    coarse.push_back({i, bt, bd, bd - chord});
    if (bd < coarse.front().distance) std::swap(coarse.front(), coarse.back());  // front: the best coarse distance
  }
  // Pass 2: a golden-section search around each coarse minimum that can still win
  // (the distance is unimodal within one sample step of its minimum at this scale).
  for (const Coarse& c : coarse) {
    if (c.bound > best.distance) continue;
    const CoreHelix& f = set.fibers[c.fiber];
    const auto dist = [&](double t) { return glm::length(corePoint(set, f, t) - p); };
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double lo = c.theta - 2.0 * window / kSamples, hi = c.theta + 2.0 * window / kSamples;
    double a = hi - g * (hi - lo), b = lo + g * (hi - lo), fa = dist(a), fb = dist(b);
    for (int it = 0; it < 50; ++it) {
      if (fa < fb) hi = b, b = a, fb = fa, a = hi - g * (hi - lo), fa = dist(a);
      else lo = a, a = b, fa = fb, b = lo + g * (hi - lo), fb = dist(b);
    }
    const double t = 0.5 * (lo + hi);
    const double d = dist(t);
    if (d < best.distance) {
      best.fiber = int(c.fiber);
      best.theta = t;
      best.distance = d;
    }
  }
  if (best.fiber >= 0) best.tangent = coreTangent(set, set.fibers[size_t(best.fiber)], best.theta);
  return best;
}

}  // namespace ft::oracle
