// core_texture_input.h — what both core-fiber texture bakes read and write
// (000_cc9bd0fbd0e08a03.txt §3.2; common/core_texture.h holds the
// conventions): the parameter block with the core-fiber list, and a baked
// texture. reference/core_texture.h bakes it on the CPU,
// gpu/core_texture_gpu.h on the GPU.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "common/core_texture.h"
#include "common/yarn_buffers.h"
#include "common/yarn_params.h"

namespace ft {

struct CoreTextureInput {
  CoreTextureParams params{};
  std::vector<glm::vec4> fibers;  // ftCoreFiberRow of each core fiber
};

// A baked texture: params.columns × params.height texels, row-major (row j = v).
struct CoreTexture {
  uint32_t columns = 0, height = 0;
  std::vector<glm::vec4> tex0;  // (h, n_u, n_v, 0); h = 0: a hole
  std::vector<glm::vec4> tex1;  // (t_u, t_v, t_w, 0)
  const glm::vec4& at0(uint32_t i, uint32_t j) const { return tex0[size_t(j) * columns + i]; }
  const glm::vec4& at1(uint32_t i, uint32_t j) const { return tex1[size_t(j) * columns + i]; }
};

// The core set of `table` (rows below the regular fibers) for ply `ply` of
// yarn `yarn`, at width × height. Throws InputError naming the value for
// sizes outside [2, 8192] or a preset without core fibers.
CoreTextureInput makeCoreTextureInput(const YarnParams& params, const std::vector<FiberCoord>& table, uint32_t width,
                                      uint32_t height, uint32_t yarn = 0, uint32_t ply = 0);

// The texture looked up at (u, v) the way a renderer does (notes §0.4:
// texel fetches and ftCoreTextureLookup's lerp; u wraps, v clamps). Needs
// columns == params.width (a whole baked texture, not a seam strip).
CoreTexel sampleCoreTexture(const CoreTexture& texture, float u, float v);

// The columns W + 1 from u = 0 to u = 1 inclusive (the seam check: column 0
// and column W look at the same place of a periodic texture).
CoreTextureInput seamStrip(CoreTextureInput input);

}  // namespace ft
