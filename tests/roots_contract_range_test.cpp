// Tests of roots.h's contract at the edges of double's range: scale invariance, coefficients
// and intervals beyond one frame's range, roots over hundreds of binades, tolerances that
// must not skip a root, the float solver at degree 40, underflow between roots, subnormal
// roots and exact zeros at 0. The references are independent as in roots_test.cpp: MPFR
// roots of the rounded polynomial, its long-double values against the noise rule's bound,
// or closed forms. (Suite RootsContract, as roots_contract_test.cpp.)
#include "roots_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace algray {
namespace {

using namespace roots_testing;

TEST(RootsContract, ScaleInvariance) {
  Problem p = fromRoots("base", {-0.3, 0.1, 0.7}, {{0.5, 0.5}}, -1, 1);
  const auto base = solveAll(p);
  for (double s : {0x1p-900, 0x1p900}) {  // exact scalings: bit-identical roots
    Problem q = p;
    for (double& x : q.c) x *= s;
    EXPECT_EQ(solveAll(q), base) << s;
  }
  for (double s : {1e-300, 1e300}) {  // rounded scalings: roots move by rounding only
    Problem q = p;
    for (double& x : q.c) x *= s;
    const auto r = solveAll(q);
    ASSERT_EQ(r.size(), base.size());
    for (size_t i = 0; i < r.size(); ++i) EXPECT_NEAR(r[i], base[i], 1e-15) << s;
  }
  // Long and short intervals in the caller's units: same polynomial scaled in t.
  for (double t : {1e-12, 1e12}) {
    Problem q = fromRoots("t-scaled", {-0.3 * t, 0.1 * t, 0.7 * t}, {{0.5 * t, 0.5 * t}}, -t, t);
    const auto r = solveAll(q);
    ASSERT_EQ(r.size(), 3u);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(r[i] / t, base[i], 1e-14);
  }
}

// Coefficients spread beyond double's exponent range in the local frame: 1e-300 + 1e300 v^4
// has no real root (its constant flushed to 0 in the frame gave a 4-fold root at 0,
// reported as tangent); with the constant negative it has two, at +-1e-150. The methods
// of the contract (Sturm and Bernstein, kept for comparison, resolve roots only down to
// their interval's scale, roots.h), on (-1, 1), and on (-1e10, 1e10) for 1 + 1e300 v^4
// (the frame's scaling by 2^(4e) is what underflows there).
TEST(RootsContract, CoefficientsBeyondTheFramesRange) {
  for (const RootMethod m : {RootMethod::Auto, RootMethod::Yuksel, RootMethod::ClosedForm}) {
    RootOptions o;
    o.method = m;
    const std::vector<double> none = {1e-300, 0, 0, 0, 1e300}, wide = {1, 0, 0, 0, 1e300};
    EXPECT_FALSE(firstRoot(none, {}, -1.0, 1.0, o)) << static_cast<int>(m);
    EXPECT_FALSE(hasRoot(none, {}, -1.0, 1.0, o)) << static_cast<int>(m);
    EXPECT_FALSE(firstRoot(wide, {}, -1e10, 1e10, o)) << static_cast<int>(m);
    const std::vector<double> two = {-1e-300, 0, 0, 0, 1e300};
    const auto r = firstRoot(two, {}, -1.0, 1.0, o);
    ASSERT_TRUE(r) << static_cast<int>(m);
    EXPECT_LT(*r, 0.0);
    EXPECT_GT(*r, -1e-60);  // -1e-150, moved by at most the frame's smallest normal
  }
}

// Intervals far wider than the roots: the local frame scales s by 2^e >= max(|lo|, |hi|),
// and a coefficient whose term is below double's range in that frame is kept as the
// smallest normal number, which moves the roots near the caller's origin to wherever
// that number puts them: x^2 - 1 on (-1e308, 1e308] gave the "root" -2.7e154 (and 1e300,
// -2e146). Polynomials from known roots, intervals up to (-1e308, 1e308], against the
// certified MPFR roots: all of them, each within 8 u cond of the reference.
TEST(RootsContract, HugeIntervalsKeepTheRootsNearTheOrigin) {
  const std::vector<std::vector<double>> polys = {
      test::expand({-1.0, 1.0}, {}), test::expand({-3.0, 0.5, 2.0}, {{1.0, 2.0}}),
      test::expand({0.25, 7.0, -7.5, 1e-3}, {}),
      test::expand({-2.0, 3.0, 11.0}, {{-1.0, 0.5}, {4.0, 1.0}}, -3.0)};
  const std::vector<std::pair<double, double>> spans = {
      {-1e308, 1e308}, {-1e300, 1e300}, {-1e200, 1e250}, {-1e150, 20.0}, {-10.0, 1.7e308}};
  for (const RootMethod m : {RootMethod::Auto, RootMethod::Yuksel, RootMethod::ClosedForm}) {
    RootOptions o;
    o.method = m;
    for (std::size_t pi = 0; pi < polys.size(); ++pi) {
      const std::vector<double>& c = polys[pi];
      for (const auto& [lo, hi] : spans) {
        const auto ref = test::refineAll(
            c, {-8.0, -2.5, -1.5, -0.5, 0.0, 0.3, 0.9, 1.5, 2.5, 5.0, 6.5, 12.0}, lo, hi);
        ASSERT_FALSE(ref.empty());
        std::vector<double> out(c.size());
        out.resize(allRoots(c, {}, lo, hi, out, o));
        char what[96];
        std::snprintf(what, sizeof what, "method %d polynomial %zu on (%g, %g]",
                      static_cast<int>(m), pi, lo, hi);
        ASSERT_EQ(out.size(), ref.size()) << what;
        auto tolerance = [&](const test::RefRoot& r) {
          return 8 * kUnitRoundoff * r.conditioning * std::max(1.0, std::abs(r.value));
        };
        for (std::size_t i = 0; i < ref.size(); ++i)
          EXPECT_LE(rootError(out[i], ref[i]), tolerance(ref[i])) << what << " root " << i;
        const auto first = firstRoot(c, {}, lo, hi, o);
        ASSERT_TRUE(first) << what;
        EXPECT_LE(rootError(*first, ref[0]), tolerance(ref[0])) << what;
      }
    }
  }
}

// High degrees on intervals far wider than their roots: the frame's scaling took the
// lower coefficients below double's range, and the cut to Cauchy's bound (1 + max |c_j /
// c_n|, ~rho^n for roots of size rho) did not bring them back: s^40 - 2^40 on (0, 1e13]
// gave 44762 instead of 2, degree 30-40 polynomials with roots near 1 lost them all from
// hi ~ 1e10 on. Fujiwara's bound (within 2n of the largest root) fits the frame to the
// roots. Against certified MPFR roots: every well-conditioned root within the accuracy
// bound, every answer a root or within noise, none twice. (Not a count of roots: on one
// draw of the seeds, session 41, three roots of degree 40 of conditioning ~1e13, 0.12
// apart, lie in one stretch where g is within its noise bound, one root to the solver.)
TEST(RootsContract, HighDegreesOnHugeIntervals) {
  std::vector<double> power(41, 0.0);
  power[0] = -0x1p40;
  power[40] = 1;  // s^40 - 2^40: roots +-2
  std::mt19937_64 rng(40);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<std::vector<double>> polys = {power}, starts = {{-2.0, 2.0}};
  for (int degree : {30, 35, 40}) {
    std::vector<double> roots;
    for (int i = 0; i < 6; ++i) roots.push_back(0.5 + 2 * uni(rng));
    std::vector<std::pair<double, double>> pairs;
    while (static_cast<int>(roots.size() + 2 * pairs.size()) < degree)
      pairs.emplace_back(2 * uni(rng), 0.3 + std::abs(uni(rng)));
    polys.push_back(test::expand(roots, pairs));
    starts.push_back(roots);
  }
  for (const RootMethod m : {RootMethod::Auto, RootMethod::Yuksel}) {
    RootOptions o;
    o.method = m;
    for (std::size_t pi = 0; pi < polys.size(); ++pi) {
      const std::vector<double>& c = polys[pi];
      for (const double hi : {1e9, 1e13, 1e20, 1e100, 1e300}) {
        const auto ref = test::refineAll(c, starts[pi], -hi, hi);
        ASSERT_FALSE(ref.empty());
        std::vector<double> out(c.size());
        out.resize(allRoots(c, {}, -hi, hi, out, o));
        SCOPED_TRACE("method " + std::to_string(static_cast<int>(m)) + " polynomial " +
                     std::to_string(pi) + " hi " + std::to_string(hi));
        checkAccuracy(ref, out, -hi, hi, nullptr);
        for (const double x : out) EXPECT_TRUE(rootOrWithinNoise(c, x));
        expectDistinctRoots(c, out);
        const auto first = firstRoot(c, {}, 0.0, hi, o);
        const auto positive = std::find_if(ref.begin(), ref.end(),
                                           [](const test::RefRoot& r) { return r.value > 0; });
        ASSERT_EQ(first.has_value(), positive != ref.end());
        if (first && wellConditioned(ref, positive - ref.begin(), -hi, hi)) {
          EXPECT_LE(rootError(*first, *positive), accuracyBound(*positive));
        } else if (first) {
          EXPECT_TRUE(rootOrWithinNoise(c, *first));
        }
      }
    }
  }
  // 1e200 s^2 - 1e-200 on (0, 1]: the root 1e-200 (the constant's term is below the
  // frame's range on (0, 1]; the cut to the bound ~1e-200 brings it back). Reference:
  // sqrt(c0 / c2) of the two doubles in long double (range to 1e-4931), whose relative
  // conditioning is 1.
  const std::vector<double> tiny = {-1e-200, 0, 1e200};
  const auto r = firstRoot(tiny, {}, 0.0, 1.0);
  ASSERT_TRUE(r);
  const long double exact =
      std::sqrt(-static_cast<long double>(tiny[0]) / static_cast<long double>(tiny[2]));
  EXPECT_NEAR(*r, static_cast<double>(exact), kAccuracyUlps * kU * static_cast<double>(exact));
}

// Roots spread over more binades than one frame holds (session 26's fuzz campaign against
// an MPFR sign scan). A frame keeps its coefficients in double's range relative to the
// largest; with roots near 1 and near 1e8 at degree 40 (1 and 1e16 at degree 20) the terms
// near the small roots are ~2^-1100 of the largest over the interval, below that range,
// and were kept as the smallest normal number: the small roots vanished and every one of
// these problems was answered with a point where |g| is its whole term sum (relative
// residual 1). The interval is now solved in pieces by magnitude (roots.cpp, rangeSplit).
// Checked: every query, against MPFR roots of the rounded polynomial, for Auto and Yuksel,
// on intervals reaching 0 and on ones that start above the small roots, with roots on
// three scales (1e-60, 1, 1e60) and in float. (Sturm's comparison solver gets the pieces
// too, but its sequence loses the small roots of one degree-20 case, roots near 1 and
// 1.9e16, whose inner piece spans 2^209 in its coefficients.)
TEST(RootsContract, RootsSpreadOverMoreBinadesThanOneFrame) {
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  struct Case {
    std::vector<double> c, starts;
  };
  std::vector<Case> cases;
  for (const int degree : {20, 30, 40})
    for (const double big : {1e8, 1e16, 1e100})
      for (int k = 0; k < 4; ++k) {
        std::vector<double> roots = {0.25 + 0.5 * uni(rng), 1 + uni(rng), big * (1 + uni(rng))};
        std::vector<std::pair<double, double>> pairs;
        while (static_cast<int>(roots.size() + 2 * pairs.size()) + 2 <= degree)
          pairs.emplace_back(2 * uni(rng) - 1, 0.1 + uni(rng));
        if (static_cast<int>(roots.size() + 2 * pairs.size()) < degree)
          roots.push_back(-2 - uni(rng));
        cases.push_back({test::expand(roots, pairs), roots});
      }
  {  // three scales: 1e-60, 1 and 1e60, degree 24
    std::vector<double> roots = {1e-60, 0.5, 1e60};
    std::vector<std::pair<double, double>> pairs;
    for (int i = 0; i < 10; ++i) pairs.emplace_back(2 * uni(rng) - 1, 0.1 + uni(rng));
    roots.push_back(-3);
    cases.push_back({test::expand(roots, pairs), roots});
  }
  for (const RootMethod m : {RootMethod::Auto, RootMethod::Yuksel}) {
    RootOptions o;
    o.method = m;
    for (std::size_t ci = 0; ci < cases.size(); ++ci) {
      const std::vector<double>& c = cases[ci].c;
      const double far = 10 * *std::max_element(cases[ci].starts.begin(), cases[ci].starts.end());
      for (const double lo :
           {-far, 0.1 * *std::min_element(
                            cases[ci].starts.begin() + 1, cases[ci].starts.end(),
                            [](double a, double b) { return std::abs(a) < std::abs(b); })}) {
        const auto ref = test::refineAll(c, cases[ci].starts, lo, far);
        ASSERT_FALSE(ref.empty()) << ci;
        const std::string what = "method " + std::to_string(static_cast<int>(m)) + " case " +
                                 std::to_string(ci) + " lo " + std::to_string(lo);
        std::vector<double> out(c.size());
        out.resize(allRoots(c, {}, lo, far, out, o));
        ASSERT_EQ(out.size(), ref.size()) << what;
        for (std::size_t i = 0; i < ref.size(); ++i)
          EXPECT_LE(rootError(out[i], ref[i]), accuracyBound(ref[i])) << what << " root " << i;
        const auto first = firstRoot(c, {}, lo, far, o);
        ASSERT_TRUE(first) << what;
        EXPECT_LE(rootError(*first, ref[0]), accuracyBound(ref[0])) << what;
        EXPECT_TRUE(hasRoot(c, {}, lo, far, o)) << what;
        const auto walk = walkRoots(c, {}, lo, far, 2 * c.size(), o);
        ASSERT_EQ(walk.size(), ref.size()) << what;
        for (std::size_t i = 0; i < ref.size(); ++i)
          EXPECT_LE(rootError(walk[i], ref[i]), accuracyBound(ref[i])) << what << " walk " << i;
        // Between the roots nothing: (ref[0], ref[1]) open at both ends has no root.
        if (ref.size() > 1) {
          // (clear of each root's noise region: (2n + 1) u cond wide, and more)
          const double wide = 100 * static_cast<double>(c.size());
          const double a = ref[0].value + wide * kU * ref[0].conditioning;
          const double b = ref[1].value - wide * kU * ref[1].conditioning;
          if (a < b) {
            EXPECT_FALSE(hasRoot(c, {}, a, b, o)) << what;
          }
        }
      }
    }
  }
  // float: the same shape at degree 20 with roots near 1 and 1e8 (float's range holds
  // ~100 binades: split there too). Reference: the float-rounded coefficients, exact in
  // double, through MPFR; float's unit roundoff and 4 u cond.
  for (int k = 0; k < 8; ++k) {
    std::vector<double> roots = {0.25 + 0.5 * uni(rng), 1e8 * (1 + uni(rng))};
    std::vector<std::pair<double, double>> pairs;
    for (int i = 0; i < 9; ++i) pairs.emplace_back(2 * uni(rng) - 1, 0.3 + uni(rng));
    const std::vector<double> cd = test::expand(roots, pairs);
    std::vector<float> cf(cd.begin(), cd.end());
    const std::vector<double> cr(cf.begin(), cf.end());
    const auto ref = test::refineAll(cr, roots, -1e9, 1e9);
    ASSERT_FALSE(ref.empty()) << k;
    const auto r = firstRoot(std::span<const float>(cf), {}, -1e9f, 1e9f);
    ASSERT_TRUE(r) << k;
    EXPECT_LE(rootError(*r, ref[0]), kAccuracyUlps * 0x1p-24 * ref[0].conditioning) << k;
  }
}

// Roots spread over hundreds of binades at low degree (session 52's audit, against sympy's
// exact root isolation): a piece of the split whose coefficients all stayed normal, but
// spanned more than the 916 binades one frame holds (c_0 at 2^-1005 of the largest term),
// was solved in one frame, where G about the smaller roots is made of terms near the
// subnormal range: a quintic with roots 1e-114, 1e-106, 1e-72 and 1e117 lost 1e-114 on
// (0, 1e118] (found on (0, 1e117]), and with closedLo another reported lo = 0, where |g|
// is 1e15 times its noise bound. Now such a frame goes to rangeSplit too. Random quintics
// with roots 10^-150 .. 10^150 alike, on (0, hi] for hi up to 1e300; references MPFR
// roots of the rounded polynomials.
TEST(RootsContract, RootsSpreadOverHundredsOfBinadesAtLowDegree) {
  const std::vector<double> audit = {0x1.9cbae7fe805b3p-881,  -0x1.4f31f8bb6a58dp-502,
                                     0x1.6d601ad376ab9p-150,  0x1.66bb7f0435c9fp+149,
                                     -0x1.961219000356bp+388, 0x1p+0};
  std::vector<std::pair<std::vector<double>, std::vector<double>>> cases = {
      {audit, {1e-114, 1e-106, -1e-90, 1e-72, 1e117}}};
  std::mt19937_64 rng(52);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  while (cases.size() < 41) {
    std::vector<double> roots;
    for (int i = 0; i < 5; ++i)
      roots.push_back((i == 2 ? -1 : 1) * (1 + uni(rng)) * std::pow(10.0, -150 + 300 * uni(rng)));
    const std::vector<double> c = test::expand(roots, {});
    // (every coefficient a normal double: the roots are those of the rounded data)
    if (std::all_of(c.begin(), c.end(), [](double v) {
          return std::abs(v) >= std::numeric_limits<double>::min() && std::abs(v) < 1e300;
        }))
      cases.push_back({c, roots});
  }
  int problems = 0;
  for (const auto& [c, starts] : cases) {
    const double largest = *std::max_element(starts.begin(), starts.end());
    for (const double hi : {2 * largest, 1e3 * largest, 1e300}) {
      if (!(hi > largest) || !std::isfinite(hi)) continue;
      const auto ref = test::refineAll(c, starts, 0.0, hi);
      std::ostringstream what;
      what << "c0 " << c[0] << " hi " << hi;
      ASSERT_FALSE(ref.empty()) << what.str();
      ++problems;
      std::vector<double> out(c.size());
      out.resize(allRoots(c, {}, 0.0, hi, out));
      ASSERT_EQ(out.size(), ref.size()) << what.str();
      for (std::size_t i = 0; i < ref.size(); ++i)
        EXPECT_LE(rootError(out[i], ref[i]), accuracyBound(ref[i])) << what.str() << " root " << i;
      const auto first = firstRoot(c, {}, 0.0, hi);
      ASSERT_TRUE(first) << what.str();
      EXPECT_LE(rootError(*first, ref[0]), accuracyBound(ref[0])) << what.str();
      RootOptions closed;
      closed.closedLo = true;
      const auto firstClosed = firstRoot(c, {}, 0.0, hi, closed);
      ASSERT_TRUE(firstClosed) << what.str();
      EXPECT_LE(rootError(*firstClosed, ref[0]), accuracyBound(ref[0])) << what.str();
    }
  }
  EXPECT_GE(problems, 100);
  // The audit's closedLo case: roots -1.24e117, -8.98e-73, -1.80e-106, -3.37e-114 and
  // 4.67e-91; g(0) = -1.26e-230 against a noise bound of 1.5e-245.
  const std::vector<double> negative = {-0x1.3938277fe5c59p-764, -0x1.2e3e7b6d47b03p-387,
                                        -0x1.6ed45d0833315p-36,  0x1.81588baceb625p+264,
                                        0x1.e5a74da67bc40p+503,  0x1.ee750d892a28fp+114};
  const auto ref = test::refineAll(negative, {4.6732e-91}, 0.0, 1e300);
  ASSERT_EQ(ref.size(), 1u);
  for (const double hi : {1e100, 1e200, 1e300}) {
    RootOptions closed;
    closed.closedLo = true;
    const auto r = firstRoot(negative, {}, 0.0, hi, closed);
    ASSERT_TRUE(r) << hi;
    EXPECT_LE(rootError(*r, ref[0]), accuracyBound(ref[0])) << hi;
  }
}

// Coefficients spread over the whole double range (session 52's review, against mpmath
// sign checks): with the split of RootsSpreadOverHundredsOfBinadesAtLowDegree, allRoots
// reported split points (-2^-427, -2^-585, -2^-850) where g keeps its sign and is far from
// 0: the caller's-grid step (roots_frame.h), put into every frame of an interval below
// 2^-52 with the slope over the whole frame, made g "within noise" at a piece's end. Now
// only frames that reach the subnormal range get it, with the slope there; that also finds
// roots 1.87e-251 and 1.65e-245 (none reported before, then 2^-815 under closedLo) and
// -1.16e-187 (0 reported before, g(0) = 2e-301). Each case: allRoots and the walk agree,
// every answer is an MPFR-certified root, and the counts are the sign changes mpmath saw.
TEST(RootsContract, CoefficientsOverTheWholeDoubleRange) {
  const struct {
    int method;
    bool closedLo;
    double lo, hi;
    std::vector<double> c;
    std::size_t roots;
  } cases[] = {
      {0,
       false,
       0x0.0p+0,
       0x1.7c7b9eb47a107p-79,
       {0x1.747c865953278p-976, -0x1.5c2fea218347cp-143, 0x1.82cb2ede19fb7p+670,
        0x1.be23a4029ae1dp+923, 0x1.c243640aa8016p+1002},
       2},
      {0,
       true,
       0x0.0p+0,
       0x1.7c7b9eb47a107p-79,
       {0x1.747c865953278p-976, -0x1.5c2fea218347cp-143, 0x1.82cb2ede19fb7p+670,
        0x1.be23a4029ae1dp+923, 0x1.c243640aa8016p+1002},
       2},
      {0,
       true,
       -0x1.25d00b0927d69p+43,
       0x0.0p+0,
       {-0x1.814343e5f875ap-849, -0x1.8df5c350c2c8ap-273, -0x1.5fccf19bd07f1p+268,
        -0x1.dc1c6dd7849bbp+736, -0x1.215af4e1ff9c9p+852, 0x1.ec6a23aa98ac6p+818},
       4},
      {0,
       true,
       -0x1.238006f62d58ep-282,
       0x0.0p+0,
       {0x1.3eebfe880d3e5p-955, -0x1.2eda65525fb9bp-49, 0x1.24afba43c022fp+698,
        0x1.010ab6e902370p+981},
       1},
      {0,
       true,
       -0x1.66fb97e3ab47ep-283,
       0x0.0p+0,
       {0x1.23c1bfd98c739p-999, 0x1.20da7f0235c54p-378, -0x1.031609224ec45p+202,
        0x1.03fc44f5ea249p+713, 0x1.72ce0716964b6p+996},
       2},
      {0,
       true,
       -0x1.25a3697f663ecp+174,
       -0x1.e9f39771edd0fp-476,
       {-0x1.3e91fa593a63dp-1000, -0x1.4ce803f023ea2p-526, 0x1.59877893d266ap-93,
        -0x1.4f9e1b67a03c5p+299, -0x1.3e9e5c27a4b27p+644, -0x1.8204ab52122f1p+914,
        0x1.f8cedf000af47p+740},
       3},
      {0,
       false,
       -0x1.8a3c0c2d1f491p-166,
       0x1.8a3c0c2d1f491p-166,
       {-0x1.ec4fd3227b7e6p-912, 0x1.a99825b34e5eep-305, 0x1.bc6476e92ed73p+177,
        0x1.77ed315f2712ap+509, 0x1.7e65738708d6ap+682, 0x1.26e929a41f1afp+851},
       5},
      {2,
       false,
       -0x1.cc2cf0240d432p-162,
       0x0.0p+0,
       {-0x1.b0810ead854d8p-764, -0x1.6d0e47765df0bp+152, -0x1.d16e0f12ca444p+538,
        0x1.02ec4dad52ed7p+701},
       2},
  };
  for (std::size_t k = 0; k < std::size(cases); ++k) {
    const auto& p = cases[k];
    RootOptions o;
    o.method = static_cast<RootMethod>(p.method);
    o.closedLo = p.closedLo;
    std::vector<double> out(p.c.size() + 1);
    out.resize(allRoots(p.c, {}, p.lo, p.hi, out, o));
    EXPECT_EQ(out.size(), p.roots) << k;
    // (the walk: the first query as asked, the next ones from each root, open there)
    std::vector<double> walk;
    if (const auto r0 = firstRoot(p.c, {}, p.lo, p.hi, o)) {
      RootOptions open = o;
      open.closedLo = false;
      walk = walkRoots(p.c, {}, *r0, p.hi, 2 * p.c.size(), open);
      walk.insert(walk.begin(), *r0);
    }
    ASSERT_EQ(walk.size(), out.size()) << k;
    const auto ref = test::refineAll(p.c, out, -std::numeric_limits<double>::infinity(),
                                     std::numeric_limits<double>::infinity());
    ASSERT_EQ(ref.size(), out.size()) << k;
    for (std::size_t i = 0; i < out.size(); ++i) {
      EXPECT_LE(rootError(out[i], ref[i]), accuracyBound(ref[i])) << k << " root " << i;
      EXPECT_LE(rootError(walk[i], ref[i]), accuracyBound(ref[i])) << k << " walk " << i;
    }
    const auto first = firstRoot(p.c, {}, p.lo, p.hi, o);
    ASSERT_TRUE(first) << k;
    EXPECT_LE(rootError(*first, ref[0]), accuracyBound(ref[0])) << k;
  }
}

// RootOptions::relTolerance is a tolerance on each root, not on the critical points that
// split the interval into monotone pieces: with 1e-2 on (-4, 4] a critical point placed
// 0.08 off put both ends of a pair of roots 0.028 apart on one side, and the pair was
// skipped (session 52's audit: 51 of 20000 random problems, firstRoot 0.55 from the first
// root). Random polynomials of degree 4-12 with close pairs of real roots: with every
// tolerance, for Auto and ClosedForm (its quartic; spread roots in the next test), every
// root the full-precision solve finds is reported within the tolerance.
TEST(RootsContract, ToleranceNeverSkipsARoot) {
  std::mt19937_64 rng(5252);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int compared = 0;
  std::vector<std::pair<RootMethod, double>> tolerances;
  for (const RootMethod method : {RootMethod::Auto, RootMethod::ClosedForm})
    for (const double tol : {1e-6, 1e-3, 1e-2, 0.1}) tolerances.emplace_back(method, tol);
  for (int k = 0; k < 3000; ++k) {
    const int degree = 4 + static_cast<int>(uni(rng) * 9);
    std::vector<double> roots;
    std::vector<std::pair<double, double>> pairs;
    while (static_cast<int>(roots.size() + 2 * pairs.size()) < degree) {
      const double x = -3.5 + 7 * uni(rng);
      if (degree - static_cast<int>(roots.size() + 2 * pairs.size()) >= 2 && uni(rng) < 0.5) {
        if (uni(rng) < 0.5)
          roots.insert(roots.end(), {x, x + std::pow(10.0, -3 + 2 * uni(rng))});
        else
          pairs.emplace_back(x, 0.05 + uni(rng));
      } else {
        roots.push_back(x);
      }
    }
    const std::vector<double> c = test::expand(roots, pairs);
    double exact[kMaxDegree], loose[kMaxDegree];
    const int n = allRoots(c, {}, -4.0, 4.0, std::span<double>(exact, c.size()));
    for (const auto& [method, tol] : tolerances) {
      RootOptions o;
      o.method = method;
      o.relTolerance = tol;
      const int m = allRoots(c, {}, -4.0, 4.0, std::span<double>(loose, c.size()), o);
      ASSERT_EQ(m, n) << "problem " << k << " tolerance " << tol << " method "
                      << static_cast<int>(method);
      for (int i = 0; i < n; ++i) EXPECT_NEAR(loose[i], exact[i], 8 * tol + 1e-9) << k << " " << i;
      const auto first = firstRoot(c, {}, -4.0, 4.0, o);
      if (n > 0) {
        ASSERT_TRUE(first) << k;
        EXPECT_NEAR(*first, exact[0], 8 * tol + 1e-9) << "problem " << k << " tolerance " << tol;
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 24000);
}

// The closed-form quartic (RootMethod::ClosedForm) polished its critical points only to the
// tolerance too; where the cubic's closed form starts Newton far off (roots spread over
// decades) a critical point stopped a tolerance away, and a root pair on one side of it was
// skipped: quartics with roots of magnitude 1e-10 - 1e10 at relTolerance 1e-6 - 1e-2 gave
// a first root far from every root in 675 of 60000 solves of a scratch harness until
// session 53 (roots up to 1e30: 3354), e.g. 1.8e9 for the first root 1.2e-6 on (0, 2 max
// |r|]. Reference: the same solver at full precision (checked against MPFR above).
TEST(RootsContract, ClosedFormQuarticToleranceKeepsSpreadRoots) {
  std::mt19937_64 rng(53);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int compared = 0;
  for (int k = 0; k < 3000; ++k) {
    std::vector<double> roots(4);
    for (double& r : roots) r = (uni(rng) < 0.3 ? -1 : 1) * std::pow(10.0, 20 * uni(rng) - 10);
    const std::vector<double> c = test::expand(roots, {});
    double top = 0;
    for (const double r : roots) top = std::max(top, std::abs(r));
    const double lo = uni(rng) < 0.5 ? 0.0 : -2 * top, hi = 2 * top;
    double exact[4], loose[4];
    const int n = allRoots(c, {}, lo, hi, std::span<double>(exact, 4));
    for (const double tol : {1e-6, 1e-3, 1e-2}) {
      RootOptions o;
      o.method = RootMethod::ClosedForm;
      o.relTolerance = tol;
      const double slack = 8 * tol * (hi - lo);
      ASSERT_EQ(allRoots(c, {}, lo, hi, std::span<double>(loose, 4), o), n) << k << " " << tol;
      for (int i = 0; i < n; ++i) EXPECT_NEAR(loose[i], exact[i], slack) << k << " " << i;
      const auto first = firstRoot(c, {}, lo, hi, o);
      ASSERT_EQ(first.has_value(), n > 0) << k;
      if (n > 0) {
        EXPECT_NEAR(*first, exact[0], slack) << "problem " << k << " tolerance " << tol;
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 9000);
}

// The same in float at degree 40, where the terms fall through float's range within two
// binades (session 27's float fuzz against an MPFR sign scan). g = s^40 - 4 s^38 + 2^-8 s
// - 2^-9 (exact in float) has the real roots -2, 0.5, 0.812 and 2: on (0, 8] its frame
// is 2^3 with the largest term 2^120, the terms near 0.5 are 2^-8, below float's range of
// 2^126 there, and C_0 was clamped to the smallest normal number. rangeSplit's split
// point was 2^2 (M(1) = 40 < 120 - 78), whose inner piece has the same frame, so it
// refused to split and the clamped frame answered 2 (the root 0.5 missed; on the fuzz's
// random degree-40 problems, points with a relative residual ~0.5 before the true first
// root, the last case below). Now it splits one binade below that.
// Reference: MPFR roots of the float data (exact in double); float's unit roundoff, 4 u
// (cond + |r|) (the answer is rounded to float).
TEST(RootsContract, FloatDegree40SplitsWhereTheTermsLeaveTheRange) {
  auto near = [](double r, const test::RefRoot& ref) {
    return std::abs(r - ref.value) <=
           kAccuracyUlps * 0x1p-24 * (ref.conditioning + std::abs(ref.value));
  };
  std::vector<float> c(41, 0.0f);
  c[40] = 1;
  c[38] = -4;
  c[1] = 0x1p-8f;
  c[0] = -0x1p-9f;
  const std::vector<double> cd(c.begin(), c.end());
  const auto small = test::refine(cd, 0.5), second = test::refine(cd, 0.81);
  ASSERT_TRUE(small && second);
  for (const auto& [lo, hi] : std::vector<std::pair<float, float>>{
           {0.0f, 8.0f}, {-1.0f, 8.0f}, {0.25f, 8.0f}, {0.0f, 4.0f}, {-1.0f, 1e6f}}) {
    for (const bool closedLo : {false, true}) {
      RootOptions o;
      o.closedLo = closedLo;
      const std::string what = "(" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
      const auto r = firstRoot(std::span<const float>(c), {}, lo, hi, o);
      EXPECT_TRUE(r && near(*r, *small)) << what << ": " << r.value_or(NAN);
      EXPECT_TRUE(hasRoot(std::span<const float>(c), {}, lo, hi, o)) << what;
      // The walk (lo = the previous root, (lo, hi]) goes on to the next root.
      const auto next = firstRoot(std::span<const float>(c), {}, r.value_or(0.5f), hi);
      EXPECT_TRUE(next && near(*next, *second)) << what << ": " << next.value_or(NAN);
      // allRoots (float's since session 27): the same two first, in order.
      float all[kMaxDegree + 1];
      const int n = allRoots(std::span<const float>(c), {}, lo, hi, std::span<float>(all), o);
      ASSERT_GE(n, 2) << what;
      EXPECT_TRUE(near(all[0], *small) && near(all[1], *second))
          << what << ": " << all[0] << ", " << all[1];
    }
  }
  // As the fuzz found it (seed 6, problem 410): random coefficients over 16 decades.
  const std::vector<float> f = {
      0x1.ead998p-25,  -0x1.71a76p+9,   0x1.8a2be4p-21,  0x1.fc2f6cp-15,  -0x1.9ccf94p-5,
      -0x1.7a3122p+0,  -0x1.5c4c8cp-17, 0x1.f0e8d8p-4,   -0x1.21476ap-23, 0x1.8c2e48p-23,
      -0x1.36a842p-1,  -0x1.dcc7f2p-18, -0x1.6514b2p+23, -0x1.1f1e08p+2,  -0x1.d6dc7cp-6,
      0x1.3330c2p+12,  0x1.52f248p+13,  0x1.18364cp-13,  0x1.dd3362p+24,  0x1.19f242p+19,
      0x1.92f4c4p-19,  0x1.c2d40ap+25,  -0x1.3f690ap+23, 0x1.bc542cp-20,  0x1.2d726ap+13,
      -0x1.52d11ep+4,  -0x1.427c2ap-14, 0x1.56e036p+14,  -0x1.01bcbcp-19, -0x1.0ba2c4p-22,
      -0x1.22ebaep+26, -0x1.c77a3ap-14, -0x1.be3a86p+24, -0x1.a8c562p+0,  0x1.352dacp+13,
      -0x1.a992d8p-18, -0x1.7c7ed4p-5,  -0x1.e00e14p-20, -0x1.6ed8b8p+18, 0x1.7f0fd2p-16,
      -0x1.31c8c8p+16};
  const std::vector<double> fd(f.begin(), f.end());
  const auto first = test::refine(fd, -0.4156);  // the first sign change of the data
  ASSERT_TRUE(first);
  RootOptions o;
  o.closedLo = true;
  const auto r = firstRoot(std::span<const float>(f), {}, -0x1.457b0cp+4f, 0x1.73e1b4p+4f, o);
  EXPECT_TRUE(r && near(*r, *first)) << r.value_or(NAN);  // was -0.47137147, residual 0.57
}

// Roots whose values between them underflow (session 18's adversarial campaign). g = s^2 -
// 2^-540 s on (-0.5, 1] has the roots 0 and 2^-540. In one frame (max |C_j| in [1, 2),
// roots_detail.h) G at the critical point 2^-542 (local) is -2^-1084, below the subnormal
// range: Horner gives +0, the noise bound 0, and the two roots merged into one tangent
// cluster (2^-541; Sturm none). Since session 21 exact zeros at the bottom are factored out
// (g = s^k h, roots.cpp): 0 and h's roots, each in its own frame. Checked against the known
// roots for k = 1..3, each query, both interval rules and the walk from 0. (Two non-zero
// roots that close to 0 have a product below the subnormal range: not representable.)
TEST(RootsContract, RootsWhoseValuesBetweenThemUnderflow) {
  for (const RootMethod m : {RootMethod::Auto, RootMethod::Yuksel}) {
    RootOptions o;
    o.method = m;
    for (int k = 1; k <= 3; ++k)
      for (const double t : {0x1p-520, 0x1p-530, 0x1p-540}) {
        std::vector<double> c(static_cast<size_t>(k) + 2, 0.0);  // s^k (s - t)
        c[k] = -t;
        c[k + 1] = 1;
        const std::vector<double> err(c.size(), 0.0);  // zero bounds: the rule still applies
        std::vector<double> out(4);
        out.resize(allRoots(c, err, -0.5, 1.0, out, o));
        ASSERT_EQ(out.size(), 2u) << static_cast<int>(m) << " k " << k << " t " << t;
        EXPECT_EQ(out[0], 0.0);
        EXPECT_NEAR(out[1], t, 4 * kU * t) << static_cast<int>(m) << " k " << k << " t " << t;
        EXPECT_EQ(firstRoot(c, {}, -0.5, 1.0, o), 0.0);
        EXPECT_NEAR(firstRoot(c, {}, 0.0, 1.0, o).value_or(1), t, 4 * kU * t);  // the walk
        RootOptions closed = o;
        closed.closedLo = true;
        EXPECT_EQ(firstRoot(c, {}, 0.0, 1.0, closed), 0.0);
        EXPECT_TRUE(hasRoot(c, {}, 0.0, 1.0, o));
        EXPECT_FALSE(hasRoot(c, {}, t * 2, 1.0, o));
        EXPECT_FALSE(firstRoot(c, {}, -0.5, -t, o).has_value());
        // One output slot: the first root only.
        std::vector<double> one(1);
        EXPECT_EQ(allRoots(c, {}, -0.5, 1.0, one, o), 1);
        EXPECT_EQ(one[0], 0.0);
      }
    // A root of h below 0 comes before the root 0; non-finite coefficients above the
    // zeros still give no root; so does an error bound on the zero coefficient's place
    // that is not zero (then 0 is not known to be a root: the general path decides).
    const std::vector<double> below{0, 0x1p-540, 1};  // s (s + 2^-540)
    EXPECT_NEAR(firstRoot(below, {}, -0.5, 1.0, o).value_or(1), -0x1p-540, 4 * kU * 0x1p-540);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> bad{0, nan, 1};
    EXPECT_FALSE(firstRoot(bad, {}, -0.5, 1.0, o).has_value());
    EXPECT_FALSE(hasRoot(bad, {}, -0.5, 1.0, o));
    std::vector<double> out(3);
    EXPECT_EQ(allRoots(bad, {}, -0.5, 1.0, out, o), 0);
    const std::vector<double> badErr{0, 0, 0}, lin{0, -0.25, 1};
    EXPECT_FALSE(firstRoot(lin, std::vector<double>{0, nan, 0}, -0.5, 1.0, o).has_value());
    EXPECT_EQ(allRoots(lin, badErr, -0.5, 1.0, out, o), 2);
  }
}

// Roots below the normal range (session 42's audit): g = -m 2^-1074 + b s (- a s^2, whose
// other root b / a > 2 lies beyond the interval) on (0, 1] and its mirror on (-1, 0], with m an
// integer and the root m / b 2^-1074 (in units of 2^-1074; the quadratic's differs from it
// by ~1e-320 relative) not on the grid. Every method must report it within one unit of
// the grid, once: in allRoots, as the first root, by hasRoot, and a walk from it must not
// find it again. Before: the frame cut a wide interval to a root bound that, rounded to the
// subnormal grid, lay below the root (no root at all, every method), and a walk from the
// answer (the double below the root) found the same root one unit on.
TEST(RootsContract, SubnormalRootsAreFoundOnce) {
  std::mt19937 rng(4203);
  std::uniform_real_distribution<double> slope(0.5, 8.0), curve(0.5, 3.0);
  std::uniform_int_distribution<int> units(20, 4000);
  const double unit = std::numeric_limits<double>::denorm_min();
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    const int m = units(rng);
    const double b = slope(rng), a = b / (1.5 + curve(rng));  // the other root, b / a > 2
    const bool quadratic = k % 2 == 1, mirrored = k % 4 >= 2;
    const double reference = (mirrored ? -1 : 1) * m / b;  // the root in units of 2^-1074
    std::vector<double> c{-m * unit, b};
    if (quadratic) c.push_back(-a);
    if (mirrored)  // g(-s): the root -m / b units on (-1, 0]
      for (size_t j = 1; j < c.size(); j += 2) c[j] = -c[j];
    const double lo = mirrored ? -1.0 : 0.0, hi = mirrored ? 0.0 : 1.0;
    for (const RootMethod method : {RootMethod::Auto, RootMethod::Yuksel, RootMethod::Sturm,
                                    RootMethod::Bernstein, RootMethod::ClosedForm}) {
      RootOptions o;
      o.method = method;
      const std::string what = "k " + std::to_string(k) + " method " +
                               std::to_string(static_cast<int>(method)) + " root " +
                               std::to_string(reference) + " units";
      std::vector<double> out(4);
      out.resize(allRoots(c, {}, lo, hi, out, o));
      ASSERT_EQ(out.size(), 1u) << what;
      EXPECT_LE(std::abs(out[0] / unit - reference), 1.0) << what;
      const std::optional<double> first = firstRoot(c, {}, lo, hi, o);
      ASSERT_TRUE(first.has_value()) << what;
      EXPECT_LE(std::abs(*first / unit - reference), 1.0) << what;
      EXPECT_TRUE(hasRoot(c, {}, lo, hi, o)) << what;
      if (!mirrored) {  // the walk from the root (a mirrored one's next query: (r, 0])
        EXPECT_FALSE(firstRoot(c, {}, *first, hi, o).has_value()) << what;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 1000);
}

// Exact zeros at the bottom at every degree: g = s^k q with a k-fold root at 0 (k = 1..3)
// and ray-shaped q (random real roots, complex pairs, any scale), on intervals around 0,
// from 0 and beside it. Each problem gets checkProblem (MPFR references of the rounded
// polynomial: every well-conditioned root within 4 u cond, first root, hasRoot and the
// walk agreeing, every answer a root of the data), and 0 is reported exactly once where
// the interval holds it.
TEST(RootsContract, ExactZerosAtTheBottomAtEveryDegree) {
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int deg : issueDegrees(4)) {
    for (int trial = 0; trial < 6; ++trial) {
      const int k = 1 + trial % 3;
      const int nReal = std::min(rayRealRootCount(deg - k, uni(rng)), deg - k);
      std::vector<double> roots(static_cast<size_t>(k), 0.0);
      for (int i = 0; i < nReal; ++i) roots.push_back(-1 + 2 * uni(rng));
      std::vector<std::pair<double, double>> pairs;
      for (int i = 0; i < (deg - k - nReal) / 2; ++i)
        pairs.emplace_back(-1.5 + 3 * uni(rng), std::pow(10.0, -2 + 2 * uni(rng)));
      if (static_cast<int>(roots.size() + 2 * pairs.size()) < deg) roots.push_back(uni(rng));
      const double lead = (uni(rng) < 0.5 ? -1 : 1) * std::pow(10.0, -3 + 6 * uni(rng));
      const double lo = trial < 3 ? -0.3 - uni(rng) : (trial == 3 ? 0.0 : 0.05);
      const double hi = 0.2 + uni(rng);
      Problem p = fromRoots("degree " + std::to_string(deg) + " k " + std::to_string(k) +
                                " trial " + std::to_string(trial),
                            roots, pairs, lo, hi, lead);
      ASSERT_EQ(static_cast<int>(p.c.size()), deg + 1);
      for (int j = 0; j < k; ++j) ASSERT_EQ(p.c[j], 0.0);  // the rule applies
      checkProblem(p);
      const std::vector<double> all = solveAll(p);
      const auto zeros = std::count(all.begin(), all.end(), 0.0);
      EXPECT_EQ(zeros, lo < 0 ? 1 : 0) << p.name;
      if (lo < 0) {
        EXPECT_TRUE(hasRoot(p.c, {}, p.lo, p.hi));
      }
    }
  }
}

}  // namespace
}  // namespace algray
