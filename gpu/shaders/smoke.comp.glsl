// smoke.comp.glsl — infrastructure smoke test: adds FT_SMOKE_ADD (default 1)
// to every uint of the buffer at binding 0.
#include "common/constants.h"

#ifndef FT_SMOKE_ADD
#define FT_SMOKE_ADD 1u
#endif

layout(local_size_x = FT_WG_GENERATE) in;
layout(std430, binding = 0) buffer SmokeData { uint values[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < uint(values.length())) values[i] += FT_SMOKE_ADD;
}
