// flyaway.h — the flyaway fibers of Huang et al. 2025 (001_dce8d4d1f783b802.txt
// §4.4, eq. 12–13; notes-rendering A8; docs/flyaways.md) and their three
// mutually seamless baked textures, as C++ and GLSL 4.50.
//
// Curve (eq. 12 with eq. 13's radius), t ∈ [0, 1], yarn-centred frame:
//   x = R(t) cos θ(t) (toward the viewer), y = R(t) sin θ(t) (across the strip),
//   z = z_0 + z_e t (along the yarn),
//   R(t) = R_0 + R_e (1 − (1 − t)^α), θ(t) = θ_0 + θ_e t, R clamped ≥ 0.
// "Noise is added to the progressive direction" [F]: a random walk on the
// steps, p_k = c(t_k) + σ_n w_k, w_0 = 0, w_k = w_{k−1} + L_k g_k, with L_k
// the k-th clean step's length and g_k ∈ [−√3, √3]³ (unit variance per axis).
//
// Candidates are drawn per pattern in four sets (docs/flyaways.md "seamless
// triple"): set 0 = B, the boundary set, stationary candidates with
// z_0 ∈ [−Z, Z) of which those crossing z = 0 are kept; sets 1–3 = I_k, the
// interior sets of layer k, z_0 ∈ [0, P), kept when the whole curve lies at
// least `margin` inside [0, P]. Layer k draws B (at z and z + P) and I_k, so
// its first and last columns hold B only: the same in every layer, and B's
// wrap makes any layer continue into any other.
#ifndef FT_FLYAWAY_H
#define FT_FLYAWAY_H
#include "prelude.h"
#include "constants.h"
#include "rng.h"

// Planted faults (validation/faults.def): the shared ones run on both sides.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultFlyawayEq13NoOneMinus = false;
inline bool ftFaultFlyawayNoWrap = false;
}
#define FT_FAULT_FLYAWAY_EQ13_NO_ONE_MINUS_ON ::ft::ftFaultFlyawayEq13NoOneMinus
#define FT_FAULT_FLYAWAY_NO_WRAP_ON ::ft::ftFaultFlyawayNoWrap
#else
#ifdef FT_FAULT_FLYAWAY_EQ13_NO_ONE_MINUS
#define FT_FAULT_FLYAWAY_EQ13_NO_ONE_MINUS_ON true
#else
#define FT_FAULT_FLYAWAY_EQ13_NO_ONE_MINUS_ON false
#endif
#ifdef FT_FAULT_FLYAWAY_NO_WRAP
#define FT_FAULT_FLYAWAY_NO_WRAP_ON true
#else
#define FT_FAULT_FLYAWAY_NO_WRAP_ON false
#endif
#endif

FT_NAMESPACE_BEGIN

// Sizes [F] (notes A8: 512×128 not given by the paper; CI 128×32).
const uint FT_FLYAWAY_WIDTH = 512u;
const uint FT_FLYAWAY_HEIGHT = 128u;
const uint FT_FLYAWAY_CI_WIDTH = 128u;
const uint FT_FLYAWAY_CI_HEIGHT = 32u;
const uint FT_FLYAWAY_STEPS = 16u;  // line segments per curve [F]
const uint FT_FLYAWAY_POINTS = FT_FLYAWAY_STEPS + 1u;
const uint FT_FLYAWAY_SETS = 4u;    // B, I_0, I_1, I_2
const uint FT_FLYAWAY_LAYERS = 3u;
const uint FT_FLYAWAY_PIECES = 4u; // frame strip pieces per yarn segment (flyaway_strip.vert.glsl)

// Bake and generation block (std140; every member a 4-byte scalar).
struct FlyawayParams {
  uint width;           // texels along u (one period P)
  uint height;          // texels across v (2 W_fly)
  uint maxPerSet;       // candidate slots per set (Poisson counts are capped here)
  uint patterns;        // independent triples drawn (1 for a bake; many for statistics)

  float period;         // P: the texture's length along the yarn (world units)
  float halfWidth;      // W_fly: v = 0 … 1 spans y = −W_fly … W_fly
  float bodyRadius;     // radius of the regular fibers' envelope that hides flyaways behind it (W)
  float lineHalfWidth;  // drawn half-width of a flyaway: max(r_f, ½ texel)

  float zeMu;           // z_e ~ N(zeMu, zeSigma) (world units)
  float zeSigma;
  float r0Mu;           // Zhao's hair root r_0 ~ N (from the ply centre)
  float r0Sigma;

  float reMu;           // R_e ~ N
  float reSigma;
  float peMu;           // θ_e ~ N (radians)
  float peSigma;

  float rootOffset;     // R_0 = rootOffset + r_0: the ply centre's distance from the yarn axis [F]
  float alpha;          // eq. 13's α (1: eq. 12)
  float noise;          // σ_n of the random walk (fraction of a step)
  float zReach;         // Z = |zeMu| + 3 zeSigma: the farthest a curve reaches along z (ftNormal clamps at 3σ)

  float margin;         // interior curves stay this far inside [0, P] (lineHalfWidth + one texel)
  float poissonThresholdB;  // exp(−λ_B / chunksB): Knuth's threshold per chunk, computed once on the host
  float poissonThresholdI;  // exp(−λ_I / chunksI)
  uint chunksB;             // λ split in chunks of ≤ 16 so that exp(−λ) stays a normal float

  uint chunksI;
  uint seed;
  uint pad0;
  uint pad1;
};
FT_ASSERT_OFFSET(FlyawayParams, period, 16)
FT_ASSERT_OFFSET(FlyawayParams, zeMu, 32)
FT_ASSERT_OFFSET(FlyawayParams, reMu, 48)
FT_ASSERT_OFFSET(FlyawayParams, rootOffset, 64)
FT_ASSERT_OFFSET(FlyawayParams, margin, 80)
FT_ASSERT_OFFSET(FlyawayParams, chunksI, 96)
FT_ASSERT_SIZE(FlyawayParams, 112)

// Shape of one candidate (eq. 12–13's random parameters).
struct FlyawayShape {
  float z0, ze, r0, re;  // r0 here is R_0 (yarn-centred)
  float theta0, thetae;
  uint present;          // slot below the set's Poisson count
  uint pad;
};

FT_FUNC uint ftFlyawaySlot(FlyawayParams f, uint pattern, uint set, uint slot) {
  return (pattern * FT_FLYAWAY_SETS + set) * f.maxPerSet + slot;
}

FT_FUNC FiberRandomKey ftFlyawayKey(FlyawayParams f, uint pattern, uint set, uint index) {
  FiberRandomKey k;
  k.yarn = pattern;
  k.plyFiber = (set << 16u) | (index & 0xFFFFu);
  k.period = 0x466C79u;  // "Fly": keeps these draws apart from 000's fiber periods
  k.seed = f.seed;
  return k;
}

// Poisson count of a set by Knuth's product of uniforms, in chunks; the
// thresholds come from the host so that both sides compare the same floats
// (a count is a discrete choice).
FT_FUNC uint ftFlyawayCount(FlyawayParams f, uint pattern, uint set) {
  uint chunks = set == 0u ? f.chunksB : f.chunksI;
  float threshold = set == 0u ? f.poissonThresholdB : f.poissonThresholdI;
  uint count = 0u;
  for (uint c = 0u; c < chunks; ++c) {
    FiberRandomKey key = ftFlyawayKey(f, pattern, set, 0xF000u + c);
    FT_PRECISE float product = 1.0f;
    for (uint i = 0u; i < 4u * f.maxPerSet; ++i) {  // bounded: llvmpipe's loop limit
      uvec4 bits = ftRandomBits(key, i / 4u);
      uint word = (i % 4u) == 0u ? bits.x : ((i % 4u) == 1u ? bits.y : ((i % 4u) == 2u ? bits.z : bits.w));
      product = product * (1.0f - ftUnitFloat(word));
      if (product <= threshold) break;
      ++count;
    }
  }
  return min(count, f.maxPerSet);
}

FT_FUNC FlyawayShape ftFlyawayShape(FlyawayParams f, uint pattern, uint set, uint slot, uint count) {
  FiberRandomKey key = ftFlyawayKey(f, pattern, set, slot);
  uvec4 a = ftRandomBits(key, 0u);
  uvec4 b = ftRandomBits(key, 1u);
  uvec4 c = ftRandomBits(key, 2u);
  FlyawayShape s;
  float u = ftUnitFloat(a.x);
  // Notes A8 [F]: z_0 uniform; B's candidates over [−Z, Z) so that every curve crossing 0 can be drawn.
  s.z0 = set == 0u ? (2.0f * u - 1.0f) * f.zReach : u * f.period;
  s.theta0 = FT_TWO_PI * ftUnitFloat(a.y);
  s.ze = ftNormal(a.z, a.w, f.zeMu, f.zeSigma);
  s.r0 = max(0.0f, f.rootOffset + ftNormal(b.x, b.y, f.r0Mu, f.r0Sigma));
  s.re = ftNormal(b.z, b.w, f.reMu, f.reSigma);
  s.thetae = ftNormal(c.x, c.y, f.peMu, f.peSigma);
  s.present = slot < count ? 1u : 0u;
  s.pad = 0u;
  return s;
}

// Eq. 13: R(t) = R_0 + R_e (1 − (1 − t)^α), clamped ≥ 0 (notes A8 [F]).
FT_FUNC float ftFlyawayRadius(float r0, float re, float alpha, float t) {
  float grow = FT_FAULT_FLYAWAY_EQ13_NO_ONE_MINUS_ON ? pow(1.0f - t, alpha) : 1.0f - pow(1.0f - t, alpha);
  return max(0.0f, r0 + re * grow);
}

// Eq. 12 without noise.
FT_FUNC vec3 ftFlyawayCleanPoint(FlyawayShape s, float alpha, float t) {
  float r = ftFlyawayRadius(s.r0, s.re, alpha, t);
  float th = s.theta0 + s.thetae * t;
  return vec3(r * cos(th), r * sin(th), s.z0 + s.ze * t);
}

// The noise step g_k ∈ [−√3, √3]³.
FT_FUNC vec3 ftFlyawayNoiseStep(FlyawayParams f, uint pattern, uint set, uint slot, uint k) {
  uvec4 bits = ftRandomBits(ftFlyawayKey(f, pattern, set, slot), 16u + k);
  vec3 u = vec3(ftUnitFloat(bits.x), ftUnitFloat(bits.y), ftUnitFloat(bits.z));
  return (2.0f * u - vec3(1.0f)) * 1.7320508f;
}

// The random walk along a curve: the clean point of the last step and the
// accumulated offset w_k (world units); the drawn point is clean + σ_n w.
struct FlyawayWalk {
  vec3 clean;
  vec3 offset;
};

FT_FUNC FlyawayWalk ftFlyawayWalkStart(FlyawayShape s, float alpha) {
  FlyawayWalk w;
  w.clean = ftFlyawayCleanPoint(s, alpha, 0.0f);
  w.offset = vec3(0.0f);
  return w;
}

// Step k = 1 … FT_FLYAWAY_STEPS.
FT_FUNC FlyawayWalk ftFlyawayWalkStep(FlyawayParams f, FlyawayShape s, uint pattern, uint set, uint slot, uint k,
                                      FlyawayWalk w) {
  vec3 c = ftFlyawayCleanPoint(s, f.alpha, float(k) / float(FT_FLYAWAY_STEPS));
  float stepLength = length(c - w.clean);
  FlyawayWalk n;
  n.offset = w.offset + stepLength * ftFlyawayNoiseStep(f, pattern, set, slot, k);
  n.clean = c;
  return n;
}

FT_FUNC vec3 ftFlyawayWalkPoint(FlyawayParams f, FlyawayWalk w) { return w.clean + f.noise * w.offset; }

// Kept flag from the curve's z range: B crosses z = 0 once (and spans less
// than P − 2 margin, so its two copies never overlap themselves); I_k lies
// `margin` inside [0, P].
FT_FUNC uint ftFlyawayKept(FlyawayParams f, uint set, float zMin, float zMax) {
  if (set == 0u) return (zMin < 0.0f && zMax >= 0.0f && zMax - zMin < f.period - 2.0f * f.margin) ? 1u : 0u;
  return (zMin >= f.margin && zMax <= f.period - f.margin) ? 1u : 0u;
}

// Copies of a curve drawn in a layer: B at shift 0 and +P (its part below
// z = 0 reappears at the right end), an interior curve once.
FT_FUNC uint ftFlyawayShiftCount(uint set) {
  if (set == 0u) return FT_FAULT_FLYAWAY_NO_WRAP_ON ? 1u : 2u;
  return 1u;
}

// ---- texels --------------------------------------------------------------------

// Texel (i, j) of a layer: z = (i + ½)/width · P, y = (2 (j + ½)/height − 1) W_fly.
FT_FUNC vec2 ftFlyawayTexelYZ(FlyawayParams f, uint i, uint j) {
  float u = (float(i) + 0.5f) / float(f.width);
  float v = (float(j) + 0.5f) / float(f.height);
  return vec2((2.0f * v - 1.0f) * f.halfWidth, u * f.period);
}

// One segment a→b drawn as an orthographic line of half-width h along −x:
// returns (covered, depth x at the closest point, 0, 0) for the texel at q = (y, z).
FT_INLINE vec2 ftFlyawaySegmentHit(vec3 a, vec3 b, vec2 q, float h) {
  vec2 a2 = vec2(a.y, a.z);
  vec2 d = vec2(b.y, b.z) - a2;
  float dd = dot(d, d);
  float s = dd > 0.0f ? clamp(dot(q - a2, d) / dd, 0.0f, 1.0f) : 0.0f;
  vec2 e = q - (a2 + s * d);
  if (dot(e, e) > h * h) return vec2(0.0f, 0.0f);
  return vec2(1.0f, a.x + s * (b.x - a.x));
}

// Hidden by the regular fibers of the same yarn (the paper's pass-1 depth
// stencil, taken as the envelope cylinder of radius W [F]): behind its front
// surface x_s = √(W² − y²).
FT_FUNC bool ftFlyawayHidden(FlyawayParams f, float y, float x) {
  if (abs(y) >= f.bodyRadius) return false;
  return x < sqrt(f.bodyRadius * f.bodyRadius - y * y);
}

// RGBA8 texel from the hit segment's direction: rgb = ½ t + ½ in the strip
// frame (t_u, t_v, t_w) = (t_z, t_y, t_x), with t_u ≥ 0; a = 1. 0 = empty.
FT_FUNC vec4 ftFlyawayTexel(vec3 a, vec3 b) {
  vec3 t = ftNormalize(b - a);
  vec3 s = vec3(t.z, t.y, t.x);
  if (s.x < 0.0f) s = -s;
  return vec4(0.5f * s + vec3(0.5f), 1.0f);
}

// Runtime: the layer of period n of yarn `yarn` (notes A8: k = hash mod 3),
// constant over the period.
FT_FUNC uint ftFlyawayLayer(uint yarn, int period, uint seed) {
  uvec4 h = ftPcg4d(uvec4(yarn, uint(period), seed, 0x466C79u));
  return h.x % FT_FLYAWAY_LAYERS;
}

FT_NAMESPACE_END
#endif  // FT_FLYAWAY_H
