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
// periods start and end at R_i·R_min (ply-disk units).
FT_FUNC float ftMigrationRadius(YarnParams p, float radiusI, float rhoMax, float f) {
  return radiusI * (p.rhoMin + (rhoMax - p.rhoMin) * 0.5f * (1.0f - cos(FT_TWO_PI * f)));
}

// Phase of eq. 2 at s = 0, in turns. FT_MIGRATION_PHASE_FIBER_ANGLE: θ_i, as
// eq. 2 of Wu & Yuksel 2017 (§2.2) writes it, so for s = 1 the radius is locked
// to the polar angle; FT_MIGRATION_PHASE_INDEPENDENT (the default): a random
// phase per fiber of each ply, drawn apart from θ_i as the presets' public
// fitting code (Zhao et al. 2016) does.
FT_FUNC float ftMigrationPhaseTurns(YarnParams p, uint yarn, uint ply, uint fiber, FiberCoord fc) {
  if (p.migrationPhase == FT_MIGRATION_PHASE_FIBER_ANGLE) return fc.thetaTurns;
  FiberRandomKey key;
  key.yarn = yarn;
  key.plyFiber = ftPackFiberId(ply, fiber);
  key.period = 0xFFFFFFFFu;  // reserved: no flyaway cell has this index
  key.seed = p.seed;
  return ftUnitFloat(ftRandomBits(key, 3u).x);
}

// Where a length coordinate falls in a fiber's migration periods and flyaway
// cells (each period is cut into p.flyawayCells equal cells). Exact or
// precise operations only, so both sides agree on the indices bit for bit.
struct PeriodPhase {
  uint index;          // flyaway cell index: period (wrapped on closed curves) · cells + cell in period
  float fraction;      // position inside the migration period, [0, 1)
  float cellFraction;  // position inside the flyaway cell, [0, 1)
};

FT_FUNC PeriodPhase ftPeriodPhase(YarnParams p, TwistRates r, float s, float phaseTurns) {
  // Phase of eq. 2 in turns, shifted by ½ so a period runs R_min → R_max → R_min.
  FT_PRECISE float phase = phaseTurns + s * r.migration + 0.5f;
  FT_PRECISE float whole = floor(phase);
  PeriodPhase ph;
  ph.fraction = phase - whole;
  uint period = uint(whole);
  if (r.migrationPeriods > 0u) period = period % r.migrationPeriods;
  uint cells = max(p.flyawayCells, 1u);
  FT_PRECISE float scaled = ph.fraction * float(cells);
  FT_PRECISE float cellWhole = floor(scaled);
  uint cell = min(uint(cellWhole), cells - 1u);
  ph.cellFraction = clamp(scaled - float(cell), 0.0f, 1.0f);
  ph.index = period * cells + cell;
  return ph;
}

// Everything random about one flyaway cell of one fiber: a pure function of
// (yarn, ply, fiber, cell, seed), so a generator may compute it once per
// cell and reuse it for every vertex in that cell. Distances are world units
// from the ply centre (reference-data §2: r1, r0, re as the presets mean them).
struct FiberPeriod {
  uint type;         // FT_FIBER_MIGRATION, FT_FIBER_LOOP or FT_FIBER_HAIR
  float loopPeak;    // r1: a loop's distance from the ply centre at the cell's middle
  float hairEnd;     // r0 + re: the hair's free end
  float hairRoot;    // r0: where the hair joins its fiber
  float hairSpan;    // fraction of the cell that is the hair (axial extent ze)
  float hairAngle;   // extra polar angle at the free end (radians, pe)
  uint hairAtEnd;    // 0: free end at the cell start, 1: at its end
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
  // The top bit: pcg4d's low bits are correlated between neighbouring
  // periods (ρ = 0.26 for bit 0 of consecutive periods; fiber_math_test).
  fp.hairAtEnd = r0.y >> 31u;
  fp.loopPeak = abs(ftNormal(r0.z, r0.w, p.loopR1Mu, p.loopR1Sigma));
  float ze = abs(ftNormal(r0.z, r0.w, p.hairZeMu, p.hairZeSigma));
  // Cell length 1 / (migration · cells); the hair keeps ≥ 5 % of the cell to rejoin.
  fp.hairSpan = clamp(ze * r.migration * float(max(p.flyawayCells, 1u)), 1.0e-3f, 0.95f);
  fp.hairRoot = abs(ftNormal(r1.x, r1.y, p.hairR0Mu, p.hairR0Sigma));
  fp.hairEnd = fp.hairRoot + abs(ftNormal(r1.z, r1.w, p.hairReMu, p.hairReSigma));
  fp.hairAngle = abs(ftNormal(r2.x, r2.y, p.hairPeMu, p.hairPeSigma));
  return fp;
}

// Distance from the ply centre of the point R·(cos a e_N, sin a e_B).
FT_FUNC float ftEllipseScale(YarnParams p, float angle) {
  return length(vec2(cos(angle) * p.ellipseN, sin(angle) * p.ellipseB));
}

// Point of fiber `fc` in ply frame `pf` at length coordinate s, given its
// cell: Δc_i of §3.1 added to the ply centre. Migration fibers follow eq. 2.
// A loop cell lifts the fiber to distance r1 at the cell's middle (never
// below its own radius); a hair cell runs from its free end at r0 + re
// linearly to r0 over the axial extent ze, then back to the fiber over the
// rest of the cell. Flyaway distances are world distances from the ply centre.
FT_FUNC vec3 ftFiberPosition(YarnParams p, TwistRates r, YarnFrame f, PlyFrame pf, float s, FiberCoord fc,
                             PeriodPhase ph, FiberPeriod fp) {
  FT_PRECISE float fiberTurns = fract(fc.thetaTurns + s * r.fiber);
  float angle = FT_TWO_PI * p.fiberTwistSign * fiberTurns;  // θ_i + θ of eq. 1
  float radius = ftMigrationRadius(p, fc.radius, p.rhoMax, ph.fraction);

  if (fp.type != FT_FIBER_MIGRATION) {
    float own = radius * ftEllipseScale(p, angle);  // the fiber's own distance from the ply centre
    float dist = own;
    if (fp.type == FT_FIBER_LOOP) {
      float bump = 0.5f * (1.0f - cos(FT_TWO_PI * ph.cellFraction));
      dist = own + bump * max(fp.loopPeak - own, 0.0f);
    } else {
      float fromFreeEnd = fp.hairAtEnd != 0u ? 1.0f - ph.cellFraction : ph.cellFraction;
      if (fromFreeEnd < fp.hairSpan) {
        float w = fromFreeEnd / fp.hairSpan;
        dist = mix(fp.hairEnd, fp.hairRoot, w);
        angle += fp.hairAngle * (1.0f - w);
      } else {
        float v = (fromFreeEnd - fp.hairSpan) / (1.0f - fp.hairSpan);
        dist = mix(own, fp.hairRoot, 0.5f + 0.5f * cos(FT_PI * v));
      }
    }
    radius = dist / ftEllipseScale(p, angle);
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
