// pcss_reference.h — the CPU side of the PCSS soft yarn shadows (001 §4.5
// eq. 17, common/pcss.h, docs/soft-shadows.md):
//  * the ground truth: the visibility of a cone light (directions uniform in
//    solid angle within angular radius α of the light's axis) from a point
//    through the yarn tubes of radius W, by many Embree shadow rays per point
//    (ShadowMapReference: the tube region the point lies in does not occlude
//    it, as the map's far side does not); and the SG-weighted visibility of
//    an SRBF lobe (notes A11 (b)), ∫G V dω / ∫G dω, by exact SG sampling;
//  * the C++ twin of the GPU lookups: common/pcss.h on read-back maps.
#pragma once
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "common/pcss.h"
#include "reference/shadow_map_reference.h"

namespace ft {

// `n` directions uniform in solid angle over the cap of half-angle α around
// the unit `axis`: a Fibonacci spiral (u = (k + ½)/n → cos θ = 1 − u(1 − cos α)).
std::vector<glm::vec3> coneDirections(glm::vec3 axis, double alpha, int n);
// `n` directions distributed as G(ω; μ, λ) = e^{λ(μ·ω − 1)}: the same spiral
// through the SG's exact inverse CDF, cos θ = 1 + ln(1 − u(1 − e^{−2λ}))/λ.
std::vector<glm::vec3> sgDirections(glm::vec3 mu, double lambda, int n);
// The share of `directions` along which each point sees no tube (TBB).
std::vector<float> directionsVisibility(const ShadowMapReference& tubes, std::span<const glm::vec3> points,
                                        std::span<const glm::vec3> directions);

// T̃ of light i / lobe j at points by common/pcss.h on read-back maps
// (FiberRenderer::readShadowMap / readLobeShadowMaps).
std::vector<float> pcssLightLookup(const ShadowMapParams& sm, const PcssParams& pc, std::span<const float> texels, int light,
                                   std::span<const glm::vec3> points);
std::vector<float> pcssLobeLookup(const PcssParams& pc, std::span<const float> texels, int lobe,
                                  std::span<const glm::vec3> points);

}  // namespace ft
