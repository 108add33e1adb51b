#pragma once
// The Bernstein nodes of the subdivision (roots_subdivide.h): the change of basis with a
// rounding bound on every coefficient, de Casteljau's split, and the tests that decide a
// node (no root, monotone, exactly one simple root, within noise).
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

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

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

// The bounds (*) of freshly converted coefficients b, at the depth cap, for a node whose
// terms' majorant is |C| at `reach` (|lo| + w from lo, |h| from 0). For pairs: beta_i (the
// second lane) -> gamma(4n + 6 + 3D) beta_i, two more roundings than (*) for the node
// tests' own subtractions, times 1 + 2 gamma(4n + 4 + 2D) for the rounding of beta itself
// (computed in the conversion and the splits from non-negative terms); returns 0. For
// plain T: the uniform bound E = gamma(4n + 4 + 3D) A(1), where A(1) = sum_j (shift of |C|
// by |lo|)_j w^j is |C| evaluated at |lo| + w: one Horner pass instead of a second shift,
// rounded up (reach by 2u, the Horner sum of non-negative terms, at most 2n roundings
// each, by gamma(2n + 2)).
template <class T, class E, class D>
T boundsAtDepthCap(const LocalPoly<T>& g, D deg, E* b, T reach) {
  const int n = deg;
  constexpr int kD = kSubdivideDepth<T>;
  if constexpr (!std::is_same_v<E, T>) {
    const T scale = gammaT<T>(4 * n + 6 + 3 * kD) * (1 + 2 * gammaT<T>(4 * n + 4 + 2 * kD));
    for (int j = 0; j <= n; ++j) b[j][1] *= scale;
    return T(0);
  } else {
    const T x = reach * (1 + 2 * kUnit<T>);
    T sumA = 0;
    for (int j = n; j >= 0; --j) sumA = sumA * x + std::abs(g.c[j]);
    sumA *= 1 + gammaT<T>(2 * n + 2);
    return gammaT<T>(4 * n + 4 + 3 * kD) * sumA;
  }
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
  return boundsAtDepthCap(g, deg, b, std::abs(lo) + w);
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
  return boundsAtDepthCap(g, deg, b, w);
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

}  // namespace algray::roots_detail
