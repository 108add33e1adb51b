// Tests of roots.h's contract (roots.h's file comment): the interval ends and the walk
// firstRoot(c, err, previousRoot, hi), noise-level ends and nodes, the quadratic fast path
// and bad input (scale invariance and the edges of double's range:
// roots_contract_range_test.cpp).
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

// A leading coefficient dropped because it lies within its own error bound still belongs
// to g: the noise bound keeps its size with its error (roots_frame.h), so that where g is
// within it the rules report a root as they would with the coefficient kept. Here c_3 =
// -0.018 with err_3 = |c_3|: the admissible cubic with 2 c_3 changes sign inside the
// interval (0.25 at 1, -0.0009 at 1.33), while the quadratic left after the drop stays above
// 0.063 (its minimum at 1.47; the computed cubic's is 0.006 there): a near miss within the
// dropped term, which the tangent rule (at 1.47) or the end rule (at hi) reports. With the
// bound of c_3's error alone, Sturm answered nothing (81 of 3000 such problems; the mutation
// audit of session 55).
TEST(RootsContract, DroppedLeadingCoefficientKeepsItsSize) {
  const std::vector<double> c = {2.2330854376163507, -2.9458065405557834, 1.0,
                                 -0.01805794226224117};
  const std::vector<double> err = {0, 0, 0, std::abs(c[3])};
  const double lo = -0.41701250624763725, hi = 1.8970506617189185;
  // The reference: an admissible cubic (c_3 doubled) has a root in (1, 1.33), exactly.
  std::vector<double> doubled = c;
  doubled[3] = 2 * c[3];
  ASSERT_GT(test::signAt(doubled, test::Mp(1.0)), 0);
  ASSERT_LT(test::signAt(doubled, test::Mp(1.33)), 0);
  for (RootMethod m : {RootMethod::Auto, RootMethod::Yuksel, RootMethod::ClosedForm,
                       RootMethod::Sturm, RootMethod::Bernstein}) {
    SCOPED_TRACE(static_cast<int>(m));
    RootOptions o;
    o.method = m;
    const auto first = firstRoot(c, err, lo, hi, o);
    ASSERT_TRUE(first.has_value());
    EXPECT_GT(*first, 1.0);  // within the noise near hi, not before it
    EXPECT_TRUE(hasRoot(c, err, lo, hi, o));
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
