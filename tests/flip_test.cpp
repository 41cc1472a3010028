// FLIP (image/flip.h) and the plain metrics (image/image_metrics.h) on images
// the test makes itself. Expected values are derived here from the published
// formulas in double precision (docs/flip.md), never by calling the code
// under test; the tolerances say how far float32 arithmetic may drift.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "image/flip.h"
#include "image/image_metrics.h"

namespace ft {
namespace {

ImageRgbaF uniform(int w, int h, float r, float g, float b) {
  ImageRgbaF img(w, h);
  for (size_t i = 0; i < img.pixelCount(); ++i) {
    float* p = img.pixels.data() + i * 4;
    p[0] = r, p[1] = g, p[2] = b, p[3] = 1.0f;
  }
  return img;
}

// Deterministic noise in [0, scale): a small LCG, so no two runs differ.
ImageRgbaF noise(int w, int h, uint32_t seed, float scale = 1.0f) {
  ImageRgbaF img(w, h);
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    seed = seed * 1664525u + 1013904223u;
    img.pixels[i] = i % 4 == 3 ? 1.0f : scale * static_cast<float>(seed >> 8) / 16777216.0f;
  }
  return img;
}

// ---- The formulas by hand, in double ----------------------------------------

constexpr double kPi = 3.14159265358979323846;
// D65 white of the sRGB primaries (row sums of the RGB → XYZ matrix).
constexpr double kXn = 0.950428545, kZn = 1.088900371;

struct Lab {
  double l, a, b;
};

double labF(double t) {
  const double d = 6.0 / 29.0;
  return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

// CIELAB of XYZ, then Hunt's adjustment (a, b scaled by L/100).
Lab huntLab(double x, double y, double z) {
  const double fx = labF(x / kXn), fy = labF(y), fz = labF(z / kZn);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(Lab p, Lab q) { return std::abs(p.l - q.l) + std::hypot(p.a - q.a, p.b - q.b); }

// Pure green and pure blue in XYZ: the G and B columns of the sRGB matrix.
double colorMaxByHand() {
  const Lab green = huntLab(8788810.0 / 24577794.0, 8788810.0 / 12288897.0, 8788810.0 / 73733382.0);
  const Lab blue = huntLab(4435075.0 / 24577794.0, 887015.0 / 12288897.0, 70074185.0 / 73733382.0);
  return std::pow(hyab(green, blue), 0.7);
}

// The colour term's remapping: knee at 0.4 cmax mapped to 0.95.
double colourError(double hyabDistance) {
  const double cmax = colorMaxByHand(), knee = 0.4 * cmax, e = std::pow(hyabDistance, 0.7);
  return e < knee ? 0.95 * e / knee : 0.95 + (e - knee) / (cmax - knee) * 0.05;
}

// On a uniform image the float32 derivative filters do not cancel exactly:
// their weights sum to ±1 only up to rounding, leaving |Δfeature| up to about
// 1e-7, and ΔEf = (that/√2)^0.5 up to about 3e-4. ΔE = ΔEc^(1 - ΔEf) then
// moves by at most ΔEf · max(x |ln x|) = ΔEf / e ≈ 1e-4 (the tool computes
// in float32 the same way).
constexpr double kUniformTolerance = 1.5e-4;

// LDR-FLIP, in double, of images whose columns are uniform (every row the
// same), from the formulas alone. Along y every filter then sees a constant
// column: the Gaussians (sum 1) leave it unchanged, the derivatives (sum 0)
// give 0, and the Cz pair h1(x)h1(y) + h2(x)h2(y) reduces to
// (S1·h1(x) + S2·h2(x)) / (S1² + S2²) with S = Σh. What remains are 1-D
// convolutions along x, with clamp to edge.
using Rgb = std::array<double, 3>;

std::vector<double> normalisedGaussian(int radius, double ppd, double b) {
  std::vector<double> g;
  double sum = 0.0;
  for (int k = -radius; k <= radius; ++k) sum += g.emplace_back(std::exp(-kPi * kPi * (k / ppd) * (k / ppd) / b));
  for (double& v : g) v /= sum;
  return g;
}

std::vector<double> convolveRow(const std::vector<double>& row, const std::vector<double>& kernel) {
  const int r = static_cast<int>(kernel.size() / 2), n = static_cast<int>(row.size());
  std::vector<double> out(n, 0.0);
  for (int x = 0; x < n; ++x)
    for (int k = -r; k <= r; ++k) out[x] += kernel[k + r] * row[std::clamp(x + k, 0, n - 1)];
  return out;
}

struct SeenRow {
  std::vector<Lab> lab;              // Hunt-adjusted CIELAB after the CSF
  std::vector<double> edge, point;   // feature strengths
};

SeenRow seeRow(const std::vector<Rgb>& rgb, double ppd) {
  const double m[3][3] = {{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                          {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                          {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
  const double inv[3][3] = {{3.241003275, -1.537398934, -0.498615861},
                            {-0.969224334, 1.875930071, 0.041554224},
                            {0.055639423, -0.204011202, 1.057148933}};
  const auto apply = [](const double (&a)[3][3], const Rgb& v) {
    return Rgb{a[0][0] * v[0] + a[0][1] * v[1] + a[0][2] * v[2], a[1][0] * v[0] + a[1][1] * v[1] + a[1][2] * v[2],
               a[2][0] * v[0] + a[2][1] * v[1] + a[2][2] * v[2]};
  };
  const size_t n = rgb.size();
  std::vector<double> yy(n), cx(n), cz(n), luminance(n);
  for (size_t i = 0; i < n; ++i) {
    const Rgb xyz = apply(m, rgb[i]);
    const double x = xyz[0] / kXn, y = xyz[1], z = xyz[2] / kZn;
    yy[i] = 116.0 * y - 16.0, cx[i] = 500.0 * (x - y), cz[i] = 200.0 * (y - z);
    luminance[i] = y;
  }
  const int r = static_cast<int>(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * kPi * kPi)) * ppd));
  const std::vector<double> gy = normalisedGaussian(r, ppd, 0.0047), gcx = normalisedGaussian(r, ppd, 0.0053);
  // Cz: 34.1·√(π/0.04)·e^(-π²ρ²/0.04) + 13.5·√(π/0.025)·e^(-π²ρ²/0.025), each term separable.
  std::vector<double> h1, h2, gcz;
  double s1 = 0.0, s2 = 0.0;
  for (int k = -r; k <= r; ++k) {
    const double d2 = (k / ppd) * (k / ppd);
    s1 += h1.emplace_back(std::sqrt(34.1 * std::sqrt(kPi / 0.04)) * std::exp(-kPi * kPi * d2 / 0.04));
    s2 += h2.emplace_back(std::sqrt(13.5 * std::sqrt(kPi / 0.025)) * std::exp(-kPi * kPi * d2 / 0.025));
  }
  for (size_t k = 0; k < h1.size(); ++k) gcz.push_back((s1 * h1[k] + s2 * h2[k]) / (s1 * s1 + s2 * s2));
  const std::vector<double> fy = convolveRow(yy, gy), fcx = convolveRow(cx, gcx), fcz = convolveRow(cz, gcz);
  SeenRow seen;
  for (size_t i = 0; i < n; ++i) {
    const double y = (fy[i] + 16.0) / 116.0, x = y + fcx[i] / 500.0, z = y - fcz[i] / 200.0;
    Rgb back = apply(inv, Rgb{x * kXn, y, z * kZn});
    for (double& c : back) c = std::clamp(c, 0.0, 1.0);
    const Rgb xyz = apply(m, back);
    seen.lab.push_back(huntLab(xyz[0], xyz[1], xyz[2]));
  }
  // Features: derivatives of a Gaussian, σ = 0.5·0.082°·ppd pixels, each sign normalised to ±1.
  const double sigma = 0.5 * 0.082 * ppd;
  const int rf = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> d1, d2;
  for (int k = -rf; k <= rf; ++k) {
    const double g = std::exp(-k * k / (2.0 * sigma * sigma));
    d1.push_back(-k * g);
    d2.push_back((k * k / (sigma * sigma) - 1.0) * g);
  }
  for (auto* d : {&d1, &d2}) {
    double pos = 0.0, neg = 0.0;
    for (double v : *d) (v > 0.0 ? pos : neg) += v;
    for (double& v : *d) v /= v > 0.0 ? pos : -neg;
  }
  for (double v : convolveRow(luminance, d1)) seen.edge.push_back(std::abs(v));
  for (double v : convolveRow(luminance, d2)) seen.point.push_back(std::abs(v));
  return seen;
}

std::vector<double> flipOfRowsByHand(const std::vector<Rgb>& reference, const std::vector<Rgb>& test, double ppd) {
  const SeenRow r = seeRow(reference, ppd), t = seeRow(test, ppd);
  std::vector<double> error;
  for (size_t i = 0; i < reference.size(); ++i) {
    const double colour = colourError(hyab(r.lab[i], t.lab[i]));
    const double feature =
        std::sqrt(std::max(std::abs(r.edge[i] - t.edge[i]), std::abs(r.point[i] - t.point[i])) / std::sqrt(2.0));
    error.push_back(std::pow(colour, 1.0 - feature));
  }
  return error;
}

ImageRgbaF fromRow(const std::vector<Rgb>& row, int height) {
  ImageRgbaF img(static_cast<int>(row.size()), height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < img.width; ++x) {
      float* p = img.at(x, y);
      p[0] = static_cast<float>(row[x][0]), p[1] = static_cast<float>(row[x][1]), p[2] = static_cast<float>(row[x][2]);
      p[3] = 1.0f;
    }
  return img;
}

// A step from colour a to colour b at column `edge`.
std::vector<Rgb> stepRow(int width, int edge, Rgb a, Rgb b) {
  std::vector<Rgb> row(width, a);
  std::fill(row.begin() + edge, row.end(), b);
  return row;
}

// ---- Filters and constants ----------------------------------------------------

// Centre weights of the normalised 1-D CSF kernels: docs/flip.md quotes them
// to 7 decimals (the fact sheet's check values); the radius is
// ceil(3 √(0.04 / 2π²) ppd) for all three channels.
TEST(FlipKernels, CsfCheckValues) {
  struct Case {
    double ppd;
    float y, cx, cz1, cz2;
  };
  for (const Case& c : {Case{67.0206433, 0.3857602f, 0.3632691f, 0.1154421f, 0.0816928f},
                        Case{67.0, 0.3858790f, 0.3633810f, 0.1154775f, 0.0817178f}}) {
    SCOPED_TRACE(c.ppd);
    const FlipCsfKernels k = flipCsfKernels(c.ppd);
    EXPECT_EQ(k.radius, static_cast<int>(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * kPi * kPi)) * c.ppd)));
    EXPECT_EQ(k.radius, 10);
    ASSERT_EQ(k.achromatic.size(), 21u);
    ASSERT_EQ(k.blueYellow2.size(), 21u);
    EXPECT_NEAR(k.achromatic[10], c.y, 1e-7);
    EXPECT_NEAR(k.redGreen[10], c.cx, 1e-7);
    EXPECT_NEAR(k.blueYellow1[10], c.cz1, 1e-7);
    EXPECT_NEAR(k.blueYellow2[10], c.cz2, 1e-7);
    // The 2-D Cz kernel h1(x)h1(y) + h2(x)h2(y) sums to (Σh1)² + (Σh2)² = 1.
    double s1 = 0.0, s2 = 0.0;
    for (int i = 0; i < 21; ++i) s1 += k.blueYellow1[i], s2 += k.blueYellow2[i];
    EXPECT_NEAR(s1 * s1 + s2 * s2, 1.0, 1e-6);
  }
}

// σ = 0.5 · 0.082° · ppd pixels, radius ceil(3σ); derivative kernels
// normalised per sign. Check values from docs/flip.md.
TEST(FlipKernels, FeatureCheckValues) {
  struct Case {
    double ppd;
    float g0, g1p1, g20, g2p3;
  };
  for (const Case& c : {Case{67.0206433, 0.1452575f, -0.1256490f, -0.2989015f, 0.0320540f},
                        Case{67.0, 0.1453019f, -0.1257211f, -0.2989764f, 0.0321714f}}) {
    SCOPED_TRACE(c.ppd);
    const FlipFeatureKernels k = flipFeatureKernels(c.ppd);
    EXPECT_EQ(k.radius, static_cast<int>(std::ceil(3.0 * 0.5 * 0.082 * c.ppd)));
    EXPECT_EQ(k.radius, 9);
    ASSERT_EQ(k.gaussian.size(), 19u);
    EXPECT_NEAR(k.gaussian[9], c.g0, 1e-7);
    EXPECT_NEAR(k.derivative1[10], c.g1p1, 1e-7);
    EXPECT_NEAR(k.derivative2[9], c.g20, 1e-7);
    EXPECT_NEAR(k.derivative2[6], c.g2p3, 1e-7);
    EXPECT_NEAR(k.derivative2[12], c.g2p3, 1e-7);
    for (const auto* kernel : {&k.derivative1, &k.derivative2}) {
      double pos = 0.0, neg = 0.0;
      for (float w : *kernel) (w > 0.0f ? pos : neg) += w;
      EXPECT_NEAR(pos, 1.0, 1e-6);
      EXPECT_NEAR(neg, -1.0, 1e-6);
    }
  }
}

// cmax from the formulas in double, and the fact sheet's float32 value.
TEST(FlipKernels, ColorMax) {
  EXPECT_NEAR(colorMaxByHand(), 41.276096, 2e-5);
  EXPECT_NEAR(flipColorMax(), colorMaxByHand(), 2e-5);
  EXPECT_NEAR(flipColorMax(), 41.276096f, 1e-5);
}

// ---- LDR-FLIP -------------------------------------------------------------------

TEST(FlipLdr, IdenticalImagesGiveZero) {
  const ImageRgbaF img = noise(48, 40, 7);
  const FlipResult r = flipLdr(img, img);
  ASSERT_EQ(r.errorMap.size(), img.pixelCount());
  EXPECT_EQ(*std::max_element(r.errorMap.begin(), r.errorMap.end()), 0.0f);
  EXPECT_EQ(r.pooled.mean, 0.0f);
  EXPECT_EQ(r.pooled.count, img.pixelCount());
  EXPECT_EQ(r.exposureCount, 0);
}

// Every step of LDR-FLIP treats the two images alike (|Δ| and squares).
TEST(FlipLdr, SwappingImagesGivesTheSameMap) {
  const ImageRgbaF a = noise(40, 32, 1), b = noise(40, 32, 2);
  const FlipResult ab = flipLdr(a, b), ba = flipLdr(b, a);
  EXPECT_EQ(ab.errorMap, ba.errorMap);
  EXPECT_GT(ab.pooled.mean, 0.1f);
}

// cmax is defined as the distance of green and blue: ΔEc = 1, and uniform
// images have no features (ΔEf = 0), so every pixel is 1. Clamp-to-edge keeps
// uniform images uniform, borders included.
TEST(FlipLdr, GreenVersusBlueIsOne) {
  const FlipResult r = flipLdr(uniform(32, 24, 0, 1, 0), uniform(32, 24, 0, 0, 1));
  for (float e : r.errorMap) ASSERT_NEAR(e, 1.0f, 1e-5);
}

// Black: XYZ 0, so f = 4/29 and L = 116·4/29 - 16 = 0, a = b = 0.
// White: XYZ = the white point, x = y = z = 1, L = 100, a = b = 0.
// HyAB = 100, e = 100^0.7 = 25.1189 > 0.4 cmax = 16.5104, so
// ΔEc = 0.95 + (25.1189 - 16.5104) / (41.2761 - 16.5104) · 0.05 = 0.967380;
// no features in uniform images: ΔE = ΔEc.
TEST(FlipLdr, BlackVersusWhiteByHand) {
  const Lab black = huntLab(0, 0, 0), white = huntLab(kXn, 1.0, kZn);
  EXPECT_NEAR(black.l, 0.0, 1e-12);
  EXPECT_NEAR(white.l, 100.0, 1e-9);
  const double expected = colourError(hyab(black, white));
  EXPECT_NEAR(expected, 0.967380, 1e-6);
  const FlipResult r = flipLdr(uniform(32, 24, 0, 0, 0), uniform(32, 24, 1, 1, 1));
  for (float e : r.errorMap) ASSERT_NEAR(e, expected, kUniformTolerance);
  EXPECT_NEAR(r.pooled.meanDouble, expected, kUniformTolerance);
}

// Uniform greys g: XYZ = g · white, so L = 116 f(g) - 16, a = b = 0 and
// HyAB = |ΔL|. The pairs put e = HyAB^0.7 on both sides of the knee 0.4 cmax
// = 16.51 (HyAB 55.0), and just above it.
TEST(FlipLdr, UniformGreysByHand) {
  const auto lightness = [](double g) { return 116.0 * labF(g) - 16.0; };
  for (const auto& [a, b] : {std::pair{0.2, 0.25}, std::pair{0.0, 0.1}, std::pair{0.0, 0.28}, std::pair{0.05, 0.6}}) {
    SCOPED_TRACE(testing::Message() << a << " vs " << b);
    const double expected = colourError(std::abs(lightness(a) - lightness(b)));
    const float fa = static_cast<float>(a), fb = static_cast<float>(b);
    const FlipResult r = flipLdr(uniform(24, 24, fa, fa, fa), uniform(24, 24, fb, fb, fb));
    for (float e : r.errorMap) ASSERT_NEAR(e, expected, kUniformTolerance);
  }
  // Black | 0.28: HyAB = 60.2, e = 17.6, within 10 % above the knee.
  const double e = std::pow(lightness(0.28), 0.7), knee = 0.4 * colorMaxByHand();
  EXPECT_GT(e, knee);
  EXPECT_LT(e, 1.1 * knee);
}

// Step edges, the test's edge 3 pixels to the right of the reference's, the
// whole map against the 1-D derivation above. A grey step stays in the RGB
// cube; a red-blue step leaves it after filtering (the three channels are
// blurred by different amounts) and exercises the clamp, the chroma and Cz.
// Outside the reach of both filters (CSF radius 10, feature radius 9) around
// the changed columns the images look alike: error exactly 0.
// Tolerance: float32 leaves L off by ~1e-5; where ΔL is tiny (the fringe of
// the filters' reach) HyAB^0.7 magnifies that, up to 2e-4 in ΔE (measured:
// 1.7e-4 on the grey step, 2e-5 where ΔE > 0.05).
constexpr double kStepTolerance = 3e-4;

TEST(FlipLdr, ShiftedStepEdgesByHand) {
  const int w = 96, h = 12, edge = 48, shift = 3;
  const double ppd = FlipOptions{}.ppd;
  const int reach = std::max(flipCsfKernels(ppd).radius, flipFeatureKernels(ppd).radius);
  struct Case {
    const char* name;
    Rgb a, b;
  };
  for (const Case& c : {Case{"grey 0.2 | 0.6", {0.2, 0.2, 0.2}, {0.6, 0.6, 0.6}},
                        Case{"red | blue", {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}},
                        Case{"dark green | light grey", {0.05, 0.3, 0.1}, {0.8, 0.8, 0.8}}}) {
    SCOPED_TRACE(c.name);
    const std::vector<Rgb> refRow = stepRow(w, edge, c.a, c.b), testRow = stepRow(w, edge + shift, c.a, c.b);
    const std::vector<double> expected = flipOfRowsByHand(refRow, testRow, ppd);
    const FlipResult r = flipLdr(fromRow(refRow, h), fromRow(testRow, h));
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const float e = r.errorMap[size_t(y) * w + x];
        if (x < edge - reach || x >= edge + shift + reach) {
          ASSERT_EQ(e, 0.0f) << x << "," << y;
        }
        ASSERT_NEAR(e, expected[x], kStepTolerance) << x << "," << y;
      }
    }
    EXPECT_GT(expected[edge + 1], 0.3);
  }
}

// Same two colours in the same proportion, different structure: stripes one
// pixel wide against a checkerboard. The CSF blurs both to nearly the same
// grey (a small colour error), but stripes have strong point responses that
// the checkerboard lacks, and ΔE = ΔEc^(1 - ΔEf) grows with the feature
// difference. The checkerboard against its inverse (also one pixel apart, no
// feature change) shows the colour-only error for comparison.
TEST(FlipLdr, FeatureChangeRaisesTheError) {
  const int n = 64;
  ImageRgbaF stripes(n, n), checker(n, n), inverse(n, n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const auto set = [&](ImageRgbaF& img, bool bright) {
        std::fill(img.at(x, y), img.at(x, y) + 3, bright ? 0.6f : 0.3f);
        img.at(x, y)[3] = 1.0f;
      };
      set(stripes, x % 2 == 0);
      set(checker, (x + y) % 2 == 0);
      set(inverse, (x + y) % 2 == 1);
    }
  const float structure = flipLdr(stripes, checker).pooled.mean;
  const float colourOnly = flipLdr(checker, inverse).pooled.mean;
  EXPECT_GT(colourOnly, 0.0f);
  EXPECT_GT(structure, 3.0f * colourOnly);
}

TEST(FlipLdr, SrgbInputIsDecodedFirst) {
  // sRGB 0.5 is linear ((0.5 + 0.055) / 1.055)^2.4 = 0.214041.
  const ImageRgbaF encoded = uniform(24, 24, 0.5f, 0.5f, 0.5f), black = uniform(24, 24, 0, 0, 0);
  const float linear = static_cast<float>(std::pow((0.5 + 0.055) / 1.055, 2.4));
  const ImageRgbaF decoded = uniform(24, 24, linear, linear, linear);
  const FlipResult viaSrgb = flipLdrSrgb(encoded, black), viaLinear = flipLdr(decoded, black);
  EXPECT_NEAR(viaSrgb.pooled.mean, viaLinear.pooled.mean, 1e-6);
  EXPECT_GT(viaSrgb.pooled.mean, 0.5f);
}

// Values outside [0, 1] are clamped: 4.0 looks like 1.0.
TEST(FlipLdr, ClampsToTheUnitRange) {
  const FlipResult r = flipLdr(uniform(24, 24, 4, 4, 4), uniform(24, 24, 1, 1, 1));
  EXPECT_EQ(r.pooled.max, 0.0f);
}

TEST(FlipLdr, RejectsBadInput) {
  const ImageRgbaF a = uniform(8, 8, 0.5f, 0.5f, 0.5f);
  EXPECT_THROW(flipLdr(a, uniform(8, 9, 0.5f, 0.5f, 0.5f)), std::invalid_argument);
  EXPECT_THROW(flipLdr(ImageRgbaF(), ImageRgbaF()), std::invalid_argument);
  FlipOptions badPpd;
  badPpd.ppd = 0.0;
  EXPECT_THROW(flipLdr(a, a, badPpd), std::invalid_argument);
  ImageRgbaF withNan = a;
  withNan.at(1, 2)[1] = std::numeric_limits<float>::quiet_NaN();
  withNan.at(3, 4)[0] = std::numeric_limits<float>::infinity();
  try {
    flipLdr(a, withNan);
    FAIL() << "a NaN pixel was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test has 2 non-finite"), std::string::npos) << m;
    EXPECT_NE(m.find("pixel (1, 2) G = nan"), std::string::npos) << m;
  }
  EXPECT_THROW(flipHdr(withNan, a), std::invalid_argument);
  // Alpha is not looked at: a NaN there changes nothing.
  ImageRgbaF nanAlpha = a;
  nanAlpha.at(0, 0)[3] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(flipLdr(a, nanAlpha).pooled.max, 0.0f);
}

// ---- Pooling --------------------------------------------------------------------

// Four values, one per bucket 10, 20, 30, 40; total 1.02.
// Weighted percentiles: running sums 0.105, 0.31, 0.615, 1.02 first exceed
// 0.255 at 0.205, 0.51 at 0.305, 0.765 at 0.405.
// Histogram: masses (i + 0.5)·0.01 = 0.105, 0.205, 0.305, 0.405 (total 1.02);
// p = 0.5: target 0.51 falls in bucket 30 after 0.31: (30 + 0.2/0.305)·0.01.
TEST(FlipPooling, ByHand) {
  const std::vector<float> errors = {0.305f, 0.105f, 0.405f, 0.205f};
  const FlipPooled p = poolFlipErrors(errors);
  EXPECT_EQ(p.count, 4u);
  EXPECT_NEAR(p.mean, 0.255f, 1e-7);
  EXPECT_NEAR(p.meanDouble, 0.255, 1e-7);
  EXPECT_EQ(p.min, 0.105f);
  EXPECT_EQ(p.max, 0.405f);
  EXPECT_EQ(p.weightedQuartile1, 0.205f);
  EXPECT_EQ(p.weightedMedian, 0.305f);
  EXPECT_EQ(p.weightedQuartile3, 0.405f);
  for (size_t i = 0; i < p.histogram.size(); ++i)
    EXPECT_EQ(p.histogram[i], i == 10 || i == 20 || i == 30 || i == 40 ? 1u : 0u) << i;
  EXPECT_NEAR(p.histogramWeighted50, (30.0 + 0.2 / 0.305) * 0.01, 1e-6);
  // p = 0.25: target 0.255 in bucket 20 after 0.105: (20 + 0.15/0.205)·0.01.
  EXPECT_NEAR(p.histogramWeighted25, (20.0 + 0.15 / 0.205) * 0.01, 1e-6);
}

// "Exceeds", not "reaches": 0.1, 0.4, 0.5 (float sums 0.1, 0.5, 1.0 exactly
// on the way): the running sum reaches half the total at 0.4 but exceeds it
// only at 0.5.
TEST(FlipPooling, WeightedPercentileNeedsToExceed) {
  EXPECT_EQ(poolFlipErrors(std::vector<float>{0.5f, 0.1f, 0.4f}).weightedMedian, 0.5f);
}

// The mean is the tool's float32 running sum: after 1.0, each 1e-8 is lost.
TEST(FlipPooling, MeanIsAFloatRunningSum) {
  std::vector<float> errors(1001, 1e-8f);
  errors[0] = 1.0f;
  const FlipPooled p = poolFlipErrors(errors);
  EXPECT_EQ(p.mean, 1.0f / 1001.0f);
  EXPECT_NEAR(p.meanDouble, (1.0 + 1000 * double(1e-8f)) / 1001.0, 1e-15);
}

TEST(FlipPooling, EdgeValuesAndMasks) {
  // 1.0 goes into the last bucket.
  EXPECT_EQ(poolFlipErrors(std::vector<float>{1.0f}).histogram[99], 1u);
  const std::vector<float> errors = {0.305f, 0.105f, 0.405f, 0.205f};
  const std::vector<uint8_t> mask = {1, 1, 0, 0};
  const FlipPooled p = poolFlipErrors(errors, mask);
  EXPECT_EQ(p.count, 2u);
  EXPECT_NEAR(p.mean, 0.205f, 1e-7);
  EXPECT_EQ(p.max, 0.305f);
  // A mask of zeros: a defined, NaN-free result with count 0.
  const FlipPooled none = poolFlipErrors(errors, std::vector<uint8_t>(4, 0));
  EXPECT_EQ(none.count, 0u);
  EXPECT_EQ(none.mean, 0.0f);
  EXPECT_EQ(none.meanDouble, 0.0);
  EXPECT_EQ(none.weightedMedian, 0.0f);
  EXPECT_EQ(none.histogramWeighted50, 0.0f);
  EXPECT_THROW(poolFlipErrors(errors, std::vector<uint8_t>{1, 2, 0, 0}), std::invalid_argument);
  EXPECT_THROW(poolFlipErrors(errors, std::vector<uint8_t>{1, 1}), std::invalid_argument);
}

// The mask restricts the pooling, not the map.
TEST(FlipPooling, MaskedFlipPoolsTheRegionOnly) {
  const ImageRgbaF a = noise(32, 32, 3), b = noise(32, 32, 4);
  std::vector<uint8_t> mask(a.pixelCount(), 0);
  std::fill(mask.begin(), mask.begin() + 5 * 32, 1);  // the top five rows
  FlipOptions o;
  o.mask = mask;
  const FlipResult masked = flipLdr(a, b, o), whole = flipLdr(a, b);
  EXPECT_EQ(masked.errorMap, whole.errorMap);
  EXPECT_EQ(masked.pooled.count, 5u * 32u);
  double sum = 0.0;
  for (size_t i = 0; i < 5 * 32; ++i) sum += whole.errorMap[i];
  EXPECT_NEAR(masked.pooled.meanDouble, sum / (5 * 32), 1e-12);
  o.mask = std::span<const uint8_t>(mask.data(), 10);
  EXPECT_THROW(flipLdr(a, b, o), std::invalid_argument);
}

// ---- HDR-FLIP -------------------------------------------------------------------

// x with T(x) = 0.85 for each tone curve, solved here in double from the
// curves' published constants: ACES (Narkowicz 2016: 2.51, 0.03, 2.43, 0.59,
// 0.14) applied to 0.6x; Hable's filmic curve (A..F = 0.15, 0.50, 0.10, 0.20,
// 0.02, 0.30) at exposure bias 2 divided by its value at white 11.2;
// Reinhard x / (1 + x).
double acesInputFor(double t) {
  const double a = 2.51 * 0.36 - t * 2.43 * 0.36, b = 0.03 * 0.6 - t * 0.59 * 0.6, c = -t * 0.14;
  return (-b + std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
}
double hable(double x) {
  const double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30;
  return (x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F) - E / F;
}
double hableInputFor(double t) {
  double lo = 0.0, hi = 100.0;  // bisection: the curve rises monotonically
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (hable(2.0 * mid) / hable(11.2) < t ? lo : hi) = mid;
  }
  return lo;
}

// A uniform reference: its brightest and its median luminance are the same,
// so start = stop = log2(x*/Y) and two (equal) exposures are evaluated.
TEST(FlipHdr, ExposureRangeOfAUniformReference) {
  const ImageRgbaF ref = uniform(24, 24, 0.5f, 0.5f, 0.5f);  // Y = 0.5
  struct Case {
    FlipToneMapper mapper;
    double x;
  };
  for (const Case& c : {Case{FlipToneMapper::Aces, acesInputFor(0.85)},
                        Case{FlipToneMapper::Hable, hableInputFor(0.85)},
                        Case{FlipToneMapper::Reinhard, 0.85 / 0.15}}) {
    FlipOptions o;
    o.toneMapper = c.mapper;
    const FlipResult r = flipHdr(ref, ref, o);
    EXPECT_NEAR(r.startExposure, std::log2(c.x / 0.5), 2e-4);
    EXPECT_NEAR(r.stopExposure, std::log2(c.x / 0.5), 2e-4);
    EXPECT_EQ(r.exposureCount, 2);
    EXPECT_EQ(r.pooled.max, 0.0f);
  }
  EXPECT_NEAR(acesInputFor(0.85), 2.118873, 1e-6);
  EXPECT_NEAR(hableInputFor(0.85), 3.127750, 2e-5);  // the folded coefficients are rounded to 6 digits
  // Luminance is 0.2126 R + 0.7152 G + 0.0722 B: pure green has Y = 0.7152.
  const FlipResult green = flipHdr(uniform(24, 24, 0, 1, 0), uniform(24, 24, 0, 1, 0));
  EXPECT_NEAR(green.startExposure, std::log2(acesInputFor(0.85) / 0.7152), 2e-5);
}

// 16 grey pixels (Y = value) 1 ... 16: max 16, median = the element of rank
// 8 (0-based: the upper median, no averaging) = 9. ACES: start =
// log2(x*/16), stop = log2(x*/9), count = max(2, ceil(log2(16/9) = 0.83)) = 2.
// Then 2^-8 ... 2^6 and 100: median rank 8 = 2^0, stop - start = log2(100)
// = 6.64 → 7 exposures.
TEST(FlipHdr, ExposureRangeFromMaxAndMedian) {
  ImageRgbaF ref(4, 4);
  const auto setGrey = [&](int i, float v) {
    std::fill(ref.pixels.begin() + i * 4, ref.pixels.begin() + i * 4 + 3, v);
  };
  for (int i = 0; i < 16; ++i) setGrey(i, float(16 - i));
  const double x = acesInputFor(0.85);
  FlipResult r = flipHdr(ref, ref);
  EXPECT_NEAR(r.startExposure, std::log2(x / 16.0), 2e-5);
  EXPECT_NEAR(r.stopExposure, std::log2(x / 9.0), 2e-5);
  EXPECT_EQ(r.exposureCount, 2);
  for (int i = 0; i < 15; ++i) setGrey(i, std::exp2(float(i - 8)));
  setGrey(15, 100.0f);
  r = flipHdr(ref, ref);
  EXPECT_NEAR(r.startExposure, std::log2(x / 100.0), 2e-5);
  EXPECT_NEAR(r.stopExposure, std::log2(x / 1.0), 2e-5);
  EXPECT_EQ(r.exposureCount, 7);
}

// More than half the reference black (a render's background): the median
// of the positive luminances sets the stop exposure.
TEST(FlipHdr, BlackBackgroundUsesThePositiveMedian) {
  ImageRgbaF ref = uniform(4, 4, 0, 0, 0);
  for (int i = 0; i < 5; ++i) std::fill(ref.pixels.begin() + i * 4, ref.pixels.begin() + i * 4 + 3, float(i + 1));
  const FlipResult r = flipHdr(ref, ref);
  // positives 1..5: rank floor(5/2) = 2 → 3.
  EXPECT_NEAR(r.stopExposure, std::log2(acesInputFor(0.85) / 3.0), 2e-5);
  EXPECT_NEAR(r.startExposure, std::log2(acesInputFor(0.85) / 5.0), 2e-5);
  // Fewer zeros than half: they count. 3 zeros and 1..13: rank 8 of all is 6
  // (of the positives alone it would be 7).
  for (int i = 0; i < 13; ++i) std::fill(ref.pixels.begin() + i * 4, ref.pixels.begin() + i * 4 + 3, float(i + 1));
  EXPECT_NEAR(flipHdr(ref, ref).stopExposure, std::log2(acesInputFor(0.85) / 6.0), 2e-5);
}

// A denormal median (a sparse path-traced image at few samples): x / L
// overflows float, the stop exposure (~130 stops) does not.
TEST(FlipHdr, DenormalMedianGivesFiniteExposures) {
  ImageRgbaF ref = uniform(4, 4, 1e-39f, 1e-39f, 1e-39f);
  std::fill(ref.pixels.begin(), ref.pixels.begin() + 3, 1.0f);
  const FlipResult r = flipHdr(ref, ref);
  const double x = acesInputFor(0.85);
  EXPECT_NEAR(r.startExposure, std::log2(x / 1.0), 2e-5);
  EXPECT_NEAR(r.stopExposure, std::log2(x / 1e-39), 0.01);  // the luminance of a denormal grey rounds
  EXPECT_EQ(r.pooled.mean, 0.0f);  // identical images
}

TEST(FlipHdr, IdenticalImagesGiveZero) {
  const ImageRgbaF img = noise(40, 32, 9, 20.0f);
  const FlipResult r = flipHdr(img, img);
  EXPECT_GE(r.exposureCount, 2);
  EXPECT_EQ(*std::max_element(r.errorMap.begin(), r.errorMap.end()), 0.0f);
  EXPECT_EQ(r.pooled.mean, 0.0f);
}

// Grey 4 against grey 8: LDR-FLIP clamps both to white and sees nothing;
// HDR-FLIP exposes them down and sees the difference. With given exposures
// the map is the per-pixel maximum of the LDR-FLIP maps of the tone-mapped
// images, here uniform greys: at exposure c the values 4·2^c and 8·2^c go
// through ACES, i.e. 0.6·4·2^c and 0.6·8·2^c through Narkowicz's curve.
TEST(FlipHdr, SeesDifferencesAboveOne) {
  const ImageRgbaF ref = uniform(24, 24, 4, 4, 4), test = uniform(24, 24, 8, 8, 8);
  EXPECT_EQ(flipLdr(ref, test).pooled.max, 0.0f);
  const auto aces = [](double x) { return x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14); };
  // Grey g: XYZ = g·white, L = 116 f(g) - 16, a = b = 0: HyAB = |ΔL|.
  const auto lightness = [](double g) { return 116.0 * labF(g) - 16.0; };
  const auto atExposure = [&](double c) {
    return colourError(std::abs(lightness(aces(0.6 * 4.0 * std::exp2(c))) - lightness(aces(0.6 * 8.0 * std::exp2(c)))));
  };
  // Exposures -2 (0.673 vs 0.840 after ACES), then -6 and -2 (the darker one
  // separates the greys more: it is the maximum).
  for (const auto& [start, stop] : {std::pair{-2.0f, -2.0f}, std::pair{-6.0f, -2.0f}}) {
    FlipOptions o;
    o.startExposure = start, o.stopExposure = stop, o.exposureCount = 2;
    const FlipResult r = flipHdr(ref, test, o);
    const double expected = std::max(atExposure(start), atExposure(stop));
    for (float e : r.errorMap) ASSERT_NEAR(e, expected, kUniformTolerance) << start << " to " << stop;
  }
  EXPECT_GT(atExposure(-6.0), atExposure(-2.0) + 0.05);
  EXPECT_GT(atExposure(-2.0), 0.2);
  // ACES exceeds 1 above x = 12.07 (0.6x through Narkowicz): 30 and 60 map
  // to 1.020 and 1.026, clamped to 1 before LDR-FLIP, so a step from either
  // to grey 0.5 looks the same.
  FlipOptions o;
  o.startExposure = 0.0f, o.stopExposure = 0.0f;
  const auto step = [](double bright) {
    return fromRow(stepRow(48, 24, {bright, bright, bright}, {0.5, 0.5, 0.5}), 8);
  };
  EXPECT_EQ(flipHdr(step(30.0), step(60.0), o).pooled.max, 0.0f);
}

// Reinhard divides the colour by 1 + its luminance (not each channel by
// 1 + itself): pure red 1 becomes 1/1.2126 = 0.8247 red, against black.
TEST(FlipHdr, ReinhardMapsByLuminance) {
  FlipOptions o;
  o.toneMapper = FlipToneMapper::Reinhard;
  o.startExposure = 0.0f, o.stopExposure = 0.0f;
  const FlipResult r = flipHdr(uniform(24, 24, 1, 0, 0), uniform(24, 24, 0, 0, 0), o);
  const double red = 1.0 / (1.0 + 0.2126);
  const Lab mapped = huntLab(red * 10135552.0 / 24577794.0, red * 2613072.0 / 12288897.0, red * 1425312.0 / 73733382.0);
  const double expected = colourError(hyab(mapped, huntLab(0, 0, 0)));
  for (float e : r.errorMap) ASSERT_NEAR(e, expected, kUniformTolerance);
}

TEST(FlipHdr, RejectsBadExposures) {
  const ImageRgbaF img = uniform(8, 8, 1, 1, 1);
  FlipOptions o;
  o.startExposure = 1.0f, o.stopExposure = 0.0f;
  EXPECT_THROW(flipHdr(img, img, o), std::invalid_argument);
  o = {};
  o.exposureCount = 1;
  EXPECT_THROW(flipHdr(img, img, o), std::invalid_argument);
  // An all-black reference has no exposure range unless one is given.
  const ImageRgbaF black = uniform(8, 8, 0, 0, 0);
  EXPECT_THROW(flipHdr(black, img), std::invalid_argument);
  o = {};
  o.startExposure = -1.0f, o.stopExposure = 1.0f;
  EXPECT_GT(flipHdr(black, img, o).pooled.mean, 0.5f);
}

// ---- Magma ------------------------------------------------------------------------

// Entries 0, 128 and 255 of matplotlib's magma: (0.001462, 0.000466, 0.013866),
// (0.716387, 0.214982, 0.475290), (0.987053, 0.991438, 0.749504); bytes
// floor(255c + 0.5).
TEST(FlipMagma, EndpointsAndMiddle) {
  const std::vector<uint8_t> rgba = magmaRgba8(std::vector<float>{0.0f, 0.5f, 1.0f, 2.0f, -1.0f});
  const std::vector<uint8_t> expected = {0, 0, 4, 255, 183, 55, 121, 255, 252, 253, 191, 255,
                                         252, 253, 191, 255, 0, 0, 4, 255};
  EXPECT_EQ(rgba, expected);
  // The entry is floor(255e + 0.5): 126.49/255 → 126, 126.51/255 → 127.
  const auto bytesOf = [](const std::array<float, 3>& c) {
    return std::vector<uint8_t>{static_cast<uint8_t>(std::floor(255.0 * c[0] + 0.5)),
                                static_cast<uint8_t>(std::floor(255.0 * c[1] + 0.5)),
                                static_cast<uint8_t>(std::floor(255.0 * c[2] + 0.5)), 255};
  };
  EXPECT_EQ(magmaRgba8(std::vector<float>{126.49f / 255.0f}), bytesOf(magmaTable()[126]));
  EXPECT_EQ(magmaRgba8(std::vector<float>{126.51f / 255.0f}), bytesOf(magmaTable()[127]));
  EXPECT_THROW(magmaRgba8(std::vector<float>{std::numeric_limits<float>::quiet_NaN()}), std::invalid_argument);
}

// ---- RMSE and relative MSE ----------------------------------------------------------

// Two pixels: reference (0.5, 0.5, 0.5), (1, 0, 0); test (0.75, 0.5, 0.5), (1, 0, 0.25).
// Squared differences 0.0625 and 0.0625 over 6 values: RMSE = √(0.125/6).
// Relative: 0.0625/(0.25 + 0.01) and 0.0625/(0 + 0.01) over 6 values.
TEST(ImageMetrics, ByHand) {
  ImageRgbaF ref(2, 1), test(2, 1);
  ref.pixels = {0.5f, 0.5f, 0.5f, 1.0f, 1.0f, 0.0f, 0.0f, 1.0f};
  test.pixels = {0.75f, 0.5f, 0.5f, 1.0f, 1.0f, 0.0f, 0.25f, 0.0f};
  const ImageMetrics m = compareImages(ref, test);
  EXPECT_EQ(m.pixels, 2u);
  EXPECT_NEAR(m.rmse, std::sqrt(0.125 / 6.0), 1e-12);
  EXPECT_NEAR(m.relMse, (0.0625 / 0.26 + 0.0625 / 0.01) / 6.0, 1e-12);
  // Only the first pixel.
  const ImageMetrics first = compareImages(ref, test, std::vector<uint8_t>{1, 0});
  EXPECT_EQ(first.pixels, 1u);
  EXPECT_NEAR(first.rmse, std::sqrt(0.0625 / 3.0), 1e-12);
  EXPECT_NEAR(first.relMse, 0.0625 / 0.26 / 3.0, 1e-12);
  const ImageMetrics none = compareImages(ref, test, std::vector<uint8_t>{0, 0});
  EXPECT_EQ(none.pixels, 0u);
  EXPECT_EQ(none.rmse, 0.0);
  EXPECT_EQ(none.relMse, 0.0);
  const ImageRgbaF rel = relativeSquaredError(ref, test);
  EXPECT_NEAR(rel.at(0, 0)[0], 0.0625 / 0.26, 1e-7);
  EXPECT_NEAR(rel.at(1, 0)[2], 6.25, 1e-6);
  EXPECT_EQ(rel.at(1, 0)[0], 0.0f);
  EXPECT_EQ(rel.at(1, 0)[3], 1.0f);
}

TEST(ImageMetrics, NonFiniteValuesAreCountedAndLeftOut) {
  ImageRgbaF ref(2, 1), test(2, 1);
  ref.pixels = {0.5f, 0.5f, 0.5f, 1.0f, 1.0f, 0.0f, 0.0f, 1.0f};
  test.pixels = {0.75f, 0.5f, 0.5f, 1.0f, std::numeric_limits<float>::infinity(), 0.0f,
                 std::numeric_limits<float>::quiet_NaN(), 1.0f};
  const ImageMetrics m = compareImages(ref, test);
  EXPECT_EQ(m.nonFiniteTest, 2u);
  EXPECT_EQ(m.nonFiniteReference, 0u);
  EXPECT_EQ(m.pixels, 1u);
  EXPECT_NEAR(m.rmse, std::sqrt(0.0625 / 3.0), 1e-12);
  EXPECT_TRUE(std::isnan(relativeSquaredError(ref, test).at(1, 0)[0]));
  // Masked out: not counted either.
  EXPECT_EQ(compareImages(ref, test, std::vector<uint8_t>{1, 0}).nonFiniteTest, 0u);
  EXPECT_THROW(compareImages(ref, ImageRgbaF(1, 1)), std::invalid_argument);
  EXPECT_THROW(compareImages(ref, test, std::vector<uint8_t>{1, 3}), std::invalid_argument);
}

}  // namespace
}  // namespace ft
