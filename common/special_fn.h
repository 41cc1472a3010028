// special_fn.h — special functions GLSL lacks, shared by C++ and GLSL.
//   * ftErf: the error function, odd by construction: Abramowitz & Stegun
//     7.1.26 (|error| ≤ 1.5e-7) for |x| ≥ ½, where 1 − poly·e^{−x²} no longer
//     cancels; below, its Maclaurin series to x¹¹ (truncation ≤ 1.4e-8, and
//     relative accuracy near 0). In float ≤ 3e-7 (tests/prt_single_scattering_test.cpp). The scaled Bessel function I0e lives in bcsdf.h
//     (ftBesselI0e), which came first.
// Used by the fabric PRT's single scattering (common/prt_single_scattering.h:
// Γ of 004 eq. 2 and the smoothed visibility Ṽ_loc of 004 §5.2.2).
#ifndef FT_SPECIAL_FN_H
#define FT_SPECIAL_FN_H
#include "prelude.h"

FT_NAMESPACE_BEGIN

// erf(x) = 1 − (a1 t + … + a5 t⁵) e^{−x²}, t = 1/(1 + p|x|), sign restored.
FT_FUNC float ftErf(float x) {
  float a = abs(x);
  if (a < 0.5f) {
    // 2/√π Σ (−1)^n x^{2n+1}/(n!(2n + 1)), n ≤ 5.
    float z = x * x;
    return 1.12837916709551257f * x *
           (1.0f + z * (-0.333333333f + z * (0.1f + z * (-0.0238095238f + z * (0.00462962963f + z * -0.000757575758f)))));
  }
  float t = 1.0f / (1.0f + 0.3275911f * a);
  float poly = t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f))));
  float y = 1.0f - poly * exp(-a * a);
  return x < 0.0f ? -y : y;
}

FT_NAMESPACE_END
#endif  // FT_SPECIAL_FN_H
