// Yuksel's polynomial solver (C. Yuksel, "High-Performance Polynomial Solver with Error
// Bounds", HPG 2022): the roots of the derivative split the interval into monotone pieces,
// and the derivative's roots come recursively from its own derivative, down to a
// quadratic solved in closed form. Inside a monotone piece with a sign change a
// safeguarded Newton iteration converges to the unique root (roots_detail.h).
//
// Degrees up to kTemplateDegree are instantiated with the degree as a template
// parameter (the whole derivative chain then has fixed-size arrays and unrolled Horner
// loops); higher degrees run the same code with a run-time degree. No heap allocation.
#include "roots_detail.h"
#include "roots_scan.h"
#include "roots_subdivide.h"

#include <algorithm>
#include <type_traits>
#include <utility>

namespace algray::roots_detail {
namespace {

// Up to 20 (was 12): the degree-16 surfaces' ray polynomials then run unrolled
// subdivision and Horner loops too (roots_bench, ns, limit 12 -> 20: random whole rays of
// degree 16 769 -> 502, 18 1094 -> 983, 20 1181 -> 1007; Chmutov-16's real rays 1339 ->
// 1017; degree 12 and below unchanged; this file compiles in 9.6 s instead of 5.1).
constexpr int kTemplateDegree = 20;

// Sign-change roots of p (degree deg) in (lo, hi), given the sorted roots of p' there.
// Used below the top level, where a tangent root of a derivative does not matter: G is
// monotone through a critical point at which G' only touches zero.
// ends (optional): p(lo) and p(hi), computed by the caller (derivRootsDyn evaluates the
// whole chain's ends at once).
template <class T, class D>
int pieceRoots(const T* p, D deg, T lo, T hi, const T* crit, int nCrit, T tol, T* out,
               const T* ends = nullptr) {
  const int n = deg;
  T noise[kMaxDegree + 1];
  const T gam = gammaT<T>(2 * n + 1);
  // Above kTemplateDegree the noise bounds are formed at the first sign change only (most
  // levels of a long chain have none); below, up front as before (lazily there, together
  // with the nodes' shared noise bounds, degree 6-8 whole rays were 2-3 % slower).
  bool haveNoise = n <= kTemplateDegree;
  if (haveNoise)
    for (int j = 0; j <= n; ++j) noise[j] = gam * std::abs(p[j]);
  int k = 0;
  T xa = lo, fa = ends ? ends[0] : horner(p, deg, xa);
  for (int i = 0; i <= nCrit; ++i) {
    const bool interior = i < nCrit;
    const T xb = interior ? crit[i] : hi;
    const T fb = interior || !ends ? horner(p, deg, xb) : ends[1];
    if (fb == 0) {
      if (interior) out[k++] = xb;
    } else if (fa != 0 && signBit(fa) != signBit(fb)) {
      if (!haveNoise) {
        for (int j = 0; j <= n; ++j) noise[j] = gam * std::abs(p[j]);
        haveNoise = true;
      }
      out[k++] = newtonInBracket(p, noise, deg, xa, xb, fa, fb, tol);
    }
    xa = xb;
    fa = fb;
  }
  return k;
}

template <class T>
int linearRoot(const T* p, T lo, T hi, T* out) {
  if (p[1] == 0) return 0;
  const T r = -p[0] / p[1];
  if (!(r > lo && r < hi)) return 0;
  out[0] = r;
  return 1;
}

// All sign-change roots in (lo, hi) of a polynomial of compile-time degree N. A
// polynomial of degree <= mono is known to be monotone on (lo, hi) (its derivative is
// root-free there, see rootFreeOrder), so its derivative is not searched.
template <class T, int N>
int derivRoots(const T* p, T lo, T hi, T tol, T* out, int mono) {
  if (N <= mono)
    return pieceRoots(p, Deg<N>{}, lo, hi, static_cast<const T*>(nullptr), 0, tol, out);
  if constexpr (N == 1) {
    return linearRoot(p, lo, hi, out);
  } else if constexpr (N == 2) {
    if (p[2] == 0) return linearRoot(p, lo, hi, out);
    T r0, r1;
    if (quadraticRoots(p[2], p[1], p[0], r0, r1) == 0) return 0;
    int k = 0;
    if (r0 > lo && r0 < hi) out[k++] = r0;
    if (r1 > lo && r1 < hi && r1 != r0) out[k++] = r1;
    return k;
  } else {
    T d[N];
    derivative(p, Deg<N>{}, d);
    T crit[N - 1];
    const int k = derivRoots<T, N - 1>(d, lo, hi, tol, crit, mono);
    return pieceRoots(p, Deg<N>{}, lo, hi, crit, k, tol, out);
  }
}

template <class T, int... Ns>
int derivRootsSmall(int n, const T* p, T lo, T hi, T tol, T* out, int mono,
                    std::integer_sequence<int, Ns...>) {
  int k = 0;
  static_cast<void>((
      (n == Ns + 1 ? (k = derivRoots<T, Ns + 1>(p, lo, hi, tol, out, mono), true) : false) || ...));
  return k;
}

// Same with a run-time degree (1 <= n <= kMaxDegree).
// Above kTemplateDegree the levels are not a recursion but one pass: every derivative of
// the chain down to max(mono, kTemplateDegree + 1) first, then all their values at lo and
// hi at once, then the levels from the lowest up. Why: most levels of a degree-30-40
// chain have no critical point or one (perf and counters, whole rays of degree 40: 24
// levels a solve, 56 evaluations, 0.3 critical points a level), so a level was its two
// end evaluations, two serial Horner chains of ~35 multiply-adds, and the next level's
// could not start before this level's Newton and branches were done. The ends of all
// levels are independent of the critical points: evaluated together (two levels at a
// time, lo and hi as one 2-lane vector, coefficients above a level's degree zero) they
// run at the core's throughput instead of one chain's latency. Bit for bit the old
// values: a level's Horner pass starts with zeros, 0 * x + 0 = +-0 and then
// +-0 * x + c_m = c_m exactly (c_m, the leading coefficient, is not 0: the frame drops a
// zero top coefficient, and the derivative's leading term is c_n times a non-zero factor).
template <class T>
int derivRootsDyn(const T* p, int n, T lo, T hi, T tol, T* out, int mono) {
  if (n <= kTemplateDegree)
    return derivRootsSmall(n, p, lo, hi, tol, out, mono,
                           std::make_integer_sequence<int, kTemplateDegree>{});
  if (n <= mono) return pieceRoots(p, n, lo, hi, static_cast<const T*>(nullptr), 0, tol, out);
  // Levels j = 0..L-1 of degree n - j; the lowest is mono (monotone, no critical point)
  // or kTemplateDegree + 1 (its critical points from the compiled chain below it).
  const int mLow = std::max(mono, kTemplateDegree + 1), L = n - mLow + 1;
  T chain[kMaxDegree - kTemplateDegree][kMaxDegree + 1];
  copyCoeffs(p, n + 1, chain[0]);
  for (int j = 1; j < L; ++j) {
    derivative(chain[j - 1], n - j + 1, chain[j]);
    chain[j][n - j + 1] = 0;
    for (int i = n - j + 2; i <= n; ++i) chain[j][i] = chain[j - 1][i];  // zeros
  }
  T ends[kMaxDegree - kTemplateDegree][2];
  {
    typedef T V __attribute__((vector_size(2 * sizeof(T))));
    const V x = {lo, hi};
    int j = 0;
    for (; j + 1 < L; j += 2) {
      const T* a = chain[j];
      const T* b = chain[j + 1];
      V fa = {a[n], a[n]}, fb = {b[n], b[n]};
      for (int i = n - 1; i >= 0; --i) {
        fa = fa * x + V{a[i], a[i]};
        fb = fb * x + V{b[i], b[i]};
      }
      ends[j][0] = fa[0];
      ends[j][1] = fa[1];
      ends[j + 1][0] = fb[0];
      ends[j + 1][1] = fb[1];
    }
    if (j < L) {
      ends[j][0] = horner(chain[j], n - j, lo);
      ends[j][1] = horner(chain[j], n - j, hi);
    }
  }
  T critA[kMaxDegree], critB[kMaxDegree];
  T* crit = critA;
  T* next = critB;
  int k = 0;
  if (mLow > mono) {
    T d[kMaxDegree] = {};  // initialized only to silence GCC's -Wmaybe-uninitialized at -O3
    derivative(chain[L - 1], mLow, d);
    k = derivRootsDyn(d, mLow - 1, lo, hi, tol, crit, mono);
  }
  for (int j = L - 1; j >= 0; --j) {
    T* dst = j == 0 ? out : next;
    const int kj = pieceRoots(chain[j], n - j, lo, hi,
                              k > 0 ? crit : static_cast<const T*>(nullptr), k, tol, dst, ends[j]);
    std::swap(crit, next);
    k = kj;
  }
  return k;
}

// Exclusion test (a cheap, sound shortcut before Yuksel's recursion). With the Taylor
// coefficients t_j of G at the midpoint m of (lo, hi) and the radius r, the k-th
// derivative satisfies, for |v - m| <= r,
//   |G^(k)(v)| / k! >= |t_k| - sum_{j>=1} C(j+k, k) |t_{j+k}| r^j,
// so it has no zero on the interval when the right side is positive (with the rounding
// of the shift, gamma(2n+2) times the same sums over the shift of |C|, subtracted).
// Returns the lowest order k >= 1 whose derivative is root-free, so that the derivative
// of order k - 1 is monotone and the recursion can start there (k = 1: G itself is
// monotone, no critical point at all); 0 when G is root-free with a margin of its noise
// bound (no root, no tangent candidate). Costs two Taylor shifts, O(n^2), against the
// O(n^2) per derivative level it saves; short intervals (a ray's span inside one cell)
// typically cut the recursion to a few levels.
template <class T, class D>
int rootFreeOrder(const LocalPoly<T>& g, D deg) {
  const int n = deg;
  T t[kMaxDegree + 1], ta[kMaxDegree + 1];
  const T r = midpointTaylor(g, deg, t, ta);
  const T gShift = gammaT<T>(2 * n + 2);
  {
    // k = 0, the common verdict on a cell-sized span (no root), with its binomials of 1.
    // The sums over j >= 1 of |t_j| r^j and ta_j r^j by Estrin's scheme: pairs
    // (a_j + a_{j+1} r), Horner in r^2 over them, times r. Every t_j is ready only when the
    // shift ends, so Horner in r (a serial chain of n multiply-adds) ran after it; the pairs
    // halve that chain. The terms are non-negative, so the sums' relative rounding is at
    // most gamma(3n/2 + 3) (a term meets at most n/2 multiplications by the rounded r^2, as
    // many additions, its pair's two roundings and the last product), no more than the
    // gamma(2n) of Horner's order; the test's margins are unchanged. Measured (session 23,
    // cells of roots_bench's shape, 4000 problems, interleaved runs, ns per solve): degree
    // 9 109 -> 104, 12 139 -> 136, 6 60 -> 60; the same answers bit for bit (first, any and
    // all roots of 170000 problems, degrees 2-40).
    const T r2 = r * r;
    T rest = 0, err = 0;
    int j = n;
    if (n % 2 == 1) {  // an odd number of terms: the top one starts the chain alone
      rest = std::abs(t[n]);
      err = ta[n];
      j = n - 1;
    }
    for (; j >= 2; j -= 2) {
      rest = rest * r2 + (std::abs(t[j - 1]) + std::abs(t[j]) * r);
      err = err * r2 + (ta[j - 1] + ta[j] * r);
    }
    rest *= r;
    err *= r;
    err = gShift * (err + ta[0]) +
          hornerAbs(g.noise.data(), deg, std::max(std::abs(g.lo), std::abs(g.hi)));
    if (std::abs(t[0]) > rest + err) return 0;
  }
  int k = 1;
  if constexpr (std::is_same_v<T, double>) {
    // Four orders k..k+3 at a time, as two 2-lane vectors (GCC/Clang vector extension).
    // Each order's sums are a serial chain of n - k multiply-adds, and one order after
    // another left the core waiting on that latency (perf, whole rays of degree 40: the
    // test was a fifth of the solve, its orders 12-23 on most undecided leaves); the
    // lanes do the same operations in the same order, so every sum is bit for bit the
    // old one. An order's chain runs while i > k: all four while i > k + 3, then the
    // finished lanes step with binomial 0 and radius 1 (rest + 0 * t = rest exactly, t
    // finite, and rest * 1 = rest).
    typedef double V __attribute__((vector_size(16)));
    for (; n >= kShiftBlockMinDegree && k + 3 <= n; k += 4) {
      V restA = {0, 0}, errA = {0, 0}, restB = {0, 0}, errB = {0, 0};
      const V rv = {r, r};
      for (int i = n; i > k + 3; --i) {
        const double* c = kBinomials.c[i] + k;
        const V at = {std::abs(t[i]), std::abs(t[i])}, aa = {ta[i], ta[i]};
        const V bA = {c[0], c[1]}, bB = {c[2], c[3]};
        restA = (restA + bA * at) * rv;
        errA = (errA + bA * aa) * rv;
        restB = (restB + bB * at) * rv;
        errB = (errB + bB * aa) * rv;
      }
      for (int i = k + 3; i > k; --i) {
        const double* c = kBinomials.c[i] + k;
        const V at = {std::abs(t[i]), std::abs(t[i])}, aa = {ta[i], ta[i]};
        const V bA = {i > k ? c[0] : 0.0, i > k + 1 ? c[1] : 0.0};
        const V bB = {i > k + 2 ? c[2] : 0.0, 0.0};
        const V rA = {i > k ? r : 1.0, i > k + 1 ? r : 1.0}, rB = {i > k + 2 ? r : 1.0, 1.0};
        restA = (restA + bA * at) * rA;
        errA = (errA + bA * aa) * rA;
        restB = (restB + bB * at) * rB;
        errB = (errB + bB * aa) * rB;
      }
      const double rest[4] = {restA[0], restA[1], restB[0], restB[1]};
      const double err[4] = {errA[0], errA[1], errB[0], errB[1]};
      for (int l = 0; l < 4; ++l)
        if (std::abs(t[k + l]) > rest[l] + gShift * (err[l] + ta[k + l])) return k + l;
    }
  }
  for (; k <= n; ++k) {
    T rest = 0, err = 0;
    for (int j = n - k; j >= 1; --j) {
      const T b = static_cast<T>(kBinomials.c[j + k][k]);
      rest = (rest + b * std::abs(t[j + k])) * r;
      err = (err + b * ta[j + k]) * r;
    }
    err = gShift * (err + ta[k]);
    if (std::abs(t[k]) > rest + err) return k;
  }
  return n;  // not reached: the order-n derivative is the constant n! C_n != 0
}

// Yuksel's sweep on (g.lo, g.hi), given rootFreeOrder(g) = order >= 1.
template <class T, class D>
int solveDirect(const LocalPoly<T>& g, D deg, int order, Query q, T tol, LocalRoot<T>* out,
                int maxOut) {
  const int n = deg;
  T crit[kMaxDegree];
  int nCrit = 0;
  if (order >= 2) {
    T d[kMaxDegree];
    derivative(g.c.data(), deg, d);
    // The critical points to full precision, whatever the tolerance: they split the
    // interval into monotone pieces, and one placed by a tolerance wider than the gap
    // between two roots put both roots' ends on one side (relTolerance 1e-2 skipped pairs
    // 0.028 apart on (-4, 4] until session 52; the audit's random campaign: 51 of 20000).
    nCrit = derivRootsDyn(d, n - 1, g.lo, g.hi, T(0), crit, n - order + 1);
  }
  auto piece = [&](T a, T b, T fa, T fb) {
    return newtonInBracket(g.c.data(), g.noise.data(), deg, a, b, fa, fb, tol);
  };
  return scanPieces(g, deg, nCrit > 0 ? crit : static_cast<const T*>(nullptr), nCrit, q, piece, out,
                    maxOut);
}

// Where the subdivision of roots_subdivide.h pays. Session 2 (tests/bench/roots_report.cpp,
// whole-ray intervals, ns before -> after): degree 6 481 -> 498, 8 1137 -> 700, 10 2005 ->
// 804, 12 3952 -> 851, 16 7783 -> 2753, 20 14258 -> 5158; it was then limited to degree 12
// because Chmutov-16's real rays got 1.4x slower. With Descartes' one-variation nodes
// (session 3; roots_bench, same run, ns with the limit at 12 -> 20): ray 16 4566 -> 1021,
// 20 7508 -> 2262; cell 16 564 -> 485, 20 945 -> 1010; Chmutov-16's real rays 6418 -> 4132
// (BM_GalleryRays). Above 20 on every interval it loses (depth cap 10 then): ray 30 20057 ->
// 16479 but 40 33842 -> 39237, cell 30 3476 -> 5458 and 40 5704 -> 17192 (ray polynomials
// of degree 30-40 cancel 13 digits in power form, so nodes near their roots stay within
// the rounding margin; a larger node budget, 8n, made it 2-5x worse still); hence the rule
// below for degrees above 20. Also measured and not kept: Sturm's solver for
// the nodes the budget leaves (Chmutov-16 4032 -> 2296 ns, degree 30 ray 20057 -> 5165),
// because its end rules merge a root with a noise-level end, so firstRoot(c, err,
// previousRoot, hi) no longer walks every root (RootsKnown.Wilkinson,
// RootsKnown.RandomRootsAllDegrees fail). On a short interval (a ray's span in one cell)
// the exclusion test of rootFreeOrder usually proves a low derivative root-free at once,
// and where that derivative is low enough (shortOrder below) the recursion is cheaper than
// any subdivision.
// Above degree 20 (session 3, roots_bench, ns, without -> with): the subdivision only
// where the exclusion test proves no derivative but the constant one root-free, i.e. on
// long spans: whole rays of degree 30 19762 -> 10396, 40 32895 -> 24443; cells (nearly
// always settled by the test) 3320 -> 3273 and 5266 -> 5366.
// Session 10, with the per-coefficient Bernstein bounds of roots_bernstein_nodes.h: above
// degree 20 a long interval (as defined below) now subdivides without the test, a short one keeps
// that rule (roots_report, 200 problems a degree, the rules side by side, two runs, ns):
// whole rays of degree 30 8470 -> 3284 and 8404 -> 3291 (Sturm 3624-3726: from 0.44x to
// 1.1x of its speed), 40 33016 -> 9821 and 19246 -> 9847 (0.18-0.29x -> 0.55x of Sturm);
// cells of degree 30 2651 -> 1525 and 2242 -> 1533, 40 5210 -> 4590 and 4955 -> 4427;
// degree 20 unchanged; errors and noise-level answers the same. Also subdividing short
// intervals of high degree (every interval, or those whose test stops above order n / 2)
// made cells of degree 30-40 1.5-8x slower.
constexpr int kSubdivideMinDegree = 3, kSubdivideMaxDegree = 40, kRecursionFirstDegree = 20;
// A short interval goes to the recursion where rootFreeOrder is at most 2 up to degree 16
// (G'' root-free: at most one critical point to polish before G), at most 3 above;
// anything else subdivides, where a one-variation node needs a single polish. Until
// session 25 the rule was order 3 at every degree, set before the subdivision's
// one-variation nodes and crossing splits (sessions 3 and 14) made it cheaper. Measured
// (session 25, Zen 5 host, roots_report built three times with order 1, 2 and 3 here,
// interleaved runs, medians of Sturm / Auto on cells): order 3 -> 2 at degrees 6-12
// (seven runs each) 3.87 -> 4.14x, 4.41 -> 4.52, 4.82 -> 5.04, 4.58 -> 4.74, 5.33 -> 5.41,
// 5.31 -> 5.48, 5.40 -> 5.39; order 1 (four runs) 4.25, 4.64, 5.09, 4.78, 5.51, 5.53, 5.56;
// at degrees 17-20 order 3 stays ahead (4.18-4.71 against 4.03-4.67 at orders 1-2, 3.69-3.75
// against 3.26-3.40 at 20). Order 1 was not kept for the gallery's surfaces (speed_report,
// three interleaved runs, primary rays against order 3: Endrass octic 0.91x, Chmutov-8
// 0.94x, Barth sextic 0.975x; shadow rays 1.02-1.04x); with order 2 primary rays 0.98-1.00x,
// shadow rays 1.005-1.036x. The report's p99 and worst errors, misses and noise-level
// answers are the same at every order (median errors within 0.01 u cond).
inline constexpr int shortOrder(int n) { return n <= 16 ? 2 : 3; }

// Whether a query that has found k roots asks for more (the first root, or all of them).
inline bool wantsMore(Query q, int k, int maxOut) {
  return k == 0 || (q == Query::All && k < maxOut);
}

// A subdivision whose node budget ran out (SubdivideState::exhausted) hands the rest,
// [resumeAt, hi], to the recursion in one piece (a cluster at resumeAt was reported by the
// node before it, see roots_scan.h); returns the roots found in all.
template <class T, class Direct>
int restAfterBudget(const LocalPoly<T>& g, LocalPoly<T>& work, bool exhausted, T resumeAt, Query q,
                    int k, Direct& direct, LocalRoot<T>* out, int maxOut) {
  if (!exhausted || !wantsMore(q, k, maxOut)) return k;
  work.lo = resumeAt;
  work.hi = g.hi;
  work.closedLo = g.closedLo && resumeAt == g.lo;
  return k + direct(work, out + k, maxOut - k);
}

// The subdivision of solveTop from the halves [g.lo, 0] and [0, g.hi] (see there); work is
// the subdivision's working copy of g, b room for a half's coefficients. (Inlined into
// solveTop, as here, speed_report's Sarti rays were 3-7 % faster than with it out of line,
// and the Barth sextic's shadow rays, which never start at 0, 2-6 % slower: code layout;
// see docs/roots.md, session 17.)
template <class T, class D, class E, class Direct>
int solveFromZero(const LocalPoly<T>& g, D deg, Query q, T tol, LocalRoot<T>* out, int maxOut,
                  LocalPoly<T>& work, E* b, Direct& direct) {
  // Both halves take the root node's noise bound at max(|lo|, |hi|), as its children would.
  const T x = std::max(-g.lo, g.hi);
  const KnownNoise<T> known{x, hornerAbs(g.noise.data(), deg, x)};
  work.lo = g.lo;
  work.hi = 0;
  T err = bernsteinFromZero(g, deg, g.lo, b);
  SubdivideState<T> left{work, g.lo, -g.lo, err, q, tol, g.closedLo};
  left.nodes = 1;  // the root node
  int k = subdivide(left, deg, b, T(0), T(1), 1, direct, out, maxOut, known);
  T resumeAt = left.resumeAt;
  bool exhausted = left.exhausted;
  if (!exhausted && wantsMore(q, k, maxOut)) {
    work.lo = 0;
    work.hi = g.hi;
    err = bernsteinFromZero(g, deg, g.hi, b);
    SubdivideState<T> right{work, T(0), g.hi, err, q, tol, false};
    right.nodes = left.nodes;
    k += subdivide(right, deg, b, T(0), T(1), 1, direct, out + k, maxOut - k, known);
    resumeAt = right.resumeAt;
    exhausted = right.exhausted;
  }
  return restAfterBudget(g, work, exhausted, resumeAt, q, k, direct, out, maxOut);
}

template <class T, class D>
int solveTop(const LocalPoly<T>& g, D deg, Query q, T tol, LocalRoot<T>* out, int maxOut) {
  const int n = deg;
  if (q == Query::Any && endpointsStraddle(g, deg)) {
    out[0] = LocalRoot<T>{g.lo + (g.hi - g.lo) / 2, false};
    return 1;
  }
  auto direct = [&](const LocalPoly<T>& piece, LocalRoot<T>* o, int m) {
    const int order = n >= 2 ? rootFreeOrder(piece, deg) : 1;
    return order == 0 ? 0 : solveDirect(piece, deg, order, q, tol, o, m);
  };
  if (n < kSubdivideMinDegree || n > kSubdivideMaxDegree) return direct(g, out, maxOut);
  // Short: at most a quarter of the frame's scale (max(|lo|, |hi|) is in [1/2, 1]). Above
  // degree 20 a short interval is subdivided only where no derivative below the constant
  // one is proved root-free (see kSubdivideMaxDegree); long ones are always subdivided.
  // (An eighth instead of a quarter, session 26: roots_report's cells 2-7 % faster at
  // degrees 8-12, but speed_report's Barth decic primary rays 0.90x; docs/roots.md.)
  const bool high = n > kRecursionFirstDegree;
  if (4 * (g.hi - g.lo) <= std::max(std::abs(g.lo), std::abs(g.hi))) {
    const int order = rootFreeOrder(g, deg);
    if (order == 0) return 0;
    if (order <= (high ? n - 1 : shortOrder(n)))
      return solveDirect(g, deg, order, q, tol, out, maxOut);
  }
  // The subdivision's working copy (node ends move); only the n + 1 live coefficients.
  LocalPoly<T> work;
  work.n = g.n;
  work.lo = g.lo;
  work.hi = g.hi;
  work.window = g.window;
  copyCoeffs(g.c.data(), n + 1, work.c.data());
  copyCoeffs(g.noise.data(), n + 1, work.noise.data());
  typename NodeElement<T, D>::type b[kMaxDegree + 1];
  // A span around 0 (the re-centred rays' spans nearly always are) starts as its two halves
  // [lo, 0] and [0, hi], each converted from 0 without a shift (bernsteinFromZero: the
  // bound there is G's majorant at the half's far end, not at 3 times the span's reach).
  // The halves are the root node's children, at depth 1, under the same node budget; the
  // split point 0 keeps the rule of the splits inside (G clear of its noise bound there:
  // G(0) = C_0 exactly, its noise bound is noise_0), and is used only between the middle
  // quarters of the span, so that neither half is much shorter than a split's child.
  // Measured (session 17, AMD EPYC Zen 3, one pinned core; with roots_subdivide.h's
  // unrolled splits and Pascal passes and its split-ratio bit mask): the gallery's real
  // rays (BM_GalleryRays' camera, 2936 primary rays a surface, best of 3 interleaved runs,
  // ns per solve) Sarti 643 -> 495, Barth decic 546 -> 416, Chmutov-16 1123 -> 860, Barth
  // sextic 188 -> 177; callgrind instructions per solve Sarti 6852 -> 4792, Chmutov-12
  // 6769 -> 4560, Chmutov-16 11075 -> 7496, Barth decic 5397 -> 4322, Endrass octic 3769 ->
  // 3178, Barth sextic 2172 -> 2010. Roots of such spans move in their last bits (another
  // bracket for the same polish): on 457k rays from six cameras no hit, miss or root count
  // changed, and against 200-bit references (300 rays a surface) the worst errors were
  // 0.7-2.1 u cond before and after (docs/roots.md).
  if (g.lo < 0 && g.hi > 0 && 4 * g.hi >= g.hi - g.lo && -4 * g.lo >= g.hi - g.lo &&
      std::abs(g.c[0]) > g.noise[0])
    return solveFromZero(g, deg, q, tol, out, maxOut, work, b, direct);
  const T err = toBernsteinWithBound(g, deg, b);
  SubdivideState<T> st{work, g.lo, g.hi - g.lo, err, q, tol, g.closedLo};
  const int k = subdivide(st, deg, b, T(0), T(1), 0, direct, out, maxOut);
  return restAfterBudget(g, work, st.exhausted, st.resumeAt, q, k, direct, out, maxOut);
}

template <class T, int... Ns>
int solveTopSmall(const LocalPoly<T>& g, Query q, T tol, LocalRoot<T>* out, int maxOut,
                  std::integer_sequence<int, Ns...>) {
  int k = 0;
  static_cast<void>(
      ((g.n == Ns + 1 ? (k = solveTop(g, Deg<Ns + 1>{}, q, tol, out, maxOut), true) : false) ||
       ...));
  return k;
}

}  // namespace

template <class T>
int solveYuksel(const LocalPoly<T>& g, Query q, T tol, LocalRoot<T>* out, int maxOut) {
  if (g.n < 1 || maxOut < 1) return 0;
  if (g.n <= kTemplateDegree)
    return solveTopSmall(g, q, tol, out, maxOut,
                         std::make_integer_sequence<int, kTemplateDegree>{});
  return solveTop(g, g.n, q, tol, out, maxOut);
}

template int solveYuksel<double>(const LocalPoly<double>&, Query, double, LocalRoot<double>*, int);
template int solveYuksel<float>(const LocalPoly<float>&, Query, float, LocalRoot<float>*, int);

}  // namespace algray::roots_detail
