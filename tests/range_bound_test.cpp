// Tests of include/algray/range_bound.h beyond those in cells_test.cpp: inputs whose
// arithmetic underflows, against roots known by construction.
#include "algray/range_bound.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <vector>

namespace algray {
namespace {

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
    SCOPED_TRACE(testing::Message() << "root " << r << " in [" << lo << ", " << hi << "], degree "
                                    << g.size() - 1);
    EXPECT_FALSE(quickNoRoot(g, {}, lo, hi));
    EXPECT_FALSE(provablyNoRoot(g, {}, lo, hi));
  }
}

}  // namespace
}  // namespace algray
