#pragma once
// Subdivision before Yuksel's recursion (roots_yuksel.cpp), for long intervals.
//
// Why: on a whole ray's span the recursion finds every critical point of every derivative
// over all of it, O(n^3) Newton work, although a closest-hit query needs only the pieces
// up to the first root, and a missing ray none. Bernstein coefficients answer the two
// questions that let most of the interval go without any root finding, in O(n) each:
//  * exclusion: on a node [va, vb], G(v) is a convex combination of its Bernstein
//    coefficients b_i, so if all of them exceed the error bound E of their computation
//    plus the noise bound of G on the node (roots_detail.h), G has no root and no
//    tangent candidate there (the same verdict the sweep would reach);
//  * monotonicity: G' has the Bernstein coefficients n (b_{i+1} - b_i); if all
//    differences have one sign beyond 2E the node is one monotone piece, and the sweep of
//    roots_scan.h runs on it with no critical point (Newton on the power form G itself);
//  * one root: if every b_i clears E plus the noise bound and they change sign exactly once,
//    the node holds exactly one simple root (Descartes' rule, oneVariation below), and its
//    ends b_0 = G(va), b_n = G(vb) bracket it for the safeguarded Newton of the sweep.
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
// Error bound E (absolute, uniform over the nodes; u = unit roundoff, n = degree):
// the Taylor shift to lo errs by at most gamma(2n) times the shift of |C| by |lo|, the
// scaling by w^j by gamma(n+1) relative, the change of basis (weights in [0, 1]) by
// gamma(n+2) sum|a_j| plus the propagated errors; each de Casteljau level, a convex
// combination with dyadic weights, adds at most 3u max|b| <= 3u A. With A = sum_j of the
// scaled shift of |C|: E = gamma(4n + 4 + 3 depth) A. The node ends va = lo + w u0 are
// rounded (the u ends are exact, see below), which moves a node by up to 2u (|v| <= 1) and
// G by |G'| 2u <= 2n u sum|C_j| |v|^j, less than the noise bound of G at v; so nodes are
// excluded only beyond E plus twice that noise bound.
#include "roots_detail.h"
#include "roots_scan.h"

#include <algorithm>

namespace algray::roots_detail {

// Split ratios are dyadic with 4 bits (1/2, 7/16, 9/16, 3/8, 5/8), so the node ends u0, u1
// are exact for up to 53/4 (double) or 24/4 (float) levels and coincide with the de
// Casteljau parameters.
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
// to hi, goes to the recursion in one piece: a polynomial whose Bernstein bound E is
// large against its values (high degree, much cancellation, |g| small along much of the
// span as on Chmutov's surfaces) would otherwise split to the full depth and then run the
// recursion on every leaf (measured: Chmutov-16 rendered 2x slower than with no
// subdivision at all before this cap took the rest in one piece).
inline constexpr int kSubdivideNodes = 24;

template <class T>
struct SubdivideState {
  LocalPoly<T>& g;  // working copy: lo, hi are moved to each node
  T lo, w;          // the root node: v = lo + w u
  T err;            // E above
  Query q;
  T tol;
  bool closedLo;    // the root node's lo is closed (LocalPoly::closedLo); inner ends are not
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

// Bernstein coefficients of G on [g.lo, g.hi] into b; returns E for depth kSubdivideDepth.
template <class T, class D>
T toBernsteinWithBound(const LocalPoly<T>& g, D deg, T* b) {
  const int n = deg;
  const T lo = g.lo, w = g.hi - g.lo;
  T a[kMaxDegree + 1];
  copyCoeffs(g.c.data(), n + 1, a);
  for (int k = 0; k < n; ++k)
    for (int i = n - 1; i >= k; --i) a[i] += lo * a[i + 1];
  T p = 1;
  for (int j = 0; j <= n; ++j, p *= w) a[j] *= p;
  // A = sum_j (shift of |C| by |lo|)_j w^j is |C| evaluated at |lo| + w: one Horner pass
  // instead of a second shift. Rounded up: |lo| + w by 2u, the Horner sum of non-negative
  // terms (at most 2n roundings each) by gamma(2n + 2).
  const T x = (std::abs(lo) + w) * (1 + 2 * kUnit<T>);
  T sumA = 0;
  for (int j = n; j >= 0; --j) sumA = sumA * x + std::abs(g.c[j]);
  sumA *= 1 + gammaT<T>(2 * n + 2);
  // b_i = sum_{j <= i} C(i, j) a_j / C(n, j): divide by C(n, j) (a table of reciprocals,
  // two roundings), then n passes of b_i += b_{i-1} (i from n down to k in pass k) form
  // the binomial sums with additions only (Pascal's rule), each of which rounds relative
  // to a partial sum of |a_j| / C(n, j) C(i, j) <= sum_j |a_j|.
  const T* inv = kInverseBinomials<T>.row(n);
  for (int j = 0; j <= n; ++j) b[j] = a[j] * inv[j];
  for (int k = 1; k <= n; ++k) {
    T cur = b[n];  // carried in a register (see splitBernstein)
    for (int i = n; i >= k; --i) {
      const T below = b[i - 1];
      b[i] = cur + below;
      cur = below;
    }
  }
  return gammaT<T>(4 * n + 4 + 3 * kSubdivideDepth<T>) * sumA;
}

// de Casteljau at the dyadic ratio t: left into l, right into r (may alias b).
template <class T, class D>
void splitBernstein(const T* b, D deg, T t, T* l, T* r) {
  const int n = deg;
  T x[kMaxDegree + 1];
  std::copy(b, b + n + 1, x);
  const T s = 1 - t;  // exact for the dyadic ratios used
  l[0] = x[0];
  r[n] = x[n];
  // The right neighbour is carried in a register: vectorised, the loop read x[i + 1]
  // with 16-byte loads straddling two earlier 16-byte stores, a store-forwarding stall
  // that was a third of a degree-12 solve (perf).
  for (int k = 1; k <= n; ++k) {
    T next = x[n - k + 1];
    for (int i = n - k; i >= 0; --i) {
      const T cur = x[i];
      x[i] = s * cur + t * next;
      next = cur;
    }
    l[k] = x[0];
    r[n - k] = x[n - k];
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

// Whether every b_i is beyond m on one side.
template <class T, class D>
bool oneSign(const T* b, D deg, T m) {
  const int n = deg;
  T lo = b[0], hi = b[0];
  for (int i = 1; i <= n; ++i) {
    lo = std::min(lo, b[i]);
    hi = std::max(hi, b[i]);
  }
  return (lo > m) | (hi < -m);
}

// Descartes' rule of signs in the Bernstein basis (Lane and Riesenfeld 1981): the number
// of roots of G in the open node is at most the number of sign variations of b and of
// the same parity. With every |b_i| beyond m the signs are those of the exact
// coefficients, so one variation means exactly one root, a simple one, and opposite signs
// at the node's ends: a bracket for the safeguarded Newton, without the monotonicity the
// derivative's test asks for (which oscillating polynomials, Chebyshev-like ones as on
// Chmutov's surfaces, reach only after many more splits).
template <class T, class D>
bool oneVariation(const T* b, D deg, T m) {
  const int n = deg;
  int changes = 0;
  T small = std::abs(b[0]);
  for (int i = 1; i <= n; ++i) {
    small = std::min(small, std::abs(b[i]));
    changes += signBit(b[i]) != signBit(b[i - 1]);
  }
  return (small > m) & (changes == 1);
}

template <class T, class D>
bool monotone(const T* b, D deg, T e) {
  const int n = deg;
  const T m = 2 * e / (1 - 2 * kUnit<T>);
  T lo = b[1] - b[0], hi = lo;
  for (int i = 1; i < n; ++i) {
    const T di = b[i + 1] - b[i];
    lo = std::min(lo, di);
    hi = std::max(hi, di);
  }
  return (lo > m) | (hi < -m);
}

// Roots of G on the node u in [u0, u1] with Bernstein coefficients b; `direct(g)` runs
// Yuksel's recursion on [g.lo, g.hi].
template <class T, class D, class Direct>
int subdivide(SubdivideState<T>& st, D deg, const T* b, T u0, T u1, int depth, Direct&& direct,
              LocalRoot<T>* out, int maxOut) {
  LocalPoly<T>& g = st.g;
  const T va = st.lo + st.w * u0, vb = u1 == 1 ? g.hi : st.lo + st.w * u1;
  if (st.exhausted) return 0;
  if (++st.nodes > kSubdivideNodes) {
    st.exhausted = true;
    st.resumeAt = va;
    return 0;
  }
  const T noise = hornerAbs(g.noise.data(), deg, std::max(std::abs(va), std::abs(vb)));
  if (oneSign(b, deg, st.err + 2 * noise)) return 0;
  const T saveLo = g.lo, saveHi = g.hi;
  g.lo = va;
  g.hi = vb;
  // A node's lo is a split point (its root, if any, was the left neighbour's to report
  // at its hi) except the first node's, which is the interval's own.
  g.closedLo = st.closedLo && u0 == 0;
  int k = 0;
  const bool small = vb - va <= std::max(st.tol, 64 * kUnit<T> * std::max(std::abs(va), std::abs(vb)));
  const bool single = oneVariation(b, deg, st.err + 2 * noise);
  if (single || monotone(b, deg, st.err)) {
    // Start where the control polygon crosses zero (Bezier clipping's estimate, Sederberg
    // and Nishita 1990): inside a one-variation node it is closer to the root than the
    // secant through the node's ends.
    auto piece = [&](T a, T c, T fa, T fc) {
      const int n = deg;
      for (int i = 0; i < n; ++i)
        if (signBit(b[i]) != signBit(b[i + 1])) {
          const T u = (T(i) + b[i] / (b[i] - b[i + 1])) / T(n);
          const T x = va + (vb - va) * u;
          if (x > a && x < c) return newtonFrom(g.c.data(), g.noise.data(), deg, a, c, fa, x, st.tol);
          break;
        }
      return newtonInBracket(g.c.data(), g.noise.data(), deg, a, c, fa, fc, st.tol);
    };
    if (single) {
      // The sweep's verdict without its evaluations: b_0 = G(va) and b_n = G(vb) within E
      // are beyond E plus twice the noise bound with opposite signs, so neither end is
      // within noise and the node holds one simple root (the sweep would evaluate both
      // ends to find just that; 2 of a root's ~9 polynomial passes: rays with a root 2-9 %
      // faster, session 8).
      const T fb = b[static_cast<int>(deg)];
      out[0] = LocalRoot<T>{st.q == Query::Any ? va + (vb - va) / 2 : piece(va, vb, b[0], fb), false};
      k = 1;
    } else {
      k = scanPieces(g, deg, static_cast<const T*>(nullptr), 0, st.q, piece, out, maxOut);
    }
  } else if (depth >= kSubdivideDepth<T> || small) {
    k = direct(g, out, maxOut);
  } else {
    // Split at the middle unless G is within its noise there (see above). The halves'
    // shared coefficient is G at the middle within E, so a value beyond E plus twice
    // the noise bound settles the common case without evaluating G.
    T t = T(0.5), mid = u0 + (u1 - u0) / 2;
    T l[kMaxDegree + 1], r[kMaxDegree + 1];
    splitBernstein(b, deg, t, l, r);
    if (!(std::abs(r[0]) > st.err + 2 * noise)) {
      for (const T f : {T(0.5), T(0.4375), T(0.5625), T(0.375), T(0.625)}) {
        const T um = u0 + (u1 - u0) * f, vm = st.lo + st.w * um;
        if (std::abs(horner(g.c.data(), deg, vm)) > hornerAbs(g.noise.data(), deg, vm)) {
          t = f;
          mid = um;
          break;
        }
      }
      if (t != T(0.5)) splitBernstein(b, deg, t, l, r);
    }
    g.lo = saveLo;
    g.hi = saveHi;
    k = subdivide(st, deg, l, u0, mid, depth + 1, direct, out, maxOut);
    if ((k > 0 && (st.q != Query::All || k >= maxOut)) || st.exhausted) return k;
    return k + subdivide(st, deg, r, mid, u1, depth + 1, direct, out + k, maxOut - k);
  }
  g.lo = saveLo;
  g.hi = saveHi;
  return k;
}

}  // namespace algray::roots_detail
