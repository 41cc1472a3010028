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

// Chain order. The 21 points (tile + halo) are visited by the three chains
// exactly once each, so a tile is evaluated with its points stored in chain
// order, back to back: positions 0..5 chain 0 (14 | 0 1 2 3 | 15), 6..14
// chain 1 (16 | 4 .. 10 | 17), 15..20 chain 2 (18 | 11 12 13 | 19 20).
// Segment k joins positions k and k + 1 of one chain; residual numbering
// (restLength, restCosine): length k − c, angle at interior position k: k − 1 − 2c.
#define FT_KNIT_CHAINS 3
FT_FUNC int knitChainStart(int c) { return c == 0 ? 0 : (c == 1 ? 6 : 15); }
FT_FUNC int knitChainLength(int c) { return c == 1 ? 9 : 6; }

// Chain position of tile point i (0..20).
FT_FUNC int knitPointPosition(int i) {
  if (i < 4) return i + 1;
  if (i < 11) return i + 3;
  if (i < 14) return i + 5;
  if (i == 14) return 0;
  if (i == 15) return 5;
  if (i == 16) return 6;
  if (i == 17) return 14;
  if (i == 18) return 15;
  return i;  // 19, 20
}

// A point, the knot j it moves with (−1: fixed) and the derivatives of its
// in-plane coordinates with respect to that knot's θ_j and l_j (its normal
// offset is fixed). No point depends on both knots.
struct KnitPointJet {
  kvec3 x;
  kvec2 dTheta;   // ∂(x, y)/∂θ_j
  kvec2 dLength;  // ∂(x, y)/∂l_j
  int knot;
};

FT_INLINE KnitPointJet knitFixedPoint(kvec2 xy, kreal h) {
  KnitPointJet o;
  o.x = kvec3(xy.x, xy.y, h);
  o.dTheta = kvec2(KR(0.0), KR(0.0));
  o.dLength = o.dTheta;
  o.knot = -1;
  return o;
}

// One knot's contact frame: d = (cos θ, sin θ), b = d × n with n = +z of the
// face frame, ∂b/∂θ and the half-length l.
struct KnitKnotFrame {
  kvec2 centre;
  kvec2 d;
  kvec2 b;
  kvec2 dbdTheta;
  kreal halfLength;
  int knot;
};

FT_INLINE KnitKnotFrame knitKnotFrame(kvec2 centre, kreal theta, kreal halfLength, int knot) {
  KnitKnotFrame k;
  k.centre = centre;
  k.d = kvec2(cos(theta), sin(theta));
  k.halfLength = halfLength;
  k.b = kvec2(k.d.y, -k.d.x);
  k.dbdTheta = k.d;
  k.knot = knot;
  return k;
}

#ifdef FT_FAULT_KNIT_CONSTRAINT_DROPPED
// Planted fault: p0/p1 keep the interpolated contact direction (tilt theta0)
// instead of following θ, dropping the perpendicularity constraint of eq. 4.
FT_INLINE KnitKnotFrame knitFrozenContact(KnitKnotFrame k, kreal theta0) {
  k.b = kvec2(sin(theta0), -cos(theta0));
  k.dbdTheta = kvec2(KR(0.0), KR(0.0));
  return k;
}
#endif

// Eq. 1–2: x = x_k + s_d l d + s_b r b + s_n r n (c0± = s_d +1, c1± = s_d −1,
// p0/p1 = s_b ±1, ± = s_n).
FT_INLINE KnitPointJet knitKnotPoint(KnitKnotFrame k, kreal r, kreal side, kreal sd, kreal sb, kreal sn) {
  KnitPointJet o;
  kvec2 xy = k.centre + sd * k.halfLength * k.d + sb * r * k.b;
  o.x = kvec3(xy.x, xy.y, sn * r * side);
  o.dTheta = sd * k.halfLength * kvec2(-k.d.y, k.d.x) + sb * r * k.dbdTheta;
  o.dLength = sd * k.d;
  o.knot = k.knot;
  return o;
}

// All 21 points of a tile for parameters t, in chain order.
struct KnitTilePoints {
  KnitPointJet at[FT_KNIT_POINTS];
};

FT_FUNC KnitTilePoints knitTilePoints(KnitProblem pr, kvec4 t) {
  KnitTilePoints q;
  KnitKnotFrame L = knitKnotFrame(pr.knot[0], t.x, t.z, 0);
  KnitKnotFrame R = knitKnotFrame(pr.knot[1], t.y, t.w, 1);
#ifdef FT_FAULT_KNIT_CONSTRAINT_DROPPED
  L = knitFrozenContact(L, pr.theta0.x);
  R = knitFrozenContact(R, pr.theta0.y);
#endif
  kreal r = pr.radius;
  kreal side = pr.side;
  // Chain 0: left tile's 13, S, then the red yarn up through L (back below the head, front above it).
  q.at[0] = knitFixedPoint(pr.fixedXY[2], pr.fixedH[2]);
  q.at[1] = knitFixedPoint(pr.fixedXY[0], pr.fixedH[0]);
  q.at[2] = knitKnotPoint(L, r, side, KR(-1.0), KR(0.0), KR(-1.0));  // 1 c1-
  q.at[3] = knitKnotPoint(L, r, side, KR(0.0), KR(1.0), KR(0.0));    // 2 p0
  q.at[4] = knitKnotPoint(L, r, side, KR(1.0), KR(0.0), KR(1.0));    // 3 c0+
  q.at[5] = knitFixedPoint(pr.fixedXY[3], pr.fixedH[3]);
  // Chain 1: the green head of the loop below, through L, the apex A, then R.
  q.at[6] = knitFixedPoint(pr.fixedXY[4], pr.fixedH[4]);
  q.at[7] = knitKnotPoint(L, r, side, KR(-1.0), KR(0.0), KR(1.0));   // 4 c1+
  q.at[8] = knitKnotPoint(L, r, side, KR(0.0), KR(-1.0), KR(0.0));   // 5 p1
  q.at[9] = knitKnotPoint(L, r, side, KR(1.0), KR(0.0), KR(-1.0));   // 6 c0-
  q.at[10] = knitFixedPoint(pr.fixedXY[1], pr.fixedH[1]);            // 7 A
  q.at[11] = knitKnotPoint(R, r, side, KR(1.0), KR(0.0), KR(-1.0));  // 8 c0-
  q.at[12] = knitKnotPoint(R, r, side, KR(0.0), KR(1.0), KR(0.0));   // 9 p0
  q.at[13] = knitKnotPoint(R, r, side, KR(-1.0), KR(0.0), KR(1.0));  // 10 c1+
  q.at[14] = knitFixedPoint(pr.fixedXY[5], pr.fixedH[5]);
  // Chain 2: the red yarn down through R, then the right tile's S and its 1.
  q.at[15] = knitFixedPoint(pr.fixedXY[6], pr.fixedH[6]);
  q.at[16] = knitKnotPoint(R, r, side, KR(1.0), KR(0.0), KR(1.0));    // 11 c0+
  q.at[17] = knitKnotPoint(R, r, side, KR(0.0), KR(-1.0), KR(0.0));   // 12 p1
  q.at[18] = knitKnotPoint(R, r, side, KR(-1.0), KR(0.0), KR(-1.0));  // 13 c1-
  q.at[19] = knitFixedPoint(pr.fixedXY[7], pr.fixedH[7]);
  q.at[20] = knitFixedPoint(pr.fixedXY[8], pr.fixedH[8]);
  return q;
}

// Point i of the tile (0..20) for parameters t.
FT_FUNC kvec3 knitPoint(KnitProblem pr, kvec4 t, int i) { return knitTilePoints(pr, t).at[knitPointPosition(i)].x; }

// The chains' segments, by chain position k: e_k = x_{k+1} − x_k, |e_k| and
// 1/|e_k| (positions 5 and 14 end a chain: e = 0, |e| = 1 there). Computed apart from
// the residuals, so that the square roots and divisions of independent
// segments overlap.
struct KnitSegments {
  kvec3 e[FT_KNIT_POINTS - 1];
  kreal len[FT_KNIT_POINTS - 1];
  kreal inv[FT_KNIT_POINTS - 1];
};

// `at` is an array parameter: the CPU passes it by address, not by copy.
FT_INLINE KnitSegments knitSegments(KnitPointJet at[FT_KNIT_POINTS]) {
  KnitSegments s;
  kreal len2[FT_KNIT_POINTS - 1];
  for (int k = 0; k < FT_KNIT_POINTS - 1; ++k) {
    bool chainEnd = k == 5 || k == 14;
    s.e[k] = chainEnd ? kvec3(KR(0.0), KR(0.0), KR(0.0)) : at[k + 1].x - at[k].x;
    len2[k] = chainEnd ? KR(1.0) : dot(s.e[k], s.e[k]);  // 1: no division by zero at a chain end
  }
  // A loop of square roots and divisions alone (vectorizable on the CPU).
  for (int k = 0; k < FT_KNIT_POINTS - 1; ++k) {
    s.len[k] = sqrt(len2[k]);
    s.inv[k] = KR(1.0) / s.len[k];
  }
  return s;
}

// Eq. 5's cosine between consecutive segments e, f (with 1/|e|, 1/|f|): one
// expression for the rest values and the residuals, so the template has zero
// energy at rest.
FT_INLINE kreal knitCosine(kvec3 e, kvec3 f, kreal invE, kreal invF) { return dot(e, f) * (invE * invF); }

// Segment lengths and interior-point cosines of the three chains, in residual
// order: the rest values of eq. 5–6 come from the template measured with this.
struct KnitMeasures {
  kreal segment[FT_KNIT_LENGTH_RESIDUALS];  // not `length`: GLSL reserves .length()
  kreal cosine[FT_KNIT_ANGLE_RESIDUALS];
};

FT_FUNC KnitMeasures knitMeasure(KnitProblem pr, kvec4 t) {
  KnitMeasures m;
  KnitTilePoints q = knitTilePoints(pr, t);
  KnitSegments s = knitSegments(q.at);
  for (int c = 0; c < FT_KNIT_CHAINS; ++c) {
    int first = knitChainStart(c);
    int last = first + knitChainLength(c) - 1;
    for (int k = first; k < last; ++k) {
      m.segment[k - c] = s.len[k];
      if (k > first) m.cosine[k - 1 - 2 * c] = knitCosine(s.e[k - 1], s.e[k], s.inv[k - 1], s.inv[k]);
    }
  }
  return m;
}

// One residual's Jacobian row, split by knot: (∂r/∂θ_j, ∂r/∂l_j) for j = L, R.
// Every residual of a tile but the angle at the apex A depends on one knot
// only, so A = Σ J Jᵀ is assembled from a 2×2 block per knot and one coupling
// block, each only from the residuals that reach it.
struct KnitJacobianRow {
  kvec2 L;
  kvec2 R;
};

// Adds ∂x_p/∂Θ · grad (grad: ∂r/∂x_p; only its in-plane part meets a derivative).
FT_INLINE KnitJacobianRow knitChainRule(KnitJacobianRow row, KnitPointJet p, kvec3 grad) {
  kvec2 c = kvec2(grad.x * p.dTheta.x + grad.y * p.dTheta.y, grad.x * p.dLength.x + grad.y * p.dLength.y);
  if (p.knot == 0) row.L += c;
  if (p.knot == 1) row.R += c;
  return row;
}

// Bit j for a point that moves with knot j; a residual depends on the union over its points.
FT_INLINE int knitKnotBit(KnitPointJet p) { return p.knot < 0 ? 0 : (p.knot == 0 ? 1 : 2); }

// The normal equations of one Gauss–Newton step (§5.2): A = Σ J Jᵀ and
// g = Σ J r over the residuals r = √w (value − rest) of eq. 5 (angles, at each
// interior chain point) and eq. 6 (lengths, each chain segment); energy = Σ r²
// is eq. 3. A by blocks: (θθ, θl, ll) of each knot and the coupling
// (θ_Lθ_R, θ_L l_R, l_Lθ_R, l_L l_R); g in Θ order.
struct KnitNormalEquations {
  kvec3 LL;
  kvec3 RR;
  kvec4 LR;
  kvec4 g;
  kreal energy;
};

// Running sums while the residuals are visited (no arrays: the CPU keeps it in registers).
struct KnitBlockSums {
  kvec3 LL;
  kvec3 RR;
  kvec4 LR;
  kvec2 gL;
  kvec2 gR;
  kreal energy;
};

// Adds residual r with Jacobian row J, which depends on the knots in `knots`.
FT_INLINE KnitBlockSums knitAddResidual(KnitBlockSums a, kreal r, KnitJacobianRow J, int knots) {
#ifdef FT_FAULT_KNIT_JACOBIAN_SWAP
  J.L = kvec2(J.L.y, J.L.x);  // planted fault: the θ_L and l_L columns of the Jacobian swapped
#endif
  a.energy += r * r;
  if ((knots & 1) != 0) {
    a.LL += kvec3(J.L.x * J.L.x, J.L.x * J.L.y, J.L.y * J.L.y);
    a.gL += J.L * r;
  }
  if ((knots & 2) != 0) {
    a.RR += kvec3(J.R.x * J.R.x, J.R.x * J.R.y, J.R.y * J.R.y);
    a.gR += J.R * r;
  }
#ifndef FT_FAULT_KNIT_COUPLING_DROPPED  // planted fault: A without its L×R block
  if (knots == 3) a.LR += kvec4(J.L.x * J.R.x, J.L.x * J.R.y, J.L.y * J.R.x, J.L.y * J.R.y);
#endif
  return a;
}

// Visits the residuals of eq. 3 per chain, each segment's length residual
// followed by the angle residual at its start point (from the chain's second
// segment on), and sums the normal equations; with withJacobian false only
// the energy (the same sum, in the same order).
FT_FUNC KnitNormalEquations knitAccumulate(KnitProblem pr, kvec4 t, kreal wAngle, kreal wLength, bool withJacobian) {
  KnitTilePoints q = knitTilePoints(pr, t);
  KnitSegments seg = knitSegments(q.at);
  kreal sa = sqrt(wAngle);
#ifdef FT_FAULT_KNIT_LENGTH_WEIGHT
  kreal sl = wLength;  // planted fault: the weight itself used where eq. 3 needs its root
#else
  kreal sl = sqrt(wLength);
#endif
  KnitJacobianRow none;
  none.L = kvec2(KR(0.0), KR(0.0));
  none.R = none.L;
  KnitBlockSums a;
  a.LL = kvec3(KR(0.0), KR(0.0), KR(0.0));
  a.RR = a.LL;
  a.LR = kvec4(KR(0.0), KR(0.0), KR(0.0), KR(0.0));
  a.gL = none.L;
  a.gR = none.L;
  a.energy = KR(0.0);
  for (int c = 0; c < FT_KNIT_CHAINS; ++c) {
    int first = knitChainStart(c);
    int last = first + knitChainLength(c) - 1;
    for (int k = first; k < last; ++k) {
      // Eq. 6 on segment k: r = √w_length (|e| − |e0|), ∂r/∂x_{k+1} = −∂r/∂x_k = √w_length ê.
      kreal r = sl * (seg.len[k] - pr.restLength[k - c]);
      KnitJacobianRow J = none;
      int knots = 0;
      if (withJacobian) {
        kvec3 u = seg.e[k] * (sl * seg.inv[k]);
        J = knitChainRule(knitChainRule(none, q.at[k + 1], u), q.at[k], -u);
        knots = knitKnotBit(q.at[k]) | knitKnotBit(q.at[k + 1]);
      }
      a = knitAddResidual(a, r, J, knots);
      if (k > first) {
        // Eq. 5 at position k, between segments e = e_{k−1} and f = e_k.
        kreal cosine = knitCosine(seg.e[k - 1], seg.e[k], seg.inv[k - 1], seg.inv[k]);
        kreal ra = sa * (cosine - pr.restCosine[k - 1 - 2 * c]);
        KnitJacobianRow Ja = none;
        int knotsA = 0;
        if (withJacobian) {
          // ∂cos/∂e = (v − cos u)/|e|, ∂cos/∂f = (u − cos v)/|f| with u, v the unit segments;
          // the three points get −∂/∂e, ∂/∂e − ∂/∂f and ∂/∂f.
          kvec3 u = seg.e[k - 1] * seg.inv[k - 1];
          kvec3 v = seg.e[k] * seg.inv[k];
          kvec3 ge = (v - cosine * u) * (sa * seg.inv[k - 1]);
          kvec3 gf = (u - cosine * v) * (sa * seg.inv[k]);
          Ja = knitChainRule(knitChainRule(knitChainRule(none, q.at[k - 1], -ge), q.at[k], ge - gf), q.at[k + 1], gf);
          knotsA = knitKnotBit(q.at[k - 1]) | knitKnotBit(q.at[k]) | knitKnotBit(q.at[k + 1]);
        }
        a = knitAddResidual(a, ra, Ja, knotsA);
      }
    }
  }
  KnitNormalEquations ne;
  ne.LL = a.LL;
  ne.RR = a.RR;
  ne.LR = a.LR;
  ne.g = kvec4(a.gL.x, a.gR.x, a.gL.y, a.gR.y);
  ne.energy = a.energy;
  return ne;
}

FT_FUNC KnitNormalEquations knitNormalEquations(KnitProblem pr, kvec4 t, kreal wAngle, kreal wLength) {
  return knitAccumulate(pr, t, wAngle, wLength, true);
}

FT_FUNC kreal knitEnergy(KnitProblem pr, kvec4 t, kreal wAngle, kreal wLength) {
  return knitAccumulate(pr, t, wAngle, wLength, false).energy;
}

// Direct solve of A x = rhs (Θ order) for the blocks of A: A = L D Lᵀ in knot
// order (θ_L, l_L, θ_R, l_R), i.e. the L block's 2×2 elimination, then the
// R block's Schur complement S = A_RR − Cᵀ A_LL⁻¹ C (C = the coupling block).
// ok = false when a pivot is not positive relative to A's largest diagonal
// entry, e.g. a parameter that no residual sees.
struct KnitSolve4 {
  kvec4 x;
  bool ok;
};

FT_FUNC KnitSolve4 knitSolveNormalEquations(KnitNormalEquations ne, kvec4 rhs) {
  KnitSolve4 o;
  o.x = kvec4(KR(0.0), KR(0.0), KR(0.0), KR(0.0));
  kreal tol = max(max(ne.LL.x, ne.LL.z), max(ne.RR.x, ne.RR.z)) * KR(1e-12);
  // A_LL = [a b; b c] = [1 0; b/a 1] diag(a, c − b²/a) [1 b/a; 0 1].
  kreal d0 = ne.LL.x;
  kreal l10 = ne.LL.y / d0;
  kreal d1 = ne.LL.z - l10 * ne.LL.y;
  // A_LL⁻¹ C, C = [θ_Lθ_R θ_L l_R; l_Lθ_R l_L l_R], by the same factors.
  kreal invDet = KR(1.0) / (d0 * d1);
  kvec2 c0 = kvec2(ne.LR.x, ne.LR.z);  // C's column for θ_R
  kvec2 c1 = kvec2(ne.LR.y, ne.LR.w);  // C's column for l_R
  kvec2 w0 = kvec2(ne.LL.z * c0.x - ne.LL.y * c0.y, ne.LL.x * c0.y - ne.LL.y * c0.x) * invDet;
  kvec2 w1 = kvec2(ne.LL.z * c1.x - ne.LL.y * c1.y, ne.LL.x * c1.y - ne.LL.y * c1.x) * invDet;
  kvec3 S = ne.RR - kvec3(dot(c0, w0), dot(c0, w1), dot(c1, w1));
  kreal d2 = S.x;
  kreal l32 = S.y / d2;
  kreal d3 = S.z - l32 * S.y;
  o.ok = d0 > tol && d1 > tol && d2 > tol && d3 > tol;
  if (!o.ok) return o;
  // Block forward substitution: y_L = A_LL⁻¹ b_L, then S x_R = b_R − Cᵀ y_L, then x_L = y_L − A_LL⁻¹ C x_R.
  kvec2 bL = kvec2(rhs.x, rhs.z);
  kvec2 bR = kvec2(rhs.y, rhs.w);
  kvec2 yL = kvec2(ne.LL.z * bL.x - ne.LL.y * bL.y, ne.LL.x * bL.y - ne.LL.y * bL.x) * invDet;
  kvec2 zR = bR - kvec2(dot(c0, yL), dot(c1, yL));
  kreal invDetS = KR(1.0) / (d2 * d3);
  kvec2 xR = kvec2(S.z * zR.x - S.y * zR.y, S.x * zR.y - S.y * zR.x) * invDetS;
  kvec2 xL = yL - (w0 * xR.x + w1 * xR.y);
  o.x = kvec4(xL.x, xR.x, xL.y, xR.y);
  return o;
}

// Three (or `iterations`) Gauss–Newton steps Θ += ΔΘ with A ΔΘ = −g (§5.2),
// then the tile's points for the final Θ. Safeguard (not in the paper): a
// step that would raise eq. 3 is halved, up to FT_KNIT_MAX_HALVINGS times, and
// dropped if it still does. Plain Gauss–Newton is not a descent method; on the
// slanted halves of split pentagons it raised the energy (measured on the
// lace patch: 1.9315 → 1.9327 → 1.9628 over three steps). A trial point's
// normal equations are summed with its energy, so an accepted step's are the
// next iteration's: three iterations cost three Jacobian passes and one
// energy pass.
#define FT_KNIT_MAX_HALVINGS 4
FT_FUNC KnitTileResult knitSolveTile(KnitProblem pr, kreal wAngle, kreal wLength, uint iterations) {
  KnitTileResult res;
  kvec4 t = pr.theta0;
  res.steps = 0u;
  for (int k = 0; k <= FT_KNIT_MAX_ITERATIONS; ++k) res.energy[k] = KR(0.0);
  uint it = min(iterations, uint(FT_KNIT_MAX_ITERATIONS));
  KnitNormalEquations ne = knitAccumulate(pr, t, wAngle, wLength, it > 0u);
  for (uint k = 0u; k < it; ++k) {
    res.energy[k] = ne.energy;
    KnitSolve4 s = knitSolveNormalEquations(ne, -ne.g);
    if (!s.ok) continue;  // ne stays valid at t: the next iteration meets the same system
    bool another = k + 1u < it;  // the Jacobian at the new Θ is needed only then
    kvec4 step = s.x;
    for (int h = 0; h <= FT_KNIT_MAX_HALVINGS; ++h) {
      KnitNormalEquations trial = knitAccumulate(pr, t + step, wAngle, wLength, another);
#ifdef FT_FAULT_KNIT_NO_SAFEGUARD
      bool accept = true;  // planted fault: plain Gauss–Newton, every step taken
#else
      bool accept = trial.energy <= ne.energy;
#endif
      if (accept) {
        t += step;
        ne = trial;
        res.steps += 1u;
        break;
      }
      step *= KR(0.5);
    }
  }
  res.energy[it] = ne.energy;
  res.theta = t;
  KnitTilePoints q = knitTilePoints(pr, t);
  for (int i = 0; i < FT_KNIT_TILE_POINTS; ++i) res.p[i] = q.at[knitPointPosition(i)].x;
  return res;
}

// Uniform Catmull–Rom between p1 and p2 at s in [0, 1): the up-sampling of §5.2.
FT_FUNC kvec3 knitCatmullRom(kvec3 p0, kvec3 p1, kvec3 p2, kvec3 p3, kreal s) {
  kreal s2 = s * s;
  kreal s3 = s2 * s;
  return KR(0.5) * ((KR(2.0) * p1) + (p2 - p0) * s + (KR(2.0) * p0 - KR(5.0) * p1 + KR(4.0) * p2 - p3) * s2 +
                    (KR(3.0) * p1 - p0 - KR(3.0) * p2 + p3) * s3);
}
