// core_texture_oracle.h — expectations for the core-fiber texture cases
// (validation/core_texture_cases.cpp) that share no code with common/: the
// helix of a core fiber written out again from 000 §2.2 eq. 1–2 with s = 1
// (§3.2), in double, its tangent by central differences, and the nearest
// helix point of a set by sampling and ternary search. A helix, migration or
// tangent wrong in common/core_texture.h on both bake sides fails against it.
#pragma once
#include <glm/glm.hpp>
#include <vector>

namespace ft::oracle {

struct CoreHelix {
  double radius;      // R_i, ply-disk units
  double thetaTurns;  // θ_i / 2π
  double phaseTurns;  // migration phase of eq. 2, turns
};

struct CoreHelixSet {
  double alpha = 0.0;        // one twist along z (world)
  double scale = 0.0;        // ply-disk units → world
  double rhoMin = 0.0, rhoMax = 0.0;
  double clockSign = 1.0;    // +1: counter-clockwise fiber twist, −1: fiber_clock_wise
  std::vector<CoreHelix> fibers;
};

// Point of fiber f at twist angle θ (radians; z = α θ / 2π), s = 1.
glm::dvec3 corePoint(const CoreHelixSet& set, const CoreHelix& f, double theta);
// Unit tangent toward growing θ (central difference).
glm::dvec3 coreTangent(const CoreHelixSet& set, const CoreHelix& f, double theta);

struct NearestCore {
  int fiber = -1;
  double theta = 0.0;
  double distance = 0.0;
  glm::dvec3 tangent{0.0};
};
// The helix point nearest to p among all fibers, searched over
// θ ∈ 2π p.z / α ± `window` (radians).
NearestCore nearestCorePoint(const CoreHelixSet& set, const glm::dvec3& p, double window);

}  // namespace ft::oracle
