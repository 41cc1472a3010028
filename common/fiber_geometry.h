// fiber_geometry.h — ply and fiber displacement (000_cc9bd0fbd0e08a03.txt
// §2.2, §3.1) and the per-period fiber types (migration, loop, hair).
//
// Angles are carried in turns (1 turn = 2π) until the last moment: the
// fractional turn is taken with exact operations (multiply, add, floor), so
// the period index — a discrete choice — is bit-identical on CPU and GPU;
// only the final sin/cos differ by rounding.
#ifndef FT_FIBER_GEOMETRY_H
#define FT_FIBER_GEOMETRY_H
#include "prelude.h"
#include "constants.h"
#include "fiber_vertex.h"
#include "rng.h"
#include "yarn_buffers.h"
#include "yarn_frame.h"
#include "yarn_params.h"

FT_NAMESPACE_BEGIN

// Twist and migration rates of one curve, in turns (or periods) per unit of
// length coordinate. On a closed curve each rate is rounded to a whole number
// of turns over the loop, so plies, fibers and fiber types join seamlessly
// where the loop closes (pitch changes by < ½ turn over the loop length).
struct TwistRates {
  float ply;
  float fiber;
  float migration;
  uint migrationPeriods;  // periods around a closed curve; 0 on an open curve
};

FT_FUNC float ftWholeTurnRate(float rate, float loopLength) {
  FT_PRECISE float turns = floor(rate * loopLength + 0.5f);
  return max(turns, 1.0f) / loopLength;
}

FT_FUNC TwistRates ftTwistRates(YarnParams p, CurveInfo c) {
  TwistRates r;
  r.ply = p.plyTurnsPerLength;
  r.fiber = p.fiberTurnsPerLength;
  r.migration = p.fiberTurnsPerLength * p.migrationS;
  r.migrationPeriods = 0u;
  if (c.closed != 0u && c.totalLength > 0.0f) {
    r.ply = ftWholeTurnRate(r.ply, c.totalLength);
    r.fiber = ftWholeTurnRate(r.fiber, c.totalLength);
    r.migration = ftWholeTurnRate(r.migration, c.totalLength);
    FT_PRECISE float periods = r.migration * c.totalLength;
    r.migrationPeriods = uint(floor(periods + 0.5f));
  }
  return r;
}

// Δc^ply of §3.1: ply centre offset and the ply's own (N, B) directions.
struct PlyFrame {
  vec3 offset;  // Δc_j^ply
  vec3 N;       // N_j^ply = Δc_j^ply / |Δc_j^ply|
  vec3 B;       // B_j^ply = T^yarn × N_j^ply
};

FT_FUNC PlyFrame ftPlyFrame(YarnParams p, TwistRates r, YarnFrame f, float s, uint ply) {
  FT_PRECISE float twistTurns = fract(s * r.ply);
#ifdef FT_FAULT_PLY_ANGLE_SIGN
  float twistSign = -p.plyTwistSign;
#else
  float twistSign = p.plyTwistSign;
#endif
  // θ_j^ply + θ with θ_j^ply = 2π j / n^ply.
  float angle = FT_TWO_PI * (twistSign * twistTurns + float(ply) / float(p.plyCount));
  PlyFrame pf;
  pf.N = f.N * cos(angle) + f.B * sin(angle);
  pf.B = cross(f.T, pf.N);
  pf.offset = pf.N * p.plyRadius;
  return pf;
}

// Migration radius of eq. 2, written with the in-period fraction f ∈ [0, 1):
// periods start and end at R_i·R_min, so a period whose R_max is raised (a
// loop) or whose end is cut loose (a hair) still joins its neighbours.
FT_FUNC float ftMigrationRadius(YarnParams p, float radiusI, float rhoMax, float f) {
  return radiusI * (p.rhoMin + (rhoMax - p.rhoMin) * 0.5f * (1.0f - cos(FT_TWO_PI * f)));
}

// Where a length coordinate falls in a fiber's migration periods. Exact
// operations only, so both sides agree on the index bit for bit.
struct PeriodPhase {
  uint index;      // period index (wrapped on closed curves)
  float fraction;  // position inside the period, [0, 1)
};

FT_FUNC PeriodPhase ftPeriodPhase(TwistRates r, float s, FiberCoord fc) {
  // Phase of eq. 2 in turns, shifted by ½ so a period runs R_min → R_max → R_min.
  FT_PRECISE float phase = fc.thetaTurns + s * r.migration + 0.5f;
  FT_PRECISE float whole = floor(phase);
  PeriodPhase ph;
  ph.fraction = phase - whole;
  ph.index = uint(whole);
  if (r.migrationPeriods > 0u) ph.index = ph.index % r.migrationPeriods;
  return ph;
}

// Everything random about one period of one fiber: a pure function of
// (yarn, ply, fiber, period, seed), so a generator may compute it once per
// period and reuse it for every vertex in that period.
struct FiberPeriod {
  uint type;         // FT_FIBER_MIGRATION, FT_FIBER_LOOP or FT_FIBER_HAIR
  float loopRhoMax;  // R_max^loop (ply-disk units) for a loop period
  float hairRadius;  // R_max^hair (ply-disk units): radius of the hair's free end
  float hairSpan;    // fraction of the period turned into the hair
  float hairAngle;   // extra polar angle at the free end (radians)
  uint hairAtEnd;    // 0: free end at the period start, 1: at its end
};

FT_FUNC FiberPeriod ftFiberPeriod(YarnParams p, TwistRates r, uint yarn, uint ply, uint fiber, uint period) {
  FiberRandomKey key;
  key.yarn = yarn;
  key.plyFiber = ftPackFiberId(ply, fiber);
#ifdef FT_FAULT_HAIR_PERIOD
  key.period = period + 1u;
#else
  key.period = period;
#endif
  key.seed = p.seed;
  uvec4 r0 = ftRandomBits(key, 0u);
  uvec4 r1 = ftRandomBits(key, 1u);
  uvec4 r2 = ftRandomBits(key, 2u);
  float u = ftUnitFloat(r0.x);
  FiberPeriod fp;
  fp.type = u < p.loopProbability                          ? FT_FIBER_LOOP
            : u < p.loopProbability + p.hairProbability ? FT_FIBER_HAIR
                                                        : FT_FIBER_MIGRATION;
  fp.hairAtEnd = r0.y & 1u;
  fp.loopRhoMax = p.rhoMax + abs(ftNormal(r0.z, r0.w, p.loopR1Mu, p.loopR1Sigma)) / p.ellipseN;
  float ze = abs(ftNormal(r0.z, r0.w, p.hairZeMu, p.hairZeSigma));
  fp.hairSpan = clamp(ze * r.migration, 0.05f, 0.95f);
  fp.hairRadius = p.rhoMax + (abs(ftNormal(r1.x, r1.y, p.hairR0Mu, p.hairR0Sigma)) +
                              abs(ftNormal(r1.z, r1.w, p.hairReMu, p.hairReSigma))) / p.ellipseN;
  fp.hairAngle = abs(ftNormal(r2.x, r2.y, p.hairPeMu, p.hairPeSigma));
  return fp;
}

// Point of fiber `fc` in ply frame `pf` at length coordinate s, given its
// period: Δc_i of §3.1 added to the ply centre.
FT_FUNC vec3 ftFiberPosition(YarnParams p, TwistRates r, YarnFrame f, PlyFrame pf, float s, FiberCoord fc,
                             PeriodPhase ph, FiberPeriod fp) {
  FT_PRECISE float fiberTurns = fract(fc.thetaTurns + s * r.fiber);
  float angle = FT_TWO_PI * p.fiberTwistSign * fiberTurns;  // θ_i + θ of eq. 1
  float rhoMax = fp.type == FT_FIBER_LOOP ? fp.loopRhoMax : p.rhoMax;
  float radius = ftMigrationRadius(p, fc.radius, rhoMax, ph.fraction);

  if (fp.type == FT_FIBER_HAIR) {
    // Part of the period becomes a hair: from its free end at R_max^hair the
    // radius runs linearly back to the migration radius where it rejoins.
    float span = fp.hairSpan;
    float fromFreeEnd = fp.hairAtEnd != 0u ? 1.0f - ph.fraction : ph.fraction;
    if (fromFreeEnd < span) {
      float w = fromFreeEnd / span;
      float join = ftMigrationRadius(p, fc.radius, p.rhoMax, fp.hairAtEnd != 0u ? 1.0f - span : span);
      radius = mix(fp.hairRadius, join, w);
      angle += fp.hairAngle * (1.0f - w);
    }
  }

#ifdef FT_FAULT_ELLIPSE_SWAP
  float eN = p.ellipseB;
  float eB = p.ellipseN;
#else
  float eN = p.ellipseN;
  float eB = p.ellipseB;
#endif
  // Δc_i = R (cos(θ_i + θ) N_j^ply e_N + sin(θ_i + θ) B_j^ply e_B).
  vec3 fiberOffset = (pf.N * (cos(angle) * eN) + pf.B * (sin(angle) * eB)) * radius;
  return f.center + pf.offset + fiberOffset;
}

// The core fiber runs along the ply centre (§3.2).
FT_FUNC vec3 ftCorePosition(YarnParams p, TwistRates r, YarnFrame f, float s, uint ply) {
  return f.center + ftPlyFrame(p, r, f, s, ply).offset;
}

FT_NAMESPACE_END
#endif  // FT_FIBER_GEOMETRY_H
