// rng.h — counter-based random numbers shared by CPU and GPU.
//
// Every random fiber parameter is a pure function of (yarn, ply, fiber,
// period, seed, stream): no state, no order dependence, so the CPU reference
// and every GPU path draw the same values for the same fiber period.
// Hash: pcg4d of Jarzynski & Olano, "Hash Functions for GPU Rendering"
// (JCGT 2020), on 32-bit unsigned integers (wrap-around arithmetic is the
// same in C++ and GLSL).
#ifndef FT_RNG_H
#define FT_RNG_H
#include "prelude.h"

FT_NAMESPACE_BEGIN

FT_FUNC uvec4 ftPcg4d(uvec4 v) {
  v = v * 1664525u + uvec4(1013904223u);
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  v = v ^ (v >> uvec4(16u));
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  return v;
}

// Key of one fiber period. `stream` selects independent draws for the same
// period (type, direction, extents, ...).
struct FiberRandomKey {
  uint yarn;
  uint plyFiber;  // ply << 16 | fiber
  uint period;
  uint seed;
};

// Four independent uniform 32-bit words for (key, stream).
FT_FUNC uvec4 ftRandomBits(FiberRandomKey k, uint stream) {
  return ftPcg4d(uvec4(k.yarn, k.plyFiber, k.period, k.seed ^ (stream * 0x9E3779B9u)));
}

// Uniform float in [0, 1): the top 24 bits, exact in binary32 on both sides.
FT_FUNC float ftUnitFloat(uint bits) { return float(bits >> 8u) * (1.0f / 16777216.0f); }

// Normal deviate N(mu, sigma) by Box-Muller, clamped to mu +- 3 sigma so every
// random extent has a bound (the frustum test needs one). Uses log/cos, so
// the two sides agree to rounding, not bit for bit; callers use it only for
// continuous quantities, never for a discrete choice.
FT_FUNC float ftNormal(uint bitsA, uint bitsB, float mu, float sigma) {
  float u1 = 1.0f - ftUnitFloat(bitsA);  // (0, 1]
  float u2 = ftUnitFloat(bitsB);
  float z = sqrt(-2.0f * log(u1)) * cos(FT_TWO_PI * u2);
  return mu + sigma * clamp(z, -3.0f, 3.0f);
}

FT_NAMESPACE_END
#endif  // FT_RNG_H
