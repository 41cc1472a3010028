#include "validation/shading_tables.h"

#include "gpu/bcsdf_gpu.h"

namespace ft {

std::vector<glm::vec3> bakeAmbientTableGpu(const GlInfo& gl, const std::vector<std::string>& defines,
                                           const FabricParams& fabric) {
  return BcsdfGpu(gl, defines).bakeAmbientTable(fabric, FT_AMBIENT_TABLE_SIZE);
}

}  // namespace ft
