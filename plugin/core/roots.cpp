// Public entry points of roots.h: input checks, the map to the local frame, the
// dispatch by method and degree.
#include "algray/roots.h"

#include "roots_detail.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>
#include <utility>

namespace algray {
namespace {

using roots_detail::gammaT;
using roots_detail::LocalPoly;
using roots_detail::LocalRoot;
using roots_detail::Query;

// The caller's frame: s = 2^e v. Why a power-of-two scaling and no shift of the origin:
// the scaling is exact, so the local polynomial has exactly the caller's roots and
// conditioning (the conditioning sum|c_i||r|^i / |g'(r)| refers to the caller's
// coefficients), while a Taylor shift to the interval's midpoint would add rounding of
// the size of one evaluation of g at the far end, and lose roots near the caller's
// origin whenever that origin is far from the midpoint (roots 2^-k with lo = 0). The
// caller chooses its expansion point (taylor.h re-centres a ray near its span); what the
// local frame buys is |v| <= 1 (no overflow at degree 40, one relative rule for noise
// and for dropping leading coefficients) and tolerances relative to the interval.
template <class T>
struct Frame {
  T lo, hi;
  int e;                 // s = 2^e v
  bool clamped = false;  // a coefficient left T's normal range (see rangeSplit)
};

// x 2^k, exact when the result is normal. The common case (both x and the result normal)
// multiplies by a power of two built from its bits instead of calling ldexp, which is a
// library call per coefficient on the per-ray path; anything else goes to std::ldexp.
// 2^k for k in the normal exponent range, from its bits.
template <class T>
T pow2(int k) {
  if constexpr (std::is_same_v<T, double>)
    return std::bit_cast<double>(static_cast<uint64_t>(k + 1023) << 52);
  else
    return std::bit_cast<float>(static_cast<uint32_t>(k + 127) << 23);
}

template <class T>
T scale2(T x, int k) {
  using Limits = std::numeric_limits<T>;
  if (k >= Limits::min_exponent - 1 && k <= Limits::max_exponent - 1) {
    const T r = x * pow2<T>(k);
    if (std::abs(r) >= Limits::min() || r == 0) return r;
  }
  return std::ldexp(x, k);
}

// Exponent of a finite non-zero x as std::ilogb, from the bits for normal numbers.
template <class T>
int exponentOf(T x) {
  if (std::abs(x) >= std::numeric_limits<T>::min()) {
    if constexpr (std::is_same_v<T, double>)
      return static_cast<int>((std::bit_cast<uint64_t>(x) >> 52) & 0x7ff) - 1023;
    else
      return static_cast<int>((std::bit_cast<uint32_t>(x) >> 23) & 0xff) - 127;
  }
  return std::ilogb(x);
}

[[noreturn, gnu::cold, gnu::noinline]] void throwSizeError(size_t nc, size_t nerr,
                                                           const char* where) {
  if (nc > static_cast<size_t>(kMaxDegree + 1))
    throw Error(std::string(where) + ": " + std::to_string(nc) +
                " coefficients, more than degree kMaxDegree = " + std::to_string(kMaxDegree) +
                " allows");
  throw Error(std::string(where) + ": error bound has " + std::to_string(nerr) + " entries for " +
              std::to_string(nc) + " coefficients");
}

// The message building stays out of line: this runs on every ray.
template <class T>
void checkSizes(std::span<const T> c, std::span<const T> err, const char* where) {
  if (c.size() > static_cast<size_t>(kMaxDegree + 1) || (!err.empty() && err.size() != c.size()))
    throwSizeError(c.size(), err.size(), where);
}

// Fujiwara's bound with the noise of the tangent rule: with a_j = |c_j| + e_j (j < n, a_0
// halved), a_n = |c_n| - e_n, e_j = err_j + gamma(2n+1) |c_j| and
//   B = 2 max_{j<n} (a_j / a_n)^(1 / (n - j)),
// every s with |s| > B has a_n |s|^n > sum_{j<n} (|c_j| + e_j) |s|^j (each term is at most
// 2^(j-n) (B / |s|)^(n-j) of the left side, 2^(1-n) for j = 0, and these sum to 1), so |g(s)|
// exceeds the noise bound there and no root, tangent or not, lies beyond it (M. Fujiwara,
// Tohoku Math. J. 10, 1916; Knuth, TAOCP vol. 2, 4.6.2 exercise 20). Unlike Cauchy's
// 1 + max_j a_j / a_n (sessions 1-10), it is within a factor 2n of the largest root, so a
// frame cut to it fits the roots: s^40 - 2^40 on (0, 1e13] was cut to Cauchy's 1e12, where
// the constant still left the normal range, and the root 2 came back as 44762 (see
// toLocalSized). In log2 (the ratios overflow), then 1 + 2^-20 for that arithmetic's
// rounding. False when there is no bound (no non-zero lower coefficient, a noise-level
// leading one, or beyond T's range).
template <class T>
bool noisyRootBound(const T* c, int n, std::span<const T> err, T& bound) {
  const T gEval = gammaT<T>(2 * n + 1);
  auto noise = [&](int j) {
    return (err.empty() ? T(0) : std::abs(err[j])) + gEval * std::abs(c[j]);
  };
  const T lead = std::abs(c[n]) - noise(n);
  if (!(lead > 0)) return false;
  double maxLog = -std::numeric_limits<double>::infinity();
  for (int j = 0; j < n; ++j) {
    const double a = static_cast<double>(std::abs(c[j])) + static_cast<double>(noise(j));
    if (a == 0) continue;
    const double halved = j == 0 ? 1.0 : 0.0;
    maxLog =
        std::max(maxLog, (std::log2(a) - halved - std::log2(static_cast<double>(lead))) / (n - j));
  }
  const double b = std::exp2(maxLog + 1) * (1 + 0x1p-20);
  if (!(b > 0 && b <= static_cast<double>(std::numeric_limits<T>::max()))) return false;
  bound = static_cast<T>(b);
  return bound > 0;
}

// Builds G(v) = g(2^e v) / 2^E with its noise bound (roots_detail.h). Returns false when
// there can be no root: non-finite input, an empty or reversed interval, a constant or
// zero polynomial.
template <class T, class Size>
bool toLocalSized(const T* c, Size size, std::span<const T> err, T lo, T hi, LocalPoly<T>& g,
                  Frame<T>& fr, bool shrunk = false) {
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) return false;

  // ---- Frame: 2^e >= max(|lo|, |hi|) ------------------------------------------------
  // max = f 2^e with f in [0.5, 1), as std::frexp (max > 0: lo < hi)
  const int e = exponentOf(std::max(std::abs(lo), std::abs(hi))) + 1;
  fr = Frame<T>{lo, hi, e};
  g.lo = scale2(lo, -e);
  g.hi = scale2(hi, -e);
  if (!(g.lo < g.hi)) return false;  // only when lo, hi are adjacent subnormals

  // ---- Degree, finiteness and the largest exponent of c_j 2^(j e), in one pass ------
  // From the exponent field of each coefficient (all ones: inf or NaN; zero: zero or
  // subnormal, which takes the exact path of exponentOf); exponents are added as integers,
  // so no intermediate overflows. (This was a third of a cell-sized degree-6 solve as a
  // loop of library calls.)
  using Bits = std::conditional_t<std::is_same_v<T, double>, std::uint64_t, std::uint32_t>;
  constexpr int kMantissa = std::numeric_limits<T>::digits - 1;
  constexpr int kField = std::is_same_v<T, double> ? 0x7ff : 0xff, kBias = kField / 2;
  // eMin: the smallest exponent of c_j 2^(j e) over the normal non-zero c_j, which tells
  // below whether the scaling takes one below T's normal range (integer work here instead
  // of a floating-point minimum over the scaled coefficients there).
  int n = -1, eMax = std::numeric_limits<int>::min(), eMin = std::numeric_limits<int>::max();
  bool subnormal = false;
  for (int j = 0; j < static_cast<int>(size); ++j) {
    const int field = static_cast<int>((std::bit_cast<Bits>(c[j]) >> kMantissa) & kField);
    if (field == kField) return false;
    if (field == 0) {
      if (c[j] == 0) continue;
      subnormal = true;
    } else {
      eMax = std::max(eMax, field - kBias + j * e);
      eMin = std::min(eMin, field - kBias + j * e);
    }
    n = j;
  }
  if (n < 1) return false;
  if (subnormal)
    for (int j = 0; j <= n; ++j)
      if (c[j] != 0) eMax = std::max(eMax, exponentOf(c[j]) + j * e);
  // The error bounds of the coefficients above n (zero ones) are checked here; those up
  // to n through the finiteness of the noise bounds below.
  for (int j = n + 1; j < static_cast<int>(err.size()); ++j)
    if (!std::isfinite(err[j])) return false;

  // ---- Coefficients C_j = c_j 2^(j e - E), max |C_j| in [1, 2) ----------------------
  const T gEval = gammaT<T>(2 * n + 1);  // one Horner evaluation, Higham Eq. (5.3)
  // |computed G(v) - exact G(v)| <= sum_j (err_j + gamma(2n+1) |C_j|) |v|^j.
  // (err_j beyond the range of C makes a noise bound infinite or NaN: no root.)
  using Limits = std::numeric_limits<T>;
  const int s0 = -eMax, s1 = n * e - eMax;  // the shifts are monotone in j
  bool finiteNoise = true;
  bool anyBelow = true;  // whether a non-zero coefficient may have left the normal range
  T leadErr = 0;         // the caller's error of C_n
  if (std::min(s0, s1) >= Limits::min_exponent - 1 &&
      std::max(s0, s1) <= Limits::max_exponent - 1) {
    // Every factor 2^shift is a normal number: one correctly rounded product each, the
    // same result as ldexp, without its range checks.
    // (Over the compile-time count, stopping at n: the loop unrolls.) Without error bounds
    // (the random problems of roots_report) the noise bounds are finite (|C_j| < 2) and
    // the caller's error terms vanish: a loop without them (the frame was a sixth of a
    // degree-6 whole ray's instructions; with eMin, session 14: the whole solve 3-4 %
    // fewer instructions at degrees 6-12, the same roots bit for bit).
    if (err.empty()) {
      for (int j = 0; j < static_cast<int>(size); ++j) {
        if (j > n) break;
        g.c[j] = c[j] * pow2<T>(j * e - eMax);
        g.noise[j] = gEval * std::abs(g.c[j]);
      }
    } else {
      for (int j = 0; j < static_cast<int>(size); ++j) {
        if (j > n) break;
        const T p = pow2<T>(j * e - eMax);
        const T ej = std::abs(err[j]) * p;
        g.c[j] = c[j] * p;
        g.noise[j] = ej + gEval * std::abs(g.c[j]);
        finiteNoise &= g.noise[j] <= Limits::max();
        leadErr = ej;
      }
    }
    // C_j = c_j 2^(j e - eMax) is below the normal range exactly when its exponent is.
    anyBelow = subnormal || eMin - eMax < Limits::min_exponent - 1;
  } else {
    for (int j = 0; j <= n; ++j) {
      const int shift = j * e - eMax;
      const T ej = err.empty() ? T(0) : scale2(std::abs(err[j]), shift);
      g.c[j] = scale2(c[j], shift);
      g.noise[j] = ej + gEval * std::abs(g.c[j]);
      finiteNoise = finiteNoise && g.noise[j] <= Limits::max();
      leadErr = ej;
    }
  }
  if (!finiteNoise) return false;
  // Coefficients the scaling took below the normal range (a spread of more than ~2^1000
  // between the terms) are kept as +-the smallest normal number: a non-zero term still
  // counts where it dominates. (1e-300 + 1e300 v^4 has no real root; with its constant
  // flushed to 0 it had a 4-fold root at 0, which the tangent rule reported.) The change,
  // below 2^-1022 against a largest coefficient in [1, 2), is harmless only where G's terms
  // stay far above it over the whole interval; where they do not (roots spread over more
  // binades than one frame holds), the callers solve the interval in pieces (rangeSplit,
  // told by Frame::clamped).
  // (The scaling loop above tracks the smallest scaled non-zero coefficient, so this loop
  // runs only where one left the normal range: degree-6 and 8 cells 2-4 % faster.)
  bool belowRange = false;
  for (int j = 0; anyBelow && j < static_cast<int>(size); ++j)
    if (j <= n && c[j] != 0 && std::abs(g.c[j]) < Limits::min()) {
      g.c[j] = std::copysign(Limits::min(), c[j]);
      g.noise[j] = std::max(g.noise[j], gEval * Limits::min());
      belowRange = true;
    }
  // Where that happens because the interval is far wider than the roots (2^e >> the
  // root bound: x^2 - 1 on (-1e308, 1e308] made its constant the smallest normal number
  // and reported the "root" -2.7e154), the interval is first cut to the bound, beyond
  // which there is no root of any kind: then the frame fits the roots.
  if (belowRange && !shrunk) {
    T bound;
    if (noisyRootBound(c, n, err, bound) && bound < std::max(std::abs(lo), std::abs(hi))) {
      const T cutLo = std::max(lo, -bound), cutHi = std::min(hi, bound);
      return cutLo < cutHi && toLocalSized(c, size, err, cutLo, cutHi, g, fr, true);
    }
  }
  fr.clamped = belowRange;  // the callers check whether that is harmless (rangeSplit)

  // ---- Drop leading coefficients that are noise -------------------------------------
  // On [-1, 1], |C_n v^n| <= |C_n| |v|^k for k < n, so a leading coefficient with
  // |C_n| <= u max_{k<n} |C_k| changes G by less than the rounding of evaluating the
  // remaining terms anywhere in the interval; one within the caller's own error bound
  // cannot be told from zero. Either way it is dropped and its size is moved into the
  // noise bound of the new leading term (|C_n v^n| <= |C_n| |v|^(n-1)), so the tangent
  // rule still accounts for it.
  // max_k |C_k| is in [1, 2), so |C_n| > 2u passes the first test without the loop.
  if (std::abs(g.c[n]) > 2 * roots_detail::kUnit<T> && std::abs(g.c[n]) > leadErr) {
    g.n = n;
    return true;
  }
  while (n >= 1) {
    T maxLower = 0;
    for (int j = 0; j < n; ++j) maxLower = std::max(maxLower, std::abs(g.c[j]));
    const T lead = std::abs(g.c[n]);
    const T leadErrN = err.empty() ? T(0) : scale2(std::abs(err[n]), n * e - eMax);
    if (lead > roots_detail::kUnit<T> * maxLower && lead > leadErrN) break;
    g.noise[n - 1] += lead + g.noise[n];
    g.c[n] = 0;
    g.noise[n] = 0;
    --n;
  }
  g.n = n;
  return n >= 1;
}

// The frame with the coefficient count known at compile time for up to 21 coefficients
// (degree 20, the solvers' compile-time degrees): its loops unroll (a third of a
// cell-sized degree-6 solve was this function with run-time loops; perf, session 8;
// unrolled, cells of degree 6-8 took 3-6 % less time, degree 12 the same).
template <class T, int... Ss>
bool toLocalSmall(std::span<const T> c, std::span<const T> err, T lo, T hi, LocalPoly<T>& g,
                  Frame<T>& fr, std::integer_sequence<int, Ss...>) {
  bool ok = false;
  const bool matched =
      ((c.size() == Ss + 2 ? (ok = toLocalSized(c.data(), std::integral_constant<int, Ss + 2>{},
                                                err, lo, hi, g, fr),
                              true)
                           : false) ||
       ...);
  if (!matched) ok = toLocalSized(c.data(), static_cast<int>(c.size()), err, lo, hi, g, fr);
  return ok;
}

template <class T>
bool toLocal(std::span<const T> c, std::span<const T> err, T lo, T hi, LocalPoly<T>& g,
             Frame<T>& fr) {
  return toLocalSmall(c, err, lo, hi, g, fr, std::make_integer_sequence<int, 20>{});
}

// ---- Pieces of one dynamic range ------------------------------------------------------
// toLocal keeps a coefficient that its scaling takes below T's normal range as +-the
// smallest normal number. That is harmless where G's terms are far above that floor over
// the whole interval; where the polynomial's roots spread over more binades than one frame
// holds (about 1000 / n: roots near 1 and 1e8 at degree 40, near 1 and 1e16 at degree 20,
// even after the cut to the root bound), G near the smaller roots is made of terms below
// the floor, those roots vanish, and the raised constants put "roots" where the data have
// none. (A fuzz campaign of session 26 against an MPFR sign scan found it: every such
// problem answered with a relative residual ~1, the true first root missed.)
// In log2, M(t) = max_j (log2|c_j| + j t) is the size of the largest term of g at |s| =
// 2^t, within a factor n + 1 of sum |c_j| |s|^j; a frame of scale 2^e holds every term
// down to M(e) - (1022 - 106) (double) with 2^-106 to spare against the clamped floor's
// change. rangeSplit returns the split point 2^t, the smallest |s| where that still holds,
// when the interval reaches below it (|s| < 2^t); the caller then solves the pieces |s| <=
// 2^t and |s| > 2^t apart, each in its own frame (the inner one splits again if needed).
// False where one frame is enough, including every interval whose coefficients all stay
// in range (toLocal's common path does not call this).
template <class T>
int envelopeLog2(std::span<const T> c, int t) {
  int m = std::numeric_limits<int>::min();
  for (int j = 0; j < static_cast<int>(c.size()); ++j)
    if (c[j] != 0) m = std::max(m, exponentOf(c[j]) + j * t);
  return m;
}

template <class T>
bool rangeSplit(std::span<const T> c, const Frame<T>& fr, T& split) {
  using Limits = std::numeric_limits<T>;
  constexpr int kRange = -(Limits::min_exponent - 1) - 2 * Limits::digits;
  const T lo = fr.lo, hi = fr.hi;
  const int e = fr.e;
  const int top = envelopeLog2(c, e);
  // The smallest |s| of the interval: 0 where it reaches 0 (then the lowest non-zero
  // term sets the floor: the envelope's limit, or no limit for c_0 == 0).
  const bool reachesZero = lo <= 0 && hi >= 0;
  const int tMin = reachesZero ? Limits::min_exponent - Limits::digits
                               : exponentOf(std::min(std::abs(lo), std::abs(hi)));
  if (envelopeLog2(c, tMin) - top >= -kRange) return false;
  // Smallest t in (tMin, e] with M(t) >= top - kRange (M is non-decreasing in t).
  int a = tMin, b = e;  // M(a) too small, M(b) large enough
  while (b - a > 1) {
    const int m = a + (b - a) / 2;
    (envelopeLog2(c, m) - top >= -kRange ? b : a) = m;
  }
  // The inner piece's frame must be smaller (its scale is 2^(b + 1)), or a piece would
  // split into itself again; and 2^b a normal number. Each split takes at least kRange - 2n
  // binades off the largest term (M(b - 1) < top - kRange and M grows by at most n per
  // binade), so in double a piece splits at most ~50 times. In float, where kRange is 78,
  // degree 40 can leave b = e - 1 (M grew by more than kRange over the two binades below
  // 2^e); the split is then at 2^(e - 2), one binade a split: the outer piece, |s| >
  // 2^(e - 2), spans at most 2n = 80 binades of terms, still 2^46 above the clamped floor,
  // and does not split again. (It answered from the clamped frame instead: a "root" with
  // a relative residual ~1 before the true first one; the float fuzz, session 27.)
  if (b > e - 2) {
    if (tMin >= e - 2) return false;
    b = e - 2;
  }
  if (b < Limits::min_exponent) return false;
  split = std::ldexp(T(1), b);
  return true;
}

// piece(a, b, options) on the pieces of (lo, hi] at -split and split in increasing order,
// (lo, -split], (-split, split], (split, hi], each where it is not empty, with closedLo on
// the first only (a split point is the previous piece's hi), until one returns true.
template <class T, class Piece>
bool forEachPiece(T lo, T hi, T split, const RootOptions& o, Piece&& piece) {
  const T cuts[3] = {-split, split, hi};
  T a = lo;
  bool first = true;
  for (const T cut : cuts) {
    const T b = std::min(cut, hi);
    if (!(b > a)) continue;
    RootOptions oi = o;
    oi.closedLo = o.closedLo && first;
    if (piece(a, b, oi)) return true;
    first = false;
    a = b;
  }
  return false;
}

// Maps a local root back to (lo, hi] ([lo, hi] with closedLo): exact (a power of two)
// except for a root within noise of hi, which the sweep reports as the local hi itself.
template <class T>
T toCaller(const Frame<T>& fr, const LocalPoly<T>& g, const LocalRoot<T>& r) {
  if (r.v >= g.hi) return fr.hi;
  const T s = scale2(r.v, fr.e);
  if (g.closedLo) return std::max(s, fr.lo);  // [lo, hi]
  return s > fr.lo ? s : std::nextafter(fr.lo, fr.hi);
}

template <class T>
int solveLocal(const LocalPoly<T>& g, Query q, const RootOptions& o, LocalRoot<T>* out,
               int maxOut) {
  const T tol = static_cast<T>(std::max(0.0, o.relTolerance)) * (g.hi - g.lo);
  switch (o.method) {
    case RootMethod::Sturm:
      if constexpr (std::is_same_v<T, double>)
        return roots_detail::solveSturm(g, q, tol, out, maxOut);
      break;
    case RootMethod::Bernstein:
      if constexpr (std::is_same_v<T, double>)
        return roots_detail::solveBernstein(g, q, tol, out, maxOut);
      break;
    case RootMethod::Yuksel:
      return roots_detail::solveYuksel(g, q, tol, out, maxOut);
    case RootMethod::ClosedForm:  // closed forms at degrees 1-4 always, Yuksel above
      return roots_detail::solveClosedForm(g, q, tol, out, maxOut);
    case RootMethod::Auto:
      break;
  }
  // Auto: the closed forms at degrees 1-2, Yuksel's recursion from degree 3 on. At 3 and 4
  // both are equally accurate and about equally fast, Yuksel by a hair (measured: double
  // firstRoot, 2-core 2 GHz Xeon shared with other builds; roots_report --degrees 3,4
  // --problems 3000, three runs, ns ClosedForm vs Yuksel):
  //   ray  degree 3: 249, 245, 243 vs 242, 235, 235   degree 4: 338, 355, 360 vs 326, 335, 348
  //   cell degree 3: 138, 124, 139 vs 140, 123, 134   degree 4: 169, 164, 116 vs 166, 167, 108
  // errors p99 / max in u cond: ray 1.43 / 1.94 vs 1.32 / 1.87 (degree 3), 1.30 / 1.38 vs
  // 1.25 / 1.38 (degree 4), cell <= 1.16 either; no misses, no false hits. The full run
  // (400 problems per degree): ray 206 vs 191, 244 vs 219; cell 148 vs 146, 161 vs 155.
  // roots_bench (5 interleaved repetitions x 3, median): ray 235 vs 208, 382 vs 353; cell
  // 149 vs 137, 190 vs 176. The closed forms' transcendentals (acos + sin + cos, or cbrt)
  // cost about what the 3-4 Newton steps they save do, and both share the exclusion test
  // that ends most cell-sized calls. Float has no Sturm/Bernstein variant and lands here.
  // (Degrees above 4 call solveYuksel here too, not through solveClosedForm, which passes
  // them on: its prologue, set up for the closed forms before the degree test, cost every
  // solve ~32 instructions, 3.5 % of a degree-6 cell; callgrind, session 22.)
  if (g.n >= 3) return roots_detail::solveYuksel(g, q, tol, out, maxOut);
  return roots_detail::solveClosedForm(g, q, tol, out, maxOut);
}

// ---- Exact roots at 0 -----------------------------------------------------------------
// With c_0 .. c_{k-1} exactly zero and no error on them, g(s) = s^k h(s) exactly: g's
// roots are 0 and h's, and h is solved on its own. In one frame G's values between 0 and a
// root of h far below the interval's scale underflow (s^2 - 2^-540 s on (-0.5, 1]: |G| ~
// 2^-1080 between the roots, below the subnormal range in any frame with max |C_j| in
// [1, 2)), so the two roots merged; h's frame keeps them apart. The noise rules keep their
// meaning: |g(s)| <= N_g(s) = |s|^k N_h(s) exactly where |h(s)| <= N_h(s), with h's
// (smaller) Horner count in N_h. Returns k, or 0 where the rule does not apply: no exact
// zero at the bottom, the zero polynomial, or non-finite input or interval (those keep
// the general path's "no root").
template <class T>
int exactZeroOrder(std::span<const T> c, std::span<const T> err, T lo, T hi) {
  const int size = static_cast<int>(c.size());
  int k = 0;
  while (k < size && c[k] == 0 && (err.empty() || err[k] == 0)) ++k;
  if (k == 0 || k == size || !(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) return 0;
  for (int j = k; j < size; ++j)
    if (!std::isfinite(c[j]) || (!err.empty() && !std::isfinite(err[j]))) return 0;
  return k;
}

// Whether the root 0 of s^k is in the interval: (lo, hi], or [lo, hi] with closedLo.
template <class T>
bool zeroInside(T lo, T hi, bool closedLo) {
  return (closedLo ? lo <= 0 : lo < 0) && 0 <= hi;
}

template <class T>
std::span<const T> withoutFirst(std::span<const T> s, int k) {
  return s.empty() ? s : s.subspan(static_cast<size_t>(k));
}

// The general path: one frame for the whole polynomial, or, where toLocal had to clamp a
// coefficient and one frame cannot hold the interval (rangeSplit), the pieces of
// forEachPiece in increasing order, each by the general path again. The pieces' path is
// out of line and cold, the common one keeps a test of Frame::clamped (callgrind, session
// 26: a degree-6 cell 930 -> 950 instructions, as with the pieces written inline;
// interleaved times within noise).
// atNoise, where given, receives whether the root came from the noise rules (a tangent
// root or an end within noise: LocalRoot::tangent) rather than from a sign change.
template <class T>
bool firstRootInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, T& root,
                      const RootOptions& o, bool* atNoise);

template <class T>
bool firstRootOf(LocalPoly<T>& g, const Frame<T>& fr, T& root, const RootOptions& o,
                 bool* atNoise) {
  g.closedLo = o.closedLo;
  if (atNoise && o.noiseBefore) g.window = T(0x1p-20) * (g.hi - g.lo);
  LocalRoot<T> r[1];
  if (solveLocal(g, Query::First, o, r, 1) == 0) return false;
  root = toCaller(fr, g, r[0]);
  if (atNoise) *atNoise = r[0].tangent;
  return true;
}

template <class T>
[[gnu::noinline, gnu::cold]] bool firstRootClamped(std::span<const T> c, std::span<const T> err,
                                                   LocalPoly<T>& g, const Frame<T>& fr, T& root,
                                                   const RootOptions& o, bool* atNoise) {
  T split;
  if (!rangeSplit(c, fr, split)) return firstRootOf(g, fr, root, o, atNoise);
  return forEachPiece(fr.lo, fr.hi, split, o, [&](T a, T b, const RootOptions& oi) {
    return firstRootInFrame(c, err, a, b, root, oi, atNoise);
  });
}

template <class T>
bool firstRootInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, T& root,
                      const RootOptions& o, bool* atNoise) {
  LocalPoly<T> g;
  Frame<T> fr;
  if (!toLocal(c, err, lo, hi, g, fr)) return false;
  if (fr.clamped) [[unlikely]]
    return firstRootClamped(c, err, g, fr, root, o, atNoise);
  return firstRootOf(g, fr, root, o, atNoise);
}

template <class T>
bool hasRootInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, const RootOptions& o);

template <class T>
bool hasRootOf(LocalPoly<T>& g, const RootOptions& o) {
  g.closedLo = o.closedLo;
  LocalRoot<T> r[1];
  return solveLocal(g, Query::Any, o, r, 1) > 0;
}

template <class T>
[[gnu::noinline, gnu::cold]] bool hasRootClamped(std::span<const T> c, std::span<const T> err,
                                                 LocalPoly<T>& g, const Frame<T>& fr,
                                                 const RootOptions& o) {
  T split;
  if (!rangeSplit(c, fr, split)) return hasRootOf(g, o);
  return forEachPiece(fr.lo, fr.hi, split, o, [&](T a, T b, const RootOptions& oi) {
    return hasRootInFrame(c, err, a, b, oi);
  });
}

template <class T>
bool hasRootInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi,
                    const RootOptions& o) {
  LocalPoly<T> g;
  Frame<T> fr;
  if (!toLocal(c, err, lo, hi, g, fr)) return false;
  if (fr.clamped) [[unlikely]]
    return hasRootClamped(c, err, g, fr, o);
  return hasRootOf(g, o);
}

template <class T>
int allRootsInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, std::span<T> out,
                    const RootOptions& options);

template <class T>
int allRootsOf(LocalPoly<T>& g, const Frame<T>& fr, std::span<T> out, const RootOptions& options) {
  g.closedLo = options.closedLo;
  LocalRoot<T> r[kMaxDegree + 1];
  const int maxOut = static_cast<int>(std::min<size_t>(out.size(), kMaxDegree + 1));
  const int k = solveLocal(g, Query::All, options, r, maxOut);
  // The sweep returns roots in increasing order; the clamping into (lo, hi] could merge
  // two of them: keep the output strictly increasing.
  int m = 0;
  for (int i = 0; i < k; ++i) {
    const T s = toCaller(fr, g, r[i]);
    if (m > 0 && s <= out[m - 1]) continue;
    out[m++] = s;
  }
  return m;
}

template <class T>
[[gnu::noinline, gnu::cold]] int allRootsClamped(std::span<const T> c, std::span<const T> err,
                                                 LocalPoly<T>& g, const Frame<T>& fr,
                                                 std::span<T> out, const RootOptions& options) {
  T split;
  if (!rangeSplit(c, fr, split)) return allRootsOf(g, fr, out, options);
  int m = 0;
  forEachPiece(fr.lo, fr.hi, split, options, [&](T a, T b, const RootOptions& oi) {
    const int mi = allRootsInFrame(c, err, a, b, out.subspan(m), oi);
    int w = m;  // strictly increasing across the split points too
    for (int j = 0; j < mi; ++j)
      if (w == 0 || out[m + j] > out[w - 1]) out[w++] = out[m + j];
    m = w;
    return m == static_cast<int>(out.size());  // full
  });
  return m;
}

template <class T>
int allRootsInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, std::span<T> out,
                    const RootOptions& options) {
  LocalPoly<T> g;
  Frame<T> fr;
  if (!toLocal(c, err, lo, hi, g, fr)) return 0;
  if (fr.clamped) [[unlikely]]
    return allRootsClamped(c, err, g, fr, out, options);
  return allRootsOf(g, fr, out, options);
}

// g = s^k h: 0 and h's roots (h(0) = c_k != 0, so h takes the general path). Out of line:
// only c_0 == 0 comes here, and the common path keeps one comparison.
template <class T>
[[gnu::noinline]] bool firstRootFactored(std::span<const T> c, std::span<const T> err, T lo, T hi,
                                         T& root, const RootOptions& o, bool* atNoise) {
  const int k = exactZeroOrder(c, err, lo, hi);
  if (k == 0) return firstRootInFrame(c, err, lo, hi, root, o, atNoise);
  T r;
  const bool found = firstRootInFrame(c.subspan(k), withoutFirst(err, k), lo, hi, r, o, atNoise);
  if (zeroInside(lo, hi, o.closedLo) && !(found && r < 0)) {
    root = 0;  // exact
    if (atNoise) *atNoise = false;
    return true;
  }
  if (found) root = r;
  return found;
}

template <class T>
[[gnu::noinline]] bool hasRootFactored(std::span<const T> c, std::span<const T> err, T lo, T hi,
                                       const RootOptions& o) {
  const int k = exactZeroOrder(c, err, lo, hi);
  if (k == 0) return hasRootInFrame(c, err, lo, hi, o);
  return zeroInside(lo, hi, o.closedLo) ||
         hasRootInFrame(c.subspan(k), withoutFirst(err, k), lo, hi, o);
}

template <class T>
[[gnu::noinline]] int allRootsFactored(std::span<const T> c, std::span<const T> err, T lo, T hi,
                                       std::span<T> out, const RootOptions& options) {
  const int k = exactZeroOrder(c, err, lo, hi);
  if (k == 0) return allRootsInFrame(c, err, lo, hi, out, options);
  // h's roots in order, with 0 put in its place (a root of h within its noise bound of 0
  // may come back as 0 itself: reported once).
  const int maxOut = static_cast<int>(std::min<size_t>(out.size(), kMaxDegree + 1));
  T h[kMaxDegree + 1];
  const int nh =
      allRootsInFrame(c.subspan(k), withoutFirst(err, k), lo, hi, std::span<T>(h, maxOut), options);
  bool zeroPending = zeroInside(lo, hi, options.closedLo);
  int m = 0;
  for (int i = 0; i < nh && m < maxOut; ++i) {
    if (zeroPending && h[i] >= 0) {
      out[m++] = 0;
      zeroPending = false;
      if (h[i] == 0 || m == maxOut) continue;
    }
    out[m++] = h[i];
  }
  if (zeroPending && m < maxOut) out[m++] = 0;
  return m;
}

template <class T>
bool firstRootT(std::span<const T> c, std::span<const T> err, T lo, T hi, T& root,
                const RootOptions& o, bool* atNoise = nullptr) {
  checkSizes(c, err, "firstRoot");
  if (!c.empty() && c[0] == 0) return firstRootFactored(c, err, lo, hi, root, o, atNoise);
  return firstRootInFrame(c, err, lo, hi, root, o, atNoise);
}

template <class T>
bool hasRootT(std::span<const T> c, std::span<const T> err, T lo, T hi, const RootOptions& o) {
  checkSizes(c, err, "hasRoot");
  if (!c.empty() && c[0] == 0) return hasRootFactored(c, err, lo, hi, o);
  return hasRootInFrame(c, err, lo, hi, o);
}

template <class T>
int allRootsT(std::span<const T> c, std::span<const T> err, T lo, T hi, std::span<T> out,
              const RootOptions& options) {
  checkSizes(c, err, "allRoots");
  if (out.empty()) return 0;
  if (!c.empty() && c[0] == 0) return allRootsFactored(c, err, lo, hi, out, options);
  return allRootsInFrame(c, err, lo, hi, out, options);
}

}  // namespace

bool solveFirstRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
                    double& root, const RootOptions& options) {
  return firstRootT(c, err, lo, hi, root, options);
}

bool solveFirstRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
                    double& root, bool& atNoise, const RootOptions& options) {
  return firstRootT(c, err, lo, hi, root, options, &atNoise);
}

bool hasRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
             const RootOptions& options) {
  return hasRootT(c, err, lo, hi, options);
}

int allRoots(std::span<const double> c, std::span<const double> err, double lo, double hi,
             std::span<double> out, const RootOptions& options) {
  return allRootsT(c, err, lo, hi, out, options);
}

bool solveFirstRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
                    float& root, const RootOptions& options) {
  return firstRootT(c, err, lo, hi, root, options);
}

bool solveFirstRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
                    float& root, bool& atNoise, const RootOptions& options) {
  return firstRootT(c, err, lo, hi, root, options, &atNoise);
}

bool hasRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
             const RootOptions& options) {
  return hasRootT(c, err, lo, hi, options);
}

int allRoots(std::span<const float> c, std::span<const float> err, float lo, float hi,
             std::span<float> out, const RootOptions& options) {
  return allRootsT(c, err, lo, hi, out, options);
}

}  // namespace algray
