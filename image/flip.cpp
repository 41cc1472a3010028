// flip.cpp — LDR-FLIP and HDR-FLIP (Andersson et al. 2020, 2021), float32
// as NVIDIA's tool computes; docs/flip.md gives every step and its source.
#include "image/flip.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

#include "image/image_io.h"

namespace ft {
namespace {

constexpr float kPi = 3.14159265358979f;  // the tool's float π
// Colour term: HyAB exponent, knee of the remapping (a
// fraction of cmax) and the error value the knee maps to.
constexpr float kQc = 0.7f, kPc = 0.4f, kPt = 0.95f;
// Feature term: detector width in degrees (peak to trough), exponent.
constexpr float kFeatureWidth = 0.082f, kQf = 0.5f;
// HDR-FLIP: the tone-mapped value the brightest (start) and the median
// (stop) reference luminance are exposed to.
constexpr float kExposureTarget = 0.85f;
// Kernel radii grow as 0.135 ppd; typical viewing gives 30 to 100.
constexpr double kMaxPpd = 1000.0;

// D65 reference white and the reciprocals the tool multiplies by.
constexpr float kWhiteX = 0.950428545f, kWhiteZ = 1.088900371f;
constexpr float kInvWhiteX = 1.052156925f, kInvWhiteZ = 0.918357670f;

using Plane = std::vector<float>;

struct Vec3 {
  float x, y, z;
};

// sRGB primaries, D65 white, as exact fractions: (1, 1, 1) maps to the white point.
Vec3 linearRgbToXyz(Vec3 c) {
  constexpr float m[3][3] = {
      {10135552.0f / 24577794.0f, 8788810.0f / 24577794.0f, 4435075.0f / 24577794.0f},
      {2613072.0f / 12288897.0f, 8788810.0f / 12288897.0f, 887015.0f / 12288897.0f},
      {1425312.0f / 73733382.0f, 8788810.0f / 73733382.0f, 70074185.0f / 73733382.0f}};
  return {m[0][0] * c.x + m[0][1] * c.y + m[0][2] * c.z, m[1][0] * c.x + m[1][1] * c.y + m[1][2] * c.z,
          m[2][0] * c.x + m[2][1] * c.y + m[2][2] * c.z};
}

Vec3 xyzToLinearRgb(Vec3 c) {
  constexpr float m[3][3] = {{3.241003275f, -1.537398934f, -0.498615861f},
                             {-0.969224334f, 1.875930071f, 0.041554224f},
                             {0.055639423f, -0.204011202f, 1.057148933f}};
  return {m[0][0] * c.x + m[0][1] * c.y + m[0][2] * c.z, m[1][0] * c.x + m[1][1] * c.y + m[1][2] * c.z,
          m[2][0] * c.x + m[2][1] * c.y + m[2][2] * c.z};
}

// YCxCz (Y', Cx, Cz): CIELAB without the cube root, linear so it can be filtered.
Vec3 xyzToYcxcz(Vec3 c) {
  const float x = c.x * kInvWhiteX, y = c.y, z = c.z * kInvWhiteZ;
  return {116.0f * y - 16.0f, 500.0f * (x - y), 200.0f * (y - z)};
}

Vec3 ycxczToXyz(Vec3 c) {
  const float y = (c.x + 16.0f) / 116.0f;
  const float x = y + c.y / 500.0f;
  const float z = y - c.z / 200.0f;
  return {x * kWhiteX, y, z * kWhiteZ};
}

float labF(float t) {
  constexpr float delta = 6.0f / 29.0f;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3.0f * delta * delta) + 4.0f / 29.0f;
}

// CIELAB with Hunt's adjustment: chroma grows with lightness (a, b scaled by L/100).
Vec3 xyzToHuntLab(Vec3 c) {
  const float fx = labF(c.x * kInvWhiteX), fy = labF(c.y), fz = labF(c.z * kInvWhiteZ);
  const float l = 116.0f * fy - 16.0f;
  const float a = 500.0f * (fx - fy), b = 200.0f * (fy - fz);
  return {l, 0.01f * l * a, 0.01f * l * b};
}

// HyAB: city-block in lightness, Euclidean in the chromatic plane.
float hyab(Vec3 p, Vec3 q) {
  const float da = p.y - q.y, db = p.z - q.z;
  return std::abs(p.x - q.x) + std::sqrt(da * da + db * db);
}

// Parallel over rows; every pixel is computed alone, so the result does not
// depend on the split.
template <class RowFn>
void forEachRow(int height, RowFn&& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y) fn(y);
  });
}

// Separable convolution, clamp to edge, into `out` (reused: no allocation
// once sized). Each pixel sums its weights in ascending offset; the loops run
// offset-outer over a row so the inner one vectorizes.
void convolveX(const Plane& in, int width, int height, const std::vector<float>& kernel, Plane& out) {
  const int r = static_cast<int>(kernel.size() / 2);
  out.resize(in.size());
  forEachRow(height, [&](int y) {
    const float* row = in.data() + static_cast<size_t>(y) * width;
    std::vector<float> padded(width + 2 * r);
    for (int i = 0; i < width + 2 * r; ++i) padded[i] = row[std::clamp(i - r, 0, width - 1)];
    float* __restrict dst = out.data() + static_cast<size_t>(y) * width;
    std::fill(dst, dst + width, 0.0f);
    for (int k = 0; k <= 2 * r; ++k) {
      const float w = kernel[k];
      const float* __restrict src = padded.data() + k;
      for (int x = 0; x < width; ++x) dst[x] += w * src[x];
    }
  });
}

void convolveY(const Plane& in, int width, int height, const std::vector<float>& kernel, Plane& out) {
  const int r = static_cast<int>(kernel.size() / 2);
  out.resize(in.size());
  forEachRow(height, [&](int y) {
    float* __restrict dst = out.data() + static_cast<size_t>(y) * width;
    std::fill(dst, dst + width, 0.0f);
    for (int k = 0; k <= 2 * r; ++k) {
      const float w = kernel[k];
      const float* __restrict src = in.data() + static_cast<size_t>(std::clamp(y + k - r, 0, height - 1)) * width;
      for (int x = 0; x < width; ++x) dst[x] += w * src[x];
    }
  });
}

struct RgbPlanes {
  int width = 0, height = 0;
  Plane r, g, b;
  explicit RgbPlanes(int w, int h) : width(w), height(h), r(size_t(w) * h), g(size_t(w) * h), b(size_t(w) * h) {}
  Vec3 at(size_t i) const { return {r[i], g[i], b[i]}; }
};

// One image as FLIP sees it.
struct Perceived {
  Plane l, a, b;      // Hunt-adjusted CIELAB of the CSF-filtered image
  Plane edge, point;  // feature strengths of the unfiltered luminance
};

// Turns images into Perceived; keeps its scratch planes between calls (HDR-FLIP
// perceives two images per exposure).
class Perceiver {
 public:
  explicit Perceiver(double ppd) : csf_(flipCsfKernels(ppd)), feature_(flipFeatureKernels(ppd)) {}

  void perceive(const RgbPlanes& img, Perceived& p) {
    const int w = img.width, h = img.height;
    const size_t n = img.r.size();
    yy_.resize(n), cx_.resize(n), cz_.resize(n), luminance_.resize(n);
    forEachRow(h, [&](int y) {
      for (size_t i = size_t(y) * w; i < size_t(y + 1) * w; ++i) {
        const Vec3 c = xyzToYcxcz(linearRgbToXyz(img.at(i)));
        yy_[i] = c.x, cx_[i] = c.y, cz_[i] = c.z;
        luminance_[i] = (c.x + 16.0f) / 116.0f;  // Y/Yn: the features see the unfiltered luminance
      }
    });

    // Contrast sensitivity: a low-pass filter per opponent channel.
    filter(yy_, w, h, csf_.achromatic, csf_.achromatic, fy_);
    filter(cx_, w, h, csf_.redGreen, csf_.redGreen, fcx_);
    filter(cz_, w, h, csf_.blueYellow1, csf_.blueYellow1, fcz1_);
    filter(cz_, w, h, csf_.blueYellow2, csf_.blueYellow2, fcz2_);
    p.l.resize(n), p.a.resize(n), p.b.resize(n);
    forEachRow(h, [&](int y) {
      for (size_t i = size_t(y) * w; i < size_t(y + 1) * w; ++i) {
        // Filtering can leave the RGB cube: clamp there before CIELAB.
        Vec3 rgb = xyzToLinearRgb(ycxczToXyz({fy_[i], fcx_[i], fcz1_[i] + fcz2_[i]}));
        rgb = {std::clamp(rgb.x, 0.0f, 1.0f), std::clamp(rgb.y, 0.0f, 1.0f), std::clamp(rgb.z, 0.0f, 1.0f)};
        const Vec3 lab = xyzToHuntLab(linearRgbToXyz(rgb));
        p.l[i] = lab.x, p.a[i] = lab.y, p.b[i] = lab.z;
      }
    });

    // Edges (first derivative of a Gaussian) and points (second derivative),
    // along x and y; the planes of the colour part are reused.
    Plane &edgeX = fy_, &edgeY = fcx_, &pointX = fcz1_, &pointY = fcz2_;
    filter(luminance_, w, h, feature_.derivative1, feature_.gaussian, edgeX);
    filter(luminance_, w, h, feature_.derivative2, feature_.gaussian, pointX);
    convolveX(luminance_, w, h, feature_.gaussian, alongX_);
    convolveY(alongX_, w, h, feature_.derivative1, edgeY);
    convolveY(alongX_, w, h, feature_.derivative2, pointY);
    p.edge.resize(n), p.point.resize(n);
    forEachRow(h, [&](int y) {
      for (size_t i = size_t(y) * w; i < size_t(y + 1) * w; ++i) {
        p.edge[i] = std::sqrt(edgeX[i] * edgeX[i] + edgeY[i] * edgeY[i]);
        p.point[i] = std::sqrt(pointX[i] * pointX[i] + pointY[i] * pointY[i]);
      }
    });
  }

 private:
  // kx along x, then ky along y.
  void filter(const Plane& in, int w, int h, const std::vector<float>& kx, const std::vector<float>& ky, Plane& out) {
    convolveX(in, w, h, kx, alongX_);
    convolveY(alongX_, w, h, ky, out);
  }

  FlipCsfKernels csf_;
  FlipFeatureKernels feature_;
  Plane yy_, cx_, cz_, luminance_, alongX_, fy_, fcx_, fcz1_, fcz2_;
};

// ΔE = ΔEc^(1 - ΔEf): a feature difference raises the colour error.
void errorMap(const Perceived& ref, const Perceived& test, int width, int height, std::vector<float>& map) {
  const float cmax = flipColorMax();
  const float knee = kPc * cmax;
  const float sqrt2 = std::sqrt(2.0f);  // maps the largest feature difference to 1
  map.resize(ref.l.size());
  forEachRow(height, [&](int y) {
    for (size_t i = size_t(y) * width; i < size_t(y + 1) * width; ++i) {
      const float e = std::pow(hyab({ref.l[i], ref.a[i], ref.b[i]}, {test.l[i], test.a[i], test.b[i]}), kQc);
      // The lower 40 % of [0, cmax] spreads over [0, 0.95], the rest over [0.95, 1].
      const float colour = e < knee ? e * kPt / knee : kPt + ((e - knee) / (cmax - knee)) * (1.0f - kPt);
      const float feature = std::pow(
          std::max(std::abs(ref.edge[i] - test.edge[i]), std::abs(ref.point[i] - test.point[i])) / sqrt2,
          kQf);
      map[i] = std::pow(colour, 1.0f - feature);
    }
  });
}

void checkInputs(const ImageRgbaF& reference, const ImageRgbaF& test, const FlipOptions& options) {
  if (!(options.ppd > 0.0 && options.ppd <= kMaxPpd))
    throw std::invalid_argument(fmt::format("FLIP: pixels per degree {} is not in (0, {}]", options.ppd, kMaxPpd));
  if (reference.width != test.width || reference.height != test.height)
    throw std::invalid_argument(fmt::format("FLIP: reference is {}x{} but test is {}x{}", reference.width,
                                            reference.height, test.width, test.height));
  if (reference.width <= 0 || reference.height <= 0)
    throw std::invalid_argument(fmt::format("FLIP: empty images ({}x{})", reference.width, reference.height));
  for (const auto& [image, name] : {std::pair{&reference, "reference"}, std::pair{&test, "test"}}) {
    size_t bad = 0, first = 0;
    for (size_t i = 0; i < image->pixelCount(); ++i)
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(image->pixels[i * 4 + c]) && bad++ == 0) first = i * 4 + c;
    if (bad)
      throw std::invalid_argument(fmt::format("FLIP: {} has {} non-finite value(s); first: pixel ({}, {}) {} = {}",
                                              name, bad, first / 4 % image->width, first / 4 / image->width,
                                              "RGB"[first % 4], image->pixels[first]));
  }
  if (!options.mask.empty() && options.mask.size() != reference.pixelCount())
    throw std::invalid_argument(fmt::format("FLIP: mask has {} values for {} pixels", options.mask.size(),
                                            reference.pixelCount()));
}

template <class Fn>
RgbPlanes mapRgb(const ImageRgbaF& image, Fn&& fn) {
  RgbPlanes p(image.width, image.height);
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    const float* px = image.pixels.data() + i * 4;
    p.r[i] = fn(px[0]), p.g[i] = fn(px[1]), p.b[i] = fn(px[2]);
  }
  return p;
}

FlipResult ldrFromPlanes(const RgbPlanes& reference, const RgbPlanes& test, const FlipOptions& options) {
  Perceiver perceiver(options.ppd);
  Perceived ref, tst;
  perceiver.perceive(reference, ref);
  perceiver.perceive(test, tst);
  FlipResult r;
  r.width = reference.width, r.height = reference.height;
  errorMap(ref, tst, r.width, r.height, r.errorMap);
  r.pooled = poolFlipErrors(r.errorMap, options.mask);
  return r;
}

// HDR-FLIP tone curves: T(x) = (k0x² + k1x + k2) / (k3x² + k4x + k5) per
// channel (Reinhard's row is used only to place the exposures).
std::array<float, 6> toneCoefficients(FlipToneMapper t) {
  switch (t) {
    case FlipToneMapper::Aces:  // Narkowicz 2016 with a pre-exposure of 0.6 folded in
      return {0.9036f, 0.018f, 0.0f, 0.8748f, 0.354f, 0.14f};
    case FlipToneMapper::Hable:  // Hable's filmic curve, white point 11.2, exposure bias 2 folded in
      return {0.231683f, 0.013791f, 0.0f, 0.18f, 0.3f, 0.018f};
    case FlipToneMapper::Reinhard:
      return {0.0f, 1.0f, 0.0f, 0.0f, 1.0f, 1.0f};
  }
  throw std::invalid_argument("FLIP: unknown tone mapper");
}

float luminance(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Into `out` (same size as `in`, reused across exposures).
void toneMap(const RgbPlanes& in, float exposure, FlipToneMapper mapper, RgbPlanes& out) {
  const float scale = std::exp2(exposure);
  const auto k = toneCoefficients(mapper);
  // Every curve saturates long before 1e18; the cap keeps x² finite.
  const auto exposed = [&](float v) { return std::min(v * scale, 1e18f); };
  for (size_t i = 0; i < in.r.size(); ++i) {
    const Vec3 c{exposed(in.r[i]), exposed(in.g[i]), exposed(in.b[i])};
    Vec3 t;
    if (mapper == FlipToneMapper::Reinhard) {
      const float d = 1.0f + luminance(c);
      t = {c.x / d, c.y / d, c.z / d};
    } else {
      const auto curve = [&](float x) { return (k[0] * x * x + k[1] * x + k[2]) / (k[3] * x * x + k[4] * x + k[5]); };
      t = {curve(c.x), curve(c.y), curve(c.z)};
    }
    out.r[i] = std::clamp(t.x, 0.0f, 1.0f);
    out.g[i] = std::clamp(t.y, 0.0f, 1.0f);
    out.b[i] = std::clamp(t.z, 0.0f, 1.0f);
  }
}

// The x with T(x) = 0.85: the larger root of (k0 - t k3)x² + (k1 - t k4)x + (k2 - t k5) = 0.
float exposureTargetInput(FlipToneMapper mapper) {
  const auto k = toneCoefficients(mapper);
  const float t = kExposureTarget;
  const float a = k[0] - t * k[3], b = k[1] - t * k[4], c = k[2] - t * k[5];
  if (a == 0.0f) return -c / b;
  return (-b + std::sqrt(b * b - 4.0f * a * c)) / (2.0f * a);
}

}  // namespace

FlipCsfKernels flipCsfKernels(double ppdIn) {
  const float ppd = static_cast<float>(ppdIn);
  // Contrast sensitivity per channel, S(ρ) = a1 √(π/b1) e^(-π²ρ²/b1) + a2 √(π/b2) e^(-π²ρ²/b2).
  struct Csf {
    float a1, b1, a2, b2;
  };
  constexpr Csf achromatic{1.0f, 0.0047f, 0.0f, 1e-5f}, redGreen{1.0f, 0.0053f, 0.0f, 1e-5f},
      blueYellow{34.1f, 0.04f, 13.5f, 0.025f};
  // One radius for all channels: three standard deviations of the widest Gaussian.
  constexpr float bMax = 0.04f;
  FlipCsfKernels k;
  k.radius = static_cast<int>(std::ceil(3.0f * std::sqrt(bMax / (2.0f * kPi * kPi)) * ppd));
  const auto gaussian = [&](float scale, float b) {
    std::vector<float> g;
    for (int i = -k.radius; i <= k.radius; ++i) {
      const float x = static_cast<float>(i) / ppd;  // degrees
      g.push_back(scale * std::exp(-kPi * kPi * x * x / b));
    }
    return g;
  };
  const auto sum = [](const std::vector<float>& v) {
    float s = 0.0f;
    for (float x : v) s += x;
    return s;
  };
  const auto normalised = [&](std::vector<float> v) {
    const float s = sum(v);
    for (float& x : v) x /= s;
    return v;
  };
  k.achromatic = normalised(gaussian(1.0f, achromatic.b1));
  k.redGreen = normalised(gaussian(1.0f, redGreen.b1));
  // Two separable terms sharing one factor, so h1(x)h1(y) + h2(x)h2(y) sums to 1.
  k.blueYellow1 = gaussian(std::sqrt(blueYellow.a1 * std::sqrt(kPi / blueYellow.b1)), blueYellow.b1);
  k.blueYellow2 = gaussian(std::sqrt(blueYellow.a2 * std::sqrt(kPi / blueYellow.b2)), blueYellow.b2);
  const float s1 = sum(k.blueYellow1), s2 = sum(k.blueYellow2);
  const float factor = 1.0f / std::sqrt(s1 * s1 + s2 * s2);
  for (float& x : k.blueYellow1) x *= factor;
  for (float& x : k.blueYellow2) x *= factor;
  return k;
}

FlipFeatureKernels flipFeatureKernels(double ppdIn) {
  const float ppd = static_cast<float>(ppdIn);
  const float sigma = 0.5f * kFeatureWidth * ppd;  // pixels
  FlipFeatureKernels k;
  k.radius = static_cast<int>(std::ceil(3.0f * sigma));
  std::vector<float> g, g1, g2;
  for (int i = -k.radius; i <= k.radius; ++i) {
    const float x = static_cast<float>(i);
    const float gi = std::exp(-(x * x) / (2.0f * sigma * sigma));
    g.push_back(gi);
    g1.push_back(-x * gi);
    g2.push_back((x * x / (sigma * sigma) - 1.0f) * gi);
  }
  float sum = 0.0f;
  for (float x : g) sum += x;
  for (float& x : g) x /= sum;
  // Derivative kernels: positive weights total +1, negative ones -1.
  const auto signNormalised = [](std::vector<float> v) {
    float pos = 0.0f, neg = 0.0f;
    for (float x : v) (x > 0.0f ? pos : neg) += x;
    for (float& x : v) x = x > 0.0f ? x / pos : x / -neg;
    return v;
  };
  k.gaussian = std::move(g);
  k.derivative1 = signNormalised(std::move(g1));
  k.derivative2 = signNormalised(std::move(g2));
  return k;
}

float flipColorMax() {
  const Vec3 green = xyzToHuntLab(linearRgbToXyz({0.0f, 1.0f, 0.0f}));
  const Vec3 blue = xyzToHuntLab(linearRgbToXyz({0.0f, 0.0f, 1.0f}));
  return std::pow(hyab(green, blue), kQc);
}

FlipPooled poolFlipErrors(std::span<const float> errors, std::span<const uint8_t> mask) {
  if (!mask.empty() && mask.size() != errors.size())
    throw std::invalid_argument(
        fmt::format("FLIP pooling: mask has {} values for {} pixels", mask.size(), errors.size()));
  std::vector<float> kept;
  kept.reserve(errors.size());
  for (size_t i = 0; i < errors.size(); ++i) {
    if (!mask.empty() && mask[i] > 1)
      throw std::invalid_argument(
          fmt::format("FLIP pooling: mask value {} at pixel {} is neither 0 nor 1", mask[i], i));
    if (mask.empty() || mask[i]) kept.push_back(errors[i]);
  }
  FlipPooled p;
  p.count = kept.size();
  if (kept.empty()) return p;
  // The tool's mean: a float running sum in row-major order.
  float sum = 0.0f;
  double sumDouble = 0.0;
  for (float e : kept) sum += e, sumDouble += e;
  p.mean = sum / static_cast<float>(kept.size());
  p.meanDouble = sumDouble / static_cast<double>(kept.size());
  for (float e : kept) {
    const size_t bucket = std::min(static_cast<size_t>(e / 0.01f), p.histogram.size() - 1);
    ++p.histogram[bucket];
  }
  std::sort(kept.begin(), kept.end());
  p.min = kept.front(), p.max = kept.back();
  const auto weighted = [&](float fraction) {
    const float target = fraction * sum;
    float running = 0.0f;
    for (float e : kept)
      if ((running += e) > target) return e;
    return kept.back();
  };
  p.weightedQuartile1 = weighted(0.25f), p.weightedMedian = weighted(0.5f), p.weightedQuartile3 = weighted(0.75f);
  // Bucket masses count × centre; linear inside the bucket the target falls in.
  const auto histogramWeighted = [&](double fraction) {
    double total = 0.0;
    for (size_t i = 0; i < p.histogram.size(); ++i) total += p.histogram[i] * (i + 0.5) * 0.01;
    const double target = fraction * total;
    double before = 0.0;
    for (size_t i = 0; i < p.histogram.size(); ++i) {
      const double mass = p.histogram[i] * (i + 0.5) * 0.01;
      if (before + mass > target) return static_cast<float>((i + (target - before) / mass) * 0.01);
      before += mass;
    }
    return 1.0f;
  };
  p.histogramWeighted25 = histogramWeighted(0.25), p.histogramWeighted50 = histogramWeighted(0.5),
  p.histogramWeighted75 = histogramWeighted(0.75);
  return p;
}

FlipResult flipLdr(const ImageRgbaF& reference, const ImageRgbaF& test, const FlipOptions& options) {
  checkInputs(reference, test, options);
  const auto clamp01 = [](float v) { return std::clamp(v, 0.0f, 1.0f); };
  return ldrFromPlanes(mapRgb(reference, clamp01), mapRgb(test, clamp01), options);
}

FlipResult flipLdrSrgb(const ImageRgbaF& reference, const ImageRgbaF& test, const FlipOptions& options) {
  checkInputs(reference, test, options);
  const auto decode = [](float v) { return srgbToLinear(std::clamp(v, 0.0f, 1.0f)); };
  return ldrFromPlanes(mapRgb(reference, decode), mapRgb(test, decode), options);
}

FlipResult flipHdr(const ImageRgbaF& reference, const ImageRgbaF& test, const FlipOptions& options) {
  checkInputs(reference, test, options);
  // Negative radiance has no meaning here and would break Reinhard's 1 + L.
  const auto nonNegative = [](float v) { return std::max(v, 0.0f); };
  const RgbPlanes ref = mapRgb(reference, nonNegative), tst = mapRgb(test, nonNegative);

  float start = 0.0f, stop = 0.0f;
  if (!options.startExposure || !options.stopExposure) {
    std::vector<float> lum(ref.r.size());
    for (size_t i = 0; i < lum.size(); ++i) lum[i] = luminance(ref.at(i));
    const float maxLum = *std::max_element(lum.begin(), lum.end());
    if (!(maxLum > 0.0f))
      throw std::invalid_argument(
          "HDR-FLIP: the reference has no positive luminance; give both the start and the stop exposure");
    // The element of rank floor(n/2), zeros included; when that is 0, the
    // median of the positive luminances (the tool v1.6 would return +inf).
    auto mid = lum.begin() + lum.size() / 2;
    std::nth_element(lum.begin(), mid, lum.end());
    float medianLum = *mid;
    if (!(medianLum > 0.0f)) {
      std::erase_if(lum, [](float v) { return !(v > 0.0f); });
      mid = lum.begin() + lum.size() / 2;
      std::nth_element(lum.begin(), mid, lum.end());
      medianLum = *mid;
    }
    // In double: x / L overflows float for a denormal L (a sparse path-traced
    // image's median), where the stop itself (~130) is an ordinary value.
    const double x = exposureTargetInput(options.toneMapper);
    start = static_cast<float>(std::log2(x / maxLum));
    stop = static_cast<float>(std::log2(x / medianLum));
  }
  if (options.startExposure) start = *options.startExposure;
  if (options.stopExposure) stop = *options.stopExposure;
  if (!std::isfinite(start) || !std::isfinite(stop) || start > stop)
    throw std::invalid_argument(
        fmt::format("HDR-FLIP: exposures {} to {}: need finite values, start <= stop", start, stop));
  // One exposure per stop; float32 spans fewer than 300 stops.
  const double stops = std::ceil(static_cast<double>(stop) - start);
  const int count = options.exposureCount.value_or(static_cast<int>(std::clamp(stops, 2.0, 301.0)));
  if (count < 2 || count > 300)
    throw std::invalid_argument(fmt::format("HDR-FLIP: {:g} exposures from {} to {}; 2 to 300 are possible",
                                            options.exposureCount ? count : stops, start, stop));

  FlipResult r;
  r.width = reference.width, r.height = reference.height;
  r.startExposure = start, r.stopExposure = stop, r.exposureCount = count;
  Perceiver perceiver(options.ppd);
  RgbPlanes toneMapped(r.width, r.height);
  Perceived refSeen, testSeen;
  std::vector<float> map;
  const float step = (stop - start) / static_cast<float>(count - 1);
  for (int i = 0; i < count; ++i) {
    const float exposure = start + static_cast<float>(i) * step;
    toneMap(ref, exposure, options.toneMapper, toneMapped);
    perceiver.perceive(toneMapped, refSeen);
    toneMap(tst, exposure, options.toneMapper, toneMapped);
    perceiver.perceive(toneMapped, testSeen);
    errorMap(refSeen, testSeen, r.width, r.height, map);
    if (i == 0) r.errorMap = map;
    else
      for (size_t p = 0; p < map.size(); ++p) r.errorMap[p] = std::max(r.errorMap[p], map[p]);
  }
  r.pooled = poolFlipErrors(r.errorMap, options.mask);
  return r;
}

}  // namespace ft
