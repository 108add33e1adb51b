// The quadric path (plugin/embree/quadric_path.cpp) through Embree: its hits against the
// general path's and a generic walk of the roots, and its tight bounds against the surface
// (moved from embree_hits_test.cpp in session 21).
#include "../plugin/embree/quadric_path.h"
#include "embree_test_util.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace algray::test {
namespace {

using EmbreeQuadric = EmbreeFixture;

// A ray along a line of the surface (a ruling: g is identically zero) has no first point to
// report (docs/accuracy.md: no hit), on the quadric path as on the general one: rulings of a
// cone through its apex, of a cylinder and of a hyperboloid of one sheet, with dyadic
// points and directions (the line exactly in the surface), double channel (whose origin is
// exact; a float ray's is uncertain by 16 float ulps, within which such a line may cross
// the surface), closest hit and occlusion. (The quadric path reported the cone's apex, the
// point of the span nearest the object-space origin, on 4 of the 12 lines below.)
TEST_F(EmbreeQuadric, RaysAlongARulingHaveNoHit) {
  struct Ruling {
    glm::dvec3 point, dir;  // a point of the line and its direction, both dyadic
  };
  const struct {
    const char* equation;
    std::array<Ruling, 4> lines;
  } cases[] = {
      {"x^2+y^2-z^2",
       {{{{0, 0, 0}, {0.75, 1, 1.25}},
         {{0, 0, 0}, {-1, 0, 1}},
         {{0.75, 1, 1.25}, {0.75, 1, 1.25}},
         {{0, 0, 0}, {0, -0.5, 0.5}}}}},
      {"x^2+y^2-1",
       {{{{1, 0, 0}, {0, 0, 1}},
         {{0, -1, 0.5}, {0, 0, -1}},
         {{-1, 0, 0}, {0, 0, 0.5}},
         {{0, 1, 0}, {0, 0, 1}}}}},
      {"x^2+y^2-z^2-1",
       {{{{1, 0, 0}, {0, 1, 1}},
         {{1, 0, 0}, {0, -1, 1}},
         {{0, 1, 0}, {1, 0, 1}},
         {{0, -1, 0}, {1, 0, 1}}}}},
  };
  int rays = 0;
  for (const auto& c : cases) {
    for (const bool generic : {false, true}) {
      SurfaceDesc desc;
      desc.polynomial = parsePolynomial(c.equation);
      desc.clip = ClipSphere{glm::dvec3(0.0), 2.5};
      desc.options.quadricPath = !generic;
      SurfaceScene scene(device, desc);
      for (const Ruling& line : c.lines) {
        const RayD ray = unboundedRay(line.point - 4.0 * line.dir, line.dir);  // exact
        const HitD hit = intersectD(scene, ray);
        EXPECT_FALSE(hit.hit) << c.equation << " t " << hit.t << (generic ? " generic" : "");
        HitD shadowHit;
        IntersectContext context;
        initIntersectContext(&context, &ray, &shadowHit, scene);
        RTCRayHit shadow = makeRayHit(context);
        rtcOccluded1(scene, &context.base, &shadow.ray);
        EXPECT_NE(shadow.ray.tfar, -std::numeric_limits<float>::infinity())
            << c.equation << (generic ? " generic" : "");
        ++rays;
      }
    }
  }
  EXPECT_EQ(rays, 24);
}

TEST_F(EmbreeQuadric, PathMatchesGeneralPath) {
  // The closed-form quadric path against the general one (Taylor restriction, origin
  // cache, Newton polish on f): an independent computation of the same hits. Quadrics
  // with a singular point (cone apex), a vanishing leading term along rulings and axes
  // (cylinder, paraboloid, hyperboloid), and an ellipsoid; origins near and far (the
  // re-centring), shadow rays leaving the hit point (the self-root rule).
  const Polynomial x = X(), y = Y(), z = Z();
  const std::vector<Polynomial> quadrics = {
      x * x + 4.0 * y * y + 0.25 * z * z - Polynomial(1.0),  // ellipsoid
      x * x + y * y - z * z - Polynomial(0.25),              // hyperboloid of one sheet
      x * x + y * y - z * z,                                 // cone, apex at 0
      x * x + y * y - z,                                     // paraboloid
      x * x + z * z - Polynomial(0.5),                       // cylinder along y
      x * y + y * z + x * z - 0.2 * x + Polynomial(0.1),     // indefinite, mixed terms
      x + 0.5 * y - 0.2 * z - Polynomial(0.1),               // planes: degree 1 takes the
      3.0 * z,                                               // quadric path too (session 54)
  };
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  int compared = 0;
  for (size_t qi = 0; qi < quadrics.size(); ++qi) {
    SurfaceDesc fast, general;
    fast.polynomial = general.polynomial = quadrics[qi];
    fast.clip = general.clip = ClipSphere{{0, 0, 0}, 1.5};
    general.options.quadricPath = false;
    ScenePair pair(device, fast, general);
    auto& [a, b, sa, sb] = pair;
    for (double dist : {2.0, 4.0, 1e4}) {
      const glm::dvec3 eye = dist * glm::dvec3(randomDir());
      for (int i = 0; i < 150; ++i) {
        RayD ray;
        ray.org = i % 2 ? eye : dist * glm::dvec3(randomDir());  // shared and distinct origins
        ray.dir = glm::dvec3(u(rng), u(rng), u(rng)) - ray.org;
        ray.tfar = std::numeric_limits<double>::infinity();
        RTCRayHit rha, rhb;
        const HitD ha = intersectD(sa, ray, &rha), hb = intersectD(sb, ray, &rhb);
        SCOPED_TRACE(testing::Message() << "quadric " << qi << " dist " << dist << " ray " << i);
        // Grazing rays may differ by the noise rule; the rest must agree exactly on hit/miss.
        if (ha.hit != hb.hit) {
          const glm::dvec3 n = glm::normalize(ha.hit ? ha.Ng : hb.Ng);
          EXPECT_LT(std::abs(glm::dot(n, glm::normalize(ray.dir))), 1e-6) << "not grazing";
          continue;
        }
        if (!ha.hit) continue;
        ++compared;
        const double scale = glm::length(ray.dir);
        EXPECT_LT(scale * std::abs(ha.t - hb.t), 1e-12 + 16 * kUnitRoundoff * dist);
        EXPECT_GT(glm::dot(glm::normalize(ha.Ng), glm::normalize(hb.Ng)), 1 - 1e-9);
        // A shadow ray leaving the hit point sees the same next hit on both paths, and
        // never its own origin.
        RayD leave;
        leave.org = ray.org + ha.t * ray.dir;
        leave.orgError = gamma(3) * (glm::length(ray.org) + glm::length(ha.t * ray.dir));
        leave.dir = ray.dir;
        leave.tfar = std::numeric_limits<double>::infinity();
        RTCRayHit la, lb;
        const HitD na = intersectD(sa, leave, &la), nb = intersectD(sb, leave, &lb);
        if (na.hit) {
          EXPECT_GT(na.t * scale, 1e-9);
        }
        if (na.hit && nb.hit) {
          EXPECT_LT(scale * std::abs(na.t - nb.t), 1e-10);
        }
      }
    }
    EXPECT_EQ(a.callbackErrors(), 0u);
  }
  EXPECT_GT(compared, 600);
}

namespace {
// A filter that rejects every other candidate it sees (reset before each query, so the
// two paths compared see the same sequence).
int filterCalls = 0;
void rejectEveryOther(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 && (filterCalls++ % 2) == 0) args->valid[i] = 0;
}
}  // namespace

TEST_F(EmbreeQuadric, CallbacksMatchGenericWalk) {
  // The dedicated quadric callbacks (quadric_path.cpp) against the generic walk of the
  // same closed-form restriction (SurfaceOptions::quadricCallbacks = false): the same
  // coefficients and firstRoot's rules, so the same hits bit for bit, for float rays and
  // the double channel, eyes near and very far, shadow rays leaving the hit with
  // tnear = 0 (the self-root rule), transforms, a box clip, a filter that rejects every
  // other candidate (the next root), and 8-ray packets.
  const Polynomial x = X(), y = Y(), z = Z();
  struct Case {
    Polynomial f;
    ClipRegion clip;
    glm::dmat4 transform;
  };
  glm::dmat4 skew(1.0);
  skew[0][1] = 0.3;
  skew[1][2] = -0.2;
  skew[3] = glm::dvec4(0.5, -0.25, 2.0, 1.0);
  const std::vector<Case> cases = {
      {spherePolynomial(1.0), ClipSphere{{0, 0, 0}, 1.2}, glm::dmat4(1.0)},
      {x * x + 4.0 * y * y + 0.25 * z * z - Polynomial(1.0), ClipSphere{{0, 0, 0}, 1.5}, skew},
      {x * x + y * y - z * z - Polynomial(0.25), ClipBox{{-1, -1.2, -0.8}, {1.1, 1, 1}},
       glm::dmat4(1.0)},
      {x * x + y * y - z, ClipSphere{{0.1, 0, 0.3}, 1.0}, skew},
      {x * y + y * z + x * z - 0.2 * x + Polynomial(0.1), ClipSphere{{0, 0, 0}, 1.5},
       glm::dmat4(1.0)},
  };
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  int hits = 0;
  for (size_t ci = 0; ci < cases.size(); ++ci) {
    for (const bool filter : {false, true}) {
      SurfaceDesc fast{cases[ci].f, cases[ci].clip, cases[ci].transform, {}}, generic = fast;
      fast.options.cellDepth = generic.options.cellDepth = 0;  // one cell
      generic.options.quadricCallbacks = false;
      SurfaceGeometry a(device, fast), b(device, generic);
      ASSERT_EQ(a.primitiveCount(), 1u);
      for (SurfaceGeometry* g : {&a, &b})
        if (filter) {
          rtcSetGeometryIntersectFilterFunction(g->geometry(), &rejectEveryOther);
          rtcSetGeometryOccludedFilterFunction(g->geometry(), &rejectEveryOther);
          rtcCommitGeometry(g->geometry());
        }
      Scene sa(device), sb(device);
      sa.attach(a.geometry());
      sb.attach(b.geometry());
      sa.commit();
      sb.commit();
      for (double dist : {2.0, 4.0, 1e4, 1e7}) {
        const glm::dvec3 eye = dist * glm::dvec3(randomDir());
        for (int i = 0; i < 100; ++i) {
          SCOPED_TRACE(testing::Message() << "case " << ci << " filter " << filter << " dist "
                                          << dist << " ray " << i);
          // Float values, so that the float and double rays are the same line.
          const glm::dvec3 o = floatValues(i % 2 ? eye : dist * glm::dvec3(randomDir()));
          const glm::dvec3 d = floatValues(glm::dvec3(u(rng), u(rng), u(rng)) - o);
          // Float rays (the filter's counter is reset so both sides see the same sequence).
          RTCRayHit fa = makeRay(glm::vec3(o), glm::vec3(d)), fb = fa;
          filterCalls = 0;
          fa = intersect1(sa, fa);
          const int seenA = filterCalls;
          filterCalls = 0;
          fb = intersect1(sb, fb);
          EXPECT_EQ(seenA, filterCalls);
          expectSameFloatHit(fa, fb);
          // Double rays.
          const RayD ray = unboundedRay(o, d);
          filterCalls = 0;
          const HitD ha = intersectD(sa, ray);
          filterCalls = 0;
          const HitD hb = intersectD(sb, ray);
          ASSERT_EQ(ha.hit, hb.hit);
          if (!ha.hit) continue;
          ++hits;
          EXPECT_EQ(ha.t, hb.t);
          EXPECT_EQ(ha.Ng, hb.Ng);
          EXPECT_EQ(ha.u, hb.u);
          // The float u, v (surfaceUVFloat) are the double ones (surfaceUV) to float
          // accuracy, where the float ray is the double one (near eyes).
          if (!filter && dist < 10.0 && fa.hit.geomID != RTC_INVALID_GEOMETRY_ID &&
              std::abs(fa.ray.tfar - ha.t) < 1e-6 * ha.t) {
            EXPECT_NEAR(fa.hit.u, ha.u, 1e-5);
            EXPECT_NEAR(fa.hit.v, ha.v, 1e-5);
          }
          // Shadow rays from the hit (float, tnear = 0) and the double ray leaving it.
          const glm::dvec3 p = o + ha.t * d;
          const glm::vec3 light = glm::vec3(3.0f * randomDir());
          RTCRay sray = makeRay(glm::vec3(p), light - glm::vec3(p), 0.0f, 1.0f).ray;
          filterCalls = 0;
          const bool occA = occluded1(sa, sray);
          filterCalls = 0;
          EXPECT_EQ(occA, occluded1(sb, sray));
          RayD leave;
          leave.org = p;
          leave.orgError = gamma(3) * (glm::length(o) + glm::length(ha.t * d));
          leave.dir = d;
          leave.tfar = std::numeric_limits<double>::infinity();
          filterCalls = 0;
          const HitD na = intersectD(sa, leave);
          filterCalls = 0;
          const HitD nb = intersectD(sb, leave);
          ASSERT_EQ(na.hit, nb.hit);
          if (na.hit) {
            EXPECT_EQ(na.t, nb.t);
            EXPECT_GT(na.t * glm::length(d), 1e-9);  // never its own origin
          }
        }
      }
      // Packets of 8 against single rays on the fast geometry.
      const glm::vec3 eye = 3.0f * randomDir();
      alignas(32) RTCRayHit8 packet{};
      alignas(32) int valid[8];
      RTCRayHit singles[8];
      const bool honoursMask = embreeHonoursValidMask(device, 8);
      for (int l = 0; l < 8; ++l) {
        valid[l] = l == 5 ? 0 : -1;
        const glm::vec3 dir = glm::vec3(u(rng), u(rng), u(rng)) - eye;
        singles[l] = makeRay(eye, dir);
        packet.ray.org_x[l] = eye.x;
        packet.ray.org_y[l] = eye.y;
        packet.ray.org_z[l] = eye.z;
        packet.ray.dir_x[l] = dir.x;
        packet.ray.dir_y[l] = dir.y;
        packet.ray.dir_z[l] = dir.z;
        packet.ray.tnear[l] = 0.0f;
        // Empty too where Embree ignores the mask (embreeHonoursValidMask).
        packet.ray.tfar[l] =
            valid[l] || honoursMask ? std::numeric_limits<float>::infinity() : -1.0f;
        packet.ray.mask[l] = ~0u;
        packet.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
      }
      if (!filter) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        rtcIntersect8(valid, sa, &context, &packet);
        for (int l = 0; l < 8; ++l) {
          if (!valid[l]) {
            EXPECT_EQ(packet.hit.geomID[l], RTC_INVALID_GEOMETRY_ID);
            continue;
          }
          const RTCRayHit one = intersect1(sa, singles[l]);
          EXPECT_EQ(packet.hit.geomID[l], one.hit.geomID);
          EXPECT_EQ(packet.ray.tfar[l], one.ray.tfar);
          EXPECT_EQ(packet.hit.u[l], one.hit.u);
        }
      }
      EXPECT_EQ(a.callbackErrors(), 0u);
      EXPECT_EQ(b.callbackErrors(), 0u);
    }
  }
  EXPECT_GT(hits, 800);
}

namespace {
// Ellipsoids for the tight-bounds tests: the gallery's sphere and ellipsoid, the latter
// also placed by a skew transform, cut by a box, and off-centre in a loose clip sphere.
struct BoundedCase {
  Polynomial f;
  ClipRegion clip;
  glm::dmat4 transform;
};
std::vector<BoundedCase> boundedCases() {
  const Polynomial x = X(), y = Y(), z = Z();
  const Polynomial ellipsoid = x * x + y * y * (1.0 / 0.5625) + z * z * 4.0 - Polynomial(1.0);
  glm::dmat4 skew(1.0);
  skew[0][1] = 0.3;
  skew[1][2] = -0.2;
  skew[2][2] = 1.7;
  skew[3] = glm::dvec4(0.5, -0.25, 2.0, 1.0);
  // (x - 0.3)^2 / 0.16 + (y + 0.2)^2 / 0.09 + (z - 0.1)^2 / 0.25 = 1, negated (A negative
  // definite), with a cross term.
  const Polynomial xs = x - Polynomial(0.3), ys = y + Polynomial(0.2), zs = z - Polynomial(0.1);
  const Polynomial tilted =
      Polynomial(-1.0) * (xs * xs * (1 / 0.16) + ys * ys * (1 / 0.09) + zs * zs * (1 / 0.25) +
                          2.0 * xs * ys - Polynomial(1.0));
  return {
      {spherePolynomial(1.0), ClipSphere{{0, 0, 0}, 1.2}, glm::dmat4(1.0)},
      {ellipsoid, ClipSphere{{0, 0, 0}, 1.2}, glm::dmat4(1.0)},
      {ellipsoid, ClipSphere{{0, 0, 0}, 1.2}, skew},
      {ellipsoid, ClipBox{{-0.8, -1, -1}, {1, 0.6, 1}}, glm::dmat4(1.0)},
      {tilted, ClipSphere{{0.1, 0, 0}, 2.0}, skew},
  };
}

RTCBounds sceneBounds(RTCScene scene) {
  RTCBounds b;
  rtcGetSceneBounds(scene, &b);
  return b;
}

bool inBounds(const RTCBounds& b, const glm::dvec3& p) {
  return p.x >= b.lower_x && p.x <= b.upper_x && p.y >= b.lower_y && p.y <= b.upper_y &&
         p.z >= b.lower_z && p.z <= b.upper_z;
}
}  // namespace

TEST_F(EmbreeQuadric, TightBoundsKeepHits) {
  // An ellipsoid's one cell is its own padded box (SurfaceOptions::quadricBounds): Embree
  // drops more rays, but only rays that miss. Random rays (float and double, near and far
  // eyes, rays grazing the box, shadow rays leaving the surface with tnear = 0, double
  // rays leaving it with their orgError) give the same hits bit for bit with and without,
  // on the quadric callbacks and on the generic walk.
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  int hits = 0, grazing = 0, tangentHits = 0;
  for (const BoundedCase& c : boundedCases()) {
    for (const bool callbacks : {true, false}) {
      SurfaceDesc tight{c.f, c.clip, c.transform, {}}, loose = tight;
      tight.options.quadricCallbacks = loose.options.quadricCallbacks = callbacks;
      tight.options.cellDepth = loose.options.cellDepth = 0;  // one cell
      loose.options.quadricBounds = false;
      SurfaceGeometry a(device, tight), b(device, loose);
      ASSERT_EQ(a.primitiveCount(), 1u);
      Scene sa(device), sb(device);
      sa.attach(a.geometry());
      sb.attach(b.geometry());
      sa.commit();
      sb.commit();
      // The bounds did shrink (by at least 10 % of the volume in every case here).
      const RTCBounds ba = sceneBounds(sa), bb = sceneBounds(sb);
      const double va =
          double(ba.upper_x - ba.lower_x) * (ba.upper_y - ba.lower_y) * (ba.upper_z - ba.lower_z);
      const double vb =
          double(bb.upper_x - bb.lower_x) * (bb.upper_y - bb.lower_y) * (bb.upper_z - bb.lower_z);
      EXPECT_LT(va, 0.9 * vb);
      const glm::dvec3 centre = glm::dvec3(c.transform * glm::dvec4(0, 0, 0, 1));
      for (double dist : {2.5, 6.0, 1e5}) {
        for (int i = 0; i < 150; ++i) {
          SCOPED_TRACE(testing::Message() << "dist " << dist << " ray " << i);
          const glm::dvec3 o = floatValues(centre + dist * glm::dvec3(randomDir()));
          // Half the rays aim at the world box's faces (grazing the tight bounds).
          glm::dvec3 target = centre + glm::dvec3(u(rng), u(rng), u(rng));
          if (i % 2) {
            const int axis = i % 3;
            const float lo[3] = {ba.lower_x, ba.lower_y, ba.lower_z},
                        hi[3] = {ba.upper_x, ba.upper_y, ba.upper_z};
            target[axis] = (i % 4 < 2) ? lo[axis] : hi[axis];
            ++grazing;
          }
          const glm::dvec3 d = floatValues(target - o);
          const RTCRayHit fa = intersect1(sa, makeRay(glm::vec3(o), glm::vec3(d)));
          const RTCRayHit fb = intersect1(sb, makeRay(glm::vec3(o), glm::vec3(d)));
          expectSameFloatHit(fa, fb);
          const RayD ray = unboundedRay(o, d);
          const HitD ha = intersectD(sa, ray), hb = intersectD(sb, ray);
          ASSERT_EQ(ha.hit, hb.hit);
          if (!ha.hit) continue;
          ++hits;
          EXPECT_EQ(ha.t, hb.t);
          EXPECT_EQ(ha.Ng, hb.Ng);
          // The hit lies inside the tight bounds.
          EXPECT_TRUE(inBounds(ba, o + ha.t * d));
          // Leaving the surface: float shadow rays and the double ray with its error.
          const glm::dvec3 p = o + ha.t * d;
          const glm::vec3 light = glm::vec3(centre + 3.0 * glm::dvec3(randomDir()));
          const RTCRay sray = makeRay(glm::vec3(p), light - glm::vec3(p), 0.0f, 1.0f).ray;
          EXPECT_EQ(occluded1(sa, sray), occluded1(sb, sray));
          const glm::vec3 back = glm::vec3(p) - 2.0f * glm::vec3(d);
          const RTCRayHit la = intersect1(sa, makeRay(glm::vec3(p), back - glm::vec3(p)));
          const RTCRayHit lb = intersect1(sb, makeRay(glm::vec3(p), back - glm::vec3(p)));
          ASSERT_EQ(la.hit.geomID, lb.hit.geomID);
          EXPECT_EQ(la.ray.tfar, lb.ray.tfar);
          RayD leave;
          leave.org = p;
          leave.orgError = gamma(3) * (glm::length(o) + glm::length(ha.t * d));
          leave.dir = d;
          leave.tfar = std::numeric_limits<double>::infinity();
          const HitD na = intersectD(sa, leave), nb = intersectD(sb, leave);
          ASSERT_EQ(na.hit, nb.hit);
          if (na.hit) {
            EXPECT_EQ(na.t, nb.t);
          }
        }
      }
      // Rays tangent to the ellipsoid, just inside, on and just outside it (where the
      // tight ball of quadricSpan's early rejection is as close as it gets): found
      // between the centre x0 and the surface point x0 + s w, f(x0 + s w) = f(x0) + s^2
      // w^T A w, and pushed along the normal by eps of s.
      const QuadricForm q = QuadricForm::fromPolynomial(c.f);
      const glm::dvec3 x0 = -0.5 * (glm::inverse(q.a) * q.b);
      const double f0 = glm::dot(x0, q.a * x0) + glm::dot(q.b, x0) + q.c;
      for (int i = 0; i < 100; ++i) {
        const glm::dvec3 w = glm::dvec3(randomDir());
        const double sw = std::sqrt(-f0 / glm::dot(w, q.a * w));
        const glm::dvec3 n = glm::normalize(q.a * w),
                         tangent = glm::normalize(glm::cross(n, glm::dvec3(randomDir())));
        const double eps = std::array<double, 5>{-1e-3, -1e-6, 0.0, 1e-6, 1e-3}[i % 5];
        const glm::dvec3 touch = x0 + sw * w + eps * sw * n;
        const glm::dvec3 wo = glm::dvec3(c.transform * glm::dvec4(touch - 3.0 * tangent, 1.0));
        const glm::dvec3 wd = glm::dvec3(c.transform * glm::dvec4(tangent, 0.0));
        SCOPED_TRACE(testing::Message() << "tangent ray " << i << " eps " << eps);
        expectSameFloatHit(intersect1(sa, makeRay(glm::vec3(wo), glm::vec3(wd))),
                           intersect1(sb, makeRay(glm::vec3(wo), glm::vec3(wd))));
        const RayD ray = unboundedRay(wo, wd);
        const HitD ha = intersectD(sa, ray), hb = intersectD(sb, ray);
        ASSERT_EQ(ha.hit, hb.hit);
        tangentHits += ha.hit;
        if (ha.hit) {
          EXPECT_EQ(ha.t, hb.t);
        }
      }
      EXPECT_EQ(a.callbackErrors(), 0u);
      EXPECT_EQ(b.callbackErrors(), 0u);
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(grazing, 1000);
  EXPECT_GT(tangentHits, 200);
}

TEST_F(EmbreeQuadric, TightBoundsHoldTheSurface) {
  // The tight bounds hold every point of the ellipsoid inside the clip region: sampled on
  // the surface as x0 + sqrt(k) C^-T w (w on the unit sphere, A = C C^T by Cholesky),
  // mapped to world space, and within a few percent of the exact box (tight, not just
  // conservative).
  for (const BoundedCase& c : boundedCases()) {
    SurfaceDesc desc{c.f, c.clip, c.transform, {}};
    desc.options.cellDepth = 0;
    SurfaceGeometry g(device, desc);
    ASSERT_EQ(g.primitiveCount(), 1u);
    Scene scene(device);
    scene.attach(g.geometry());
    scene.commit();
    const RTCBounds b = sceneBounds(scene);
    // The quadric's A, b, c (f = x^T A x + b.x + c), and its sign made positive.
    const Polynomial& f = c.f;
    glm::dmat3 a(0.0);
    glm::dvec3 lin(0.0);
    const glm::ivec3 e[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int r = 0; r < 3; ++r) {
      for (int s = 0; s < 3; ++s) {
        const glm::ivec3 m = e[r] + e[s];
        a[s][r] = f.coeff(m.x, m.y, m.z) * (r == s ? 1.0 : 0.5);
      }
      lin[r] = f.coeff(e[r].x, e[r].y, e[r].z);
    }
    double c0 = f.coeff(0, 0, 0);
    if (a[0][0] < 0) {
      a = -a;
      lin = -lin;
      c0 = -c0;
    }
    const glm::dvec3 x0 = -0.5 * (glm::inverse(a) * lin);
    const double k = glm::dot(x0, a * x0) - c0;
    // Cholesky A = C C^T (lower C); x = x0 + sqrt(k) C^-T w.
    glm::dmat3 chol(0.0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j <= i; ++j) {
        double sum = a[j][i];
        for (int l = 0; l < j; ++l) sum -= chol[l][i] * chol[l][j];
        chol[j][i] = i == j ? std::sqrt(sum) : sum / chol[j][j];
      }
    const glm::dmat3 map = std::sqrt(k) * glm::inverse(glm::transpose(chol));
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi = -lo;
    int inside = 0;
    for (int i = 0; i < 20000; ++i) {
      const glm::dvec3 p = x0 + map * glm::normalize(glm::dvec3(randomDir()));
      ASSERT_LT(std::abs(f.evaluate(p)), 1e-12);
      const bool inClip = std::holds_alternative<ClipSphere>(c.clip)
                              ? glm::length(p - std::get<ClipSphere>(c.clip).center) <=
                                    std::get<ClipSphere>(c.clip).radius
                              : glm::all(glm::lessThanEqual(std::get<ClipBox>(c.clip).lo, p)) &&
                                    glm::all(glm::lessThanEqual(p, std::get<ClipBox>(c.clip).hi));
      if (!inClip) continue;
      ++inside;
      const glm::dvec3 w = glm::dvec3(c.transform * glm::dvec4(p, 1.0));
      EXPECT_TRUE(inBounds(b, w)) << i;
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
    EXPECT_GT(inside, 5000);
    // Tight: the sampled box's extent is within 5 % of the bounds' on every axis (without
    // a transform: with one, the bounds are the box of the transformed object-space box).
    if (c.transform != glm::dmat4(1.0)) continue;
    EXPECT_GT(hi.x - lo.x, 0.95 * (b.upper_x - b.lower_x));
    EXPECT_GT(hi.y - lo.y, 0.95 * (b.upper_y - b.lower_y));
    EXPECT_GT(hi.z - lo.z, 0.95 * (b.upper_z - b.lower_z));
  }
}

// A quadric with a single cross term (x y, x z or y z) is not diagonal: QuadricForm's
// diagonal flag, which lets the path take A d as the diagonal's products, must see each of
// the three off-diagonal entries. The ellipsoid x^2 + y^2 + z^2 + 1.2 m = 1 (m one cross
// term; definite as 1.2 < 2) against its closed form along the ray: f(o + t d) = a t^2 + b t
// + c with a = |d|^2 + 1.2 m(d, d), b = 2 o . d + 1.2 (m(o, d) + m(d, o)), c = |o|^2 + 1.2
// m(o, o) - 1, the smaller root in long double; Ng along grad f = 2 p + 1.2 grad m(p).
TEST_F(EmbreeQuadric, EachSingleCrossTermReachesThePath) {
  std::mt19937 random(5902);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int pair = 0; pair < 3; ++pair) {
    const int i = pair == 2 ? 1 : 0, j = pair == 0 ? 1 : 2;  // (x, y), (x, z), (y, z)
    SCOPED_TRACE(pair);
    const Polynomial v[3] = {X(), Y(), Z()};
    SurfaceDesc desc;
    desc.polynomial =
        v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + 1.2 * (v[i] * v[j]) - Polynomial(1.0);
    desc.clip = ClipSphere{glm::dvec3(0.0), 4.0};
    const SurfaceScene scene(device, desc);
    using LD = long double;
    int hits = 0;
    for (int k = 0; k < 200; ++k) {
      const glm::dvec3 o =
          3.0 * glm::normalize(glm::dvec3(uniform(random), uniform(random), uniform(random)));
      const glm::dvec3 d =
          glm::normalize(0.5 * glm::dvec3(uniform(random), uniform(random), uniform(random)) - o);
      const LD a = LD(d.x) * d.x + LD(d.y) * d.y + LD(d.z) * d.z + 1.2L * d[i] * d[j];
      const LD b = 2 * (LD(o.x) * d.x + LD(o.y) * d.y + LD(o.z) * d.z) +
                   1.2L * (LD(o[i]) * d[j] + LD(d[i]) * o[j]);
      const LD c = LD(o.x) * o.x + LD(o.y) * o.y + LD(o.z) * o.z + 1.2L * o[i] * o[j] - 1;
      const LD disc = b * b - 4 * a * c;
      const HitD hit = intersectD(scene, RayD{o, d, 0.0, 1e30});
      // Rays within 1e-6 of tangent are left out (a touch may round either way).
      if (std::abs(disc) < 1e-6L) continue;
      ASSERT_EQ(hit.hit, disc > 0) << k;
      if (!hit.hit) continue;
      ++hits;
      const double t = double((-b - std::sqrt(disc)) / (2 * a));
      EXPECT_NEAR(hit.t, t, 1e-12) << k;
      const glm::dvec3 p = o + t * d;
      glm::dvec3 g = 2.0 * p;
      g[i] += 1.2 * p[j];
      g[j] += 1.2 * p[i];
      EXPECT_GT(glm::dot(glm::normalize(glm::dvec3(hit.Ng)), glm::normalize(g)), 1.0 - 1e-12) << k;
    }
    EXPECT_GT(hits, 100);
  }
}

}  // namespace
}  // namespace algray::test
