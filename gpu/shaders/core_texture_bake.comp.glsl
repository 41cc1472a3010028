// The core-fiber texture of 000 §3.2 (CoreTextureGpu::bake): one invocation
// per texel casts its −x ray against every core fiber's capsule chain
// (common/core_texture.h, the same functions the CPU capsule bake calls) and
// writes the nearest hit's height, normal and fiber direction.
#include "common/constants.h"
#include "common/core_texture.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_CORE_TEXTURE) in;
layout(std140, binding = FT_UBO_CORE_TEXTURE) uniform CoreTextureBlock { CoreTextureParams core; };
layout(std430, binding = FT_SSBO_CORE_FIBERS) readonly buffer CoreFibers { vec4 fibers[]; };
layout(std430, binding = FT_SSBO_CORE_TEX0) writeonly buffer CoreTex0 { vec4 tex0[]; };
layout(std430, binding = FT_SSBO_CORE_TEX1) writeonly buffer CoreTex1 { vec4 tex1[]; };
uniform uint groupsX;

void main() {
  uint index = flatInvocationIndex(groupsX, FT_WG_CORE_TEXTURE);
  if (index >= core.columns * core.height) return;
  uint column = index % core.columns;
  uint row = index / core.columns;
  vec3 o = ftCoreTexelOrigin(core, column, row);
  vec3 best = vec3(0.0);
  uint bestFiber = 0u;
  for (uint f = 0u; f < core.coreFibers; ++f) {
    vec3 hit = ftCoreFiberCapsuleHit(core, fibers[f], o);
#ifdef FT_FAULT_CORE_TEXTURE_FAR_HIT
    bool nearer = hit.x < best.x;  // planted: keeps the farthest surface, the far side of the core
#else
    bool nearer = hit.x > best.x;
#endif
    if (hit.z != 0.0 && (best.z == 0.0 || nearer)) {
      best = hit;
      bestFiber = f;
    }
  }
  CoreTexel t = ftCoreEmptyTexel();
  if (best.z != 0.0) t = ftCoreTexelAt(core, fibers[bestFiber], vec3(best.x, o.y, o.z), best.y);
  tex0[index] = t.tex0;
  tex1[index] = t.tex1;
}
