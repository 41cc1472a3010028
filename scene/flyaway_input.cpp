#include "scene/flyaway_input.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "scene/input_error.h"

namespace ft {

namespace {
// Knuth's product method per chunk: exp(−λ_c) must stay a normal float.
constexpr double kMaxChunkLambda = 16.0;

void chunkLambda(double lambda, uint32_t& chunks, float& threshold) {
  chunks = std::max<uint32_t>(1u, uint32_t(std::ceil(lambda / kMaxChunkLambda)));
  threshold = float(std::exp(-lambda / chunks));
}
}  // namespace

double flyawayLambda(const FlyawayParams& f, double densityPerLength, uint32_t set) {
  return densityPerLength * (set == 0 ? 2.0 * double(f.zReach) : double(f.period));
}

FlyawayParams makeFlyawayParams(const YarnPreset& fitted, const YarnParams& p, const FlyawaySettings& s) {
  auto bad = [&](const std::string& what) {
    return InputError(fmt::format("flyaways for yarn preset {}: {}", fitted.name, what));
  };
  if (s.width < 2 || s.height < 2 || s.width > 8192 || s.height > 8192)
    throw bad(fmt::format("texture size {}×{} (--flyaway-size: each side 2 … 8192)", s.width, s.height));
  if (s.patterns < 1 || s.patterns > 4096) throw bad(fmt::format("{} patterns (1 … 4096)", s.patterns));
  if (!(s.alpha > 0.0f) || !std::isfinite(s.alpha)) throw bad(fmt::format("α = {} (--flyaway-alpha: must be > 0)", s.alpha));
  if (!(s.noise >= 0.0f) || !(s.noise <= 1.0f)) throw bad(fmt::format("noise σ_n = {} (--flyaway-noise: 0 … 1)", s.noise));
  if (!(s.lengthScale > 0.0f) || !std::isfinite(s.lengthScale))
    throw bad(fmt::format("length scale {} (--flyaway-length: must be > 0)", s.lengthScale));
  const double density = double(p.plyCount) * fitted.hairDensity;  // [F] Zhao's density is per ply
  if (!(density >= 0.0) || !std::isfinite(density)) throw bad(fmt::format("hair density {}", fitted.hairDensity));

  FlyawayParams f{};
  f.width = s.width;
  f.height = s.height;
  f.patterns = s.patterns;
  f.zeMu = float(fitted.hairZe.mu * s.lengthScale);
  f.zeSigma = float(std::abs(fitted.hairZe.sigma) * s.lengthScale);
  f.r0Mu = float(fitted.hairR0.mu);
  f.r0Sigma = float(std::abs(fitted.hairR0.sigma));
  f.reMu = float(fitted.hairRe.mu * s.lengthScale);
  f.reSigma = float(std::abs(fitted.hairRe.sigma) * s.lengthScale);
  f.peMu = float(fitted.hairPe.mu);
  f.peSigma = float(std::abs(fitted.hairPe.sigma));
  f.rootOffset = p.plyRadius;  // [F] Zhao's r_0 is from the ply centre; the texture is yarn-centred
  f.alpha = s.alpha;
  f.noise = s.noise;
  f.zReach = std::abs(f.zeMu) + 3.0f * f.zeSigma;
  f.bodyRadius = p.plyRadius + std::max(p.ellipseN, p.ellipseB) * p.rhoMax;  // W: the regular fibers' reach
  const double reach = f.rootOffset + std::max(0.0f, f.r0Mu + 3.0f * f.r0Sigma) + std::max(0.0f, f.reMu + 3.0f * f.reSigma);
  f.halfWidth = float(1.1 * std::max<double>(reach, f.bodyRadius));  // 10 % for the noise [F]
  // P [F]: the ply twist (one yarn_alpha), times the smallest integer that
  // leaves room for a boundary curve and the margins.
  const double twist = 1.0 / double(p.plyTurnsPerLength);
  if (!(twist > 0.0) || !std::isfinite(twist)) throw bad(fmt::format("ply twist length {}", twist));
  double period = twist;
  for (int k = 2; k <= 64 && period < 2.5 * f.zReach; ++k) period = k * twist;
  if (period < 2.5 * f.zReach) throw bad(fmt::format("flyaway reach {} along the yarn (z_e scaled by --flyaway-length {}) is longer than 64 ply twists allow", f.zReach, s.lengthScale));
  f.period = float(period);
  const double du = period / s.width, dv = 2.0 * f.halfWidth / s.height;
  f.lineHalfWidth = float(std::max<double>(p.fiberRadius, 0.5 * std::max(du, dv)));  // ≥ one texel wide [F]
  f.margin = float(f.lineHalfWidth + du);
  const double lB = flyawayLambda(f, density, 0), lI = flyawayLambda(f, density, 1);
  chunkLambda(lB, f.chunksB, f.poissonThresholdB);
  chunkLambda(lI, f.chunksI, f.poissonThresholdI);
  const double lMax = std::max(lB, lI);
  const double cap = std::ceil(lMax + 8.0 * std::sqrt(lMax) + 16.0);
  if (cap > 4096.0) throw bad(fmt::format("{:.0f} flyaways per texture period (at most ~4000)", lMax));
  f.maxPerSet = uint32_t(cap);
  f.seed = s.seed ^ p.seed;
  return f;
}

void checkFlyawayTextures(const FlyawayTextures& t, const std::string& what) {
  const size_t want = size_t(t.width) * t.height * FT_FLYAWAY_LAYERS;
  if (t.width == 0 || t.height == 0 || t.texels.size() != want)
    throw InputError(fmt::format("{}: flyaway textures hold {} texels, {}×{}×3 = {} expected", what, t.texels.size(),
                                 t.width, t.height, want));
}

}  // namespace ft
