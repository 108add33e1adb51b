// Cells and range bounds (cells.h, range_bound.h) against independent references:
//  * surface points certified by an exact sign change (MPFR evaluation of the stored
//    coefficients at two double points a few ulps apart, found by long-double bisection
//    along random lines) must lie in some kept cell;
//  * range enclosures must contain the exact value of f at random points of the box;
//  * closed-form distances to a sphere for tightness; exact ray/box geometry in MPFR.
#include "algray/cells.h"
#include "algray/gallery.h"
#include "algray/parser.h"
#include "algray/range_bound.h"
#include "support/scales.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <cmath>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace algray {
namespace {

// ---- References -----------------------------------------------------------------------
// Exact sign of f at a double point: every monomial of doubles is exact at 53 (m + 1)
// bits, and the sum of terms spanning the exponent range of |p| <= 2^10 fits in the
// precision below for the degrees used here (the sum is rounded at most once, far below
// any term that decides the sign).
// With offset: the exact sign of f(p) - offset.
int exactSign(const Polynomial& f, const glm::dvec3& p, double offset = 0.0) {
  mpfr_t sum, term, power[3];
  const mpfr_prec_t prec = 53 * (f.degree() + 2) + 2200;
  mpfr_inits2(prec, sum, term, power[0], power[1], power[2], static_cast<mpfr_ptr>(nullptr));
  mpfr_set_d(sum, -offset, MPFR_RNDN);
  const auto c = f.coeffs();
  for (int n = 0; n <= f.degree(); ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      if (c[idx] == 0) return;
      mpfr_set_d(term, c[idx], MPFR_RNDN);
      const int e[3] = {i, j, k};
      for (int a = 0; a < 3; ++a) {
        mpfr_set_d(power[a], p[a], MPFR_RNDN);
        mpfr_pow_ui(power[a], power[a], e[a], MPFR_RNDN);
        mpfr_mul(term, term, power[a], MPFR_RNDN);
      }
      mpfr_add(sum, sum, term, MPFR_RNDN);
    });
  const int s = mpfr_sgn(sum);
  mpfr_clears(sum, term, power[0], power[1], power[2], static_cast<mpfr_ptr>(nullptr));
  return s;
}

// f in long double, straight from the monomials (independent of Polynomial::evaluate).
long double evalLong(const Polynomial& f, const glm::dvec3& p) {
  const int m = f.degree();
  std::vector<long double> pw[3];
  for (int a = 0; a < 3; ++a) {
    pw[a].assign(m + 1, 1.0L);
    for (int e = 1; e <= m; ++e) pw[a][e] = pw[a][e - 1] * static_cast<long double>(p[a]);
  }
  long double s = 0;
  const auto c = f.coeffs();
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      if (c[idx] != 0) s += c[idx] * pw[0][i] * pw[1][j] * pw[2][k];
    });
  return s;
}

struct SurfacePoint {
  glm::dvec3 a, b;  // f(a) and f(b) have opposite exact signs: a zero lies on [a, b]
};

// Zeros of f on random lines through the clip box, each certified by an exact sign
// change between two double points a few ulps apart.
std::vector<SurfacePoint> sampleSurface(const Polynomial& f, const glm::dvec3& lo,
                                        const glm::dvec3& hi, int lines, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> gauss;
  const double diag = glm::length(hi - lo);
  std::vector<SurfacePoint> out;
  for (int l = 0; l < lines; ++l) {
    glm::dvec3 o, d;
    for (int a = 0; a < 3; ++a) o[a] = lo[a] + u01(rng) * (hi[a] - lo[a]);
    for (int a = 0; a < 3; ++a) d[a] = gauss(rng);
    d /= glm::length(d);
    auto at = [&](double t) { return o + t * d; };  // a double point
    const int steps = 300;
    double tPrev = -diag;
    long double fPrev = evalLong(f, at(tPrev));
    for (int s = 1; s <= steps; ++s) {
      const double t = -diag + 2 * diag * s / steps;
      const long double ft = evalLong(f, at(t));
      if ((fPrev < 0) != (ft < 0)) {
        double ta = tPrev, tb = t;
        const bool negA = fPrev < 0;
        for (int it = 0; it < 200; ++it) {
          const double tm = 0.5 * (ta + tb);
          if (tm == ta || tm == tb) break;
          ((evalLong(f, at(tm)) < 0) == negA ? ta : tb) = tm;
        }
        const glm::dvec3 pa = at(ta), pb = at(tb);
        const int sa = exactSign(f, pa), sb = exactSign(f, pb);
        if (sa * sb <= 0) out.push_back({pa, pb});
      }
      tPrev = t;
      fPrev = ft;
    }
  }
  return out;
}

bool boxesOverlap(const glm::dvec3& lo1, const glm::dvec3& hi1, const Cell& c) {
  for (int a = 0; a < 3; ++a)
    if (hi1[a] < c.lo[a] || lo1[a] > c.hi[a]) return false;
  return true;
}

bool inside(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
  return glm::all(glm::lessThanEqual(lo, p)) && glm::all(glm::lessThanEqual(p, hi));
}

// Every certified surface point inside the clip region has a cell touching its segment.
// Returns the number of points checked (the caller asserts it is not vacuous).
int checkCovered(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
                 const std::optional<CellSphere>& sphere, const std::vector<Cell>& cells, int lines,
                 unsigned seed) {
  int checked = 0;
  for (const SurfacePoint& s : sampleSurface(f, lo, hi, lines, seed)) {
    const glm::dvec3 sLo = glm::min(s.a, s.b), sHi = glm::max(s.a, s.b);
    if (!inside(sLo, lo, hi) || !inside(sHi, lo, hi)) continue;
    if (sphere && (glm::length(s.a - sphere->center) > sphere->radius ||
                   glm::length(s.b - sphere->center) > sphere->radius))
      continue;
    ++checked;
    bool found = false;
    for (const Cell& c : cells) found = found || boxesOverlap(sLo, sHi, c);
    EXPECT_TRUE(found) << "surface point (" << s.a.x << ", " << s.a.y << ", " << s.a.z
                       << ") in no cell of " << cells.size();
    if (!found) break;
  }
  return checked;
}

// ---- Surfaces built from Polynomial operations (independent of the parser) -------------
Polynomial X() { return Polynomial::variable(0); }
Polynomial Y() { return Polynomial::variable(1); }
Polynomial Z() { return Polynomial::variable(2); }
Polynomial sphere(glm::dvec3 c, double r) {
  return (X() - Polynomial(c.x)).pow(2) + (Y() - Polynomial(c.y)).pow(2) +
         (Z() - Polynomial(c.z)).pow(2) - Polynomial(r * r);
}
// Torus about the z axis: (x^2 + y^2 + z^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2).
Polynomial torus(double R, double r) {
  const Polynomial s = X().pow(2) + Y().pow(2) + Z().pow(2);
  return (s + Polynomial(R * R - r * r)).pow(2) - 4 * R * R * (X().pow(2) + Y().pow(2));
}
// Clebsch-like cubic with a singular point mix: x^3 + y^3 + z^3 + 1 - (x + y + z + 1)^3.
Polynomial cubic() {
  return X().pow(3) + Y().pow(3) + Z().pow(3) + Polynomial(1.0) -
         (X() + Y() + Z() + Polynomial(1.0)).pow(3);
}
// Product of n spheres of radius r on the unit circle: degree 2n.
Polynomial sphereChain(int n, double r) {
  Polynomial f(1.0);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    f = f * sphere({std::cos(a), std::sin(a), 0.0}, r);
  }
  return f;
}

const glm::dvec3 kLo(-1.5), kHi(1.5);

// ---- Range enclosures ---------------------------------------------------------------------
TEST(RangeBoundTest, ContainsExactValuesAtRandomPoints) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0), w(0.0, 1.0);
  const Polynomial surfaces[] = {sphere({0.1, -0.2, 0.3}, 1.0), torus(1.0, 0.3), cubic(),
                                 sphereChain(4, 0.3)};
  for (const Polynomial& f : surfaces) {
    for (int box = 0; box < 100; ++box) {
      glm::dvec3 lo, hi;
      for (int a = 0; a < 3; ++a) {
        lo[a] = u(rng);
        hi[a] = lo[a] + std::ldexp(w(rng), -(box % 12));
      }
      const Interval r =
          rangeOverBox(f, lo, hi, box % 2 ? RangeBound::Bernstein : RangeBound::Centred);
      for (int s = 0; s < 20; ++s) {
        glm::dvec3 p;
        for (int a = 0; a < 3; ++a)
          p[a] = std::clamp(lo[a] + w(rng) * (hi[a] - lo[a]), lo[a], hi[a]);
        if (s < 8)  // the corners too
          for (int a = 0; a < 3; ++a) p[a] = (s >> a) & 1 ? hi[a] : lo[a];
        // Exact containment: f(p) - lower >= 0 and upper - f(p) >= 0 in exact arithmetic.
        const int below = exactSign(f, p, r.lower());
        const int above = -exactSign(f, p, r.upper());
        ASSERT_GE(below, 0) << "f below the enclosure at box " << box;
        ASSERT_GE(above, 0) << "f above the enclosure at box " << box;
      }
    }
  }
}

// The centred form is tight to first order: for a linear f it is exact up to rounding,
// and on a small box about a regular point of the sphere its width is ~ the true range.
TEST(RangeBoundTest, CentredFormIsTight) {
  const Polynomial lin = 2.0 * X() - 3.0 * Y() + Z() + Polynomial(0.5);
  const Interval r = rangeOverBox(lin, glm::dvec3(0.0), glm::dvec3(1.0));
  // True range over [0,1]^3: [0.5 - 3, 0.5 + 2 + 1] = [-2.5, 3.5].
  EXPECT_NEAR(r.lower(), -2.5, 1e-13);
  EXPECT_NEAR(r.upper(), 3.5, 1e-13);
  const Polynomial s = sphere({0, 0, 0}, 1.0);
  const double h = 1e-3;
  const Interval q = rangeOverBox(s, glm::dvec3(1 - h, -h, -h), glm::dvec3(1 + h, h, h));
  // True range: |p|^2 - 1 over the box is [(1-h)^2 - 1, (1+h)^2 + 2h^2 - 1] ~ [-2h, 2h].
  EXPECT_LT(q.width(), 4 * h * 1.01 + 6 * h * h);
  EXPECT_TRUE(q.containsZero());
}

// Bernstein is tighter than the centred form on a large box of a high-degree surface
// (and never looser: rangeOverBox intersects the two), while both contain the true range.
TEST(RangeBoundTest, BernsteinIsTighterOnLargeBoxes) {
  const Polynomial f = sphereChain(5, 0.4);  // degree 10
  const glm::dvec3 lo(0.2, -0.7, -0.5), hi(1.4, 0.5, 0.7);
  const Interval c = rangeOverBox(f, lo, hi, RangeBound::Centred);
  const Interval b = rangeOverBox(f, lo, hi, RangeBound::Bernstein);
  EXPECT_LT(b.width(), 0.75 * c.width());  // measured: 248 vs 433
  EXPECT_GE(b.lower(), c.lower());
  EXPECT_LE(b.upper(), c.upper());
  // The exact value at the box centre and a corner lies in both.
  for (const glm::dvec3& p : {0.5 * (lo + hi), lo}) {
    EXPECT_GE(exactSign(f, p, b.lower()), 0);
    EXPECT_LE(exactSign(f, p, b.upper()), 0);
  }
}

TEST(RangeBoundTest, RejectsBadInput) {
  const Polynomial s = sphere({0, 0, 0}, 1.0);
  EXPECT_THROW(rangeOverBox(s, glm::dvec3(1.0), glm::dvec3(0.0)), Error);
  EXPECT_THROW(rangeOverBox(s, glm::dvec3(NAN), glm::dvec3(1.0)), Error);
  Polynomial bad = s;
  bad.setCoeff(1, 0, 0, INFINITY);
  EXPECT_THROW(rangeOverBox(bad, glm::dvec3(0.0), glm::dvec3(1.0)), Error);
}

// Univariate enclosures (a ray's polynomial over a cell's span): the exact value of every
// polynomial with coefficients within err of c, at random points of the span, is inside;
// where quickNoRoot proves "no root", the exact samples all have one strict sign.
TEST(RangeBoundTest, UnivariateContainsExactValues) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.0, 1.0);
  mpfr_t acc, term, x;
  mpfr_inits2(4000, acc, term, x, static_cast<mpfr_ptr>(nullptr));
  for (int trial = 0; trial < 3000; ++trial) {
    const int n = 1 + trial % 40;
    std::vector<double> c(n + 1), err(n + 1);
    for (int i = 0; i <= n; ++i) {
      c[i] = std::ldexp(u(rng), static_cast<int>(u(rng) * 20));
      err[i] = trial % 2 ? std::abs(c[i]) * 1e-12 * w(rng) : 0.0;
    }
    const double lo = 3 * u(rng), hi = lo + std::ldexp(w(rng), -(trial % 30));
    const Interval r = rangeOverInterval(c, err, lo, hi);
    const bool quick = quickNoRoot(c, err, lo, hi);
    int signs[2] = {0, 0};  // exact values seen < 0, > 0
    for (int k = 0; k < 10; ++k) {
      const double s = k == 0 ? lo : k == 1 ? hi : std::clamp(lo + w(rng) * (hi - lo), lo, hi);
      // A polynomial within the error bounds, evaluated exactly (Horner at 4000 bits).
      mpfr_set_zero(acc, 1);
      mpfr_set_d(x, s, MPFR_RNDN);
      for (int i = n; i >= 0; --i) {
        mpfr_mul(acc, acc, x, MPFR_RNDN);
        mpfr_set_d(term, err[i], MPFR_RNDN);
        mpfr_mul_d(term, term, k % 2 ? 1.0 : -1.0, MPFR_RNDN);
        mpfr_add_d(term, term, c[i], MPFR_RNDN);
        mpfr_add(acc, acc, term, MPFR_RNDN);
      }
      ASSERT_GE(mpfr_cmp_d(acc, r.lower()), 0) << "trial " << trial << " degree " << n;
      ASSERT_LE(mpfr_cmp_d(acc, r.upper()), 0) << "trial " << trial << " degree " << n;
      if (mpfr_sgn(acc) <= 0) ++signs[0];
      if (mpfr_sgn(acc) >= 0) ++signs[1];
    }
    // quickNoRoot claims one strict sign over the span: the exact samples agree.
    if (quick) {
      EXPECT_TRUE(signs[0] == 0 || signs[1] == 0) << "quickNoRoot wrong at trial " << trial;
    }
  }
  mpfr_clears(acc, term, x, static_cast<mpfr_ptr>(nullptr));
}

TEST(RangeBoundTest, UnivariateRootExclusion) {
  // (s - 0.3)(s + 2) = s^2 + 1.7 s - 0.6 has a root in [0, 1]: never excluded.
  const std::vector<double> g = {-0.6, 1.7, 1.0};
  EXPECT_FALSE(provablyNoRoot(g, {}, 0.0, 1.0));
  EXPECT_FALSE(provablyNoRoot(g, {}, 0.29, 0.31));
  // ... and none in [0.4, 0.5] or [-1.9, -0.1]: the centred form proves it.
  EXPECT_TRUE(provablyNoRoot(g, {}, 0.4, 0.5));
  EXPECT_TRUE(provablyNoRoot(g, {}, -1.9, -0.1));
  // s^2 + 1 on [-1, 1]: the even term is bounded in [0, 1], so the range is [1, 2].
  const std::vector<double> p = {1.0, 0.0, 1.0};
  const Interval r = rangeOverInterval(p, {}, -1.0, 1.0);
  EXPECT_GE(r.lower(), 1.0 - 1e-14);
  EXPECT_LE(r.upper(), 2.0 + 1e-14);
  // Coefficient errors count: 1e-3 +- 2e-3 may vanish.
  EXPECT_FALSE(provablyNoRoot(std::vector<double>{1e-3}, std::vector<double>{2e-3}, 0.0, 1.0));
  // The O(m) test: never where there is a root, and it proves easy cases.
  EXPECT_FALSE(quickNoRoot(g, {}, 0.0, 1.0));
  EXPECT_FALSE(quickNoRoot(g, {}, 0.29, 0.31));
  EXPECT_TRUE(quickNoRoot(g, {}, 0.45, 0.5));
  EXPECT_TRUE(quickNoRoot(std::vector<double>{2.0, 0.0, 1.0}, {}, -1.0, 1.0));  // s^2 + 2
  EXPECT_FALSE(quickNoRoot(std::vector<double>{1e-3}, std::vector<double>{2e-3}, 0.0, 1.0));
  EXPECT_FALSE(quickNoRoot(std::vector<double>{1.0, NAN}, {}, 0.0, 1.0));
  EXPECT_FALSE(quickNoRoot(g, {}, 0.4, NAN));
  // Non-finite input proves nothing.
  EXPECT_FALSE(provablyNoRoot(std::vector<double>{1.0, NAN}, {}, 0.0, 1.0));
  EXPECT_FALSE(provablyNoRoot(g, {}, 0.4, INFINITY));
}

// ---- Cells: conservativeness -------------------------------------------------------------
TEST(CellsTest, CoverSurfacePointsOfClassicSurfaces) {
  struct Case {
    const char* name;
    Polynomial f;
  };
  const Case cases[] = {{"sphere", sphere({0.1, -0.2, 0.05}, 1.0)},
                        {"torus", torus(1.0, 0.3)},
                        {"cubic", cubic()},
                        {"sphere chain (degree 12)", sphereChain(6, 0.4)}};
  for (const Case& c : cases) {
    for (int depth : {2, 4, 6}) {
      CellStats stats;
      const auto cells = buildCells(c.f, kLo, kHi, std::nullopt, {.depth = depth}, &stats);
      ASSERT_FALSE(cells.empty()) << c.name;
      EXPECT_EQ(stats.depth, depth) << c.name;
      const int checked = checkCovered(c.f, kLo, kHi, std::nullopt, cells, 100, 11 + depth);
      EXPECT_GE(checked, 40) << c.name << ": too few surface samples to mean anything";
    }
  }
}

// The Bernstein test keeps fewer cells and stays conservative.
TEST(CellsTest, BernsteinCellsCoverAndPruneMore) {
  const Polynomial f = torus(1.0, 0.3);
  const auto centred = buildCells(f, kLo, kHi, std::nullopt, {.depth = 3});
  const auto bern =
      buildCells(f, kLo, kHi, std::nullopt, {.depth = 3, .bound = RangeBound::Bernstein});
  EXPECT_LT(bern.size(), centred.size());
  EXPECT_GE(checkCovered(f, kLo, kHi, std::nullopt, bern, 100, 21), 40);
  const Polynomial chain = sphereChain(6, 0.4);
  const auto chainCells =
      buildCells(chain, kLo, kHi, std::nullopt, {.depth = 3, .bound = RangeBound::Bernstein});
  EXPECT_GE(checkCovered(chain, kLo, kHi, std::nullopt, chainCells, 100, 22), 20);
}

// The Bernstein enclosure culls a box where f keeps one sign, either sign: f and -f have
// the same cells (a cull of f > 0 alone kept every box where f < 0 throughout, unseen by
// the coverage tests: the mutation audit of session 55).
TEST(CellsTest, BernsteinCullIsSignSymmetric) {
  const Polynomial x = Polynomial::variable(0), y = Polynomial::variable(1),
                   z = Polynomial::variable(2), one(1.0);
  const Polynomial surfaces[] = {torus(1.0, 0.3), sphereChain(6, 0.4),
                                 x * x * x - 3 * x * y * y + z * z - 0.2 * one};
  for (const Polynomial& f : surfaces) {
    const CellOptions options{.depth = 4, .bound = RangeBound::Bernstein};
    const auto plus = buildCells(f, kLo, kHi, std::nullopt, options);
    const auto minus = buildCells(-f, kLo, kHi, std::nullopt, options);
    ASSERT_EQ(plus.size(), minus.size());
    for (size_t i = 0; i < plus.size(); ++i) EXPECT_EQ(plus[i].index, minus[i].index) << i;
    // And fewer than the centred form's alone (the enclosure culls at all).
    EXPECT_LT(plus.size(), buildCells(f, kLo, kHi, std::nullopt, {.depth = 4}).size());
  }
}

TEST(CellsTest, CoverWithClipSphereAndAutomaticDepth) {
  const Polynomial f = torus(1.0, 0.4);
  // A clip ball much larger than the torus: most rays miss the surface, cells pay.
  const CellSphere ball{{0.2, 0.0, 0.1}, 3.5};
  const glm::dvec3 lo = ball.center - glm::dvec3(ball.radius),
                   hi = ball.center + glm::dvec3(ball.radius);
  CellStats stats;
  const auto cells = buildCells(f, lo, hi, ball, {}, &stats);
  ASSERT_FALSE(cells.empty());
  EXPECT_GE(stats.depth, 3);
  EXPECT_LE(stats.rayCoverage, 0.3);
  EXPECT_LE(static_cast<long>(cells.size()), CellOptions{}.maxCells);
  // Every cell touches the ball (the ones wholly outside were dropped).
  for (const Cell& c : cells) {
    const glm::dvec3 nearest = glm::clamp(ball.center, c.lo, c.hi);
    EXPECT_LE(glm::length(nearest - ball.center), ball.radius * (1 + 1e-12));
  }
  EXPECT_GE(checkCovered(f, lo, hi, ball, cells, 200, 5),
            25);  // 38 measured: the ball is mostly empty
  // rayCoverage against sampled axis-parallel rays through the ball.
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double sum = 0;
  for (int axis = 0; axis < 3; ++axis) {
    int through = 0, meet = 0;
    for (int k = 0; k < 3000; ++k) {
      glm::dvec3 o = ball.center, d(0.0);
      o[(axis + 1) % 3] += ball.radius * u(rng);
      o[(axis + 2) % 3] += ball.radius * u(rng);
      o[axis] = lo[axis] - 1.0;
      d[axis] = 1.0;
      const glm::dvec3 q = o - ball.center;
      if (q[(axis + 1) % 3] * q[(axis + 1) % 3] + q[(axis + 2) % 3] * q[(axis + 2) % 3] >
          ball.radius * ball.radius)
        continue;
      ++through;
      bool any = false;
      for (const Cell& c : cells) any = any || clipRayToBox(o, d, c.lo, c.hi, 0.0, 1e9).has_value();
      meet += any;
    }
    sum += static_cast<double>(meet) / through;
  }
  EXPECT_NEAR(stats.rayCoverage, sum / 3, 0.05);
  // The same torus filling a tight ball: the cells would meet most rays, so the
  // automatic choice is one cell for the whole region.
  const CellSphere tight{{0.0, 0.0, 0.0}, 1.5};
  CellStats tightStats;
  const auto one = buildCells(f, glm::dvec3(-1.5), glm::dvec3(1.5), tight, {}, &tightStats);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(tightStats.depth, 0);
  EXPECT_GT(tightStats.rayCoverage, 0.3);
  // Decided by the probe lines, without building a level, and the probe measures the
  // torus's own crossing fraction. Closed form over the disk of radius 1.5 (area
  // 2.25 pi): lines along z cross the annulus R - r <= rho <= R + r, area 4 pi R r; lines
  // along x (or y) cross where |z| <= r and |y| <= R + sqrt(r^2 - z^2), area
  // 4 R r + pi r^2. Mean over the axes: 0.435.
  EXPECT_EQ(tightStats.boxesTested, 0);
  const double kPi = 3.14159265358979323846, R = 1.0, r = 0.4, disk = 2.25 * kPi;
  const double expected = (4 * kPi * R * r / disk + 2 * (4 * R * r + kPi * r * r) / disk) / 3;
  EXPECT_NEAR(tightStats.rayCoverage, expected, 0.02);
  EXPECT_EQ(one[0].lo, glm::dvec3(-1.5));
  EXPECT_EQ(one[0].hi, glm::dvec3(1.5));
}

// A non-cubic clip box: the kd split takes the long axis first.
// The automatic choice on gallery surfaces (cells.cpp, "Skipping a build that cannot
// pay"): Barth's sextic and Chmutov's octic fill their clip balls (probed coverage 0.23
// and 0.27), get one cell and build no level at all; the octic in a ball of 3x the radius
// (probed 0.009) gets a level whose cells meet few rays.
TEST(CellsTest, AutomaticDepthSkipsBuildsThatCannotPay) {
  for (const char* name : {"barth-sextic", "chmutov-8"}) {
    SCOPED_TRACE(name);
    const GallerySurface& s = *findGallerySurface(name);
    for (const double scale : {1.0, 3.0}) {
      const double r = scale * s.clipRadius;
      CellStats stats;
      const auto cells = buildCells(s.build(), glm::dvec3(-r), glm::dvec3(r),
                                    CellSphere{glm::dvec3(0.0), r}, {.maxCells = 4096}, &stats);
      if (scale == 1.0) {
        EXPECT_EQ(cells.size(), 1u) << scale;
        EXPECT_EQ(stats.boxesTested, 0) << scale;
      } else if (std::string_view(name) == "chmutov-8") {
        EXPECT_GT(cells.size(), 1000u);
        EXPECT_LE(stats.rayCoverage, 0.3);
      }
    }
  }
}

TEST(CellsTest, CoverInElongatedBox) {
  const Polynomial f = sphere({0.0, 0.0, 0.0}, 1.0);
  const glm::dvec3 lo(-3.0, -1.2, -0.4), hi(3.0, 1.2, 0.7);
  const auto cells = buildCells(f, lo, hi, std::nullopt, {.depth = 5});
  ASSERT_FALSE(cells.empty());
  for (const Cell& c : cells) {
    EXPECT_TRUE(inside(c.lo, lo, hi) && inside(c.hi, lo, hi));  // clipped to the box
    EXPECT_LE(c.hi.x - c.lo.x, 6.0 / 32 * (1 + 1e-12));         // depth 5 of the 6-long edge
    EXPECT_LE(c.hi.y - c.lo.y, 6.0 / 32 * (1 + 1e-12));
  }
  EXPECT_GE(checkCovered(f, lo, hi, std::nullopt, cells, 80, 3), 40);
}

// Degree 40: a product of 20 spheres. Built at a modest depth, still conservative.
// (At this depth the centred form keeps every box: its terms sum |c_m| over 12341
// coefficients of a product that cancels; docs/cells-summary.md.)
TEST(CellsTest, DegreeFortyProductOfSpheres) {
  const Polynomial f = sphereChain(20, 0.1);
  ASSERT_EQ(f.degree(), 40);
  CellStats stats;
  const auto cells = buildCells(f, kLo, kHi, std::nullopt, {.depth = 2}, &stats);
  ASSERT_FALSE(cells.empty());
  // Certified points near each sphere: the radial line through its centre crosses it.
  int checked = 0;
  for (int i = 0; i < 20; i += 3) {
    const double a = 2 * M_PI * i / 20;
    const glm::dvec3 c(std::cos(a), std::sin(a), 0.0);
    // Vertically through the centre: only this sphere is crossed, at t = 0.1.
    const glm::dvec3 dir(0.0, 0.0, 1.0);
    double ta = 0.05, tb = 0.15;
    const bool negA = evalLong(f, c + ta * dir) < 0;
    for (int it = 0; it < 60; ++it) {
      const double tm = 0.5 * (ta + tb);
      ((evalLong(f, c + tm * dir) < 0) == negA ? ta : tb) = tm;
    }
    const glm::dvec3 pa = c + ta * dir, pb = c + tb * dir;
    if (exactSign(f, pa) * exactSign(f, pb) > 0) continue;  // long double misjudged: skip
    bool found = false;
    for (const Cell& cell : cells)
      found = found || boxesOverlap(glm::min(pa, pb), glm::max(pa, pb), cell);
    EXPECT_TRUE(found) << "sphere " << i;
    ++checked;
  }
  EXPECT_GE(checked, 5);
  // Automatic depth on degree 40 stays within its small build budget (64 cells).
  CellStats autoStats;
  const auto autoCells = buildCells(f, kLo, kHi, std::nullopt, {}, &autoStats);
  EXPECT_FALSE(autoCells.empty());
  EXPECT_LE(autoCells.size(), 64u);
  EXPECT_LE(autoStats.boxesTested, 200);
}

// ---- Cells: empty and degenerate regions -------------------------------------------------
TEST(CellsTest, EmptyRegionsGiveNoCells) {
  const Polynomial f = sphere({0, 0, 0}, 1.0);
  EXPECT_TRUE(buildCells(f, glm::dvec3(1.0), glm::dvec3(-1.0)).empty());
  EXPECT_TRUE(buildCells(f, glm::dvec3(-1.0, 0.0, 0.0), glm::dvec3(1.0, -0.1, 1.0)).empty());
  EXPECT_TRUE(buildCells(f, kLo, kHi, CellSphere{{0, 0, 0}, -1.0}).empty());
  // The surface misses the clip box: proved at the root already.
  CellStats stats;
  EXPECT_TRUE(buildCells(f, glm::dvec3(5.0), glm::dvec3(6.0), std::nullopt, {}, &stats).empty());
  EXPECT_EQ(stats.boxesTested, 1);
  // The clip box overlaps the surface but the clip sphere (radius 0.5) does not.
  EXPECT_TRUE(
      buildCells(f, glm::dvec3(-2.0), glm::dvec3(2.0), CellSphere{{0, 0, 0}, 0.5}, {.depth = 5})
          .empty());
  // A constant non-zero polynomial has no surface.
  EXPECT_TRUE(buildCells(Polynomial(2.0), kLo, kHi).empty());
}

TEST(CellsTest, DegenerateBoxes) {
  const Polynomial f = sphere({0, 0, 0}, 1.0);
  // A flat box (the plane z = 0) crossing the sphere's equator; (1, 0, 0) and (0, -1, 0)
  // are exact surface points.
  const auto cells = buildCells(f, glm::dvec3(-2.0, -2.0, 0.0), glm::dvec3(2.0, 2.0, 0.0),
                                std::nullopt, {.depth = 4});
  ASSERT_FALSE(cells.empty());
  for (glm::dvec3 p : {glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0)}) {
    bool found = false;
    for (const Cell& c : cells) found = found || boxesOverlap(p, p, c);
    EXPECT_TRUE(found);
  }
  // A point box: one cell on the surface, none off it.
  EXPECT_EQ(buildCells(f, glm::dvec3(1, 0, 0), glm::dvec3(1, 0, 0)).size(), 1u);
  EXPECT_TRUE(buildCells(f, glm::dvec3(0.5, 0, 0), glm::dvec3(0.5, 0, 0)).empty());
  // ... also at an explicit depth: a point cannot be split, so one cell and level 0.
  CellStats pointStats;
  EXPECT_EQ(buildCells(f, glm::dvec3(1, 0, 0), glm::dvec3(1, 0, 0), std::nullopt, {.depth = 3},
                       &pointStats)
                .size(),
            1u);
  EXPECT_EQ(pointStats.depth, 0);
  // A clip ball of radius 0 is the closed ball {centre}: a point, not an empty region. On
  // the surface it keeps a cell, off it none.
  EXPECT_FALSE(buildCells(f, kLo, kHi, CellSphere{{1, 0, 0}, 0.0}, {.depth = 3}).empty());
  EXPECT_TRUE(buildCells(f, kLo, kHi, CellSphere{{0.5, 0, 0}, 0.0}, {.depth = 3}).empty());
}

TEST(CellsTest, RejectsNonFiniteInput) {
  const Polynomial f = sphere({0, 0, 0}, 1.0);
  EXPECT_THROW(buildCells(f, glm::dvec3(NAN), kHi), Error);
  EXPECT_THROW(buildCells(f, kLo, glm::dvec3(INFINITY)), Error);
  EXPECT_THROW(buildCells(f, kLo, kHi, CellSphere{{0, NAN, 0}, 1.0}), Error);
  EXPECT_THROW(buildCells(f, kLo, kHi, CellSphere{{0, 0, 0}, INFINITY}), Error);
  // Every axis is checked, the last one too.
  for (int a = 0; a < 3; ++a) {
    glm::dvec3 lo = kLo, hi = kHi;
    lo[a] = NAN;
    EXPECT_THROW(buildCells(f, lo, kHi), Error) << a;
    hi[a] = INFINITY;
    EXPECT_THROW(buildCells(f, kLo, hi), Error) << a;
  }
  Polynomial bad = f;
  bad.setCoeff(0, 0, 0, NAN);
  EXPECT_THROW(buildCells(bad, kLo, kHi), Error);
  EXPECT_THROW(buildCells(f, kLo, kHi, std::nullopt, {.depth = 2, .maxCells = 0}), Error);
  // -1 is the automatic depth; -7 was silently taken for it.
  EXPECT_THROW(buildCells(f, kLo, kHi, std::nullopt, {.depth = -7}), Error);
  EXPECT_NO_THROW(buildCells(f, kLo, kHi, std::nullopt, {.depth = -1}));
}

// ---- Cells: tightness and budgets --------------------------------------------------------
// The three coordinate planes, f = x y z, on the cube [-1, 1]^3 at depth 3 (grid 8^3, step
// 1/4): the planes lie on grid planes, so the closed cells meeting f = 0 are those with an
// index 3 or 4 (a face on x, y or z = 0): 8^3 - 6^3 = 296 cells (at depth 2: 4^3 - 2^3 =
// 56). On every other box f keeps one strict sign, and so do the Bernstein coefficients of
// a product of linear factors (each factor's are its values at the box's ends), so the
// Bernstein test keeps exactly those cells (the enclosure of a touching cell is [0, u] up to
// rounding, widened outward: kept). A count against a closed form, for the budget too.
TEST(CellsTest, BernsteinKeepsExactlyTheCellsTouchingCoordinatePlanes) {
  const Polynomial f = X() * Y() * Z();
  const glm::dvec3 lo(-1.0), hi(1.0);
  for (const Polynomial& g : {f, -f}) {
    CellStats stats;
    const auto cells =
        buildCells(g, lo, hi, std::nullopt, {.depth = 3, .bound = RangeBound::Bernstein}, &stats);
    EXPECT_EQ(stats.depth, 3);
    EXPECT_EQ(cells.size(), 296u);
    for (const Cell& c : cells) {
      const glm::ivec3 i = c.index;
      EXPECT_TRUE(i.x == 3 || i.x == 4 || i.y == 3 || i.y == 4 || i.z == 3 || i.z == 4)
          << i.x << " " << i.y << " " << i.z;
    }
  }
  // maxCells caps the level only when it keeps more (cells.h): 296 allows depth 3, 295 not
  // (the level of 56 cells is returned).
  CellStats capped;
  EXPECT_EQ(buildCells(f, lo, hi, std::nullopt,
                       {.depth = 3, .maxCells = 296, .bound = RangeBound::Bernstein}, &capped)
                .size(),
            296u);
  EXPECT_EQ(capped.depth, 3);
  EXPECT_EQ(buildCells(f, lo, hi, std::nullopt,
                       {.depth = 3, .maxCells = 295, .bound = RangeBound::Bernstein}, &capped)
                .size(),
            56u);
  EXPECT_EQ(capped.depth, 2);
}

// Explicit depths up to kMaxCellDepth are honoured, deeper ones capped there (cells.h). The
// point surface x^2 + y^2 + z^2 = 0 (the origin) keeps a few cells per level, so depth 25
// is cheap; its cells have edges 2 / 2^depth (the root box rounded outward by an ulp) and
// one of them holds the origin.
TEST(CellsTest, DeepLevelsAreHonouredUpToTheCap) {
  const Polynomial f = X().pow(2) + Y().pow(2) + Z().pow(2);
  for (const int depth : {25, 40}) {
    CellStats stats;
    const auto cells =
        buildCells(f, glm::dvec3(-1.0), glm::dvec3(1.0), std::nullopt, {.depth = depth}, &stats);
    const int expected = std::min(depth, kMaxCellDepth);
    EXPECT_EQ(stats.depth, expected);
    ASSERT_FALSE(cells.empty());
    bool origin = false;
    for (const Cell& c : cells) {
      EXPECT_NEAR(c.hi.x - c.lo.x, std::ldexp(2.0, -expected), std::ldexp(1e-9, -expected));
      origin = origin || inside(glm::dvec3(0.0), c.lo, c.hi);
    }
    EXPECT_TRUE(origin);
  }
}

// A surface inside the clip box but wholly outside the clip ball gives no cells, also with
// the automatic depth, whose probe lines must stay within the ball: the sphere of radius
// 2.5 about the ball's centre misses the ball of radius 1.5 (closed form), while within the
// box [-3, 3]^3 most axis-parallel lines cross it.
TEST(CellsTest, SurfaceOutsideTheClipBallGivesNoCells) {
  const Polynomial f = sphere({0, 0, 0}, 2.5);
  const CellSphere ball{glm::dvec3(0.0), 1.5};
  for (const int depth : {-1, 4}) {
    EXPECT_TRUE(buildCells(f, glm::dvec3(-3.0), glm::dvec3(3.0), ball, {.depth = depth}).empty())
        << depth;
  }
}

// Kept cells hug the surface: the centre of every cell at depth d is within a few cell
// diagonals of the unit sphere (closed-form distance | |c| - 1 |), and the kept volume
// shrinks about 2x per level as it must for a surface.
TEST(CellsTest, CellsHugTheSphere) {
  const Polynomial f = sphere({0, 0, 0}, 1.0);
  CellStats stats;
  const auto cells = buildCells(f, kLo, kHi, std::nullopt, {.depth = 6}, &stats);
  const double diag = std::sqrt(3.0) * 3.0 / 64;
  for (const Cell& c : cells) {
    const glm::dvec3 centre = 0.5 * (c.lo + c.hi);
    EXPECT_LE(std::abs(glm::length(centre) - 1.0), 1.5 * diag);
  }
  ASSERT_EQ(stats.keptVolumeFraction.size(), 7u);
  for (int l = 3; l < 6; ++l)
    EXPECT_LT(stats.keptVolumeFraction[l + 1], 0.7 * stats.keptVolumeFraction[l]) << l;
  // The sphere's area 4 pi over cell faces (3/64)^2 gives ~5700 cells crossed; a shell a
  // few cells thick is at most ~4x that.
  EXPECT_LT(cells.size(), 4 * 5720u);
  EXPECT_GT(cells.size(), 5720u / 4);
}

// surfaceReach bounds the distance of every surface point from the given point, and within
// 1.5 times it where its search converges (quadrics and quartics in regions up to 1e9 times
// their size, where the capped cells reach ~1e-3 of the region; the quartics not at 1e50).
// References: the farthest points in closed form (a sphere's radius; a torus's R + r; an
// offset sphere's |centre| + r), and surface points found along random lines (sign changes
// of f, bisected) that must all lie within the bound. A surface outside the region gives 0.
TEST(CellsTest, SurfaceReachBoundsEverySurfacePoint) {
  struct Case {
    const char* name;
    Polynomial f;
    double farthest;
  };
  const Case cases[] = {{"sphere", sphere({0, 0, 0}, 1.0), 1.0},
                        {"torus", torus(1.0, 0.4), 1.4},
                        {"offset sphere", sphere({60, 0, 80}, 1.0), 101.0},
                        {"quartic", parsePolynomial("x^4+y^4+z^4-1"), std::pow(3.0, 0.25)}};
  std::mt19937_64 gen(51);
  std::normal_distribution<double> normal;
  for (const Case& c : cases)
    for (const double R : {200.0, 1e4, 1e9, 1e50}) {
      SCOPED_TRACE(std::string(c.name) + " in a region of " + std::to_string(R));
      const glm::dvec3 lo(-R), hi(R);
      const double ball =
          surfaceReach(c.f, lo, hi, CellSphere{glm::dvec3(0.0), R}, glm::dvec3(0.0));
      const double box = surfaceReach(c.f, lo, hi, std::nullopt, glm::dvec3(0.0));
      for (const double reach : {ball, box}) {
        EXPECT_GE(reach, c.farthest);
        if (R < 1e10 || c.f.degree() == 2) {
          EXPECT_LE(reach, 1.5 * c.farthest);
        }
      }
      // Points of the surface: sign changes along lines through it.
      for (int k = 0; k < 200; ++k) {
        const glm::dvec3 a = c.farthest * glm::dvec3(normal(gen), normal(gen), normal(gen));
        const glm::dvec3 b = c.farthest * glm::dvec3(normal(gen), normal(gen), normal(gen));
        double s0 = 0, s1 = 1;
        const double f0 = c.f.evaluate(a), f1 = c.f.evaluate(b);
        if (!(f0 * f1 < 0)) continue;
        for (int i = 0; i < 60; ++i) {
          const double m = 0.5 * (s0 + s1);
          (c.f.evaluate(a + m * (b - a)) * f0 > 0 ? s0 : s1) = m;
        }
        EXPECT_LE(glm::length(a + s0 * (b - a)), ball * (1 + 1e-12));
      }
    }
  // `enough`: where the lattice shows the surface reaching that far, the region's farthest
  // corner at once (a sphere filling its box); where it cannot (a unit sphere in a box of
  // 200), the search as without it.
  const Polynomial unit = sphere({0, 0, 0}, 1.0);
  EXPECT_GE(surfaceReach(unit, glm::dvec3(-1.5), glm::dvec3(1.5), std::nullopt, glm::dvec3(0.0),
                         4e6, 1e-3),
            1.5 * std::sqrt(3.0));
  EXPECT_EQ(surfaceReach(unit, glm::dvec3(-200), glm::dvec3(200), std::nullopt, glm::dvec3(0.0),
                         4e6, 0.1),
            surfaceReach(unit, glm::dvec3(-200), glm::dvec3(200), std::nullopt, glm::dvec3(0.0)));
  // A surface wholly outside the region: 0; a bad point or work: an error.
  EXPECT_EQ(surfaceReach(sphere({100, 0, 0}, 1.0), glm::dvec3(-10), glm::dvec3(10), std::nullopt,
                         glm::dvec3(0.0)),
            0.0);
  EXPECT_THROW(surfaceReach(sphere({0, 0, 0}, 1.0), glm::dvec3(-2), glm::dvec3(2), std::nullopt,
                            glm::dvec3(std::nan(""))),
               Error);
  EXPECT_THROW(surfaceReach(sphere({0, 0, 0}, 1.0), glm::dvec3(-2), glm::dvec3(2), std::nullopt,
                            glm::dvec3(0.0), -1.0),
               Error);
}

TEST(CellsTest, MaxCellsCapsTheLevel) {
  const Polynomial f = torus(1.0, 0.3);
  CellStats stats;
  const auto cells = buildCells(f, kLo, kHi, std::nullopt, {.depth = 8, .maxCells = 500}, &stats);
  EXPECT_LE(cells.size(), 500u);
  EXPECT_LT(stats.depth, 8);
  EXPECT_FALSE(cells.empty());
  // The returned level is complete: it is exactly the level built with that depth.
  const auto direct = buildCells(f, kLo, kHi, std::nullopt, {.depth = stats.depth});
  EXPECT_EQ(direct.size(), cells.size());
}

// The cells are one level of a regular grid: index and grid describe each nominal box
// (the adapter uses them to give a root on a shared face to exactly one cell).
TEST(CellsTest, GridIndicesDescribeTheCells) {
  const Polynomial f = torus(1.0, 0.3);
  const glm::dvec3 lo(-1.5, -1.5, -0.75), hi(1.5, 1.5, 0.75);  // elongated: grid 16 x 16 x 8
  CellStats stats;
  const auto cells = buildCells(f, lo, hi, std::nullopt, {.depth = 4}, &stats);
  ASSERT_FALSE(cells.empty());
  EXPECT_EQ(stats.grid, glm::ivec3(16, 16, 8));
  std::set<std::tuple<int, int, int>> seen;
  for (const Cell& c : cells) {
    EXPECT_TRUE(seen.emplace(c.index.x, c.index.y, c.index.z).second) << "duplicate index";
    for (int a = 0; a < 3; ++a) {
      ASSERT_GE(c.index[a], 0);
      ASSERT_LT(c.index[a], stats.grid[a]);
      const double step = (hi[a] - lo[a]) / stats.grid[a];
      EXPECT_NEAR(c.lo[a], lo[a] + step * c.index[a], 1e-12);
      EXPECT_NEAR(c.hi[a], lo[a] + step * (c.index[a] + 1), 1e-12);
    }
  }
}

// Enormous clip boxes overflow the enclosure to infinity: every box is kept (correct,
// if useless), nothing crashes or hangs.
TEST(CellsTest, HugeBoxesStayConservative) {
  const Polynomial f = sphere({0, 0, 0}, 1.0);
  CellStats stats;
  const auto cells =
      buildCells(f, glm::dvec3(-1e300), glm::dvec3(1e300), std::nullopt, {.depth = 2}, &stats);
  EXPECT_FALSE(cells.empty());
  bool containsOrigin = false;
  for (const Cell& c : cells)
    containsOrigin = containsOrigin || inside(glm::dvec3(1, 0, 0), c.lo, c.hi);
  EXPECT_TRUE(containsOrigin);
}

// buildCells with flush-to-zero and denormals-are-zero on (a host building surfaces in its
// TBB workers): the interval arithmetic of the range test assumes gradual underflow (a
// rounded sum is 0 only if the exact one is, a product's underflow is within the smallest
// subnormal), which FTZ breaks: 1e-305 (x^3 + y^3 + z^3 - 1 + 0.1 x y z) lost 8 of 3004
// cells at depth 5, and a surface point with them. Against points of the surface found by
// bisection of sign changes of the unscaled polynomial along random segments (brute
// force), and the cells built with gradual underflow.
TEST(CellsTest, FlushToZeroLosesNoCell) {
#if defined(__SSE__)
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (const std::string eq : {"x^3+y^3+z^3-1+0.1*x*y*z", "(x^2+y^2+z^2+0.75)^2-4*(x^2+y^2)"}) {
    const Polynomial g = parsePolynomial(eq);
    for (const double scale : {1e-305, 1e-300}) {
      const Polynomial f = g * scale;
      CellOptions options;
      options.depth = 5;
      const glm::dvec3 lo(-2.0), hi(2.0);
      const std::vector<Cell> gradual = buildCells(f, lo, hi, std::nullopt, options);
      const unsigned saved = _mm_getcsr();
      _mm_setcsr(saved | 0x8040u);  // FTZ (bit 15) | DAZ (bit 6)
      const std::vector<Cell> flushed = buildCells(f, lo, hi, std::nullopt, options);
      const bool restored = _mm_getcsr() == (saved | 0x8040u);
      _mm_setcsr(saved);
      EXPECT_TRUE(restored) << "buildCells left the caller's floating-point mode changed";
      ASSERT_EQ(flushed.size(), gradual.size()) << eq << " times " << scale;
      int points = 0, missed = 0;
      for (int i = 0; i < 6000; ++i) {  // 4000 gave 499 points of the torus on a draw
        glm::dvec3 a(u(gen), u(gen), u(gen)), b(u(gen), u(gen), u(gen));
        double fa = g.evaluate(a);
        if (fa * g.evaluate(b) >= 0) continue;
        for (int it = 0; it < 80; ++it) {
          const glm::dvec3 m = 0.5 * (a + b);
          const double fm = g.evaluate(m);
          if (fm * fa > 0) {
            a = m;
            fa = fm;
          } else {
            b = m;
          }
        }
        ++points;
        bool in = false;
        for (const Cell& c : flushed)
          in = in || inside(a, c.lo - glm::dvec3(1e-12), c.hi + glm::dvec3(1e-12));
        missed += !in;
      }
      EXPECT_GT(points, 500) << eq;
      EXPECT_EQ(missed, 0) << eq << " times " << scale << ": surface points in no cell";
    }
  }
#else
  GTEST_SKIP() << "no SSE control register";
#endif
}

// The level refinement runs in parallel (cells.cpp, Builder::refine). Its cells must be the
// serial build's, in the same order, on any number of threads, including a level over
// budget (maxCells) and automatic depth; and a host that calls buildCells from a TBB task
// whose context captured flush-to-zero (tasks inherit the context's floating-point mode,
// so every chunk sets its own) still loses no cell.
TEST(CellsTest, ParallelBuildIsTheSerialOne) {
  auto same = [](const std::vector<Cell>& a, const std::vector<Cell>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
      if (a[i].lo != b[i].lo || a[i].hi != b[i].hi || a[i].index != b[i].index) return false;
    return true;
  };
  for (const char* name : {"torus", "chmutov-8", "heart"}) {
    const GallerySurface* s = findGallerySurface(name);
    ASSERT_NE(s, nullptr);
    const Polynomial f = s->build();
    const double r = 3 * s->clipRadius;
    const CellSphere ball{glm::dvec3(0.0), r};
    for (const int depth : {5, -1}) {
      for (const int maxCells : {1 << 16, 300}) {
        CellOptions options;
        options.depth = depth;
        options.maxCells = maxCells;
        std::vector<Cell> serial;
        {
          tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
          serial = buildCells(f, glm::dvec3(-r), glm::dvec3(r), ball, options);
        }
        const std::vector<Cell> parallel =
            buildCells(f, glm::dvec3(-r), glm::dvec3(r), ball, options);
        EXPECT_TRUE(same(serial, parallel))
            << name << " depth " << depth << " maxCells " << maxCells << ": " << serial.size()
            << " serial cells, " << parallel.size() << " parallel";
      }
    }
  }
#if defined(__SSE__)
  // (Without each chunk's guard this build kept 2996 of its 3004 cells.)
  const Polynomial f = parsePolynomial("x^3+y^3+z^3-1+0.1*x*y*z") * 1e-305;
  CellOptions options;
  options.depth = 5;
  const glm::dvec3 lo(-2.0), hi(2.0);
  const std::vector<Cell> gradual = buildCells(f, lo, hi, std::nullopt, options);
  const unsigned saved = _mm_getcsr();
  tbb::task_group_context flushing;
  _mm_setcsr(saved | 0x8040u);  // FTZ | DAZ, captured by the context
  flushing.capture_fp_settings();
  _mm_setcsr(saved);
  std::vector<Cell> inTask;
  tbb::parallel_for(
      0, 1, [&](int) { inTask = buildCells(f, lo, hi, std::nullopt, options); }, flushing);
  EXPECT_TRUE(same(gradual, inTask)) << gradual.size() << " cells, " << inTask.size()
                                     << " from a task whose context flushes to zero";
#endif
}

// ---- Ray / box clipping ---------------------------------------------------------------------
TEST(ClipRayTest, SimpleCases) {
  const glm::dvec3 lo(0.0), hi(1.0);
  auto s = clipRayToBox(glm::dvec3(-1.0), glm::dvec3(1.0), lo, hi, 0.0, 10.0);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->t0, 1.0, 1e-14);
  EXPECT_NEAR(s->t1, 2.0, 1e-14);
  // Clamped to [tMin, tMax].
  s = clipRayToBox(glm::dvec3(-1.0), glm::dvec3(1.0), lo, hi, 1.5, 10.0);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->t0, 1.5);
  EXPECT_FALSE(clipRayToBox(glm::dvec3(-1.0), glm::dvec3(1.0), lo, hi, 0.0, 0.5));
  // Zero direction components: inside the slab (also on its face) or not at all.
  EXPECT_TRUE(clipRayToBox({0.5, 0.5, -1.0}, {0.0, 0.0, 1.0}, lo, hi, 0.0, 10.0));
  EXPECT_TRUE(clipRayToBox({1.0, 0.0, -1.0}, {0.0, 0.0, 1.0}, lo, hi, 0.0, 10.0));
  EXPECT_FALSE(clipRayToBox({1.5, 0.5, -1.0}, {0.0, 0.0, 1.0}, lo, hi, 0.0, 10.0));
  // -0 as +0, also with the origin on either face (0 / -0 = NaN, 1 / -0 = -inf).
  for (const double x : {0.0, 0.5, 1.0}) {
    for (const double dx : {0.0, -0.0}) {
      const auto span = clipRayToBox({x, 0.5, -1.0}, {dx, 0.0, 1.0}, lo, hi, 0.0, 10.0);
      ASSERT_TRUE(span) << x << " " << dx;
      EXPECT_NEAR(span->t0, 1.0, 1e-14);
      EXPECT_NEAR(span->t1, 2.0, 1e-14);
    }
  }
  EXPECT_FALSE(clipRayToBox({-0x1p-30, 0.5, -1.0}, {-0.0, 0.0, 1.0}, lo, hi, 0.0, 10.0));
  // A subnormal entry parameter (exact 1.5 2^-1074, rounded to 2^-1073) stays before the
  // face, and a subnormal exit parameter after it.
  auto sub = clipRayToBox({-3 * 0x1p-1074, 0.5, 0.5}, {2.0, 0.0, 0.0}, lo, hi, 0.0, 10.0);
  ASSERT_TRUE(sub);
  EXPECT_LE(sub->t0, 0x1p-1074);
  sub = clipRayToBox({1.0 - 0x1p-53, 0.5, 0.5}, {0x1p-52, 0.0, 0.0}, lo, hi, 0.0, 10.0);
  ASSERT_TRUE(sub);
  EXPECT_GE(sub->t1, 0.5);
  // Misses and bad input.
  EXPECT_FALSE(clipRayToBox({-1.0, 2.0, 0.5}, {1.0, 0.0, 0.0}, lo, hi, 0.0, 10.0));
  EXPECT_FALSE(clipRayToBox(glm::dvec3(NAN), glm::dvec3(1.0), lo, hi, 0.0, 10.0));
  EXPECT_FALSE(clipRayToBox(glm::dvec3(-1.0), glm::dvec3(1.0), lo, hi, 5.0, 1.0));
  EXPECT_FALSE(clipRayToBox(glm::dvec3(-1.0), glm::dvec3(1.0), lo, hi, 0.0, NAN));
}

// Grazing corners: the box's lower corner is the exact point o + t* d rounded down, so
// the exact ray touches the box at t*; the span must contain t*.
TEST(ClipRayTest, GrazingCornersAreKept) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-10.0, 10.0), pos(0.01, 5.0);
  mpfr_t x;
  mpfr_init2(x, 300);
  for (int trial = 0; trial < 20000; ++trial) {
    glm::dvec3 o, d, lo, hi;
    for (int a = 0; a < 3; ++a) o[a] = u(rng), d[a] = u(rng);
    const double t = pos(rng);
    for (int a = 0; a < 3; ++a) {
      mpfr_set_d(x, d[a], MPFR_RNDN);
      mpfr_mul_d(x, x, t, MPFR_RNDN);  // exact at 300 bits
      mpfr_add_d(x, x, o[a], MPFR_RNDN);
      // The entry faces on the side the ray comes from, rounded so that the exact point
      // o + t d is inside the closed box by less than one ulp on every axis.
      if (d[a] > 0) {
        lo[a] = mpfr_get_d(x, MPFR_RNDD);
        hi[a] = lo[a] + pos(rng);
      } else {
        hi[a] = mpfr_get_d(x, MPFR_RNDU);
        lo[a] = hi[a] - pos(rng);
      }
    }
    const auto s = clipRayToBox(o, d, lo, hi, 0.0, 1e30);
    ASSERT_TRUE(s) << "trial " << trial;
    EXPECT_LE(s->t0, t);
    EXPECT_GE(s->t1, t);
  }
  mpfr_clear(x);
}

// A subnormal direction component (|d_a| < 2^-1024, whose reciprocal overflows) is not a
// zero one: the ray still crosses that slab's faces, at (face - o_a) / d_a, from an origin
// within a few d_a of the face. Before, 1 / d_a = inf made the slab all or nothing: a ray
// entering x >= 0 at t = 1 ((-1e-310, -5, 0.5) + t (1e-310, 1, 0)) missed the box, and one
// leaving it at t = 2 kept its whole span. Against the slab intervals in long double
// (64-bit significand, exponents far below double's: the quotients to 2^-63).
TEST(ClipRayTest, SubnormalDirectionComponentIsNotZero) {
  const glm::dvec3 lo(0.0, -1.0, -1.0), hi(1.0, 1.0, 1.0);
  auto enter = clipRayToBox({-1e-310, -5.0, 0.5}, {1e-310, 1.0, 0.0}, lo, hi, 0.0, 10.0);
  ASSERT_TRUE(enter);
  EXPECT_NEAR(enter->t0, 4.0, 1e-14);
  EXPECT_NEAR(enter->t1, 6.0, 1e-14);
  EXPECT_FALSE(clipRayToBox({2e-310, -5.0, 0.5}, {-1e-310, 1.0, 0.0}, lo, hi, 0.0, 10.0));

  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int spans = 0, empty = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double sign = u(rng) < 0.5 ? -1.0 : 1.0;
    glm::dvec3 d(sign * std::pow(10.0, -323.0 + 15.0 * u(rng)), 1.0, 0.1 * (u(rng) - 0.5));
    // Where the ray crosses x = 0: entering (d.x > 0) or leaving (d.x < 0) the box.
    const double tx = 10.0 * u(rng);
    const glm::dvec3 o(-d.x * tx, -5.0 + (u(rng) - 0.5), u(rng) - 0.5);
    if (o.x == 0.0 || d.x == 0.0) continue;  // rounded away: nothing to cross
    long double t0 = 0.0L, t1 = 10.0L;
    test::slabSpan(o, d, lo, hi, t0, t1);  // d.z = 0: inside the z slab by construction
    const auto s = clipRayToBox(o, d, lo, hi, 0.0, 10.0);
    const long double margin = 1e-12L * (std::abs(t0) + std::abs(t1));
    if (t0 > t1 + margin) {
      EXPECT_FALSE(s) << "trial " << trial << " exact span empty";
      ++empty;
    } else if (t0 < t1 - margin) {
      ASSERT_TRUE(s) << "trial " << trial << " exact span [" << (double)t0 << ", " << (double)t1
                     << "]";
      // Contains the exact span, widened by no more than the rounding allowance.
      EXPECT_LE(s->t0, t0 * (1.0L + 0x1p-60L)) << "trial " << trial;
      EXPECT_GE(s->t1, t1 * (1.0L - 0x1p-60L)) << "trial " << trial;
      EXPECT_GE(s->t0, t0 * (1.0L - 1e-14L)) << "trial " << trial;
      EXPECT_LE(s->t1, t1 * (1.0L + 1e-14L)) << "trial " << trial;
      ++spans;
    }
  }
  EXPECT_GT(spans, 3000);
  EXPECT_GT(empty, 3000);
}

}  // namespace
}  // namespace algray
