#include "validation/shading_tables.h"

#include <cmath>

namespace ft {

// MERGE-PLACEHOLDER: replaced by BcsdfGpu::bakeAmbientTable when the bcsdf branch lands.
std::vector<glm::vec3> bakeAmbientTableGpu(const GlInfo&, const std::vector<std::string>&, const FabricParams& p) {
  std::vector<glm::vec3> t(FT_AMBIENT_TABLE_SIZE);
  const int n = 200000;
  for (int k = 0; k < FT_AMBIENT_TABLE_SIZE; ++k) {
    const float to = ftAmbientTexelAngle(k, FT_AMBIENT_TABLE_SIZE);
    glm::dvec3 s(0.0);
    for (int i = 0; i < n; ++i) {
      const double ti = -0.5 * M_PI + (i + 0.5) * M_PI / n;
      const vec3 F = ftFiberFresnel(vec3(p.colorR), float(ti));
      const vec3 v = F * ftLongitudinal(float(ti), to, p.colorR.w) +
                     (vec3(1.0f) - F) * vec3(p.colorTT) * ftLongitudinal(float(ti), to, p.colorTT.w);
      s += glm::dvec3(v) * (std::cos(ti) * std::cos(ti) * M_PI / n);
    }
    t[k] = glm::vec3(s);
  }
  return t;
}

}  // namespace ft
