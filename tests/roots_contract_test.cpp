// Tests of roots.h's contract (roots.h's file comment): the interval ends and the walk
// firstRoot(c, err, previousRoot, hi), noise-level ends and nodes, scale invariance, frames
// at the edges of double's range, exact zeros at 0, the quadratic fast path and bad input.
// The references are independent as in roots_test.cpp: MPFR roots of the rounded
// polynomial, its long-double values against the noise rule's bound, or closed forms.
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

// ---- Interval ends, noise, bad input -------------------------------------------------

// Long intervals at degrees 13-40 (the subdivision with per-coefficient bounds): g =
// (x - r) q(x) or (x - r)^2 q(x), q complex pairs 0.05-1 off the axis (and one real root
// below the interval), 300 problems per degree. The reference is the rounded polynomial
// itself, evaluated in long double (64-bit significand): (a) an answer before r must be
// within the noise rule's bound there (a grazing or noise-level answer, never a value of g
// beyond its rounding); (b) when g changes sign clearly at r -+ 1e-4 and nothing is
// answered before, the answer is r within 1e-4. The session-start solver answered 0.9896
// for the clear simple root 0.5368 of one degree-37 problem (its bound was set by the
// interval's far end); it also missed 2.5x as many tangent roots, which (b) does not
// demand (a double root may round into a complex pair).
TEST(RootsContract, HighDegreeLongIntervalsKeepEveryClearRoot) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0, 1);
  int clearChecked = 0;
  for (int tangent = 0; tangent <= 1; ++tangent)
    for (int deg = 13; deg <= 40; ++deg)
      for (int t = 0; t < 300; ++t) {
        const double r = 0.1 + 0.8 * unit(rng);
        std::vector<double> p =
            tangent ? std::vector<double>{r * r, -2 * r, 1} : std::vector<double>{-r, 1};
        int d = tangent ? 2 : 1;
        for (; d + 2 <= deg; d += 2) {
          const double a = 2 * unit(rng) - 0.5, b = 0.05 + unit(rng);
          p = product(p, {a * a + b * b, -2 * a, 1});
        }
        if (d < deg) p = product(p, {1.5 + unit(rng), 1});
        const double lo = -0.2 * unit(rng), hi = 1.0 + 0.5 * unit(rng);
        const std::optional<double> got = firstRoot(p, {}, lo, hi);
        const std::string what = "degree " + std::to_string(deg) +
                                 (tangent ? " (x - r)^2" : " (x - r)") +
                                 " r = " + std::to_string(r);
        long double bound;
        if (got && *got < r - 1e-4) {
          const long double v = evalLong(p, *got, bound);
          EXPECT_LE(std::fabs(v), acceptedBound(p, bound))
              << what << ": answer " << *got << " beyond the noise bound";
          continue;
        }
        long double b0, b1;
        const long double g0 = evalLong(p, r - 1e-4, b0), g1 = evalLong(p, r + 1e-4, b1);
        if (std::fabs(g0) > b0 && std::fabs(g1) > b1 && std::signbit(g0) != std::signbit(g1)) {
          ++clearChecked;
          ASSERT_TRUE(got.has_value()) << what << ": no root";
          EXPECT_NEAR(*got, r, 1e-4) << what;
        }
      }
  EXPECT_GT(clearChecked, 8000);  // the clear simple roots (tangent ones rarely clear)
}

TEST(RootsContract, IntervalEnds) {
  const std::vector<double> c{-0.5, 1};  // root 0.5
  EXPECT_FALSE(firstRoot(c, {}, 0.5, 1.0).has_value());
  EXPECT_EQ(firstRoot(c, {}, 0.0, 0.5), 0.5);  // (lo, hi]: a root on hi is reported
  EXPECT_EQ(firstRoot(c, {}, 0.0, 1.0), 0.5);
  // Cubic with roots 0, 1/2, 1 on (0, 1): only 1/2 and 1.
  const std::vector<double> cubic{0, 0.5, -1.5, 1};
  std::vector<double> out(4);
  out.resize(allRoots(cubic, {}, 0.0, 1.0, out));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0], 0.5, 1e-15);
  EXPECT_EQ(out[1], 1.0);
}

// solveFirstRoot's atNoise: a root at a sign change of g is not one of the noise rules; a
// double root (an extremum within the noise bound, the tangent rule), a quadruple one
// within its noise region of a closed lo, and a root within noise of hi are. The same
// root as the plain call, in double and in float.
TEST(RootsContract, AtNoiseTellsTheNoiseRulesRoots) {
  const std::vector<double> simple{-0.25, 1.0};                                    // 1/4
  const std::vector<double> doubleRoot = test::expand({0.5, 0.5, -3.0}, {}, 1.0);  // 1/2 twice
  const std::vector<double> quadruple = test::expand({0.3, 0.3, 0.3, 0.3, -0.75}, {}, 1.0);
  RootOptions closed;
  closed.closedLo = true;
  struct Case {
    const std::vector<double>* c;
    double lo, hi;
    RootOptions o;
    bool noise;
  };
  for (const Case& k :
       {Case{&simple, 0.0, 1.0, {}, false}, Case{&doubleRoot, 0.0, 1.0, {}, true},
        Case{&quadruple, 0.3 - 1e-6, 1.0, closed, true}, Case{&simple, 0.0, 0.25, {}, true}}) {
    double r = -1, plain = -2;
    bool atNoise = !k.noise;
    ASSERT_TRUE(solveFirstRoot(*k.c, {}, k.lo, k.hi, r, atNoise, k.o)) << (*k.c)[0];
    ASSERT_TRUE(solveFirstRoot(*k.c, {}, k.lo, k.hi, plain, k.o));
    EXPECT_EQ(r, plain) << (*k.c)[0];
    EXPECT_EQ(atNoise, k.noise) << (*k.c)[0] << " on (" << k.lo << ", " << k.hi << "]";
    const std::vector<float> cf(k.c->begin(), k.c->end());
    float rf = -1;
    bool atNoiseF = !k.noise;
    ASSERT_TRUE(solveFirstRoot(std::span<const float>(cf), {}, static_cast<float>(k.lo),
                               static_cast<float>(k.hi), rf, atNoiseF, k.o));
    EXPECT_EQ(atNoiseF, k.noise) << "float " << (*k.c)[0];
  }
}

// RootOptions::noiseBefore through the public call: g = (s + 1/2)^3 + (s + 1/2)/100 -
// 0.0956 (in power form below) is increasing with its one root near -0.05; with an error
// bound 0.2 on the s coefficient its noise bound 0.2|s| covers |g| over a shelf about
// -0.947 .. -0.477 (a function within those errors of g may have two roots there), then g
// is clear up to the root's own noise region (tests/roots_scan_test.cpp has the regions).
// With the query: atNoise, and a point before the clear stretch where |g| is within that
// bound (checked here in long double, with 1 % to spare). With an error bound of 1e-12
// the query changes nothing; a root whose own noise region is wider than 2^-20 of the
// interval is reported with atNoise, unmoved. In double and in float.
template <class T>
void expectNoiseBefore() {
  const std::vector<T> c{T(0.0344), T(0.76), T(1.5), T(1.0)};
  const std::vector<T> wide{0, T(0.2), 0, 0}, narrow{0, T(1e-12), 0, 0};
  RootOptions query;
  query.noiseBefore = true;
  auto gAt = [&](long double s) {
    return ((static_cast<long double>(c[3]) * s + c[2]) * s + c[1]) * s + c[0];
  };
  T plain = 0, r = 0;
  bool atNoise = false;
  ASSERT_TRUE(solveFirstRoot(std::span<const T>(c), std::span<const T>(wide), T(-1), T(0.2), r,
                             atNoise, query));
  EXPECT_TRUE(atNoise);
  EXPECT_GT(r, T(-1));
  EXPECT_LT(r, T(-0.47));
  EXPECT_LE(std::abs(gAt(r)), 0.2L * std::abs(static_cast<long double>(r)) * 1.01L) << r;

  atNoise = true;
  ASSERT_TRUE(solveFirstRoot(std::span<const T>(c), std::span<const T>(narrow), T(-1), T(0.2), r,
                             atNoise, query));
  EXPECT_FALSE(atNoise);
  ASSERT_TRUE(solveFirstRoot(std::span<const T>(c), std::span<const T>(narrow), T(-1), T(0.2),
                             plain, RootOptions{}));
  EXPECT_EQ(r, plain);
  EXPECT_NEAR(r, -0.05, 1e-3);

  const std::vector<T> line{T(-0.25), T(1.0)}, lineErr{T(1e-3), 0};  // noise region 2e-3 wide
  atNoise = false;
  ASSERT_TRUE(solveFirstRoot(std::span<const T>(line), std::span<const T>(lineErr), T(0), T(1), r,
                             atNoise, query));
  EXPECT_TRUE(atNoise);
  ASSERT_TRUE(solveFirstRoot(std::span<const T>(line), std::span<const T>(lineErr), T(0), T(1),
                             plain, RootOptions{}));
  EXPECT_EQ(r, plain);
}
TEST(RootsContract, NoiseBeforeReportsAStretchWithinNoise) {
  expectNoiseBefore<double>();
  expectNoiseBefore<float>();
}

// RootOptions::closedLo: the interval becomes [lo, hi]. A simple root exactly at lo and a
// quadruple root within its noise region of lo (rounded coefficients: about u^(1/4) of
// the scale) are reported with it and not without it, by every method; a root inside
// is unaffected.
TEST(RootsContract, ClosedLoReportsARootAtLo) {
  const std::vector<double> linear{-0.25, 1.0};  // x - 1/4
  const std::vector<double> quadruple =
      test::expand({0.3, 0.3, 0.3, 0.3, -0.75}, {}, 1.0);  // root 0.3 (rounded)
  const std::vector<double> inside = test::expand({0.5, -0.2, 0.9}, {}, 1.0);
  for (RootMethod m : {RootMethod::Auto, RootMethod::ClosedForm, RootMethod::Yuksel,
                       RootMethod::Sturm, RootMethod::Bernstein}) {
    RootOptions open, closed;
    open.method = closed.method = m;
    closed.closedLo = true;
    const int id = static_cast<int>(m);
    EXPECT_FALSE(firstRoot(linear, {}, 0.25, 1.0, open)) << id;
    ASSERT_TRUE(firstRoot(linear, {}, 0.25, 1.0, closed)) << id;
    EXPECT_EQ(*firstRoot(linear, {}, 0.25, 1.0, closed), 0.25) << id;
    EXPECT_TRUE(hasRoot(linear, {}, 0.25, 1.0, closed)) << id;
    // lo 1e-6 before the quadruple root: inside its noise region.
    EXPECT_FALSE(firstRoot(quadruple, {}, 0.3 - 1e-6, 1.0, open)) << id;
    const auto q = firstRoot(quadruple, {}, 0.3 - 1e-6, 1.0, closed);
    ASSERT_TRUE(q) << id;
    EXPECT_NEAR(*q, 0.3, 1e-3) << id;
    std::vector<double> all(8);
    all.resize(allRoots(quadruple, {}, 0.3 - 1e-6, 1.0, all, closed));
    EXPECT_EQ(all.size(), 1u) << id;
    // A root away from lo: the same answer either way.
    EXPECT_EQ(firstRoot(inside, {}, -0.5, 1.0, open), firstRoot(inside, {}, -0.5, 1.0, closed))
        << id;
  }
}

// At degree 33-40 the noise bound of a long interval's far end exceeds |G| there, and a
// monotone piece then runs from a clearly non-zero end into a noise-level one, with its
// root far from that end: (9/8 - s)^n - 1 on (-11/8, 13/8] has the simple root 1/8
// (condition (5/4)^n / n: 1e-14 accuracy), no other root there (-7/8 is outside), and
// |G| >= 1 at hi in exact arithmetic. The sweep reported hi (found by algray-query on
// "(x+1)^35 - 1" seen from x = 3). Its mirror image, the noise-level end at an open lo,
// must find the root -1/8 after it too. Coefficients: the binomial expansion in long
// double, rounded once.
TEST(RootsContract, SimpleRootBeforeANoiseLevelEnd) {
  for (int n = 30; n <= kMaxDegree; ++n) {
    std::vector<double> falling(n + 1), rising(n + 1);  // (9/8 - s)^n - 1, (9/8 + s)^n - 1
    long double binomial = 1;
    for (int i = 0; i <= n; ++i) {
      rising[i] = static_cast<double>(binomial * std::pow(1.125L, n - i));
      falling[i] = i % 2 ? -rising[i] : rising[i];
      binomial = binomial * (n - i) / (i + 1);
    }
    falling[0] -= 1;
    rising[0] -= 1;
    for (RootMethod m : {RootMethod::Auto, RootMethod::Yuksel}) {
      RootOptions open, closed;
      open.method = closed.method = m;
      closed.closedLo = true;
      const std::string what =
          "n = " + std::to_string(n) + ", method " + std::to_string(static_cast<int>(m));
      for (const RootOptions& o : {open, closed}) {
        const auto r = firstRoot(falling, {}, -1.375, 1.625, o);
        ASSERT_TRUE(r) << what;
        EXPECT_NEAR(*r, 0.125, 1e-12) << what;
        std::vector<double> all(4);
        all.resize(allRoots(falling, {}, -1.375, 1.625, all, o));
        ASSERT_FALSE(all.empty()) << what;
        EXPECT_NEAR(all[0], 0.125, 1e-12) << what;
      }
      const auto r = firstRoot(rising, {}, -1.625, 1.375, open);
      ASSERT_TRUE(r) << what;
      EXPECT_NEAR(*r, -0.125, 1e-12) << what;
    }
  }
}

// The walk from a grazing root past a node that is within noise at its ends only (the
// noise-node rule of roots_subdivide.h, degrees above 20). A degree-40 polynomial
// (adversarial campaign, session 18: a tangent problem (s - a)^2 + d times pairs, d 1e-4 of
// the noise bound at a, expanded in MPFR and rounded) with a grazing root at 1.5952 and
// a second one in the noise region from 2.42 on (|g| below its bound gamma(81) sum |c_i|
// |s|^i there, 1.65e11 against 7.8e11 at 2.56); between them |g| clears its bound by up to
// 5e4. allRoots reports both; firstRoot from the first skipped the second: its first node
// had both ends within noise, and the bound of the rule, the noise at the node's far end,
// is 1e4 times that at 1.6, so the node was dropped. The rule now also asks G within noise
// at the quarter points.
TEST(RootsContract, WalkPastANoiseLevelNode) {
  const std::vector<double> c{
      -0x1.143c5085dd639p+59, 0x1.4349e3721ef7ep+62,  -0x1.2d7f52e36c9bep+64,
      0x1.ebb05644e1681p+64,  -0x1.5da1a51f8982ap+63, -0x1.2c982fe853084p+65,
      0x1.e3e40757fa49p+65,   -0x1.c17800dee520ap+64, -0x1.3a7a75284b3fp+64,
      0x1.198bcf50d2ebbp+65,  -0x1.35607d465194ap+64, -0x1.31994eb0b085ep+59,
      0x1.0dd6bf6941475p+63,  -0x1.5d5bfbd67a507p+62, -0x1.53e753ab24338p+56,
      0x1.3c45e5c0dba9ap+61,  -0x1.ac8a6ee3bbc8ep+60, 0x1.40ee7e6d6bfefp+58,
      0x1.90ee63bbda5dap+57,  -0x1.dd723930dc4b4p+56, -0x1.99d560af3784ep+52,
      0x1.abdab70139092p+54,  -0x1.0e110841bdf57p+53, -0x1.50aac78e440d5p+50,
      0x1.b38d9d0216c0ep+50,  -0x1.d31e34a75a8f3p+48, -0x1.0ee5048cbbe8ap+44,
      0x1.6dbd4a866c739p+45,  -0x1.97159117f023dp+43, 0x1.a0ec19e72c3f2p+39,
      0x1.cefcde8d22641p+38,  -0x1.35b74f2d01c93p+37, 0x1.311b60bf01126p+34,
      0x1.c885bd52eab74p+29,  -0x1.8f9a9959c0c1bp+29, 0x1.3e972cce6bb4fp+27,
      -0x1.2f593d972e626p+24, 0x1.7e63f1aa739a1p+20,  -0x1.3bf9d8295b2ebp+16,
      0x1.39060eae673dp+11,   -0x1.1bb16681a882fp+5};
  const double lo = -0x1.092d04a700c97p+1, hi = 0x1.be89e852f323cp+1;
  std::vector<double> all(kMaxDegree + 1);
  all.resize(allRoots(c, {}, lo, hi, all));
  ASSERT_EQ(all.size(), 2u);
  EXPECT_NEAR(all[0], 1.5952, 1e-3);
  EXPECT_GT(all[1], 2.4);
  const std::vector<double> walk = walkRoots(c, {}, lo, hi, 4);
  ASSERT_EQ(walk.size(), all.size());
  EXPECT_NEAR(walk[0], all[0], 1e-3);
  EXPECT_GT(walk[1], 2.4);  // in the same noise region as all[1]
  for (double r : walk) {
    long double bound;
    const long double v = evalLong(c, r, bound);
    EXPECT_LE(std::fabs(v), acceptedBound(c, bound)) << r;
  }
}

// The walk from a root past a clean stretch to a root within noise of hi (adversarial
// campaign, session 18: a degree-35 tangent problem with coefficient error bounds).
// allRoots on (-310.69, 932.0765] gives -0.00682, 700.157 and hi (|g| within its bound from
// about 905 on); firstRoot from 700.157 gave none, though |g| clears its bound by up to
// 600x between 704 and 880. In exact arithmetic g' has one root in (700.157, hi), 738.96
// (g's minimum), and is within its own noise bound from about 905 on; the derivative
// chain's polish of g' started at the secant point, inside that noise region, stopped
// there by the noise rule (913.1, slope untrusted), so g's sweep saw no critical point
// in the clean stretch and merged the cluster at lo with the one at hi. The polish now
// looks for a clear point of the other sign beside an untrusted noise-level stop
// (rootBesideNoise, roots_detail.h). Fails without it (walk 2 roots, allRoots 3).
TEST(RootsContract, WalkPastACleanStretchToANoiseLevelHi) {
  const std::vector<double> c{
      0x1.452c2eb756ec5p+300,  0x1.7463990d74e83p+308,  0x1.aa720eaa7d2eep+314,
      -0x1.2c976581f5dcfp+307, -0x1.493faddb77b0dp+300, 0x1.255dc6b4b80bep+293,
      0x1.33cd314bdc9c7p+284,  -0x1.055bd902ab4f4p+278, 0x1.7ba0ed9844742p+268,
      0x1.127ea683b1242p+261,  -0x1.0a41399c1e7cfp+253, 0x1.dbd1eeffa7e4ep+240,
      0x1.771f1d2b2fefbp+235,  -0x1.96f035c50aa89p+226, 0x1.42e906e0db0bp+203,
      0x1.4dab44f799c8ep+208,  -0x1.061e0dc73e7cfp+199, -0x1.4098ff667e81p+183,
      0x1.08c466c8da80fp+180,  -0x1.51ca8622055d4p+170, 0x1.45f18dcc22b33p+156,
      0x1.98768420b62a4p+150,  -0x1.d61b9230267e3p+140, 0x1.8d627ba78503cp+128,
      0x1.20b882bf2789ap+120,  -0x1.576da6da08928p+110, 0x1.1095fd92579a4p+99,
      0x1.c69069b398915p+87,   -0x1.9fd63e2f1bf14p+78,  0x1.ec2316dc083fep+67,
      -0x1.170f02dc2ecf3p+56,  0x1.1071f2e1b684ap+37,   0x1.e46534e33a4ffp+32,
      -0x1.6cd830786e0bp+21,   0x1.f754dce9a1079p+8,    -0x1.1e31358adf45dp-5};
  const std::vector<double> err{
      0x1.78a9a0b440adp+252,  0x1.af5b0bc6750a2p+260, 0x1.edf8c7c983dedp+266,
      0x1.5c30664cd0fffp+259, 0x1.7d625bd338771p+252, 0x1.53d1e5df1060dp+245,
      0x1.648a78b134967p+236, 0x1.2ebe7ccf4110cp+230, 0x1.b7bdd855301ddp+220,
      0x1.3df5c776a4638p+213, 0x1.346a55460c82ap+205, 0x1.139511eac0a75p+193,
      0x1.b2855402e4b5cp+187, 0x1.d7602c788efddp+178, 0x1.760ac3c531b76p+155,
      0x1.828121f215fa1p+160, 0x1.2f9f7210d6e4bp+151, 0x1.735cfd57a9c09p+135,
      0x1.32b13517f6c44p+132, 0x1.87477bb802709p+122, 0x1.798e40958ae84p+108,
      0x1.d9244893611e4p+102, 0x1.10461bc98b343p+93,  0x1.cc4f2c7da2946p+80,
      0x1.4e7050ef84696p+72,  0x1.8dcf202c2d06bp+62,  0x1.3bbfbdd3bbb6cp+51,
      0x1.07457c710cc0cp+40,  0x1.e1aeecf8c32a3p+30,  0x1.1d085e0a492e2p+20,
      0x1.433f256001728p+8,   0x1.3b95fe1eed789p-11,  0x1.188c837efd9bdp-15,
      0x1.a69dce2300fb3p-27,  0x1.238425aa4fd23p-39,  0x1.4b828437ea889p-53};
  const double lo = -0x1.36b131d841691p+8, hi = 0x1.d209cac4621d9p+9;
  std::vector<double> all(kMaxDegree + 1);
  all.resize(allRoots(c, err, lo, hi, all));
  const std::vector<double> walk = walkRoots(c, err, lo, hi, all.size() + 2);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[2], hi);
  ASSERT_EQ(walk.size(), all.size());
  // The same roots: the root near 700.157 has a noise region ~0.02 wide (the caller's
  // error bounds), which the two queries' different brackets end at different points of.
  for (size_t i = 0; i < walk.size(); ++i)
    EXPECT_NEAR(walk[i], all[i], 1e-6 * std::fabs(all[i]) + 1e-12) << i;
}

// The general mechanism of WalkPastACleanStretchToANoiseLevelHi: random tangent problems
// of degree 21-40 (a factor (s - a)^2 + b^2 whose minimum is 1e-4..1e4 times the noise
// bound at a, real roots and complex pairs; half with coefficient error bounds 2^-40..2^-51
// relative), on spans (lo, hi] with lo in [0.75, 0.95] hi, where the derivative chain runs
// (the exclusion test settles such spans; the noise bound grows like (hi / lo)^n over
// them, so a derivative's piece can run from its root into a wide noise region). The walk
// firstRoot(c, err, previousRoot, hi) must give the roots allRoots gives, up to noise:
// each root of one list has a root of the other with |g| within 16 times its bound
// (long double) at 64 points between them, and between consecutive roots of the walk
// every point where |g| clears 16 times its bound has the same sign (no skipped root).
// Every reported root has |g| within twice its bound (the bound is rigorous for the
// computed value). Without rootBesideNoise (roots_detail.h) problem 3329 below (degree 37)
// fails: the walk skips a root allRoots reports (seeds 1-8: one such problem in 8 x 15000;
// in the session's campaign with MPFR-expanded problems 3 of 9000, |g| 400-600 times its
// bound between the roots). 0.8 s.
constexpr int kWalkProblems = 15000;
constexpr int kWholeSpanProblems = 3000;

// Span shapes: lo in [0.75, 0.95] hi (Near), around 0 (lo in [-hi, -0.3 hi]), from near 0
// (lo in [0, 0.02 hi]).
enum class WalkSpan { Near, AroundZero, FromNearZero };

void checkWalksOnTangentProblems(WalkSpan span, unsigned seed, int count) {
  auto valueAndBound = [](const std::vector<double>& c, const std::vector<double>& err,
                          long double x, long double& bound) {
    const int n = static_cast<int>(c.size()) - 1;
    const long double gam = (2.0L * n + 1) * 0x1p-53L / (1 - (2.0L * n + 1) * 0x1p-53L);
    long double v = 0, b = 0;
    for (int i = n; i >= 0; --i) {
      v = v * x + c[i];
      b = b * std::fabs(x) + (err.empty() ? 0 : err[i]) + gam * std::fabs(c[i]);
    }
    bound = b;
    return v;
  };
  auto ratio = [&](const std::vector<double>& c, const std::vector<double>& err, long double x) {
    long double b;
    const long double v = valueAndBound(c, err, x, b);
    return v / b;  // signed: |ratio| > 1 is clear of the bound
  };
  // Whether |g| stays within 16 times its bound between x and y (64 points).
  auto together = [&](const std::vector<double>& c, const std::vector<double>& err, double x,
                      double y) {
    for (int k = 1; k < 64; ++k)
      if (std::fabs(ratio(c, err, x + (static_cast<long double>(y) - x) * k / 64)) > 16)
        return false;
    return true;
  };
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  int problems = 0, walkedRoots = 0;
  for (int t = 0; t < count; ++t) {
    const int n = 21 + static_cast<int>(rng() % 20);
    const double scale = std::ldexp(1.0, static_cast<int>(rng() % 21) - 10);
    const double hi = scale * (0.5 + unit(rng));
    const double lo = span == WalkSpan::Near         ? hi * (0.75 + 0.2 * unit(rng))
                      : span == WalkSpan::AroundZero ? -hi * (0.3 + 0.7 * unit(rng))
                                                     : hi * 0.02 * unit(rng);
    // Factors: tangent ones (s - a)^2 + b^2 (b set below), real roots, complex pairs.
    std::vector<double> real;
    std::vector<std::pair<double, double>> pairs;
    const int nTangent = 1 + static_cast<int>(rng() % 2);
    for (int k = 0; k < nTangent; ++k) pairs.push_back({lo + (hi - lo) * unit(rng), 0.0});
    int deg = 2 * nTangent;
    for (int k = static_cast<int>(rng() % 4); k > 0 && deg < n; --k, ++deg)
      real.push_back(lo + (hi - lo) * unit(rng));
    for (; deg + 2 <= n; deg += 2)
      pairs.push_back({lo - scale + 3 * scale * unit(rng), scale * std::pow(10.0, -3 * unit(rng))});
    if (deg < n) real.push_back(lo - scale * (1 + unit(rng)));
    const double lead = std::ldexp(1.0, static_cast<int>(rng() % 200) - 100);
    const bool withErr = rng() % 2;
    const double rel = std::ldexp(1.0, -40 - static_cast<int>(rng() % 12));
    auto build = [&] {
      std::vector<double> c{lead};
      for (double r : real) c = product(c, {-r, 1});
      for (auto [a, b] : pairs) c = product(c, {a * a + b * b, -2 * a, 1});
      return c;
    };
    auto errOf = [&](const std::vector<double>& c) {
      std::vector<double> err;
      if (withErr)
        for (double x : c) err.push_back(std::fabs(x) * rel * (0.5 + unit(rng)));
      return err;
    };
    std::vector<double> c = build();
    // b^2 = m noise(a) / q(a), q = g / (s - a)^2 estimated at a + (hi - lo) / 100: the
    // tangent factor's minimum is about m times the noise bound there.
    for (int k = 0; k < nTangent; ++k) {
      const double m = std::pow(10.0, -4 + 8 * unit(rng));
      const double a = pairs[k].first, h = (hi - lo) / 100;
      long double noiseA, unused;
      valueAndBound(c, errOf(c), a, noiseA);
      const double q =
          static_cast<double>(std::fabs(valueAndBound(c, {}, a + h, unused))) / (h * h);
      if (q > 0) pairs[k].second = std::sqrt(m * static_cast<double>(noiseA) / q);
    }
    c = build();
    const std::vector<double> err = errOf(c);
    std::vector<double> all(kMaxDegree + 1);
    all.resize(allRoots(c, err, lo, hi, all));
    // Not const: the checks below take &all and &walk as one pointer type.
    std::vector<double> walk = walkRoots(c, err, lo, hi, all.size() + 3);
    ++problems;
    walkedRoots += static_cast<int>(walk.size());
    for (const auto* list : {&all, &walk})
      for (double r : *list) EXPECT_LE(std::fabs(ratio(c, err, r)), 2) << t << ": root " << r;
    for (const auto& [from, to] : {std::pair{&all, &walk}, std::pair{&walk, &all}})
      for (double r : *from) {
        bool found = false;
        for (double s : *to) found = found || together(c, err, r, s);
        EXPECT_TRUE(found) << "problem " << t << ", degree " << n << ": root " << r << " of "
                           << (from == &all ? "allRoots" : "the walk") << " (" << all.size()
                           << " against " << walk.size() << ")";
      }
    std::vector<double> ends{lo};
    ends.insert(ends.end(), walk.begin(), walk.end());
    ends.push_back(hi);
    for (size_t i = 0; i + 1 < ends.size(); ++i) {
      int sign = 0;
      for (int k = 1; k < 128; ++k) {
        const long double x = ends[i] + (static_cast<long double>(ends[i + 1]) - ends[i]) * k / 128;
        const long double q = ratio(c, err, x);
        if (std::fabs(q) <= 16) continue;
        const int s = q > 0 ? 1 : -1;
        EXPECT_TRUE(sign == 0 || s == sign)
            << "problem " << t << ": a sign change at " << x << " between walked roots";
        sign = s;
      }
    }
  }
  EXPECT_EQ(problems, count);
  EXPECT_GT(walkedRoots, count / 4);
}

TEST(RootsContract, WalkMatchesAllRootsOnTangentProblems) {
  checkWalksOnTangentProblems(WalkSpan::Near, 5, kWalkProblems);
}

// The same on whole spans (around 0 and from near 0), where the subdivision and its
// noise-node rule run (roots_subdivide.h: above degree 20 a node within noise reports
// nothing, proved to 4 times the noise bound since session 20). 1.0 s.
TEST(RootsContract, WalkMatchesAllRootsOnWholeSpans) {
  checkWalksOnTangentProblems(WalkSpan::AroundZero, 6, kWholeSpanProblems);
  checkWalksOnTangentProblems(WalkSpan::FromNearZero, 7, kWholeSpanProblems);
}

TEST(RootsContract, NoiseLeadingCoefficientIsDropped) {
  // x^2 - 1 + 1e-30 x^3: the cubic term is rounding noise on [-2, 2]; its far root
  // (-1e30) is outside anyway, but a solver that kept it would see a degree-3 problem.
  const std::vector<double> c{-1, 0, 1, 1e-30};
  std::vector<double> out(4);
  out.resize(allRoots(c, {}, -2.0, 2.0, out));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0], -1);
  EXPECT_DOUBLE_EQ(out[1], 1);
  // With a caller's error bound larger than the leading coefficient it is dropped too.
  const std::vector<double> d{-1, 0, 1, 1e-10}, err{0, 0, 0, 2e-10};
  out.assign(4, 0);
  out.resize(allRoots(d, err, -2.0, 2.0, out));
  EXPECT_EQ(out.size(), 2u);
}

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

TEST(RootsContract, QuadraticFastPathIsFirstRoot) {
  // firstRootQuadratic promises firstRoot's answer bit for bit (the frame scaling it
  // skips is exact). Random quadratics of every shape the quadric path produces: two
  // roots, tangent (double root within noise), no root, roots on or near the ends,
  // noise-level leading coefficients, caller error bounds, and huge/tiny scales that
  // take its fallback.
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> uni(-1, 1);
  int compared = 0, found = 0;
  for (int i = 0; i < 20000; ++i) {
    const double scale = std::ldexp(1.0, static_cast<int>(uni(rng) * (i % 10 == 0 ? 400 : 30)));
    const double r0 = uni(rng) * 2, r1 = (i % 7 == 0) ? r0 * (1 + 1e-9 * uni(rng)) : uni(rng) * 2;
    const double lead = (i % 13 == 0 ? 1e-17 : 1.0) * uni(rng);
    std::array<double, 3> c{lead * r0 * r1 * scale, -lead * (r0 + r1) * scale, lead * scale};
    if (i % 11 == 0) {
      // A double root lifted by 0 to 12 rounding units of g at the vertex: the tangent
      // rule's verdict flips inside this range, so both paths must use the same bound.
      c = {lead * r0 * r0 * scale, -2 * lead * r0 * scale, lead * scale};
      const double v = r0, mag = std::abs(c[0]) + std::abs(c[1] * v) + std::abs(c[2] * v * v);
      c[0] += std::copysign(std::abs(uni(rng)) * 12 * kU * mag, lead);
    }
    std::array<double, 3> err{0, 0, 0};
    if (i % 3 == 0)
      for (int k = 0; k < 3; ++k) err[k] = 1e-14 * std::abs(c[k]) * std::abs(uni(rng));
    double lo = uni(rng) * 2, hi = lo + std::abs(uni(rng)) * 3;
    if (i % 19 == 0) {
      // An exact root at 0 (c0 = 0 with no error: firstRoot factors it out, roots.cpp)
      // beside a root whose slope's error bound can put both in one noise cluster (err1 >=
      // |c1| / 2 makes the vertex a tangent root in one frame).
      c[0] = 0;
      err = {0, std::abs(c[1]) * 4 * std::abs(uni(rng)), 0};
      lo = -std::abs(lo);
    }
    if (i % 5 == 0) lo = r0;  // the previous root as lo
    if (i % 17 == 0) hi = r1;
    if (!(lo < hi)) continue;
    const auto general = firstRoot(c, err, lo, hi);
    const auto fast = firstRootQuadratic(c, err, lo, hi);
    ASSERT_EQ(general.has_value(), fast.has_value()) << i;
    if (general) {
      EXPECT_EQ(*general, *fast) << i;
      ++found;
    }
    ++compared;
  }
  EXPECT_GT(compared, 15000);
  EXPECT_GT(found, 5000);
}

TEST(RootsContract, BadInput) {
  const double nan = std::nan(""), inf = INFINITY;
  const std::vector<double> c{-0.5, 1};
  EXPECT_FALSE(firstRoot(std::vector<double>{nan, 1}, {}, 0.0, 1.0).has_value());
  EXPECT_FALSE(firstRoot(std::vector<double>{-0.5, inf}, {}, 0.0, 1.0).has_value());
  EXPECT_FALSE(firstRoot(c, std::vector<double>{0, nan}, 0.0, 1.0).has_value());
  EXPECT_FALSE(firstRoot(c, {}, nan, 1.0).has_value());
  EXPECT_FALSE(firstRoot(c, {}, 0.0, inf).has_value());
  EXPECT_FALSE(firstRoot(c, {}, 1.0, 0.0).has_value());
  EXPECT_FALSE(firstRoot(c, {}, 0.25, 0.25).has_value());
  EXPECT_FALSE(hasRoot(c, {}, -inf, inf));
  EXPECT_FALSE(firstRoot(std::vector<double>{}, {}, 0.0, 1.0).has_value());
  EXPECT_FALSE(firstRoot(std::vector<double>{0, 0, 0}, {}, 0.0, 1.0).has_value());
  EXPECT_FALSE(firstRoot(std::vector<double>{3}, {}, 0.0, 1.0).has_value());
  EXPECT_THROW(firstRoot(std::vector<double>(kMaxDegree + 2, 1.0), {}, 0.0, 1.0), Error);
  EXPECT_THROW(firstRoot(c, std::vector<double>{1}, 0.0, 1.0), Error);
  // Options outside their ranges are refused by every query and precision (they were taken
  // for the defaults: a caller's mistake solved something else than asked).
  for (const double tol : {nan, -1e-3, 1.5, inf}) {
    RootOptions o;
    o.relTolerance = tol;
    EXPECT_THROW(firstRoot(c, {}, 0.0, 1.0, o), Error) << tol;
    EXPECT_THROW(hasRoot(c, {}, 0.0, 1.0, o), Error) << tol;
    double out[2];
    EXPECT_THROW(allRoots(c, {}, 0.0, 1.0, out, o), Error) << tol;
    const std::vector<float> cf{-0.5f, 1.0f};
    EXPECT_THROW(firstRoot(cf, {}, 0.0f, 1.0f, o), Error) << tol;
  }
  for (const int m : {-1, 5, 1000}) {
    RootOptions o;
    o.method = static_cast<RootMethod>(m);
    try {
      firstRoot(c, {}, 0.0, 1.0, o);
      ADD_FAILURE() << "method " << m << " was taken";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("RootMethod"), std::string::npos) << e.what();
    }
    EXPECT_THROW(hasRoot(c, {}, 0.0, 1.0, o), Error) << m;
  }
  for (const double tol : {0.0, 1e-6, 1.0}) {
    RootOptions o;
    o.relTolerance = tol;
    EXPECT_NEAR(firstRoot(c, {}, 0.0, 1.0, o).value_or(-1.0), 0.5, tol + 1e-15) << tol;
  }
  // Huge but finite values: no hang, no non-finite root.
  const std::vector<double> huge{-1e308, 1e308, -1e308, 1e308};
  const auto r = firstRoot(huge, {}, -1e300, 1e300);
  if (r) {
    EXPECT_TRUE(std::isfinite(*r));
  }
}

}  // namespace
}  // namespace algray
