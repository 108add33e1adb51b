// tests/support/float_values.h: values rounded to float, as doubles. Session 27 found
// GCC 12.2 folding the vectorised (double)(float) round trip away, so that the "float"
// inputs of the benchmarks and of the tests that trace one line through both channels kept
// all 53 bits; both tests below fail with plain casts in place of floatValue.
#include "support/float_values.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include "bench/roots_problems.h"

namespace algray::test {
namespace {

// From the bits, not by another round trip the compiler could fold: a double in float's
// normal range is a float exactly when the 29 mantissa bits float lacks are zero (the
// values below are above 1e-38 in magnitude, or 0).
bool isFloat(double x) { return (std::bit_cast<std::uint64_t>(x) & 0x1fffffff) == 0; }

// The benchmarks' random problem shape (tests/bench/roots_problems.h): the float and double
// rows of roots_report and roots_bench solve the same interval.
TEST(FloatValues, BenchIntervalEndsAreFloats) {
  std::mt19937_64 rng(27);
  for (int k = 0; k < 2000; ++k) {
    const bench::ProblemShape p = bench::randomProblemShape(2 + k % 19, k % 2 == 1, rng);
    ASSERT_TRUE(isFloat(p.lo)) << "problem " << k << ": lo " << p.lo;
    ASSERT_TRUE(isFloat(p.hi)) << "problem " << k << ": hi " << p.hi;
    ASSERT_LT(p.lo, p.hi) << "problem " << k;
  }
}

// The pattern of the tests that trace one ray through both channels (origin and direction
// as floats, so both are the same line; tests/embree_filter_test.cpp and others): rays
// built in a loop and kept, checked afterwards.
TEST(FloatValues, VectorComponentsAreFloats) {
  struct Line {
    glm::dvec3 org, dir;
  };
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Line> lines;
  for (int k = 0; k < 2000; ++k) {
    const glm::dvec3 o(u(rng), u(rng), u(rng)), target(u(rng) / 3, u(rng) / 3, u(rng) / 3);
    const glm::dvec3 d = floatValues(target - o);
    lines.push_back(Line{floatValues(o), d});
  }
  for (size_t k = 0; k < lines.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(isFloat(lines[k].org[c])) << "ray " << k << ": origin " << c;
      ASSERT_TRUE(isFloat(lines[k].dir[c])) << "ray " << k << ": direction " << c;
    }
}

}  // namespace
}  // namespace algray::test
