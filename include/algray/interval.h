#pragma once
// Interval: a closed range [lo, hi] of reals with conservatively rounded arithmetic.
//
// Model: pbrt-v4's Interval (util/float.h). Every operation computes its bounds in
// round-to-nearest double and then moves each bound outward. Round-to-nearest is off by
// at most half an ulp, i.e. |x - exact| <= 2^-53 |x| for a normal result x (Higham,
// "Accuracy and Stability of Numerical Algorithms", Sec. 2.2), so the widened result
// contains the exact real result of the operation on any reals in the operands.
//
// The outward step: pbrt steps one ulp with NextFloatUp/Down (bit manipulation and
// branches). Here a bound moves by 2^-51 |x| instead (two to four ulps: x + 2^-51|x|
// rounds to at least x + ulp(x) >= x + 2^-53|x|), which is branch-free: the cell builder
// (cells.cpp) spends nearly all its time in these operations, and the branchy version
// measured ~3x slower there. Exceptions, for correctness and speed:
//  * A result of 0 is kept exact when it provably is: a rounded sum is 0 only if the
//    exact sum is (Hauser, "Handling floating-point exceptions in numeric programs",
//    TOPLAS 1996: with gradual underflow x + y never rounds to 0; subnormal sums are
//    exact), and a product is exactly 0 iff a factor is. This keeps the many zero
//    coefficients of sparse polynomials exact; widening them would create subnormal
//    bounds, and subnormal arithmetic is ~100x slower on x86.
//  * A non-zero product may underflow: it is widened by the smallest subnormal too.
//
// Non-finite values: bounds may overflow to +-inf, which stays conservative. A NaN bound
// (from inf - inf) makes every comparison false; callers that prune on a bound must
// therefore test "provably empty" (a comparison that is false for NaN), never "possibly
// non-empty".
// C++20 (std::span, std::bit_cast, concepts): older dialects fail here, by name, not deep
// inside a header (a C++17 consumer's first error was polynomial.h's std::span).
#if __cplusplus < 202002L
#error "algray needs C++20 (-std=c++20; CMake consumers get it from algray::algray)"
#endif

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace algray {

// The next double above / below v (v itself for +inf / -inf and NaN). Bit arithmetic
// instead of std::nextafter: the cell builder calls these in its innermost loop.
inline double nextUp(double v) {
  if (!(v < std::numeric_limits<double>::infinity())) return v;    // +inf or NaN
  if (v == 0.0) return std::numeric_limits<double>::denorm_min();  // +0 and -0
  auto bits = std::bit_cast<std::uint64_t>(v);
  bits = v > 0 ? bits + 1 : bits - 1;  // sign-magnitude: away from 0 when positive
  return std::bit_cast<double>(bits);
}
inline double nextDown(double v) { return -nextUp(-v); }

class Interval {
 public:
  constexpr Interval() = default;  // [0, 0]
  constexpr explicit Interval(double v) : lo_(v), hi_(v) {}
  // The bounds may be given in either order.
  constexpr Interval(double a, double b) : lo_(std::min(a, b)), hi_(std::max(a, b)) {}
  // [v - err, v + err] rounded outward: a computed value with an absolute error bound.
  static Interval fromValueAndError(double v, double err) {
    return fromBounds(sumDown(v - err), sumUp(v + err));
  }

  double lower() const { return lo_; }
  double upper() const { return hi_; }
  double midpoint() const { return 0.5 * lo_ + 0.5 * hi_; }  // no overflow for huge bounds
  // Upper bound on hi - lo.
  double width() const { return nextUp(hi_ - lo_); }
  // max |x| over the interval.
  double magnitude() const { return std::max(std::abs(lo_), std::abs(hi_)); }
  // min |x| over the interval (0 if it contains 0).
  double mignitude() const { return containsZero() ? 0.0 : std::min(std::abs(lo_), std::abs(hi_)); }

  bool contains(double v) const { return lo_ <= v && v <= hi_; }
  bool containsZero() const { return lo_ <= 0.0 && 0.0 <= hi_; }
  bool isFinite() const { return std::isfinite(lo_) && std::isfinite(hi_); }
  // True if the two intervals share a point.
  bool overlaps(const Interval& o) const { return lo_ <= o.hi_ && o.lo_ <= hi_; }

  Interval operator-() const { return Interval(-hi_, -lo_); }  // exact

  Interval& operator+=(const Interval& o) { return *this = *this + o; }
  Interval& operator-=(const Interval& o) { return *this = *this - o; }
  Interval& operator*=(const Interval& o) { return *this = *this * o; }
  Interval& operator*=(double s) { return *this = *this * s; }

  friend Interval operator+(const Interval& a, const Interval& b) {
    return fromBounds(sumDown(a.lo_ + b.lo_), sumUp(a.hi_ + b.hi_));
  }
  friend Interval operator-(const Interval& a, const Interval& b) {
    return fromBounds(sumDown(a.lo_ - b.hi_), sumUp(a.hi_ - b.lo_));
  }
  friend Interval operator*(const Interval& a, const Interval& b) {
    // The extremes of a bilinear function lie at the corners.
    const double lo = std::min({productDown(a.lo_, b.lo_), productDown(a.lo_, b.hi_),
                                productDown(a.hi_, b.lo_), productDown(a.hi_, b.hi_)});
    const double hi = std::max({productUp(a.lo_, b.lo_), productUp(a.lo_, b.hi_),
                                productUp(a.hi_, b.lo_), productUp(a.hi_, b.hi_)});
    return fromBounds(lo, hi);
  }
  // Scaling by a point value: two products instead of four.
  friend Interval operator*(const Interval& a, double s) {
    return s >= 0 ? fromBounds(productDown(a.lo_, s), productUp(a.hi_, s))
                  : fromBounds(productDown(a.hi_, s), productUp(a.lo_, s));
  }
  friend Interval operator*(double s, const Interval& a) { return a * s; }
  friend Interval operator+(const Interval& a, double s) { return a + Interval(s); }
  friend Interval operator+(double s, const Interval& a) { return a + Interval(s); }
  friend Interval operator-(const Interval& a, double s) { return a - Interval(s); }
  friend Interval operator-(double s, const Interval& a) { return Interval(s) - a; }

  // Smallest interval containing both.
  friend Interval hull(const Interval& a, const Interval& b) {
    return fromBounds(std::min(a.lo_, b.lo_), std::max(a.hi_, b.hi_));
  }
  friend Interval abs(const Interval& a) {
    if (a.lo_ >= 0) return a;
    if (a.hi_ <= 0) return -a;
    return fromBounds(0.0, std::max(-a.lo_, a.hi_));
  }
  // x^2 is never negative: tighter than a * a when a contains 0 (the dependency problem).
  friend Interval square(const Interval& a) {
    const Interval m = abs(a);
    return fromBounds(m.lo_ == 0.0 ? 0.0 : nextDown(m.lo_ * m.lo_), nextUp(m.hi_ * m.hi_));
  }
  // x^n for n >= 0 by binary powering of |x| (monotone on [0, inf)); odd powers keep the
  // sign. Each multiplication widens by one ulp, so the result is conservative.
  friend Interval pow(const Interval& a, int n) {
    if (n <= 0) return Interval(1.0);
    if (n == 1) return a;
    const bool even = (n % 2) == 0;
    if (!even) {
      // Odd powers are monotone increasing: bound each end separately.
      return fromBounds(powLower(a.lo_, n), powUpper(a.hi_, n));
    }
    const Interval m = abs(a);
    return fromBounds(m.lo_ == 0.0 ? 0.0 : powLower(m.lo_, n), powUpper(m.hi_, n));
  }

  friend bool operator==(const Interval& a, const Interval& b) {
    return a.lo_ == b.lo_ && a.hi_ == b.hi_;
  }

 private:
  // Outward rounding of one computed sum / product (see the notes at the top). The
  // std::max / std::min keep +-inf bounds (inf - inf would be NaN) and compile to one
  // maxsd / minsd.
  static constexpr double kWiden = 0x1p-51;
  static double sumUp(double s) { return std::max(s, s + std::abs(s) * kWiden); }
  static double sumDown(double s) { return std::min(s, s - std::abs(s) * kWiden); }
  // A zero factor gives an exact 0 (also against an infinite bound: every real times 0).
  static double productUp(double x, double y) {
    const bool nonZero = (x != 0.0) & (y != 0.0);
    const double p = nonZero ? x * y : 0.0;
    const double tiny = nonZero ? std::numeric_limits<double>::denorm_min() : 0.0;
    return std::max(p, p + (std::abs(p) * kWiden + tiny));
  }
  static double productDown(double x, double y) {
    const bool nonZero = (x != 0.0) & (y != 0.0);
    const double p = nonZero ? x * y : 0.0;
    const double tiny = nonZero ? std::numeric_limits<double>::denorm_min() : 0.0;
    return std::min(p, p - (std::abs(p) * kWiden + tiny));
  }

  static constexpr Interval fromBounds(double lo, double hi) {
    Interval r;
    r.lo_ = lo;
    r.hi_ = hi;
    return r;
  }
  // Lower / upper bound of x^n (x any sign, n >= 1) by repeated squaring; for x < 0 and
  // odd n the bounds of |x|^n swap roles.
  static double powLower(double x, int n) { return x >= 0 ? powDown(x, n) : -powUp(-x, n); }
  static double powUpper(double x, int n) { return x >= 0 ? powUp(x, n) : -powDown(-x, n); }
  // x >= 0: a value <= x^n (powDown) / >= x^n (powUp).
  static double powUp(double x, int n) {
    double r = 1.0, b = x;
    for (; n > 0; n >>= 1) {
      if (n & 1) r = nextUp(r * b);
      if (n > 1) b = nextUp(b * b);
    }
    return r;
  }
  static double powDown(double x, int n) {
    double r = 1.0, b = x;
    for (; n > 0; n >>= 1) {
      if (n & 1) r = std::max(0.0, nextDown(r * b));
      if (n > 1) b = std::max(0.0, nextDown(b * b));
    }
    return r;
  }

  double lo_ = 0;
  double hi_ = 0;
};

}  // namespace algray
