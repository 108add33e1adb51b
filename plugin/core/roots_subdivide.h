#pragma once
// Subdivision before Yuksel's recursion (roots_yuksel.cpp), for long intervals.
//
// Why: on a whole ray's span the recursion finds every critical point of every derivative
// over all of it, O(n^3) Newton work, although a closest-hit query needs only the pieces
// up to the first root, and a missing ray none. Bernstein coefficients answer the two
// questions that let most of the interval go without any root finding, in O(n) each:
//  * exclusion: on a node [va, vb], G(v) is a convex combination of its Bernstein
//    coefficients b_i, so if all of them exceed the error bound (*) of their computation
//    plus the noise bound of G on the node (roots_detail.h), G has no root and no
//    tangent candidate there (the same verdict the sweep would reach);
//  * monotonicity: G' has the Bernstein coefficients n (b_{i+1} - b_i); if all
//    differences have one sign beyond their bounds the node is one monotone piece, and the
//    sweep of roots_scan.h runs on it with no critical point (Newton on the power form G);
//  * one root: if every b_i clears its bound plus the noise bound and they change sign
//    exactly once, the node holds exactly one simple root (Descartes' rule, oneVariation
//    below), and its ends b_0 = G(va), b_n = G(vb) bracket it for the safeguarded Newton
//    of the sweep.
// Anything else is split by de Casteljau's algorithm, left half first, so the first node
// with a root ends a First/Any query (Lane and Riesenfeld, "Bounds on a polynomial", BIT
// 21, 1981; Farin, "Curves and Surfaces for CAGD", Sec. 4.2). A node still undecided at
// the depth cap, or too short, goes to Yuksel's recursion (`direct`), which on a short
// interval is cut by its own exclusion test to a few levels.
//
// The Bernstein data only decide where to look; every root comes from G in power form,
// so the accuracy and the noise rules are those of the sweep. Nodes share their end
// points, and the sweep's end rules report a root at a shared point once (by the left
// node). A split point where G is within its noise would turn a simple root near it into
// an end-point root at the split point, so the split moves off such points.
//
// The node data and tests (the change of basis, its error bound (*), the split, the
// decisions) are in roots_bernstein_nodes.h.
#include "roots_bernstein_nodes.h"
#include "roots_detail.h"
#include "roots_scan.h"

#include <algorithm>
#include <bit>
#include <iterator>
#include <type_traits>

namespace algray::roots_detail {

// Nodes examined before the rest of the interval, from the first node not yet examined
// to hi, goes to the recursion in one piece: a polynomial whose Bernstein bounds are
// large against its values (high degree, much cancellation, |g| small along much of the
// span as on Chmutov's surfaces) would otherwise split to the full depth and then run the
// recursion on every leaf (measured: Chmutov-16 rendered 2x slower than with no
// subdivision at all before this cap took the rest in one piece).
inline constexpr int kSubdivideNodes = 24;
// Above this degree a node where G is within noise from end to end reports nothing
// (see withinBounds and its use in subdivide).
inline constexpr int kNoiseNodeDegree = 20;

template <class T>
struct SubdivideState {
  LocalPoly<T>& g;  // working copy: lo, hi are moved to each node
  T lo, w;          // the root node: v = lo + w u
  T err;            // the uniform bound E of plain-T nodes (0 with pairs)
  Query q;
  T tol;
  bool closedLo;  // the root node's lo is closed (LocalPoly::closedLo); inner ends are not
  int nodes = 0;
  bool exhausted = false;  // the budget ran out at node end `resumeAt`; the rest is open
  T resumeAt = 0;
};

// A node's noise bound is G's at x = max(|va|, |vb|), a degree-n Horner pass (a serial
// chain of n multiply-adds). With paired nodes (above kPairNodeDegree) a child shares x
// with its parent, or has x = |vm|, the split point, where the parent evaluated the bound
// while splitting; both are handed down, and a child whose x matches one reuses it (the
// same function of the same x: bit for bit the same margin). Measured (session 13, perf,
// whole rays of degree 40): the nodes' and the split points' Horner passes were half of
// subdivide's own time, a fifth of the solve; on a span with lo >= 0 every node but the
// first matches. Plain nodes evaluate their own (their chains are short; with the session's
// changes at every degree, degree 6-8 whole rays were 2-8 % slower).
template <class T>
struct KnownNoise {
  T x0 = -1, n0 = 0;  // x = -1: none (x >= 0)
  T x1 = -1, n1 = 0;
};

// Roots of G on the node u in [u0, u1] with Bernstein coefficients b; `direct(g)` runs
// Yuksel's recursion on [g.lo, g.hi].
template <class T, class E, class D, class Direct>
int subdivide(SubdivideState<T>& st, D deg, const E* b, T u0, T u1, int depth, Direct&& direct,
              LocalRoot<T>* out, int maxOut, KnownNoise<T> known = {}) {
  LocalPoly<T>& g = st.g;
  const T va = st.lo + st.w * u0, vb = u1 == 1 ? g.hi : st.lo + st.w * u1;
  if (st.exhausted) return 0;
  if (++st.nodes > kSubdivideNodes) {
    st.exhausted = true;
    st.resumeAt = va;
    return 0;
  }
  T xNoise = std::max(std::abs(va), std::abs(vb));
  constexpr bool kPairs = std::is_same_v<E, BPair<T>>;
  T noise;
  if constexpr (!kPairs) {
    // Plain nodes take the bound their parent used, which holds for every |v| <= its x
    // (a Horner pass of non-negative terms grows with |v|), hence for the whole node:
    // the root node's is the only Horner pass. The margin grows by at most twice G's
    // noise bound at the interval's far end, less than the uniform bound E it is added to
    // (gamma(4n + 19) |C|(|lo| + w) against gamma(2n + 1) |C|(max |v|) without caller
    // errors), so nodes decide as before. Measured (session 14, callgrind, 2000 whole rays
    // a degree): instructions per solve 0.99-1.0x at degrees 6-8, 0.98x at 10-12.
    if (xNoise <= known.x0) {
      xNoise = known.x0;
      noise = known.n0;
    } else {
      noise = hornerAbs(g.noise.data(), deg, xNoise);
    }
  } else {
    noise = xNoise == known.x0   ? known.n0
            : xNoise == known.x1 ? known.n1
                                 : hornerAbs(g.noise.data(), deg, xNoise);
  }
  const T margin = st.err + 2 * noise * (1 + 4 * kUnit<T>);
  if (oneSign(b, deg, margin)) return 0;
  // A node within noise from end to end (above kNoiseNodeDegree): G within its noise
  // bound at va, vb and at five points between them, and no Bernstein coefficient clear of
  // its bound, so |G| stays within a few times the noise bound at the node's far end (the
  // margin's) on the whole node. Its lo is then in a cluster this node would not report
  // (the interval's own lo, or a split point whose cluster began in a node to the left,
  // which reported it if it was not its own lo's), and the node reports nothing, without a
  // split or a sweep. The sweep could still find G emerging from its noise bound inside the
  // node and report a grazing hit or a root there; a root that G's values decide nowhere
  // across a node 1/32 of the span or more has no digit anyway (the report's reference
  // roots, 1e6 u cond from their neighbours, cannot lie in one: |G'| <= 2n^2 / width max|G|
  // there). The points between (session 18): the noise bound grows like |v|^n, so "a few
  // times the far end's" can be 1e5 times G's own bound at the near end, and the ends alone
  // dropped nodes where G clears its bound by 1e2-1e4 between them: firstRoot(c, err,
  // previousRoot, hi) from a grazing root skipped the next root that allRoots reports
  // (RootsContract.WalkPastANoiseLevelNode; in the session's campaign 13 of 8800 random
  // problems on spans around 0 and 4 of 10531 tangent ones, all of degree 25-40; none with
  // the points below). G clears its bound where that bound is smallest, near the end
  // closer to 0, so the points are 1/16, 1/8, 1/4, 1/2 and 3/4 of the way from there (the
  // quarter points alone still dropped a node whose first sixth was clear of noise).
  // Five more Horner passes, only on nodes the rule drops. The points are samples; what
  // is proved (session 20, provedWithinNoise) is |G| <= 4 times its noise bound on the
  // whole node, an O(n^2) conversion of the noise bound to Bernstein form run only where
  // every point is within noise. Measured (callgrind, 400 roots_bench-shaped whole rays a
  // degree, Ir of firstRoot): degree 21 1.00x, 25 1.004x, 30 1.002x, 35 1.006x, 40 1.015x,
  // the same answers; in 3 x 9000 random tangent problems of degree 21-40 (spans near hi,
  // around 0, from near 0) walks that skip a sign change clear on both sides 14 -> 12,
  // all at noise level before and after (neither sign clears the original coefficients'
  // Horner bound by more than 1.44x before, 1.31x after).
  // Why: at degree 40 a ray polynomial cancels ~13 digits in power form, and long
  // stretches of a ray's span have G far below its noise bound (1e-24 against 1e-23 ..
  // 1e-21): a span starting there walked node after node to the depth cap, ran the
  // recursion on each leaf (exclusion orders 12-23, every critical point within noise, no
  // answer: the lo cluster) and exhausted the node budget, and the recursion then took the
  // rest of the span in one piece at order 38-40; 10 % of the rays, 39 % of the time.
  // Measured (callgrind, 200 roots_bench-shaped problems a degree, Ir per firstRoot):
  // whole rays of degree 40 141434 -> 96174, 30 45696 -> 45908, 20 unchanged; cells of
  // degree 30 24359 -> 21665, 40 37939 -> 35935. roots_report (400 problems a degree):
  // the same errors, no missed or false root, noise-level answers 57 -> 56 (ray, 30) and
  // 99 -> 96 (ray, 40).
  if constexpr (kPairs) {
    if (deg > kNoiseNodeDegree && (u0 != 0 || !st.closedLo) && withinBounds(b, deg, margin)) {
      // The ends first (a node they keep costs no more than before), then the points
      // between, from the end nearer 0.
      const bool nearA = std::abs(va) <= std::abs(vb);
      const T from = nearA ? va : vb, step = nearA ? vb - va : va - vb;
      const T points[7] = {va,
                           vb,
                           from + step * T(0.0625),
                           from + step * T(0.125),
                           from + step * T(0.25),
                           from + step * T(0.5),
                           from + step * T(0.75)};
      const bool within = std::all_of(std::begin(points), std::end(points), [&](T v) {
        T f, nv;
        hornerNoise(g.c.data(), g.noise.data(), deg, v, f, nv);
        return std::abs(f) <= nv;
      });
      const T delta = 2 * kUnit<T> * (std::abs(st.lo) + st.w);  // the ends' rounding
      if (within && provedWithinNoise(g, deg, b, va, vb, delta)) return 0;
    }
  }
  const T saveLo = g.lo, saveHi = g.hi;
  g.lo = va;
  g.hi = vb;
  // A node's lo is a split point (its root, if any, was the left neighbour's to report
  // at its hi) except the first node's, which is the interval's own.
  g.closedLo = st.closedLo && u0 == 0;
  int k = 0;
  const bool small =
      vb - va <= std::max(st.tol, 64 * kUnit<T> * std::max(std::abs(va), std::abs(vb)));
  const bool single = oneVariation(b, deg, margin);
  if (single || monotone(b, deg, st.err)) {
    // Start where the control polygon crosses zero (Bezier clipping's estimate, Sederberg
    // and Nishita 1990): inside a one-variation node it is closer to the root than the
    // secant through the node's ends.
    auto piece = [&](T a, T c, T fa, T fc) {
      const int n = deg;
      for (int i = 0; i < n; ++i) {
        const T bi = coeff<T>(b[i]), bj = coeff<T>(b[i + 1]);
        if (signBit(bi) != signBit(bj)) {
          const T u = (T(i) + bi / (bi - bj)) / T(n);
          const T x = va + (vb - va) * u;
          if (x > a && x < c)
            return newtonFrom(g.c.data(), g.noise.data(), deg, a, c, fa, x, st.tol);
          break;
        }
      }
      return newtonInBracket(g.c.data(), g.noise.data(), deg, a, c, fa, fc, st.tol);
    };
    if (single) {
      // The sweep's verdict without its evaluations: b_0 = G(va) and b_n = G(vb) are beyond
      // their bounds plus twice the noise bound with opposite signs, so neither end is
      // within noise and the node holds one simple root (the sweep would evaluate both
      // ends to find just that; 2 of a root's ~9 polynomial passes: rays with a root 2-9 %
      // faster, session 8).
      const T fa = coeff<T>(b[0]), fb = coeff<T>(b[static_cast<int>(deg)]);
      out[0] = LocalRoot<T>{st.q == Query::Any ? va + (vb - va) / 2 : piece(va, vb, fa, fb), false};
      // The noise-before query (roots_scan.h), on a monotone node with the node's noise
      // bound (at its far end from 0) for G's at va. A node that is not monotone gets only
      // the test at r - window: a shelf within noise would have to come within the noise
      // bound between control points that all clear it by twice that bound.
      if (g.window > 0 && st.q != Query::Any) {
        bool noisy = false;
        if (monotone(b, deg, st.err))
          out[0].v = noiseBefore(g, deg, va, fa, noise, out[0].v, noisy);
        else
          noisy = noiseAt(g, deg, fa, out[0].v - g.window, va);
        out[0].tangent = noisy;
      }
      k = 1;
    } else {
      k = scanPieces(g, deg, static_cast<const T*>(nullptr), 0, st.q, piece, out, maxOut);
    }
  } else if (depth >= kSubdivideDepth<T> || small) {
    k = direct(g, out, maxOut);
  } else {
    // Split at the middle unless G is within its noise there (see above). The halves'
    // shared coefficient is G at the middle within its bound, so a value beyond that plus
    // twice the noise bound settles the common case without evaluating G. With paired
    // nodes G and its noise bound at the middle are evaluated before the split anyway:
    // the split's independent work hides their latency, the bound is the left child's
    // (KnownNoise), and at degree 30-40 the test on r[0] fails on most splits (G's
    // Bernstein bounds there are far above its noise bound). Plain nodes evaluate them
    // only where that test fails, as before.
    constexpr bool kEarly = kPairs;
    // Plain nodes (degree <= 12) with two or more sign changes in the control polygon
    // split between its first two crossings instead of at the middle, so that the first
    // root more often lands alone in the left child (one variation: straight to the
    // polish); the crossings are estimated from the indices only (no division on the
    // path to the split) and the ratio is kept in [1/4, 3/4] (clamped to [1/16, 15/16], a
    // near miss's dip at a node's end left nodes that hardly shrank, and more went to the
    // recursion at the depth cap). Measured (session 14, 1000 whole-ray problems a degree
    // and outcome): with a root, nodes per solve 3.13 -> 2.72 (degree 6) and 3.80 -> 3.22
    // (12), splits 1.68 -> 1.31 and 2.03 -> 1.56, polish evaluations 3.23 -> 3.10 and
    // 3.25 -> 3.06; near misses 10.7 -> 8.8 nodes (6), recursion calls 0.46 -> 0.09;
    // callgrind instructions per solve (all outcomes) 0.95x (6), 0.97x (7), 0.94x (8),
    // 0.98x (9), 0.95x (10), 0.97x (11), 1.01x (12); interleaved timings 0.95-0.99x at
    // degrees 6-10, 1.00x at 11-12, cells 0.98-1.02x (noise).
    // With the crossings interpolated (two divisions before the split could start) whole
    // rays of degree 6-7 were 7-10 % slower despite 4-5 % fewer instructions.
    T t = T(0.5);
    int t16 = 8;  // t in sixteenths (dyadic: the node ends stay exact, see above)
    if constexpr (!kPairs) {
      const int n = deg;
      // The first two sign changes, without branches: bit i of `changes` is a change
      // between b_i and b_{i+1}; the lowest two set bits are the first two. (As a loop that
      // selected c1, c2 per index, a serial chain of conditional moves, it was a tenth of
      // subdivide's samples on Sarti's rays; the same indices.)
      static_assert(kPairNodeDegree < 32);
      unsigned changes = 0;
#pragma GCC unroll 24
      for (int i = 0; i < n; ++i)
        changes |= static_cast<unsigned>(signBit(b[i]) != signBit(b[i + 1])) << i;
      const unsigned rest = changes & (changes - 1);  // without the first change
      if (rest != 0) {
        const int c1 = std::countr_zero(changes), c2 = std::countr_zero(rest);
        t16 = std::clamp((8 * (c1 + c2 + 1) + n / 2) / n, 4, 12);
        t = T(t16) / 16;
      }
    }
    T mid = u0 + (u1 - u0) * t;
    const T vMid = st.lo + st.w * mid;
    T fMid = 0, noiseMid = 0;
    if (kEarly) hornerNoise(g.c.data(), g.noise.data(), deg, vMid, fMid, noiseMid);
    E l[kMaxDegree + 1], r[kMaxDegree + 1];
    KnownNoise<T> childKnown{xNoise, noise, kEarly ? std::abs(vMid) : T(-1), noiseMid};
    // (the loop below, kept apart for compile-time degrees: as one lambda for both paths
    // their code changed, and degree-20 whole rays measured 2-3 % slower)
    auto moveOff = [&] {
      for (const T f : {T(0.4375), T(0.5625), T(0.375), T(0.625)}) {
        const T um = u0 + (u1 - u0) * f, vm = st.lo + st.w * um;
        T fm, noiseM;
        hornerNoise(g.c.data(), g.noise.data(), deg, vm, fm, noiseM);
        if (std::abs(fm) > noiseM) {
          t = f;
          mid = um;
          childKnown.x1 = std::abs(vm);
          childKnown.n1 = noiseM;
          return;
        }
      }
    };
    // Run-time degrees (above 20) choose the ratio before the split, from G at the middle
    // evaluated above, instead of splitting again when the test on r[0] fails (it fails on
    // most splits there, see above; G within noise at the middle on 0.3 splits of 4.8 a
    // whole ray at degree 40). The same ratio unless r[0] clears its margin while G's value
    // at the middle is within noise (not seen: no answer changed on the problems below).
    // Measured (callgrind, whole rays, Ir per firstRoot): degree 40 84464 -> 82395, 30
    // 40693 -> 39977; cells 0.997-1.00x.
    constexpr bool kRatioFirst = std::is_same_v<D, int>;
    if (kRatioFirst && !(std::abs(fMid) > noiseMid)) moveOff();
    splitBernstein(b, deg, t, l, r);
    const bool rDecides = kRatioFirst || std::abs(coeff<T>(r[0])) - bound<T>(r[0]) > margin;
    if (!kEarly && !rDecides) {
      hornerNoise(g.c.data(), g.noise.data(), deg, vMid, fMid, noiseMid);
      childKnown.x1 = std::abs(vMid);
      childKnown.n1 = noiseMid;
    }
    if (!rDecides && !(std::abs(fMid) > noiseMid)) {
      for (const int d16 : {-1, 1, -2, 2}) {  // -1/16, +1/16, -1/8, +1/8 around t
        const T f = T(t16 + d16) / 16;
        const T um = u0 + (u1 - u0) * f, vm = st.lo + st.w * um;
        T fm, noiseM;
        hornerNoise(g.c.data(), g.noise.data(), deg, vm, fm, noiseM);
        if (std::abs(fm) > noiseM) {
          t = f;
          mid = um;
          childKnown.x1 = std::abs(vm);
          childKnown.n1 = noiseM;
          break;
        }
      }
      if (t != T(t16) / 16) splitBernstein(b, deg, t, l, r);
    }
    g.lo = saveLo;
    g.hi = saveHi;
    k = subdivide(st, deg, l, u0, mid, depth + 1, direct, out, maxOut, childKnown);
    if ((k > 0 && (st.q != Query::All || k >= maxOut)) || st.exhausted) return k;
    return k + subdivide(st, deg, r, mid, u1, depth + 1, direct, out + k, maxOut - k, childKnown);
  }
  g.lo = saveLo;
  g.hi = saveHi;
  return k;
}

}  // namespace algray::roots_detail
