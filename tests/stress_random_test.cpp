// Numerical-stability stress suite, part 3: random surfaces. Products of random quadrics
// and planes (some factors cubed), under random affine transforms, in a clip sphere or
// box, with random cell depths, against brute force: every sign change of the product of
// the factors (each evaluated in long double in object space) along the ray, found by
// sampling and bisection, the first one inside the clip region. And random quadrics of
// every kind against their closed forms in long double, with rays leaving each hit. No
// expected value comes from the library.
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
    return a[0] + a[1] * x + a[2] * y + a[3] * z + a[4] * x * x + a[5] * y * y + a[6] * z * z +
           a[7] * x * y + a[8] * y * z + a[9] * z * x;
  }
  void gradient(long double x, long double y, long double z, long double g[3]) const {
    g[0] = a[1] + 2 * a[4] * x + a[7] * y + a[9] * z;
    g[1] = a[2] + 2 * a[5] * y + a[7] * x + a[8] * z;
    g[2] = a[3] + 2 * a[6] * z + a[8] * y + a[9] * x;
  }
  Polynomial polynomial() const {
    auto c = [&](int i) { return Polynomial(static_cast<double>(a[i])); };
    return c(0) + c(1) * X() + c(2) * Y() + c(3) * Z() + c(4) * X() * X() + c(5) * Y() * Y() +
           c(6) * Z() * Z() + c(7) * X() * Y() + c(8) * Y() * Z() + c(9) * Z() * X();
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
      const glm::dvec3 o(3 * u(rng), 3 * u(rng), 3 * u(rng)),
          target(0.7 * u(rng), 0.7 * u(rng), 0.7 * u(rng));
      const glm::dvec3 d = target - o;
      auto object = [&](long double t, long double p[3]) {
        const long double w[3] = {o.x + t * d.x - b.x, o.y + t * d.y - b.y, o.z + t * d.z - b.z};
        for (int i = 0; i < 3; ++i) p[i] = ai[0][i] * w[0] + ai[1][i] * w[1] + ai[2][i] * w[2];
      };
      auto value = [&](long double t) {
        long double p[3], v = 1;
        object(t, p);
        for (int k = 0; k < factors; ++k)
          v *= power[k] == 1 ? qs[k](p[0], p[1], p[2]) : std::pow(qs[k](p[0], p[1], p[2]), 3);
        return v;
      };
      auto inClip = [&](long double t) {
        long double p[3];
        object(t, p);
        if (box)
          return p[0] >= boxLo.x && p[0] <= boxHi.x && p[1] >= boxLo.y && p[1] <= boxHi.y &&
                 p[2] >= boxLo.z && p[2] <= boxHi.z;
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
        ADD_FAILURE() << "surface " << surface << " ray " << r
                      << " missed t = " << static_cast<double>(ref)
                      << " (the ray enters the clip region at " << static_cast<double>(entry)
                      << ")";
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

// Random quadrics of every kind (ellipsoids, hyperboloids and cones, cylinders and
// paraboloids, plane pairs), rotated, in a random clip sphere or box, through the quadric
// path and the generic walk: the first hit against the long-double closed form, and a ray
// leaving each hit in a random direction (origin = the double hit point, with its error
// bound) against the other root of its own quadratic (the first is 0: never a self-hit).
// Rays near a tangency or with a root near the clip boundary are skipped (either answer
// is right there).
TEST(StressRandom, QuadricsAgainstClosedForms) {
  using LD = long double;
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> u(-1, 1);
  int checked = 0, leaving = 0;
  for (int surface = 0; surface < 200; ++surface) {
    // f = x^T A x + b.x + c, A = R diag(l) R^T.
    double l[3] = {u(rng), u(rng), u(rng)};
    const int kind = static_cast<int>(rng() % 6);
    if (kind == 0)
      for (double& v : l) v = std::abs(v) + 0.2;  // ellipsoid
    if (kind == 1) l[2] = 0;                      // cylinder or paraboloid
    if (kind == 2) {                              // hyperboloid or cone
      l[0] = std::abs(l[0]) + 0.2;
      l[1] = std::abs(l[1]) + 0.2;
      l[2] = -std::abs(l[2]) - 0.2;
    }
    if (kind == 3) l[1] = l[2] = 0;  // plane pair or parabolic cylinder
    const glm::dvec3 r0 = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const glm::dvec3 r1(u(rng), u(rng), u(rng));
    const glm::dvec3 e1 = glm::normalize(r1 - glm::dot(r0, r1) * r0),
                     rot[3] = {r0, e1, glm::cross(r0, e1)};
    double a[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        a[i][j] = rot[0][i] * l[0] * rot[0][j] + rot[1][i] * l[1] * rot[1][j] +
                  rot[2][i] * l[2] * rot[2][j];
    double b[3] = {0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)}, c = 0.3 * u(rng);
    if (kind == 5) b[0] = b[1] = b[2] = c = 0;  // a cone through the origin
    const Polynomial vars[3] = {X(), Y(), Z()};
    Polynomial f(c);
    for (int i = 0; i < 3; ++i) {
      f = f + Polynomial(b[i]) * vars[i];
      for (int j = 0; j < 3; ++j) f = f + Polynomial(a[i][j]) * vars[i] * vars[j];
    }
    if (f.degree() < 2) continue;
    const bool box = rng() % 2;
    const glm::dvec3 centre(0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng));
    const double radius = 0.8 + 0.4 * std::abs(u(rng));
    const glm::dvec3 lo = centre - glm::dvec3(radius),
                     hi = centre + glm::dvec3(0.8 * radius, radius, 1.1 * radius);
    auto inClip = [&](const LD p[3]) {
      if (box)
        return p[0] >= lo.x && p[0] <= hi.x && p[1] >= lo.y && p[1] <= hi.y && p[2] >= lo.z &&
               p[2] <= hi.z;
      const LD dx = p[0] - centre.x, dy = p[1] - centre.y, dz = p[2] - centre.z;
      return dx * dx + dy * dy + dz * dz <= static_cast<LD>(radius) * radius;
    };
    auto nearBoundary = [&](const LD p[3]) {  // within 1e-7 of the clip boundary
      for (int axis = 0; axis < 3; ++axis)
        for (LD step : {-1e-7L, 1e-7L}) {
          LD q[3] = {p[0], p[1], p[2]};
          q[axis] += step;
          if (inClip(q) != inClip(p)) return true;
        }
      return false;
    };
    // g(t) = qa t^2 + qb t + qc along (o, d), in long double.
    auto quadratic = [&](const glm::dvec3& o, const glm::dvec3& d, LD& qa, LD& qb, LD& qc) {
      const LD O[3] = {o.x, o.y, o.z}, D[3] = {d.x, d.y, d.z};
      qa = 0, qb = 0, qc = c;
      for (int i = 0; i < 3; ++i) {
        qb += b[i] * D[i];
        qc += b[i] * O[i];
        for (int j = 0; j < 3; ++j) {
          qa += a[i][j] * D[i] * D[j];
          qb += a[i][j] * (O[i] * D[j] + D[i] * O[j]);
          qc += a[i][j] * O[i] * O[j];
        }
      }
    };
    for (int path = 0; path < 2; ++path) {
      SurfaceDesc desc;
      desc.polynomial = f;
      if (box)
        desc.clip = ClipBox{lo, hi};
      else
        desc.clip = ClipSphere{centre, radius};
      desc.options.quadricPath = path == 0;
      OneSurface s(desc);
      std::mt19937_64 rays(surface);  // the same rays for both paths
      for (int r = 0; r < 48; ++r) {
        std::uniform_real_distribution<double> v(-1, 1);
        const glm::dvec3 o(3 * v(rays), 3 * v(rays), 3 * v(rays));
        glm::dvec3 d = centre + 0.7 * glm::dvec3(v(rays), v(rays), v(rays)) - o;
        if (r % 4 == 0) d = glm::normalize(d);
        const glm::dvec3 e = glm::normalize(glm::dvec3(v(rays), v(rays), v(rays)));
        LD qa, qb, qc;
        quadratic(o, d, qa, qb, qc);
        std::vector<LD> roots;
        if (qa == 0) {
          if (qb != 0) roots.push_back(-qc / qb);
        } else if (const LD disc = qb * qb - 4 * qa * qc; disc >= 0) {
          const LD q = -(qb + std::copysign(std::sqrt(disc), qb)) / 2;
          LD t0 = q / qa, t1 = q != 0 ? qc / q : t0;
          if (t0 > t1) std::swap(t0, t1);
          roots = {t0, t1};
        }
        bool ambiguous =
            roots.size() == 2 && std::abs(static_cast<double>(roots[1] - roots[0])) < 1e-6;
        LD ref = -1;
        for (const LD t : roots) {
          if (t <= 1e-9L) continue;
          const LD p[3] = {o.x + t * d.x, o.y + t * d.y, o.z + t * d.z};
          ambiguous = ambiguous || nearBoundary(p);
          if (inClip(p)) {
            ref = t;
            break;
          }
        }
        const auto hit = s.intersect(rayD(o, d), "quadric");
        if (ambiguous) continue;
        ++checked;
        ASSERT_EQ(hit.has_value(), ref >= 0)
            << "surface " << surface << " kind " << kind << " path " << path << " ray " << r;
        if (!hit) continue;
        EXPECT_NEAR(hit->t, static_cast<double>(ref), 1e-9 * (1 + static_cast<double>(ref)))
            << "surface " << surface;
        // Leaving the hit: roots 0 (the origin, on the surface) and -qb/qa.
        const glm::dvec3 p = o + hit->t * d;
        RayD leave = rayD(p, e);
        leave.orgError = gamma(3) * (glm::length(o) + hit->t * glm::length(d));
        quadratic(p, e, qa, qb, qc);
        const LD other = qa != 0 ? -qb / qa : -1;
        const LD q[3] = {p.x + other * e.x, p.y + other * e.y, p.z + other * e.z};
        const auto next = s.intersect(leave, "leaving");
        ++leaving;
        if (next) {
          EXPECT_GT(next->t, 1e-6)
              << "self-hit, surface " << surface << " kind " << kind << " path " << path;
        }
        if (other > 1e-6L && !nearBoundary(q) && std::abs(static_cast<double>(qa)) > 1e-6) {
          ASSERT_EQ(next.has_value(), inClip(q))
              << "surface " << surface << " kind " << kind << " path " << path;
          if (next) {
            EXPECT_NEAR(next->t, static_cast<double>(other),
                        1e-8 * (1 + static_cast<double>(other)));
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 15000);
  EXPECT_GT(leaving, 4000);
}

// Random multiple surfaces, f = h^k q with h a plane, a quadric or their product, k = 2 or
// 3 and q > 0 in the clip ball: grad f vanishes on h = 0, so the hit's normal comes from
// beside it (hit_normal.cpp), at a distance delta where grad f clears its rounding noise.
// Against grad h in long double at the hit point the angle is then about delta times the
// normal's turning rate |hess h| / |grad h|, which grows without bound towards h's singular
// curve (P = Q = 0 of h = P Q). Asserted: angle < floor + delta |hess h| / |grad h| with
// (floor, delta) = (2e-5, 2e-5) for k = 2 and (1e-4, 2e-2) for k = 3 (a triple root's
// gradient clears its noise only ~1e-4 to 1e-2 clip radii away), and the orientation
// (facing the ray for k = 2, as grad h for k = 3) where that bound is below 0.5 radians.
// Set from 40 seeds of this generator (session 39: worst angle * |grad h| / |hess h| where
// the rate exceeds 1e-2, 7.6e-6 for k = 2 and 8.8e-3 for k = 3; the angle elsewhere at most
// 2.5e-6 and 3.7e-5) and checked on 40 others: at most 0.15 and 0.42 of the bound, every
// orientation right where the bound is below 0.5 (118097 triple hits); the 23 triple hits
// of the 80 seeds with the wrong orientation all have bounds above 3.5 radians, |grad h| <
// 0.03. (This test's thresholds before session 39 were fixed constants that held on its
// own seed only: on three other seeds up to 2.6e-4 radians for k = 2 against 2e-5, near
// the singular curve.) Before hit_normal.cpp most of these normals were beyond these
// angles and a third had the wrong orientation (on random cubics h of a scratch campaign:
// 70 % and 34 % of 16321 hits).
TEST(StressRandom, MultipleSurfacesGetTheirOwnNormal) {
  std::mt19937_64 rng(3502);
  std::uniform_real_distribution<double> u(-1, 1);
  using LD = long double;
  int hits = 0;
  double worst[2] = {0, 0};
  for (int surface = 0; surface < 120; ++surface) {
    const int kind = surface % 3;  // plane, quadric, plane * quadric
    const int k = 2 + (surface / 3) % 2;
    Quadric plane{}, quadric{};
    for (int i = 0; i < 4; ++i) plane.a[i] = u(rng);
    for (int i = 0; i < 10; ++i) quadric.a[i] = u(rng);
    plane.a[0] *= 0.5;
    quadric.a[0] *= 0.3;
    const Polynomial h = kind == 0   ? plane.polynomial()
                         : kind == 1 ? quadric.polynomial()
                                     : plane.polynomial() * quadric.polynomial();
    const double c = 0.1 * u(rng);
    Polynomial f = h * h;
    if (k == 3) f = f * h;
    f = f * (Polynomial(1.0) + 0.2 * (X() * X() + Y() * Y() + Z() * Z()) + c * X());
    SurfaceDesc desc;
    desc.polynomial = f;
    desc.clip = ClipSphere{{0, 0, 0}, 1.0};
    OneSurface s(desc);
    for (int r = 0; r < 100; ++r) {
      const glm::dvec3 o = 3.0 * glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
      const glm::dvec3 d = 0.9 * glm::dvec3(u(rng), u(rng), u(rng)) - o;
      const auto hit = s.intersect(rayD(o, d), "multiple surface");
      if (!hit) continue;
      const LD p[3] = {o.x + static_cast<LD>(hit->t) * d.x, o.y + static_cast<LD>(hit->t) * d.y,
                       o.z + static_cast<LD>(hit->t) * d.z};
      LD g[3];
      if (kind == 0) {
        plane.gradient(p[0], p[1], p[2], g);
      } else if (kind == 1) {
        quadric.gradient(p[0], p[1], p[2], g);
      } else {  // grad (P Q) = Q grad P + P grad Q
        LD gp[3], gq[3];
        plane.gradient(p[0], p[1], p[2], gp);
        quadric.gradient(p[0], p[1], p[2], gq);
        const LD pv = plane(p[0], p[1], p[2]), qv = quadric(p[0], p[1], p[2]);
        for (int i = 0; i < 3; ++i) g[i] = qv * gp[i] + pv * gq[i];
      }
      const glm::dvec3 gh(static_cast<double>(g[0]), static_cast<double>(g[1]),
                          static_cast<double>(g[2]));
      if (!(glm::length(gh) > 1e-3)) continue;
      // hess h: the quadric's constant one, or for h = P Q, P hess Q + grad P grad Q^T +
      // grad Q grad P^T (P is linear); |hess h| its Frobenius norm.
      LD hess[3][3] = {};
      if (kind != 0) {
        const long double* a = quadric.a;
        const LD hq[3][3] = {
            {2 * a[4], a[7], a[9]}, {a[7], 2 * a[5], a[8]}, {a[9], a[8], 2 * a[6]}};
        LD gp[3] = {}, gq[3] = {}, pv = 1;
        if (kind == 2) {
          plane.gradient(p[0], p[1], p[2], gp);
          quadric.gradient(p[0], p[1], p[2], gq);
          pv = plane(p[0], p[1], p[2]);
        }
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) hess[i][j] = pv * hq[i][j] + gp[i] * gq[j] + gq[i] * gp[j];
      }
      LD hess2 = 0;
      for (const auto& row : hess)
        for (const LD v : row) hess2 += v * v;
      const double rate = static_cast<double>(std::sqrt(hess2)) / glm::length(gh);
      ++hits;
      const double cosine = glm::dot(glm::normalize(hit->Ng), glm::normalize(gh));
      const double angle = std::acos(std::min(1.0, std::abs(cosine)));
      const double bound = k == 2 ? 2e-5 + 2e-5 * rate : 1e-4 + 2e-2 * rate;
      worst[k - 2] = std::max(worst[k - 2], angle / bound);
      EXPECT_LT(angle, bound) << "surface " << surface << " ray " << r << " rate " << rate;
      if (bound >= 0.5) continue;
      if (k == 2)
        EXPECT_LT(glm::dot(hit->Ng, d), 0.0) << "surface " << surface << " ray " << r;
      else
        EXPECT_GT(cosine, 0.0) << "surface " << surface << " ray " << r;
    }
  }
  std::printf("multiple surfaces: %d hits, worst angle / bound %.3g (k = 2), %.3g (k = 3)\n", hits,
              worst[0], worst[1]);
  EXPECT_GT(hits, 4000);
}

}  // namespace
}  // namespace algray::test
