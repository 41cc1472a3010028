// knit_stitch.h — the knit tile layout (001_dce8d4d1f783b802.txt §3, §5.2) and
// the per-stitch record the GPU optimizer reads (std430).
//
// One tile per stitch face: 14 yarn control points (docs/knit-deformation.md
// has a figure). Two knots, L and R, where the face's loop legs (the "red" yarn
// of the face's row) pass through the head of the loop below (the "green"
// yarn of the row below). Each knot j has a centre x_k (interpolated from the
// mesh, fixed), a tilt angle θ_j and a half-length l_j, the parameters
// Θ = (θ_L, θ_R, l_L, l_R) of §5.2. Eq. 1–2 place six points per knot:
//   c0± = x_k + l d ± r n,  c1± = x_k − l d ± r n,  p0/p1 = x_k ± r b,
//   d = (cos θ, sin θ) in the face plane, b = d × n.
// Tile points, in yarn order within three chains:
//   0 S   sinker (fixed)          7 A   apex of the head below (fixed)
//   1 c1- 2 p0 3 c0+  red,  L     8 c0- 9 p0 10 c1+  green, R (descending)
//   4 c1+ 5 p1 6 c0-  green, L   11 c0+ 12 p1 13 c1-  red, R (descending)
// Halo points 14..20 are neighbour tiles' points, fixed at their interpolated
// positions, so each tile is optimized on its own:
//   chain 0: 14 | 0 1 2 3 | 15      (14 = left tile's 13, 15 = upper tile's 4)
//   chain 1: 16 | 4 .. 10 | 17      (16 = lower tile's 3, 17 = lower tile's 11)
//   chain 2: 18 | 11 12 13 | 19 20  (18 = upper tile's 10, 19, 20 = right tile's 0, 1)
// Chain 2 reaches one point further than chain 0 so that the tile is mirror
// symmetric: the angle at the right tile's sinker mirrors the one at ours.
// A row's yarn visits, per stitch: S, red L, the upper tile's 4..10, red R.
#ifndef FT_KNIT_STITCH_H
#define FT_KNIT_STITCH_H
#include "prelude.h"

#define FT_KNIT_TILE_POINTS 14
#define FT_KNIT_HALO_POINTS 7
#define FT_KNIT_POINTS 21        // tile + halo
#define FT_KNIT_FIXED_POINTS 9   // S, A and the seven halo points
#define FT_KNIT_PARAMS 4         // θ_L, θ_R, l_L, l_R
#define FT_KNIT_ANGLE_RESIDUALS 15
#define FT_KNIT_LENGTH_RESIDUALS 18
#define FT_KNIT_MAX_ITERATIONS 8
// Rendering vertices per control-point segment (§5.2: 14 × 4 = 56 per stitch).
#define FT_KNIT_UPSAMPLE 4

FT_NAMESPACE_BEGIN

// One stitch for the GPU optimizer. Positions are in the deformed face's 2D
// frame (origin, e1, e2; normal n), so their float rounding is relative to the
// stitch size, not to the garment's.
struct KnitStitchGpu {
  vec4 origin;         // xyz: face frame origin (world)
  vec4 e1;             // xyz: course axis
  vec4 e2;             // xyz: n × e1
  vec4 normal;         // xyz: n
  vec4 knots;          // (x_kL, y_kL, x_kR, y_kR) in the frame
  vec4 theta0;         // initial (θ_L, θ_R, l_L, l_R)
  vec4 fixedXY[5];     // (x, y) of S, A, halo 14..20, two per vec4
  vec4 fixedH[3];      // their normal offsets
  vec4 restLength[5];  // eq. 6 rest lengths, 18 used
  vec4 restCosine[4];  // eq. 5 rest cosines, 15 used
  vec4 misc;           // (yarn radius r, side: +1 knit / -1 purl, 0, 0)
};
FT_ASSERT_SIZE(KnitStitchGpu, 384)
FT_ASSERT_OFFSET(KnitStitchGpu, knots, 64)
FT_ASSERT_OFFSET(KnitStitchGpu, fixedXY, 96)
FT_ASSERT_OFFSET(KnitStitchGpu, fixedH, 176)
FT_ASSERT_OFFSET(KnitStitchGpu, restLength, 224)
FT_ASSERT_OFFSET(KnitStitchGpu, restCosine, 304)
FT_ASSERT_OFFSET(KnitStitchGpu, misc, 368)

// Solver settings (std140 uniform block).
struct KnitSolveParams {
  float wAngle;    // eq. 3 weight of eq. 5 (paper: 1)
  float wLength;   // eq. 3 weight of eq. 6 (paper: 100)
  uint iterations; // Gauss–Newton iterations (paper: 3)
  uint stitchCount;
};
FT_ASSERT_SIZE(KnitSolveParams, 16)

// What the GPU optimizer reports per stitch (std430, one record per stitch):
// eq. 3 before iteration k in energy[k], after the last in energy[iterations].
struct KnitEnergyGpu {
  float energy[FT_KNIT_MAX_ITERATIONS + 1];
  uint steps;  // iterations that changed Θ
  uint pad0;
  uint pad1;
};
FT_ASSERT_SIZE(KnitEnergyGpu, 48)
FT_ASSERT_OFFSET(KnitEnergyGpu, steps, 36)

FT_NAMESPACE_END
#endif  // FT_KNIT_STITCH_H
