#pragma once
// Private building blocks of the root solvers (roots*.cpp). Not installed.
//
// Every solver works on the *local* polynomial G(v) = g(2^e v) on the local interval
// (lo, hi) = 2^-e (caller's lo, hi) inside [-1, 1] (roots.cpp builds it: 2^e is the
// smallest power of two >= max(|lo|, |hi|), and the coefficients are scaled by another
// power of two to max |C_j| in [1, 2)). Both scalings are exact, so G has exactly the
// caller's roots and conditioning; |v| <= 1 makes the noise rules simple and keeps
// degree-40 powers in range whatever the caller's units.
#include "algray/polynomial.h"

#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

namespace algray::roots_detail {

template <class T>
inline constexpr T kUnit = std::numeric_limits<T>::epsilon() / 2;  // unit roundoff

// sqrt of T's smallest normal number (2^-1022, 2^-126): products of two numbers above it
// stay normal.
template <class T>
inline constexpr T kSqrtMin = std::is_same_v<T, double> ? T(0x1p-511) : T(0x1p-63);

// Higham's gamma_n for the precision T (Accuracy and Stability, Eq. (3.8)).
template <class T>
constexpr T gammaT(int n) {
  return n * kUnit<T> / (1 - n * kUnit<T>);
}

template <class T>
using Coeffs = std::array<T, kMaxDegree + 1>;

// G(v) = sum_{j <= n} c[j] v^j on [-1, 1], with noise[j] >= 0 such that
//   |computed G(v) - exact G(v)| <= sum_j noise[j] |v|^j
// covers the caller's coefficient error, the mapping to the local frame and the Horner
// rounding of one evaluation (so one Horner pass over noise[] bounds the noise at v).
// Entries above n are left uninitialised (no solver reads them): zeroing 2 x 41 values
// on every call was a measurable part of a degree-6 solve.
template <class T>
struct LocalPoly {
  int n = -1;
  T lo = -1, hi = 1;  // the open interval searched, -1 <= lo < hi <= 1
  // Whether a root within noise of lo is reported (RootOptions::closedLo: lo is a
  // region's boundary) or taken as the caller's previous root (the default).
  bool closedLo = false;
  // The noise-before query (RootOptions::noiseBefore, roots_scan.h): > 0, the stretch before
  // a first root within which G may be within its noise unreported (2^-20 of the caller's
  // interval); 0, no such query.
  T window = 0;
  Coeffs<T> c;
  Coeffs<T> noise;
};

// A degree given at compile time (std::integral_constant) or at run time (int): loops
// written against `int(deg)` unroll in the first case and stay generic in the second.
template <int N>
using Deg = std::integral_constant<int, N>;

// Copies count coefficients. A plain loop: with the degree known at compile time it
// becomes a few moves, where std::copy became a call to memmove (measured against
// std::copy: Auto's whole rays 3-9 % faster at degrees 3-20, cells 2-6 %; de Casteljau's
// working copy, splitBernstein, measured 8 % slower at degree 6 as a loop and keeps it).
template <class T>
inline void copyCoeffs(const T* from, int count, T* to) {
  for (int i = 0; i < count; ++i) to[i] = from[i];
}

// ---- Evaluation -------------------------------------------------------------------
// Plain Horner everywhere, on purpose. Measured and reverted in session 8: the value and
// the polish's derivatives as even/odd (second-order Horner) passes halve an evaluation's
// dependency chain (a polish iteration 1.3-1.5x faster in a latency-bound loop; whole
// rays 4-7 % and cells 3-4 % faster in roots_bench), but the value near a root then is
// the small difference of two large sums, and the roots lost accuracy: roots_report's
// p99 error rose from 0.2-0.6 to 0.7-2.6 u cond on cells and to 3.1 u cond on whole rays
// at degree 14, beyond the Sturm solver's (0.1-1.2 u cond, whose evaluations stayed
// Horner): faster, but no longer "at equal or better accuracy".
template <class T, class D>
inline T horner(const T* c, D deg, T x) {
  const int n = deg;
  T r = c[n];
  for (int i = n - 1; i >= 0; --i) r = r * x + c[i];
  return r;
}

// Value f, derivative df, the Taylor coefficients dd = f''/2 and d3 = f'''/6, the
// noise bound nb at x and its slope nbSlope (the bound the coefficients' noise puts on
// f'(x)) in one pass. The recurrences are independent from one step to
// the next, so on a superscalar core the extra ones hide in the latency of the value
// recurrence.
template <class T, class D>
inline void hornerNewton(const T* c, const T* noise, D deg, T x, T& f, T& df, T& dd, T& d3, T& nb,
                         T& nbSlope) {
  const int n = deg;
  const T ax = std::abs(x);
  f = c[n];
  df = 0;
  dd = 0;
  d3 = 0;
  nb = noise[n];
  nbSlope = 0;
  for (int i = n - 1; i >= 0; --i) {
    d3 = d3 * x + dd;
    dd = dd * x + df;
    df = df * x + f;
    f = f * x + c[i];
    nbSlope = nbSlope * ax + nb;
    nb = nb * ax + noise[i];
  }
}

// sum a_i |x|^i for non-negative a (a noise bound).
template <class T, class D>
inline T hornerAbs(const T* a, D deg, T x) {
  const int n = deg;
  const T ax = std::abs(x);
  T r = a[n];
  for (int i = n - 1; i >= 0; --i) r = r * ax + a[i];
  return r;
}

// horner(c, deg, x) and hornerAbs(noise, deg, x) in one loop: the same two chains, bit for
// bit, but interleaved, so each hides the other's latency (written as two calls, GCC
// emitted two loops one after the other: at degree 40 a value and its noise bound took
// twice one Horner chain's ~320 cycles; perf, session 13).
template <class T, class D>
inline void hornerNoise(const T* c, const T* noise, D deg, T x, T& f, T& nb) {
  const int n = deg;
  if (n <= 12) {  // short, unrolled chains overlap anyway: as before, two calls
    f = horner(c, deg, x);
    nb = hornerAbs(noise, deg, x);
    return;
  }
  const T ax = std::abs(x);
  T r = c[n], a = noise[n];
  for (int i = n - 1; i >= 0; --i) {
    r = r * x + c[i];
    a = a * ax + noise[i];
  }
  f = r;
  nb = a;
}

// Derivative coefficients divided by the degree (d[i] = (i+1) c[i+1] / n): the same roots
// as g', but the scale of the coefficients does not grow like n!/(n-k)! down the chain
// of derivatives (degree 40 would otherwise approach the overflow threshold).
template <class T, class D>
inline void derivative(const T* c, D deg, T* d) {
  const int n = deg;
  const T inv = T(1) / T(n);
  for (int i = 0; i < n; ++i) d[i] = c[i + 1] * (T(i + 1) * inv);
}

inline bool signBit(double x) { return std::signbit(x); }
inline bool signBit(float x) { return std::signbit(x); }

// Binomial coefficients C(i, j), exact in double up to C(40, 20) ~ 1.4e11.
struct Binomials {
  double c[kMaxDegree + 1][kMaxDegree + 1] = {};
  constexpr Binomials() {
    for (int i = 0; i <= kMaxDegree; ++i) {
      c[i][0] = 1;
      for (int j = 1; j <= i; ++j) c[i][j] = c[i - 1][j - 1] + (j < i ? c[i - 1][j] : 0);
    }
  }
};
inline constexpr Binomials kBinomials;

// ---- Taylor shift -------------------------------------------------------------------
// p(x) -> p(x + m) in place: n passes p[i] += m p[i + 1], i from n - 1 down to k in pass
// k (V: T, or a 2-lane vector of (value, magnitude) pairs). Within a pass each step
// needs the one before it, a serial chain of multiply-adds; pass k + 1 needs of pass k
// only the element it is at, so four passes run side by side, skewed by one element
// each (pass k + d at element s + d in step s), as four independent chains. Each
// element gets the same operations on the same operands as in the plain loop: bit for
// bit the same coefficients. Measured (session 13, perf, whole rays of degree 40): the
// shift of rootFreeOrder was its main cost, the plain passes overlapping only as far as
// the out-of-order window reached.
// Up to degree kShiftBlockMinDegree - 1 the plain loop: the short passes overlap anyway,
// and with this and session 13's other changes at every degree, whole rays of degree 6-8
// were 2-8 % slower (restricted as they are now: within noise).
inline constexpr int kShiftBlockMinDegree = 10;
template <class V, class M>
inline void taylorShift(V* p, int n, M m) {
  int k = 0;
  for (; n >= kShiftBlockMinDegree && k + 4 <= n; k += 4) {
    // c_d: pass k + d's last element; the prologue starts passes k + 1, k + 2, k + 3.
    V c0 = p[n], c1 = p[n], c2 = p[n], c3 = p[n];
    c0 = p[n - 1] + m * c0;
    {
      const V n0 = p[n - 2] + m * c0, n1 = c0 + m * c1;
      c0 = n0;
      c1 = n1;
    }
    {
      const V n0 = p[n - 3] + m * c0, n1 = c0 + m * c1, n2 = c1 + m * c2;
      c0 = n0;
      c1 = n1;
      c2 = n2;
    }
    for (int s = n - 4; s >= k; --s) {
      const V n0 = p[s] + m * c0, n1 = c0 + m * c1, n2 = c1 + m * c2, n3 = c2 + m * c3;
      c0 = n0;
      c1 = n1;
      c2 = n2;
      c3 = n3;
      p[s + 3] = n3;  // pass k + 3 is the last to touch element s + 3
    }
    p[k] = c0;
    p[k + 1] = c1;
    p[k + 2] = c2;
  }
  for (; k < n; ++k)
    for (int i = n - 1; i >= k; --i) p[i] += m * p[i + 1];
}

// ---- Taylor coefficients at the midpoint (the exclusion tests) ----------------------
// t_j of G at the midpoint m of (lo, hi) and ta_j, the same shift applied to |C| and |m|
// (gamma(2n+2) ta_j bounds the rounding of t_j); returns the radius r of the interval
// about m, enlarged to cover the rounding of m. Shared by the exclusion tests of
// Yuksel's solver (rootFreeOrder) and of the closed forms (rootFree).
// The two shifts run as one on (value, magnitude) pairs, a 2-lane vector (GCC/Clang
// vector extension; the same arithmetic, half the instructions).
template <class T, class D>
T midpointTaylor(const LocalPoly<T>& g, D deg, T* t, T* ta) {
  typedef T Pair __attribute__((vector_size(2 * sizeof(T))));
  const int n = deg;
  const T m = g.lo + (g.hi - g.lo) / 2;
  Pair p[kMaxDegree + 1];
  for (int i = 0; i <= n; ++i) p[i] = Pair{g.c[i], std::abs(g.c[i])};
  const Pair mm = {m, std::abs(m)};
  taylorShift(p, n, mm);
  for (int i = 0; i <= n; ++i) {
    t[i] = p[i][0];
    ta[i] = p[i][1];
  }
  return (g.hi - g.lo) / 2 * (1 + 4 * kUnit<T>);
}

// ---- Safeguarded Halley/Newton in a monotone bracket -------------------------------
// p is monotone on [a, b] and p(a), p(b) have opposite signs (neither zero), so the
// bracket always holds exactly one simple root. Steps that leave the bracket are
// replaced by bisection (Yuksel, HPG 2022, Sec. 4; the classic rtsafe of Numerical
// Recipes Sec. 9.4). The step is Halley's where it is well defined, else Newton's: the
// second derivative comes with the first from one Horner pass, and the cubic
// convergence cut the iterations of a whole-ray solve from 5.4 to 4.0 on average
// (roots_bench problems, degrees 6-16; 3-7 % of the solve time). Stopping rules, all
// relative:
//  * the step is below `tol` (the caller's tolerance in the local frame), or the error
//    predicted after it (Newton |p''/(2p')| step^2, Halley see below) is below the
//    rounding of x (full precision without the extra confirming iteration), or the step
//    itself is 4 ulp;
//  * |p(x)| is within its rounding bound (`noise`, see LocalPoly): the iterate is as good
//    as the data; the last step is kept when it stays in the bracket, since it removes
//    the truncation error while noise moves it by only noise/p';
//  * the bracket has collapsed to adjacent doubles.
// The loop is capped (kMaxNewton), which also bounds the work on NaN-free but
// pathological input; bisection alone needs <= 64 halvings to reach adjacent doubles of
// [-1, 1] at normal magnitudes.
inline constexpr int kMaxNewton = 96;

// The bisection point of (a, b). Halving the value needs ~ log2(|b| / |root|) steps,
// which for a root near 1e-40 in (-1, 1) is more than the cap (the iterate stopped near
// 2^-86, not a root). When the bracket spans more than a factor 4 in magnitude the
// split is in the exponent instead (the geometric mean, computed as sqrt |a| sqrt |b|
// so that it neither overflows nor underflows; 0 as an end counts as the smallest normal
// number), and a bracket around 0 is split at 0 first: ~11 such steps bring any bracket
// to one binade, then halving finishes within the cap.
template <class T>
T bisectionPoint(T a, T b) {
  if (a < 0 && b > 0) return T(0);
  const T lo = std::min(std::abs(a), std::abs(b)), hi = std::max(std::abs(a), std::abs(b));
  if (!(hi > 4 * lo)) return a + (b - a) / 2;
  const T g = std::sqrt(std::max(lo, std::numeric_limits<T>::min())) * std::sqrt(hi);
  return b > 0 ? g : -g;
}

// The Halley or Newton step of newtonFrom from ratios, for f or f' below kSqrtMin, where
// the products f f' and f'^2 underflow (out of line: inlined, the branch cost the polish
// of degree-20 whole rays 8 %).
template <class T>
[[gnu::noinline, gnu::cold]] T stepAsRatios(T x, T f, T df, T dd, bool& halley) {
  const T ratio = f / df, h = ratio * (dd / df);
  halley = 2 * std::abs(h) < 1;
  return halley ? x - ratio / (1 - h) : x - ratio;
}

// Whether the error predicted after a step of size `step` (see newtonFrom) is below the
// rounding of xn. With a compile-time degree (Yuksel's solver up to degree 20) the test is
// multiplied through by f'^2 (or |f'|): two divisions fewer per iteration, on the path to
// the loop's exit branch (session 14, interleaved timings: whole rays of degree 8-12
// 0.97-0.99x the time, the same roots bit for bit on 14000 random problems). The run-time
// degrees (Sturm's and the Bernstein comparison solver's polish, Yuksel above degree 20)
// keep the quotients, and so does any step, slope or iterate below 2^-300 (2^-30 in
// float), where the products would underflow (the root 1 of s^2 - 1 on (-1e150, 20] is
// 2^-498 in the local frame: step^3 underflowed to 0 and the polish stopped 1 % off;
// RootsContract.HugeIntervalsKeepTheRootsNearTheOrigin).
template <class T>
inline constexpr T kPredictMin = std::is_same_v<T, double> ? T(0x1p-300) : T(0x1p-30);
template <class T, class D>
inline bool predictedBelow(T df, T dd, T d3, bool halley, T step, T xn, D) {
  const T adf = std::abs(df), axn = std::abs(xn);
  if (std::is_same_v<D, int> || !(std::min(std::min(adf, axn), step) >= kPredictMin<T>)) {
    const T k = std::abs(dd / df);
    const T predicted = halley ? (k * k + std::abs(d3 / df)) * step * step * step : k * step * step;
    return predicted <= kUnit<T> * axn;
  }
  // |f'|, |xn|, step in [2^-300, 2^2]: neither side underflows to 0 where the quotient
  // test's sides do not (dd and d3 are bounded by the frame: |C_j| < 2, |v| <= 1).
  const T bound = kUnit<T> * axn * adf;
  return halley ? (dd * dd + std::abs(d3) * adf) * (step * step * step) <= bound * adf
                : std::abs(dd) * (step * step) <= bound;
}

// On a monotone piece between a clearly non-zero end `clear` (value fClear) and a
// noise-level point `noisy`: a point m between them where p is clearly non-zero with the
// sign opposite to fClear, found by bisection towards `noisy` (a clear point of fClear's
// sign moves the search past it, a noise-level one back towards `clear`). Such a point
// proves the piece's root in (clear, m) (the noise bounds are rigorous). Only where the
// noise bound is smaller inside the piece than at `noisy` (|v| smaller: the bound grows
// with |v|) can it exist: between the root and `noisy` the monotone p is below
// |p(noisy)| <= noise(noisy) in magnitude; elsewhere no point is tried.
template <class T, class D>
bool clearCrossing(const T* p, const T* noise, D deg, T clear, T fClear, T noisy, T& m, T& fm) {
  const T nearZero = (clear < 0) != (noisy < 0) ? T(0) : std::min(std::abs(clear), std::abs(noisy));
  if (!(nearZero < std::abs(noisy))) return false;
  T a = clear, b = noisy;  // the crossing, if any, lies between a (fClear's sign) and b
  for (int it = 0; it < 16; ++it) {
    m = a + (b - a) / 2;
    if (m == a || m == b) return false;
    T nm;
    hornerNoise(p, noise, deg, m, fm, nm);
    if (std::abs(fm) <= nm)
      b = m;
    else if (signBit(fm) == signBit(fClear))
      a = m;
    else
      return true;
  }
  return false;
}

template <class T, class D>
T newtonIterate(const T* p, const T* noise, D deg, T a, T b, T fa, T x, T tol, bool& untrusted);

// Where the polish stops at noise level with an untrusted last step (see newtonFrom), x may
// lie in a wide noise region far from the piece's root: the noise bound grows with |v|, so
// a monotone piece can run from a clear end with a well-conditioned root into a stretch
// where p is within its bound, and the secant start lands there. Below the top level this
// lost critical points: G' of a degree-35 tangent problem had its simple root (G's minimum,
// |G| 470 times its bound) at 739 and was within noise from 900 on; the polish stopped at
// 913, G's pieces then ran from the previous root through the minimum without a critical
// point, and firstRoot(c, err, previousRoot, hi) merged the root at lo with the one within
// noise of hi (tests/roots_contract_test.cpp,
// RootsContract.WalkPastACleanStretchToANoiseLevelHi).
// As the sweep does for G itself (roots_scan.h), a clear point of the other sign between a
// clear end of the bracket [a0, b0] and x proves the root beside it; it is polished there
// (without a further search). Otherwise x is as good as the data. Only on this exit (rare:
// multiple roots, flat pieces), out of line.
template <class T, class D>
[[gnu::noinline, gnu::cold]] T rootBesideNoise(const T* p, const T* noise, D deg, T a0, T b0, T x,
                                               T tol) {
  T m, fm, f0, n0;
  bool unused = false;  // (the polish beside the noise searches no further)
  hornerNoise(p, noise, deg, a0, f0, n0);
  if (std::abs(f0) > n0 && clearCrossing(p, noise, deg, a0, f0, x, m, fm))
    return newtonIterate(p, noise, deg, a0, m, f0, a0 + (m - a0) / 2, tol, unused);
  hornerNoise(p, noise, deg, b0, f0, n0);
  if (std::abs(f0) > n0 && clearCrossing(p, noise, deg, b0, f0, x, m, fm))
    return newtonIterate(p, noise, deg, m, b0, fm, m + (b0 - m) / 2, tol, unused);
  return x;
}

// The iteration from a given start x in (a, b); `untrusted` is set where it stops at noise
// level with an untrusted step (see rootBesideNoise).
template <class T, class D>
T newtonIterate(const T* p, const T* noise, D deg, T a, T b, T fa, T x, T tol, bool& untrusted) {
  const bool negA = signBit(fa);
  T stepOld = b - a;
  for (int it = 0; it < kMaxNewton; ++it) {
    T f, df, dd, d3, nb, nbSlope;
    hornerNewton(p, noise, deg, x, f, df, dd, d3, nb, nbSlope);
    if (f == 0) return x;
    if (signBit(f) == negA)
      a = x;
    else
      b = x;
    const bool atNoise = std::abs(f) <= nb;
    // Halley's step, x - f f' / (f'^2 - f f''/2) (cubic convergence; Traub, "Iterative
    // Methods for the Solution of Equations", 1964, Sec. 5.2), one division as Newton's.
    // With f''/2 = dd it is x - f df / (df^2 - f dd); where f dd is not small against
    // df^2 (far from the root, near an inflection) the plain Newton step is taken.
    // Where f or f' is below sqrt(T's smallest normal number) the products f f', f'^2
    // underflow (a root near 1e-105 of s^3 + 1e-105 s + 1e-210 came out 7e-8 relative off,
    // RootsKnown.TinyRootsAndTheStopRule); there the same steps are taken as ratios,
    // whose extra division stays off the common path.
    const T d2 = df * df, fdd = f * dd;
    bool halley = 2 * std::abs(fdd) < d2;
    T xn = halley ? x - f * df / (d2 - fdd) : x - f / df;
    if (std::min(std::abs(f), std::abs(df)) < kSqrtMin<T>) [[unlikely]]
      xn = stepAsRatios(x, f, df, dd, halley);
    // Bisect when the step leaves the bracket (also df == 0, NaN) or when it does not at
    // least halve the previous step: far from the root of a steep piece (x^n-like growth
    // towards one end) Newton creeps by a factor 1 - 1/n per step (rtsafe's rule,
    // Numerical Recipes Sec. 9.4). Halley creeps by (n - 1)/(n + 1), which for n = 3 just
    // passes that rule and would exhaust the cap on a root at 1e-40 in (0, 1); so while
    // the bracket spans more than a binade (where bisectionPoint splits the exponent) a
    // step must shrink by 3. (A factor 3 everywhere cost Sturm's polish 6-20 %: its
    // brackets are often wide at the root's own scale.)
    const bool inside = xn > a && xn < b;
    const T aLo = std::min(std::abs(a), std::abs(b)), aHi = std::max(std::abs(a), std::abs(b));
    const T creep = (a < 0 && b > 0) || aHi > 4 * aLo ? T(3) : T(2);
    // At noise level the last step is kept only near a simple root, where it removes the
    // truncation error and noise moves it by only noise / p': the slope clearly beyond
    // its own noise bound and nearly constant over the step. At a multiple root p' is
    // itself noise and the step is garbage: a triple root of G' sent a step across a fifth
    // of the node and lost a ray's 4-fold root (x^4 = 0: 1 % of rays missed).
    // And the model's own error over the step within the noise bound: the residual the
    // step leaves, about dd h^2 after Newton's and (dd^2 / df - d3) h^3 after Halley's
    // (Traub, Sec. 5.2; multiplied through by |df|). Without it, a flat simple root at
    // degree 39 (|df| 1e-23, d3 5e-19) took a Halley step of 0.008 from the edge of its
    // noise region to a point where |G| was 3 times its bound.
    auto trusted = [&] {
      const T h = std::abs(xn - x), adf = std::abs(df);
      if (!(2 * std::abs(dd) * h <= adf && adf > 2 * nbSlope)) return false;
      return halley ? (dd * dd + std::abs(d3 * df)) * (h * h * h) <= nb * adf
                    : std::abs(dd) * (h * h) <= nb;
    };
    if (!inside || creep * std::abs(xn - x) > stepOld) {
      if (atNoise) {
        if (inside && trusted()) return xn;
        untrusted = true;
        return x;
      }
      xn = bisectionPoint(a, b);
      if (!(xn > a && xn < b)) xn = a + (b - a) / 2;
      if (!(xn > a && xn < b)) return x;  // adjacent doubles
    } else {
      if (atNoise) {
        if (trusted()) return xn;
        untrusted = true;
        return x;
      }
      // The error after a step of size h (Taylor with remainder): Newton's is about
      // |K| h^2, Halley's |K^2 - L| h^3, K = f''/(2f') = dd/df, L = f'''/(6f') = d3/df
      // (Traub, Sec. 5.2). When it is below the rounding of x the next step could not
      // move x.
      // The prediction is trusted only where it is the whole error: the step is at most
      // half of |x| (xn = x - step rounds relative to |x|, not |xn|: a step from 1e-17 to
      // a root near 2e-33 left an error the size of the root; a step from x = 0, a
      // bisection point, ignored the s^5 term of s^5 + 1e-92 s^2 + ...). That holds at any
      // ordinary convergence; elsewhere one more step is taken.
      const T step = std::abs(xn - x);
      if (step <= 4 * kUnit<T> * std::abs(xn) ||
          (2 * step <= std::abs(x) && predictedBelow(df, dd, d3, halley, step, xn, deg)))
        return xn;
      // A tolerance (RootOptions::relTolerance) ends the polish where a sign change within
      // it of xn is seen: a step below it is no bound on the error (until session 52 it
      // ended there, and answers lay up to 10 tolerances from the root).
      if (step <= tol && tol > 0) [[unlikely]] {
        const T lo = std::max(a, xn - tol), hi = std::min(b, xn + tol);
        const bool negLo = lo == a ? negA : signBit(horner(p, deg, lo));
        const bool negHi = hi == b ? !negA : signBit(horner(p, deg, hi));
        if (negLo != negHi) return xn;
      }
    }
    stepOld = std::abs(xn - x);
    x = xn;
  }
  return x;
}

// The polish from a given start x in (a, b) (newtonFrom: a closed form's value, polished on
// the original polynomial; newtonInBracket: the secant point). An untrusted stop at noise
// level looks for the root beside the noise (rootBesideNoise). The rule sits outside the
// iteration: written into its loop (the bracket's first ends kept for the search), GCC no
// longer built the loop's IPA-SRA clone (newtonFrom<double, 6> 0x7b5 bytes before, 0x85c
// and a call to a lambda then; newtonIterate's clone is 0x7c9, the loop as before but two
// flag stores on its exits).
template <class T, class D>
T newtonFrom(const T* p, const T* noise, D deg, T a, T b, T fa, T x, T tol) {
  bool untrusted = false;
  const T r = newtonIterate(p, noise, deg, a, b, fa, x, tol, untrusted);
  if (untrusted) [[unlikely]]
    return rootBesideNoise(p, noise, deg, a, b, r, tol);
  return r;
}

template <class T, class D>
T newtonInBracket(const T* p, const T* noise, D deg, T a, T b, T fa, T fb, T tol) {
  // Start at the secant (regula falsi) point: for a monotone piece it is inside the
  // bracket and usually much closer to the root than the midpoint.
  T x = (a * fb - b * fa) / (fb - fa);
  if (!(x > a && x < b)) x = a + (b - a) / 2;
  return newtonFrom(p, noise, deg, a, b, fa, x, tol);
}

// ---- Quadratic, stable --------------------------------------------------------------
// Discriminant b^2 - 4ac with an FMA-recovered rounding error of both products (Kahan,
// "On the cost of floating-point computation without extra-precise arithmetic", 2004;
// Boldo, "Kahan's algorithm for a correct discriminant computation at last formally
// proven", IEEE TC 2009): accurate to a few ulps even when the two products cancel.
// Where they do not (|p - q| > (p + |q|) / 2) the correction, at most u (p + |q|) < 2u
// |p - q|, is left out: std::fma is a library call in a build without FMA, two of them
// on the dependency chain of every quadric ray (session 11, speed_report's sphere, seven
// interleaved runs: primary rays 0.92-0.96x -> 0.98-1.00x of Embree's sphere). The
// quadric path's scalar and SIMD kernels (quadric_path.cpp, quadric_packet_group.inc)
// repeat this rule exactly.
template <class T>
inline T discriminant(T a, T b, T c) {
  const T p = b * b, q = 4 * a * c, d0 = p - q;
  if (std::abs(d0) > T(0.5) * (p + std::abs(q))) return d0;
  const T dp = std::fma(b, b, -p);
  const T dq = std::fma(4 * a, c, -q);
  return d0 + (dp - dq);
}

// Real roots of a v^2 + b v + c with a != 0, in increasing order; returns 0 or 2 (a
// double root counts as none here: callers decide tangency with their own rule).
// Citardauq form: q = -(b + sign(b) sqrt(D)) / 2, roots q / a and c / q, so neither root
// suffers the cancellation of the textbook formula (Higham, Sec. 1.8; Press et al.,
// Numerical Recipes Eq. 5.6.4).
template <class T>
inline int quadraticRoots(T a, T b, T c, T& r0, T& r1) {
  const T d = discriminant(a, b, c);
  if (!(d > 0)) return 0;
  const T q = -(b + std::copysign(std::sqrt(d), b)) / 2;
  if (q == 0) return 0;  // b == 0 and d == 0 after rounding: handled above; guard anyway
  r0 = q / a;
  r1 = c / q;
  if (r1 < r0) std::swap(r0, r1);
  return 2;
}

// ---- What the solvers return ---------------------------------------------------------
enum class Query { First, Any, All };

template <class T>
struct LocalRoot {
  T v;           // root in the local frame
  bool tangent;  // decided by the noise rule (an extremum or an endpoint): no polishing
};

// Each solver writes at most maxOut roots in increasing order and returns their number.
// Query::First and Query::Any stop after the first; Query::Any may return an unrefined
// point of the right piece. tol is an absolute tolerance in the local frame (0: full
// precision), roots.cpp derives it from the caller's relative one.
template <class T>
int solveYuksel(const LocalPoly<T>& g, Query q, T tol, LocalRoot<T>* out, int maxOut);
template <class T>
int solveClosedForm(const LocalPoly<T>& g, Query q, T tol, LocalRoot<T>* out, int maxOut);
int solveSturm(const LocalPoly<double>& g, Query q, double tol, LocalRoot<double>* out, int maxOut);
int solveBernstein(const LocalPoly<double>& g, Query q, double tol, LocalRoot<double>* out,
                   int maxOut);

}  // namespace algray::roots_detail
