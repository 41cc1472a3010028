// yarn_params.h — procedural yarn parameters as the shaders see them
// (uniform block, std140). Filled on the host from a yarn preset
// (scene/yarn_presets.h); meanings follow shared reference-data §2 and
// 000_cc9bd0fbd0e08a03.txt §2.2/§3.1. All members are 4-byte scalars, so
// std140 packs them contiguously.
#ifndef FT_YARN_PARAMS_H
#define FT_YARN_PARAMS_H
#include "prelude.h"

FT_NAMESPACE_BEGIN

struct YarnParams {
  uint plyCount;         // n^ply
  uint fiberCount;       // fibers per ply in the fitted model (rows of the fiber table)
  uint regularFibers;    // outermost fibers drawn individually at full detail (<= fiberCount)
  uint maxSubdivisions;  // line segments per fiber per yarn segment at full detail

  float plyRadius;            // |Δc^ply| = ½ R^ply = yarn_radius / 2
  float ellipseN;             // e_N: ply semi-axis along the yarn→ply direction (ellipse_short)
  float ellipseB;             // e_B: ply semi-axis across it (ellipse_long)
  float fiberRadius;          // half-width of a drawn regular fiber (world units)

  float plyTurnsPerLength;    // 1 / yarn_alpha (ply twist pitch)
  float fiberTurnsPerLength;  // 1 / alpha (fiber twist pitch)
  float plyTwistSign;         // +1 counter-clockwise, -1 clockwise
  float fiberTwistSign;

  float migrationS;           // s of eq. 2: migration periods per fiber turn
  float rhoMin;               // R_min of eq. 2 (fraction of R_i)
  float rhoMax;               // R_max of eq. 2
  float coreRadius;           // core fiber radius in ply-disk units (farthest core fiber at rhoMax)

  float loopProbability;      // P(flyaway cell is a loop): loops expected per cell (<= 0.5 with hairs)
  float hairProbability;      // P(flyaway cell is a hair): hairs expected per cell
  float loopR1Mu;             // loop peak distance r1 from the ply centre (world units), normal
  float loopR1Sigma;

  float hairZeMu;             // hair axial extent (world units along the yarn), normal
  float hairZeSigma;
  float hairR0Mu;             // hair root distance r0 from the ply centre (world units), normal
  float hairR0Sigma;

  float hairReMu;             // hair radial extent re (world units): the free end at r0 + re, normal
  float hairReSigma;
  float hairPeMu;             // hair angular extent (radians), normal
  float hairPeSigma;

  float boundRadius;          // max distance of any fiber point from the yarn axis (culling margin)
  uint seed;
  uint flyawayCells;          // flyaway cells per migration period (>= 1; 1 = the paper's one per period)
  uint migrationPhase;        // FT_MIGRATION_PHASE_INDEPENDENT (presets) or FT_MIGRATION_PHASE_FIBER_ANGLE (eq. 2)
};
FT_ASSERT_OFFSET(YarnParams, plyRadius, 16)
FT_ASSERT_OFFSET(YarnParams, plyTurnsPerLength, 32)
FT_ASSERT_OFFSET(YarnParams, migrationS, 48)
FT_ASSERT_OFFSET(YarnParams, loopProbability, 64)
FT_ASSERT_OFFSET(YarnParams, hairZeMu, 80)
FT_ASSERT_OFFSET(YarnParams, hairReMu, 96)
FT_ASSERT_OFFSET(YarnParams, boundRadius, 112)
FT_ASSERT_OFFSET(YarnParams, seed, 116)
FT_ASSERT_SIZE(YarnParams, 128)

FT_NAMESPACE_END
#endif  // FT_YARN_PARAMS_H
