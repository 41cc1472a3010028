// knit_solver.h — knot-based yarn optimization of one stitch tile
// (001_dce8d4d1f783b802.txt §3.2, §5.2), written once for both precisions.
//
// Precision-generic: this file has no include guard and uses the scalar and
// vector types kreal, kvec2, kvec3, kvec4 and the constructor KR(x), which the
// includer defines first:
//   * GLSL: #define kreal float, kvec2 vec2, ..., KR(x) float(x)
//   * C++: knit/knit_solver.h includes it twice, inside namespace ft::knit64
//     (double, the CPU reference) and ft::knit32 (float, for diagnosing the
//     GPU twin), with typedefs and KR(x) = kreal(x).
// Include it at most once per namespace (C++) or shader (GLSL).
// Tile layout and notation: knit_stitch.h.
#include "prelude.h"
#include "knit_stitch.h"

// Gauss–Newton state of one tile (§5.2): points in the face frame, xy in the
// plane and z along the normal (the template-prescribed offset).
struct KnitProblem {
  kvec2 knot[2];
  kvec4 theta0;                       // (θ_L, θ_R, l_L, l_R)
  kvec2 fixedXY[FT_KNIT_FIXED_POINTS];  // S, A, halo 14..19
  kreal fixedH[FT_KNIT_FIXED_POINTS];
  kreal restLength[FT_KNIT_LENGTH_RESIDUALS];
  kreal restCosine[FT_KNIT_ANGLE_RESIDUALS];
  kreal radius;  // r
  kreal side;    // +1 knit, -1 purl: the sign of every normal offset
};

struct KnitTileResult {
  kvec3 p[FT_KNIT_TILE_POINTS];  // face frame
  kvec4 theta;
  kreal energy[FT_KNIT_MAX_ITERATIONS + 1];  // eq. 3 before each iteration and after the last
  uint steps;                                 // iterations that changed Θ
};

// Per point i of the tile: ivec4(knot j, s_d, s_b, s_n), the point being
// x_k + s_d l d + s_b r b + s_n r n (eq. 1–2); j = -1 for the fixed S and A.
FT_FUNC ivec4 knitPointCode(int i) {
  if (i == 1) return ivec4(0, -1, 0, -1);   // c1-
  if (i == 2) return ivec4(0, 0, 1, 0);     // p0
  if (i == 3) return ivec4(0, 1, 0, 1);     // c0+
  if (i == 4) return ivec4(0, -1, 0, 1);    // c1+
  if (i == 5) return ivec4(0, 0, -1, 0);    // p1
  if (i == 6) return ivec4(0, 1, 0, -1);    // c0-
  if (i == 8) return ivec4(1, 1, 0, -1);    // c0-
  if (i == 9) return ivec4(1, 0, 1, 0);     // p0
  if (i == 10) return ivec4(1, -1, 0, 1);   // c1+
  if (i == 11) return ivec4(1, 1, 0, 1);    // c0+
  if (i == 12) return ivec4(1, 0, -1, 0);   // p1
  if (i == 13) return ivec4(1, -1, 0, -1);  // c1-
  return ivec4(-1, 0, 0, 0);
}

// Index into KnitProblem::fixedXY of a fixed point (tile 0, tile 7, halo 14..20).
FT_FUNC int knitFixedSlot(int i) {
  if (i == 0) return 0;
  if (i == 7) return 1;
  return i - 12;
}

// Chain c (0..2) has knitChainLength(c) points; knitChainPoint(c, j) is a
// point index 0..20 (knit_stitch.h).
FT_FUNC int knitChainLength(int c) { return c == 1 ? 9 : 6; }
FT_FUNC int knitChainPoint(int c, int j) {
  int last = knitChainLength(c) - 1;
  if (c == 0) return j == 0 ? 14 : (j == last ? 15 : j - 1);
  if (c == 1) return j == 0 ? 16 : (j == last ? 17 : j + 3);
  return j == 0 ? 18 : (j <= 3 ? j + 10 : j + 15);
}

FT_FUNC kvec2 knitDirection(kreal theta) { return kvec2(cos(theta), sin(theta)); }

// All 21 points (tile + halo) for parameters t, with their derivatives with
// respect to Θ (nonzero only for the point's own knot's θ_j and l_j). One
// sin/cos pair per knot.
struct KnitJets {
  kvec3 x[FT_KNIT_POINTS];
  kvec3 dTheta[FT_KNIT_POINTS];   // ∂x/∂θ_j of the point's knot j
  kvec3 dLength[FT_KNIT_POINTS];  // ∂x/∂l_j
  int knot[FT_KNIT_POINTS];       // j, or -1 for a fixed point
};

FT_FUNC KnitJets knitJets(KnitProblem pr, kvec4 t) {
  KnitJets o;
  kvec2 dk[2];
  dk[0] = knitDirection(t.x);
  dk[1] = knitDirection(t.y);
  for (int i = 0; i < FT_KNIT_POINTS; ++i) {
    ivec4 code = knitPointCode(i);
    o.knot[i] = code.x;
    o.dTheta[i] = kvec3(KR(0.0), KR(0.0), KR(0.0));
    o.dLength[i] = kvec3(KR(0.0), KR(0.0), KR(0.0));
    if (code.x < 0) {
      int s = knitFixedSlot(i);
      o.x[i] = kvec3(pr.fixedXY[s].x, pr.fixedXY[s].y, pr.fixedH[s]);
      continue;
    }
    kvec2 d = dk[code.x];
    kreal len = code.x == 0 ? t.z : t.w;
    kvec2 b = kvec2(d.y, -d.x);   // b = d × n with n = +z of the frame
    kvec2 dd = kvec2(-d.y, d.x);  // ∂d/∂θ
    kreal sd = kreal(code.y);
    kreal sb = kreal(code.z);
#ifdef FT_FAULT_KNIT_CONSTRAINT_DROPPED
    // Planted fault: p0/p1 keep the interpolated contact direction instead of
    // following θ, dropping the perpendicularity constraint of eq. 4.
    kvec2 b0 = kvec2(sin(pr.theta0[code.x]), -cos(pr.theta0[code.x]));
    kvec2 xy = pr.knot[code.x] + sd * len * d + sb * pr.radius * b0;
    kvec2 dbTheta = kvec2(KR(0.0), KR(0.0));
#else
    kvec2 xy = pr.knot[code.x] + sd * len * d + sb * pr.radius * b;  // eq. 1
    kvec2 dbTheta = d;  // ∂b/∂θ
#endif
    o.x[i] = kvec3(xy.x, xy.y, kreal(code.w) * pr.radius * pr.side);  // eq. 2
    kvec2 gT = sd * len * dd + sb * pr.radius * dbTheta;
    kvec2 gL = sd * d;
    o.dTheta[i] = kvec3(gT.x, gT.y, KR(0.0));
    o.dLength[i] = kvec3(gL.x, gL.y, KR(0.0));
  }
  return o;
}

// Segment lengths and interior-point cosines of the three chains, in the
// residual order of knitNormalEquations: the rest values of eq. 5–6 come from
// the template measured with this.
struct KnitMeasures {
  kreal segment[FT_KNIT_LENGTH_RESIDUALS];  // not `length`: GLSL reserves .length()
  kreal cosine[FT_KNIT_ANGLE_RESIDUALS];
};

FT_FUNC KnitMeasures knitMeasure(KnitProblem pr, kvec4 t) {
  KnitMeasures m;
  KnitJets q = knitJets(pr, t);
  int li = 0;
  int ai = 0;
  for (int c = 0; c < 3; ++c) {
    int n = knitChainLength(c);
    for (int j = 0; j + 1 < n; ++j) {
      kvec3 e = q.x[knitChainPoint(c, j + 1)] - q.x[knitChainPoint(c, j)];
      m.segment[li] = sqrt(dot(e, e));
      ++li;
      if (j + 2 < n) {
        kvec3 f = q.x[knitChainPoint(c, j + 2)] - q.x[knitChainPoint(c, j + 1)];
        m.cosine[ai] = dot(e, f) / (sqrt(dot(e, e)) * sqrt(dot(f, f)));
        ++ai;
      }
    }
  }
  return m;
}

// The normal equations of one Gauss–Newton step (§5.2): A = Σ J Jᵀ and
// g = Σ J r over the residuals r = √w (value − rest) of eq. 5 (angles, at each
// interior chain point) and eq. 6 (lengths, each chain segment); energy = Σ r²
// is eq. 3. With withJacobian false only the energy is summed.
struct KnitNormalEquations {
  kreal a[16];
  kvec4 g;
  kreal energy;
};

FT_FUNC KnitNormalEquations knitAccumulate(KnitProblem pr, kvec4 t, kreal wAngle, kreal wLength, bool withJacobian) {
  KnitNormalEquations ne;
  for (int k = 0; k < 16; ++k) ne.a[k] = KR(0.0);
  ne.g = kvec4(KR(0.0), KR(0.0), KR(0.0), KR(0.0));
  ne.energy = KR(0.0);
  KnitJets q = knitJets(pr, t);
  kreal sa = sqrt(wAngle);
#ifdef FT_FAULT_KNIT_LENGTH_WEIGHT
  kreal sl = wLength;  // planted fault: the weight itself used where eq. 3 needs its root
#else
  kreal sl = sqrt(wLength);
#endif
  int angleIndex = 0;
  int lengthIndex = 0;
  for (int c = 0; c < 3; ++c) {
    int n = knitChainLength(c);
    for (int j = 0; j + 1 < n; ++j) {
      int i0 = knitChainPoint(c, j);
      int i1 = knitChainPoint(c, j + 1);
      kvec3 e = q.x[i1] - q.x[i0];
      kreal len = sqrt(dot(e, e));
      kvec3 u = e / len;
      // Eq. 6: r = √w_length (|e| − |e0|), ∂r/∂Θ = √w_length û·(∂q1 − ∂q0).
      kreal r = sl * (len - pr.restLength[lengthIndex]);
      ne.energy += r * r;
      ++lengthIndex;
      if (withJacobian) {
        // J[p] = √w_length û·(∂x1/∂Θ_p − ∂x0/∂Θ_p); a point moves with its own knot's θ_j, l_j only.
        kvec4 J = kvec4(KR(0.0), KR(0.0), KR(0.0), KR(0.0));
        int k0 = q.knot[i0];
        int k1 = q.knot[i1];
        if (k1 >= 0) {
          J[k1] += dot(u, q.dTheta[i1]);
          J[k1 + 2] += dot(u, q.dLength[i1]);
        }
        if (k0 >= 0) {
          J[k0] -= dot(u, q.dTheta[i0]);
          J[k0 + 2] -= dot(u, q.dLength[i0]);
        }
        J *= sl;
#ifdef FT_FAULT_KNIT_JACOBIAN_SWAP
        // Planted fault: the θ_L and l_L columns of the Jacobian swapped.
        kreal swapTmp = J.x;
        J.x = J.z;
        J.z = swapTmp;
#endif
        for (int p = 0; p < 4; ++p)
          for (int s = 0; s < 4; ++s) ne.a[p * 4 + s] += J[p] * J[s];
        ne.g += J * r;
      }
      if (j + 2 < n) {
        // Eq. 5 at the interior point q1, between segments e (q0→q1) and f (q1→q2).
        int i2 = knitChainPoint(c, j + 2);
        kvec3 f = q.x[i2] - q.x[i1];
        kreal lf = sqrt(dot(f, f));
        kvec3 v = f / lf;
        kreal cosine = dot(u, v);
        kreal ra = sa * (cosine - pr.restCosine[angleIndex]);
        ne.energy += ra * ra;
        ++angleIndex;
        if (withJacobian) {
          // ∂cos/∂e = (v − cos u)/|e|, ∂cos/∂f = (u − cos v)/|f|.
          kvec3 ge = (v - cosine * u) / len;
          kvec3 gf = (u - cosine * v) / lf;
          // Coefficients of the three points: −ge, ge − gf, gf.
          kvec4 Ja = kvec4(KR(0.0), KR(0.0), KR(0.0), KR(0.0));
          int a0 = q.knot[i0];
          int a1 = q.knot[i1];
          int a2 = q.knot[i2];
          kvec3 g1 = ge - gf;
          if (a0 >= 0) {
            Ja[a0] -= dot(ge, q.dTheta[i0]);
            Ja[a0 + 2] -= dot(ge, q.dLength[i0]);
          }
          if (a1 >= 0) {
            Ja[a1] += dot(g1, q.dTheta[i1]);
            Ja[a1 + 2] += dot(g1, q.dLength[i1]);
          }
          if (a2 >= 0) {
            Ja[a2] += dot(gf, q.dTheta[i2]);
            Ja[a2 + 2] += dot(gf, q.dLength[i2]);
          }
          Ja *= sa;
#ifdef FT_FAULT_KNIT_JACOBIAN_SWAP
          kreal swapTmp2 = Ja.x;
          Ja.x = Ja.z;
          Ja.z = swapTmp2;
#endif
          for (int p = 0; p < 4; ++p)
            for (int s = 0; s < 4; ++s) ne.a[p * 4 + s] += Ja[p] * Ja[s];
          ne.g += Ja * ra;
        }
      }
    }
  }
  return ne;
}

FT_FUNC KnitNormalEquations knitNormalEquations(KnitProblem pr, kvec4 t, kreal wAngle, kreal wLength) {
  return knitAccumulate(pr, t, wAngle, wLength, true);
}

FT_FUNC kreal knitEnergy(KnitProblem pr, kvec4 t, kreal wAngle, kreal wLength) {
  return knitAccumulate(pr, t, wAngle, wLength, false).energy;
}

// Point i of the tile (0..20) for parameters t.
FT_FUNC kvec3 knitPoint(KnitProblem pr, kvec4 t, int i) { return knitJets(pr, t).x[i]; }

// Direct solve of A x = rhs by Cholesky (A is symmetric positive
// semi-definite); ok = false when a pivot is not positive, e.g. a parameter
// that no residual sees.
struct KnitSolve4 {
  kvec4 x;
  bool ok;
};

FT_FUNC KnitSolve4 knitCholeskySolve(kreal a[16], kvec4 rhs) {
  KnitSolve4 o;
  o.ok = true;
  o.x = kvec4(KR(0.0), KR(0.0), KR(0.0), KR(0.0));
  kreal l[16];
  for (int k = 0; k < 16; ++k) l[k] = KR(0.0);
  kreal scale = max(max(a[0], a[5]), max(a[10], a[15]));
  for (int j = 0; j < 4; ++j) {
    kreal s = a[j * 4 + j];
    for (int k = 0; k < j; ++k) s -= l[j * 4 + k] * l[j * 4 + k];
    if (!(s > scale * KR(1e-12))) {
      o.ok = false;
      return o;
    }
    kreal d = sqrt(s);
    l[j * 4 + j] = d;
    for (int i = j + 1; i < 4; ++i) {
      kreal t = a[i * 4 + j];
      for (int k = 0; k < j; ++k) t -= l[i * 4 + k] * l[j * 4 + k];
      l[i * 4 + j] = t / d;
    }
  }
  kvec4 y = kvec4(KR(0.0), KR(0.0), KR(0.0), KR(0.0));
  for (int i = 0; i < 4; ++i) {
    kreal t = rhs[i];
    for (int k = 0; k < i; ++k) t -= l[i * 4 + k] * y[k];
    y[i] = t / l[i * 4 + i];
  }
  for (int i = 3; i >= 0; --i) {
    kreal t = y[i];
    for (int k = i + 1; k < 4; ++k) t -= l[k * 4 + i] * o.x[k];
    o.x[i] = t / l[i * 4 + i];
  }
  return o;
}

// Three (or `iterations`) Gauss–Newton steps Θ += ΔΘ with A ΔΘ = −g (§5.2),
// then the tile's points for the final Θ. Safeguard (not in the paper): a
// step that would raise eq. 3 is halved, up to FT_KNIT_MAX_HALVINGS times, and
// dropped if it still does. Plain Gauss–Newton is not a descent method; on the
// slanted halves of split pentagons it raised the energy (measured on the
// lace patch: 1.9315 → 1.9327 → 1.9628 over three steps).
#define FT_KNIT_MAX_HALVINGS 4
FT_FUNC KnitTileResult knitSolveTile(KnitProblem pr, kreal wAngle, kreal wLength, uint iterations) {
  KnitTileResult res;
  kvec4 t = pr.theta0;
  res.steps = 0u;
  for (int k = 0; k <= FT_KNIT_MAX_ITERATIONS; ++k) res.energy[k] = KR(0.0);
  uint it = min(iterations, uint(FT_KNIT_MAX_ITERATIONS));
  kreal e = it == 0u ? knitEnergy(pr, t, wAngle, wLength) : KR(0.0);
  for (uint k = 0u; k < it; ++k) {
    KnitNormalEquations ne = knitNormalEquations(pr, t, wAngle, wLength);
    e = ne.energy;  // the same sum, in the same order, as the accepted trial's
    res.energy[k] = e;
    KnitSolve4 s = knitCholeskySolve(ne.a, -ne.g);
    if (!s.ok) continue;
    kvec4 step = s.x;
    for (int h = 0; h <= FT_KNIT_MAX_HALVINGS; ++h) {
      kreal trial = knitEnergy(pr, t + step, wAngle, wLength);
#ifdef FT_FAULT_KNIT_NO_SAFEGUARD
      bool accept = true;  // planted fault: plain Gauss–Newton, every step taken
#else
      bool accept = trial <= e;
#endif
      if (accept) {
        t += step;
        e = trial;
        res.steps += 1u;
        break;
      }
      step *= KR(0.5);
    }
  }
  res.energy[it] = e;
  res.theta = t;
  KnitJets q = knitJets(pr, t);
  for (int i = 0; i < FT_KNIT_TILE_POINTS; ++i) res.p[i] = q.x[i];
  return res;
}

// Uniform Catmull–Rom between p1 and p2 at s in [0, 1): the up-sampling of §5.2.
FT_FUNC kvec3 knitCatmullRom(kvec3 p0, kvec3 p1, kvec3 p2, kvec3 p3, kreal s) {
  kreal s2 = s * s;
  kreal s3 = s2 * s;
  return KR(0.5) * ((KR(2.0) * p1) + (p2 - p0) * s + (KR(2.0) * p0 - KR(5.0) * p1 + KR(4.0) * p2 - p3) * s2 +
                    (KR(3.0) * p1 - p0 - KR(3.0) * p2 + p3) * s3);
}
