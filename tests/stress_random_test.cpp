// Numerical-stability stress suite, part 3: random surfaces against brute force. Products
// of random quadrics and planes (some factors cubed), under random affine transforms, in a
// clip sphere or box, with random cell depths; rays from random origins outside towards
// random points inside. Reference: every sign change of the product of the factors (each
// evaluated in long double in object space) along the ray, found by sampling and
// bisection, the first one inside the clip region. No expected value comes from the
// library.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <glm/matrix.hpp>

#include "support/stress.h"

namespace algray::test {
namespace {

struct Quadric {  // c + b.x + x^T A x, in the monomials 1 x y z xx yy zz xy yz zx
  long double a[10];
  long double operator()(long double x, long double y, long double z) const {
    return a[0] + a[1] * x + a[2] * y + a[3] * z + a[4] * x * x + a[5] * y * y + a[6] * z * z + a[7] * x * y +
           a[8] * y * z + a[9] * z * x;
  }
  Polynomial polynomial() const {
    auto c = [&](int i) { return Polynomial(static_cast<double>(a[i])); };
    return c(0) + c(1) * X() + c(2) * Y() + c(3) * Z() + c(4) * X() * X() + c(5) * Y() * Y() + c(6) * Z() * Z() +
           c(7) * X() * Y() + c(8) * Y() * Z() + c(9) * Z() * X();
  }
};

// No ray with a reference root may miss. Session 6 found, on this seed, a ray missed
// behind a far origin taken for a surface point (f's expansion there was all noise), a
// root reported at the clip region's far end and dropped, and one within the noise
// region of a cubed factor at the span's start (the solver's interval was open there).
// Multiple roots are located only to their noise region (cubed factors of a degree-16
// product: up to a few 1e-2 here), so positions are checked on the rays whose factors
// are all simple.
TEST(StressRandom, ProductsOfQuadricsAgainstBruteForce) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-1, 1);
  int rays = 0, withRoot = 0, misses = 0;
  for (int surface = 0; surface < 25; ++surface) {
    const int factors = 1 + static_cast<int>(rng() % 4);
    std::vector<Quadric> qs(factors);
    std::vector<int> power(factors, 1);
    Polynomial f(1.0);
    for (int k = 0; k < factors; ++k) {
      const bool plane = rng() % 3 == 0;
      for (int i = 0; i < 10; ++i) qs[k].a[i] = (plane && i >= 4) ? 0.0 : u(rng);
      qs[k].a[0] = u(rng) * 0.5;
      f = f * qs[k].polynomial();
      if (rng() % 3 == 0) {
        f = f * qs[k].polynomial() * qs[k].polynomial();
        power[k] = 3;
      }
    }
    SurfaceDesc desc;
    desc.polynomial = f;
    const bool box = rng() % 2;
    const glm::dvec3 boxLo(-1, -0.8, -0.6), boxHi(1, 0.9, 0.7), centre(0.1, 0, -0.1);
    if (box)
      desc.clip = ClipBox{boxLo, boxHi};
    else
      desc.clip = ClipSphere{centre, 1.0};
    desc.options.cellDepth = static_cast<int>(rng() % 4) - 1;  // automatic, 0, 1, 2
    glm::dmat3 a(1.0);
    glm::dvec3 b(0.0);
    if (rng() % 2) {
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) a[c][r] = (c == r ? 1.0 : 0.0) + 0.4 * u(rng);
      b = glm::dvec3(0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng));
    }
    desc.transform = glm::dmat4(a);
    desc.transform[3] = glm::dvec4(b, 1.0);
    const glm::dmat3 ai = glm::inverse(a);
    bool simple = true;
    for (int p : power) simple = simple && p == 1;
    OneSurface s(desc);
    for (int r = 0; r < 400; ++r, ++rays) {
      const glm::dvec3 o(3 * u(rng), 3 * u(rng), 3 * u(rng)), target(0.7 * u(rng), 0.7 * u(rng), 0.7 * u(rng));
      const glm::dvec3 d = target - o;
      auto object = [&](long double t, long double p[3]) {
        const long double w[3] = {o.x + t * d.x - b.x, o.y + t * d.y - b.y, o.z + t * d.z - b.z};
        for (int i = 0; i < 3; ++i) p[i] = ai[0][i] * w[0] + ai[1][i] * w[1] + ai[2][i] * w[2];
      };
      auto value = [&](long double t) {
        long double p[3], v = 1;
        object(t, p);
        for (int k = 0; k < factors; ++k) v *= power[k] == 1 ? qs[k](p[0], p[1], p[2]) : std::pow(qs[k](p[0], p[1], p[2]), 3);
        return v;
      };
      auto inClip = [&](long double t) {
        long double p[3];
        object(t, p);
        if (box) return p[0] >= boxLo.x && p[0] <= boxHi.x && p[1] >= boxLo.y && p[1] <= boxHi.y && p[2] >= boxLo.z && p[2] <= boxHi.z;
        const long double dx = p[0] - centre.x, dy = p[1], dz = p[2] - centre.z;
        return dx * dx + dy * dy + dz * dz <= 1.0L;
      };
      // The first sign change inside the clip region, and where the ray enters it.
      constexpr int kSamples = 8000;
      constexpr long double kLength = 6.0L;
      long double ref = -1, entry = -1, prev = value(0);
      for (int k = 1; k <= kSamples && ref < 0; ++k) {
        const long double t = kLength * k / kSamples, v = value(t);
        if (entry < 0 && inClip(t)) entry = t;
        if ((prev < 0) != (v < 0)) {
          long double lo = kLength * (k - 1) / kSamples, hi = t, flo = prev;
          for (int it = 0; it < 80; ++it) {
            const long double m = (lo + hi) / 2, fm = value(m);
            if ((fm < 0) == (flo < 0)) {
              lo = m;
              flo = fm;
            } else {
              hi = m;
            }
          }
          if (inClip(lo)) ref = lo;
        }
        prev = v;
      }
      const auto hit = s.intersect(rayD(o, d), "random product");
      if (ref < 0) continue;
      ++withRoot;
      if (!hit) {
        ++misses;
        ADD_FAILURE() << "surface " << surface << " ray " << r << " missed t = " << static_cast<double>(ref)
                      << " (the ray enters the clip region at " << static_cast<double>(entry) << ")";
        continue;
      }
      // A hit before the reference is a root the sampling stepped over (two close ones,
      // or a tangent); after it, it is an error unless the factors are multiple.
      if (simple) {
        EXPECT_LT(hit->t, static_cast<double>(ref) + 1e-9) << "surface " << surface << " ray " << r;
      }
    }
  }
  EXPECT_GT(withRoot, 5000);
  EXPECT_EQ(misses, 0) << "of " << withRoot << " rays with a root";
}

}  // namespace
}  // namespace algray::test
