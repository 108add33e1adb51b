// Rays leaving a surface must not find their own origin again (no shadow acne, no
// speckles), on every gallery surface, without any epsilon: shadow and bounce rays start
// at hit points computed as o + t d, with tnear = 0, through the float and the double
// channel.
#include "embree_test_util.h"

#include "algray/gallery.h"

#include "support/reference.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <vector>

namespace algray::test {
namespace {

struct Counts {
  int primary = 0;         // primary hits (each gives the origin of leaving rays)
  int leaving = 0;         // leaving rays traced
  int selfHits = 0;        // leaving rays that hit within selfDistance of their origin
  double closest = 1e300;  // closest accepted hit distance seen, relative to the clip radius
};

// A hit closer than this (relative to the clip radius) to the ray's origin counts as the
// origin found again: orders of magnitude below any feature of the gallery surfaces and
// far above the rounding of the hit points. Unless the ray from the exact surface point
// meets the surface there too (genuineReentry, MPFR): a direction within ~1e-6 rad of the
// tangent plane re-enters a curved surface that close (one draw of the seeds, session 41:
// 6.9e-7 rad on the Barth sextic, f clear of its noise between, re-entry at 3.3e-7 R).
constexpr double kSelfDistance = 1e-6;

class EmbreeShadow : public ::testing::TestWithParam<std::string_view> {};

TEST_P(EmbreeShadow, LeavingRaysNeverHitTheirOrigin) {
  const GallerySurface* g = findGallerySurface(GetParam());
  ASSERT_NE(g, nullptr);
  Device device;
  const Polynomial f = g->build();
  SurfaceDesc desc;
  desc.polynomial = f;
  desc.clip = ClipSphere{glm::dvec3(0.0), g->clipRadius};
  SurfaceGeometry surface(device, desc);
  Scene scene(device);
  const unsigned id = scene.attach(surface.geometry());
  scene.commit();
  const double R = g->clipRadius;

  std::mt19937 rng(2024);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
  Counts dbl, flt;
  // A hit at t along d from p is the origin found again (see kSelfDistance).
  const auto selfHit = [&](const glm::dvec3& p, const glm::dvec3& d, double t) {
    return t * glm::length(d) / R < kSelfDistance && !genuineReentry(f, p, d, t);
  };
  for (int i = 0; i < 150; ++i) {
    // ---- Primary ray from a camera 3 clip radii away ---------------------------------
    const glm::dvec3 cam = 3.0 * R * randomUnit();
    const glm::dvec3 target = 0.8 * R * glm::dvec3(u(rng), u(rng), u(rng));
    RayD primary{cam, target - cam, 0.0, std::numeric_limits<double>::infinity(), 0.0};
    const HitD hit = intersectD(scene, primary);
    const RTCRayHit fhit = intersect1(scene, makeRay(glm::vec3(cam), glm::vec3(target - cam)));
    for (int leave = 0; leave < 8; ++leave) {
      // Half the rays leave on the side the primary ray came from (shadow rays towards a
      // light), half go through the surface (refraction): both must skip the origin.
      glm::dvec3 dir = randomUnit();
      // ---- Double channel: p = o + t d and its pbrt-style error bound ----------------
      if (hit.hit) {
        const glm::dvec3 p = primary.org + hit.t * primary.dir;
        const double pError =
            gamma(3) * (glm::length(primary.org) + glm::length(hit.t * primary.dir));
        RayD ray{p, dir, 0.0, std::numeric_limits<double>::infinity(), pError};
        const HitD h = intersectD(scene, ray);
        ++dbl.leaving;
        if (h.hit) {
          const double dist = h.t * glm::length(dir) / R;
          dbl.closest = std::min(dbl.closest, dist);
          if (selfHit(p, dir, h.t)) ++dbl.selfHits;
        }
        // Occlusion takes the same path.
        RTCRay shadow = makeRayHit(ray).ray;
        IntersectContext ctx;
        HitD occ;
        initIntersectContext(&ctx, &ray, &occ);
        rtcOccluded1(scene, &ctx.base, &shadow);
        if (occ.hit && selfHit(p, dir, occ.t)) ++dbl.selfHits;
      }
      // ---- Float channel: the host's float hit point, tnear = 0 ------------------------
      if (fhit.hit.geomID == id) {
        const glm::vec3 o(fhit.ray.org_x, fhit.ray.org_y, fhit.ray.org_z);
        const glm::vec3 d(fhit.ray.dir_x, fhit.ray.dir_y, fhit.ray.dir_z);
        const glm::vec3 p = o + fhit.ray.tfar * d;
        const RTCRayHit s = intersect1(scene, makeRay(p, glm::vec3(dir)));
        ++flt.leaving;
        if (s.hit.geomID == id) {
          const double dist = s.ray.tfar / R;
          flt.closest = std::min(flt.closest, dist);
          if (selfHit(glm::dvec3(p), glm::dvec3(glm::vec3(dir)), s.ray.tfar)) ++flt.selfHits;
        }
      }
    }
    dbl.primary += hit.hit;
    flt.primary += fhit.hit.geomID == id;
  }
  RecordProperty("primary_hits", dbl.primary);
  EXPECT_GT(dbl.primary, 10) << "too few primary hits to test " << g->name;
  EXPECT_EQ(dbl.selfHits, 0) << g->name << " double channel, closest " << dbl.closest;
  EXPECT_EQ(flt.selfHits, 0) << g->name << " float channel, closest " << flt.closest;
  EXPECT_EQ(surface.callbackErrors(), 0u);
  std::printf("%-16s primary %3d/%3d  leaving %4d/%4d  closest leaving hit %.3g / %.3g R\n",
              std::string(g->name).c_str(), dbl.primary, flt.primary, dbl.leaving, flt.leaving,
              dbl.closest, flt.closest);
}

// Float hosts in a clip region larger than the object (the clip sphere 100 or 20 times
// the gallery's): a camera 4.55 clip radii away (algray-render's quick view), rays leaving
// its float hit points in every direction. Session 51 first sized a float origin's assumed
// uncertainty by the object alone (its cells' reach, 1.2-1.7 radii here), which covered
// cameras within ~8 of those: 49 of ~110 lit-side shadow rays of the sphere met their own
// origin, 24 of the torus's, 23 of the heart's (the review of session 51); now the scene's
// radius, the clip radius up to 2^10 object radii (SurfaceData::sceneRadius).
TEST(EmbreeShadowLargeClip, FloatLeavingRaysOfACameraFarAwayNeverHitTheirOrigin) {
  struct Case {
    const char* surface;
    double clipFactor;
    double cameraRadii = 4.55;  // the camera's distance in clip radii
  };
  // (And the sphere 8000 times, its camera 10 clip radii away: 8e4 object radii, the
  // farthest camera the cap of 2^13 object radii covers.)
  for (const Case c : {Case{"sphere", 100.0}, Case{"torus", 20.0}, Case{"heart", 20.0},
                       Case{"sphere", 8000.0, 10.0}}) {
    const GallerySurface* g = findGallerySurface(c.surface);
    ASSERT_NE(g, nullptr);
    Device device;
    const Polynomial f = g->build();
    const double R = c.clipFactor * g->clipRadius;
    SurfaceDesc desc;
    desc.polynomial = f;
    desc.clip = ClipSphere{glm::dvec3(0.0), R};
    SurfaceGeometry surface(device, desc);
    Scene scene(device);
    const unsigned id = scene.attach(surface.geometry());
    scene.commit();
    std::mt19937 rng(51);
    std::normal_distribution<double> n;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
    int primary = 0, leaving = 0, selfHits = 0;
    for (int i = 0; i < 200; ++i) {
      const glm::dvec3 cam = c.cameraRadii * R * randomUnit();
      const glm::dvec3 target = 0.8 * g->clipRadius * glm::dvec3(u(rng), u(rng), u(rng));
      const RTCRayHit fhit = intersect1(scene, makeRay(glm::vec3(cam), glm::vec3(target - cam)));
      if (fhit.hit.geomID != id) continue;
      ++primary;
      const glm::vec3 o(fhit.ray.org_x, fhit.ray.org_y, fhit.ray.org_z);
      const glm::vec3 d(fhit.ray.dir_x, fhit.ray.dir_y, fhit.ray.dir_z);
      const glm::vec3 p = o + fhit.ray.tfar * d;
      for (int leave = 0; leave < 8; ++leave) {
        const glm::vec3 dir(randomUnit());
        const RTCRayHit s = intersect1(scene, makeRay(p, dir));
        RTCRay shadow = makeRay(p, dir).ray;
        const bool occluded = occluded1(scene, shadow);
        ++leaving;
        // An outward ray (at least 0.2 from the tangent plane, along grad f) meeting the
        // surface within 0.05 of the gallery's radius met its own origin: a float hit point
        // from the farthest camera here lies up to ~3e-3 of it off the surface (so the exact
        // ray from it can cross the surface there, which genuineReentry would call real),
        // and these surfaces do not curve back that sharply.
        const glm::dvec3 normal = glm::normalize(f.evaluateWithBound(glm::dvec3(p)).gradient);
        const bool outward = glm::dot(normal, glm::dvec3(dir)) > 0.2;
        if (outward && s.hit.geomID == id && s.ray.tfar < 0.05 * g->clipRadius) ++selfHits;
        // Occlusion takes the same path: occluded exactly where the closest hit hits.
        EXPECT_EQ(occluded, s.hit.geomID == id) << c.surface << " ray " << i << " " << leave;
      }
    }
    EXPECT_GT(primary, 50) << c.surface;
    EXPECT_EQ(selfHits, 0) << c.surface << ": of " << leaving << " leaving rays";
    EXPECT_EQ(surface.callbackErrors(), 0u);
  }
}

// Taubin's heart along its equator ellipse (z = 0, x^2 + 9/4 y^2 = 1), where f's gradient
// vanishes though the surface is smooth: f ~ dist^3, so a hit there lies off the surface by
// more than its rounding, and g of a ray leaving it has a near-triple cluster of roots
// beyond the window of the origin's stated uncertainty; with g(0) set to 0, q = g / s had
// real roots there 1e-8..3e-6 radii from the origin (98 of 2400 leaving rays in session
// 46's audit, where the exact restriction has no real root; ray_roots.cpp, inOriginNoise).
// Primary rays aimed within 1e-7..1e-2 of the equator from 3 radii, rays leaving each hit
// with pbrt's bound, double channel, closest hit and occlusion; a hit within kSelfDistance
// that the exact ray from the surface point does not meet there (genuineReentry) is the
// origin found again.
TEST(EmbreeShadowHeart, LeavingRaysNearTheEquatorDoNotFindTheirOrigin) {
  const GallerySurface* heart = findGallerySurface("heart");
  ASSERT_NE(heart, nullptr);
  Device device;
  const Polynomial f = heart->build();
  SurfaceDesc desc;
  desc.polynomial = f;
  desc.clip = ClipSphere{glm::dvec3(0.0), heart->clipRadius};
  const SurfaceScene scene(device, desc);
  const double R = heart->clipRadius;
  std::mt19937 rng(4647);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
  int primary = 0, leaving = 0, selfHits = 0;
  for (int i = 0; i < 300; ++i) {
    const double phi = 2.0 * std::numbers::pi * u(rng);
    const double z = (i % 2 ? 1.0 : -1.0) * std::pow(10.0, -7.0 + 5.0 * u(rng));
    const glm::dvec3 target(std::cos(phi), std::sin(phi) / 1.5, z);
    const glm::dvec3 cam = 3.0 * R * randomUnit();
    const RayD ray{cam, target - cam, 0.0, std::numeric_limits<double>::infinity(), 0.0};
    const HitD hit = intersectD(scene, ray);
    if (!hit.hit) continue;
    ++primary;
    const glm::dvec3 p = ray.org + hit.t * ray.dir;
    const double pError = gamma(3) * (glm::length(ray.org) + glm::length(hit.t * ray.dir));
    for (int k = 0; k < 4; ++k) {
      const glm::dvec3 dir = randomUnit();
      const RayD leave{p, dir, 0.0, std::numeric_limits<double>::infinity(), pError};
      const HitD h = intersectD(scene, leave);
      ++leaving;
      const auto self = [&](double t) {
        return t * glm::length(dir) / R < kSelfDistance && !genuineReentry(f, p, dir, t);
      };
      if (h.hit && self(h.t)) ++selfHits;
      RTCRay shadow = makeRayHit(leave).ray;
      IntersectContext ctx;
      HitD occ;
      initIntersectContext(&ctx, &leave, &occ);
      rtcOccluded1(scene, &ctx.base, &shadow);
      if (occ.hit && self(occ.t)) ++selfHits;
    }
  }
  EXPECT_GT(primary, 200);
  // 14 of 1184 without the rule (closest hit and occlusion counted apart).
  EXPECT_EQ(selfHits, 0) << "of " << leaving << " leaving rays";
  std::printf("heart equator: %d self-hits of %d leaving rays\n", selfHits, leaving);
}

// Pinch points and double curves, where grad f nearly vanishes and f is quadratic in the
// offset from them: a host's hit 1e-12..1e-8 radii from one lies between two sheets closer
// than its own uncertainty, and the self-root rule's first-order test (|f(o)| within twice
// |grad f| orgError) took it for a point off the surface: leaving rays hit again 1e-19 to
// 3.5e-15 away, inside the self-root window of twice orgError that README promises to skip
// (session 47's audit: 37-86 of 330-1280 such rays on these surfaces; originOnSurface's
// second-order term). Primary rays from 3 clip radii at the pinch points and at points of
// the double lines (offset 1e-12..1e-8 radii), rays leaving each hit with pbrt's bound in
// random directions, double channel: no hit and no occlusion within the window. (And a
// pair of planes through a line, on the quadric path: the review found quadricLane without
// the window, 9 of 1440 such rays within it.)
TEST(EmbreeShadowSingular, LeavingRaysNextToPinchPointsSkipTheSelfRootWindow) {
  struct SingularCase {
    const char* equation;  // or a gallery name
    double clipRadius;
    std::vector<glm::dvec3> points;  // pinch points and points of double lines
  };
  const SingularCase cases[] = {
      {"roman-surface", 0.75, {{0.5, 0, 0}, {0, 0, 0.5}, {0, -0.5, 0}, {0.2, 0, 0}, {0, 0, -0.3}}},
      {"z*(x^2+y^2) - 2*x*y", 1.5, {{0, 0, 1}, {0, 0, -1}, {0, 0, 0.4}}},
      {"x^2 - y^2*z", 1.0, {{0, 0, 0}, {0, 0, 1e-6}, {0, 0, 0.5}}},
      {"4*x^2*(x^2+y^2+z^2+z) + y^2*(y^2+z^2-1)", 1.5, {{0, 0, 0}, {0, 0, -1}, {0, 0, -0.5}}},
      // A pair of planes 0.2 rad apart through the z axis, on the quadric path (quadricLane).
      {"x^2 - 1e-2*y^2", 1.0, {{0, 0, 0}, {0, 0, 0.5}, {0, 0, -0.3}}},
  };
  Device device;
  std::mt19937 rng(4749);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
  int primary = 0, leaving = 0, windowHits = 0;
  for (const SingularCase& c : cases) {
    SurfaceDesc desc;
    const GallerySurface* g = findGallerySurface(c.equation);
    desc.polynomial = g ? g->build() : parsePolynomial(c.equation);
    desc.clip = ClipSphere{glm::dvec3(0.0), c.clipRadius};
    const SurfaceScene scene(device, desc);
    const double R = c.clipRadius;
    for (const glm::dvec3& point : c.points) {
      for (int i = 0; i < 40; ++i) {
        const glm::dvec3 cam = point + 3.0 * R * randomUnit();
        const glm::dvec3 target = point + std::pow(10.0, -12.0 + 4.0 * u(rng)) * R * randomUnit();
        const RayD ray{cam, target - cam, 0.0, std::numeric_limits<double>::infinity(), 0.0};
        const HitD hit = intersectD(scene, ray);
        if (!hit.hit) continue;
        ++primary;
        const glm::dvec3 p = cam + hit.t * ray.dir;
        const double pError = gamma(3) * (glm::length(cam) + glm::length(hit.t * ray.dir));
        for (int k = 0; k < 8; ++k) {
          const glm::dvec3 dir = randomUnit();
          RayD leave{p, dir, 0.0, std::numeric_limits<double>::infinity(), pError};
          ++leaving;
          const double window = 2.0 * pError * (1.0 + 0x1p-20);
          const HitD h = intersectD(scene, leave);
          SCOPED_TRACE(testing::Message() << c.equation << " point " << point.x << " " << point.y
                                          << " " << point.z << " ray " << i);
          if (h.hit && h.t <= window) ++windowHits;
          EXPECT_FALSE(h.hit && h.t <= window) << "hit at " << h.t;
          RTCRay shadow = makeRayHit(leave).ray;
          IntersectContext ctx;
          HitD occ;
          initIntersectContext(&ctx, &leave, &occ);
          rtcOccluded1(scene, &ctx.base, &shadow);
          EXPECT_FALSE(occ.hit && occ.t <= window) << "occluded at " << occ.t;
        }
      }
    }
  }
  EXPECT_GT(primary, 300);
  std::printf("next to pinch points: %d of %d leaving rays hit within the window\n", windowHits,
              leaving);
}

// The other side of inOriginNoise (the review of session 46): roots that g as computed has
// too are surfaces, however close. Thin shells (unit spheres 3e-8 and 1e-5 apart, about the
// origin and about (10, 0, 0)) left from one sheet towards the other, and a unit sphere
// written about (100, 0, 0) left inwards 1e-4 radians from its tangent plane: the first
// version of the rule (g within its bound on g(0)) skipped the near sheet on all four (a
// miss, or the far side at 0.6). References: the exact roots of the stored polynomials
// along the rays (mpmath, 60 digits).
TEST(EmbreeShadowOffset, ThinShellsAndGrazingReentriesAreHits) {
  struct ShellCase {
    const char* equation;
    glm::dvec3 centre;
    const char* o[3];
    const char* d[3];
    const char* orgError;
    double expected;
  };
  const char* shell10 = "((x-10)^2+y^2+z^2-1)*((x-10)^2+y^2+z^2-1.0000200001)";
  const ShellCase cases[] = {
      {"((x-100)^2+y^2+z^2-1)*((x-100)^2+2*y^2+z^2+1)",
       {100, 0, 0},
       {"0x1.8e81bd92bbca2p+6", "-0x1.bbc781f3bd47bp-1", "0x1.52a9fe0bc41ep-2"},
       {"0x1.d55eaa240df92p-1", "-0x1.98e419cf929a9p-2", "-0x1.8ababe2b0ab9p-7"},
       "0x1.c25c268497682p-44",
       1.9999997897e-4},
      {"(x^2+y^2+z^2-1)*(x^2+y^2+z^2-1.00000006)",
       {0, 0, 0},
       {"-0x1.d2ae7def14d9ap-6", "-0x1.aa5fea79a9161p-1", "-0x1.1b153bb4eedfbp-1"},
       {"-0x1.5041186ce3a97p-1", "-0x1.3e2b751a09132p-1", "0x1.b57865c87f77bp-2"},
       "0",
       9.99999836e-8},
      {shell10,
       {10, 0, 0},
       {"0x1.3f16a8c108759p+3", "-0x1.aa5fea79a9161p-1", "-0x1.1b153bb4eedfbp-1"},
       {"-0x1.5041186ce3a97p-1", "-0x1.3e2b751a09132p-1", "0x1.b57865c87f77bp-2"},
       "0",
       3.33694966e-5},
      {shell10,
       {10, 0, 0},
       {"0x1.3f16a8281c5e5p+3", "-0x1.aa6101e775c9cp-1", "-0x1.1b15f53a5eaa9p-1"},
       {"0x1.5041186ce3a97p-1", "0x1.3e2b751a09132p-1", "-0x1.b57865c87f77bp-2"},
       "0",
       3.33728750e-5},
  };
  Device device;
  for (const ShellCase& c : cases) {
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial(c.equation);
    desc.clip = ClipBox{c.centre - glm::dvec3(2.0), c.centre + glm::dvec3(2.0)};
    const SurfaceScene scene(device, desc);
    RayD ray;
    for (int i = 0; i < 3; ++i) {
      ray.org[i] = std::strtod(c.o[i], nullptr);
      ray.dir[i] = std::strtod(c.d[i], nullptr);
    }
    ray.tfar = 10.0;
    ray.orgError = std::strtod(c.orgError, nullptr);
    const HitD hit = intersectD(scene, ray);
    SCOPED_TRACE(c.equation);
    EXPECT_TRUE(hit.hit);
    if (hit.hit) {
      EXPECT_NEAR(hit.t, c.expected, 1e-6 * c.expected);
    }
    RayD shadow = ray;
    shadow.tfar = 2.0 * c.expected;
    HitD occ;
    IntersectContext ctx;
    initIntersectContext(&ctx, &shadow, &occ);
    RTCRay r = makeRayHit(ctx).ray;
    rtcOccluded1(scene, &ctx.base, &r);
    EXPECT_TRUE(occ.hit);
  }
}

// A thin shell's other sheet is not the origin's cluster: a ray leaving the inner sheet of
// (|x|^2 - 1)(|x|^2 - (1 + w)^2) outwards, from an origin off that sheet towards the outer
// one by delta, with orgError 1-3 delta, meets the outer sheet at its exact distance. The
// shell's mid-surface, where grad f vanishes, is then within the origin's uncertainty's
// reach, so the self-root rule asked whether c_1 (and c_2) are zero within it, as on a
// squared sphere, and took the crossings for a multiple root: its window swallowed the
// outer sheet along grazing rays (multipleRootWindow's splitCluster now tells sheets apart
// by f's sign changes). Shells w = 1e-5..1e-3, delta 0.02-0.45 w, orgError up to a fourth
// of the outer sheet's distance w - delta (an origin within about twice orgError of it may
// be taken for one of its points), directions 0.01-0.5 rad out of the tangent plane; the
// outer sheet beyond the self-root window 2 orgError; closest hit and occlusion, double
// channel. Reference: the sphere of radius 1 + w along the ray (stable formula in long
// double).
TEST(EmbreeShadowOffset, AShellsOuterSheetIsNotTheOriginsCluster) {
  Device device;
  std::mt19937 rng(4747);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
  int rays = 0, crossing = 0, passing = 0;
  for (const double w : {1e-5, 1e-4, 1e-3}) {
    const double outer = (1.0 + w) * (1.0 + w);
    char equation[128];
    std::snprintf(equation, sizeof equation, "(x^2+y^2+z^2-1)*(x^2+y^2+z^2-%.17g)", outer);
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial(equation);
    desc.clip = ClipSphere{glm::dvec3(0.0), 1.5};
    const SurfaceScene scene(device, desc);
    for (int i = 0; i < 120; ++i) {
      const glm::dvec3 normal = randomUnit();
      const double delta = (0.02 + 0.43 * u(rng)) * w;
      const double orgError = std::min((1.0 + 2.0 * u(rng)) * delta, (w - delta) / 4.5);
      const glm::dvec3 o = (1.0 + delta) * normal;
      const double sinA = std::pow(10.0, -2.0 + 1.7 * u(rng));
      glm::dvec3 side = randomUnit();
      side = glm::normalize(side - glm::dot(side, normal) * normal);
      const glm::dvec3 dir = std::sqrt(1.0 - sinA * sinA) * side + sinA * normal;
      // The outer sphere's root ahead: |o + t d|^2 = outer with |o|^2 < outer (c < 0).
      using L = long double;
      const L b = L(o.x) * dir.x + L(o.y) * dir.y + L(o.z) * dir.z,
              a = L(dir.x) * dir.x + L(dir.y) * dir.y + L(dir.z) * dir.z,
              c = L(o.x) * o.x + L(o.y) * o.y + L(o.z) * o.z - L(outer);
      const double t = static_cast<double>((-b + std::sqrt(b * b - a * c)) / a);
      if (!(t > 4.0 * orgError)) continue;  // within the self-root window's reach
      ++rays;
      const RayD ray{o, dir, 0.0, 10.0, orgError};
      const HitD hit = intersectD(scene, ray);
      SCOPED_TRACE(testing::Message() << "w " << w << " ray " << i << " delta " << delta
                                      << " orgError " << orgError << " sin " << sinA);
      EXPECT_TRUE(hit.hit);
      // At t to the root's conditioning, 64 u times |f|'s scale (|p|^2 + 1)(|p|^2 + outer)
      // ~ 4 over |G'(t)| = (outer - 1) 2 |p . d| (p the sheet's point; plus 1e-9 t), also
      // where the ray passes its origin's sheet by (b^2 - a c' < 0, c' = |o|^2 - 1: no root
      // is the origin's; g / s had f = f(o)'s roots there, up to 23 % off in t).
      const L innerC = L(o.x) * o.x + L(o.y) * o.y + L(o.z) * o.z - 1;
      const bool crossesInner = b * b - a * innerC >= 0;
      ++(crossesInner ? crossing : passing);
      const glm::dvec3 p = o + t * dir;
      const double slope = (outer - 1.0) * 2.0 * std::abs(glm::dot(p, dir));
      if (hit.hit) {
        EXPECT_NEAR(hit.t, t, 1e-9 * t + 64.0 * 0x1p-53 * 4.0 / slope);
      }
      RayD shadow = ray;
      shadow.tfar = (1.0 + 1e-6) * (hit.hit ? hit.t : t);
      HitD occ;
      IntersectContext ctx;
      initIntersectContext(&ctx, &shadow, &occ);
      RTCRay r = makeRayHit(ctx).ray;
      rtcOccluded1(scene, &ctx.base, &r);
      EXPECT_TRUE(occ.hit);
    }
  }
  EXPECT_GT(rays, 300);
  std::printf("%d rays crossing their origin's sheet, %d passing it by\n", crossing, passing);
}

// Surfaces of multiplicity m (f = h^m: a double or triple plane, a squared sphere): a ray
// leaving a point of the surface outwards meets nothing, in either channel, for closest hit
// and occlusion in either order; one leaving the sphere inwards meets its far side. The
// origin lies off h = 0 by its rounding, so g's coefficients c_1..c_(m-1) at the origin are
// small but not zero; the walk starts past a window over the origin's whole cluster of
// roots (multipleRootWindow, ray_roots.cpp). Dividing out c_0 alone left a root at 2 t*
// (3 t* for m = 3), t* the origin's own crossing: 3552 of 20000 leaving rays hit the double
// plane there.
struct MultipleCase {
  const char* equation;
  bool sphere;  // the unit sphere's h, else the plane 0.6 x + 0.8 y - 0.1
  // Rays inwards too. Not for m = 4: the far side's fourfold root at 1e-2 to 1e-1 rad from
  // the tangent plane, within its noise band's reach, is missed by 15 of 100 such rays
  // (12 before session 43, and 36 more found over 1e-3 off): README's known limitations
  // (docs/status.md).
  bool inward = true;
};
class EmbreeShadowMultiple : public ::testing::TestWithParam<MultipleCase> {};

TEST_P(EmbreeShadowMultiple, LeavingRaysMeetOnlyTheFarSide) {
  const MultipleCase& k = GetParam();
  Device device;
  SurfaceDesc desc;
  desc.polynomial = parsePolynomial(k.equation);
  desc.clip = ClipSphere{glm::dvec3(0.0), 1.5};
  const SurfaceScene scene(device, desc);
  std::mt19937 rng(4343);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
  const glm::dvec3 planeNormal(0.6, 0.8, 0.0);
  int outward = 0, inward = 0;
  for (int i = 0; i < 400; ++i) {
    // A point of the surface and its exact normal; a direction at angle asin(s) to the
    // tangent plane, s log-uniform in [1e-4, 1e-1], outwards (or inwards for a quarter of
    // the sphere's rays, at s >= 1e-2 so that the far side lies clear of the noise band).
    glm::dvec3 p, normal;
    if (k.sphere) {
      normal = randomUnit();
      p = normal;
    } else {
      normal = planeNormal;
      const glm::dvec3 along = glm::dvec3(-0.8, 0.6, 0.0) * (2.0 * u(rng) - 1.0) +
                               glm::dvec3(0.0, 0.0, 2.0 * u(rng) - 1.0);
      p = 0.1 * planeNormal + along;
    }
    const bool in = k.sphere && k.inward && i % 4 == 0;
    const double sinA = in ? 1e-2 + 0.09 * u(rng) : std::pow(10.0, -4.0 + 3.0 * u(rng));
    glm::dvec3 w = randomUnit();
    w = glm::normalize(w - glm::dot(w, normal) * normal);
    const glm::dvec3 dir = std::sqrt(1.0 - sinA * sinA) * w + (in ? -sinA : sinA) * normal;
    const glm::vec3 pf(p), df(dir);
    // The exact sphere's far side along the float ray (in double: its error is far below
    // the tolerance), else nothing.
    const glm::dvec3 po(pf), dd(df);
    const double b = glm::dot(po, dd), c = glm::dot(po, po) - 1.0, a = glm::dot(dd, dd);
    const double farT = (-b + std::sqrt(b * b - a * c)) / a;
    auto check = [&](bool hit, double t, const char* what) {
      if (in) {
        EXPECT_TRUE(hit) << what << " " << i;
        if (hit) {
          EXPECT_NEAR(t, farT, 1e-3) << what << " " << i;
        }
      } else {
        EXPECT_FALSE(hit) << what << " " << i << " t " << t << " sin " << sinA;
      }
    };
    (in ? inward : outward)++;
    // ---- Float channel: occlusion, closest hit, occlusion again ----------------------------
    const RTCRayHit rayHit = makeRay(pf, df, 0.0f, 10.0f);
    const bool occluded = occluded1(scene, rayHit.ray);
    const RTCRayHit h = intersect1(scene, rayHit);
    const bool hit = h.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    check(hit, h.ray.tfar, "float");
    EXPECT_EQ(occluded, hit) << "float occlusion first " << i;
    EXPECT_EQ(occluded1(scene, rayHit.ray), hit) << "float occlusion after " << i;
    // ---- Double channel: the float point with a host bound, and the double point --------
    for (const auto& [origin, bound] :
         {std::pair{po, 1e-7}, std::pair{p, 4.0 * kUnitRoundoff * glm::length(p)}}) {
      RayD ray{origin, dir, 0.0, 10.0, bound};
      const HitD hd = intersectD(scene, ray);
      check(hd.hit, hd.t, "double");
      RTCRay shadow = makeRayHit(ray).ray;
      IntersectContext ctx;
      HitD occ;
      initIntersectContext(&ctx, &ray, &occ);
      rtcOccluded1(scene, &ctx.base, &shadow);
      EXPECT_EQ(occ.hit, hd.hit) << "double occlusion " << i;
    }
  }
  EXPECT_GT(outward, 250);
}

INSTANTIATE_TEST_SUITE_P(
    Multiplicity, EmbreeShadowMultiple,
    ::testing::Values(MultipleCase{"0.6*x + 0.8*y - 0.1", false},
                      MultipleCase{"(0.6*x + 0.8*y - 0.1)^2", false},
                      MultipleCase{"(0.6*x + 0.8*y - 0.1)^3", false},
                      MultipleCase{"x^2 + y^2 + z^2 - 1", true},
                      MultipleCase{"(x^2 + y^2 + z^2 - 1)^2", true},
                      MultipleCase{"(x^2 + y^2 + z^2 - 1)^3", true},
                      MultipleCase{"(x^2 + y^2 + z^2 - 1)^4", true, false},
                      MultipleCase{"(x^2 + y^2 + z^2 - 1) * (x^2 + y^2 + z^2 - 16)", true}),
    [](const ::testing::TestParamInfo<MultipleCase>& param) {
      return std::string(param.param.sphere ? "Sphere" : "Plane") + std::to_string(param.index);
    });

// The same with tnear < 0 (a host whose segment starts behind its origin): the origin's own
// roots, kept in the search span behind it, are skipped inside the self-root window by the
// walk (surface_intersect.cpp), and the far side is the hit. Double rays leaving an exact
// point of the sphere (m = 1, 2, 3; the quadric path too) inwards, orgError 1e-12, against
// the closed form -2 p.d (to u^(1/m)). Without the walk's skip, 27 of 200 rays on the double
// sphere reported the origin (t ~ 1e-16; the mutation audit of session 55).
TEST(EmbreeShadowMultipleBehind, LeavingRaysWithNegativeTnearMeetOnlyTheFarSide) {
  Device device;
  // The far side's accuracy is that of an m-fold root, u^(1/m) of the scale.
  for (const auto& [equation, tolerance] :
       {std::pair{"x^2 + y^2 + z^2 - 1", 1e-9}, std::pair{"(x^2 + y^2 + z^2 - 1)^2", 1e-6},
        std::pair{"(x^2 + y^2 + z^2 - 1)^3", 1e-4}}) {
    for (const bool quadric : {true, false}) {
      SurfaceDesc desc;
      desc.polynomial = parsePolynomial(equation);
      desc.clip = ClipSphere{glm::dvec3(0.0), 1.5};
      desc.options.quadricCallbacks = quadric;
      const SurfaceScene scene(device, desc);
      std::mt19937 rng(2);
      std::normal_distribution<double> n;
      auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
      for (int k = 0; k < 200; ++k) {
        const glm::dvec3 p = randomUnit();
        const glm::dvec3 d = glm::normalize(-p + 0.5 * randomUnit());
        const double farT = -2.0 * glm::dot(p, d);  // the sphere's other root from p
        for (const double tnear : {0.0, -0.25}) {
          const HitD hit = intersectD(scene, RayD{p, d, tnear, 10.0, 1e-12});
          ASSERT_TRUE(hit.hit) << equation << " " << k << " tnear " << tnear;
          EXPECT_NEAR(hit.t, farT, tolerance)
              << equation << " quadric " << quadric << " ray " << k << " tnear " << tnear;
        }
      }
    }
  }
}

// A host's origin off the surface by delta, within the self-root rule's reach (|f(o)| up to
// twice what orgError moves f by): the rule takes the root near the origin for the
// origin's own and divides it out. The far side must then be where the ray from that
// origin meets it, to the solver's accuracy: dividing by s (as if f(o) were 0) moved every
// other root by about the near one (Vieta: the roots' sum is unchanged), and the far
// side of a unit sphere clipped at its own radius left the clip region (lost) for delta
// >= 1e-4 with orgError 0.6 delta. Origins inside and outside by delta (log-uniform 1e-12
// .. 1e-3), orgError 0.6, 1 and 2 delta, directions at least 0.1 rad into the sphere, the
// quadric path and the generic one (also on the sphere times a positive quadric, degree 4),
// clip radius 1 and 1.25; closest hit and occlusion just before and after it, double
// channel. Reference: the exact sphere's far root along the ray (stable formula in long
// double).
struct OffsetCase {
  const char* equation;
  bool quadricPath;
};
class EmbreeShadowOffset : public ::testing::TestWithParam<OffsetCase> {};

TEST_P(EmbreeShadowOffset, FarSideFromAnOriginOffTheSurfaceIsWhereTheRayMeetsIt) {
  const OffsetCase& k = GetParam();
  Device device;
  std::mt19937 rng(4646);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
  int rays = 0, worst = -1;
  double worstError = 0.0;
  for (const double clipRadius : {1.0, 1.25}) {
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial(k.equation);
    desc.clip = ClipSphere{glm::dvec3(0.0), clipRadius};
    desc.options.quadricPath = k.quadricPath;
    const SurfaceScene scene(device, desc);
    for (int i = 0; i < 300; ++i) {
      const glm::dvec3 normal = randomUnit();
      const double delta = std::pow(10.0, -12.0 + 9.0 * u(rng));
      const double side = i % 2 ? 1.0 : -1.0;
      const double bound = delta * (i % 3 == 0 ? 0.6 : i % 3 == 1 ? 1.0 : 2.0);
      const glm::dvec3 o = (1.0 + side * delta) * normal;
      const double sinA = 0.1 + 0.85 * u(rng);
      glm::dvec3 w = randomUnit();
      w = glm::normalize(w - glm::dot(w, normal) * normal);
      const glm::dvec3 dir = std::sqrt(1.0 - sinA * sinA) * w - sinA * normal;
      // The far root of |o + t d|^2 = 1 (c < 0 or tiny: the larger root, b < 0).
      using L = long double;
      const L b = L(o.x) * dir.x + L(o.y) * dir.y + L(o.z) * dir.z,
              a = L(dir.x) * dir.x + L(dir.y) * dir.y + L(dir.z) * dir.z,
              c = L(o.x) * o.x + L(o.y) * o.y + L(o.z) * o.z - 1;
      const L q = -b + std::sqrt(b * b - a * c);
      const double farT = static_cast<double>(q / a);
      const RayD ray{o, dir, 0.0, 10.0, bound};
      const HitD hit = intersectD(scene, ray);
      SCOPED_TRACE(testing::Message() << "clip " << clipRadius << " ray " << i << " delta " << delta
                                      << " side " << side << " orgError " << bound);
      ++rays;
      EXPECT_TRUE(hit.hit);
      if (!hit.hit) continue;
      const double error = std::abs(hit.t - farT) / farT;
      EXPECT_LT(error, 1e-13) << "t " << hit.t << " far " << farT;
      if (error > worstError) worstError = error, worst = i;
      for (const double f : {1.0 - 1e-9, 1.0 + 1e-9}) {
        RayD shadow = ray;
        shadow.tfar = f * farT;
        HitD occ;
        IntersectContext ctx;
        initIntersectContext(&ctx, &shadow, &occ);
        RTCRay r = makeRayHit(ctx).ray;
        rtcOccluded1(scene, &ctx.base, &r);
        EXPECT_EQ(occ.hit, f > 1.0) << "occlusion to " << f << " far";
      }
    }
  }
  EXPECT_EQ(rays, 600);
  std::printf("worst relative error of the far side %.3g (ray %d)\n", worstError, worst);
}

// The review of session 47's first version of the shell split and the nearly tangent
// division (rays from its repros, references by exact rational restriction and mpmath):
// (a) a torus shell's far sheet from an origin 3.6e-9 off its sheet, 5.7e-5 rad from its
// tangent plane, double channel: dividing out the origin's root with r's uncertainty in
// every quotient coefficient's bound (dr |q_(k+1)|, dr = 6.6e-8 at its tiny slope) put a
// hit in the gap between the sheets (1.28800 instead of 1.28733); Sarti's float leaving
// rays likewise hit points on no surface. (b) Cayley's float leaving ray 4.5e-6 rad from
// its tangent plane crosses its own sheet either side of the origin (-0.0087, +0.0062); the
// ray from the surface point meets nothing ahead: both crossings are the origin's. (c) A
// double plane times a sphere, orgError 1.7e-3 and 3e-3: a long cluster window with the
// sphere's crossings in it; the split reported a point 2.6-3.6 orgError off both surfaces.
// (d) The second review: the quadric path kept no origin window (faad847's, the walk's);
// (e) G restored for rays passing their sheet by lost the sheet's re-crossing (f58089f);
// (f) the third review: a nearly tangent division where the quadratic models G badly.
TEST(EmbreeShadowOffset, ReviewedNearlyTangentLeavingRays) {
  Device device;
  auto hex = [](const char* text) { return std::strtod(text, nullptr); };
  // A gallery surface in its clip sphere.
  auto gallery = [](const char* name) {
    const GallerySurface* g = findGallerySurface(name);
    SurfaceDesc desc;
    if (g == nullptr) return desc;
    desc.polynomial = g->build();
    desc.clip = ClipSphere{glm::dvec3(0.0), g->clipRadius};
    return desc;
  };
  {  // (a) torus shell, double channel; exact first root 1.2873290181137182
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial(
        "((x^2+y^2+z^2+1-0.16)^2-4*(x^2+y^2))*((x^2+y^2+z^2+1-(0.4+1e-3)^2)^2-4*(x^2+y^2))");
    desc.clip = ClipSphere{glm::dvec3(0.0), 1.6};
    const SurfaceScene scene(device, desc);
    const glm::dvec3 o(hex("-0x1.bfa3dda3882b4p-1"), hex("0x1.5ac408fcec8dap-4"),
                       hex("-0x1.8748e5a8a26ebp-2"));
    const glm::dvec3 d(hex("0x1.cb76b52f363b7p-1"), hex("0x1.627a87cb03794p-2"),
                       hex("0x1.182aa63d81bd1p-2"));
    for (const double orgError :
         {2.162179806922718e-09, 6.4865394207681544e-09, 1.9459618262304462e-08}) {
      const HitD hit = intersectD(scene, RayD{o, d, 0.0, 10.0, orgError});
      EXPECT_TRUE(hit.hit) << "torus shell, orgError " << orgError;
      if (hit.hit) {
        EXPECT_NEAR(hit.t, 1.2873290181137182, 1e-9) << "torus shell, orgError " << orgError;
      }
    }
  }
  {  // (a) Sarti, float channel: no root in the clip span; the second one's at 4.9477537615
    const SurfaceScene scene(device, gallery("sarti-dodecic"));
    const RTCRayHit none = intersect1(
        scene,
        makeRay(glm::vec3(hex("0x1.0bd58p+1"), hex("0x1.8f9038p-1"), hex("-0x1.fe28bcp-1")),
                glm::vec3(hex("-0x1.d4d0dep-1"), hex("-0x1.0a7a8p-3"), hex("0x1.8572c2p-2"))));
    EXPECT_EQ(none.hit.geomID, RTC_INVALID_GEOMETRY_ID) << "Sarti: t " << none.ray.tfar;
    const RTCRayHit far = intersect1(
        scene,
        makeRay(glm::vec3(hex("0x1.48829p-1"), hex("-0x1.6de4d4p+0"), hex("0x1.1154ep+1")),
                glm::vec3(hex("-0x1.23d48p-2"), hex("0x1.ea215ap-2"), hex("-0x1.a93374p-1"))));
    EXPECT_NE(far.hit.geomID, RTC_INVALID_GEOMETRY_ID);
    EXPECT_NEAR(far.ray.tfar, 4.9477537615, 1e-5);
  }
  {  // (b) Cayley, float channel: nothing ahead before 0.03 (the sheet's pair is the origin's)
    const SurfaceScene scene(device, gallery("cayley-cubic"));
    const RTCRayHit rh = intersect1(
        scene,
        makeRay(glm::vec3(hex("-0x1.7759p-7"), hex("-0x1.fffdap-1"), hex("-0x1.7c61p-5")),
                glm::vec3(hex("-0x1.e9c7b8p-1"), hex("-0x1.173262p-10"), hex("0x1.2a63c4p-2"))));
    EXPECT_FALSE(rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && rh.ray.tfar < 0.03f)
        << "Cayley: t " << rh.ray.tfar;
  }
  {  // (d) quadric path (quadricLane): nothing within 2 orgError of origins between two
     // planes through a line (the exact roots of line 1 are -1.845e-15 and 2.137e-15)
    struct PlanePair {
      const char* equation;
      const char* o[3];
      const char* d[3];
      const char* orgError;
    };
    const PlanePair pairs[] = {
        {"x^2-1e-2*y^2",
         {"-0x1p-52", "0x1.34p-46", "0x1.eap-44"},
         {"0x1.b5d7711f54607p-1", "-0x1.f544a0bb34635p-2", "-0x1.5d337bb9db2f9p-3"},
         "0x1.1ffffffffffa7p-49"},
        {"x^2-1e-6*y^2",
         {"0", "0x1.2944p-39", "0x1.0e81ebp-27"},
         {"-0x1.c332575b35434p-1", "0x1.386266b8142cap-4", "-0x1.ddaa1ae21e2f5p-2"},
         "0x1.1ffffffe34d3fp-49"},
    };
    for (const PlanePair& c : pairs) {
      SurfaceDesc desc;
      desc.polynomial = parsePolynomial(c.equation);
      desc.clip = ClipSphere{glm::dvec3(0.0), 1.0};
      const SurfaceScene scene(device, desc);
      const glm::dvec3 o(hex(c.o[0]), hex(c.o[1]), hex(c.o[2]));
      const glm::dvec3 d(hex(c.d[0]), hex(c.d[1]), hex(c.d[2]));
      const double orgError = hex(c.orgError);
      const HitD hit = intersectD(scene, RayD{o, d, 0.0, 10.0, orgError});
      EXPECT_FALSE(hit.hit && hit.t <= 2.0 * orgError) << c.equation << ": t " << hit.t;
    }
  }
  {  // (e) nearly tangent rays that pass their origin's sheet by: the ray from the exact hit
     // point re-crosses the sheet just ahead, which g / s finds (g = G from the rounded
     // origin found the far side: the second review). Torus, float, from a float hit 7.4e-8
     // inside, 1.4e-4 rad: 4.3549e-4 (from p0); Roman surface, double, 3.7e-9 rad: 1.20987e-8.
    const SurfaceScene scene(device, gallery("torus"));
    const RTCRayHit rh = intersect1(
        scene,
        makeRay(glm::vec3(hex("-0x1.950f7p-1"), hex("-0x1.767adcp-4"), hex("0x1.6091acp-2")),
                glm::vec3(hex("0x1.322844p-3"), hex("-0x1.fa232cp-1"), hex("-0x1.50a4fcp-6"))));
    EXPECT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
    EXPECT_NEAR(rh.ray.tfar, 4.3549e-4, 1e-7) << "torus";
    const SurfaceScene romanScene(device, gallery("roman-surface"));
    const RayD ray{
        {hex("-0x1.793d04b105e6p-5"), hex("0x1.379bb4facce7p-4"), hex("-0x1.cedf2f326p-9")},
        {hex("0x1.e61885d11fe16p-1"), hex("-0x1.34ea885cd3433p-2"), hex("0x1.658e09284a2dfp-4")},
        0.0,
        10.0,
        hex("0x1.a904ad61f9b48p-50")};
    const HitD hit = intersectD(romanScene, ray);
    EXPECT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 1.2098654957501098e-08, 1e-13) << "Roman surface";
  }
  {  // (f) Clebsch cubic, float: the sheet's re-crossing ahead (from the exact hit point
     // 0.0098623 and 0.0126923; g / s: 0.0098833, 0.0127886), where the quadratic's root
     // was no model of G and a crossing behind was divided out (a miss: the third review)
    const SurfaceScene scene(device, gallery("clebsch-cubic"));
    const float rays[2][6] = {
        {-0.03516697883605957f, 1.0245974063873291f, -0.72387957572937012f, -0.79485493898391724f,
         -0.58844220638275146f, -0.14812642335891724f},
        {0.66413140296936035f, -0.13439583778381348f, -0.44172382354736328f, -0.66937160491943359f,
         -0.73940908908843994f, 0.072220750153064728f}};
    const double expected[2] = {0.0098623039, 0.01269225};
    for (int i = 0; i < 2; ++i) {
      const RTCRayHit rh =
          intersect1(scene, makeRay(glm::vec3(rays[i][0], rays[i][1], rays[i][2]),
                                    glm::vec3(rays[i][3], rays[i][4], rays[i][5])));
      EXPECT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << "Clebsch ray " << i;
      EXPECT_NEAR(rh.ray.tfar, expected[i], 2e-4) << "Clebsch ray " << i;
    }
  }
  {  // (c) x^2 (x^2 + y^2 + z^2 - 0.7): a miss, or the sphere at 0.24373875335662676
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial("x^2*(x^2+y^2+z^2-0.7)");
    desc.clip = ClipSphere{glm::dvec3(0.0), 1.0};
    const SurfaceScene scene(device, desc);
    const glm::dvec3 o(-0.00093932706531650112, -0.37760151702420708, -0.48618107768265229);
    const glm::dvec3 d(-0.022072911275646433, -0.92122238295583481, -0.38840971631640536);
    for (const double orgError : {0.0017128587792939762, 0.003}) {
      const HitD hit = intersectD(scene, RayD{o, d, 0.0, 10.0, orgError});
      if (hit.hit) {
        EXPECT_NEAR(hit.t, 0.24373875335662676, 1e-9) << "double plane, orgError " << orgError;
      }
    }
  }
}

// The same for rays leaving nearly tangentially (sin of the angle to the tangent plane
// 1.45-2.5 sqrt(delta), where the ray crosses the sphere at all: 1.41), where -c_0 / c_1 is
// no estimate of the origin's root (rho above 1/8: divideNearTangentRoot finds it among the
// crossings near the origin; the quadric path by its stable formula, nearTangentRootsApart):
// g / s moved the far side by the origin's root, delta / sin ~ sqrt(delta) (3e-3 from 1e-6
// off with orgError 1e-6). Origins outside by delta (1e-10 .. 1e-5) heading in, and inside
// by delta heading along; clip radius 1.25. Reference: the exact sphere's far root along
// the ray, to its conditioning (64 u times |f|'s scale, 8, over |G'(t)| = |grad f . d| at
// the root).
TEST_P(EmbreeShadowOffset, GrazingFarSideFromAnOriginOffTheSurface) {
  const OffsetCase& k = GetParam();
  Device device;
  std::mt19937 rng(4748);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto randomUnit = [&] { return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng))); };
  SurfaceDesc desc;
  desc.polynomial = parsePolynomial(k.equation);
  desc.clip = ClipSphere{glm::dvec3(0.0), 1.25};
  desc.options.quadricPath = k.quadricPath;
  const SurfaceScene scene(device, desc);
  for (int i = 0; i < 400; ++i) {
    const glm::dvec3 normal = randomUnit();
    const double delta = std::pow(10.0, -10.0 + 5.0 * u(rng));
    const double side = i % 2 ? 1.0 : -1.0;
    const double orgError = delta * (0.6 + 1.4 * u(rng));
    const glm::dvec3 o = (1.0 + side * delta) * normal;
    const double sinA = (1.45 + 1.05 * u(rng)) * std::sqrt(delta);
    glm::dvec3 w = randomUnit();
    w = glm::normalize(w - glm::dot(w, normal) * normal);
    const glm::dvec3 dir = std::sqrt(1.0 - sinA * sinA) * w - sinA * normal;
    using L = long double;
    const L b = L(o.x) * dir.x + L(o.y) * dir.y + L(o.z) * dir.z,
            a = L(dir.x) * dir.x + L(dir.y) * dir.y + L(dir.z) * dir.z,
            c = L(o.x) * o.x + L(o.y) * o.y + L(o.z) * o.z - 1;
    const double farT = static_cast<double>((-b + std::sqrt(b * b - a * c)) / a);
    const glm::dvec3 p = o + farT * dir;
    const double slope = std::abs(glm::dot(desc.polynomial.gradient(p), dir));
    const RayD ray{o, dir, 0.0, 10.0, orgError};
    const HitD hit = intersectD(scene, ray);
    SCOPED_TRACE(testing::Message() << "ray " << i << " delta " << delta << " side " << side
                                    << " orgError " << orgError << " sin " << sinA);
    EXPECT_TRUE(hit.hit);
    if (hit.hit) {
      EXPECT_NEAR(hit.t, farT, 1e-9 * farT + 64.0 * 0x1p-53 * 8.0 / slope);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Paths, EmbreeShadowOffset,
                         ::testing::Values(OffsetCase{"x^2 + y^2 + z^2 - 1", true},
                                           OffsetCase{"x^2 + y^2 + z^2 - 1", false},
                                           OffsetCase{"(x^2 + y^2 + z^2 - 1) * (x^2 + 2*y^2 + 1)",
                                                      false}),
                         [](const ::testing::TestParamInfo<OffsetCase>& param) {
                           return std::string(param.param.quadricPath ? "Quadric" : "Generic") +
                                  std::to_string(param.index);
                         });

std::vector<std::string_view> galleryNames() {
  std::vector<std::string_view> names;
  for (const GallerySurface& s : gallery()) names.push_back(s.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Gallery, EmbreeShadow, ::testing::ValuesIn(galleryNames()),
                         [](const ::testing::TestParamInfo<std::string_view>& param) {
                           std::string name(param.param);
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace algray::test
