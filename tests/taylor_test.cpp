// The Taylor restriction identity g(t) = f(o + t d), checked coefficient by coefficient
// against an MPFR expansion of f along the ray, for both paths, on every gallery surface
// and on random dense polynomials, with origins near and 1e3, 1e6 clip radii away.
#include "algray/taylor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "algray/gallery.h"
#include "support/box_reference.h"
#include "support/mp.h"
#include "support/scales.h"

namespace algray {
namespace {

using test::Mp;

// Coefficients of f(p + s d) in MPFR: expand every monomial as a product of the linear
// polynomials (p.x + s d.x) etc. in 320-bit arithmetic.
std::vector<Mp> mpRestrict(const Polynomial& f, const glm::dvec3& p, const glm::dvec3& d) {
  const int m = f.degree();
  auto powersOf = [m](double a, double b) {
    std::vector<std::vector<Mp>> pw(m + 1);
    pw[0] = {Mp(1.0)};
    for (int e = 1; e <= m; ++e) {
      pw[e].assign(e + 1, Mp());
      for (int r = 0; r < e; ++r) {
        pw[e][r] += pw[e - 1][r] * Mp(a);
        pw[e][r + 1] += pw[e - 1][r] * Mp(b);
      }
    }
    return pw;
  };
  const auto px = powersOf(p.x, d.x), py = powersOf(p.y, d.y), pz = powersOf(p.z, d.z);
  std::vector<Mp> g(m + 1);
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      const double c = f.coeffs()[idx];
      if (c == 0.0) return;
      std::vector<Mp> yz(j + k + 1);
      for (int a = 0; a <= j; ++a)
        for (int b = 0; b <= k; ++b) yz[a + b] += py[j][a] * pz[k][b];
      for (int a = 0; a <= i; ++a)
        for (int b = 0; b <= j + k; ++b) g[a + b] += Mp(c) * px[i][a] * yz[b];
    });
  return g;
}

struct Case {
  std::string name;
  Polynomial f;
  double radius;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const GallerySurface& s : gallery())
    out.push_back({std::string(s.name), s.build(), s.clipRadius});
  std::mt19937_64 rng(1234);
  std::uniform_real_distribution<double> c(-1.0, 1.0);
  for (int degree : {3, 7, 10}) {
    Polynomial f;
    for (int n = 0; n <= degree; ++n)
      forEachMonomialOfDegree(n, [&](int i, int j, int k, int) { f.setCoeff(i, j, k, c(rng)); });
    out.push_back({"random-" + std::to_string(degree), f, 1.0});
  }
  // Degree 40: a product of 20 concentric spheres (the library's degree limit).
  const Polynomial r2 = Polynomial::variable(0).pow(2) + Polynomial::variable(1).pow(2) +
                        Polynomial::variable(2).pow(2);
  Polynomial spheres(1.0);
  for (int k = 0; k < 20; ++k) spheres = spheres * (r2 - Polynomial(std::pow(0.3 + 0.035 * k, 2)));
  out.push_back({"spheres-40", spheres, 1.2});
  return out;
}

// Checks every coefficient against the MPFR expansion about the same double point and
// returns the largest ratio error / bound seen (must be <= 1).
double checkAgainstReference(const RayPolynomial& g, const Polynomial& f, const glm::dvec3& p,
                             const glm::dvec3& d, const std::string& what) {
  const std::vector<Mp> ref = mpRestrict(f, p, d);
  double worst = 0.0;
  for (int n = 0; n <= f.degree(); ++n) {
    const double c = n <= g.degree ? g.coeff[n] : 0.0;
    const double bound = n <= g.degree ? g.error[n] : 0.0;
    const double err = std::abs((Mp(c) - ref[n]).toDouble());
    EXPECT_LE(err, bound) << what << " coefficient " << n;
    if (bound > 0) worst = std::max(worst, err / bound);
  }
  return worst;
}

// Equal values (+0 == -0) in the whole record.
void expectSameValues(const RayPolynomial& a, const RayPolynomial& b, const std::string& what) {
  ASSERT_EQ(a.degree, b.degree) << what;
  EXPECT_EQ(a.tShift, b.tShift) << what;
  for (int n = 0; n <= kMaxDegree; ++n) {
    EXPECT_EQ(a.coeff[n], b.coeff[n]) << what << ", coefficient " << n;
    EXPECT_EQ(a.error[n], b.error[n]) << what << ", bound " << n;
  }
}

// Bit for bit (the sign of a zero too), the whole record.
void expectSameBits(const RayPolynomial& a, const RayPolynomial& b, const std::string& what) {
  ASSERT_EQ(a.degree, b.degree) << what;
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a.tShift), std::bit_cast<std::uint64_t>(b.tShift)) << what;
  for (int n = 0; n <= kMaxDegree; ++n) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.coeff[n]), std::bit_cast<std::uint64_t>(b.coeff[n]))
        << what << ", coefficient " << n << ": " << a.coeff[n] << " vs " << b.coeff[n];
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.error[n]), std::bit_cast<std::uint64_t>(b.error[n]))
        << what << ", bound " << n << ": " << a.error[n] << " vs " << b.error[n];
  }
}

TEST(Taylor, BothPathsMatchHighPrecisionWithinTheirBounds) {
  std::mt19937_64 rng(99);
  std::normal_distribution<double> normal;
  for (const Case& cs : cases()) {
    const HornerForm box(cs.f);
    RayPolynomial reused;  // restrict(d, g) into a record holding an earlier ray's data
    reused.degree = kMaxDegree;
    reused.coeff.fill(7.0);
    reused.error.fill(7.0);
    const OriginExpansion* cached = nullptr;
    for (double distance : {0.5, 3.0, 1e3, 1e6}) {
      // An origin at `distance` clip radii, aimed at a random point of the clip ball.
      glm::dvec3 dir{normal(rng), normal(rng), normal(rng)};
      const glm::dvec3 o = cs.radius * distance * glm::normalize(dir);
      OriginExpansion expansion(cs.f, o);
      cached = &expansion;
      const int rays = cs.f.degree() > 20 ? 1 : 6;  // the MPFR reference costs O(m^5)
      for (int ray = 0; ray < rays; ++ray) {
        glm::dvec3 target{normal(rng), normal(rng), normal(rng)};
        target *= 0.5 * cs.radius;
        const glm::dvec3 d = target - o;  // not unit length on purpose
        const std::string what = cs.name + " at distance " + std::to_string(distance);

        // Path (1): shared origin.
        const RayPolynomial g1 = cached->restrict(d);
        checkAgainstReference(g1, cs.f, o, d, what + " (origin expansion)");
        cached->restrict(d, reused);
        ASSERT_EQ(reused.degree, g1.degree) << what;
        for (int n = 0; n <= g1.degree; ++n) {
          EXPECT_EQ(reused.coeff[n], g1.coeff[n]) << what << " in place, coefficient " << n;
          EXPECT_EQ(reused.error[n], g1.error[n]) << what << " in place, bound " << n;
        }

        // Path (2): direct, re-centred at the closest point to the clip centre.
        const double tShift = closestParameter(o, d, glm::dvec3(0.0));
        const RayPolynomial g = restrictToRay(cs.f, o, d, tShift);
        EXPECT_EQ(g.tShift, tShift);
        checkAgainstReference(g, cs.f, o + tShift * d, d, what + " (direct)");

        // The same over the precompiled Horner box: on f's own box the same operations on
        // the same non-zero data, so the same values (bits but for the sign of a zero, see
        // support/box_reference.h), and the same bits as before its unrolled kernels; on
        // squared coordinates (even axes, taylor_box.cpp) its own bound.
        const RayPolynomial gb = restrictToRay(box, o, d, tShift);
        const glm::dvec3 p = tShift == 0.0 ? o : o + tShift * d;
        if (box.restrictsOnSquares(p, d)) {
          checkAgainstReference(gb, cs.f, p, d, what + " (box, even axes)");
        } else {
          expectSameValues(gb, g, what + " box");
          expectSameBits(gb, test::restrictToRayReference(box, o, d, tShift),
                         what + " box vs reference");
        }
      }
    }
  }
}

// The box path's unrolled kernels (taylor_box.cpp) against its run-time-loop reference
// (bit for bit) and the Polynomial path (value for value) on box shapes the gallery lacks (sparse
// random polynomials: gaps, rows longer or shorter than their neighbours, zero blocks, degrees past
// the unrolled lengths) and on rays with zero and negative-zero components (signed zeros through
// the value chain). Where the restriction runs on squared coordinates (a polynomial with even
// axes, HornerForm::restrictsOnSquares) it is checked against MPFR within its bound instead;
// rays with a component outside that path's range (an even polynomial's fallback to its own
// box) keep the bit-for-bit check.
TEST(Taylor, BoxPathIsBitIdenticalOnAnyShape) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> normal;
  std::vector<Polynomial> polys;
  for (const Case& cs : cases()) polys.push_back(cs.f);
  for (int degree : {0, 1, 2, 4, 5, 9, 12, 13, 16, 17, 18, 24})
    for (double density : {0.05, 0.2, 0.5, 0.9}) {
      Polynomial f;
      for (int n = 0; n <= degree; ++n)
        forEachMonomialOfDegree(n, [&](int i, int j, int k, int) {
          if (0.5 * (u(rng) + 1.0) < density) f.setCoeff(i, j, k, u(rng));
        });
      f.setCoeff(degree, 0, 0, 1.0);  // keep the degree
      polys.push_back(f);
    }
  const std::vector<glm::dvec3> special = {
      {0.0, 0.0, 1.0}, {-0.0, 1.0, -0.0}, {1.0, -0.0, 0.0}, {0.0, -0.6, 0.8}, {-0.0, -0.0, -1.0}};
  int onSquares = 0, ownBoxOfEven = 0, ownBox = 0;
  for (const Polynomial& f : polys) {
    const HornerForm box(f);
    for (int ray = 0; ray < 14; ++ray) {
      glm::dvec3 o{normal(rng), normal(rng), normal(rng)}, d{normal(rng), normal(rng), normal(rng)};
      if (ray < 5) d = special[ray];
      if (ray >= 5 && ray < 8) o = glm::dvec3(0.0);
      if (ray == 8) o = glm::dvec3(-0.0, 0.5, -0.0);
      if (ray == 12) o.x = 0x1p-401;  // outside the even path's range on x (and on y below)
      if (ray == 13) d.y = -0x1p-402;
      const double tShift = ray % 2 == 0 ? 0.0 : closestParameter(o, d, glm::dvec3(0.0));
      const std::string what =
          "degree " + std::to_string(f.degree()) + " ray " + std::to_string(ray);
      const RayPolynomial gb = restrictToRay(box, o, d, tShift);
      const glm::dvec3 p = tShift == 0.0 ? o : o + tShift * d;
      if (box.restrictsOnSquares(p, d)) {
        checkAgainstReference(gb, f, p, d, what + " (even axes)");
        ++onSquares;
        continue;
      }
      ++(box.evenAxes() != 0 ? ownBoxOfEven : ownBox);
      expectSameBits(gb, test::restrictToRayReference(box, o, d, tShift), what + " vs reference");
      expectSameValues(gb, restrictToRay(f, o, d, tShift), what + " vs Polynomial path");
    }
  }
  EXPECT_GT(onSquares, 50);
  EXPECT_GT(ownBoxOfEven, 10);
  EXPECT_GT(ownBox, 300);
}

// closestParameter against the closest point in long double (64-bit significand): within
// inverseSquaredLength's relative 2^-40 for near-unit directions (float-normalised ones,
// and double ones up to 2^-20 off unit length) and the rounding of the dot product, and
// a plain quotient for every other length.
// RayPolynomial's fields are public; a degree beyond its arrays is refused (evaluate read
// past them).
TEST(Taylor, RayPolynomialRefusesADegreeBeyondItsArrays) {
  RayPolynomial g;
  g.degree = 2;
  g.coeff[0] = -1.0;
  g.coeff[2] = 1.0;
  double bound = 0.0, slope = 0.0;
  EXPECT_EQ(g.evaluate(2.0), 3.0);
  EXPECT_EQ(g.evaluateWithBound(2.0, bound, slope), 3.0);
  EXPECT_EQ(slope, 4.0);
  for (const int degree : {kMaxDegree + 1, 1000}) {
    g.degree = degree;
    EXPECT_THROW(g.evaluate(0.5), Error) << degree;
    EXPECT_THROW(g.evaluateWithBound(0.5, bound), Error) << degree;
    EXPECT_THROW(g.evaluateWithBound(0.5, bound, slope), Error) << degree;
  }
}

TEST(Taylor, ClosestParameterWithinItsBound) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 o =
        std::pow(10.0, 6.0 * std::abs(u(rng))) * glm::dvec3(u(rng), u(rng), u(rng));
    const glm::dvec3 c(u(rng), u(rng), u(rng));
    glm::dvec3 d = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const int kind = i % 4;
    if (kind == 1) d = glm::dvec3(glm::normalize(glm::vec3(d)));  // float-normalised
    if (kind == 2) d *= 1.0 + 0x1p-21 * u(rng);                   // near unit
    if (kind == 3) d *= std::pow(10.0, 3.0 * u(rng));             // any length
    const double dd = glm::dot(d, d), inv = inverseSquaredLength(dd);
    if (std::abs(dd - 1.0) <= 0x1p-20)
      EXPECT_LE(std::abs((long double)inv * dd - 1.0L), 0x1p-40L + 0x1p-51L) << dd;
    else
      EXPECT_EQ(inv, 1.0 / dd);
    long double dot = 0, dotAbs = 0, ddL = 0;
    for (int k = 0; k < 3; ++k) {
      dot += ((long double)c[k] - o[k]) * d[k];
      dotAbs += std::abs(((long double)c[k] - o[k]) * d[k]);
      ddL += (long double)d[k] * d[k];
    }
    const long double ref = dot / ddL, t = closestParameter(o, d, c);
    // the quotient's or product's 2^-40 and rounding, and the dot product's rounding
    // (gamma(4) over |c - o| |d|, c - o rounded too)
    const long double bound = (0x1p-40L + 0x1p-50L) * std::abs(ref) + 0x1p-49L * dotAbs / ddL;
    EXPECT_LE(std::abs(t - ref), bound) << "kind " << kind << " ray " << i;
  }
}

TEST(Taylor, RecentringKeepsFarRaysAccurate) {
  // Far origins: the re-centred coefficients stay at the scale of the clip region, so the
  // error of g near the surface is tiny relative to g's own scale there; the expansion
  // about the far origin is exact-as-bounded but its bound is huge by comparison.
  const Polynomial sphere = Polynomial::variable(0).pow(2) + Polynomial::variable(1).pow(2) +
                            Polynomial::variable(2).pow(2) - Polynomial(1.0);
  const glm::dvec3 o{1e6, 2e5, -3e5}, d = glm::normalize(-o);
  const RayPolynomial near = restrictToRay(sphere, o, d, closestParameter(o, d, glm::dvec3(0.0)));
  const RayPolynomial far = OriginExpansion(sphere, o).restrict(d);
  EXPECT_LT(near.error[0], 1e-15);
  EXPECT_GT(far.error[0], 1e-6);
  // The roots of the re-centred quadratic are -1 and +1 (a unit sphere through its centre).
  EXPECT_NEAR(near.coeff[0], -1.0, 1e-15);
  EXPECT_NEAR(near.coeff[1], 0.0, 1e-9);
  EXPECT_NEAR(near.coeff[2], 1.0, 1e-15);
}

TEST(Taylor, HomogeneousPartsAreTheDirectionalDerivatives) {
  // g_n = (d . grad)^n f(o) / n!: for n = 1 the directional derivative, checked against the
  // gradient; g_0 = f(o).
  const Polynomial f = Polynomial::variable(0).pow(3) * Polynomial::variable(1) -
                       2.0 * Polynomial::variable(2).pow(2) + Polynomial(0.5);
  const glm::dvec3 o{0.3, -1.2, 0.7}, d{0.2, 0.9, -0.4};
  const RayPolynomial g = OriginExpansion(f, o).restrict(d);
  EXPECT_NEAR(g.coeff[0], f.evaluate(o), 1e-15);
  EXPECT_NEAR(g.coeff[1], glm::dot(f.gradient(o), d), 1e-14);
  const RayPolynomial h = restrictToRay(f, o, d);
  for (int n = 0; n <= 4; ++n) EXPECT_NEAR(g.coeff[n], h.coeff[n], 1e-14) << n;
}

// Flush-to-zero and denormals-are-zero for the scope (MXCSR bits 15 and 6), as Embree's and
// TBB's worker threads run: a result below double's normal range becomes 0, a subnormal
// operand reads as 0.
struct FlushToZero {
#if defined(__SSE__)
  unsigned saved = _mm_getcsr();
  FlushToZero() { _mm_setcsr(saved | 0x8040u); }
  ~FlushToZero() { _mm_setcsr(saved); }
#endif
};

// |computed - exact| <= error for every coefficient of g against the MPFR expansion of f
// about p (exact arithmetic on the double data: no underflow in MPFR's exponent range). A
// non-finite coefficient (overflow) must come with an infinite bound. Returns how many
// coefficients broke the bound and describes the first in `first`.
int boundViolations(const RayPolynomial& g, const Polynomial& f, const glm::dvec3& p,
                    const glm::dvec3& d, std::string& first, const std::string& what) {
  const std::vector<Mp> ref = mpRestrict(f, p, d);
  int bad = 0;
  for (int n = 0; n <= f.degree(); ++n) {
    const double c = n <= g.degree ? g.coeff[n] : 0.0;
    const double bound = n <= g.degree ? g.error[n] : 0.0;
    const bool ok =
        std::isfinite(c) ? std::abs((Mp(c) - ref[n]).toDouble()) <= bound : bound == INFINITY;
    if (ok) continue;
    if (bad++ == 0) {
      char buf[256];
      std::snprintf(buf, sizeof buf, " coefficient %d: computed %.17g exact %.17g bound %.3g", n, c,
                    ref[n].toDouble(), bound);
      first = what + buf;
    }
  }
  return bad;
}

// The bounds of both paths where products leave double's normal range: coefficients from
// 1e-300 to 1e300, origins up to 1e150, directions from 1e-150 to 1e150 (the powers of a
// small component underflow; under flush-to-zero each such product loses up to 2^-1022,
// which a relative bound never covers), with gradual underflow and with FTZ/DAZ, against
// MPFR; every fifth case with subnormal components of the ray and a subnormal coefficient,
// which DAZ reads as 0. The first cases are the session notes' example: coefficients
// ~1e-300, an origin ~1e100 and a direction ~1e-20 (before the underflow floor: bounds
// 1e15 times too small there; 167 of the 800 cases and modes broke a bound).
TEST(Taylor, BoundsHoldWhereProductsUnderflow) {
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto signedPow10 = [&](double lo, double hi) { return test::signedPow10(rng, lo, hi); };
  int checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int m = 1 + trial % 6;
    const double scale = trial < 20 ? 1e-300 : std::pow(10.0, -300.0 + 600.0 * u(rng));
    Polynomial f;
    for (int n = 0; n <= m; ++n)
      forEachMonomialOfDegree(n, [&](int i, int j, int k, int) {
        if (u(rng) < 0.7) f.setCoeff(i, j, k, scale * signedPow10(-3.0, 0.0));
      });
    f.setCoeff(0, 0, m, scale);
    glm::dvec3 o, d;
    const double oScale = trial < 20 ? 100.0 : -150.0 + 300.0 * u(rng);
    const double dScale = trial < 20 ? -20.0 : -150.0 + 300.0 * u(rng);
    for (int a = 0; a < 3; ++a) {
      const double top = std::min(oScale, 150.0);
      o[a] = u(rng) < 0.15 ? 0.0 : signedPow10(top - 4.0, top);
      d[a] = u(rng) < 0.15 ? 0.0 : signedPow10(dScale - 4.0, dScale);
    }
    if (d == glm::dvec3(0.0)) d.x = std::pow(10.0, dScale);
    if (trial % 5 == 4) {  // subnormal components and a subnormal coefficient (0 under DAZ)
      for (int a = 0; a < 3; ++a) {
        if (u(rng) < 0.3) o[a] = signedPow10(-322.0, -308.0);
        if (u(rng) < 0.3) d[a] = signedPow10(-322.0, -308.0);
      }
      if (u(rng) < 0.5) f.setCoeff(0, 1, 0, signedPow10(-322.0, -308.0));
    }
    const HornerForm box(f);
    double tShift = closestParameter(o, d, glm::dvec3(0.0));
    if (!std::isfinite(tShift)) tShift = 0.0;
    for (const bool flush : {false, true}) {
      RayPolynomial direct, directBox, shifted, expansion;
      glm::dvec3 pShift;
      {
        std::optional<FlushToZero> mode;
        if (flush) mode.emplace();
        direct = restrictToRay(f, o, d);
        directBox = restrictToRay(box, o, d, tShift);
        pShift = tShift == 0.0 ? o : o + tShift * d;  // as restrictToRay forms it, in this mode
        shifted = restrictToRay(f, o, d, tShift);
        expansion = OriginExpansion(f, o).restrict(d);
      }
      const std::string what = "trial " + std::to_string(trial) + (flush ? " FTZ/DAZ" : " gradual");
      std::string first;
      int bad = boundViolations(direct, f, o, d, first, what + " direct");
      bad += boundViolations(directBox, f, pShift, d, first, what + " box, re-centred");
      bad += boundViolations(shifted, f, pShift, d, first, what + " direct, re-centred");
      bad += boundViolations(expansion, f, o, d, first, what + " origin expansion");
      EXPECT_EQ(bad, 0) << first;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 800);
}

// A subnormal top coefficient (f built in normal mode, as a host's main thread does): DAZ
// reads it as 0, so the box's degree stops below f's, and the box path wrote 0 with a bound
// of 0 above it; 1e-310 x^3 + x^2 + y^2 + z^2 - 1 from (0.5, 0.25, 0) along (1e50, 0, 0)
// has g_3 = 1e-160 (the audit's case, session 43). Every slot gets its underflow floor.
// Random lower terms, origins and directions over wide ranges, against MPFR, both modes.
TEST(Taylor, BoundsHoldForASubnormalTopCoefficientUnderFlushToZero) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto signedPow10 = [&](double lo, double hi) { return test::signedPow10(rng, lo, hi); };
  int bad = 0, checked = 0;
  std::string first;
  for (int trial = 0; trial < 300; ++trial) {
    const int m = 2 + trial % 5;
    Polynomial f;
    glm::dvec3 o(0.5, 0.25, 0.0), d(trial % 2 ? 1e50 : 1.0, 0.0, 0.0);
    if (trial < 2) {  // the audit's case
      f.setCoeff(3, 0, 0, 1e-310);
      f.setCoeff(2, 0, 0, 1.0);
      f.setCoeff(0, 2, 0, 1.0);
      f.setCoeff(0, 0, 2, 1.0);
      f.setCoeff(0, 0, 0, -1.0);
    } else {
      for (int n = 0; n < m; ++n)
        forEachMonomialOfDegree(n, [&](int i, int j, int k, int) {
          if (u(rng) < 0.6) f.setCoeff(i, j, k, signedPow10(-3.0, 3.0));
        });
      // One to three subnormal coefficients of the top block.
      forEachMonomialOfDegree(m, [&](int i, int j, int k, int) {
        if (u(rng) < 0.4 || (i == m)) f.setCoeff(i, j, k, signedPow10(-323.0, -308.5));
      });
      for (int a = 0; a < 3; ++a) {
        o[a] = u(rng) < 0.2 ? 0.0 : signedPow10(-2.0, 2.0);
        d[a] = u(rng) < 0.2 ? 0.0 : signedPow10(-5.0, 60.0 / m);
      }
      if (d == glm::dvec3(0.0)) d.x = 1.0;
    }
    const HornerForm box(f);  // in normal mode
    for (const bool flush : {false, true}) {
      RayPolynomial g;
      {
        std::optional<FlushToZero> mode;
        if (flush) mode.emplace();
        g = restrictToRay(box, o, d);
      }
      const std::string what = "trial " + std::to_string(trial) + (flush ? " FTZ/DAZ" : " gradual");
      bad += boundViolations(g, f, o, d, first, what);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 600);
  EXPECT_EQ(bad, 0) << first;
}

// Polynomial::translate's relative bound (gamma_{6m} of the shift of |f| by |o|) excludes
// underflow, as polynomial.h says: -3e-310 y z^2 about (0, 0, -0.23727448698610765) has
// the y coefficient -3e-310 o_z^2 = -1.689e-311 (MPFR), returned 75 bounds off (the
// audit's case, session 43, where the header claimed the bound without that exception).
// OriginExpansion, the bound's consumer, covers it with its floor: its restrictions along
// random directions hold against MPFR, restricted with gradual underflow and with FTZ/DAZ.
TEST(Taylor, TranslateBoundExcludesUnderflowAndOriginExpansionCoversIt) {
  Polynomial f;
  f.setCoeff(0, 1, 2, -3e-310);
  const glm::dvec3 o(0.0, 0.0, -0.23727448698610765);
  const Mp exact = Mp(-3e-310) * Mp(o.z) * Mp(o.z);
  const double computed = f.translate(o).coeff(0, 1, 0);
  const double relativeBound = gamma(6 * 3) * (3e-310 * o.z * o.z);
  EXPECT_GT(std::abs((Mp(computed) - exact).toDouble()), 10.0 * relativeBound)
      << "the exception polynomial.h documents no longer shows: update the header";
  // (Built with gradual underflow: under DAZ every coefficient of this f reads as 0 and
  // the expansion is the zero polynomial, a different matter.)
  const OriginExpansion expansion(f, o);
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int bad = 0;
  std::string first;
  for (int trial = 0; trial < 200; ++trial) {
    glm::dvec3 d(u(rng), u(rng), u(rng));
    if (trial == 0) d = glm::dvec3(0.0, 1.0, 0.0);
    d *= std::pow(10.0, 3.0 * u(rng));
    for (const bool flush : {false, true}) {
      RayPolynomial g;
      {
        std::optional<FlushToZero> mode;
        if (flush) mode.emplace();
        g = expansion.restrict(d);
      }
      bad += boundViolations(g, f, o, d, first,
                             "trial " + std::to_string(trial) + (flush ? " FTZ/DAZ" : " gradual"));
    }
  }
  EXPECT_EQ(bad, 0) << first;
}

// RayPolynomial::evaluateWithBound where Horner's products underflow: coefficients from
// 1e-300 to 1e-100 with exact (zero) error bounds and s from 1e-150 to 1e150, gradual and
// FTZ/DAZ, against the MPFR value of the same coefficients: 1e-300 + 1e-300 s^2 at
// s = 1e-10 has a subnormal product (1e-320, flushed under FTZ), and the relative bound
// missed what it lost.
TEST(Taylor, EvaluateWithBoundHoldsWhereProductsUnderflow) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto signedPow10 = [&](double lo, double hi) { return test::signedPow10(rng, lo, hi); };
  int bad = 0;
  std::string first;
  for (int trial = 0; trial < 3000; ++trial) {
    RayPolynomial g;
    g.degree = trial % 8;
    const double scale = -300.0 + 200.0 * u(rng);
    for (int i = 0; i <= g.degree; ++i) g.coeff[i] = signedPow10(scale - 20.0, scale);
    const double s = signedPow10(-150.0, 150.0);
    Mp exact;
    for (int i = g.degree; i >= 0; --i) exact = exact * Mp(s) + Mp(g.coeff[i]);
    for (const bool flush : {false, true}) {
      double bound = 0.0, v = 0.0;
      {
        std::optional<FlushToZero> mode;
        if (flush) mode.emplace();
        v = g.evaluateWithBound(s, bound);
      }
      const bool ok =
          std::isfinite(v) ? std::abs((Mp(v) - exact).toDouble()) <= bound : bound == INFINITY;
      if (!ok && bad++ == 0) {
        char buf[200];
        std::snprintf(buf, sizeof buf, "degree %d at s = %.17g%s: %.17g, exact %.17g, bound %.3g",
                      g.degree, s, flush ? " FTZ/DAZ" : "", v, exact.toDouble(), bound);
        first = buf;
      }
    }
  }
  EXPECT_EQ(bad, 0) << first;
}

TEST(Taylor, EvaluateWithBoundCoversTheValue) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Case& cs : cases()) {
    const glm::dvec3 o{2.0 * cs.radius, 0.3, -0.2}, d{-1.0, u(rng) * 0.2, u(rng) * 0.2};
    const RayPolynomial g = restrictToRay(cs.f, o, d);
    const std::vector<Mp> ref = mpRestrict(cs.f, o, d);
    for (int s = 0; s < 20; ++s) {
      const double t = 2.0 * cs.radius * (1.0 + u(rng));
      double bound = 0;
      const double v = g.evaluateWithBound(t, bound);
      // Reference: f at the MPFR point o + t d, via the MPFR coefficients.
      Mp r;
      for (int n = cs.f.degree(); n >= 0; --n) r = r * Mp(t) + ref[n];
      EXPECT_LE(std::abs((Mp(v) - r).toDouble()), bound) << cs.name;
      // The form with the slope: the same value and bound, and g'(t) of g's own (double)
      // coefficients within Horner's rounding of the derivative, gamma(2n) sum i |c_i| |t|^(i-1).
      double bound2 = 0, slope = 0;
      const double v2 = g.evaluateWithBound(t, bound2, slope);
      EXPECT_EQ(v2, v);
      EXPECT_EQ(bound2, bound);
      Mp dr;
      double mag = 0;
      for (int n = g.degree; n >= 1; --n) {
        dr = dr * Mp(t) + Mp(g.coeff[n]) * Mp(static_cast<double>(n));
        mag = mag * std::abs(t) + n * std::abs(g.coeff[n]);
      }
      const double u2n = 2.0 * g.degree * 0x1p-53 / (1.0 - 2.0 * g.degree * 0x1p-53);
      EXPECT_LE(std::abs((Mp(slope) - dr).toDouble()), 1.01 * u2n * mag) << cs.name;
    }
  }
}

// ---- The restriction on squared coordinates (even axes, taylor_box.cpp) ----

// A random f of degree m (even, >= 2) with every exponent even on the axes of `mask`: about
// `density` of those monomials set, coefficients +-scale 10^[-3, 0]; a pure power on each
// axis (m on an even one, 1 on the others) decides the axes and keeps the degree.
Polynomial evenPolynomial(std::mt19937_64& rng, unsigned mask, int m, double density,
                          double scale) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Polynomial f;
  test::forEachMonomialEvenOn(mask, m, [&](int i, int j, int k) {
    if (u(rng) < density) f.setCoeff(i, j, k, scale * test::signedPow10(rng, -3.0, 0.0));
  });
  for (int a = 0; a < 3; ++a) {
    int e[3] = {0, 0, 0};
    e[a] = (mask >> a & 1u) != 0 ? m : 1;
    f.setCoeff(e[0], e[1], e[2], scale);
  }
  return f;
}

// The range of the even path, from the bits: +-0 or normal, and on an even axis
// 2^-400 <= |v| < 2^401 (HornerForm::restrictsOnSquares).
TEST(TaylorEvenAxes, PathTakenExactlyInItsRange) {
  std::mt19937_64 rng(7);
  const HornerForm even(evenPolynomial(rng, 1u, 4, 0.5, 1.0));  // x even only
  const HornerForm odd(evenPolynomial(rng, 0u, 3, 0.5, 1.0));
  ASSERT_EQ(even.evenAxes(), 1u);
  ASSERT_EQ(odd.evenAxes(), 0u);
  const glm::dvec3 d{0.3, -0.2, 0.9};
  const double lo = 0x1p-400, hi = 0x1p401;
  for (const double s : {1.0, -1.0}) {
    EXPECT_TRUE(even.restrictsOnSquares({s * lo, 1.0, 1.0}, d));
    EXPECT_FALSE(even.restrictsOnSquares({s * std::nextafter(lo, 0.0), 1.0, 1.0}, d));
    EXPECT_TRUE(even.restrictsOnSquares({s * std::nextafter(hi, 0.0), 1.0, 1.0}, d));
    EXPECT_FALSE(even.restrictsOnSquares({s * hi, 1.0, 1.0}, d));
    EXPECT_TRUE(even.restrictsOnSquares({s * 0.0, 1.0, 1.0}, {s * 0.0, 1.0, 1.0}));
    EXPECT_FALSE(even.restrictsOnSquares({1.0, 1.0, 1.0}, {s * hi, 1.0, 1.0}));
    // Odd axes: any normal number or +-0, no subnormal, inf or NaN.
    EXPECT_TRUE(even.restrictsOnSquares({1.0, s * 1e-300, s * 1e300}, d));
    EXPECT_FALSE(even.restrictsOnSquares({1.0, s * 1e-310, 1.0}, d));
    EXPECT_FALSE(even.restrictsOnSquares({1.0, 1.0, s * INFINITY}, d));
    EXPECT_FALSE(even.restrictsOnSquares({1.0, 1.0, 1.0}, {0.0, std::nan(""), 1.0}));
  }
  EXPECT_FALSE(odd.restrictsOnSquares({1.0, 1.0, 1.0}, d));
}

// Every subset of even axes, degrees 2 (f's own box) and 4 to 20 (F's), ray components from
// ~1e-130 to 1e125 (the path's range ends near 2^-400 ~ 3.9e-121 and 2^401 ~ 5.2e120), zero
// and negative-zero components, components at and next to the range's ends: every
// coefficient within its bound of the MPFR expansion about the same double point, on both
// paths; the even path taken where restrictsOnSquares says so (and bit-identical to f's own
// box elsewhere).
TEST(TaylorEvenAxes, BoundsHoldAgainstMpfrOnEverySubset) {
  std::mt19937_64 rng(2718);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double edges[] = {0x1p-400, std::nextafter(0x1p-400, 0.0), std::nextafter(0x1p401, 0.0),
                          0x1p401};
  int onSquares = 0, fallback = 0, finiteChecked = 0;
  for (unsigned mask = 1; mask < 8; ++mask)
    for (int m = 2; m <= 20; m += 2)
      for (const double density : {0.3, 1.0}) {
        for (int ray = 0; ray < 6; ++ray) {
          // One scale per ray, each component within 10^[e - 3, e]; the coefficients scaled
          // so that the restriction's magnitudes stay near 1 where that fits in a double.
          const double e = ray == 0 ? 0.0 : -130.0 + 255.0 * u(rng);
          const double coeffScale = std::pow(10.0, std::clamp(-m * e, -300.0, 300.0));
          const Polynomial f = evenPolynomial(rng, mask, m, density, coeffScale);
          const HornerForm box(f);
          ASSERT_EQ(box.evenAxes(), mask);
          glm::dvec3 o, d;
          for (int a = 0; a < 3; ++a) {
            o[a] = test::signedPow10(rng, e - 3.0, e);
            d[a] = test::signedPow10(rng, e - 3.0, e);
            const double z = u(rng);
            if (z < 0.1) o[a] = 0.0;
            if (z > 0.9) o[a] = -0.0;
            const double zd = u(rng);
            if (zd < 0.1) d[a] = 0.0;
            if (zd > 0.9) d[a] = -0.0;
          }
          if (ray == 5) {  // an edge of the range on a random axis
            const int a = static_cast<int>(3 * u(rng)) % 3;
            const double v = edges[static_cast<int>(4 * u(rng)) % 4] * (u(rng) < 0.5 ? -1 : 1);
            (u(rng) < 0.5 ? o : d)[a] = v;
          }
          if (d == glm::dvec3(0.0)) d.z = 1.0;
          double tShift = ray % 2 == 0 ? 0.0 : closestParameter(o, d, glm::dvec3(0.0));
          if (!std::isfinite(tShift)) tShift = 0.0;
          const RayPolynomial g = restrictToRay(box, o, d, tShift);
          const glm::dvec3 p = tShift == 0.0 ? o : o + tShift * d;
          char buf[160];
          std::snprintf(buf, sizeof buf, "mask %u degree %d scale 1e%.0f ray %d", mask, m, e, ray);
          std::string first;
          EXPECT_EQ(boundViolations(g, f, p, d, first, buf), 0) << first;
          EXPECT_TRUE(m >= 4 || !box.restrictsOnSquares(p, d)) << buf;  // quadrics: own box
          if (box.restrictsOnSquares(p, d)) {
            ++onSquares;
            bool finite = true;
            for (int n = 0; n <= m; ++n) finite = finite && std::isfinite(g.error[n]);
            finiteChecked += finite ? 1 : 0;
          } else {
            ++fallback;
            expectSameBits(g, test::restrictToRayReference(box, o, d, tShift), buf);
          }
        }
      }
  EXPECT_GT(onSquares, 500);
  EXPECT_GT(finiteChecked, 400);
  EXPECT_GT(fallback, 60);
}

// The even path where products underflow, with gradual underflow and with FTZ/DAZ
// (Taylor.BoundsHoldWhereProductsUnderflow for f's own box): coefficients from 1e-300 to
// 1e300, ray components from 2^-400 to 2^400 (inside the path's range, whose squares are
// then from 2^-800), degrees 4 to 12 in every subset of even axes.
TEST(TaylorEvenAxes, BoundsHoldWhereProductsUnderflow) {
  std::mt19937_64 rng(4243);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int onSquares = 0;
  for (int trial = 0; trial < 420; ++trial) {
    const unsigned mask = 1u + static_cast<unsigned>(trial % 7);
    const int m = 4 + 2 * (trial / 7 % 5);
    const double scale = trial < 14 ? 1e-300 : std::pow(10.0, -300.0 + 600.0 * u(rng));
    const Polynomial f = evenPolynomial(rng, mask, m, 0.7, scale);
    glm::dvec3 o, d;
    const double oScale = trial < 14 ? 100.0 : -118.0 + 236.0 * u(rng);
    const double dScale = trial < 14 ? -20.0 : -118.0 + 236.0 * u(rng);
    for (int a = 0; a < 3; ++a) {
      o[a] = u(rng) < 0.15 ? 0.0 : test::signedPow10(rng, oScale - 2.0, oScale);
      d[a] = u(rng) < 0.15 ? 0.0 : test::signedPow10(rng, dScale - 2.0, dScale);
    }
    if (d == glm::dvec3(0.0)) d.x = std::pow(10.0, dScale);
    const HornerForm box(f);
    for (const bool flush : {false, true}) {
      RayPolynomial g;
      glm::dvec3 p;
      double tShift = 0.0;
      {
        std::optional<FlushToZero> mode;
        if (flush) mode.emplace();
        tShift = trial % 2 == 0 ? 0.0 : closestParameter(o, d, glm::dvec3(0.0));
        if (!std::isfinite(tShift)) tShift = 0.0;
        g = restrictToRay(box, o, d, tShift);
        p = tShift == 0.0 ? o : o + tShift * d;  // as restrictToRay forms it, in this mode
        onSquares += box.restrictsOnSquares(p, d) ? 1 : 0;
      }
      std::string first;
      const std::string what = "trial " + std::to_string(trial) + (flush ? " FTZ/DAZ" : " gradual");
      EXPECT_EQ(boundViolations(g, f, p, d, first, what), 0) << first;
    }
  }
  EXPECT_GT(onSquares, 600);
}

}  // namespace
}  // namespace algray
