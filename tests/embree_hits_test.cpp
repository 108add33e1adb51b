// Hit records of algray surfaces through Embree (rtcIntersect1 / rtcOccluded1), against
// closed forms and brute-force references computed independently of the library.
#include "../plugin/embree/double_channel.h"
#include "../plugin/embree/quadric_path.h"
#include "embree_test_util.h"
#include "support/scales.h"

#include <gtest/gtest.h>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdio>
#include <optional>
#include <random>
#include <string>

namespace algray::test {
namespace {

// Torus (x^2+y^2+z^2+R^2-r^2)^2 - 4R^2(x^2+y^2) evaluated directly (no Polynomial).
long double torusValue(long double x, long double y, long double z, long double R, long double r) {
  const long double s = x * x + y * y + z * z + R * R - r * r;
  return s * s - 4 * R * R * (x * x + y * y);
}
// Brute force: dense sign scan of the torus function along the ray inside |p| < clip,
// then bisection. Independent of the library's restriction and solver.
std::optional<long double> torusRoot(glm::dvec3 o, glm::dvec3 d, double R, double r, double clip) {
  const double dd = glm::dot(d, d);
  const double tc = -glm::dot(o, d) / dd;
  const double h2 = clip * clip - glm::dot(o + tc * d, o + tc * d);
  if (h2 <= 0) return std::nullopt;
  const double dt = std::sqrt(h2 / dd);
  const long double t0 = std::max(0.0, tc - dt), t1 = tc + dt;
  auto g = [&](long double t) {
    return torusValue(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z, R, r);
  };
  const int n = 20000;
  long double prev = g(t0);
  for (int i = 1; i <= n; ++i) {
    long double a = t0 + (t1 - t0) * (i - 1) / n, b = t0 + (t1 - t0) * i / n;
    const long double gb = g(b);
    if ((prev < 0) != (gb < 0)) {
      for (int k = 0; k < 200; ++k) {
        const long double m = 0.5L * (a + b);
        if ((g(m) < 0) == (prev < 0))
          a = m;
        else
          b = m;
      }
      return 0.5L * (a + b);
    }
    prev = gb;
  }
  return std::nullopt;
}

using EmbreeHits = EmbreeFixture;

// The hits of a host stepping along a double ray: tnear = the previous HitD.t, up to 8.
std::vector<double> stepThrough(RTCScene scene, RayD ray) {
  std::vector<double> hits;
  for (int step = 0; step < 8; ++step) {
    const HitD hit = intersectD(scene, ray);
    if (!hit.hit) break;
    hits.push_back(hit.t);
    ray.tnear = hit.t;
  }
  return hits;
}

// A host stepping along a double ray (tnear = the previous HitD.t) meets each root once, in
// order: the roots of the torus along the ray, from a dense long-double sign scan and
// bisection, against the steps. The double nearest a root may lie below it, and a search
// from just before tnear found the same root again one double on (on 1152 of 14313 such
// rays): a root within f's rounding noise of tnear counts as at tnear (README).
TEST_F(EmbreeHits, DoubleRaysSteppingPastAHitMeetEachRootOnce) {
  const double R = 1.0, r = 0.4, clip = 1.5;
  SurfaceDesc desc;
  desc.polynomial = torusPolynomial(R, r);
  desc.clip = ClipSphere{glm::dvec3(0.0), clip};
  SurfaceScene scene(device, desc);
  std::mt19937_64 gen(44);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  auto random3 = [&] { return glm::dvec3(uniform(gen), uniform(gen), uniform(gen)); };
  int raysWithHits = 0, repeats = 0, strays = 0, extra = 0;
  for (int k = 0; k < 3000; ++k) {
    const glm::dvec3 o = 4.5 * glm::normalize(random3());
    const glm::dvec3 d = glm::normalize(0.9 * random3() - o);
    // ---- Reference: every sign change of the torus function in the clip sphere ------
    std::vector<long double> roots;
    const double tc = -glm::dot(o, d), h2 = clip * clip - glm::dot(o + tc * d, o + tc * d);
    if (h2 > 0) {
      const long double t0 = tc - std::sqrt(h2), t1 = tc + std::sqrt(h2);
      auto g = [&](long double t) {
        return torusValue(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z, R, r);
      };
      const int n = 4000;
      long double a = t0, ga = g(t0);
      for (int i = 1; i <= n; ++i) {
        long double b = t0 + (t1 - t0) * i / n, gb = g(b);
        if ((ga < 0) != (gb < 0)) {
          long double lo = a, hi = b;
          for (int it = 0; it < 100; ++it) {
            const long double m = 0.5L * (lo + hi);
            ((g(m) < 0) == (ga < 0) ? lo : hi) = m;
          }
          roots.push_back(0.5L * (lo + hi));
        }
        a = b;
        ga = gb;
      }
    }
    // ---- Steps: each hit a root of the list, past the previous one ----------------------
    const std::vector<double> hits = stepThrough(scene, unboundedRay(o, d));
    raysWithHits += !hits.empty();
    for (size_t i = 0; i < hits.size(); ++i) {
      if (i > 0 && hits[i] - hits[i - 1] < 1e-9) ++repeats;
      bool near = false;
      for (long double root : roots) near = near || std::abs(hits[i] - root) < 1e-9L;
      strays += !near;
    }
    extra += hits.size() > roots.size();
  }
  EXPECT_GT(raysWithHits, 1500);
  EXPECT_EQ(repeats, 0);
  EXPECT_EQ(strays, 0);
  EXPECT_EQ(extra, 0);
}

// A leaving double ray asked again with tnear one double before its hit (README: a root whose
// noise band holds tnear counts as at tnear and is not reported) gets no hit: the quadric
// path's linear rest after the self-root division (linearFirst) must drop a root within
// noise of its span's start, as firstRoot does. From points of the unit sphere inwards the
// line meets the sphere at the origin and at the far root (sphereRoot's closed form in long
// double), which the first query must find.
TEST_F(EmbreeHits, LeavingRaysAskedJustBeforeTheirHitDoNotGetItAgain) {
  const SurfaceScene scene(device, sphereDesc(1.0, 1.25));
  std::mt19937_64 gen(47);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  auto random3 = [&] { return glm::dvec3(uniform(gen), uniform(gen), uniform(gen)); };
  int again = 0;
  for (int k = 0; k < 2000; ++k) {
    const glm::dvec3 o = glm::normalize(random3());
    glm::dvec3 d = glm::normalize(random3());
    if (glm::dot(d, o) > -0.1) d = glm::normalize(d - 1.5 * o);  // inwards, not grazing
    // The far root lies at -2 o . d >= 0.2; the near one within rounding of 0.
    const long double far = *sphereRoot(o, d, 1.0L, 0.1L);
    const HitD first = intersectD(scene, unboundedRay(o, d));
    ASSERT_TRUE(first.hit) << "ray " << k;
    EXPECT_NEAR(first.t, static_cast<double>(far), 1e-12) << "ray " << k;
    RayD ray = unboundedRay(o, d);
    ray.tnear = std::nextafter(first.t, 0.0);
    const HitD next = intersectD(scene, ray);
    if (next.hit && again++ == 0)
      ADD_FAILURE() << "ray " << k << ": t " << next.t << " again after " << first.t;
  }
  EXPECT_EQ(again, 0);
}

// Dekker's TwoProduct (productError, without hardware FMA) gives the product's exact error,
// as std::fma does, over operands of every scale, signs and subnormal and huge ones included.
TEST(TwoProduct, ProductErrorIsTheExactError) {
  std::mt19937_64 gen(4401);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  std::uniform_int_distribution<int> exponent(-1074, 1023), sign(0, 1);
  int checked = 0;
  for (int k = 0; k < 200000; ++k) {
    auto draw = [&] {
      const double v = std::ldexp(mantissa(gen), exponent(gen) / (k % 3 == 0 ? 1 : 8));
      return sign(gen) ? -v : v;
    };
    const double a = draw(), b = draw(), prod = a * b;
    if (!std::isfinite(prod)) continue;
    const double exact = std::fma(a, b, -prod);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(productError(a, b, prod)),
              std::bit_cast<std::uint64_t>(exact))
        << std::hexfloat << a << " " << b;
    ++checked;
  }
  EXPECT_GT(checked, 150000);
  for (const double a : {0.0, -0.0, 3.0, -0x1p-1074})
    for (const double b : {0.0, -0.0, -5.0})
      EXPECT_EQ(std::bit_cast<std::uint64_t>(productError(a, b, a * b)),
                std::bit_cast<std::uint64_t>(std::fma(a, b, -(a * b))))
          << a << " " << b;
}

// Rays exactly through a singular or tangent point at the object-space origin (dyadic
// o = -s d: o + s d = 0 in exact arithmetic) find it at t = s: the node of the horn torus
// and of the ding-dong, the isolated point of x^4 + y^4 + z^4, and rays touching a sphere
// through 0 (times a plane far off, so that the generic path takes it). The re-centred
// expansion point was rounded off the line by ~u |o|, which g's bound does not cover where
// f's terms all vanish (restrictAbout, ray_roots.cpp): 5-8 % of such rays missed. (The float
// channel still misses the fourfold point on 6 of 200 rays in the default cells, whose
// corners meet there; without cells it finds all: not checked here, README.)
TEST_F(EmbreeHits, RaysThroughASingularPointAtTheOriginFindIt) {
  struct Case {
    const char* equation;
    bool tangent;      // d . (1, 2, 2) = 0: rays along the sphere's tangent plane at 0
    double tolerance;  // relative to s: the root's multiplicity (2 or 4) within rounding
    bool floatRays;    // the float channel checked too
  };
  const Case cases[] = {{"(x^2+y^2+z^2)^2-4*(x^2+y^2)", false, 1e-6, true},
                        {"x^2+y^2-(1-z)*z^2", false, 1e-6, true},
                        {"x^4+y^4+z^4", false, 1e-3, false},
                        {"(x^2+y^2+z^2-2*x-4*y-4*z)*(x+5)", true, 1e-6, true}};
  std::mt19937 gen(4444);
  std::uniform_int_distribution<int> component(-64, 64), along(24, 128);
  for (const Case& c : cases) {
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial(c.equation);
    desc.clip = ClipSphere{glm::dvec3(0.0), 2.5};
    SurfaceScene scene(device, desc);
    int missed = 0, rays = 0;
    while (rays < 200) {
      glm::dvec3 d(component(gen), component(gen), component(gen));
      if (c.tangent) d = glm::cross(d, glm::dvec3(1, 2, 2));
      d /= 64.0;
      if (glm::length(d) < 0.25 || glm::length(d) > 2.0) continue;
      const double s = along(gen) / 64.0;
      const glm::dvec3 o = -s * d;  // exact: a few bits each
      ++rays;
      // The span about the point (the horn torus and the ding-dong have other sheets
      // before it on most of these rays).
      const double tnear = s * (1 - 0x1p-8), tfar = s * (1 + 0x1p-8);
      const RTCRayHit rh = intersect1(
          scene,
          makeRay(glm::vec3(o), glm::vec3(d), static_cast<float>(tnear), static_cast<float>(tfar)));
      const HitD hit = intersectD(scene, RayD{o, d, tnear, tfar, 0});
      const bool doubleFound = hit.hit && std::abs(hit.t - s) <= c.tolerance * s;
      const bool floatFound =
          !c.floatRays || (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID &&
                           std::abs(rh.ray.tfar - s) <= std::max(c.tolerance, 1e-5) * s);
      missed += !doubleFound + !floatFound;
    }
    EXPECT_EQ(missed, 0) << c.equation;
  }
}

// Stepping past a hit skips only the root within f's noise of tnear, not a distinct one
// close by: two planes 1e-8 and 1e-6 apart (f between them far above its noise), and a
// torus seen from 1e9 radii (roots 3e6 ulps apart), every root in order against its closed
// form. (A first version of the rule skipped every root within 2^-30 of tnear: the second
// plane and three of the torus's four roots were lost.)
TEST_F(EmbreeHits, SteppingPastAHitKeepsACloseDistinctRoot) {
  struct Case {
    const char* equation;
    double clip;
    glm::dvec3 o, d;
    std::vector<double> roots;
  };
  const double far = 1e9;
  const Case cases[] = {
      {"x*(x-1e-8)*(x+5)", 2, {-5.5, 0.1, 0.2}, {1, 0, 0}, {5.5, 5.5 + 1e-8}},
      {"(x-0.3)*(x-0.3-1e-6)*(x+5)", 2, {-5.5, 0.1, 0.2}, {1, 0, 0}, {5.8, 5.8 + 1e-6}},
      {"(x^2+y^2+z^2+0.84)^2-4*(x^2+y^2)",
       1.6,
       {-far, 0, 0},
       {1, 0, 0},
       {far - 1.4, far - 0.6, far + 0.6, far + 1.4}},
  };
  for (const Case& c : cases) {
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial(c.equation);
    desc.clip = ClipSphere{glm::dvec3(0.0), c.clip};
    SurfaceScene scene(device, desc);
    const std::vector<double> hits = stepThrough(scene, unboundedRay(c.o, c.d));
    ASSERT_EQ(hits.size(), c.roots.size()) << c.equation;
    for (size_t i = 0; i < hits.size(); ++i)
      EXPECT_NEAR(hits[i], c.roots[i], 1e-10 * std::max(1.0, std::abs(c.roots[i])))
          << c.equation << " root " << i;
  }
}

TEST_F(EmbreeHits, SphereMatchesClosedForm) {
  SurfaceDesc desc = sphereDesc(1.0, 1.5);
  desc.options.uv = true;
  SurfaceGeometry sphere(device, desc);
  Scene scene(device);
  const unsigned id = scene.attach(sphere.geometry());
  scene.commit();
  std::uniform_real_distribution<float> u(-0.9f, 0.9f);
  int hits = 0;
  for (int i = 0; i < 500; ++i) {
    const glm::vec3 o = 4.0f * randomDir();
    const glm::vec3 target(u(rng), u(rng), u(rng));
    const glm::vec3 d = (target - o) * (0.5f + 0.01f * i);  // not unit length
    const RTCRayHit rh = intersect1(scene, makeRay(o, d));
    const auto ref = sphereRoot(asD(rh, true), asD(rh, false), 1.0L, 0.0L);
    ASSERT_EQ(ref.has_value(), rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) << i;
    if (!ref) continue;
    ++hits;
    EXPECT_EQ(rh.hit.geomID, id);
    EXPECT_EQ(rh.hit.instID[0], RTC_INVALID_GEOMETRY_ID);
    EXPECT_LT(rh.hit.primID, sphere.primitiveCount());
    // The double root rounded to float: within one float ulp of the reference.
    EXPECT_NEAR(rh.ray.tfar, (double)*ref, 2e-7 * (double)*ref) << i;
    const glm::dvec3 p = asD(rh, true) + (double)*ref * asD(rh, false);
    const glm::vec3 n = hitNormal(rh);
    EXPECT_NEAR(glm::dot(glm::dvec3(n), glm::normalize(p)), 1.0, 1e-6);
    // u, v: spherical angles of the hit point about the clip centre.
    const double phi = std::atan2(p.y, p.x);
    EXPECT_NEAR(rh.hit.u, (phi < 0 ? phi + 2 * M_PI : phi) / (2 * M_PI), 1e-5);
    EXPECT_NEAR(rh.hit.v, std::acos(p.z / glm::length(p)) / M_PI, 1e-5);
  }
  EXPECT_GT(hits, 300);
  EXPECT_EQ(sphere.callbackErrors(), 0u);
}

TEST_F(EmbreeHits, FromAnEquationString) {
  // The torus of radii R = 1, r = 0.4 from text with parameters; a ray down the z axis
  // through x = 1 hits the tube's top at z = 0.4: t = 3 - 0.4 from z = 3.
  SurfaceGeometry torus(device, "(x^2+y^2+z^2+R^2-r^2)^2 = 4*R^2*(x^2+y^2)",
                        ClipSphere{{0, 0, 0}, 1.6}, {.parameters = {{"R", 1.0}, {"r", 0.4}}});
  Scene scene(device);
  scene.attach(torus.geometry());
  scene.commit();
  const RTCRayHit rh = intersect1(scene, makeRay(glm::vec3(1, 0, 3), glm::vec3(0, 0, -1)));
  ASSERT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_NEAR(rh.ray.tfar, 2.6, 1e-6);
  EXPECT_NEAR(hitNormal(rh).z, 1.0, 1e-6);
  // A malformed equation reports its column.
  try {
    SurfaceGeometry bad(device, "x^2 + y^^2", ClipSphere{});
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.column(), 9);
  }
}

TEST_F(EmbreeHits, SphereInsideHitsFarSide) {
  const SurfaceScene scene(device, sphereDesc(2.0, 3.0));
  const RTCRayHit rh = intersect1(scene, makeRay({0.5f, 0, 0}, {1, 0, 0}));
  EXPECT_FLOAT_EQ(rh.ray.tfar, 1.5f);
  EXPECT_GT(rh.hit.Ng_x, 0.0f);  // gradient points outward, whichever side the ray came from
}

// A ray starting on the surface outside the clip ball (restrictQuadricRay skips the
// self-root rule there: the root at the origin lies outside the ray's span) finds the
// other root inside the ball, for a diagonal quadric (the cylinder) and a mixed one
// (the saddle z = xy). Both restrictions are 4.5 t (t - 1)-shaped: the hit is t = 1.
TEST_F(EmbreeHits, OriginOnTheSurfaceOutsideTheClipBall) {
  struct Line {
    const char* f;
    glm::vec3 o, d, normal;
  };
  for (const Line& l : {Line{"x^2 + y^2 - 1", {1, 0, 3}, {-2, 0, -3}, {-2, 0, 0}},
                        Line{"x*y - z", {2, 2, 4}, {-1.5f, -3, -4.5f}, {-1, 0.5f, -1}}}) {
    SCOPED_TRACE(l.f);
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial(l.f);
    desc.clip = ClipSphere{{0, 0, 0}, 2.0};
    SurfaceGeometry g(device, desc);
    Scene scene(device);
    scene.attach(g.geometry());
    scene.commit();
    const RTCRayHit rh = intersect1(scene, makeRay(l.o, l.d));
    ASSERT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
    EXPECT_NEAR(rh.ray.tfar, 1.0f, 1e-6f);
    const glm::vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    EXPECT_NEAR(glm::dot(glm::normalize(ng), glm::normalize(l.normal)), 1.0f, 1e-6f);
    EXPECT_FALSE(occluded1(scene, makeRay(l.o, l.d, 0.0f, 0.999f).ray));
    EXPECT_TRUE(occluded1(scene, makeRay(l.o, l.d, 0.0f, 1.001f).ray));
    EXPECT_EQ(g.callbackErrors(), 0u);
  }
  // Double rays from points of the cylinder at 2 (1 + eps) from the centre, on the clip
  // sphere and up to far beyond the rule's margin (2^-9), to the far side (-1, 0, 0) at
  // t = 1: never their own origin, always that hit.
  SurfaceDesc desc;
  desc.polynomial = parsePolynomial("x^2 + y^2 - 1");
  desc.clip = ClipSphere{{0, 0, 0}, 2.0};
  const SurfaceScene scene(device, desc);
  for (const double eps : {0.0, 1e-15, 1e-12, 1e-9, 0x1p-10, 0x1p-9, 0x1p-8, 1e-2}) {
    const double z = std::sqrt(4.0 * (1.0 + eps) * (1.0 + eps) - 1.0);
    const HitD hit = intersectD(scene, unboundedRay({1.0, 0.0, z}, {-2.0, 0.0, -z}));
    ASSERT_TRUE(hit.hit) << eps;
    EXPECT_NEAR(hit.t, 1.0, 1e-12) << eps;
  }
}

// The float u, v of a hit (surfaceUVFloat: polynomial atan, no libm) are the exact ones
// (long double atan2 of the azimuth and of the polar angle as atan2(rho, z), which near
// the poles is more accurate than surfaceUV's acos) rounded to float, or a neighbour:
// points in every octant, near the axes and poles, and of any magnitude.
TEST_F(EmbreeHits, FloatUvAreTheDoubleOnesToAnUlp) {
  SurfaceDesc desc = sphereDesc(1.0, 1.2);
  desc.clip = ClipSphere{{0.25, -0.5, 0.125}, 1.2};
  SurfaceGeometry g(device, desc);
  const auto& data = *static_cast<const SurfaceData*>(rtcGetGeometryUserData(g.geometry()));
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  auto ulps = [](float a, float b) {
    return std::abs(static_cast<long>(std::bit_cast<std::int32_t>(a)) -
                    std::bit_cast<std::int32_t>(b));
  };
  for (int i = 0; i < 200000; ++i) {
    glm::dvec3 r(uni(rng), uni(rng), uni(rng));
    if (i % 5 == 1) r[i % 3] *= 1e-9;            // near an axis plane
    if (i % 5 == 2) r.x *= 1e-12, r.y *= 1e-12;  // near a pole
    r *= std::pow(10.0, 8.0 * uni(rng));
    const glm::dvec3 point = data.centre + r;
    const glm::dvec3 rr = point - data.centre;  // as the kernel rounds it
    const long double pi = 3.141592653589793238462643383279503L;
    long double phi = std::atan2((long double)rr.y, (long double)rr.x);
    if (phi < 0) phi += 2 * pi;
    const long double rho = std::hypot((long double)rr.x, (long double)rr.y);
    const long double ud = std::min(phi / (2 * pi), (long double)std::nextafter(1.0, 0.0)),
                      vd = std::atan2(rho, (long double)rr.z) / pi;
    float uf, vf;
    surfaceUVFloat(data, point, uf, vf);
    EXPECT_LE(ulps(uf, static_cast<float>(ud)), 1) << i << " " << ud << " " << uf;
    EXPECT_LE(ulps(vf, static_cast<float>(vd)), 1) << i << " " << vd << " " << vf;
  }
}

TEST_F(EmbreeHits, TorusMatchesBruteForce) {
  const double R = 1.0, r = 0.4, clip = 1.6;
  SurfaceDesc desc;
  desc.polynomial = torusPolynomial(R, r);
  desc.clip = ClipSphere{{0, 0, 0}, clip};
  const SurfaceScene scene(device, desc);
  // Axis ray in closed form: the x axis crosses the tube at x = -(R+r), -(R-r), R-r, R+r.
  RTCRayHit rh = intersect1(scene, makeRay({-5, 0, 0}, {1, 0, 0}));
  EXPECT_FLOAT_EQ(rh.ray.tfar, (float)(5 - (R + r)));
  EXPECT_NEAR(hitNormal(rh).x, -1.0f, 1e-6f);
  rh = intersect1(scene, makeRay({0, 0, 0}, {1, 0, 0}));
  EXPECT_FLOAT_EQ(rh.ray.tfar, (float)(R - r));
  EXPECT_NEAR(hitNormal(rh).x, -1.0f, 1e-6f);  // inner equator: gradient points to the axis
  int hits = 0;
  std::uniform_real_distribution<float> u(-1.3f, 1.3f);
  for (int i = 0; i < 300; ++i) {
    const glm::vec3 o = 3.0f * randomDir();
    const glm::vec3 d = glm::vec3(u(rng), u(rng), 0.3f * u(rng)) - o;
    rh = intersect1(scene, makeRay(o, d));
    const auto ref = torusRoot(asD(rh, true), asD(rh, false), R, r, clip);
    ASSERT_EQ(ref.has_value(), rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) << i;
    if (!ref) continue;
    ++hits;
    EXPECT_NEAR(rh.ray.tfar, (double)*ref, 4e-7 * (double)*ref) << i;
    const glm::dvec3 p = asD(rh, true) + (double)*ref * asD(rh, false);
    EXPECT_GT(glm::dot(glm::dvec3(hitNormal(rh)), glm::normalize(torusGradient(p, R, r))), 1 - 1e-5)
        << i;
  }
  EXPECT_GT(hits, 100);
}

TEST_F(EmbreeHits, DoubleChannelIsAccurate) {
  SurfaceGeometry sphere(device, sphereDesc(1.0, 1.5));
  Scene scene(device);
  const unsigned id = scene.attach(sphere.geometry());
  scene.commit();
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  for (double dist : {3.0, 3000.0}) {
    for (int i = 0; i < 200; ++i) {
      RayD ray;
      ray.org = dist * glm::dvec3(randomDir());
      ray.dir = glm::dvec3(u(rng), u(rng), u(rng)) - ray.org;
      ray.tfar = std::numeric_limits<double>::infinity();
      RTCRayHit rh;
      const HitD hit = intersectD(scene, ray, &rh);
      const auto ref = sphereRoot(ray.org, ray.dir, 1.0L, 0.0L);
      ASSERT_EQ(ref.has_value(), hit.hit);
      if (!ref) continue;
      EXPECT_EQ(hit.geomID, id);
      EXPECT_EQ(rh.hit.geomID, id);
      // Hit point within 1e-12 of the clip radius (position error, not t error: t of a
      // far ray is only known to u |o| / |d|).
      const double err = glm::length(ray.dir) * std::abs(hit.t - (double)*ref);
      EXPECT_LT(err, 1e-12 + 16 * kUnitRoundoff * dist) << dist << " " << i;
      const glm::dvec3 p = ray.org + hit.t * ray.dir;
      EXPECT_NEAR(glm::dot(glm::normalize(hit.Ng), glm::normalize(p)), 1.0, 1e-12);
    }
  }
}

TEST_F(EmbreeHits, SurfaceTransformMovesHitsAndNormals) {
  // Unit sphere scaled by (2, 1, 1) and moved by (0, 0, 5): the ellipsoid
  // (x/2)^2 + y^2 + (z-5)^2 = 1. Ng = A^-T grad f_object, proportional to
  // (x/4, y, z-5) at the hit.
  SurfaceDesc desc = sphereDesc(1.0, 1.2);
  desc.transform = glm::dmat4(1.0);
  desc.transform[0][0] = 2.0;
  desc.transform[3] = glm::dvec4(0, 0, 5, 1);
  const SurfaceScene scene(device, desc);
  RTCRayHit rh = intersect1(scene, makeRay({-10, 0, 5}, {1, 0, 0}));
  EXPECT_FLOAT_EQ(rh.ray.tfar, 8.0f);
  EXPECT_NEAR(hitNormal(rh).x, -1.0f, 1e-6f);
  const glm::vec3 o(-3, 0.2f, 5.3f), d(1, 0.05f, -0.02f);
  rh = intersect1(scene, makeRay(o, d));
  ASSERT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  // Reference: the object-space ray against the unit sphere.
  const glm::dvec3 oo(o.x / 2.0, o.y, o.z - 5.0), od(d.x / 2.0, d.y, d.z);
  const auto ref = sphereRoot(oo, od, 1.0L, 0.0L);
  ASSERT_TRUE(ref);
  EXPECT_NEAR(rh.ray.tfar, (double)*ref, 1e-6);
  const glm::dvec3 p = glm::dvec3(o) + (double)*ref * glm::dvec3(d);
  const glm::dvec3 n = glm::normalize(glm::dvec3(p.x / 4, p.y, p.z - 5));
  EXPECT_GT(glm::dot(glm::dvec3(hitNormal(rh)), n), 1 - 1e-6);
}

// An object placed far from the world origin (or tiny and far): a double ray from a point
// inside it a few percent of its radius off the surface has no root at its origin, and
// its first hit is the closed form's. The bound on the map's rounding once scaled with
// |o| + |b| instead of |o - b|: such origins were taken to lie on the surface, and the
// self-root rule's division by s lost the hit or moved it to where |f| was 0.16 of f's
// scale. Quadric path (the sphere) and generic walk (the sphere times a far plane).
TEST_F(EmbreeHits, SelfRootRuleOfFarTranslatedObjects) {
  struct Case {
    double scale, shift, z0;  // world = scale * object + (shift, 0, 0); origin at object (0, 0, z0)
  };
  for (const Case& k : {Case{1e-8, 6e5, 0.85}, Case{1.0, 1e12, 0.999}, Case{1e-3, 1e6, 0.99}}) {
    for (const bool quadric : {true, false}) {
      SurfaceDesc desc = sphereDesc(1.0, 1.2);
      if (!quadric) desc.polynomial = spherePolynomial(1.0) * (X() - Polynomial(10.0));
      desc.transform = glm::dmat4(k.scale);
      desc.transform[3] = glm::dvec4(k.shift, 0, 0, 1);
      const SurfaceScene scene(device, desc);
      for (const glm::dvec3 objectDir :
           {glm::dvec3(1, 0, 0), glm::dvec3(0.6, 0, -0.8), glm::dvec3(0, 0.6, 0.8)}) {
        RayD ray;
        ray.org = glm::dvec3(k.shift, 0, 0) + k.scale * glm::dvec3(0, 0, k.z0);
        ray.dir = objectDir;  // a uniform scale keeps directions; t scales by 1 / scale
        ray.tfar = std::numeric_limits<double>::infinity();
        // The object-space ray (o - b is exact here: Sterbenz, and z0 scale - 0), in long double.
        const glm::dvec3 ob = ray.org - glm::dvec3(k.shift, 0, 0);
        const auto ref = sphereRoot(ob / k.scale, objectDir / k.scale, 1.0L, 0.0L);
        ASSERT_TRUE(ref.has_value());
        const HitD hit = intersectD(scene, ray);
        ASSERT_TRUE(hit.hit) << k.scale << " " << k.shift << " quadric " << quadric;
        // Position error in object radii.
        EXPECT_LT(std::abs(hit.t - (double)*ref) / k.scale, 1e-9)
            << k.scale << " " << k.shift << " quadric " << quadric << " t " << hit.t << " ref "
            << (double)*ref;
      }
    }
  }
}

TEST_F(EmbreeHits, MixedSceneClosestHitEitherOrder) {
  for (bool surfaceFirst : {true, false}) {
    SurfaceGeometry sphere(device, sphereDesc(1.0, 1.5));
    RTCGeometry quad = makeQuad(device, 0.5f, 3.0f);  // cuts the sphere at z = 0.5
    Scene scene(device);
    // Required for the double channel in scenes holding Embree's own geometry types.
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    unsigned sid, qid;
    if (surfaceFirst) {
      sid = scene.attach(sphere.geometry());
      qid = scene.attach(quad);
    } else {
      qid = scene.attach(quad);
      sid = scene.attach(sphere.geometry());
    }
    rtcReleaseGeometry(quad);
    scene.commit();
    // From above: the sphere (z = 1) is in front of the quad (z = 0.5).
    RTCRayHit rh = intersect1(scene, makeRay({0, 0, 5}, {0, 0, -1}));
    EXPECT_EQ(rh.hit.geomID, sid);
    EXPECT_FLOAT_EQ(rh.ray.tfar, 4.0f);
    // From below, aimed past the sphere's silhouette: only the quad.
    rh = intersect1(scene, makeRay({2, 2, -5}, {0, 0, 1}));
    EXPECT_EQ(rh.hit.geomID, qid);
    EXPECT_FLOAT_EQ(rh.ray.tfar, 5.5f);
    // From inside the sphere upwards: the quad at z = 0.5 comes before the sphere at 1.
    rh = intersect1(scene, makeRay({0, 0, 0}, {0, 0, 1}));
    EXPECT_EQ(rh.hit.geomID, qid);
    EXPECT_FLOAT_EQ(rh.ray.tfar, 0.5f);
    // Double channel: the HitD is the surface's, the float record says the quad won.
    RayD ray{{0, 0, 0}, {0, 0, 1}, 0, 10, 0};
    RTCRayHit out;
    const HitD hit = intersectD(scene, ray, &out);
    EXPECT_EQ(out.hit.geomID, qid);
    EXPECT_NE(hit.hit && hit.geomID == out.hit.geomID, true);
  }
}

// Counts the calls of a geometry's intersect and occluded callbacks (installed in place of
// the adapter's: the bounds and primitives stay the adapter's).
std::atomic<int> calls{0};
void countIntersect(const RTCIntersectFunctionNArguments*) { ++calls; }
void countOccluded(const RTCOccludedFunctionNArguments*) { ++calls; }

// A ray that misses a surface's box never reaches its callbacks, also where the surface is
// one cell, the only user primitive of its scene: Embree tests a primitive's box only from
// the node above it, and a bare leaf at the BVH's root has none (every ray of the scene,
// the triangles' too, called the callback, session 54's audit). Rays from above onto a
// floor quad, wide of the unit sphere's clip ball of radius 1.5 (its box [-1.5, 1.5]^3
// padded by far less than 0.5), against two through the centre (the counter's check).
TEST_F(EmbreeHits, RaysWideOfALoneCellNeverCallIt) {
  for (bool quadricPath : {true, false})
    for (bool withQuad : {true, false}) {
      SurfaceDesc desc = sphereDesc(1.0, 1.5);
      desc.options.quadricCallbacks = quadricPath;
      SurfaceGeometry sphere(device, desc);
      ASSERT_EQ(sphere.primitiveCount(), 1u);
      rtcSetGeometryIntersectFunction(sphere.geometry(), &countIntersect);
      rtcSetGeometryOccludedFunction(sphere.geometry(), &countOccluded);
      rtcCommitGeometry(sphere.geometry());
      Scene scene(device);
      scene.attach(sphere.geometry());
      if (withQuad) {
        RTCGeometry quad = makeQuad(device, -2.0f, 20.0f);
        scene.attach(quad);
        rtcReleaseGeometry(quad);
      }
      scene.commit();
      const std::string what =
          std::string(quadricPath ? "quadric" : "generic") + (withQuad ? " with quad" : "");
      calls = 0;
      for (float x : {-10.0f, -2.0f, 2.0f, 7.0f})
        for (float y : {-9.0f, -2.0f, 2.0f, 5.0f}) {
          intersect1(scene, makeRay({x, y, 5}, {0, 0, -1}));
          occluded1(scene, makeRay({x, y, 5}, {0, 0, -1}).ray);
        }
      EXPECT_EQ(calls.load(), 0) << what;
      // (Ending at z = 0, before the quad: an occluded ray may stop at the quad first.)
      intersect1(scene, makeRay({0, 0, 5}, {0, 0, -1}, 0.0f, 5.0f));
      occluded1(scene, makeRay({0, 0, 5}, {0, 0, -1}, 0.0f, 5.0f).ray);
      EXPECT_EQ(calls.load(), 2) << what;
    }
}

// Two surfaces 1e-8 apart (concentric spheres, separate geometries): the double channel
// reports the closer one whichever Embree meets first. After the first hit Embree's float
// tfar is its t rounded up to float (2.1 -> 2.1000001), past the other sphere's 2.1 + 1e-8,
// so the candidate must be judged against the double hit kept so far, not the float tfar
// alone (the mutation audit of session 55: the inner sphere was reported 1e-8 late).
TEST_F(EmbreeHits, DoubleChannelKeepsTheCloserOfTwoHitsWithinAFloatUlp) {
  for (int order = 0; order < 2; ++order) {
    SurfaceGeometry outer(device, sphereDesc(1.0, 1.5));
    SurfaceGeometry inner(device, sphereDesc(1.0 - 1e-8, 1.5));
    Scene scene(device);
    unsigned outerId, innerId;
    if (order == 0) {
      outerId = scene.attach(outer.geometry());
      innerId = scene.attach(inner.geometry());
    } else {
      innerId = scene.attach(inner.geometry());
      outerId = scene.attach(outer.geometry());
    }
    scene.commit();
    for (double z0 : {-3.1, -3.3, -2.7, -3.7}) {
      const HitD hit = intersectD(scene, RayD{{0, 0, z0}, {0, 0, 1}, 0, 100, 0});
      ASSERT_TRUE(hit.hit);
      EXPECT_EQ(hit.geomID, outerId) << order << " " << z0 << " (inner " << innerId << ")";
      EXPECT_NEAR(hit.t, -z0 - 1.0, 1e-12) << order << " " << z0;  // closed form
    }
  }
}

// The float hit's primID is the cell that reported the hit (the primitive Embree called the
// callback for, which the double channel's HitD::primID records), and a sphere cut into
// cells is hit in many of them (written as 0, the primIDs passed every test that only
// bounded them: the mutation audit of session 55).
TEST_F(EmbreeHits, FloatPrimIdIsTheCellThatHit) {
  SurfaceDesc desc = sphereDesc(1.0, 1.5);
  desc.options.cellDepth = 2;
  desc.options.quadricCallbacks = false;
  SurfaceScene scene(device, desc);
  std::vector<unsigned> seen;
  for (int k = 0; k < 200; ++k) {
    const glm::dvec3 o = 4.0 * glm::dvec3(randomDir());
    RTCRayHit rh;
    const HitD hit = intersectD(scene, RayD{o, -o, 0, 100, 0}, &rh);
    ASSERT_TRUE(hit.hit) << k;  // aimed at the centre
    EXPECT_EQ(rh.hit.primID, hit.primID) << k;
    EXPECT_LT(rh.hit.primID, scene.geometry.primitiveCount()) << k;
    if (std::find(seen.begin(), seen.end(), rh.hit.primID) == seen.end())
      seen.push_back(rh.hit.primID);
  }
  EXPECT_GT(seen.size(), 8u) << "of " << scene.geometry.primitiveCount() << " cells";
}

TEST_F(EmbreeHits, OcclusionAndSpan) {
  SurfaceGeometry sphere(device, sphereDesc(1.0, 1.5));
  Scene scene(device);
  scene.attach(sphere.geometry());
  scene.commit();
  RTCRay ray = makeRay({0, 0, -5}, {0, 0, 1}).ray;
  EXPECT_TRUE(occluded1(scene, ray));
  ray.tfar = 3.9f;  // stops before the sphere (t = 4)
  EXPECT_FALSE(occluded1(scene, ray));
  ray = makeRay({3, 0, -5}, {0, 0, 1}).ray;  // passes beside
  EXPECT_FALSE(occluded1(scene, ray));
  // tnear beyond the first root gives the second one; tfar before the first: miss.
  RTCRayHit rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}, 4.5f));
  EXPECT_FLOAT_EQ(rh.ray.tfar, 6.0f);
  rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}, 0.0f, 3.99f));
  EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_FLOAT_EQ(rh.ray.tfar, 3.99f);
  rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}, 6.01f));
  EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
}

TEST_F(EmbreeHits, RayMaskRespected) {
  SurfaceGeometry sphere(device, sphereDesc(1.0, 1.5));
  rtcSetGeometryMask(sphere.geometry(), 0x2);
  rtcCommitGeometry(sphere.geometry());
  Scene scene(device);
  scene.attach(sphere.geometry());
  scene.commit();
  RTCRayHit rh = makeRay({0, 0, -5}, {0, 0, 1});
  rh.ray.mask = 0x1;
  EXPECT_EQ(intersect1(scene, rh).hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_FALSE(occluded1(scene, rh.ray));
  rh.ray.mask = 0x3;
  EXPECT_NE(intersect1(scene, rh).hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_TRUE(occluded1(scene, rh.ray));
}

TEST_F(EmbreeHits, NonFiniteAndDegenerateRaysMissQuietly) {
  const SurfaceScene scene(device, sphereDesc(1.0, 1.5));
  // Float rays Embree accepts (Embree 3 itself asserts on NaN/inf origins or directions,
  // so those never reach a user geometry): zero direction, inverted or empty span.
  const std::vector<RTCRayHit> rays = {
      makeRay({0, 0, -5}, {0, 0, 0}), makeRay({0, 0, 0}, {0, 0, 0}),
      makeRay({0, 0, -5}, {0, 0, 1}, 5.0f, 3.0f), makeRay({0, 0, -5}, {0, 0, 1}, 3.0f, 3.0f)};
  for (size_t i = 0; i < rays.size(); ++i) {
    EXPECT_EQ(intersect1(scene, rays[i]).hit.geomID, RTC_INVALID_GEOMETRY_ID) << i;
    EXPECT_FALSE(occluded1(scene, rays[i].ray)) << i;
  }
  // A tiny but non-zero direction is a legitimate ray: it hits at t = 4e10.
  const RTCRayHit tiny = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1e-10f}));
  EXPECT_NEAR(tiny.ray.tfar, 4e10f, 1e4f);
  // Denormal directions: whatever Embree's float traversal does, no crash, no error.
  intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1e-40f}));
  // Non-finite double rays reach the kernel through the double channel (the float ray
  // Embree sees is valid): no hit, no error, no hang.
  const double dnan = std::nan(""), dinf = std::numeric_limits<double>::infinity();
  const std::vector<RayD> bad = {
      {{0, 0, dnan}, {0, 0, 1}, 0, 10, 0},  {{0, 0, -5}, {dnan, 0, 1}, 0, 10, 0},
      {{0, 0, -5}, {0, 0, dinf}, 0, 10, 0}, {{-dinf, 0, 0}, {1, 0, 0}, 0, 10, 0},
      {{0, 0, -5}, {0, 0, 1}, dnan, 10, 0}, {{0, 0, -5}, {0, 0, 1}, 0, dnan, 0},
      {{0, 0, -5}, {0, 0, 0}, 0, 10, 0},    {{0, 0, -5}, {0, 0, 1}, 0, 10, dnan}};
  for (size_t i = 0; i < bad.size(); ++i) {
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &bad[i], &hit);
    RTCRayHit rh = makeRay({0, 0, -5}, {0, 0, 1}, 0.0f, 10.0f);
    rtcIntersect1(scene, &context.base, &rh);
    EXPECT_FALSE(hit.hit) << i;
    EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << i;
    RTCRay ray = makeRay({0, 0, -5}, {0, 0, 1}, 0.0f, 10.0f).ray;
    rtcOccluded1(scene, &context.base, &ray);
    EXPECT_FALSE(hit.hit) << i;
  }
  // makeRayHit of a non-finite double ray gives a float ray Embree accepts and that
  // hits nothing.
  for (const RayD& r : bad) {
    bool finiteRay = true;
    for (int k = 0; k < 3; ++k)
      finiteRay = finiteRay && std::isfinite(r.org[k]) && std::isfinite(r.dir[k]);
    if (finiteRay) continue;
    EXPECT_FALSE(intersectD(scene, r).hit);
  }
  EXPECT_EQ(scene.geometry.callbackErrors(), 0u);
}

TEST_F(EmbreeHits, SeveralSurfacesInOneScene) {
  std::vector<SurfaceGeometry> surfaces;
  Scene scene(device);
  std::vector<unsigned> ids;
  for (int i = 0; i < 5; ++i) {
    surfaces.emplace_back(device, sphereDesc(0.5, 0.75, {3.0 * i, 0, 0}));
  }
  // The polynomial above is centred at the origin: place the spheres by transform.
  surfaces.clear();
  for (int i = 0; i < 5; ++i) {
    SurfaceDesc desc = sphereDesc(0.5, 0.75);
    desc.transform[3] = glm::dvec4(3.0 * i, 0, 0, 1);
    surfaces.emplace_back(device, desc);
    ids.push_back(scene.attach(surfaces.back().geometry()));
  }
  scene.commit();
  for (int i = 0; i < 5; ++i) {
    RTCRayHit rh = intersect1(scene, makeRay({3.0f * i, 0, -5}, {0, 0, 1}));
    EXPECT_EQ(rh.hit.geomID, ids[i]);
    EXPECT_FLOAT_EQ(rh.ray.tfar, 4.5f);
  }
  // Along the row: the first sphere's near side.
  RTCRayHit rh = intersect1(scene, makeRay({-5, 0, 0}, {1, 0, 0}));
  EXPECT_EQ(rh.hit.geomID, ids[0]);
  EXPECT_FLOAT_EQ(rh.ray.tfar, 4.5f);
  rh = intersect1(scene, makeRay({20, 0, 0}, {-1, 0, 0}));
  EXPECT_EQ(rh.hit.geomID, ids[4]);
  EXPECT_FLOAT_EQ(rh.ray.tfar, 7.5f);
}

TEST_F(EmbreeHits, BadDescriptionsThrow) {
  auto make = [&](SurfaceDesc desc) { SurfaceGeometry g(device, std::move(desc)); };
  SurfaceDesc desc = sphereDesc(1.0, 1.5);
  EXPECT_NO_THROW(make(desc));
  SurfaceDesc zero = desc;
  zero.polynomial = Polynomial();
  EXPECT_THROW(make(zero), Error);
  SurfaceDesc constant = desc;
  constant.polynomial = Polynomial(2.0);
  EXPECT_THROW(make(constant), Error);
  SurfaceDesc nanCoeff = desc;
  nanCoeff.polynomial.setCoeff(1, 0, 0, std::nan(""));
  EXPECT_THROW(make(nanCoeff), Error);
  SurfaceDesc badRadius = desc;
  badRadius.clip = ClipSphere{{0, 0, 0}, -1.0};
  EXPECT_THROW(make(badRadius), Error);
  SurfaceDesc infRadius = desc;
  infRadius.clip = ClipSphere{{0, 0, 0}, std::numeric_limits<double>::infinity()};
  EXPECT_THROW(make(infRadius), Error);
  SurfaceDesc emptyBox = desc;
  emptyBox.clip = ClipBox{{0, 0, 0}, {1, -1, 1}};
  EXPECT_THROW(make(emptyBox), Error);
  SurfaceDesc singular = desc;
  singular.transform[2][2] = 0.0;
  EXPECT_THROW(make(singular), Error);
  SurfaceDesc projective = desc;
  projective.transform[0][3] = 0.5;
  EXPECT_THROW(make(projective), Error);
  // Squashed along one axis beyond 2^40 (condition number): each column passes the
  // singularity test, but the hits were noise (a torus of thickness 1e-16 was missed, one
  // of 1e-15 had the normal (-0.6, -0.06, 0), exit code 0 in algray-render); 2^39 passes,
  // and so does a uniform scale however small.
  for (const double squash : {0x1p-41, 1e-20, 1e-300}) {
    SurfaceDesc flat = desc;
    flat.transform[2][2] = squash;
    try {
      make(flat);
      ADD_FAILURE() << squash << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("condition number"), std::string::npos) << e.what();
    }
  }
  SurfaceDesc flattish = desc;
  flattish.transform[2][2] = 0x1p-39;
  EXPECT_NO_THROW(make(flattish));
  for (const int depth : {-5, -2, 31, 1000}) {  // -1 and 0..30 only
    SurfaceDesc badDepth = desc;
    badDepth.options.cellDepth = depth;
    EXPECT_THROW(make(badDepth), Error) << depth;
  }
  // The solver's options, refused with the field's name (in a callback the solver's own
  // refusal would count as a miss on every ray).
  for (const double tol : {std::nan(""), -1.0, 2.0}) {
    SurfaceDesc badTolerance = desc;
    badTolerance.options.roots.relTolerance = tol;
    try {
      make(badTolerance);
      ADD_FAILURE() << "relTolerance " << tol << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("options.roots.relTolerance"), std::string::npos)
          << e.what();
    }
  }
  SurfaceDesc badMethod = desc;
  badMethod.options.roots.method = static_cast<RootMethod>(7);
  EXPECT_THROW(make(badMethod), Error);
  for (const int depth : {-1, 0, 3}) {
    SurfaceDesc goodDepth = desc;
    goodDepth.options.cellDepth = depth;
    EXPECT_NO_THROW(make(goodDepth)) << depth;
  }
  // Scales far from 1 are not singular: 1e80 with a clip radius of 1.5e-80 is a surface
  // of world size ~1 (it hits where the unscaled one does); the same at 1e110 is refused
  // for its object space (SurfaceGeometry's range, 1e-100 .. 1e100), and 1e200 for its
  // world size, beyond Embree's reach.
  SurfaceDesc tiny = desc;
  tiny.transform = glm::dmat4(glm::dmat3(1e80));
  tiny.polynomial = spherePolynomial(1e-80);
  tiny.clip = ClipSphere{{0, 0, 0}, 1.5e-80};
  SurfaceDesc tinier = desc;
  tinier.transform = glm::dmat4(glm::dmat3(1e110));
  tinier.polynomial = spherePolynomial(1e-110);
  tinier.clip = ClipSphere{{0, 0, 0}, 1.5e-110};
  try {
    make(tinier);
    ADD_FAILURE() << "an object space of size 1e-110 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("object space"), std::string::npos) << e.what();
  }
  // As a ScaleError: the finding apart from the remedy through the transform, for a host
  // whose users set the scale otherwise (algray-query); what() has both.
  try {
    make(tinier);
  } catch (const ScaleError& e) {
    EXPECT_EQ(e.problem().find("transform"), std::string::npos) << e.problem();
    EXPECT_EQ(std::string(e.what()), "algray::SurfaceGeometry: " + e.problem() +
                                         ": scale the polynomial's variables instead of "
                                         "undoing it by the transform");
  }
  {
    const SurfaceScene scene(device, tiny);
    const RTCRayHit rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}));
    EXPECT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
    EXPECT_NEAR(rh.ray.tfar, 4.0f, 1e-5f);
  }
  SurfaceDesc huge = desc;
  huge.transform = glm::dmat4(glm::dmat3(1e200));
  try {
    make(huge);
    ADD_FAILURE() << "a surface of world size 1e200 was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SurfaceGeometry(nullptr, desc), Error);
  // A condition number beyond double's range is named as such, not printed as inf or nan
  // (the inverse of a scale of 1e-300 against 1 overflows).
  SurfaceDesc flat = desc;
  flat.transform =
      glm::dmat4(glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1e-300, 0), glm::dvec3(0, 0, 1)));
  try {
    make(flat);
    ADD_FAILURE() << "a transform of condition 1e300 was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("condition number is beyond double's range"), std::string::npos) << what;
  }
  // The object-space size to the degree, R^m, within 1e-250 .. 1e250: x^m + y^m + z^m = R^m
  // seen from x = -1.5 R along +x hits at x = -R (closed form: t = 0.5 R) inside that range,
  // and is refused beyond it (degree 20 at R = 6e14 was hit at x = -3.7e14, inside the
  // surface; degree 40 at 2e7 and 3e-8 missed).
  const auto power = [](int m, double r) {
    Polynomial p = X().pow(m) + Y().pow(m) + Z().pow(m);
    p.setCoeff(0, 0, 0, -std::pow(r, m));
    return p;
  };
  for (const auto& [m, r] : {std::pair{20, 1e12}, {40, 1e6}, {40, 1e-6}, {20, 1e-12}}) {
    SurfaceDesc ok;
    ok.polynomial = power(m, r);
    ok.clip = ClipSphere{{0, 0, 0}, 1.25 * r};
    const SurfaceScene scene(device, ok);
    const HitD hit = intersectD(scene, RayD{{-1.5 * r, 0.1 * r, 0.05 * r},
                                            {1, 0, 0},
                                            0,
                                            std::numeric_limits<double>::infinity(),
                                            0});
    EXPECT_TRUE(hit.hit) << m << " " << r;
    EXPECT_NEAR(hit.t, 0.5 * r, 1e-12 * r) << m << " " << r;
  }
  for (const auto& [m, r] : {std::pair{20, 6e14}, {40, 2e7}, {40, 3e-8}, {30, 1e10}}) {
    SurfaceDesc bad;
    bad.polynomial = power(m, r);
    bad.clip = ClipSphere{{0, 0, 0}, 1.25 * r};
    try {
      make(bad);
      ADD_FAILURE() << "degree " << m << " at size " << r << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("put the scale in the transform"), std::string::npos)
          << e.what();
    }
  }
}

// The measurement switches of SurfaceOptions change the path, not the answer: every
// configuration finds the same hits (to double precision; the float solver to float).
TEST_F(EmbreeHits, OptionsGiveTheSameHits) {
  std::vector<SurfaceOptions> configs(6);
  configs[1].originCache = true;  // off by default
  configs[2].recentre = false;
  configs[3].useCells = false;
  configs[4].cellDepth = 2;
  configs[5].singlePrecision = true;
  std::vector<RayD> rays;
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  for (int i = 0; i < 200; ++i) {
    // Half from one camera position (the origin cache path), half from random origins.
    const glm::dvec3 o = i % 2 ? glm::dvec3(0.3, -0.2, -4.0) : 4.0 * glm::dvec3(randomDir());
    rays.push_back(RayD{o, glm::dvec3(u(rng), u(rng), 0.3 * u(rng)) - o, 0.0, 1e30, 0.0});
  }
  std::vector<HitD> reference;
  int floatDisagreements = 0;
  for (size_t c = 0; c < configs.size(); ++c) {
    SurfaceDesc desc;
    desc.polynomial = torusPolynomial(1.0, 0.4);
    desc.clip = ClipSphere{{0, 0, 0}, 1.6};
    desc.options = configs[c];
    const SurfaceScene scene(device, desc);
    for (size_t i = 0; i < rays.size(); ++i) {
      const HitD hit = intersectD(scene, rays[i]);
      if (c == 0) {
        reference.push_back(hit);
        continue;
      }
      if (c == 5 && hit.hit != reference[i].hit) {
        ++floatDisagreements;  // the float solver decides near-tangent rays differently
        continue;
      }
      ASSERT_EQ(hit.hit, reference[i].hit) << "config " << c << " ray " << i;
      if (!hit.hit) continue;
      const double tol = c == 5 ? 1e-3 : 1e-12;
      EXPECT_NEAR(hit.t, reference[i].t, tol * reference[i].t) << "config " << c << " ray " << i;
    }
  }
  EXPECT_LE(floatDisagreements, 4);
}

TEST_F(EmbreeHits, ClipBoxCutsTheSurface) {
  SurfaceDesc desc = sphereDesc(1.0, 1.0);
  desc.clip = ClipBox{{-2, -2, -2}, {2, 2, 0.5}};  // cap z > 0.5 removed
  const SurfaceScene scene(device, desc);
  // Downwards through the removed cap: enters at the far (bottom) side z = -1.
  RTCRayHit rh = intersect1(scene, makeRay({0, 0, 5}, {0, 0, -1}));
  EXPECT_FLOAT_EQ(rh.ray.tfar, 6.0f);
  EXPECT_LT(rh.hit.Ng_z, 0.0f);
  rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}));
  EXPECT_FLOAT_EQ(rh.ray.tfar, 4.0f);
}

// The adapter's slab test (surface_data.h, clipToBox: the clip box and the cells) with a
// subnormal direction component below 2^-1024, whose reciprocal overflows: not a zero
// component, the ray crosses the faces it is within a few d_a of. Before, 1 / d_a = inf
// made the slab all or nothing: a ray entering x >= 0 at t = 1 missed [0, 1]^3 and one
// leaving it at t = 2 kept its whole span (the widened cell slabs turned inf - inf into
// NaN and kept all of it). In the adapter the clip region is padded by 2^-20 of its size
// and tiny directions are scaled up first, so only a face at 0 within a box of size
// ~1e-300 could show it there; checked here on the function itself against the slab
// intervals in long double (exponents far below double's, quotients to 2^-63).
TEST(AdapterClip, SubnormalDirectionComponentIsNotZero) {
  const glm::dvec3 lo(0.0, -1.0, -1.0), hi(1.0, 1.0, 1.0);
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int spans = 0, empty = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double sign = u(rng) < 0.5 ? -1.0 : 1.0;
    glm::dvec3 d(sign * std::pow(10.0, -323.0 + 15.0 * u(rng)), 1.0, 0.1 * (u(rng) - 0.5));
    const double tx = 10.0 * u(rng);  // where the ray crosses x = 0
    glm::dvec3 o(-d.x * tx, -5.0 + (u(rng) - 0.5), u(rng) - 0.5);
    if (trial == 0) o = {-1e-310, -5.0, 0.5}, d = {1e-310, 1.0, 0.0};  // enters at t = 1
    if (trial == 1) o = {2e-310, -5.0, 0.5}, d = {-1e-310, 1.0, 0.0};  // leaves at t = 2
    if (o.x == 0.0 || d.x == 0.0) continue;
    long double t0 = 0.0L, t1 = 10.0L;
    test::slabSpan(o, d, lo, hi, t0, t1);  // d.z = 0: inside the z slab by construction
    const long double margin = 1e-12L * (std::abs(t0) + std::abs(t1));
    for (const bool widen : {false, true}) {
      double s0 = 0.0, s1 = 10.0;
      const bool got = clipToBox(lo, hi, o, d, s0, s1, widen) && s0 <= s1;
      const std::string what = "trial " + std::to_string(trial) + (widen ? " widened" : "");
      if (t0 > t1 + margin) {
        EXPECT_FALSE(got) << what << ": exact span empty";
        empty += !widen;
      } else if (t0 < t1 - margin) {
        ASSERT_TRUE(got) << what << ": exact span [" << (double)t0 << ", " << (double)t1 << "]";
        // The widened span holds the exact one; the plain one is within its roundings.
        const long double slack = widen ? 0x1p-60L : 0x1p-50L;
        EXPECT_LE(s0, t0 * (1.0L + slack)) << what;
        EXPECT_GE(s1, t1 * (1.0L - slack)) << what;
        EXPECT_GE(s0, t0 * (1.0L - 1e-14L)) << what;
        EXPECT_LE(s1, t1 * (1.0L + 1e-14L)) << what;
        spans += !widen;
      }
    }
  }
  EXPECT_GT(spans, 3000);
  EXPECT_GT(empty, 3000);
}

TEST_F(EmbreeHits, HugeAndTinyCoefficientsKeepTheNormal) {
  // The unit sphere times 1e200 and 1e-200: the same hits, and Embree's float Ng keeps
  // the direction of a gradient beyond float's range (closed form: Ng parallel to p).
  for (double scale : {1e200, 1e-200, 1.0}) {
    SurfaceDesc desc = sphereDesc(1.0, 1.5);
    desc.polynomial *= scale;
    const SurfaceScene scene(device, desc);
    for (int i = 0; i < 50; ++i) {
      const glm::vec3 o = 3.0f * randomDir();
      const glm::vec3 d = 0.5f * randomDir() - o;
      const RTCRayHit rh = intersect1(scene, makeRay(o, d));
      const auto ref = sphereRoot(asD(rh, true), asD(rh, false), 1.0L, 0.0L);
      ASSERT_EQ(ref.has_value(), rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) << scale;
      if (!ref) continue;
      EXPECT_NEAR(rh.ray.tfar, (double)*ref, 2e-7 * (double)*ref) << scale;
      const glm::vec3 n = hitNormal(rh);
      ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << scale;
      const glm::dvec3 p = asD(rh, true) + (double)*ref * asD(rh, false);
      EXPECT_NEAR(glm::dot(glm::dvec3(n), glm::normalize(p)), 1.0, 1e-6) << scale;
    }
  }
}

// Flush-to-zero and denormals-are-zero for the scope: how Embree's TBB worker threads
// (and so a host's tbb::parallel_for beside Embree, as algray-query's and algray-render's)
// run, where a product below double's normal range becomes 0.
struct FlushToZero {
#if defined(__SSE__)
  unsigned saved = _mm_getcsr();
  FlushToZero() { _mm_setcsr(saved | 0x8040u); }  // FTZ (bit 15) | DAZ (bit 6)
  ~FlushToZero() { _mm_setcsr(saved); }
#endif
};

// f and c f are the same surface: a torus (generic walk) and a sphere (quadric path)
// written with an overall factor from 2^-1000 to 1e300 get the unscaled polynomial's hits
// (double channel, rays from inside the clip region in random directions, with and
// without flush-to-zero): bit for bit for a power of two, within 1e-13 for a decimal
// factor (its product rounds each coefficient). The kernels' products with small powers
// of the ray left double's normal range before the surface scaled such a polynomial: in
// algray-query's TBB threads a torus times 1e-300 moved 4 of 2000 hits by 1e-9 of the
// radius (their noise bounds did not cover the flushed products).
TEST_F(EmbreeHits, OverallFactorOfThePolynomialChangesNoHit) {
  for (const bool flush : {false, true}) {
    std::optional<FlushToZero> mode;
    if (flush) mode.emplace();
    for (const std::string equation : {"(x^2+y^2+z^2+0.75)^2-4*(x^2+y^2)", "x^2+y^2+z^2-1"}) {
      SurfaceDesc plain;
      plain.polynomial = parsePolynomial(equation);
      plain.clip = ClipSphere{glm::dvec3(0.0), 2.0};
      for (const std::string factor : {"2^-1000", "2^600", "1e-300", "1e300", "1e-200"}) {
        SurfaceDesc scaled = plain;
        scaled.polynomial = parsePolynomial(factor + "*(" + equation + ")");
        const ScenePair pair(device, plain, scaled);
        const bool exact = factor.starts_with("2^");
        std::mt19937 gen(77);  // the same rays for every factor
        std::uniform_real_distribution<double> inside(-0.3, 0.3);
        std::normal_distribution<double> gauss;
        // Four rays that moved by 1e-9 with the factor 1e-300 (nearly level with the top of
        // the torus's tube: tiny z components), then random ones.
        std::vector<RayD> rays = {
            {{-0.13531386707898133, -0.07028036420745126, 0.2884700727229584},
             {0.9206835256510592, -0.05745529917409921, -0.010524355411913601}},
            {{0.24776113862248778, 0.2424231251627968, 0.2988454288855132},
             {0.2890713782858783, -0.2011776235580851, 0.00705369937711551}},
            {{0.04738413386128504, -0.040137790762485304, -0.17436304477280892},
             {-1.4962461339894435, 0.5400580211917891, 0.8834185494731329}},
            {{0.08387603324281967, 0.2311673387930015, -0.29900011676272537},
             {-0.3584908178481061, -0.09607198081603684, -0.006696342454642689}}};
        for (int i = 0; i < 2000; ++i)
          rays.push_back(
              {{inside(gen), inside(gen), inside(gen)}, {gauss(gen), gauss(gen), gauss(gen)}});
        int hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
          RayD ray = rays[i];
          ray.tnear = 0.0;
          ray.tfar = std::numeric_limits<double>::infinity();
          const HitD want = intersectD(pair.sa, ray), got = intersectD(pair.sb, ray);
          ASSERT_EQ(got.hit, want.hit) << factor << (flush ? " flush-to-zero" : "") << " ray " << i;
          if (!want.hit) continue;
          ++hits;
          if (exact)
            EXPECT_EQ(got.t, want.t) << factor << (flush ? " flush-to-zero" : "") << " ray " << i;
          else
            EXPECT_NEAR(got.t, want.t, 1e-13 * std::max(1.0, want.t))
                << factor << (flush ? " flush-to-zero" : "") << " ray " << i;
        }
        EXPECT_GT(hits, 500) << factor;
      }
    }
  }
}

// Rays with directions near 1e308 (and origins near it) against the unit sphere, in both
// channels, with and without flush-to-zero: the closed-form t (long double; a t near
// 1e-308 to a few subnormal steps) and the entry's normal -d / |d| (every ray passes
// through the centre). Under flush-to-zero (Embree's and TBB's threads) the float proxy
// stopped at the sphere's centre (its last moves' t ~ 1e-308 flushed to 0) and reported
// the exit, a hit at t ~ 1e-308 came back as t = 0, and an origin near (1e308, 1e308,
// 1e308) with a unit direction missed in the float channel (the arc length to the scene
// overflowed).
TEST_F(EmbreeHits, DirectionsAndOriginsNear1e308HitTheEntry) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const SurfaceScene scene(device, sphereDesc(1.0, 2.0));
  constexpr double c = 1.7e308;
  const RayD rays[] = {{{3, 0, 0}, {-c, 0, 0}, 0, kInf, 0},   {{c, 0, 0}, {-c, 0, 0}, 0, kInf, 0},
                       {{c, c, c}, {-1, -1, -1}, 0, kInf, 0}, {{c, c, c}, {-c, -c, -c}, 0, kInf, 0},
                       {{-c, 0, 0}, {1, 0, 0}, 0, kInf, 0},   {{0, -c, c}, {0, 1, -1}, 0, kInf, 0}};
  for (const bool flush : {false, true}) {
    std::optional<FlushToZero> mode;
    if (flush) mode.emplace();
    for (const RayD& ray : rays) {
      SCOPED_TRACE(testing::Message()
                   << "flush " << flush << " o " << ray.org.x << " " << ray.org.y << " "
                   << ray.org.z << " d " << ray.dir.x << " " << ray.dir.y << " " << ray.dir.z);
      // |o + t d| = 1, first root, with o and d scaled by 2^-1024 (exact) for the squares.
      using LD = long double;
      const LD s = std::ldexp(LD(1), -1024);
      LD oo = 0, od = 0, dd = 0;
      for (int i = 0; i < 3; ++i) {
        const LD o = LD(ray.org[i]) * s, d = LD(ray.dir[i]) * s;
        oo += o * o, od += o * d, dd += d * d;
      }
      const LD cc = oo - s * s;  // |o|^2 - 1, scaled by 2^-2048
      const LD tExact = (-od - std::sqrt(od * od - dd * cc)) / dd;
      RTCRayHit viaFloat = makeRayHit(ray, scene);
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      rtcIntersect1(scene, &context, &viaFloat);
      const HitD hit = intersectD(scene, ray);
      ASSERT_TRUE(hit.hit);
      const double subnormalSteps = 4 * std::numeric_limits<double>::denorm_min();
      EXPECT_NEAR(hit.t, double(tExact), 4e-16 * double(tExact) + subnormalSteps);
      ASSERT_NE(viaFloat.hit.geomID, RTC_INVALID_GEOMETRY_ID);
      const double tFloat = fromFloatParameter(ray, viaFloat.ray.tfar, scene);
      EXPECT_NEAR(tFloat, double(tExact), 1e-6 * double(tExact) + subnormalSteps);
      const glm::dvec3 n =
          glm::normalize(glm::dvec3(viaFloat.hit.Ng_x, viaFloat.hit.Ng_y, viaFloat.hit.Ng_z));
      const glm::dvec3 nd = glm::normalize(hit.Ng);
      const double m = std::max({std::abs(ray.dir.x), std::abs(ray.dir.y), std::abs(ray.dir.z)});
      const glm::dvec3 expected = -glm::normalize(ray.dir / m);
      EXPECT_GT(glm::dot(n, expected), 0.999);
      EXPECT_GT(glm::dot(nd, expected), 0.999);
    }
  }
}

// u lies in [0, 1) also just below the seam (y -> 0-, x > 0), where the exact u is
// 1 - atan(|y| / x) / (2 pi) (closed form for a hit at (x, y, 0)): the float u must be below
// 1 (a host indexing a texture by u * width) and within float's rounding of it. The cast
// to float gave 1.0f for |y| below ~2e-7, in every path: quadric callbacks and packets,
// the generic walk, a torus, and the double channel's float record.
TEST_F(EmbreeHits, FloatUStaysBelowOneAtTheSeam) {
  for (int surface = 0; surface < 3; ++surface) {
    SCOPED_TRACE(testing::Message() << "surface " << surface);
    SurfaceDesc desc = sphereDesc(1.0, 1.5);
    desc.options.quadricCallbacks = surface == 0;
    desc.options.uv = true;
    if (surface == 2) {
      desc.polynomial = torusPolynomial(1.0, 0.4);
      desc.clip = ClipSphere{{0, 0, 0}, 1.6};
    }
    const SurfaceScene scene(device, desc);
    constexpr double kPi = 3.14159265358979323846;
    const float ys[4] = {-1e-9f, -1e-8f, -1e-7f, -1e-30f};
    alignas(16) RTCRayHit4 packet{};
    alignas(16) int valid[4] = {-1, -1, -1, -1};
    for (int l = 0; l < 4; ++l) {
      const float y = ys[l];
      const double x = surface == 2 ? 1.4 : 1.0;  // the hit's x: the outer radius
      const double exact = 1.0 - std::atan(std::abs(double(y)) / x) / (2.0 * kPi);
      setPacketLane(packet.ray, l, makeRay({5, y, 0}, {-1, 0, 0}).ray);
      packet.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
      const RTCRayHit one = intersect1(scene, makeRay({5, y, 0}, {-1, 0, 0}));
      RTCRayHit viaDouble;
      const HitD hit = intersectD(scene, RayD{{5, y, 0}, {-1, 0, 0}, 0, 100, 0}, &viaDouble);
      ASSERT_NE(one.hit.geomID, RTC_INVALID_GEOMETRY_ID);
      ASSERT_TRUE(hit.hit);
      for (const float u : {one.hit.u, viaDouble.hit.u}) {
        EXPECT_LT(u, 1.0f) << "y " << y;
        EXPECT_NEAR(u, exact, 1e-7) << "y " << y;
      }
      EXPECT_LT(hit.u, 1.0);
      EXPECT_NEAR(hit.u, exact, 1e-12);
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect4(valid, scene, &context, &packet);
    for (int l = 0; l < 4; ++l) EXPECT_LT(packet.hit.u[l], 1.0f) << "packet lane " << l;
  }
}

// SurfaceOptions::uv off: every hit field as with the default except u = v = 0, for
// single float rays, 8-ray packets (the quadric's SIMD lanes and the generic walk's lane
// loop) and the double channel; and the default's u, v are not all zero (the test can fail).
TEST_F(EmbreeHits, UvOffWritesZeroAndKeepsTheHit) {
  std::uniform_real_distribution<float> u(-1.3f, 1.3f);
  for (const bool quadric : {true, false}) {
    SCOPED_TRACE(quadric ? "sphere" : "torus");
    SurfaceDesc desc = quadric ? sphereDesc(1.0, 1.2) : SurfaceDesc{};
    if (!quadric) {
      desc.polynomial = torusPolynomial(1.0, 0.4);
      desc.clip = ClipSphere{{0, 0, 0}, 1.6};
    }
    desc.options.uv = true;
    SurfaceDesc off = desc;
    off.options = SurfaceOptions{};  // the default: no u, v
    ScenePair pair(device, desc, off);
    auto& [ga, gb, sa, sb] = pair;
    const glm::vec3 eye(0.4f, -3.1f, 1.7f);
    int hits = 0, nonZeroUV = 0;
    for (int k = 0; k < 40; ++k) {
      RTCRayHit8 pa{}, pb{};
      alignas(32) int valid[8];  // rtcIntersect8 loads the mask as one vector
      RTCRayHit singles[8];
      for (int l = 0; l < 8; ++l) {
        valid[l] = -1;
        const glm::vec3 dir = glm::vec3(u(rng), u(rng), u(rng)) - eye;
        singles[l] = makeRay(eye, dir);
        for (RTCRayHit8* p : {&pa, &pb}) {
          setPacketLane(p->ray, l, singles[l].ray);
          p->hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
        }
      }
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      rtcIntersect8(valid, sa, &context, &pa);
      rtcInitIntersectContext(&context);
      rtcIntersect8(valid, sb, &context, &pb);
      for (int l = 0; l < 8; ++l) {
        const RTCRayHit a = intersect1(sa, singles[l]), b = intersect1(sb, singles[l]);
        ASSERT_EQ(a.hit.geomID, b.hit.geomID);
        ASSERT_EQ(pa.hit.geomID[l], a.hit.geomID);
        ASSERT_EQ(pb.hit.geomID[l], a.hit.geomID);
        if (a.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        ++hits;
        nonZeroUV += a.hit.u != 0.0f || a.hit.v != 0.0f;
        EXPECT_EQ(b.ray.tfar, a.ray.tfar);
        EXPECT_EQ(b.hit.Ng_x, a.hit.Ng_x);
        EXPECT_EQ(b.hit.Ng_y, a.hit.Ng_y);
        EXPECT_EQ(b.hit.Ng_z, a.hit.Ng_z);
        EXPECT_EQ(b.hit.primID, a.hit.primID);
        EXPECT_EQ(b.hit.u, 0.0f);
        EXPECT_EQ(b.hit.v, 0.0f);
        EXPECT_EQ(pb.ray.tfar[l], a.ray.tfar);
        EXPECT_EQ(pa.hit.u[l], a.hit.u);
        EXPECT_EQ(pb.hit.u[l], 0.0f);
        EXPECT_EQ(pb.hit.v[l], 0.0f);
        // The double channel.
        const RayD ray{glm::dvec3(eye),
                       glm::dvec3(singles[l].ray.dir_x, singles[l].ray.dir_y, singles[l].ray.dir_z),
                       0.0, 1e30, 0.0};
        const HitD da = intersectD(sa, ray), db = intersectD(sb, ray);
        ASSERT_TRUE(da.hit && db.hit);
        EXPECT_EQ(db.t, da.t);
        EXPECT_EQ(db.u, 0.0);
        EXPECT_EQ(db.v, 0.0);
        EXPECT_NE(da.u, 0.0);
      }
    }
    EXPECT_GT(hits, 100);
    EXPECT_GT(nonZeroUV, hits - 2);
    EXPECT_EQ(ga.callbackErrors() + gb.callbackErrors(), 0u);
  }
}

}  // namespace
}  // namespace algray::test
