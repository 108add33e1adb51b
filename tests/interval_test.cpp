// Interval arithmetic (interval.h) against exact references: std::nextafter for the ulp
// steps, MPFR at a precision where sums and products of doubles are exact for the
// operations, and closed-form identities for square and pow.
#include "algray/interval.h"

#include <gtest/gtest.h>
#include <mpfr.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace algray {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// An MPFR number wide enough that every sum, difference and product of two doubles, and
// every power x^n (n <= 40) of a double, is exact: 40 * 53 bits of mantissa plus the
// exponent span of the sums of doubles in [2^-300, 2^300].
class Exact {
 public:
  Exact() { mpfr_init2(v_, 4096); }
  explicit Exact(double d) : Exact() { mpfr_set_d(v_, d, MPFR_RNDN); }
  ~Exact() { mpfr_clear(v_); }
  Exact(const Exact& o) : Exact() { mpfr_set(v_, o.v_, MPFR_RNDN); }
  Exact& operator=(const Exact& o) {
    mpfr_set(v_, o.v_, MPFR_RNDN);
    return *this;
  }
  friend Exact operator+(const Exact& a, const Exact& b) { return op(mpfr_add, a, b); }
  friend Exact operator-(const Exact& a, const Exact& b) { return op(mpfr_sub, a, b); }
  friend Exact operator*(const Exact& a, const Exact& b) { return op(mpfr_mul, a, b); }
  Exact pow(int n) const {
    Exact r;
    mpfr_pow_si(r.v_, v_, n, MPFR_RNDN);
    return r;
  }
  // -1, 0, +1 as this compares with d.
  int cmp(double d) const { return mpfr_cmp_d(v_, d); }
  bool inside(const Interval& i) const { return cmp(i.lower()) >= 0 && cmp(i.upper()) <= 0; }
  double toDouble() const { return mpfr_get_d(v_, MPFR_RNDN); }

 private:
  template <class Fn>
  static Exact op(Fn fn, const Exact& a, const Exact& b) {
    Exact r;
    fn(r.v_, a.v_, b.v_, MPFR_RNDN);
    return r;
  }
  mpfr_t v_;
};

// Random doubles of both signs over a wide exponent range, with some exact zeros and
// small integers (the cases where exact results hit interval bounds).
class RandomDoubles {
 public:
  explicit RandomDoubles(unsigned seed) : rng_(seed) {}
  double next(int minExp = -60, int maxExp = 60) {
    const int kind = std::uniform_int_distribution<int>(0, 9)(rng_);
    if (kind == 0) return 0.0;
    if (kind == 1) return std::uniform_int_distribution<int>(-8, 8)(rng_);
    const double m = std::uniform_real_distribution<double>(1.0, 2.0)(rng_);
    const int e = std::uniform_int_distribution<int>(minExp, maxExp)(rng_);
    return (rng_() & 1 ? -1.0 : 1.0) * std::ldexp(m, e);
  }
  Interval interval(int minExp = -60, int maxExp = 60) {
    return Interval(next(minExp, maxExp), next(minExp, maxExp));
  }
  // A point of [i.lower(), i.upper()].
  double inside(const Interval& i) {
    const double t = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
    return std::clamp(i.lower() + t * (i.upper() - i.lower()), i.lower(), i.upper());
  }

 private:
  std::mt19937_64 rng_;
};

// ulps between two finite doubles of the same sign (how far a bound is from exact).
double ulpsApart(double a, double b) {
  return std::abs(a - b) / std::max(std::nextafter(std::abs(b), kInf) - std::abs(b),
                                    std::numeric_limits<double>::denorm_min());
}

TEST(IntervalTest, NextUpDownMatchNextafter) {
  std::vector<double> special = {0.0,
                                 -0.0,
                                 std::numeric_limits<double>::denorm_min(),
                                 -std::numeric_limits<double>::denorm_min(),
                                 std::numeric_limits<double>::min(),
                                 std::numeric_limits<double>::max(),
                                 -std::numeric_limits<double>::max(),
                                 1.0,
                                 -1.0,
                                 0.5,
                                 -2.0};
  RandomDoubles rnd(1);
  for (int i = 0; i < 10000; ++i) special.push_back(rnd.next(-1074, 1023));
  for (double v : special) {
    EXPECT_EQ(nextUp(v), std::nextafter(v, kInf)) << v;
    EXPECT_EQ(nextDown(v), std::nextafter(v, -kInf)) << v;
  }
  EXPECT_EQ(nextUp(kInf), kInf);
  EXPECT_EQ(nextDown(-kInf), -kInf);
  EXPECT_TRUE(std::isnan(nextUp(std::nan(""))));
}

TEST(IntervalTest, BasicQueries) {
  const Interval a(3.0, -1.0);  // either order
  EXPECT_EQ(a.lower(), -1.0);
  EXPECT_EQ(a.upper(), 3.0);
  EXPECT_EQ(a.midpoint(), 1.0);
  EXPECT_GE(a.width(), 4.0);
  EXPECT_TRUE(a.contains(-1.0) && a.contains(3.0) && a.contains(0.0));
  EXPECT_FALSE(a.contains(3.0000001));
  EXPECT_TRUE(a.containsZero());
  EXPECT_EQ(a.magnitude(), 3.0);
  EXPECT_EQ(a.mignitude(), 0.0);
  EXPECT_EQ(Interval(2.0, 5.0).mignitude(), 2.0);
  EXPECT_EQ(hull(Interval(1.0, 2.0), Interval(4.0, 5.0)), Interval(1.0, 5.0));
  EXPECT_EQ(abs(Interval(-3.0, 2.0)), Interval(0.0, 3.0));
  EXPECT_EQ(abs(Interval(-3.0, -2.0)), Interval(2.0, 3.0));
  EXPECT_TRUE(Interval(1.0, 2.0).overlaps(Interval(2.0, 3.0)));
  EXPECT_FALSE(Interval(1.0, 2.0).overlaps(Interval(2.5, 3.0)));
  const Interval e = Interval::fromValueAndError(1.0, 0.25);
  EXPECT_LT(e.lower(), 0.75);
  EXPECT_GT(e.upper(), 1.25);
}

// For + - *: the extremes over a box of operands are at its corners, so containing the
// exact corner results (and a few interior points) is containment for all operands.
TEST(IntervalTest, ArithmeticContainsExactResults) {
  RandomDoubles rnd(2);
  for (int trial = 0; trial < 20000; ++trial) {
    const Interval a = rnd.interval(), b = rnd.interval();
    const Interval sum = a + b, diff = a - b, prod = a * b;
    const double s = rnd.next();
    const Interval scaled = a * s;
    std::vector<double> xs = {a.lower(), a.upper(), rnd.inside(a)};
    std::vector<double> ys = {b.lower(), b.upper(), rnd.inside(b)};
    for (double x : xs) {
      for (double y : ys) {
        const Exact ex(x), ey(y);
        ASSERT_TRUE((ex + ey).inside(sum)) << x << " + " << y;
        ASSERT_TRUE((ex - ey).inside(diff)) << x << " - " << y;
        ASSERT_TRUE((ex * ey).inside(prod)) << x << " * " << y;
      }
      ASSERT_TRUE((Exact(x) * Exact(s)).inside(scaled)) << x << " * " << s;
    }
  }
}

// Conservative but not loose: each bound is within 5 ulps of the exact extreme (half an
// ulp for round-to-nearest, at most four for the outward step of 2^-51 relative).
TEST(IntervalTest, ArithmeticIsTight) {
  RandomDoubles rnd(3);
  for (int trial = 0; trial < 5000; ++trial) {
    const Interval a = rnd.interval(-20, 20), b = rnd.interval(-20, 20);
    const Interval prod = a * b;
    double exactLo = kInf, exactHi = -kInf;
    for (double x : {a.lower(), a.upper()})
      for (double y : {b.lower(), b.upper()}) {
        const double p = (Exact(x) * Exact(y)).toDouble();
        exactLo = std::min(exactLo, p);
        exactHi = std::max(exactHi, p);
      }
    if (exactLo != 0) {
      EXPECT_LE(ulpsApart(prod.lower(), exactLo), 5.0);
    }
    if (exactHi != 0) {
      EXPECT_LE(ulpsApart(prod.upper(), exactHi), 5.0);
    }
    const Interval sum = a + b;
    const double sLo = (Exact(a.lower()) + Exact(b.lower())).toDouble();
    if (sLo != 0) {
      EXPECT_LE(ulpsApart(sum.lower(), sLo), 5.0);
    }
  }
}

TEST(IntervalTest, SquareIsNonNegativeAndContainsExact) {
  RandomDoubles rnd(4);
  // The dependency problem: a * a of [-2, 3] is [-6, 9], square is [0, 9].
  EXPECT_LT((Interval(-2.0, 3.0) * Interval(-2.0, 3.0)).lower(), 0.0);
  EXPECT_EQ(square(Interval(-2.0, 3.0)).lower(), 0.0);
  EXPECT_GE(square(Interval(-2.0, 3.0)).upper(), 9.0);
  for (int trial = 0; trial < 10000; ++trial) {
    const Interval a = rnd.interval();
    const Interval sq = square(a);
    EXPECT_GE(sq.lower(), 0.0);
    for (double x : {a.lower(), a.upper(), rnd.inside(a)})
      ASSERT_TRUE((Exact(x) * Exact(x)).inside(sq)) << x;
    if (a.containsZero()) {
      EXPECT_EQ(sq.lower(), 0.0);
    }
  }
}

TEST(IntervalTest, PowContainsExactPowers) {
  RandomDoubles rnd(5);
  for (int trial = 0; trial < 4000; ++trial) {
    const Interval a = rnd.interval(-6, 6);
    for (int n : {0, 1, 2, 3, 4, 5, 7, 8, 12, 21, 40}) {
      const Interval p = pow(a, n);
      std::vector<double> xs = {a.lower(), a.upper(), rnd.inside(a)};
      if (a.containsZero()) xs.push_back(0.0);
      for (double x : xs) ASSERT_TRUE(Exact(x).pow(n).inside(p)) << x << "^" << n;
      if (n % 2 == 0) {
        EXPECT_GE(p.lower(), 0.0);
      }
      // Tight: the bound at the larger end is within ~2 ulps per multiplication.
      const double m = a.magnitude();
      if (m > 0 && n > 0) {
        const double exact = Exact(m).pow(n).toDouble();
        const double hi = n % 2 == 0 || a.upper() == m ? p.upper() : -p.lower();
        EXPECT_LE(std::abs(hi - exact), 4.0 * n * 0x1p-52 * exact) << m << "^" << n;
      }
    }
  }
}

TEST(IntervalTest, NonFiniteNeverHangsAndStaysConservative) {
  const Interval big(1e300, 1e308);
  const Interval overflow = big * big;
  EXPECT_EQ(overflow.upper(), kInf);
  EXPECT_FALSE(overflow.isFinite());
  const Interval inf(-kInf, kInf);
  EXPECT_EQ(inf * Interval(0.0), Interval(0.0));       // every real times 0
  const Interval r = Interval(kInf) - Interval(kInf);  // NaN bounds, no crash
  EXPECT_FALSE(r.lower() > 0.0);  // NaN compares false: never "proves" anything
  EXPECT_FALSE(r.upper() < 0.0);
  EXPECT_FALSE(pow(inf, 40).isFinite());
}

// Exact zeros stay exact (a rounded sum is 0 only if exact; a product with a zero factor
// is 0), other results are widened.
TEST(IntervalTest, ExactZerosStayExact) {
  EXPECT_EQ(Interval(0.0) + Interval(0.0), Interval(0.0));
  EXPECT_EQ(Interval(1.5) - Interval(1.5), Interval(0.0));
  EXPECT_EQ(Interval(0.0) * 3.0, Interval(0.0));
  EXPECT_EQ(Interval(-2.0, 5.0) * Interval(0.0), Interval(0.0));
  const Interval tiny = Interval(1e-300) * Interval(1e-300);  // underflows: not exact
  EXPECT_GT(tiny.upper(), 0.0);
  EXPECT_TRUE(tiny.contains(0.0));
  EXPECT_LT((Interval(1.0) + Interval(2.0)).lower(), 3.0);
}

}  // namespace
}  // namespace algray
