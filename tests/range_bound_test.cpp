// Tests of include/algray/range_bound.h beyond those in cells_test.cpp: inputs whose
// arithmetic underflows, against roots known by construction.
#include "algray/range_bound.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace algray {
namespace {

// Beyond degree 40 the univariate tests refuse, as firstRoot does: they dropped the terms
// above it, so s^41 - 1 on [0, 2] (root s = 1, range [-1, 2^41 - 1]) had the enclosure
// [-1, -1] and "no root".
TEST(RangeBound, UnivariateTestsRefuseDegreesAbove40) {
  std::vector<double> c(42, 0.0);
  c[0] = -1.0;
  c[41] = 1.0;
  EXPECT_THROW(rangeOverInterval(c, {}, 0.0, 2.0), Error);
  EXPECT_THROW(provablyNoRoot(c, {}, 0.0, 2.0), Error);
  EXPECT_THROW(quickNoRoot(c, {}, 0.0, 2.0), Error);
  c.pop_back();  // degree 40 (40 + 1 coefficients): accepted, s^40 - 1 has its root at 1
  c[40] = 1.0;
  EXPECT_FALSE(provablyNoRoot(c, {}, 0.0, 2.0));
  EXPECT_FALSE(quickNoRoot(c, {}, 0.0, 2.0));
  EXPECT_LE(rangeOverInterval(c, {}, 0.0, 2.0).lower(), -1.0);
}

// A table's degree outside 0..40 is refused by name (-5 threw std::length_error from a
// vector's size).
TEST(RangeBound, MonomialTablesRefuseDegreesOutsideTheRange) {
  for (const int degree : {-5, -1, 41}) EXPECT_THROW(MonomialTables{degree}, Error) << degree;
  EXPECT_EQ(MonomialTables(40).terms, Polynomial::termCount(40));
}

// g(s) = 2^-1074 * a * (s - r) (and its square for degree 2) with integer a * r: the
// coefficients are exact subnormals, every product of the evaluation underflows, and r
// is a root by construction. No test may claim "no root" on a span containing r.
TEST(RangeBound, NoRootTestsSurviveUnderflow) {
  const double tiny = std::numeric_limits<double>::denorm_min();
  // The case that once failed: the root 7/8 of 2^-1074 (8 s - 7) on [0.857, 2.559].
  const std::vector<double> once = {-7 * tiny, 8 * tiny};
  EXPECT_FALSE(quickNoRoot(once, {}, 0.85697571450635079, 2.5586755026334993));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> reach(0.0, 2.0);
  std::uniform_int_distribution<int> small(-24, 24), slope(1, 3);
  for (int trial = 0; trial < 20000; ++trial) {
    const double a = 8.0 * slope(rng) * (trial % 2 ? 1 : -1), r = small(rng) / 8.0;  // a r integer
    std::vector<double> g = {-a * r * tiny, a * tiny};
    // Every third: a (s - r)^2 / 2^1074, a double root.
    if (trial % 3 == 0) g = {a * r * r * tiny, -2 * a * r * tiny, a * tiny};
    const double lo = r - reach(rng), hi = r + reach(rng);
    SCOPED_TRACE(testing::Message()
                 << "root " << r << " in [" << lo << ", " << hi << "], degree " << g.size() - 1);
    EXPECT_FALSE(quickNoRoot(g, {}, lo, hi));
    EXPECT_FALSE(provablyNoRoot(g, {}, lo, hi));
  }
}

// BoxPolynomial::subBox scales the coefficient of w^e by 2^-(e * splits): for a degree-40
// surface 29 levels deep that power is 2^-1160, below the smallest double, yet the
// coefficient times it need not be (a box of half-width 2^20 brings h^40 = 2^800). With
// f = x^40, F(w) = 2^800 w^40 and the sub-box at centre 1/2, 29 halvings has
//   G(w) = 2^800 (1/2 + 2^-29 w)^40,  coefficient of w^e = C(40, e) 2^(800 - (40 - e) - 29 e),
// every one a normal double: each interval must contain it.
TEST(RangeBound, SubBoxKeepsCoefficientsWhosePowerOfTwoUnderflows) {
  Polynomial f;
  f.setCoeff(40, 0, 0, 1.0);
  const MonomialTables tables(40);
  const BoxPolynomial box(f, glm::dvec3(0.0), glm::dvec3(0x1p20), tables);
  const int splits[3] = {29, 0, 0};
  BoxPolynomial sub;
  box.subBox(glm::dvec3(0.5, 0.0, 0.0), splits, sub);
  double binomial = 1.0;  // C(40, e), exact in double
  for (int e = 0; e <= 40; ++e) {
    const double exact = std::ldexp(binomial, 800 - (40 - e) - 29 * e);
    const Interval c = sub.coeffs()[Polynomial::index(e, 0, 0)];
    EXPECT_TRUE(c.contains(exact))
        << "w^" << e << ": [" << c.lower() << ", " << c.upper() << "] misses " << exact;
    binomial = binomial * (40 - e) / (e + 1);
  }
}

}  // namespace
}  // namespace algray
