// core_texture.h — the CPU reference bake of the core-fiber texture
// (000_cc9bd0fbd0e08a03.txt §3.2; common/core_texture.h holds the conventions):
// Embree round linear curves through the core fibers' helices (the same 256
// points per twist as the GPU's capsule chain, but Embree's own intersection),
// one ray per texel, TBB over rows. The surface attributes at a hit come from
// the shared header, so the two sides differ only in how the ray meets the tube.
#pragma once
#include "scene/core_texture_input.h"

namespace ft {

// The reference: Embree round linear curves (TBB over rows).
CoreTexture bakeCoreTextureEmbree(const CoreTextureInput& input);
// The shared capsule chain of common/core_texture.h run in C++ (the GPU
// shader's loop): for tests that need the GPU's geometry without a GPU.
CoreTexture bakeCoreTextureCapsules(const CoreTextureInput& input);

}  // namespace ft
