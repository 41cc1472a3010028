#include "scene/core_texture_input.h"

#include <fmt/format.h>

#include "scene/input_error.h"

namespace ft {

CoreTextureInput makeCoreTextureInput(const YarnParams& params, const std::vector<FiberCoord>& table, uint32_t width,
                                      uint32_t height, uint32_t yarn, uint32_t ply) {
  if (width < 2 || width > 8192) throw InputError(fmt::format("core texture width {} outside [2, 8192]", width));
  if (height < 2 || height > 8192) throw InputError(fmt::format("core texture height {} outside [2, 8192]", height));
  const uint32_t core = ftCoreFiberCount(params);
  if (core == 0 || table.size() < params.fiberCount)
    throw InputError(fmt::format("core texture: no core fibers ({} fibers per ply, {} regular, fiber table of {})",
                                 params.fiberCount, params.regularFibers, table.size()));
  CoreTextureInput in;
  // The table is sorted by R_i: the last core row is the farthest (§3.2).
  in.params = ftCoreTextureParams(params, table[core - 1].radius, width, height);
  in.fibers.reserve(core);
  for (uint32_t i = 0; i < core; ++i) in.fibers.push_back(ftCoreFiberRow(params, table[i], yarn, ply, i));
  return in;
}

CoreTexel sampleCoreTexture(const CoreTexture& t, float u, float v) {
  if (t.columns < 2 || t.height < 2 || t.tex0.size() != size_t(t.columns) * t.height)
    throw InputError(fmt::format("sampleCoreTexture: a {}×{} texture with {} texels", t.columns, t.height, t.tex0.size()));
  const CoreLookup l = ftCoreTextureLookup(t.columns, t.height, u, v);
  const auto lerp2 = [&](const std::vector<glm::vec4>& tex) {
    const auto at = [&](uint32_t i, uint32_t j) { return tex[size_t(j) * t.columns + i]; };
    return glm::mix(glm::mix(at(l.i.x, l.j.x), at(l.i.y, l.j.x), l.w.x),
                    glm::mix(at(l.i.x, l.j.y), at(l.i.y, l.j.y), l.w.x), l.w.y);
  };
  CoreTexel out;
  out.tex0 = lerp2(t.tex0);
  out.tex1 = lerp2(t.tex1);
  return out;
}

CoreTextureInput seamStrip(CoreTextureInput input) {
  input.params.columns = input.params.width + 1;
  input.params.uOffset = 0.0f;
  return input;
}

}  // namespace ft
