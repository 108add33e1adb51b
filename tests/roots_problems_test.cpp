// The benchmarks' random problem shape (tests/bench/roots_problems.h): its interval ends
// are floats, so the float and double rows of roots_report and roots_bench solve the same
// interval. Session 27 found them with all 53 bits: GCC 12.2 folded the vectorised
// (double)(float) round trip of lo and hi away (see roundedToFloat).
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>

#include "bench/roots_problems.h"

namespace algray {
namespace {

TEST(RootsProblems, IntervalEndsAreFloats) {
  std::mt19937_64 rng(27);
  for (int k = 0; k < 2000; ++k) {
    const int degree = 2 + k % 19;
    const bench::ProblemShape p = bench::randomProblemShape(degree, k % 2 == 1, rng);
    // From the bits, not by another round trip the compiler could fold: a double in
    // float's normal range (the ends are in [0, 1], above 1e-38 where non-zero) is a float
    // exactly when the 29 mantissa bits float lacks are zero.
    auto isFloat = [](double x) { return (std::bit_cast<std::uint64_t>(x) & 0x1fffffff) == 0; };
    ASSERT_TRUE(isFloat(p.lo)) << "problem " << k << ": lo " << p.lo;
    ASSERT_TRUE(isFloat(p.hi)) << "problem " << k << ": hi " << p.hi;
    ASSERT_LT(p.lo, p.hi) << "problem " << k;
  }
}

}  // namespace
}  // namespace algray
