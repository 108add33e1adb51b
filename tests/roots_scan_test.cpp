// The noise-before query of the top-level sweep (plugin/core/roots_scan.h, a private
// header: noiseBefore) on a monotone piece with known regions. G = (v + 1/2)^3 + (v + 1/2)
// / 100 - 0.0956 is increasing (G' > 0: no critical point) with its root near -0.05; a
// noise bound 0.2 |v| covers |G| over a shelf about -0.947 .. -0.477 and the root's own
// region about -0.076 .. -0.038, and G is clear between them and on [-1, -0.947]. The
// regions are checked here first by a sweep in long double, so the expectations do not
// rest on the numbers above.
#include "roots_scan.h"

#include <gtest/gtest.h>

#include <cmath>

namespace algray {
namespace {

using roots_detail::LocalPoly;

LocalPoly<double> shelfPiece(double noise1, double window) {
  LocalPoly<double> g;
  g.n = 3;
  g.lo = -1.0;
  g.hi = 0.2;
  g.window = window;
  const double c[4] = {0.0344, 0.76, 1.5, 1.0};
  for (int i = 0; i <= 3; ++i) {
    g.c[i] = c[i];
    g.noise[i] = 1e-15 * std::abs(c[i]);  // (the rounding part, generously)
  }
  g.noise[1] += noise1;
  return g;
}

long double valueAt(const LocalPoly<double>& g, long double v) {
  return ((static_cast<long double>(g.c[3]) * v + g.c[2]) * v + g.c[1]) * v + g.c[0];
}
long double boundAt(const LocalPoly<double>& g, long double v) {
  const long double a = std::abs(v);
  return ((static_cast<long double>(g.noise[3]) * a + g.noise[2]) * a + g.noise[1]) * a +
         g.noise[0];
}
bool withinNoise(const LocalPoly<double>& g, long double v) {
  return std::abs(valueAt(g, v)) <= boundAt(g, v);
}

// The root of the piece by bisection on the long double values (G increasing).
double rootOf(const LocalPoly<double>& g) {
  long double a = -1.0L, b = 0.2L;
  for (int k = 0; k < 100; ++k) {
    const long double m = (a + b) / 2;
    (valueAt(g, m) < 0 ? a : b) = m;
  }
  return static_cast<double>(a);
}

TEST(RootsScan, NoiseBeforeFindsAShelfAClearStretchSeparatesFromTheRoot) {
  const LocalPoly<double> g = shelfPiece(0.2, 0x1p-20 * 1.2);
  // The regions the test rests on: [-1, -0.95] clear, a point of the shelf within noise,
  // [-0.45, -0.1] clear, the root's region reaching 2^-20 * 1.2 before the root.
  for (int k = 0; k <= 1000; ++k) {
    ASSERT_FALSE(withinNoise(g, -1.0L + 0.05L * k / 1000)) << k;
    ASSERT_FALSE(withinNoise(g, -0.45L + 0.35L * k / 1000)) << k;
  }
  ASSERT_TRUE(withinNoise(g, -0.7L));
  const double r = rootOf(g);
  ASSERT_TRUE(withinNoise(g, r - g.window));

  const double a = g.lo, fa = static_cast<double>(valueAt(g, a));
  const double na = static_cast<double>(boundAt(g, a));
  bool noisy = false;
  const double z = roots_detail::noiseBefore(g, 3, a, fa, na, r, noisy);
  EXPECT_TRUE(noisy);
  EXPECT_GT(z, -0.95);
  EXPECT_LT(z, -0.45);
  EXPECT_TRUE(withinNoise(g, z)) << z;
}

TEST(RootsScan, NoiseBeforeProvesAClearPiece) {
  // Noise 1e-9 |v|: the root's region is ~1e-10 wide, below the window, and the rest clear.
  const LocalPoly<double> g = shelfPiece(1e-9, 0x1p-20 * 1.2);
  const double r = rootOf(g);
  bool noisy = true;
  const double z = roots_detail::noiseBefore(g, 3, g.lo, static_cast<double>(valueAt(g, g.lo)),
                                             static_cast<double>(boundAt(g, g.lo)), r, noisy);
  EXPECT_FALSE(noisy);
  EXPECT_EQ(z, r);
}

TEST(RootsScan, NoiseBeforeKeepsARootWhoseOwnRegionIsWide) {
  // Noise 0.01 |v|: no shelf (|G| >= 0.0956 - ... against 0.01 there), the root's region
  // ~1.6e-3 wide: reported with noisy, unmoved.
  const LocalPoly<double> g = shelfPiece(0.01, 0x1p-20 * 1.2);
  for (int k = 0; k <= 1000; ++k) ASSERT_FALSE(withinNoise(g, -1.0L + 0.9L * k / 1000)) << k;
  const double r = rootOf(g);
  ASSERT_TRUE(withinNoise(g, r - g.window));
  bool noisy = false;
  const double z = roots_detail::noiseBefore(g, 3, g.lo, static_cast<double>(valueAt(g, g.lo)),
                                             static_cast<double>(boundAt(g, g.lo)), r, noisy);
  EXPECT_TRUE(noisy);
  EXPECT_EQ(z, r);
}

}  // namespace
}  // namespace algray
