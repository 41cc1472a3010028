// The shared BCSDF (common/bcsdf.h) on a list of requests, one invocation
// each (BcsdfGpu): f of 000 eq. 6, one of its lobes, or f_spec of eq. 5, from
// angles or from directions; the angles of directions; or the ambient table
// looked up at θ_o through ftAmbientLookup.
#include "common/constants.h"
#include "common/fiber_shading.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_BCSDF) in;
// Angles: (θ_i, θ_o, φ, 0) per request; directions: t, ω_i, ω_o (xyz) per
// request; lookup: (θ_o, 0, 0, 0).
layout(std430, binding = FT_SSBO_BCSDF_INPUT) readonly buffer BcsdfInput {
  FabricParams fabric;
  vec4 requests[];
};
layout(std430, binding = FT_SSBO_AMBIENT_TABLE) readonly buffer AmbientTable { vec4 table[]; };
layout(std430, binding = FT_SSBO_BCSDF_OUTPUT) writeonly buffer BcsdfOutput { vec4 results[]; };
uniform uint requestCount;
uniform uint groupsX;
uniform uint model;       // FT_SHADING_KHUNGURN or FT_SHADING_SIMPLE
uniform uint lobes;       // Khungurn: FT_BCSDF_LOBE_R | FT_BCSDF_LOBE_TT (common/constants.h)
uniform uint kind;        // 0: f of angles, 1: f of directions, 2: angles of directions, 3: table lookup
uniform uint texels;      // lookup: texels of the table
uniform vec2 simple;      // k_s, β of eq. 5

void main() {
  uint j = flatInvocationIndex(groupsX, FT_WG_BCSDF);
  if (j >= requestCount) return;
  if (kind == 3u) {  // callers fetch the two texels and mix (common/bcsdf.h)
    vec3 l = ftAmbientLookup(requests[j].x, int(texels));
    results[j] = vec4(mix(table[int(l.x)].xyz, table[int(l.y)].xyz, l.z), 0.0);
    return;
  }
  FiberAngles a;
  if (kind != 0u) {
    a = ftFiberAngles(requests[3u * j].xyz, requests[3u * j + 1u].xyz, requests[3u * j + 2u].xyz);
  } else {
    a.thetaI = requests[j].x;
    a.thetaO = requests[j].y;
    a.phi = requests[j].z;
  }
  if (kind == 2u) {
    results[j] = vec4(a.thetaI, a.thetaO, a.phi, 0.0);
    return;
  }
  vec3 f;
  if (model == FT_SHADING_SIMPLE) f = vec3(ftSimpleSpecular(simple.x, simple.y, a));
  else if (lobes == (FT_BCSDF_LOBE_R | FT_BCSDF_LOBE_TT)) f = ftBcsdf(fabric, a);
  else if (lobes == FT_BCSDF_LOBE_R) f = ftBcsdfR(fabric, a);
  else if (lobes == FT_BCSDF_LOBE_TT) f = ftBcsdfTT(fabric, a);
  else f = vec3(0.0);
  results[j] = vec4(f, 0.0);
}
