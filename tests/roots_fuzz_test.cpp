// A differential fuzz of firstRoot / hasRoot / allRoots against an MPFR sign scan (session
// 26: a longer run of this driver found the wrong answers that
// RootsContract.RootsSpreadOverMoreBinadesThanOneFrame now pins down). Problems of every
// kind the contract names: random coefficients over up to 16 decades, products of real
// roots with double roots, clusters and complex pairs up to 1e-9 off the axis, scales from
// 1e-100 to 1e100, exact zeros at 0, noise-level or zero leading coefficients, caller error
// bounds, closedLo, and intervals around 0, far from it, ending on a root or up to 1e96
// wide. The reference is independent of the solver: the exact value of the rounded
// polynomial (MPFR, 256 bits) at 3000 points of the interval, the first sign change
// bisected in MPFR. What is asserted, with the noise bound N(s) = sum (err_i + gamma(2n+1)
// |c_i|) |s|^i as the contract's measure of "within rounding":
//  * every answer lies in (lo, hi] ([lo, hi] with closedLo), and hasRoot, firstRoot and
//    allRoots' first agree;
//  * a sign change whose sample ends are clear of N is found, and not passed: an answer
//    beyond it by more than 16 u cond(root) must lie in a stretch within N from the root
//    (a cluster the data cannot resolve);
//  * an answer before the scan's first sign change is a certified root of the rounded
//    polynomial near it (two roots between samples) or within N there.
#include "roots_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace algray {
namespace {

using test::Mp;

struct ScanRoot {
  bool found = false;
  double root = 0;
  bool clear = false;  // the bracketing samples are beyond the noise bound (relative g)
};

// The first sign change of the rounded polynomial on M samples of [lo, hi], bisected in
// MPFR to 2^-120 relative.
ScanRoot firstSignChange(const std::vector<double>& c, double lo, double hi, int samples,
                         double relNoise) {
  ScanRoot out;
  double xa = lo;
  int sa = test::signAt(c, Mp(lo));
  for (int k = 1; k <= samples; ++k) {
    const double x = k == samples ? hi : lo + (hi - lo) * (static_cast<double>(k) / samples);
    if (!(x > xa)) continue;
    const int s = test::signAt(c, Mp(x));
    if (s == 0) {
      out.found = true;
      out.root = x;
      return out;
    }
    if (sa != 0 && s != sa) {
      Mp l(xa), h(x), m, width, scale;
      for (int it = 0; it < 4000; ++it) {
        mpfr_sub(width.get(), h.get(), l.get(), MPFR_RNDN);
        mpfr_abs(scale.get(), h.get(), MPFR_RNDN);
        mpfr_mul_2si(scale.get(), scale.get(), -120, MPFR_RNDN);
        if (it > 0 && mpfr_cmp(width.get(), scale.get()) <= 0) break;
        mpfr_add(m.get(), l.get(), h.get(), MPFR_RNDN);
        mpfr_div_2ui(m.get(), m.get(), 1, MPFR_RNDN);
        const int sm = test::signAt(c, m);
        if (sm == 0) break;
        (sm == sa ? l : h) = m;
      }
      out.found = true;
      out.root = m.toDouble();
      out.clear = test::relativeResidual(c, xa) > 4 * relNoise &&
                  test::relativeResidual(c, x) > 4 * relNoise;
      return out;
    }
    sa = s;
    xa = x;
  }
  return out;
}

struct FuzzProblem {
  std::vector<double> c, err, known;
  double lo = 0, hi = 0;
  RootOptions options;
};

FuzzProblem draw(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  FuzzProblem p;
  const int n = 1 + static_cast<int>(u(rng) * (u(rng) < 0.5 ? 12 : 40));
  const double scale =
      u(rng) < 0.1 ? std::pow(10.0, -100 + 200 * u(rng)) : std::pow(10.0, -3 + 6 * u(rng));
  if (u(rng) < 1.0 / 3) {  // random coefficients
    const double decades = u(rng) < 0.5 ? 1 : 8;
    for (int i = 0; i <= n; ++i)
      p.c.push_back((u(rng) < 0.5 ? -1 : 1) * std::pow(10.0, decades * (2 * u(rng) - 1)));
  } else {  // from roots
    std::vector<std::pair<double, double>> pairs;
    int left = n;
    while (left > 0) {
      const double w = u(rng);
      if (left >= 2 && w < 0.35) {
        pairs.emplace_back(scale * (4 * u(rng) - 2), scale * std::pow(10.0, -9 * u(rng)));
        left -= 2;
      } else if (left >= 2 && w < 0.5) {  // a double root
        p.known.push_back(scale * (4 * u(rng) - 2));
        p.known.push_back(p.known.back());
        left -= 2;
      } else if (w < 0.6 && !p.known.empty()) {  // a cluster member
        p.known.push_back(p.known.back() * (1 + std::pow(10.0, -1 - 8 * u(rng))));
        left -= 1;
      } else {
        p.known.push_back(scale * (4 * u(rng) - 2));
        left -= 1;
      }
    }
    p.c = test::expand(p.known, pairs, (u(rng) < 0.5 ? -1 : 1) * std::pow(10.0, 6 * u(rng) - 3));
  }
  const double extra = u(rng);
  if (extra < 0.1) {  // exact zeros at 0
    const int k = 1 + static_cast<int>(u(rng) * 3);
    if (static_cast<int>(p.c.size()) + k <= kMaxDegree + 1) p.c.insert(p.c.begin(), k, 0.0);
  } else if (extra < 0.2 && p.c.size() <= kMaxDegree) {  // a noise-level leading coefficient
    double largest = 0;
    for (double x : p.c) largest = std::max(largest, std::abs(x));
    p.c.push_back(largest * 1e-18 * (u(rng) < 0.5 ? -1 : 1));
  } else if (extra < 0.25 && p.c.size() <= kMaxDegree) {
    p.c.push_back(0.0);
  }
  if (u(rng) < 0.3)
    for (double x : p.c) p.err.push_back(std::abs(x) * 0x1p-50);
  p.options.closedLo = u(rng) < 0.2;
  const double where = u(rng);
  if (where < 0.15 && !p.known.empty()) {  // an end on a root
    const double r = p.known[static_cast<size_t>(u(rng) * p.known.size())];
    const double len = scale * std::pow(10.0, -4 * u(rng));
    p.lo = u(rng) < 0.5 ? r : r - len;
    p.hi = p.lo == r ? r + len : r;
  } else if (where < 0.3) {  // around 0
    p.lo = -scale * 3 * u(rng);
    p.hi = scale * 3 * u(rng);
  } else {
    p.lo = scale * (6 * u(rng) - 3);
    p.hi = p.lo + scale * std::pow(10.0, 1 - 5 * u(rng));
  }
  return p;
}

TEST(RootsFuzz, AgainstAnMpfrSignScan) {
  std::mt19937_64 rng(2026);
  int checked = 0;
  for (int t = 0; t < 2500; ++t) {
    const FuzzProblem p = draw(rng);
    if (!(p.lo < p.hi)) continue;
    ++checked;
    const std::vector<double>& c = p.c;
    const std::string what = "problem " + std::to_string(t);
    const auto first = firstRoot(c, p.err, p.lo, p.hi, p.options);
    const bool any = hasRoot(c, p.err, p.lo, p.hi, p.options);
    double all[kMaxDegree + 1];
    const int nAll = allRoots(c, p.err, p.lo, p.hi, std::span<double>(all), p.options);
    if (first) {
      EXPECT_TRUE(p.options.closedLo ? *first >= p.lo : *first > p.lo) << what;
      EXPECT_LE(*first, p.hi) << what;
    }
    EXPECT_EQ(any, first.has_value()) << what;
    ASSERT_EQ(nAll > 0, first.has_value()) << what;
    if (first) {
      EXPECT_EQ(all[0], *first) << what;
    }

    const int n = static_cast<int>(c.size()) - 1;
    const double relNoise = gamma(2 * n + 1) + (p.err.empty() ? 0.0 : 0x1p-50);
    const ScanRoot scan = firstSignChange(
        c, p.options.closedLo ? std::nextafter(p.lo, -INFINITY) : p.lo, p.hi, 3000, relNoise);
    if (scan.found && scan.clear) {
      ASSERT_TRUE(first) << what << ": the sign change at " << scan.root << " was missed";
      const auto ref = test::refine(c, scan.root);
      const double cond = ref ? ref->conditioning : INFINITY;
      const double tol =
          16 * roots_testing::kU * cond + 4 * roots_testing::kU * std::abs(scan.root);
      if (*first > scan.root + tol) {  // passed: only inside one stretch within the noise
        bool withinNoise = test::relativeResidual(c, *first) <= 4 * relNoise;
        for (int k = 1; withinNoise && k < 64; ++k)
          withinNoise =
              test::relativeResidual(c, scan.root + (*first - scan.root) * k / 64) <= 4 * relNoise;
        EXPECT_TRUE(withinNoise) << what << ": answered " << *first << " past the root "
                                 << scan.root;
      }
    }
    if (first && (!scan.found || *first < scan.root)) {
      const auto ref = test::refine(c, *first);
      const bool certified =
          ref && std::abs(ref->value - *first) <= 16 * roots_testing::kU * ref->conditioning +
                                                      4 * roots_testing::kU * std::abs(*first);
      EXPECT_TRUE(certified || test::relativeResidual(c, *first) <= 4 * relNoise)
          << what << ": " << *first << " is neither a root nor within the noise bound";
    }
  }
  EXPECT_GT(checked, 2000);
}

}  // namespace
}  // namespace algray
