// Numerical-stability stress suite, stepping hosts: a host stepping along a ray through
// every hit (tnear = the previous hit), from one double past it, or walking on with a filter
// that rejects roots, meets each root of f once, where f has it, near singular lines, at
// grazing points and roots of odd multiplicity, with and without the origin cache. Expected
// results are closed forms or the MPFR reference of tests/support/reference.h.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "algray/gallery.h"
#include "algray/parser.h"
#include "support/stress.h"

namespace algray::test {
namespace {

// The hits of a host stepping along ray (tnear = the previous hit), stopping one past the
// degree.
std::vector<double> steppingHits(OneSurface& s, RayD ray, int degree, const std::string& what) {
  std::vector<double> hits;
  while (static_cast<int>(hits.size()) <= degree) {
    const auto hit = s.intersect(ray, what);
    if (!hit) break;
    hits.push_back(hit->t);
    ray.tnear = hit->t;
  }
  return hits;
}

// Steps along ray (its k-th) and counts it in `over` where it meets more roots than the
// degree, reporting the first three.
void expectEachRootOnce(OneSurface& s, const RayD& ray, int degree, const std::string& what, int k,
                        int& over) {
  const std::vector<double> hits = steppingHits(s, ray, degree, what);
  if (static_cast<int>(hits.size()) <= degree || ++over > 3) return;
  std::string list;
  for (const double t : hits) list += " " + std::to_string(t);
  ADD_FAILURE() << what << " ray " << k << ": more hits than the degree " << degree << ":" << list;
}

const glm::dmat4 kSteppingTransform =
    glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, -0.2, 0.1)), 0.7,
                glm::dvec3(1.0, 2.0, 3.0)) *
    glm::scale(glm::dmat4(1.0), glm::dvec3(1.3));

// o + t d in object space moved to world space by kSteppingTransform where `transformed`.
RayD steppingRay(glm::dvec3 o, glm::dvec3 d, bool transformed) {
  if (transformed) {
    o = glm::dvec3(kSteppingTransform * glm::dvec4(o, 1.0));
    d = glm::dvec3(kSteppingTransform * glm::dvec4(d, 0.0));
  }
  return rayD(o, d);
}

// A host stepping along a ray (tnear = the previous hit) through every hit meets each root
// once: a line meets a surface of degree m at most m times. The gallery from 3 radii, from
// its hits (leaving rays) and from 0.3 radii inside, plain and under a transform; rays near
// double lines below (ASteppingHostNearDoubleLinesMeetsEachRootOnce).
TEST(StressShadow, ASteppingHostMeetsEachRootOnce) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  auto gaussian = [&] { return glm::dvec3{normal(rng), normal(rng), normal(rng)}; };
  for (const GallerySurface& g : gallery()) {
    for (const bool transformed : {false, true}) {
      SurfaceDesc desc = describe(g.build(), g.clipRadius);
      if (transformed) desc.transform = kSteppingTransform;
      const int degree = desc.polynomial.degree();
      const std::string what = std::string(g.name) + (transformed ? " (transformed)" : "");
      OneSurface s(desc);
      int over = 0;
      for (int k = 0; k < 150; ++k) {
        const double radius = g.clipRadius;
        const glm::dvec3 o = (k % 3 == 2 ? 0.3 : 3.0) * radius * glm::normalize(gaussian());
        RayD ray = steppingRay(o, 0.35 * radius * gaussian() - o, transformed);
        if (k % 3 == 1) {
          const auto first = s.intersect(ray, what);
          if (!first) continue;
          ray = leavingRayD(ray.org, ray.dir, first->t, gaussian());
        }
        expectEachRootOnce(s, ray, degree, what, k, over);
      }
      EXPECT_EQ(over, 0) << what;
    }
  }
}

// Surfaces with a double line along a coordinate axis: Steiner's Roman surface (x), Whitney's
// umbrella, Pluecker's conoid and the cross-cap (z).
struct DoubleLine {
  const char* equation;
  int axis;
};
constexpr DoubleLine kDoubleLines[] = {{"x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z", 0},
                                       {"x^2 - y^2*z", 2},
                                       {"x^2*z - y^2*z - 2*x*y", 2},
                                       {"4*x^2*(x^2+y^2+z^2+z) + y^2*(y^2+z^2-1)", 2}};

// A point of the double line in (-0.8, 0.8) moved 1e-12..1e-1 off it in a random direction.
glm::dvec3 nearDoubleLine(const DoubleLine& c, std::mt19937_64& rng,
                          std::normal_distribution<double>& normal,
                          std::uniform_real_distribution<double>& u) {
  glm::dvec3 target(0.0), off{normal(rng), normal(rng), normal(rng)};
  target[c.axis] = 0.8 * (2.0 * u(rng) - 1.0);
  off[c.axis] = 0.0;
  return target + std::pow(10.0, -1.0 - 11.0 * u(rng)) * glm::normalize(off);
}

// The same for rays aimed 1e-12..1e-1 from the double lines of Steiner's Roman surface,
// Whitney's umbrella, Pluecker's conoid and the cross-cap (from 3 and 0.3 clip radii, plain
// and under a transform). There the restriction placed the root just reported, 0.5 ulp
// before tnear, up to 1e-13 after it, past f's noise reach, and the host met it again, up
// to six times (without rootAtTnear's fallsBackOnTnear: 20-50 of each surface's 300 rays,
// plain or transformed, had more hits than the degree; the third review of session 48,
// session 49).
TEST(StressShadow, ASteppingHostNearDoubleLinesMeetsEachRootOnce) {
  for (const DoubleLine& c : kDoubleLines) {
    for (const bool transformed : {false, true}) {
      SurfaceDesc desc = describe(parsePolynomial(c.equation), 1.0);
      if (transformed) desc.transform = kSteppingTransform;
      const int degree = desc.polynomial.degree();
      const std::string what = std::string(c.equation) + (transformed ? " (transformed)" : "");
      OneSurface s(desc);
      std::mt19937_64 rng(3);
      std::normal_distribution<double> normal;
      std::uniform_real_distribution<double> u(0.0, 1.0);
      auto gaussian = [&] { return glm::dvec3{normal(rng), normal(rng), normal(rng)}; };
      int over = 0;
      for (int k = 0; k < 300; ++k) {
        const glm::dvec3 o = (k % 2 == 1 ? 0.3 : 3.0) * glm::normalize(gaussian());
        const glm::dvec3 target = nearDoubleLine(c, rng, normal, u);
        expectEachRootOnce(s, steppingRay(o, target - o, transformed), degree, what, k, over);
      }
      EXPECT_EQ(over, 0) << what;
    }
  }
}

// The ray o + t d through f (clip sphere of radius 1), asked again with tnear = its first
// hit, or one double past it (`doublePast`), with and without the origin cache, meets the
// MPFR reference's first root past tnear (tests/support/reference.h), within 1e-9.
void expectNextHitIsFsNextRoot(const Polynomial& f, const glm::dvec3& o, const glm::dvec3& d,
                               bool doublePast, const std::string& name) {
  for (const bool cache : {false, true}) {
    SurfaceDesc desc = describe(f, 1.0);
    desc.options.originCache = cache;
    OneSurface s(desc);
    const std::string what = name + (cache ? ", origin cache" : "");
    const auto first = s.intersect(rayD(o, d), what);
    ASSERT_TRUE(first) << what;
    const double tnear = doublePast ? std::nextafter(first->t, kInfD) : first->t;
    const RayRef want = referenceFirstHit(f, o, d, tnear, kInfD, glm::dvec3(0.0), 1.0);
    ASSERT_TRUE(want.hit);
    // The reference after tnear is f's root past the one just met (tnear lies after it).
    ASSERT_GT(want.t, first->t + 1e-9);
    const auto next = s.intersect(rayD(o, d, tnear), what);
    ASSERT_TRUE(next) << what;
    EXPECT_NEAR(next->t, want.t, 1e-9) << what << ", first hit " << first->t;
  }
}

// Past a root the restriction placed past f's noise reach of tnear (the host's last hit),
// the next hit is f's next root: the ray is searched again from that root, not the rest of
// g's list taken (settleBesideTnear's searchPast). A ray from inside the Roman surface's
// clip sphere crossing near a double line, stepping from its first hit 0.98356236363684379
// (f's root 0.983562363636839, 4.5e-15 before it): g about the span's middle placed that
// root again 1.05e-13 past tnear and listed 1.00000026 next, where f has roots at
// 1.0000000048 and 1.0000005193 (mpmath); the walk that dropped the repeat and took the
// list's next root reported 1.00000026 (session 49), and so did the origin cache's first
// root, polished back onto tnear, whose record was not searched past it (the session's
// review). Expected: the MPFR reference's first root past tnear
// (tests/support/reference.h), within its conditioning; with and without the cache.
TEST(StressShadow, PastARootPlacedBeyondTnearTheNextHitIsTheNextRoot) {
  const glm::dvec3 o(0x1.a7674d7f6de37p-4, -0x1.f41a8b95f7f56p-5, -0x1.1987deeb5a44fp-2);
  const glm::dvec3 d(-0x1.a7674dab2d815p-4, -0x1.1764c0ff37012p-2, 0x1.1987dedc11a79p-2);
  expectNextHitIsFsNextRoot(findGallerySurface("roman-surface")->build(), o, d, false, "roman");
}

// A grazing point is met once: a ray through the transformed Roman surface passes 1.2e-11
// past a double line, where f has a minimum 2,500 times its evaluation's noise (a complex
// pair; within what the transform's rounding of the origin allows, so the tangent rule
// reports it, README). A host stepping on from that hit met it again 3 and 1 ulps on, where
// f's rounding moved the polish: five hits for degree 4 without rootAtTnear's grazing form
// (session 50, oneGrazingPoint). Expected: each hit at least 1e-9 past the previous one.
TEST(StressShadow, AGrazingPointIsMetOnce) {
  OneSurface s([] {
    SurfaceDesc desc = describe(parsePolynomial("x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z"), 1.0);
    desc.transform = kSteppingTransform;
    return desc;
  }());
  const glm::dvec3 o(-0x1.d3d137f3ca332p-3, -0x1.7e6607d0efdf7p-5, 0x1.82a55c18567ebp-3);
  const glm::dvec3 d(0x1.d3d137f3b148p-3, -0x1.15dccd1acb168p-1, -0x1.82a55c183a56p-3);
  const std::vector<double> hits = steppingHits(s, steppingRay(o, d, true), 4, "roman");
  ASSERT_GE(hits.size(), 3u);
  EXPECT_LE(hits.size(), 4u);
  for (size_t i = 1; i < hits.size(); ++i)
    EXPECT_GT(hits[i] - hits[i - 1], 1e-9)
        << std::setprecision(17) << hits[i - 1] << " then " << hits[i];
}

// Past a root the walk skips (settled behind tnear, or tnear's own) the next hit is f's next
// root, not the next of g's list: a host stepping from one double past its last hit (the
// cross-cap from 1.7 clip radii, near its double line) got the settled first root behind
// tnear, and the walk took the next root of the list of g expanded about tnear,
// 0.99999999951908314, where the ray passes a complex pair 4e-9 from the axis (f there 3e6
// times its noise bound), before f's root 1.4591 (the second review of session 49); and
// where the first root was tnear's own within f's reach, g's list held a point between two
// roots 1e-8 apart (settleBesideTnear now searches past both kinds). The same for rays aimed
// 1e-12..1e-1 from the double lines of the Roman surface, Whitney's umbrella, Pluecker's
// conoid and the cross-cap, from 1.7 clip radii, stepping from one double past the first
// hit (without the search past, session 50: 10 of 107 compared Roman rays and 34 of 166
// cross-cap rays gave a point on no surface or skipped a root). Expected: the MPFR
// reference's first root past tnear (tests/support/reference.h), within 1e-9; rays whose
// reference root is ill-conditioned (cond >= 1e-11), or within 1e-9 of tnear, are not
// compared.
TEST(StressShadow, PastARootSettledBehindTnearTheNextHitIsFsNextRoot) {
  {
    const glm::dvec3 o(0x1.040148957e22fp+0, 0x1.4aea5c612c2c7p-1, 0x1.334755c7f2295p+0);
    const glm::dvec3 d(-0x1.040148d0259cbp+0, -0x1.4aea5c5c94b2bp-1, -0x1.35eb965b389cdp+0);
    expectNextHitIsFsNextRoot(parsePolynomial("4*x^2*(x^2+y^2+z^2+z) + y^2*(y^2+z^2-1)"), o, d,
                              true, "cross-cap");
  }
  for (const DoubleLine& c : kDoubleLines) {
    const Polynomial f = parsePolynomial(c.equation);
    OneSurface s(describe(f, 1.0));
    std::mt19937_64 rng(11);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const glm::dvec3 o = 1.7 * glm::normalize(glm::dvec3(1.1, 0.7, 1.3));
    int compared = 0, wrong = 0;
    for (int k = 0; k < 200; ++k) {
      const glm::dvec3 d = nearDoubleLine(c, rng, normal, u) - o;
      const auto first = s.intersect(rayD(o, d), c.equation);
      if (!first) continue;
      const double tnear = std::nextafter(first->t, kInfD);
      const RayRef want = referenceFirstHit(f, o, d, tnear, kInfD, glm::dvec3(0.0), 1.0);
      if (want.hit && !(want.cond < 1e-11 && want.t > tnear * (1.0 + 1e-9))) continue;
      ++compared;
      const auto next = s.intersect(rayD(o, d, tnear), c.equation);
      const bool same = want.hit ? next && std::abs(next->t - want.t) <= 1e-9 : !next;
      if (!same && ++wrong <= 3)
        ADD_FAILURE() << std::setprecision(17) << c.equation << " ray " << k << ", tnear " << tnear
                      << ": " << (next ? next->t : -1.0) << ", reference "
                      << (want.hit ? want.t : -1.0) << " (-1: no hit); d = " << std::hexfloat << d.x
                      << " " << d.y << " " << d.z;
    }
    EXPECT_EQ(wrong, 0) << c.equation << " (" << compared << " compared)";
    EXPECT_GT(compared, 50) << c.equation;
  }
}

// A host filter that rejects the next `gRejectOffers` roots offered (rejectOffers).
int gRejectOffers = 0;
void rejectOffers(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 && gRejectOffers-- > 0) args->valid[i] = 0;
}

// A host filter walking on past the root after a stepping host's hit (tnear = the hit, the
// filter rejecting the first root offered) meets f's next root, with the origin cache too:
// the search past the skipped root re-expanded the cached g about that root, and the
// walk's later roots from that expansion were points beside complex pairs 5e-8 from the
// axis, near the Roman surface's double lines (1.0000004394929 where f has no root past
// 0.6425; 1.0000000602 between f's roots 0.99999999974 and 1.00000012; the review of
// session 50); occlusion with the same filter and tfar = 1.5 said "occluded" on the first.
// Expected: the MPFR reference's root after the rejected one (tests/support/reference.h),
// or none.
TEST(StressShadow, AFilterWalkPastASteppingHostsNextRootMeetsFsRoots) {
  const Polynomial f = parsePolynomial("x^2*y^2 + y^2*z^2 + z^2*x^2 - x*y*z");
  const struct {
    glm::dvec3 o, d;
  } rays[] = {{{0x1.20e47c3302ef9p+0, -0x1.4257ef7a28ae5p+0, -0x1.68df375a73ef8p-3},
               {-0x1.20e4754483b3fp+0, 0x1.e8d64ff3a8f52p+0, 0x1.68df1f804e03cp-3}},
              {{-0x1.39ba4ab4067cep+0, -0x1.19027cc0cee0dp+0, 0x1.b650aabf5b79dp-2},
               {0x1.39ba4ac2316f9p+0, 0x1.19027a7994406p+0, -0x1.ccb481ba9ebd5p-2}}};
  for (const bool cache : {false, true}) {
    for (const auto& [o, d] : rays) {
      SurfaceDesc desc = describe(f, 1.0);
      desc.options.originCache = cache;
      OneSurface s(desc);
      s.setFilter(&rejectOffers);
      const std::string what = cache ? "roman, origin cache" : "roman";
      gRejectOffers = 0;
      const auto first = s.intersect(rayD(o, d), what);
      ASSERT_TRUE(first) << what;
      const RayRef rejected =
          referenceFirstHit(f, o, d, first->t * (1 + 1e-9), kInfD, glm::dvec3(0.0), 1.0);
      ASSERT_TRUE(rejected.hit);
      const RayRef want =
          referenceFirstHit(f, o, d, rejected.t * (1 + 1e-9), kInfD, glm::dvec3(0.0), 1.0);
      gRejectOffers = 1;
      const auto next = s.intersect(rayD(o, d, first->t), what);
      EXPECT_EQ(next.has_value(), want.hit) << what << ", after " << first->t;
      if (next && want.hit) {
        EXPECT_NEAR(next->t, want.t, 1e-9) << what;
      }
      gRejectOffers = 1;
      EXPECT_EQ(s.occluded(rayD(o, d, first->t, 1.5)), want.hit && want.t < 1.5) << what;
    }
  }
}

// A camera with the origin cache inside the clip region (the rays of the second review of
// session 49, the cache primed by two rays from the camera first). (1) The closest hit asked
// again at once, and occlusion, agree with it: a ray from inside completes its root list in
// a cell before the hit (completeRoots), which moved the cached first root onto the
// re-centred restriction, where tShift + roots[0] lay 25 ulps from the t reported (a hit
// 0.022 from the camera, tShift ~0.6): the same query asked again got that other value, and
// in the review's harness occlusion with tfar one double past the hit said "no" (3,344 such
// checks on the gallery disagreed, none without the cache; RayRoots::firstT).
// (2) A host stepping on from a hit meets the next root, not the same one again: the walk's
// polish had left a Chmutov-8 hit at the near edge of f's noise region (f within its bound
// there), and the next query placed the root at its far edge, 2.1e-14 (191 ulps) on, past
// f's reach at tnear (rootAtTnear: f within its noise at both). Expected: the MPFR
// reference's first root past the hit (tests/support/reference.h).
TEST(StressShadow, CachedCameraRaysFromInsideTheClipRegion) {
  auto primed = [](const char* name) {
    SurfaceDesc desc =
        describe(findGallerySurface(name)->build(), findGallerySurface(name)->clipRadius);
    desc.options.originCache = true;
    return desc;
  };
  {
    const SurfaceDesc desc = primed("clebsch-cubic");
    OneSurface s(desc);
    const glm::dvec3 o(0x1.6f10def12a8bbp-2, 0x1.d32cbea74d6bep-3, 0x1.b1ce1ebfec769p-2);
    const glm::dvec3 d(0x1.3657a830c599cp-1, 0x1.82e55b76d1eb4p-3, -0x1.a79bf1b82c058p+0);
    s.intersect(rayD(o, -o));
    s.intersect(rayD(o, -o));
    const auto hit = s.intersect(rayD(o, d), "clebsch");
    ASSERT_TRUE(hit);
    EXPECT_TRUE(s.occluded(rayD(o, d, 0.0, std::nextafter(hit->t, kInfD)))) << hit->t;
    EXPECT_FALSE(s.occluded(rayD(o, d, 0.0, hit->t))) << hit->t;
    const auto again = s.intersect(rayD(o, d), "clebsch");
    ASSERT_TRUE(again);
    EXPECT_EQ(again->t, hit->t);
  }
  {
    const SurfaceDesc desc = primed("chmutov-8");
    OneSurface s(desc);
    const glm::dvec3 o(0x1.412ec313053a4p-2, 0x1.98c726d263be7p-3, 0x1.7b945ae7eee7cp-2);
    const glm::dvec3 d(-0x1.be8d3c11cfba1p-1, -0x1.d7138c5a26fccp-2, -0x1.cc36b2d74a05fp+0);
    s.intersect(rayD(o, -o));
    s.intersect(rayD(o, -o));
    const auto first = s.intersect(rayD(o, d, 0x1.b75516ac6c949p-5), "chmutov-8");
    ASSERT_TRUE(first);
    const auto next = s.intersect(rayD(o, d, first->t), "chmutov-8");
    const RayRef want =
        referenceFirstHit(desc.polynomial, o, d, first->t * (1 + 1e-9), kInfD, glm::dvec3(0.0),
                          findGallerySurface("chmutov-8")->clipRadius);
    ASSERT_TRUE(want.hit);
    ASSERT_TRUE(next) << "after " << first->t;
    EXPECT_NEAR(next->t, want.t, 1e-9) << "after " << first->t;
  }
}

// A sheet grazed just past the last hit is met (rootAtTnear's far-edge rule takes t's noise
// over the slope of tnear's root, not over the slope at t, which is 0 where the ray touches a
// sheet): the plane x = 0, then the unit sphere about (2^-30, 1, 0), which touches the x axis
// at x = 2^-30, along that axis from x = -1 (tnear = the plane's hit, t = 1); and the same
// with the sphere about (2^-20, 1, 0) from x = -1000. Without it the touching point went
// (the third review of session 49; 139 of 600 random planes with a sphere grazed just past
// them, f clear of its noise between the two). Expected: the touching point, exactly
// 1 + 2^-30 (or 1000 + 2^-20).
TEST(StressShadow, ASheetGrazedJustPastTheLastHitIsMet) {
  const struct {
    const char* equation;
    double from;  // the ray starts at x = -from along the x axis
  } cases[] = {{"x*((x-9.313225746154785e-10)^2+y^2-2*y+z^2)", 1.0},
               {"x*((x-9.5367431640625e-07)^2+y^2-2*y+z^2)", 1000.0}};
  for (const auto& c : cases) {
    OneSurface s(describe(parsePolynomial(c.equation), 2.0));
    const glm::dvec3 o(-c.from, 0.0, 0.0), d(1.0, 0.0, 0.0);
    const auto plane = s.intersect(rayD(o, d), c.equation);
    ASSERT_TRUE(plane) << c.equation;
    EXPECT_EQ(plane->t, c.from) << c.equation;
    const auto touch = s.intersect(rayD(o, d, plane->t), c.equation);
    ASSERT_TRUE(touch) << c.equation << ": no hit past the plane";
    const double want = c.from + (c.from == 1.0 ? 0x1p-30 : 0x1p-20);
    EXPECT_NEAR(touch->t, want, 1e-9 * c.from) << c.equation;
  }
}

// A host stepping through every hit of a surface of odd multiplicity m (a cylinder, a sphere
// and a plane, cubed; the cylinder to the fifth) meets each crossing once, within its noise
// region ((u E)^(1/m) wide, E the sum of |terms|: up to 1e-5 for m = 3, 1e-3 for m = 5): an
// m-fold root whose noise region holds tnear counts as at tnear (README). Without the
// noise-region form of settleBesideTnear's test (inTnearsNoiseRegion) each step settled a
// point further into the region (five hits for one crossing of the triple cylinder: the
// review of session 50), and before session 50 the next root of g's list stood in the region
// too: 48-84 of each case's 200 rays failed either way. Plain, and under a transform with
// the origin cache. Expected: the quadric's crossings (closed form), rays crossing twice
// within one noise region (grazing) not compared.
TEST(StressShadow, AHostSteppingThroughARootOfOddMultiplicityMeetsItOnce) {
  const struct {
    const char* equation;
    int m;
    glm::dvec3 scale;  // the quadric (p * scale)^2 = level, or the plane z = level
    double level;
  } cases[] = {{"(x^2+y^2-0.25)^3", 3, {1, 1, 0}, 0.25},
               {"(x^2+y^2-0.25)^5", 5, {1, 1, 0}, 0.25},
               {"(x^2+y^2+z^2-0.5)^3", 3, {1, 1, 1}, 0.5},
               {"(z-0.3)^3", 3, {0, 0, 0}, 0.3}};
  for (const auto& c : cases) {
    for (const bool transformed : {false, true}) {
      SurfaceDesc desc = describe(parsePolynomial(c.equation), 1.0);
      if (transformed) {
        desc.transform = kSteppingTransform;
        desc.options.originCache = true;
      }
      OneSurface s(desc);
      const std::string what = std::string(c.equation) + (transformed ? " (transformed)" : "");
      std::mt19937_64 rng(3);
      std::normal_distribution<double> normal;
      auto gaussian = [&] { return glm::dvec3{normal(rng), normal(rng), normal(rng)}; };
      int wrong = 0, crossings = 0;
      for (int k = 0; k < 200; ++k) {
        const glm::dvec3 o = 3.0 * glm::normalize(gaussian());
        const glm::dvec3 d = 0.6 * gaussian() - o;
        // The crossings in (0, inf) inside the clip sphere |o + t d| <= 1.
        std::vector<double> want;
        const auto inClip = [&](double t) { return t > 0 && glm::length(o + t * d) <= 1.0; };
        if (c.scale == glm::dvec3(0.0)) {
          const double t = (c.level - o.z) / d.z;
          if (inClip(t)) want.push_back(t);
        } else {
          const glm::dvec3 os = o * c.scale, ds = d * c.scale;
          const double a = glm::dot(ds, ds), b = glm::dot(os, ds), e = glm::dot(os, os) - c.level;
          const double disc = b * b - a * e;
          if (disc > 0)
            for (const double t : {(-b - std::sqrt(disc)) / a, (-b + std::sqrt(disc)) / a})
              if (inClip(t)) want.push_back(t);
        }
        // Two crossings within one noise region count once anywhere there (a grazing ray):
        // not compared.
        const double tolerance = c.m == 3 ? 1e-4 : 1e-2;
        if (want.size() == 2 && want[1] - want[0] <= 4 * tolerance) continue;
        crossings += static_cast<int>(want.size());
        const std::vector<double> hits =
            steppingHits(s, steppingRay(o, d, transformed), 2 * c.m, what);
        bool same = hits.size() == want.size();
        for (size_t i = 0; same && i < hits.size(); ++i)
          same = std::abs(hits[i] - want[i]) <= tolerance;
        if (!same && ++wrong <= 3) {
          std::string list;
          for (const double t : hits) list += " " + std::to_string(t);
          for (const double t : want)
            list += (t == want[0] ? ", crossings " : " ") + std::to_string(t);
          ADD_FAILURE() << what << " ray " << k << ": hits" << list;
        }
      }
      EXPECT_EQ(wrong, 0) << what;
      EXPECT_GT(crossings, 50) << what;
    }
  }
}

// A simple root just past a many-fold root's noise region is met, once, by a host stepping
// from the noise region's start: the planes x = 0.3 (6-, 7- and 9-fold) and x = 0.31, 0.32,
// 0.35, along the x axis from x = -1. f between the regions rises to 10-110 times its noise,
// but is within it at tnear, halfway and at the simple root: with only those three checks,
// inTnearsNoiseRegion took the simple root for tnear's and the host lost it (the second
// review of session 50). Expected: two hits, the second the simple root (closed form),
// within its conditioning (f' there is only 1e-12 for the 6-fold case).
TEST(StressShadow, ASimpleRootJustPastAManyFoldRootIsMet) {
  const struct {
    const char* equation;
    double simple;  // the simple root's x
  } cases[] = {
      {"(x-0.3)^7*(x-0.32)", 0.32}, {"(x-0.3)^9*(x-0.35)", 0.35}, {"(x-0.3)^6*(x-0.31)", 0.31}};
  for (const auto& c : cases) {
    OneSurface s(describe(parsePolynomial(c.equation), 2.0));
    const glm::dvec3 o(-1.0, 0.1, 0.2), d(1.0, 0.0, 0.0);
    const std::vector<double> hits = steppingHits(s, rayD(o, d), 10, c.equation);
    ASSERT_EQ(hits.size(), 2u) << c.equation << (hits.empty() ? "" : ", first hit ")
                               << (hits.empty() ? 0.0 : hits[0]);
    EXPECT_NEAR(hits[0], 1.3, 0.02) << c.equation;
    EXPECT_NEAR(hits[1], 1.0 + c.simple, 1e-4) << c.equation;  // (its conditioning: ~4e-5)
  }
}

}  // namespace
}  // namespace algray::test
