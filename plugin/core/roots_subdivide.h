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
// Error bound, per node and per coefficient (u = unit roundoff, n = degree, D = depth).
// Let A(v) be the Taylor shift of |C| to |lo| scaled by w (A_j = (shift of |C| by |lo|)_j
// w^j, all >= 0): a majorant of every term of G(lo + w u). Each Bernstein coefficient is a
// combination of the a_j with non-negative weights, so |b_i| <= beta_i, the same
// combination of the A_j, i.e. the Bernstein coefficients of A; de Casteljau's convex
// combinations keep that on every node. The rounding of b_i then follows the same
// weights: the shift to lo errs by gamma(2n) A_j, the scaling by w^j by gamma(n+1), the
// change of basis by gamma(n+2) beta_i, each de Casteljau level by 3u beta_i, so
//   |computed b_i - exact b_i| <= gamma(4n + 4 + 3 depth) beta_i          (*)
// on every node, with beta_i split along with b_i (the same arithmetic on non-negative
// numbers, relative error gamma(4n + 4 + 2 depth), covered by a factor 1 + 2 gamma). Why
// per coefficient and not one E = gamma(...) A(1) for the whole interval (sessions 2-9):
// A grows like |C|(|v|) along the interval, by (1.5)^n from one end of a ray's span to the
// other for roots spread over it, 2e5 at degree 30, so a uniform bound was set by the far
// end and left the near nodes (where a closest-hit query starts) undecided within a
// margin far above their rounding. Measured (session 10, roots_report, the uniform and the
// per-coefficient bound side by side, 400 problems a degree): whole rays of degree 30
// 21039 -> 8870 ns, 40 46326 -> 30642 ns, cells of degree 30-40 0.89-0.94x; degrees 5-20
// 0.89-1.15x over two runs (noise); errors, misses and noise-level answers the same to
// the digit, one miss fewer at degree 40. With it a deeper or longer subdivision still
// loses above degree 20 (depth 8-12, 64-200 nodes: 1.1-3.8x slower): the undecided nodes
// there are those where G is within its noise, which only the sweep's critical points
// settle. Up to degree 12 the nodes keep the uniform bound (see kPairNodeDegree: there
// the second lane cost more than it decided).
// The node ends va = lo + w u0 are rounded (the u ends are exact, see below), which moves
// a node by up to 2u (|v| <= 1) and G by |G'| 2u <= 2n u sum|C_j| |v|^j, less than the
// noise bound of G at v; so nodes are excluded only beyond (*) plus twice that noise bound.
#include "roots_detail.h"
#include "roots_scan.h"

#include <algorithm>
#include <bit>
#include <iterator>
#include <type_traits>

namespace algray::roots_detail {

// Split ratios are dyadic with 4 bits (k/16: 1/2, 7/16, 9/16, 3/8, 5/8, and for plain nodes
// 1/4-3/4 between the control polygon's crossings), so the node ends u0, u1 are exact for
// up to 53/4 (double) or 24/4 (float) levels and coincide with the de Casteljau
// parameters. (With splits up to 3/4 a node at the depth cap is up to (3/4)^5 = 0.24 of
// the span.)
// Depth cap: a node still undecided after 5 splits (1/32 of the span) goes to Yuksel's
// recursion, whose exclusion test usually settles so short a piece at a low derivative.
// Measured (roots_bench BM_GalleryRays and BM_FirstRoot, same session, ns per solve for
// depth 3 / 4 / 5 / 6 / 7 / 8 / 10 / 20): Chmutov-16's real rays 2297 / 1675 / 1335 /
// 1552 / 2080 / 2619 / 4176 / 5581, Sarti's 762 / 568 / 529 / 526 / 523 / 531 / 563 /
// 551, random whole rays of degree 16 943 / 803 / 763 / 794 / 878 / 884 / 862 / 1052 and
// degree 12 445 / 369 / 349 / 341 / 337 / 340 / 391 / 373; degrees 6-8 and the Barth
// sextic within noise. Deeper nodes cost an O(n^2) split each and, where g is small
// against its coefficients (Chebyshev-like ray polynomials), rarely decide.
template <class T>
inline constexpr int kSubdivideDepth = 5;
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

// 1 / C(n, j) for n <= kMaxDegree, rounded (the binomials of roots_detail.h are exact).
template <class T>
struct InverseBinomials {
  T v[(kMaxDegree + 1) * (kMaxDegree + 2) / 2] = {};
  constexpr InverseBinomials() {
    for (int n = 0, idx = 0; n <= kMaxDegree; ++n)
      for (int j = 0; j <= n; ++j) v[idx++] = static_cast<T>(1.0 / kBinomials.c[n][j]);
  }
  constexpr const T* row(int n) const { return v + n * (n + 1) / 2; }
};
template <class T>
inline constexpr InverseBinomials<T> kInverseBinomials{};

// A node's coefficients are of type E: up to degree kPairNodeDegree plain T, with one
// bound for the whole interval, E = gamma(4n + 4 + 3D) A(1) >= every beta_i (the rule of
// sessions 2-9, kept in SubdivideState::err); above, (b_i, e_i) with the bound (*) of each
// coefficient, a 2-lane vector (GCC/Clang vector extension), so that the bound goes
// through the shift, the change of basis and every split by the same instructions.
// Why both (session 10, roots_bench BM_GalleryRays and roots_report, side by side against
// the plain nodes everywhere): pairs at every degree cost the gallery's real rays of
// degree 10-12 6-10 % (Barth decic, Chmutov-12, Sarti: the splits are most of a solve
// there; the second lane as a second array made them 1.5x slower), with the bound per
// coefficient or not. With pairs above degree 12 only, those rays are as fast as before
// (0.97-1.03x, two runs), Chmutov-16's real rays 0.74-0.78x the time, random problems of
// degree 13-20 0.94-1.04x, whole rays of degree 30 0.22-0.28x and 40 0.34-0.36x, cells
// of degree 30-40 0.75-1.06x; errors and misses the same.
inline constexpr int kPairNodeDegree = 12;

template <class T>
struct BernsteinLanes {
  typedef T type __attribute__((vector_size(2 * sizeof(T))));
};
template <class T>
using BPair = typename BernsteinLanes<T>::type;

template <class T, class D>
struct NodeElement {
  using type = BPair<T>;  // run-time degrees are above 20
};
template <class T, int N>
struct NodeElement<T, Deg<N>> {
  using type = std::conditional_t<(N <= kPairNodeDegree), T, BPair<T>>;
};

// A coefficient's value, and its own bound (0 for plain T: the node's bound is uniform).
template <class T, class E>
T coeff(const E& x) {
  if constexpr (std::is_same_v<E, T>)
    return x;
  else
    return x[0];
}
template <class T, class E>
T bound(const E& x) {
  if constexpr (std::is_same_v<E, T>)
    return T(0);
  else
    return x[1];
}

// The n passes b_i += b_{i-1} (i from n down to k in pass k) of the change of basis to
// Bernstein form (toBernsteinWithBound, bernsteinFromZero). With a compile-time degree both
// loops unroll fully and b stays in registers (as loops of varying length,
// bernsteinFromZero was 16 % of a solve of Sarti's real rays in perf, unrolled 8 %);
// run-time degrees (above 20) keep the loops. The same additions in the same order either
// way.
template <class E, class D>
inline void pascalPasses(E* b, D deg) {
  const int n = deg;
  if constexpr (std::is_same_v<D, int>) {
    for (int k = 1; k <= n; ++k) {
      E cur = b[n];  // carried in a register (see splitBernstein)
      for (int i = n; i >= k; --i) {
        const E below = b[i - 1];
        b[i] = cur + below;
        cur = below;
      }
    }
  } else {
#pragma GCC unroll 24
    for (int k = 1; k <= n; ++k) {
      E cur = b[n];
#pragma GCC unroll 24
      for (int i = n; i >= k; --i) {
        const E below = b[i - 1];
        b[i] = cur + below;
        cur = below;
      }
    }
  }
}

// b_i = sum_{j <= i} C(i, j) / C(n, j) a_j w^j, the Bernstein coefficients on [0, 1] of
// sum_j a_j (w u)^j: a_j w^j / C(n, j) (a table of reciprocals), then the n Pascal passes
// (toBernsteinWithBound counts the roundings).
template <class T, class E, class D>
inline void scaledToBernstein(const E* a, D deg, T w, E* b) {
  const int n = deg;
  const T* inv = kInverseBinomials<T>.row(n);
  T p = 1;
  for (int j = 0; j <= n; ++j, p *= w) b[j] = (a[j] * p) * inv[j];
  pascalPasses(b, deg);
}

// Measured and not kept (session 10): the conversion by Horner's rule in the Bernstein
// basis (Farouki and Rajan 1988; roots_bernstein.cpp's), whose intermediates stay below
// sum |C_j| M^j, M = max(|lo|, |hi|), where the Taylor shift's reach sum |C_j| (|lo| +
// w)^j, up to 3^n more on spans around 0 as the re-centred rays' are: on the gallery's
// real rays 0.9-1.1x the time (noise), random problems of degree 16-30 5-21 % slower (its
// own bound is gamma(8n), twice the shift's, and the spans there start at lo >= 0).
// Bernstein coefficients of G on [g.lo, g.hi] into b. For plain T returns the uniform
// bound E; for pairs writes the bounds (*) for depth kSubdivideDepth into the second
// lane and returns 0.
template <class T, class E, class D>
T toBernsteinWithBound(const LocalPoly<T>& g, D deg, E* b) {
  constexpr bool kPairs = !std::is_same_v<E, T>;
  const int n = deg;
  const T lo = g.lo, w = g.hi - g.lo;
  // The shift of C by lo (with pairs: of (C, |C|) by (lo, |lo|)) and the scaling by w^j.
  E a[kMaxDegree + 1];
  E shift;
  if constexpr (kPairs) {
    for (int j = 0; j <= n; ++j) a[j] = E{g.c[j], std::abs(g.c[j])};
    shift = E{lo, std::abs(lo)};
  } else {
    copyCoeffs(g.c.data(), n + 1, a);
    shift = lo;
  }
  taylorShift(a, n, shift);
  // b_i = sum_{j <= i} C(i, j) a_j / C(n, j): divide by C(n, j) (a table of reciprocals,
  // two roundings), then n passes of b_i += b_{i-1} (i from n down to k in pass k) form
  // the binomial sums with additions only (Pascal's rule), each of which rounds relative
  // to a partial sum of |a_j| / C(n, j) C(i, j) <= beta_i.
  // The scaling by w^j and the division share one loop (as two, the second re-read what
  // the first had just stored, in pairs once vectorised: the stall of plugin/CMakeLists.txt).
  scaledToBernstein(a, deg, w, b);
  constexpr int kD = kSubdivideDepth<T>;
  if constexpr (kPairs) {
    // beta_i -> the bound (*) at the depth cap: gamma(4n + 6 + 3D), two more roundings
    // than (*) for the node tests' own subtractions, times 1 + 2 gamma(4n + 4 + 2D) for
    // the rounding of beta itself (computed above and in the splits from non-negative
    // terms).
    const T scale = gammaT<T>(4 * n + 6 + 3 * kD) * (1 + 2 * gammaT<T>(4 * n + 4 + 2 * kD));
    for (int j = 0; j <= n; ++j) b[j][1] *= scale;
    return T(0);
  } else {
    // A(1) = sum_j (shift of |C| by |lo|)_j w^j is |C| evaluated at |lo| + w: one Horner
    // pass instead of a second shift. Rounded up: |lo| + w by 2u, the Horner sum of
    // non-negative terms (at most 2n roundings each) by gamma(2n + 2).
    const T x = (std::abs(lo) + w) * (1 + 2 * kUnit<T>);
    T sumA = 0;
    for (int j = n; j >= 0; --j) sumA = sumA * x + std::abs(g.c[j]);
    sumA *= 1 + gammaT<T>(2 * n + 2);
    return gammaT<T>(4 * n + 4 + 3 * kD) * sumA;
  }
}

// Bernstein coefficients of G on the node between 0 and h (h of either sign; b_0 at the
// node's left end, as toBernsteinWithBound orders them), with the same bounds. Why (the
// start at 0 of solveTop): the shift by lo is what the bound (*) pays for. Shifted to lo
// and scaled by w, the coefficients' majorant is A(1) = |C|(|lo| + w), which on a span
// around 0 is |C| at up to 3 max(|lo|, |hi|): 3^n times G's own majorant there (5e5 at
// degree 12, the re-centred rays' spans being nearly symmetric). From 0 there is no shift
// (the shift by 0 is exact: every step adds 0 times a coefficient) and A(1) = |C|(|h|).
// For h < 0 the node is G(-|h| u'), u' = 1 - u: the odd coefficients negated (exact),
// scaled by |h|^j, converted, and read backwards. The derivation of (*) holds term for
// term with the shift's rounding absent (each remaining rounding relative to the same
// majorants), so the bounds and the uniform E returned are those of
// toBernsteinWithBound's formula at lo = 0, w = |h|.
template <class T, class E, class D>
T bernsteinFromZero(const LocalPoly<T>& g, D deg, T h, E* b) {
  constexpr bool kPairs = !std::is_same_v<E, T>;
  const int n = deg;
  const T w = std::abs(h);
  const bool left = h < 0;
  const T* inv = kInverseBinomials<T>.row(n);
  T p = 1;
  for (int j = 0; j <= n; ++j, p *= w) {
    const T c = left && (j & 1) ? -g.c[j] : g.c[j];
    if constexpr (kPairs)
      b[j] = (E{c, std::abs(c)} * p) * inv[j];
    else
      b[j] = (c * p) * inv[j];
  }
  pascalPasses(b, deg);
  if (left)
    for (int i = 0, j = n; i < j; ++i, --j) std::swap(b[i], b[j]);
  constexpr int kD = kSubdivideDepth<T>;
  if constexpr (kPairs) {
    const T scale = gammaT<T>(4 * n + 6 + 3 * kD) * (1 + 2 * gammaT<T>(4 * n + 4 + 2 * kD));
    for (int j = 0; j <= n; ++j) b[j][1] *= scale;
    return T(0);
  } else {
    const T x = w * (1 + 2 * kUnit<T>);
    T sumA = 0;
    for (int j = n; j >= 0; --j) sumA = sumA * x + std::abs(g.c[j]);
    sumA *= 1 + gammaT<T>(2 * n + 2);
    return gammaT<T>(4 * n + 4 + 3 * kD) * sumA;
  }
}

// de Casteljau at the dyadic ratio t: left into l, right into r (may alias b).
template <class T, class E, class D>
void splitBernstein(const E* b, D deg, T t, E* l, E* r) {
  const int n = deg;
  E x[kMaxDegree + 1];
  std::copy(b, b + n + 1, x);
  const T s = 1 - t;  // exact for the dyadic ratios used
  l[0] = x[0];
  r[n] = x[n];
  // The right neighbour is carried in a register: vectorised, the loop read x[i + 1]
  // with 16-byte loads straddling two earlier 16-byte stores, a store-forwarding stall
  // that was a third of a degree-12 solve (perf).
  int k = 1;
  if constexpr (std::is_same_v<D, int>) {
    // Run-time degrees (above 20): two levels per pass, level k's value at i kept in a
    // register for level k + 1 (the same operations in the same order, bit for bit the
    // one-level passes). Half the loads, stores and loop steps: the splits were 42-45 % of
    // a whole ray's instructions at degree 30-40. Measured (callgrind, Ir per firstRoot,
    // answers bit for bit the same on 12000 problems of degree 21-40): whole rays of
    // degree 40 96174 -> 84464, 30 45908 -> 40693; cells of degree 30-40 0.97-0.98x.
    for (; k < n; k += 2) {
      E nextX = x[n - k + 1];
      const E top = x[n - k];
      E nextY = s * top + t * nextX;  // level k at n - k
      r[n - k] = nextY;
      nextX = top;
      for (int i = n - k - 1; i >= 0; --i) {
        const E cur = x[i];
        const E y = s * cur + t * nextX;  // level k at i
        x[i] = s * y + t * nextY;         // level k + 1 at i
        nextX = cur;
        nextY = y;
      }
      l[k] = nextY;
      l[k + 1] = x[0];
      r[n - k - 1] = x[n - k - 1];
    }
  }
  if constexpr (std::is_same_v<D, int>) {
    for (; k <= n; ++k) {
      E next = x[n - k + 1];
      for (int i = n - k; i >= 0; --i) {
        const E cur = x[i];
        x[i] = s * cur + t * next;
        next = cur;
      }
      l[k] = x[0];
      r[n - k] = x[n - k];
    }
  } else {
    // Compile-time degrees: unrolled in full, x in registers, the same operations in the
    // same order. As loops of varying length (entered through a jump per level) the
    // gallery's real rays took longer: roots_bench BM_GalleryRays, medians of 3
    // interleaved runs, ns per solve, loops -> unrolled: Barth decic 525 -> 472,
    // Chmutov-12 629 -> 602, Chmutov-16 1143 -> 1002, Endrass octic 372 -> 316, Sarti
    // 635 -> 622, Barth sextic 187 -> 187.
#pragma GCC unroll 24
    for (; k <= n; ++k) {
      E next = x[n - k + 1];
#pragma GCC unroll 24
      for (int i = n - k; i >= 0; --i) {
        const E cur = x[i];
        x[i] = s * cur + t * next;
        next = cur;
      }
      l[k] = x[0];
      r[n - k] = x[n - k];
    }
  }
}

// The node tests below run over all coefficients without early exits and decide with
// one branch: on random ray polynomials the position of the first failing coefficient is
// unpredictable, and the loops' exits mispredicted more than the O(n) work they saved
// (session 8, whole-ray problems of roots_bench's shape side by side, ns per solve:
// rays with a root 10-17 % faster at degrees 6-12, near misses 6-15 %, all problems
// 4-13 %; rays without a root 0-8 % slower, cells within +-3 %). The coefficients are
// finite (the frame's max |C_j| is in [1, 2)), so min/max lose no NaN. Measured and not
// kept: boolean accumulators instead of min/max (slower than the exits), two min/max
// chains (no gain), the polygon's first crossing without an exit (no gain), a convexity
// test that settles a valley by Newton on G' (near misses 5-15 % faster, rays with a
// root 4-12 % slower), the midpoint split as sums scaled once (no gain: not the
// bottleneck).

// Every test below compares computed values with a computed margin; a difference of
// two computed numbers rounds to a value of the same sign, so "x - m > 0" decides x > m
// exactly, and the margins carry the bound (*) with the roundings of their own sums.
// m is the noise margin (twice G's noise bound on the node), inflated by 4u so that a
// rounded b_i - e_i beyond it puts the exact one beyond the noise bound.

// Whether every b_i is beyond its bound plus m on one side.
template <class T, class E, class D>
bool oneSign(const E* b, D deg, T m) {
  const int n = deg;
  if constexpr (std::is_same_v<E, T>) {  // the uniform bound is in m
    T lo = b[0], hi = b[0];
    for (int i = 1; i <= n; ++i) {
      lo = std::min(lo, b[i]);
      hi = std::max(hi, b[i]);
    }
    return (lo > m) | (hi < -m);
  }
  T lo = coeff<T>(b[0]) - bound<T>(b[0]), hi = coeff<T>(b[0]) + bound<T>(b[0]);
  for (int i = 1; i <= n; ++i) {
    lo = std::min(lo, coeff<T>(b[i]) - bound<T>(b[i]));
    hi = std::max(hi, coeff<T>(b[i]) + bound<T>(b[i]));
  }
  return (lo > m) | (hi < -m);
}

// Descartes' rule of signs in the Bernstein basis (Lane and Riesenfeld 1981): the number
// of roots of G in the open node is at most the number of sign variations of b and of
// the same parity. With every |b_i| beyond its bound plus m the signs are those of the
// exact coefficients, so one variation means exactly one root, a simple one, and opposite
// signs at the node's ends: a bracket for the safeguarded Newton, without the
// monotonicity the derivative's test asks for (which oscillating polynomials,
// Chebyshev-like ones as on Chmutov's surfaces, reach only after many more splits).
template <class T, class E, class D>
bool oneVariation(const E* b, D deg, T m) {
  const int n = deg;
  int changes = 0;
  if constexpr (std::is_same_v<E, T>) {  // the uniform bound is in m
    T small = std::abs(b[0]);
    for (int i = 1; i <= n; ++i) {
      small = std::min(small, std::abs(b[i]));
      changes += signBit(b[i]) != signBit(b[i - 1]);
    }
    return (small > m) & (changes == 1);
  }
  T small = std::abs(coeff<T>(b[0])) - bound<T>(b[0]);
  for (int i = 1; i <= n; ++i) {
    small = std::min(small, std::abs(coeff<T>(b[i])) - bound<T>(b[i]));
    changes += signBit(coeff<T>(b[i])) != signBit(coeff<T>(b[i - 1]));
  }
  return (small > m) & (changes == 1);
}

// Whether the differences b_{i+1} - b_i (G' up to the factor n / w) have one sign beyond
// their bounds: e_i + e_{i+1} (x (1 + 4u) for the roundings of the sums), or 2E with the
// uniform bound E.
template <class T, class E, class D>
bool monotone(const E* b, D deg, T uniform) {
  const int n = deg;
  constexpr T k = 1 + 4 * kUnit<T>;
  if constexpr (std::is_same_v<E, T>) {
    const T m = 2 * uniform * k;
    T lo = b[1] - b[0], hi = lo;
    for (int i = 1; i < n; ++i) {
      const T di = b[i + 1] - b[i];
      lo = std::min(lo, di);
      hi = std::max(hi, di);
    }
    return (lo > m) | (hi < -m);
  }
  T lo = std::numeric_limits<T>::max(), hi = -lo;
  for (int i = 0; i < n; ++i) {
    const T di = coeff<T>(b[i + 1]) - coeff<T>(b[i]);
    const T ei = (bound<T>(b[i + 1]) + bound<T>(b[i])) * k;
    lo = std::min(lo, di - ei);
    hi = std::max(hi, di + ei);
  }
  return (lo > 0) | (hi < 0);
}

// Whether no b_i is beyond its bound plus m (none has a certain sign): then |G| <=
// max(|b_i| + e_i) <= max(2 e_i) + m, a few times G's noise bound, on the whole node.
template <class T, class E, class D>
bool withinBounds(const E* b, D deg, T m) {
  const int n = deg;
  T big = std::abs(coeff<T>(b[0])) - bound<T>(b[0]);
  for (int i = 1; i <= n; ++i) big = std::max(big, std::abs(coeff<T>(b[i])) - bound<T>(b[i]));
  return !(big > m);
}

// The noise-node rule's proved bound: a node it drops has |G| <= kNoiseNodeFactor times
// G's noise bound everywhere (provedWithinNoise). Why 4: the Bernstein coefficients' own
// rounding bounds (*) are about twice the noise bound (gamma(4n + 21) against the Horner
// bound's gamma(2n + 1) on the same majorant), so below ~3 no node at noise level is
// provable; at 4 the proof holds on 2153 of the 2162 nodes the sampled points drop in
// 3000 random whole-span tangent problems of degree 21-40 (session 20; 716 at 1, 963 at 2).
inline constexpr int kNoiseNodeFactor = 4;

// Whether |G(v)| <= kNoiseNodeFactor N(|v|) on the whole node is proved, N(x) = sum_j
// noise_j x^j the noise bound of LocalPoly. N(|v|) is a polynomial in v on a node that
// does not contain 0, so G -+ c N have Bernstein coefficients b_i -+ c nu_i there, nu_i
// those of N; if |b_i| + e_i <= c nu_i for every i, both have one sign on the node (the
// convex hull property, as oneSign) and |G| <= c N. nu is computed from non-negative
// numbers only (a Taylor shift of noise[] by x0 >= 0, the scaling and the Pascal passes),
// so each nu_i errs by at most gamma(5n + 4) nu_i; the node's computed ends lie within
// delta = 2u (|lo| + w) of the exact ones, and nu is taken on [x0 - 2 delta, x1 - 2 delta]
// (the computed |v| less delta is at most the exact |v| at every u, one more delta covers
// the subtraction's rounding; N grows with |v|). A node within 2 delta of 0 takes the
// constant N(0) = noise_0, a lower bound of N(|v|) everywhere.
template <class T, class E, class D>
bool provedWithinNoise(const LocalPoly<T>& g, D deg, const E* b, T va, T vb, T delta) {
  const int n = deg;
  const bool negative = vb <= 0;
  const T x0 = negative ? -vb : va, x1 = negative ? -va : vb;
  T nu[kMaxDegree + 1];
  if (!(x0 > 2 * delta)) {  // also a node around 0
    for (int i = 0; i <= n; ++i) nu[i] = g.noise[0];
  } else {
    const T s = x0 - 2 * delta, w = x1 - x0;
    copyCoeffs(g.noise.data(), n + 1, nu);
    taylorShift(nu, n, s);
    scaledToBernstein(nu, deg, w, nu);
    if (negative)
      for (int i = 0, j = n; i < j; ++i, --j) std::swap(nu[i], nu[j]);
  }
  const T keep = kNoiseNodeFactor * (1 - gammaT<T>(6 * n + 12));
  bool within = true;
  for (int i = 0; i <= n; ++i)
    within &= (std::abs(coeff<T>(b[i])) + bound<T>(b[i])) * (1 + 4 * kUnit<T>) <= keep * nu[i];
  return within;
}

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
