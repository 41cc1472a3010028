// core_texture.h — the core-fiber texture of Wu & Yuksel 2017 (000_cc9bd0fbd0e08a03.txt
// §3.2, eq. 3): the fibers a ply's core fiber stands for, seen orthographically
// over one full fiber twist, baked into
//   tex0 = (h, n_u, n_v, 0): height h = 0.5 + 0.5 x_hit / R_core (0: a hole)
//          and the 2D normal (n_z, n_y) of the nearest fiber surface;
//   tex1 = (t_u, t_v, t_w, 0): the fiber direction (t_z, t_y, t_x), t_u > 0.
// Both bakes (reference/core_texture.cpp with Embree round curves,
// gpu/shaders/core_texture_bake.comp.glsl with the capsule chain below) share
// the texel mapping, the helix and the surface attributes at a hit; only the
// ray intersection differs.
//
// Bake frame (ply-local, circular; notes-rendering A1): x along the ply's N,
// y along its B, z along the ply axis, in world units. The ply ellipse is
// replaced by a circle of radius e = max(e_N, e_B) (the runtime applies the
// ellipse to the strip width only). Fiber i, twist angle θ ∈ ℝ (one twist =
// 2π, z = α θ / 2π):
//   c_i(θ) = R_i(θ) (cos φ, sin φ, 0) + (0, 0, α θ / 2π),  φ = σ_f (2π θ_i + θ),
//   R_i(θ) = e R_i (ρ_min + (ρ_max − ρ_min) ½ (1 − cos 2π f)),  f = phase_i + s θ / 2π + ½,
// the migration of eq. 2 with s = 1 (§3.2: "we use s = 1 … tiles seamlessly"),
// written as ftMigrationRadius and ftPeriodPhase write it. The rays run along
// −x; texel (i, j) sits at z = u α, y = (2v − 1) R_core with
// u = (i + uOffset) / width, v = (j + ½) / height.
#ifndef FT_CORE_TEXTURE_H
#define FT_CORE_TEXTURE_H
#include "prelude.h"
#include "constants.h"
#include "fiber_geometry.h"
#include "yarn_buffers.h"
#include "yarn_params.h"

// Planted faults (validation/faults.def). The shared ones live here and so run
// on both sides: the C++ side reads a run-time switch (the harness turns it
// on), the GLSL side the define.
#ifdef __cplusplus
namespace ft {
inline bool ftFaultCoreTexturePresetS = false;
inline bool ftFaultCoreTextureTangentSign = false;
inline bool ftFaultCoreTextureViewSign = false;
}
#define FT_FAULT_CORE_TEXTURE_VIEW_SIGN_ON ::ft::ftFaultCoreTextureViewSign
#define FT_FAULT_CORE_TEXTURE_PRESET_S_ON ::ft::ftFaultCoreTexturePresetS
#define FT_FAULT_CORE_TEXTURE_TANGENT_SIGN_ON ::ft::ftFaultCoreTextureTangentSign
#else
#ifdef FT_FAULT_CORE_TEXTURE_PRESET_S
#define FT_FAULT_CORE_TEXTURE_PRESET_S_ON true
#else
#define FT_FAULT_CORE_TEXTURE_PRESET_S_ON false
#endif
#ifdef FT_FAULT_CORE_TEXTURE_TANGENT_SIGN
#define FT_FAULT_CORE_TEXTURE_TANGENT_SIGN_ON true
#else
#define FT_FAULT_CORE_TEXTURE_TANGENT_SIGN_ON false
#endif
#ifdef FT_FAULT_CORE_TEXTURE_VIEW_SIGN
#define FT_FAULT_CORE_TEXTURE_VIEW_SIGN_ON true
#else
#define FT_FAULT_CORE_TEXTURE_VIEW_SIGN_ON false
#endif
#endif

FT_NAMESPACE_BEGIN

// Sizes (notes-rendering A1 [F]): u spans one twist (about 18:1 for cotton1).
const uint FT_CORE_TEXTURE_WIDTH = 512u;
const uint FT_CORE_TEXTURE_HEIGHT = 64u;
const uint FT_CORE_TEXTURE_CI_WIDTH = 128u;
const uint FT_CORE_TEXTURE_CI_HEIGHT = 16u;
// Capsules per twist per fiber of the shared chain (notes A1): the chord
// leaves the helix by κ L² / 8 ≈ 2e-3 r_f for cotton1.
const uint FT_CORE_TEXTURE_SEGMENTS = 256u;

// The bake's uniform block (std140; every member a 4-byte scalar).
struct CoreTextureParams {
  uint width;             // texels per twist along u
  uint height;            // texels across the core thickness (v)
  uint columns;           // columns baked: width, or width + 1 for a strip that ends at u = 1
  uint coreFibers;        // rows of the core-fiber list (FT_SSBO_CORE_FIBERS)

  uint segmentsPerTwist;  // capsules per twist per fiber
  float uOffset;          // texel i at u = (i + uOffset) / width: ½ for texel centres, 0 for u = 0 … 1
  float alpha;            // one fiber twist along the ply (world units): 1 / fiberTurnsPerLength
  float coreHalfWidth;    // R_core = e · max_core R_i ρ_max + r_f

  float fiberRadius;      // r_f (YarnParams.fiberRadius)
  float twistSign;        // σ_f (fiber_clock_wise)
  float migrationS;       // s of eq. 2 in the bake: 1 (§3.2)
  float rhoMin;           // R_min of eq. 2

  float rhoMax;           // R_max of eq. 2
  float plyScale;         // e = max(e_N, e_B): ply-disk units → world
  float rayStart;         // x where the rays start, outside every fiber
  float pad0;
};
FT_ASSERT_OFFSET(CoreTextureParams, segmentsPerTwist, 16)
FT_ASSERT_OFFSET(CoreTextureParams, fiberRadius, 32)
FT_ASSERT_OFFSET(CoreTextureParams, rhoMax, 48)
FT_ASSERT_SIZE(CoreTextureParams, 64)

// The core set: every fiber-table row below the `regularFibers` outermost.
FT_FUNC uint ftCoreFiberCount(YarnParams p) { return p.fiberCount > p.regularFibers ? p.fiberCount - p.regularFibers : 0u; }

// One row of the core-fiber list: (R_i in ply-disk units, θ_i in turns, the
// migration phase of eq. 2 in turns, 0). `fiber` is the fiber-table row; the
// phase is that of ply `ply` of yarn `yarn` (the texture is baked once per
// preset, for one ply: with FT_MIGRATION_PHASE_INDEPENDENT every ply draws its
// own phases, which the texture cannot follow).
FT_FUNC vec4 ftCoreFiberRow(YarnParams p, FiberCoord fc, uint yarn, uint ply, uint fiber) {
  return vec4(fc.radius, fc.thetaTurns, ftMigrationPhaseTurns(p, yarn, ply, fiber, fc), 0.0f);
}

// `farthestRadius`: the largest R_i of the core set (ply-disk units).
FT_FUNC CoreTextureParams ftCoreTextureParams(YarnParams p, float farthestRadius, uint width, uint height) {
  CoreTextureParams c;
  c.width = width;
  c.height = height;
  c.columns = width;
  c.coreFibers = ftCoreFiberCount(p);
  c.segmentsPerTwist = FT_CORE_TEXTURE_SEGMENTS;
  c.uOffset = 0.5f;
  c.alpha = 1.0f / p.fiberTurnsPerLength;
  c.fiberRadius = p.fiberRadius;
  c.twistSign = p.fiberTwistSign;
  // §3.2: the core's fibers migrate once per twist, whatever the preset's s.
  c.migrationS = FT_FAULT_CORE_TEXTURE_PRESET_S_ON ? p.migrationS : 1.0f;
  c.rhoMin = p.rhoMin;
  c.rhoMax = p.rhoMax;
  c.plyScale = max(p.ellipseN, p.ellipseB);
  c.coreHalfWidth = c.plyScale * farthestRadius * p.rhoMax + p.fiberRadius;
  // Past the farthest point of any core fiber: ρ may exceed ρ_max where ρ_min > ρ_max.
  c.rayStart = c.plyScale * farthestRadius * max(p.rhoMin, p.rhoMax) + 2.0f * p.fiberRadius;
  c.pad0 = 0.0f;
  return c;
}

// ---- the helix ---------------------------------------------------------------

FT_FUNC float ftCoreTwistStep(CoreTextureParams c) { return FT_TWO_PI / float(c.segmentsPerTwist); }

// Migration angle ψ = 2π phase_i + s θ; R_i(θ) = e R_i (ρ_min + (ρ_max − ρ_min) ½ (1 + cos ψ))
// (the ½ period shift of ftPeriodPhase turns 1 − cos into 1 + cos).
FT_FUNC float ftCoreMigrationAngle(CoreTextureParams c, vec4 fiber, float theta) {
  return FT_TWO_PI * fiber.z + c.migrationS * theta;
}

FT_FUNC vec3 ftCoreHelixPoint(CoreTextureParams c, vec4 fiber, float theta) {
  float amp = c.plyScale * fiber.x * (c.rhoMax - c.rhoMin) * 0.5f;
  float radius = c.plyScale * fiber.x * c.rhoMin + amp * (1.0f + cos(ftCoreMigrationAngle(c, fiber, theta)));
  float phi = c.twistSign * (FT_TWO_PI * fiber.y + theta);
  return vec3(radius * cos(phi), radius * sin(phi), c.alpha * theta / FT_TWO_PI);
}

// dc/dθ (sign = σ_f) and d²c/dθ².
FT_FUNC vec3 ftCoreHelixDerivative(CoreTextureParams c, vec4 fiber, float theta, float sign) {
  float amp = c.plyScale * fiber.x * (c.rhoMax - c.rhoMin) * 0.5f;
  float m = ftCoreMigrationAngle(c, fiber, theta);
  float radius = c.plyScale * fiber.x * c.rhoMin + amp * (1.0f + cos(m));
  float dr = -amp * c.migrationS * sin(m);
  float phi = sign * (FT_TWO_PI * fiber.y + theta);
  return vec3(dr * cos(phi) - sign * radius * sin(phi), dr * sin(phi) + sign * radius * cos(phi),
              c.alpha / FT_TWO_PI);
}

FT_FUNC vec3 ftCoreHelixSecond(CoreTextureParams c, vec4 fiber, float theta) {
  float amp = c.plyScale * fiber.x * (c.rhoMax - c.rhoMin) * 0.5f;
  float m = ftCoreMigrationAngle(c, fiber, theta);
  float radius = c.plyScale * fiber.x * c.rhoMin + amp * (1.0f + cos(m));
  float dr = -amp * c.migrationS * sin(m);
  float ddr = -amp * c.migrationS * c.migrationS * cos(m);
  float s = c.twistSign;
  float phi = s * (FT_TWO_PI * fiber.y + theta);
  return vec3((ddr - radius) * cos(phi) - 2.0f * s * dr * sin(phi), (ddr - radius) * sin(phi) + 2.0f * s * dr * cos(phi),
              0.0f);
}

// ---- texel mapping -----------------------------------------------------------

FT_FUNC float ftCoreTexelU(CoreTextureParams c, uint column) {
  return (float(column) + c.uOffset) / float(c.width);
}
FT_FUNC float ftCoreTexelV(CoreTextureParams c, uint row) { return (float(row) + 0.5f) / float(c.height); }

// The ray of texel (column, row): origin (rayStart, y, z), direction −x.
FT_FUNC vec3 ftCoreTexelOrigin(CoreTextureParams c, uint column, uint row) {
  float z = ftCoreTexelU(c, column) * c.alpha;
  float y = (2.0f * ftCoreTexelV(c, row) - 1.0f) * c.coreHalfWidth;
  return vec3(c.rayStart, y, z);
}

// ---- ray vs capsule chain (the GPU bake's intersection) ------------------------

// Nearest entry of the ray o + τ (−1, 0, 0), τ > 0, into the capsule of radius
// r around segment a–b (Quílez's ray–capsule test). Returns (τ, w, 1) with w ∈ [0, 1]
// the axis parameter of the hit, or (0, 0, 0) for a miss. The caller puts o
// just outside the capsule, so every term stays at the capsule's own scale.
FT_FUNC vec3 ftRayCapsule(vec3 o, vec3 a, vec3 b, float r) {
  vec3 rd = vec3(-1.0f, 0.0f, 0.0f);
  vec3 ba = b - a;
  vec3 oa = o - a;
  float baba = dot(ba, ba);
  float bard = dot(ba, rd);
  float baoa = dot(ba, oa);
  float rdoa = dot(rd, oa);
  float oaoa = dot(oa, oa);
  float qa = baba - bard * bard;
  float qb = baba * rdoa - baoa * bard;
  float qc = baba * oaoa - baoa * baoa - r * r * baba;
  float h = qb * qb - qa * qc;
  if (h < 0.0f || baba <= 0.0f) return vec3(0.0f);
  if (qa > 0.0f) {
    float t = (-qb - sqrt(h)) / qa;
    float y = baoa + t * bard;
    if (y > 0.0f && y < baba && t > 0.0f) return vec3(t, y / baba, 1.0f);
  }
  // The caps: the sphere at the end the cylinder hit lies beyond (or the nearer one).
  float yc = qa > 0.0f ? baoa + ((-qb - sqrt(h)) / qa) * bard : baoa;
  vec3 oc = yc <= 0.0f ? oa : o - b;
  float sb = dot(rd, oc);
  float sc = dot(oc, oc) - r * r;
  float sh = sb * sb - sc;
  if (sh <= 0.0f) return vec3(0.0f);
  float t = -sb - sqrt(sh);
  if (t <= 0.0f) return vec3(0.0f);
  return vec3(t, yc <= 0.0f ? 0.0f : 1.0f, 1.0f);
}

// The nearest hit of texel ray `o` on fiber `fiber`'s capsule chain: (x_hit,
// θ of the axis point, 1), or (0, 0, 0). Only the capsules whose z range
// (± r_f) holds the ray's z can be hit: a handful per fiber.
FT_FUNC vec3 ftCoreFiberCapsuleHit(CoreTextureParams c, vec4 fiber, vec3 o) {
  float dz = c.alpha / float(c.segmentsPerTwist);
  float step = ftCoreTwistStep(c);
  int k0 = int(floor((o.z - c.fiberRadius) / dz)) - 1;
  int k1 = int(floor((o.z + c.fiberRadius) / dz)) + 1;
  vec3 best = vec3(0.0f);
  for (int k = k0; k <= k1; ++k) {
    vec3 a = ftCoreHelixPoint(c, fiber, float(k) * step);
    vec3 b = ftCoreHelixPoint(c, fiber, float(k + 1) * step);
    // Start the ray just outside this capsule: keeps the quadratic's terms at r_f scale.
    vec3 local = vec3(max(a.x, b.x) + 2.0f * c.fiberRadius, o.y, o.z);
    vec3 hit = ftRayCapsule(local, a, b, c.fiberRadius);
    if (hit.z == 0.0f) continue;
    float x = local.x - hit.x;
    if (best.z == 0.0f || x > best.x) best = vec3(x, (float(k) + hit.y) * step, 1.0f);
  }
  return best;
}

// ---- surface attributes at a hit (both bakes) ----------------------------------

// θ of the point of the helix nearest to p, from a start θ0 on the chord:
// Newton on g(θ) = (p − c(θ))·c'(θ), two steps (θ0 is within a fraction of a
// segment, g' ≈ −|c'|²).
FT_FUNC float ftCoreNearestTheta(CoreTextureParams c, vec4 fiber, vec3 p, float theta0) {
  float theta = theta0;
  for (int it = 0; it < 2; ++it) {
    vec3 d = p - ftCoreHelixPoint(c, fiber, theta);
    vec3 d1 = ftCoreHelixDerivative(c, fiber, theta, c.twistSign);
    vec3 d2 = ftCoreHelixSecond(c, fiber, theta);
    float g = dot(d, d1);
    float dg = dot(d, d2) - dot(d1, d1);
    theta -= g / dg;
  }
  return theta;
}

// The texel of a hit at p on fiber `fiber` (θ0: the axis parameter of the
// hit): tex0 = (h, n_z, n_y, 0), tex1 = (t_z, t_y, t_x, 0). The normal is that
// of the true helix's tube at its nearest point, so n ⟂ t.
struct CoreTexel {
  vec4 tex0;
  vec4 tex1;
};

FT_FUNC CoreTexel ftCoreEmptyTexel() {
  CoreTexel t;
  t.tex0 = vec4(0.0f);
  t.tex1 = vec4(0.0f);
  return t;
}

FT_FUNC CoreTexel ftCoreTexelAt(CoreTextureParams c, vec4 fiber, vec3 p, float theta0) {
  float theta = ftCoreNearestTheta(c, fiber, p, theta0);
  vec3 n = ftNormalize(p - ftCoreHelixPoint(c, fiber, theta));
  vec3 axis = ftNormalize(ftCoreHelixDerivative(c, fiber, theta, c.twistSign));
  // At a rim the true tube's normal may face a hair away from the viewer
  // (the hit is on the chain, the normal the helix's): the texture stores
  // only n_x ≥ 0, so such a hit takes the silhouette normal, ⟂ t and ⟂ x.
  if (n.x < 0.0f) {
    vec3 rim = ftNormalize(vec3(0.0f, axis.z, -axis.y));
    n = dot(rim, n) >= 0.0f ? rim : -rim;
  }
  vec3 t = FT_FAULT_CORE_TEXTURE_TANGENT_SIGN_ON ? ftNormalize(ftCoreHelixDerivative(c, fiber, theta, 1.0f)) : axis;
  CoreTexel texel;
  // h ∈ (0, 1]: kept ≥ 2^-16 so a hit is never read as a hole (16-bit texture).
  float h = max(0.5f + 0.5f * p.x / c.coreHalfWidth, 1.0f / 65536.0f);
  texel.tex0 = vec4(h, n.z, n.y, 0.0f);
  texel.tex1 = vec4(t.z, t.y, t.x, 0.0f);
  return texel;
}

// Reconstructed 3D normal in the bake frame: (n_x ≥ 0 toward the viewer, n_y, n_z).
FT_FUNC vec3 ftCoreTexelNormal(vec4 tex0) {
  return vec3(sqrt(max(1.0f - tex0.y * tex0.y - tex0.z * tex0.z, 0.0f)), tex0.z, tex0.y);
}

// ---- the runtime lookup (notes-rendering A1 "Use") ------------------------------

// Eq. 3 as extracted is dimensionally garbled; its semantic reading is
// u = frac(Φ(s)/2π − k_ψ ψ_rel/2π), Φ the phase of the fiber bundle. Φ(s) in
// turns: s/α for the fiber twist, plus kPly · s / yarn_alpha where ψ_rel is
// measured in a frame that does not turn with the ply. k_ψ (paper: ½) and
// its sign, and kPly, are parameters: notes A1 C5 settles them against an
// explicit-fiber render (not done yet, docs/core-texture.md).
FT_FUNC float ftCoreBundlePhaseTurns(YarnParams p, float s, float kPly) {
  return s * p.fiberTurnsPerLength + kPly * s * p.plyTurnsPerLength;
}

FT_FUNC float ftCoreTextureU(float phaseTurns, float psiRel, float kPsi) {
  return fract(phaseTurns - kPsi * psiRel / FT_TWO_PI);
}

// The convention the frame uses, settled by notes A1 C5 (validation case
// appearance/core-texture/eq3, table in docs/core-texture.md): |k_ψ| = 1
// with the sign of σ_f (fiber_clock_wise), and no ply-twist term (ψ_rel is
// measured from the ply's own N̂_j, which turns with the ply, as the
// generator places the fibers: ftFiberPosition).
const float FT_CORE_TEXTURE_K_PSI = 1.0f;  // |k_ψ|
const float FT_CORE_TEXTURE_K_PLY = 0.0f;
FT_FUNC float ftCoreTextureKPsi(YarnParams p) {
  float k = FT_CORE_TEXTURE_K_PSI * p.fiberTwistSign;
  return FT_FAULT_CORE_TEXTURE_VIEW_SIGN_ON ? -k : k;
}

// Texel (i, j) of (u, v) in the width × height texture: u wraps (the texture
// tiles, §3.2), v clamps. Returns the two texels along u and along v and
// the lerp weights: value = mix(mix(T(i0,j0), T(i1,j0), w.x), mix(T(i0,j1), T(i1,j1), w.x), w.y)
// (texelFetch + this lerp, notes §0.4, rather than the sampler's 8-bit weights).
struct CoreLookup {
  uvec2 i;  // columns i0, i1
  uvec2 j;  // rows j0, j1
  vec2 w;
};

FT_FUNC CoreLookup ftCoreTextureLookup(uint width, uint height, float u, float v) {
  CoreLookup l;
  float x = fract(u) * float(width) - 0.5f;
  float fx = floor(x);
  l.w.x = x - fx;
  // fx ∈ [−1, width − 1] (fract(u) ≤ 1 — x − floor(x) rounds to 1 for a
  // tiny negative u — and width − 0.5 floors to width − 1), so one wrap
  // suffices: no integer division, which llvmpipe runs lane by lane. min()
  // keeps the column inside the texture whatever a GPU's int() makes of a NaN u.
  int i0 = int(fx);
  if (i0 < 0) i0 += int(width);
  uint i = min(uint(i0), width - 1u);
  l.i = uvec2(i, i + 1u == width ? 0u : i + 1u);
  float y = clamp(v, 0.0f, 1.0f) * float(height) - 0.5f;
  float fy = floor(y);
  l.w.y = y - fy;
  int j0 = int(fy);
  if (j0 < 0) {
    j0 = 0;
    l.w.y = 0.0f;
  }
  int j1 = min(j0 + 1, int(height) - 1);
  l.j = uvec2(uint(j0), uint(j1));
  return l;
}

FT_NAMESPACE_END
#endif  // FT_CORE_TEXTURE_H
