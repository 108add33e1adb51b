// A differential fuzz of firstRoot / hasRoot / allRoots against an MPFR sign scan (session
// 26: a longer run of this driver found the wrong answers that
// RootsContract.RootsSpreadOverMoreBinadesThanOneFrame now pins down), for the double
// solver and for the float one (roots.h's float variants, the renderer's
// SurfaceOptions::singlePrecision). Problems of every kind the contract names: random
// coefficients over up to 16 decades, products of real roots with double roots, clusters
// and complex pairs up to 1e-9 off the axis, scales from 1e-100 to 1e100 (1e-30 to 1e30 in
// float), exact zeros at 0, noise-level or zero leading coefficients, caller error bounds,
// closedLo, and intervals around 0, far from it, ending on a root or up to 1e96 wide.
// Each problem is drawn in double and rounded to the solver's type (coefficients, error
// bounds, interval ends). The reference is independent of the solver: the exact value of
// the rounded polynomial (its coefficients converted to double exactly, MPFR, 256 bits) at
// 3000 points of the interval, the first sign change bisected in MPFR. What is asserted,
// with the noise bound N(s) = sum (err_i + gamma(2n+1) |c_i|) |s|^i (gamma of the solver's
// type) as the contract's measure of "within rounding", and u the solver's unit roundoff:
//  * every answer lies in (lo, hi] ([lo, hi] with closedLo), and hasRoot, firstRoot and
//    allRoots' first agree;
//  * a sign change whose sample ends are clear of N is found, and not passed: an answer
//    beyond it by more than 16 u cond(root) + 4 u |root| must lie in a stretch within N
//    from the root (a cluster the data cannot resolve);
//  * an answer before the scan's first sign change is a certified root of the rounded
//    polynomial near it (two roots between samples) or within N there.
// ALGRAY_ROOTS_FUZZ_SEED and ALGRAY_ROOTS_FUZZ_PROBLEMS replace the seed and the problem
// count, for longer campaigns (each failure prints the problem in hex floats).
#include "roots_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace algray {
namespace {

using test::Mp;

// What differs between the double and the float fuzz: the unit roundoff, the range of
// scales, and the sizes of the caller's error bounds and noise-level leading coefficients
// relative to it (for double the values the suite had before it was templated, so the
// double problems are the same).
template <class T>
struct Precision;

template <>
struct Precision<double> {
  static constexpr double kU = 0x1p-53;
  static constexpr double kScaleDecades = 100;  // scales 1e-100 .. 1e100
  static constexpr double kErrRel = 0x1p-50;    // caller error bounds, 8 u |c_i|
  static constexpr double kNoiseLead = 1e-18;   // a noise-level leading coefficient
};

template <>
struct Precision<float> {
  static constexpr double kU = 0x1p-24;
  static constexpr double kScaleDecades = 30;
  static constexpr double kErrRel = 0x1p-21;
  static constexpr double kNoiseLead = 5e-10;
};

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

template <class T>
struct FuzzProblem {
  std::vector<T> c, err;
  std::vector<double> known;
  T lo = 0, hi = 0;
  RootOptions options;
};

// The problem as code: exact hex floats, for a reproduction.
template <class T>
std::string describe(const FuzzProblem<T>& p) {
  std::ostringstream s;
  s << std::hexfloat << "\n  c = {";
  for (T x : p.c) s << x << ", ";
  s << "}\n  err = {";
  for (T x : p.err) s << x << ", ";
  s << "}\n  lo = " << p.lo << ", hi = " << p.hi << ", closedLo = " << p.options.closedLo;
  return s.str();
}

// Drawn in double, then rounded to T (the order of the random draws does not depend on T).
template <class T>
FuzzProblem<T> draw(std::mt19937_64& rng) {
  using P = Precision<T>;
  std::uniform_real_distribution<double> u(0, 1);
  FuzzProblem<T> p;
  std::vector<double> c, err;
  double lo = 0, hi = 0;
  const int n = 1 + static_cast<int>(u(rng) * (u(rng) < 0.5 ? 12 : 40));
  const double scale = u(rng) < 0.1
                           ? std::pow(10.0, -P::kScaleDecades + 2 * P::kScaleDecades * u(rng))
                           : std::pow(10.0, -3 + 6 * u(rng));
  if (u(rng) < 1.0 / 3) {  // random coefficients
    const double decades = u(rng) < 0.5 ? 1 : 8;
    for (int i = 0; i <= n; ++i)
      c.push_back((u(rng) < 0.5 ? -1 : 1) * std::pow(10.0, decades * (2 * u(rng) - 1)));
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
    c = test::expand(p.known, pairs, (u(rng) < 0.5 ? -1 : 1) * std::pow(10.0, 6 * u(rng) - 3));
  }
  const double extra = u(rng);
  if (extra < 0.1) {  // exact zeros at 0
    const int k = 1 + static_cast<int>(u(rng) * 3);
    if (static_cast<int>(c.size()) + k <= kMaxDegree + 1) c.insert(c.begin(), k, 0.0);
  } else if (extra < 0.2 && c.size() <= kMaxDegree) {  // a noise-level leading coefficient
    double largest = 0;
    for (double x : c) largest = std::max(largest, std::abs(x));
    c.push_back(largest * P::kNoiseLead * (u(rng) < 0.5 ? -1 : 1));
  } else if (extra < 0.25 && c.size() <= kMaxDegree) {
    c.push_back(0.0);
  }
  for (double x : c) p.c.push_back(static_cast<T>(x));
  if (u(rng) < 0.3)
    for (T x : p.c) p.err.push_back(static_cast<T>(std::abs(x) * P::kErrRel));
  p.options.closedLo = u(rng) < 0.2;
  const double where = u(rng);
  if (where < 0.15 && !p.known.empty()) {  // an end on a root
    const double r = p.known[static_cast<size_t>(u(rng) * p.known.size())];
    const double len = scale * std::pow(10.0, -4 * u(rng));
    lo = u(rng) < 0.5 ? r : r - len;
    hi = lo == r ? r + len : r;
  } else if (where < 0.3) {  // around 0
    lo = -scale * 3 * u(rng);
    hi = scale * 3 * u(rng);
  } else {
    lo = scale * (6 * u(rng) - 3);
    hi = lo + scale * std::pow(10.0, 1 - 5 * u(rng));
  }
  p.lo = static_cast<T>(lo);
  p.hi = static_cast<T>(hi);
  return p;
}

// The solver's answers: firstRoot, hasRoot, and allRoots' count and first.
struct Answers {
  std::optional<double> first;
  bool any = false;
  int nAll = 0;
  double all0 = 0;
};

template <class T>
Answers solve(const FuzzProblem<T>& p) {
  Answers a;
  const auto first = firstRoot(std::span<const T>(p.c), p.err, p.lo, p.hi, p.options);
  if (first) a.first = *first;
  a.any = hasRoot(std::span<const T>(p.c), p.err, p.lo, p.hi, p.options);
  T all[kMaxDegree + 1] = {};
  a.nAll = allRoots(std::span<const T>(p.c), p.err, p.lo, p.hi, std::span<T>(all), p.options);
  a.all0 = all[0];
  return a;
}

// 16 u cond(root) + 4 u |root|, or infinity where the root is not certified.
template <class T>
double rootTolerance(const std::optional<test::RefRoot>& ref, double root) {
  const double cond = ref ? ref->conditioning : INFINITY;
  return 16 * Precision<T>::kU * cond + 4 * Precision<T>::kU * std::abs(root);
}

template <class T>
void checkProblem(const FuzzProblem<T>& p, const std::string& what) {
  const Answers a = solve(p);
  const std::optional<double> first = a.first;
  const double lo = p.lo, hi = p.hi;
  if (first) {
    EXPECT_TRUE(p.options.closedLo ? *first >= lo : *first > lo) << what << describe(p);
    EXPECT_LE(*first, hi) << what << describe(p);
  }
  EXPECT_EQ(a.any, first.has_value()) << what << describe(p);
  ASSERT_EQ(a.nAll > 0, first.has_value()) << what << describe(p);
  if (first) {
    EXPECT_EQ(a.all0, *first) << what << describe(p);
  }

  const std::vector<double> c(p.c.begin(), p.c.end());  // exact
  const int n = static_cast<int>(c.size()) - 1;
  const double relNoise = test::gammaOfUnit(2 * n + 1, Precision<T>::kU) +
                          (p.err.empty() ? 0.0 : Precision<T>::kErrRel);
  const ScanRoot scan = firstSignChange(c, p.options.closedLo ? std::nextafter(lo, -INFINITY) : lo,
                                        hi, 3000, relNoise);
  if (scan.found && scan.clear) {
    ASSERT_TRUE(first) << what << ": the sign change at " << scan.root << " was missed"
                       << describe(p);
    const double tol = rootTolerance<T>(test::refine(c, scan.root), scan.root);
    if (*first > scan.root + tol) {  // passed: only inside one stretch within the noise
      bool withinNoise = test::relativeResidual(c, *first) <= 4 * relNoise;
      for (int k = 1; withinNoise && k < 64; ++k)
        withinNoise =
            test::relativeResidual(c, scan.root + (*first - scan.root) * k / 64) <= 4 * relNoise;
      EXPECT_TRUE(withinNoise) << what << ": answered " << *first << " past the root " << scan.root
                               << describe(p);
    }
  }
  if (first && (!scan.found || *first < scan.root)) {
    const auto ref = test::refine(c, *first);
    const bool certified = ref && std::abs(ref->value - *first) <= rootTolerance<T>(ref, *first);
    EXPECT_TRUE(certified || test::relativeResidual(c, *first) <= 4 * relNoise)
        << what << ": " << *first << " is neither a root nor within the noise bound" << describe(p);
  }
}

// A campaign: `problems` draws from `seed` (or the environment's), each checked.
template <class T>
void fuzz(unsigned long long seed, int problems) {
  if (const char* s = std::getenv("ALGRAY_ROOTS_FUZZ_SEED")) seed = std::strtoull(s, nullptr, 0);
  if (const char* s = std::getenv("ALGRAY_ROOTS_FUZZ_PROBLEMS")) problems = std::atoi(s);
  std::mt19937_64 rng(seed);
  int checked = 0;
  for (int t = 0; t < problems; ++t) {
    const FuzzProblem<T> p = draw<T>(rng);
    if (!(p.lo < p.hi)) continue;
    ++checked;
    checkProblem(p, "seed " + std::to_string(seed) + " problem " + std::to_string(t));
  }
  EXPECT_GT(checked, problems * 4 / 5);
}

TEST(RootsFuzz, AgainstAnMpfrSignScan) { fuzz<double>(2026, 2500); }

TEST(RootsFuzz, FloatAgainstAnMpfrSignScan) { fuzz<float>(2027, 2500); }

}  // namespace
}  // namespace algray
