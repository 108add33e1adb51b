#pragma once
// The caller's frame of roots.cpp: the map of g(s) on (lo, hi] to G(v) = g(2^e v) / 2^E
// on a local interval within [-1, 1] (exact: a power-of-two scaling), with G's noise
// bound and its leading coefficients that are noise dropped; the split of an interval
// whose terms span more binades than one frame holds (rangeSplit); and the map of a local
// root back (toCaller). Only roots.cpp includes it (the public entry points map every
// query through it).
#include "roots_detail.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <utility>

namespace algray::roots_detail {

// The binades of terms one frame holds (rangeSplit below): the normal range less 2^-2p to
// spare, 916 in double, 78 in float.
template <class T>
constexpr int kFrameRange = -(std::numeric_limits<T>::min_exponent - 1) -
                            2 * std::numeric_limits<T>::digits;

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
  bool clamped = false;  // a coefficient left T's normal range or kFrameRange (rangeSplit)
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
// rounding, and upwards on the subnormal grid, where rounding is absolute: a degree-1
// bound is the root itself, and -1000 2^-1074 + 3 s on (0, 1] was cut to 333 2^-1074, below
// its root 333.33 2^-1074, which no query then found. False when there is no bound (no
// non-zero lower coefficient, a noise-level leading one, or beyond T's range).
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
  const double b =
      std::exp2(maxLog + 1) * (1 + 0x1p-20) + 4 * std::numeric_limits<double>::denorm_min();
  if (!(b > 0 && b <= static_cast<double>(std::numeric_limits<T>::max()))) return false;
  bound = static_cast<T>(b);
  if (static_cast<double>(bound) < b) bound = std::nextafter(bound, std::numeric_limits<T>::max());
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
  bool wide = true;      // whether one may lie beyond the frame's range (kFrameRange)
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
    wide = anyBelow || eMin - eMax < -kFrameRange<T>;
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
  // The callers check whether that is harmless (rangeSplit), and so where a coefficient is
  // still normal but beyond the frame's range: G is then made of terms near the subnormal
  // range about the smaller roots (a root at 1e-114 of a quintic whose other roots reach
  // 1e117, on (0, 1e118]: its piece (0, 2^-66] held c_0 at 2^-1005 of the largest term, and
  // the root was lost; session 52's audit).
  fr.clamped = belowRange || wide;

  // ---- The caller's grid, where it is coarser than the frame's ------------------------
  // An answer v goes back as v 2^e rounded to T, whose grid below the normal range is
  // absolute (T's smallest subnormal, 2^-1074 in double): a frame that low steps by
  // 2^-1074-e in v, which near v = 0 can be far more than its own u |v|. |G'| <= sum_j j
  // |C_j| over |v| <= 1, so G at the answer the caller gets is off by up to that step times
  // it, which joins the noise bound: then from the answer a walk's next query sees it
  // within noise at its lo (the root 72.2 2^-1074 of -354 2^-1074 + 4.9 s - 2.46 s^2 came
  // back as 72 2^-1074, and from there as 73 2^-1074: one root twice). Only for frames whose
  // step is a normal number (e <= -52 in double, from intervals below 2^-52): elsewhere it
  // is below the smallest normal number, where G's own noise bound is far larger unless G
  // is that small, and the subnormal arithmetic is slow.
  // Only where the interval reaches T's subnormal range, and with the slope over that part
  // of it, |v| <= w = 2^(-1022 - e): elsewhere the caller's grid is relative, u |s|, which
  // G's noise bound covers. (With the slope over the whole frame, and on intervals away
  // from 0, the step in noise[0] made G "within noise" where g is far from 0: at the far
  // end of a piece of rangeSplit, and at 0 beside roots near 1e-187; session 52's review.)
  constexpr int kSubnormalStep = Limits::min_exponent - Limits::digits;  // log2 denorm_min
  if (e <= kSubnormalStep - (Limits::min_exponent - 1) && lo < Limits::min() && hi > -Limits::min())
      [[unlikely]] {
    const T w = std::min(T(1), scale2(T(1), Limits::min_exponent - 1 - e));
    T slope = 0;  // sum_j j |C_j| w^(j-1), by Horner in w
    for (int j = n; j >= 1; --j) slope = slope * w + T(j) * std::abs(g.c[j]);
    g.noise[0] += scale2(Limits::denorm_min(), -e) * slope;
  }

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
  constexpr int kRange = kFrameRange<T>;
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

// Maps a local root back to (lo, hi] ([lo, hi] with closedLo): exact (a power of two)
// except for a root within noise of hi, which the sweep reports as the local hi itself.
template <class T>
T toCaller(const Frame<T>& fr, const LocalPoly<T>& g, const LocalRoot<T>& r) {
  if (r.v >= g.hi) return fr.hi;
  const T s = scale2(r.v, fr.e);
  if (g.closedLo) return std::max(s, fr.lo);  // [lo, hi]
  return s > fr.lo ? s : std::nextafter(fr.lo, fr.hi);
}

}  // namespace algray::roots_detail
