// Knot-based yarn optimization (001_dce8d4d1f783b802.txt §5.2): one
// invocation per stitch runs the Gauss–Newton solve of common/knit_solver.h in
// float and writes the tile's 14 control points in world space.
#include "shaders/knit_precision.glsl"
#include "common/constants.h"
#include "common/knit_solver.h"
#include "shaders/flat_dispatch.glsl"

layout(local_size_x = FT_WG_KNIT) in;
layout(std140, binding = FT_UBO_KNIT_PARAMS) uniform KnitParamsBlock { KnitSolveParams knit; };
layout(std430, binding = FT_SSBO_KNIT_STITCHES) readonly buffer StitchBuffer { KnitStitchGpu stitches[]; };
layout(std430, binding = FT_SSBO_KNIT_POINTS) writeonly buffer PointBuffer { vec4 points[]; };
layout(std430, binding = FT_SSBO_KNIT_ENERGY) writeonly buffer EnergyBuffer { KnitEnergyGpu energies[]; };
uniform uint groupsX;

void main() {
  uint t = flatInvocationIndex(groupsX, FT_WG_KNIT);
  if (t >= knit.stitchCount) return;
  KnitStitchGpu s = stitches[t];
  KnitProblem pr;
  pr.knot[0] = s.knots.xy;
  pr.knot[1] = s.knots.zw;
  pr.theta0 = s.theta0;
  for (int i = 0; i < FT_KNIT_FIXED_POINTS; ++i) {
    vec4 xy = s.fixedXY[i / 2];
    pr.fixedXY[i] = (i % 2) == 0 ? xy.xy : xy.zw;
    pr.fixedH[i] = s.fixedH[i / 4][i % 4];
  }
  for (int i = 0; i < FT_KNIT_LENGTH_RESIDUALS; ++i) pr.restLength[i] = s.restLength[i / 4][i % 4];
  for (int i = 0; i < FT_KNIT_ANGLE_RESIDUALS; ++i) pr.restCosine[i] = s.restCosine[i / 4][i % 4];
  pr.radius = s.misc.x;
  pr.side = s.misc.y;

  KnitTileResult r = knitSolveTile(pr, knit.wAngle, knit.wLength, knit.iterations);
  for (int i = 0; i < FT_KNIT_TILE_POINTS; ++i) {
    vec3 p = r.p[i];
    points[t * uint(FT_KNIT_TILE_POINTS) + uint(i)] =
        vec4(s.origin.xyz + p.x * s.e1.xyz + p.y * s.e2.xyz + p.z * s.normal.xyz, 1.0);
  }
  KnitEnergyGpu e;
  for (int k = 0; k <= FT_KNIT_MAX_ITERATIONS; ++k) e.energy[k] = float(r.energy[k]);
  e.steps = r.steps;
  e.pad0 = 0u;
  e.pad1 = 0u;
  energies[t] = e;
}
