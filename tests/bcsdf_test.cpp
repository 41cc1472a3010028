// Independent checks of the shared fiber BCSDF (common/bcsdf.h; Wu & Yuksel
// 2019 (000) §4.3 eq. 5–10 with the fills of notes-rendering §0.2 and A4) and
// of its CPU ambient table (reference/bcsdf_tables.h). Every expected value is
// written here, in double, from the formulas and the preset rows: none of the
// header's helpers computes an expectation, since a wrong formula in common/
// runs on the CPU and the GPU alike and passes every cross-check between them.
// Also: the fabric-table parser (scene/fabric.h) on bad files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "reference/bcsdf_tables.h"
#include "scene/fabric.h"
#include "scene/input_error.h"
#include "validation/draw_order.h"

namespace ft {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// ---- The formulas, written out (notes-rendering §0.2) ------------------------

double gaussian(double x, double beta) {
  const double r = x / beta;
  return std::exp(-0.5 * r * r) / (std::sqrt(2.0 * kPi) * beta);
}

// Schlick, as 000 and the TSV give it: F = C_R + (1 − C_R)(1 − |cos θ_i|)^5.
double schlick(double colorR, double thetaI) {
  const double m = 1.0 - std::abs(std::cos(thetaI));
  return colorR + (1.0 - colorR) * m * m * m * m * m;
}

// von Mises centred at φ = π: exp(κ cos(φ − π)) / (2π I0(κ)).
double vonMises(double phi, double kappa) {
  return std::exp(kappa * std::cos(phi - kPi)) / (2.0 * kPi * std::cyl_bessel_i(0.0, kappa));
}

// n-point Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n).
struct Rule {
  std::vector<double> x, w;
};
Rule gaussLegendre(int n) {
  Rule r;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    r.x.push_back(x);
    r.w.push_back(2.0 / ((1.0 - x * x) * dp * dp));
  }
  return r;
}

// ∫_a^b f by 10-point Gauss–Legendre on panels no wider than maxPanel, split
// at every cut inside (a, b). R: double or glm::dvec3.
template <class F>
auto integrate(F&& f, double a, double b, std::vector<double> cuts, double maxPanel) {
  using R = decltype(f(a));
  static const Rule rule = gaussLegendre(10);
  cuts.push_back(a);
  cuts.push_back(b);
  std::erase_if(cuts, [&](double x) { return !(x >= a && x <= b); });
  std::sort(cuts.begin(), cuts.end());
  R sum = R(0.0);
  for (size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double len = cuts[i + 1] - cuts[i];
    if (len <= 0.0) continue;
    const int panels = std::max(1, int(std::ceil(len / maxPanel)));
    const double h = len / panels;
    for (int p = 0; p < panels; ++p) {
      const double c = cuts[i] + (p + 0.5) * h;
      for (size_t k = 0; k < rule.x.size(); ++k) sum += (0.5 * h * rule.w[k]) * f(c + 0.5 * h * rule.x[k]);
    }
  }
  return sum;
}

// Cuts at every lobe width within ±n widths of a lobe's centre.
void addLobeCuts(std::vector<double>& cuts, double centre, double beta, int n = 8) {
  for (int j = -n; j <= n; ++j) cuts.push_back(centre + j * beta);
}

// Z(θ_i) = ∫_{−π/2}^{π/2} g(θ + θ_i; β) cos²θ dθ by brute force over the
// lobe's ±9β (outside it g < e^(−40) of its peak).
double zBrute(double thetaI, double beta) {
  std::vector<double> cuts;
  addLobeCuts(cuts, -thetaI, beta, 9);
  const double lo = std::max(-0.5 * kPi, -thetaI - 9.0 * beta), hi = std::min(0.5 * kPi, -thetaI + 9.0 * beta);
  return integrate(
      [&](double t) {
        const double c = std::cos(t);
        return gaussian(t + thetaI, beta) * c * c;
      },
      lo, hi, cuts, beta);
}

// The closed form of Z for an untruncated Gaussian: ½(1 + e^(−2β²) cos 2θ_i).
double zClosedForm(double thetaI, double beta) {
  return 0.5 * (1.0 + std::exp(-2.0 * beta * beta) * std::cos(2.0 * thetaI));
}

// A fabric preset as doubles (from the preset row, radians), and the float
// block the header gets.
struct Fabric {
  std::string name;
  double colorR[3], colorTT[3], betaR, betaTT, kappa;
  FabricParams params;
};

std::vector<Fabric> fabrics() {
  std::vector<Fabric> out;
  for (const FabricPreset& p : builtinFabricPresets()) {
    Fabric f;
    f.name = p.name;
    for (int c = 0; c < 3; ++c) {
      f.colorR[c] = p.colorR[c];
      f.colorTT[c] = p.colorTT[c];
    }
    f.betaR = p.betaRDegrees * kDeg;
    f.betaTT = p.betaTTDegrees * kDeg;
    const double gamma = p.gammaTTDegrees * kDeg;
    f.kappa = 1.0 / (gamma * gamma);
    f.params = p.params();
    out.push_back(f);
  }
  return out;
}

// f of eq. 6 per channel, with both normalisers Z_R(θ_i), Z_TT(θ_i) given.
glm::dvec3 bcsdfExpected(const Fabric& f, double thetaI, double thetaO, double phi, double zR, double zTT) {
  glm::dvec3 out;
  const double mR = gaussian(thetaO + thetaI, f.betaR) / zR, mTT = gaussian(thetaO + thetaI, f.betaTT) / zTT;
  for (int c = 0; c < 3; ++c) {
    const double F = schlick(f.colorR[c], thetaI);
    out[c] = F * mR / (2.0 * kPi) + (1.0 - F) * f.colorTT[c] * mTT * vonMises(phi, f.kappa);
  }
  return out;
}

FiberAngles angles(double thetaI, double thetaO, double phi) {
  return FiberAngles{float(thetaI), float(thetaO), float(phi)};
}

double relError(double got, double want) { return std::abs(got - want) / std::abs(want); }

// ---- I0e ---------------------------------------------------------------------

// A&S 9.8.1 has |ε| < 1.6e-7 on I0 (≥ 1, so relative), 9.8.2 |ε| < 1.9e-7 on
// √x e^−x I0 ≥ 0.3989, i.e. 4.8e-7 relative; float evaluation adds a few ulp
// (exp(−x), the polynomial, sqrt, the division). Measured: 5.5e-7 (x ≥ 3.75),
// 2.6e-7 below. Tolerance 1e-6: the bound plus float rounding.
TEST(Bcsdf, BesselI0eMatchesStdCylBesselI) {
  double worstLow = 0.0, worstHigh = 0.0;
  std::vector<double> xs;
  for (int i = 0; i <= 2000; ++i) xs.push_back(0.005 * i);      // [0, 10]
  for (int i = 1; i <= 900; ++i) xs.push_back(10.0 + 0.1 * i);  // (10, 100]
  for (const Fabric& f : fabrics()) xs.push_back(double(f.params.lobes.y));
  for (double x : xs) {
    const float xf = float(x);
    const double want = std::cyl_bessel_i(0.0, double(xf)) * std::exp(-double(xf));
    const double e = relError(ftBesselI0e(xf), want);
    (xf < 3.75f ? worstLow : worstHigh) = std::max(xf < 3.75f ? worstLow : worstHigh, e);
    EXPECT_EQ(ftBesselI0e(-xf), ftBesselI0e(xf)) << "I0 is even; x = " << xf;
  }
  std::printf("I0e: max relative error %.3g (x < 3.75), %.3g (x >= 3.75)\n", worstLow, worstHigh);
  EXPECT_LE(worstLow, 1e-6);
  EXPECT_LE(worstHigh, 1e-6);
}

// ---- Z -----------------------------------------------------------------------

std::vector<double> betasOfThePresets() {
  std::vector<double> out;
  for (const Fabric& f : fabrics()) {
    out.push_back(double(f.params.colorR.w));
    out.push_back(double(f.params.colorTT.w));
  }
  return out;
}

std::vector<double> thetaRange(int n, double lo = -0.5 * kPi, double hi = 0.5 * kPi) {
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(double(float(lo + (hi - lo) * i / (n - 1))));
  return out;
}

// Z against brute force everywhere, and against the closed form where the
// header uses it (|θ_i| + 6β ≤ π/2). Float evaluation: the closed form loses
// up to ~1/Z ulp to cancellation near the window's edge (Z ≈ 0.01 at β = 1°),
// the 20-point rule a few ulp. Measured 1.0e-6 (closed-form region) and
// 1.1e-6 (quadrature region); tolerance 1e-5 leaves room for other libms.
TEST(Bcsdf, LongitudinalNormMatchesBruteForceAndClosedForm) {
  double worstClosed = 0.0, worstQuadrature = 0.0, worstFormula = 0.0;
  for (double beta : betasOfThePresets()) {
    for (double thetaI : thetaRange(361)) {
      const float ti = float(thetaI), b = float(beta);
      const double want = zBrute(double(ti), double(b));
      const double e = relError(ftLongitudinalNorm(ti, b), want);
      const bool closed = std::abs(double(ti)) + 6.0 * double(b) <= 0.5 * kPi;
      (closed ? worstClosed : worstQuadrature) = std::max(closed ? worstClosed : worstQuadrature, e);
      if (closed) worstFormula = std::max(worstFormula, relError(zClosedForm(double(ti), double(b)), want));
    }
  }
  std::printf(
      "Z: max relative error %.3g (closed-form region), %.3g (quadrature region); closed form vs brute "
      "force in its region %.3g\n",
      worstClosed, worstQuadrature, worstFormula);
  EXPECT_LE(worstClosed, 1e-5);
  EXPECT_LE(worstQuadrature, 1e-5);
  // The closed form itself (double) within its range: the truncated tails beyond 6β are < 1e-8.
  EXPECT_LE(worstFormula, 1e-8);
  // ... and why it is not used beyond (notes §0.2: β = 27°, θ_i = 1.2 is ~10% off).
  const double outside = relError(zClosedForm(1.2, 27.197 * kDeg), zBrute(1.2, 27.197 * kDeg));
  std::printf("Z: closed form at β = 27.197°, θ_i = 1.2 is off by %.3g\n", outside);
  EXPECT_GT(outside, 0.05);
}

// ---- The frame's lobe-normalisation table ------------------------------------

// Z looked up in the table (bakeLobeNormTableCpu + lookupLobeNormCpu, what the
// fragment stage does) against brute force, for every preset: at random θ_i
// and densely over the window [π/2 − 6β, π/2] where the table is read. Linear
// interpolation of 255 steps over 6β: ≤ h²/8 |Z''|/Z, measured 1.35e-4 (worst
// at the grazing end, where Z ~ β²/2 is smallest); tolerance 3e-4. Outside the
// window the lookup is the closed form itself; and Z is even in θ_i.
TEST(Bcsdf, LobeNormTableLookupMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-0.5 * kPi, 0.5 * kPi);
  double worst = 0.0;
  for (const Fabric& f : fabrics()) {
    const std::vector<glm::vec2> table = bakeLobeNormTableCpu(f.params);
    ASSERT_EQ(table.size(), size_t(FT_LOBE_NORM_TABLE_SIZE));
    const double betas[2] = {double(f.params.colorR.w), double(f.params.colorTT.w)};
    std::vector<double> thetas;
    for (int i = 0; i < 200; ++i) thetas.push_back(unit(rng));
    for (const double beta : betas) {
      const double lo = std::max(0.0, 0.5 * kPi - 6.0 * beta);
      for (int i = 0; i <= 300; ++i) thetas.push_back(lo + (0.5 * kPi - lo) * (i + 0.37) / 301.0);
    }
    for (const double theta : thetas) {
      const float t = float(theta);
      const glm::vec2 got = lookupLobeNormCpu(f.params, table, t);
      const glm::vec2 mirrored = lookupLobeNormCpu(f.params, table, -t);
      for (int c = 0; c < 2; ++c) {
        const double want = zBrute(double(t), betas[c]);
        worst = std::max(worst, relError(got[c], want));
        EXPECT_EQ(got[c], mirrored[c]) << f.name << " θ_i " << t;
        if (std::abs(double(t)) + 6.0 * betas[c] < 0.5 * kPi - 1e-6) {  // below the window: the closed form
          EXPECT_EQ(got[c], ftLongitudinalNorm(t, float(betas[c]))) << f.name << " θ_i " << t;
        }
      }
    }
  }
  std::printf("Z from the table: max relative error %.3g\n", worst);
  EXPECT_LE(worst, 3e-4);
}

// ---- B1: albedo --------------------------------------------------------------

// ∫∫ f cos²θ_o dθ_o dφ over θ_o ∈ [−π/2, π/2], φ ∈ [0, 2π] (f even in φ:
// twice [0, π], by the trapezoid rule, spectrally accurate for the periodic
// von Mises), θ_o by Gauss–Legendre panels cut at every lobe width.
glm::dvec3 albedoQuadrature(const Fabric& f, float thetaI) {
  constexpr int kPhi = 32;
  std::vector<double> cuts;
  addLobeCuts(cuts, -double(thetaI), double(f.params.colorR.w));
  addLobeCuts(cuts, -double(thetaI), double(f.params.colorTT.w));
  return integrate(
      [&](double thetaO) {
        glm::dvec3 s(0.0);
        for (int m = 0; m <= kPhi; ++m) {
          const double w = (m == 0 || m == kPhi ? 0.5 : 1.0) * 2.0 * kPi / kPhi;
          s += w * glm::dvec3(ftBcsdf(f.params, angles(thetaI, thetaO, kPi * m / kPhi)));
        }
        const double c = std::cos(thetaO);
        return s * (c * c);
      },
      -0.5 * kPi, 0.5 * kPi, cuts, 0.1);
}

// B1: ρ(θ_i) = F + (1 − F) C_TT for every preset, θ_i and channel, grazing
// included. The quadrature of the test is exact to ~1e-10 on these lobes; the
// float evaluation of f leaves ~1e-6 (measured 1.7e-6). Tolerance 1e-4
// (notes A4 C1).
TEST(Bcsdf, AlbedoMatchesFresnelPlusTransmission) {
  const double thetas[] = {-0.5 * kPi, -1.56, -1.5, -1.3, -1.0, -0.6, -0.2,     0.0,
                           0.3,        0.7,   1.1,  1.4,  1.52, 1.56, 0.5 * kPi};
  double worst = 0.0;
  for (const Fabric& f : fabrics()) {
    for (double t : thetas) {
      const float ti = float(t);
      const glm::dvec3 got = albedoQuadrature(f, ti);
      for (int c = 0; c < 3; ++c) {
        const double F = schlick(f.colorR[c], double(ti));
        const double want = F + (1.0 - F) * f.colorTT[c];
        const double e = relError(got[c], want);
        worst = std::max(worst, e);
        EXPECT_LE(e, 1e-4) << f.name << " θ_i " << ti << " channel " << c << ": " << got[c] << " vs " << want;
      }
    }
  }
  std::printf("B1 albedo: max relative error %.3g\n", worst);
}

// ---- B4 and the azimuthal shape ------------------------------------------------

// ∫_0^{2π} N_TT dφ = 1 (trapezoid on the periodic function, 4096 steps: exact
// to double rounding for κ ≤ 400). The shape against the von Mises in double:
// exp(−κ(1 + cos φ)) carries the float rounding of its argument (≤ 2κ, so
// 2κ·2^−24 absolute, plus cos φ's κ·2^−24), i.e. a relative error up to
// ~3κ·6e-8 (2.4e-5 at κ = 400, 1.5e-6 at the presets' κ ≤ 8.4).
TEST(Bcsdf, AzimuthalTTIntegratesToOneAndIsAVonMises) {
  std::vector<double> kappas = {0.05, 0.5, 1.0, 3.0, 3.75, 4.0, 10.0, 50.0, 400.0};
  for (const Fabric& f : fabrics()) kappas.push_back(double(f.params.lobes.y));
  double worstIntegral = 0.0, worstShape = 0.0;
  for (double kappa : kappas) {
    const float k = float(kappa);
    constexpr int kSteps = 4096;
    double sum = 0.0;
    for (int m = 0; m < kSteps; ++m) sum += ftAzimuthalTT(float(2.0 * kPi * m / kSteps), k);
    sum *= 2.0 * kPi / kSteps;
    worstIntegral = std::max(worstIntegral, std::abs(sum - 1.0));
    EXPECT_NEAR(sum, 1.0, 1e-5) << "κ = " << kappa;
    if (kappa > 500.0) continue;  // I0(κ) overflows double beyond ~700
    const double peak = vonMises(kPi, double(k));
    for (int m = 0; m <= 180; ++m) {
      const float phi = float(kPi * m / 180.0);
      const double want = vonMises(double(phi), double(k));
      // Relative, with a floor of 1e-3 of the peak (far tails underflow).
      const double e = std::abs(ftAzimuthalTT(phi, k) - want) / std::max(want, 1e-3 * peak);
      worstShape = std::max(worstShape, e / (1e-6 + 4.0 * kappa * FLT_EPSILON));
      EXPECT_LE(e, 1e-6 + 4.0 * kappa * FLT_EPSILON) << "κ = " << kappa << ", φ = " << phi;
    }
  }
  std::printf("B4: max |∫N_TT − 1| %.3g; N_TT vs von Mises (double): max error / its bound %.3g\n", worstIntegral,
              worstShape);
}

// ---- f against the formula written out -----------------------------------------

// f of eq. 6 on a 33 × 33 × 32 grid against the double formula with brute-force
// normalisers. Relative, with a floor of 1e-3 of the largest value at the same
// θ_i: there a Gaussian's float argument (θ_o + θ_i)²/2β² has lost up to
// 7 × 6e-8 of relative precision, and nothing a render shows depends on less.
// Measured 4.9e-6; tolerance 1e-4 (notes §0.4: smooth quantities, float).
TEST(Bcsdf, MatchesTheFormulaWrittenOut) {
  const std::vector<double> thetas = thetaRange(33);
  double worst = 0.0;
  for (const Fabric& f : fabrics()) {
    for (double ti : thetas) {
      const double zR = zBrute(ti, double(f.params.colorR.w)), zTT = zBrute(ti, double(f.params.colorTT.w));
      std::vector<glm::dvec3> want;
      std::vector<glm::vec3> got;
      glm::dvec3 peak(0.0);
      for (double to : thetas)
        for (int m = 0; m < 32; ++m) {
          const double phi = double(float(kPi * m / 31.0));
          // The expectation uses the preset's doubles, the header the float block:
          // their difference (≤ 6e-8 relative) is far inside the tolerance.
          want.push_back(bcsdfExpected(f, ti, to, phi, zR, zTT));
          got.push_back(ftBcsdf(f.params, angles(ti, to, phi)));
          peak = glm::max(peak, want.back());
        }
      for (size_t i = 0; i < want.size(); ++i)
        for (int c = 0; c < 3; ++c) {
          const double e = std::abs(double(got[i][c]) - want[i][c]) / std::max(want[i][c], 1e-3 * peak[c]);
          if (!(e <= worst)) worst = e;  // NaN sticks
        }
    }
  }
  std::printf("f vs the formula written out: max relative error %.3g\n", worst);
  EXPECT_LE(worst, 1e-4);
}

// ---- B2, B3 ----------------------------------------------------------------------

// B2: f ≥ 0 and finite; even in φ; f(θ_i, θ_o) = f(−θ_i, −θ_o). Every
// operation of the header is odd- or even-symmetric in float, so these hold
// exactly; the tolerance (1e-6 relative) only allows another libm.
TEST(Bcsdf, NonNegativeEvenInPhiAndMirrorSymmetric) {
  const std::vector<double> thetas = thetaRange(33);
  for (const Fabric& f : fabrics()) {
    size_t negative = 0, nonFinite = 0;
    double worstEven = 0.0, worstMirror = 0.0;
    for (double ti : thetas)
      for (double to : thetas)
        for (int m = 0; m <= 32; ++m) {
          const double phi = kPi * m / 32.0;
          const glm::vec3 a = ftBcsdf(f.params, angles(ti, to, phi));
          const glm::vec3 b = ftBcsdf(f.params, angles(ti, to, -phi));
          const glm::vec3 c = ftBcsdf(f.params, angles(-ti, -to, phi));
          for (int k = 0; k < 3; ++k) {
            nonFinite += !std::isfinite(a[k]);
            negative += a[k] < 0.0f;
            const double scale = std::max(double(a[k]), 1e-30);
            worstEven = std::max(worstEven, std::abs(double(a[k]) - b[k]) / scale);
            worstMirror = std::max(worstMirror, std::abs(double(a[k]) - c[k]) / scale);
          }
        }
    EXPECT_EQ(nonFinite, 0u) << f.name;
    EXPECT_EQ(negative, 0u) << f.name;
    EXPECT_LE(worstEven, 1e-6) << f.name;
    EXPECT_LE(worstMirror, 1e-6) << f.name;
  }
}

// B3: f is not reciprocal, and must never be asserted to be: M is normalised
// over θ_o for each θ_i (Z depends on θ_i) and F depends on θ_i only, so
// swapping ω_i and ω_o changes f. One pair shows it: silk at (10°, −60°) and
// (−60°, 10°), where θ_i + θ_o and so the Gaussians are the same both ways.
TEST(Bcsdf, IsNotReciprocal) {
  const Fabric silk = fabrics()[2];
  ASSERT_EQ(silk.name, "silk");
  const double a = 10.0 * kDeg, b = -60.0 * kDeg;
  const glm::vec3 io = ftBcsdf(silk.params, angles(a, b, 2.0));
  const glm::vec3 oi = ftBcsdf(silk.params, angles(b, a, 2.0));
  const double e = relError(io.y, oi.y);
  std::printf("B3: silk f(10°, −60°) / f(−60°, 10°) − 1 = %.3g (green)\n", double(io.y) / oi.y - 1.0);
  EXPECT_GT(e, 1e-2);
}

// ---- The ambient table -------------------------------------------------------------

// A(θ_o) of eq. 8 by brute force: the integrand written out (Z brute force),
// Gauss–Legendre panels cut at every lobe width around −θ_o.
glm::dvec3 ambientBrute(const Fabric& f, double thetaO) {
  const double bR = double(f.params.colorR.w), bTT = double(f.params.colorTT.w);
  std::vector<double> cuts;
  addLobeCuts(cuts, -thetaO, bR);
  addLobeCuts(cuts, -thetaO, bTT);
  return integrate(
      [&](double thetaI) {
        const double c = std::cos(thetaI);
        const double mR = gaussian(thetaO + thetaI, bR) / zBrute(thetaI, bR);
        const double mTT = gaussian(thetaO + thetaI, bTT) / zBrute(thetaI, bTT);
        glm::dvec3 out;
        for (int k = 0; k < 3; ++k) {
          const double F = schlick(f.colorR[k], thetaI);
          out[k] = (F * mR + (1.0 - F) * f.colorTT[k] * mTT) * c * c;
        }
        return out;
      },
      -0.5 * kPi, 0.5 * kPi, cuts, 0.05);
}

// The CPU table against the brute force for every preset and texel. The bake
// integrates the header's float integrand (rounding ~1e-6 relative: Z's
// closed form near its window's edge, above) in double; measured 3.2e-6, the
// Gauss–Kronrod estimate 6.6e-7. Tolerance 1e-5.
TEST(Bcsdf, AmbientTableMatchesBruteForceQuadrature) {
  double worst = 0.0, worstEstimate = 0.0;
  size_t evaluations = 0;
  for (const Fabric& f : fabrics()) {
    const AmbientTableCpu table = bakeAmbientTableCpuParts(f.params);
    const std::vector<glm::dvec3> total = table.total();
    ASSERT_EQ(total.size(), size_t(FT_AMBIENT_TABLE_SIZE));
    worstEstimate = std::max(worstEstimate, table.errorEstimate);
    evaluations += table.evaluations;
    for (int k = 0; k < FT_AMBIENT_TABLE_SIZE; ++k) {
      const double thetaO = -0.5 * kPi + (k + 0.5) * kPi / FT_AMBIENT_TABLE_SIZE;
      const glm::dvec3 want = ambientBrute(f, double(float(thetaO)));
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(total[size_t(k)][c])) << f.name << " texel " << k;
        const double e = relError(total[size_t(k)][c], want[c]);
        worst = std::max(worst, e);
        EXPECT_LE(e, 1e-5) << f.name << " texel " << k << " channel " << c;
      }
    }
  }
  std::printf(
      "ambient table vs brute force: max relative error %.3g; Gauss-Kronrod estimate %.3g; %zu "
      "evaluations for 5 tables\n",
      worst, worstEstimate, evaluations);
}

// A is even in θ_o (B2 carried through eq. 8): texel k against texel n − 1 − k.
// Each texel is within ~3e-6 of the exact value (the test above) and the two
// texel angles are negatives up to float rounding (~1e-7 rad): 1e-5 relative
// (measured 3.9e-6, at the grazing texels).
TEST(Bcsdf, AmbientTableIsEvenInThetaO) {
  for (const Fabric& f : fabrics()) {
    const std::vector<glm::vec3> a = bakeAmbientTableCpu(f.params);
    const int n = int(a.size());
    for (int k = 0; k < n / 2; ++k)
      for (int c = 0; c < 3; ++c)
        EXPECT_LE(relError(a[size_t(k)][c], a[size_t(n - 1 - k)][c]), 1e-5) << f.name << " texel " << k;
  }
}

// β → 0: the R part of A tends to F(θ_o). For β_R = 1° (silk, cotton) a
// second-order expansion gives R(θ_o) − F ≈ β²(2 − 1/cos²θ_o) F + ½β² F''
// (Z(θ_i) ≈ cos²θ_i − β² cos 2θ_i), below 1e-3 (absolute, reflectance) while
// |θ_o| ≤ 60° (−6e-4·F at 60°) and growing towards grazing, where the lobe is
// clipped. Measured 2.8e-4 (silk) and 4.5e-4 (cotton).
TEST(Bcsdf, AmbientReflectionTendsToFresnelForNarrowLobes) {
  for (const Fabric& f : fabrics()) {
    if (f.name != "silk" && f.name != "cotton") continue;
    ASSERT_NEAR(f.betaR, kDeg, 1e-12) << f.name;
    const AmbientTableCpu table = bakeAmbientTableCpuParts(f.params);
    double worst = 0.0;
    for (int k = 0; k < FT_AMBIENT_TABLE_SIZE; ++k) {
      const double thetaO = -0.5 * kPi + (k + 0.5) * kPi / FT_AMBIENT_TABLE_SIZE;
      if (std::abs(thetaO) > 60.0 * kDeg) continue;
      for (int c = 0; c < 3; ++c) {
        const double e = std::abs(table.r[size_t(k)][c] - schlick(f.colorR[c], thetaO));
        worst = std::max(worst, e);
        EXPECT_LE(e, 1e-3) << f.name << " θ_o " << thetaO / kDeg << "° channel " << c;
      }
    }
    std::printf("%s: max |A_R − F| for |θ_o| ≤ 60°: %.3g\n", f.name.c_str(), worst);
  }
}

// ---- Eq. 5, the simple model -------------------------------------------------------

// f_spec = k_s cos(φ/2) exp(−θ_h²/2β²), θ_h = (θ_i + θ_o)/2: against the
// formula (relative 1e-5 above 1e-3 k_s: float argument rounding), peak on the
// specular cone θ_o = −θ_i, symmetric under i ↔ o.
TEST(Bcsdf, SimpleModelPeaksOnTheSpecularConeAndIsSymmetric) {
  const float ks = 0.8f;
  for (double betaDeg : {1.0, 5.0, 12.0}) {
    const float beta = float(betaDeg * kDeg);
    double worst = 0.0, worstSym = 0.0;
    for (double ti : thetaRange(33))
      for (double to : thetaRange(33))
        for (int m = 0; m <= 16; ++m) {
          const double phi = double(float(kPi * m / 16.0));
          const double th = 0.5 * (ti + to);
          const double want = ks * std::cos(0.5 * phi) * std::exp(-th * th / (2.0 * double(beta) * double(beta)));
          const float got = ftSimpleSpecular(ks, beta, angles(ti, to, phi));
          worst = std::max(worst, std::abs(got - want) / std::max(want, 1e-3 * ks));
          worstSym = std::max(worstSym, double(std::abs(got - ftSimpleSpecular(ks, beta, angles(to, ti, phi)))));
        }
    std::printf("eq. 5, β = %g°: max relative error %.3g, max |f(i,o) − f(o,i)| %.3g\n", betaDeg, worst, worstSym);
    EXPECT_LE(worst, 1e-5) << "β = " << betaDeg;
    EXPECT_LE(worstSym, 1e-6 * ks) << "β = " << betaDeg;
    // The peak over θ_o (steps of β/8 around the cone) is on the cone.
    for (double ti : {-1.2, -0.4, 0.0, 0.5, 1.3}) {
      double best = -1.0, at = 0.0;
      for (int j = -40; j <= 40; ++j) {
        const double to = -ti + j * double(beta) / 8.0;
        const double v = ftSimpleSpecular(ks, beta, angles(ti, to, 0.3));
        if (v > best) best = v, at = to;
      }
      EXPECT_NEAR(at, -ti, 1e-9) << "β = " << betaDeg << ", θ_i = " << ti;
    }
  }
}

// ---- ftFiberAngles ---------------------------------------------------------------

// ftAtan2 against std::atan2 in every quadrant, on the axes and at 0:
// Cephes atanf's reduction and polynomial, ≤ 2e-7 rad (float rounding of a
// result up to π is 1.2e-7 alone). Measured 2.7e-7; tolerance 4e-7.
TEST(Bcsdf, Atan2MatchesStdAtan2) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  std::uniform_real_distribution<double> logRadius(-20.0, 20.0);
  double worst = 0.0;
  const auto check = [&](float y, float x) {
    const double want = std::atan2(double(y), double(x));
    worst = std::max(worst, std::abs(double(ftAtan2(y, x)) - want));
  };
  for (int i = 0; i < 200000; ++i) {
    const double a = angle(rng), r = std::exp(logRadius(rng));
    check(float(r * std::sin(a)), float(r * std::cos(a)));
  }
  for (float y : {-1.0f, -1e-30f, 0.0f, 1e-30f, 1.0f})
    for (float x : {-1.0f, -1e-30f, 0.0f, 1e-30f, 1.0f}) check(y, x);
  std::printf("ftAtan2: max error %.3g rad\n", worst);
  EXPECT_LE(worst, 4e-7);
  EXPECT_EQ(ftAtan2(0.0f, 0.0f), 0.0f);
}

// Directions built from (θ_i, θ_o, φ) in double about random tangents, with
// random lengths, come back as those angles. θ = atan2(ω·t, |ω⊥|) is well
// conditioned everywhere, poles included: float directions and ftAtan2 give
// ~3e-7 rad (measured 2.1e-7); tolerance 1e-6, against the 3.9e-4 of
// Mesa's GLSL asin. φ's conditioning is 1/|ω⊥| (φ is undefined at the
// poles), so φ is checked for |θ| ≤ 85° over all of [0, π]: ~1e-6 (measured
// 1.1e-6); tolerance 5e-6.
TEST(Bcsdf, FiberAnglesRecoverConstructedDirections) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worstTheta = 0.0, worstPhi = 0.0;
  for (int i = 0; i < 100000; ++i) {
    glm::dvec3 t = drawVec3<glm::dvec3>(normal, rng);
    t = glm::normalize(t);
    const glm::dvec3 u = glm::normalize(glm::cross(t, std::abs(t.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 v = glm::cross(t, u);
    const bool pole = i % 2 == 0;  // half the samples over all θ, the others within ±85°
    const double span = pole ? 0.5 * kPi : 85.0 * kDeg;
    const double ti = span * (2.0 * unit(rng) - 1.0), to = span * (2.0 * unit(rng) - 1.0);
    const double p = kPi * unit(rng), p0 = 2.0 * kPi * unit(rng);
    const auto dir = [&](double th, double ph) {
      const double length = std::exp(4.0 * unit(rng) - 2.0);
      return glm::vec3(length * (std::sin(th) * t + std::cos(th) * (std::cos(ph) * u + std::sin(ph) * v)));
    };
    const FiberAngles a = ftFiberAngles(glm::vec3(t), dir(ti, p0), dir(to, p0 + p));
    worstTheta = std::max({worstTheta, std::abs(a.thetaI - ti), std::abs(a.thetaO - to)});
    if (!pole) worstPhi = std::max(worstPhi, std::abs(a.phi - p));
  }
  std::printf("ftFiberAngles: max error θ %.3g rad (all θ), φ %.3g rad (|θ| <= 85°)\n", worstTheta, worstPhi);
  EXPECT_LE(worstTheta, 1e-6);
  EXPECT_LE(worstPhi, 5e-6);
  // Parallel to t: φ = 0 by convention, θ = ±π/2.
  const FiberAngles a = ftFiberAngles(glm::vec3(0, 0, 1), glm::vec3(0, 0, 2), glm::vec3(1, 0, 0));
  EXPECT_NEAR(a.thetaI, 0.5 * kPi, 1e-7);
  EXPECT_EQ(a.thetaO, 0.0f);
  EXPECT_EQ(a.phi, 0.0f);
}

// ---- scene/fabric: the preset table ---------------------------------------------------

TEST(FabricPresets, BuiltinTableHoldsTheFiveFabricsOfTheNotes) {
  const std::vector<Fabric> f = fabrics();
  ASSERT_EQ(f.size(), 5u);
  const char* names[] = {"fleece", "gabardine", "silk", "cotton", "polyester"};
  const double betaR[] = {7.238, 2.141, 1.000, 1.000, 5.238}, betaTT[] = {10, 10, 10, 27.197, 10},
               gammaTT[] = {25.989, 23.548, 19.823, 38.269, 25.0};  // notes-rendering §0.2
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(f[i].name, names[i]);
    EXPECT_NEAR(f[i].params.colorR.w, betaR[i] * kDeg, 1e-7);
    EXPECT_NEAR(f[i].params.colorTT.w, betaTT[i] * kDeg, 1e-7);
    EXPECT_NEAR(f[i].params.lobes.x, gammaTT[i] * kDeg, 1e-7);
    const double gamma = gammaTT[i] * kDeg;
    EXPECT_NEAR(f[i].params.lobes.y, 1.0 / (gamma * gamma), 1e-6 / (gamma * gamma));
  }
}

const char* kHeader = "name\tC_R_r\tC_R_g\tC_R_b\tC_TT_r\tC_TT_g\tC_TT_b\tbeta_R_deg\tbeta_TT_deg\tgamma_TT_deg\n";

// The InputError of parsing `text`, or "" when it parsed.
std::string parseError(const std::string& text) {
  try {
    parseFabricPresets(text, "test.tsv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FabricPresets, BadFilesAreInputErrorsNamingLineColumnAndValue) {
  const std::string good = "ok\t0.1\t0.1\t0.1\t0.5\t0.5\t0.5\t2\t10\t25\n";
  ASSERT_EQ(parseError(std::string(kHeader) + good), "");
  struct Bad {
    std::string text;
    std::vector<std::string> mentions;
  };
  const std::vector<Bad> bad = {
      {"name\tC_R_r\tC_R_g\tC_R_b\tC_TT_r\tC_TT_g\tC_TT_b\tbeta_R_deg\tbeta_TT_deg\nsilk\t1\t1\t1\t1\t1\t1\t1\t1\n",
       {"test.tsv", "line 1", "gamma_TT_deg"}},
      {std::string(kHeader) + good + "x\t0.1\t0.1\t0.1\t0.5\t1.25\t0.5\t2\t10\t25\n",
       {"test.tsv", "line 3", "C_TT_g", "1.25"}},
      {std::string(kHeader) + "x\t0.1\tnan\t0.1\t0.5\t0.5\t0.5\t2\t10\t25\n", {"line 2", "C_R_g", "nan"}},
      {std::string(kHeader) + "x\t0.1\t0.1\t0.1\t0.5\t0.5\t0.5\t2\tinf\t25\n", {"line 2", "beta_TT_deg", "inf"}},
      {std::string(kHeader) + "x\t0.1\t0.1\t0.1\t0.5\t0.5\t0.5\t-2\t10\t25\n", {"line 2", "beta_R_deg", "-2"}},
      {std::string(kHeader) + "x\t0.1\t0.1\t0.1\t0.5\t0.5\t0.5\t2\t10\t0\n", {"line 2", "gamma_TT_deg", "0"}},
      {std::string(kHeader) + "x\t0.1\t0.1\t0.1\t0.5\t0.5\t0.5\t2\t10\n", {"line 2", "expected 10 fields"}},
      {std::string(kHeader) + "x\t0.1\t0.1\t0.1\t0.5\t0.5\t0.5\t2\tten\t25\n", {"line 2", "beta_TT_deg", "ten"}},
  };
  for (const Bad& b : bad) {
    const std::string what = parseError(b.text);
    ASSERT_NE(what, "") << "accepted:\n" << b.text;
    for (const std::string& m : b.mentions)
      EXPECT_NE(what.find(m), std::string::npos) << "'" << what << "' lacks " << m;
  }
}

}  // namespace
}  // namespace ft
