// view_params.h — camera data for LoD (eq. 4 of 000_cc9bd0fbd0e08a03.txt)
// and frustum culling (§3.3). Uniform block, std140.
#ifndef FT_VIEW_PARAMS_H
#define FT_VIEW_PARAMS_H
#include "prelude.h"

FT_NAMESPACE_BEGIN

struct ViewParams {
  mat4 viewProj;            // world → clip, column-major (GLM and GLSL agree)
  vec4 frustumPlanes[6];    // world space, xyz unit normal pointing inside, w offset: inside iff dot(n,p)+w >= 0
  vec4 cameraPos;           // xyz eye; w = pixels per world unit at view depth 1 = H / (2 tan(fovy/2))
  float lodThresholdPx;     // ω^LoD in pixels
  uint lodEnabled;          // 0: λ = 1 everywhere
  uint cullEnabled;         // 0: no frustum culling
  float chordErrorPx;       // target chord error of the fiber polylines, pixels (lod.h); 0: always the subdivision cap
};
FT_ASSERT_OFFSET(ViewParams, frustumPlanes, 64)
FT_ASSERT_OFFSET(ViewParams, cameraPos, 160)
FT_ASSERT_OFFSET(ViewParams, lodThresholdPx, 176)
FT_ASSERT_OFFSET(ViewParams, cullEnabled, 184)
FT_ASSERT_OFFSET(ViewParams, chordErrorPx, 188)
FT_ASSERT_SIZE(ViewParams, 192)

FT_NAMESPACE_END
#endif  // FT_VIEW_PARAMS_H
