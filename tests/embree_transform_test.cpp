// SurfaceDesc::transform and float rays: the origin's uncertainty is world-space, so a map
// that both stretches and moves the object far away must not spread it over object space
// in every direction (plugin/embree/surface_data.h: originMove, selfRootWindow).
#include "embree_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace algray::test {
namespace {

struct Placement {
  glm::dvec3 scale, shift;  // world = scale * object + shift (componentwise)
};

// The world ray of rh in object space (a diagonal map: one rounding per coordinate, far
// below the tests' tolerances).
void objectRayOf(const Placement& k, const RTCRayHit& rh, glm::dvec3& o, glm::dvec3& d) {
  const glm::dvec3 wo(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z);
  const glm::dvec3 wd(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
  o = (wo - k.shift) / k.scale;  // wo - shift is exact here (Sterbenz), the division rounds
  d = wd / k.scale;
}

// The four rays as one packet (rtcIntersect4, the quadric path's SIMD lanes) hit as each
// did alone, bit for bit (expectSameFloatHit on each lane).
void expectPacketAsSingles(RTCScene scene, const RTCRayHit (&single)[4]) {
  alignas(16) RTCRayHit4 packet{};
  alignas(16) int valid[4] = {-1, -1, -1, -1};
  for (unsigned l = 0; l < 4; ++l) {
    setPacketLane(packet.ray, l,
                  makeRay({single[l].ray.org_x, single[l].ray.org_y, single[l].ray.org_z},
                          {single[l].ray.dir_x, single[l].ray.dir_y, single[l].ray.dir_z})
                      .ray);
    packet.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
    packet.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect4(valid, scene, &context, &packet);
  for (unsigned l = 0; l < 4; ++l) {
    SCOPED_TRACE(l);
    RTCRayHit lane = single[l];
    lane.ray.tfar = packet.ray.tfar[l];
    lane.hit.geomID = packet.hit.geomID[l];
    lane.hit.primID = packet.hit.primID[l];
    lane.hit.Ng_x = packet.hit.Ng_x[l];
    lane.hit.Ng_y = packet.hit.Ng_y[l];
    lane.hit.Ng_z = packet.hit.Ng_z[l];
    lane.hit.u = packet.hit.u[l];
    lane.hit.v = packet.hit.v[l];
    expectSameFloatHit(lane, single[l]);
  }
}

class EmbreeTransform : public EmbreeFixture {
 protected:
  // The unit sphere (degree 2: the quadric path and its packets) or the unit sphere times a
  // plane outside its clip ball (degree 3: the generic walk), under the placement.
  static SurfaceDesc placedSphere(const Placement& k, bool quadric) {
    SurfaceDesc desc = sphereDesc(1.0, 1.6);
    if (!quadric) desc.polynomial = spherePolynomial(1.0) * (X() - Polynomial(10.0));
    desc.transform = glm::dmat4(1.0);
    for (int i = 0; i < 3; ++i) desc.transform[i][i] = k.scale[i];
    desc.transform[3] = glm::dvec4(k.shift, 1.0);
    return desc;
  }
  static constexpr Placement kPlacements[] = {
      {{1.0, 1.0, 1e-3}, {1e4, 0.0, 0.0}},
      {{1e-3, 1.0, 1.0}, {0.0, -3e3, 5e3}},
      {{1.0, 2e-4, 1.0}, {-2e4, 0.0, 7e3}},
  };
};

// Float rays towards the object from a few radii: every ray the closed form says hits
// is reported at its root. The float origin stands for a point within 4 u_float |o| of it
// in world space; through the flattening map that is up to 5 object radii along the thin
// axis but not across it, where the gradient at these origins points. Taken isotropically
// (|A^-1|_F), the self-root rule found such origins on the surface (|f(o)| = 15 within
// 2 |grad f| 4.8) and divided the real hit out: most of these rays missed.
TEST_F(EmbreeTransform, FloatRaysHitFlattenedSurfacesFarAway) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Placement& k : kPlacements) {
    for (const bool quadric : {true, false}) {
      const SurfaceScene scene(device, placedSphere(k, quadric));
      int hits = 0;
      RTCRayHit single[4];
      for (int i = 0; i < 200; ++i) {
        // From about 4 radii, the thin axis's coordinate 0 (so that the float origin keeps
        // the object-space point), towards a point inside the sphere.
        glm::dvec3 from(u(rng), u(rng), u(rng));
        for (int a = 0; a < 3; ++a)
          if (k.scale[a] < 1.0) from[a] = 0.0;
        from = 4.0 * glm::normalize(from);
        const glm::dvec3 to = 0.5 * glm::dvec3(u(rng), u(rng), u(rng));
        const glm::vec3 wo(k.scale * from + k.shift), wd(k.scale * (to - from));
        const RTCRayHit rh = intersect1(scene, makeRay(wo, wd));
        single[i % 4] = rh;
        if (i % 4 == 3) expectPacketAsSingles(scene, single);
        glm::dvec3 o, d;
        objectRayOf(k, rh, o, d);
        const auto ref = sphereRoot(o, d, 1.0L, 0.0L);
        ASSERT_EQ(ref.has_value(), rh.hit.geomID != RTC_INVALID_GEOMETRY_ID)
            << i << " quadric " << quadric << " scale " << k.scale.z;
        if (!ref) continue;
        ++hits;
        EXPECT_NEAR(rh.ray.tfar, (double)*ref, 1e-6 * (double)*ref) << i << " quadric " << quadric;
      }
      EXPECT_GT(hits, 150) << "quadric " << quadric;
    }
  }
}

// Rays leaving the rim inwards (origin a float hit point, direction across the object
// through the interior) reach the far side. The self-root rule applies there (the origin is
// on the surface), and its window, the parameter range a root is taken for the origin's
// own, follows the world-space uncertainty along the ray: 2 |o| 4 u_float / |d_world|,
// not that uncertainty through |A^-1|_F over the object-space |d| (5 object radii: the far
// side skipped). Single rays and packets alike (a packet lane goes to the scalar path there).
TEST_F(EmbreeTransform, RaysLeavingFlattenedSurfacesFarAwayReachTheFarSide) {
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  for (const Placement& k : kPlacements) {
    int thin = 0;
    for (int a = 0; a < 3; ++a)
      if (k.scale[a] < 1.0) thin = a;
    const int a1 = (thin + 1) % 3, a2 = (thin + 2) % 3;
    for (const bool quadric : {true, false}) {
      const SurfaceScene scene(device, placedSphere(k, quadric));
      RTCRayHit single[4];
      for (int i = 0; i < 200; ++i) {
        // Two points of the rim (the great circle across the thin axis) at least 100 degrees
        // apart: the chord is longer than 1.5 radii.
        const double p0 = angle(rng), p1 = p0 + 1.75 + 2.78 * angle(rng) / 6.283185307179586;
        glm::dvec3 from(0.0), to(0.0);
        from[a1] = std::cos(p0), from[a2] = std::sin(p0);
        to[a1] = std::cos(p1), to[a2] = std::sin(p1);
        const glm::vec3 wo(k.scale * from + k.shift), wd(k.scale * (to - from));
        const RTCRayHit rh = intersect1(scene, makeRay(wo, wd));
        glm::dvec3 o, d;
        objectRayOf(k, rh, o, d);
        // The far side: the larger root of the rounded ray (its origin is within rounding of
        // the sphere, so the smaller one lies at |t| tiny). The rule takes the origin for a
        // point of the surface, which moves the far root by up to the origin's world-space
        // uncertainty over |d_world| (4 u_float |o| here, ~1e-4), no more.
        const auto ref = sphereRoot(o, d, 1.0L, 0.25L);
        ASSERT_TRUE(ref.has_value()) << i;
        ASSERT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << i << " quadric " << quadric;
        const double tolerance = 16.0 * 0x1p-24 * glm::length(glm::dvec3(wo)) / glm::length(wd);
        EXPECT_NEAR(rh.ray.tfar, (double)*ref, tolerance) << i << " quadric " << quadric;
        single[i % 4] = rh;
        if (i % 4 == 3) expectPacketAsSingles(scene, single);
      }
    }
  }
}

// A cell's world box is the hull of its 8 corners through the transform (worldBounds,
// surface_geometry.cpp). Under a rotation in general position each world axis takes its
// extreme at one corner alone, so a corner left out shrinks the box. The plane x + y + z =
// 2.95 in the clip box [-1, 1]^3 is the triangle near the corner (1, 1, 1) with x, y, z >=
// 0.95; the rotation whose third row is (1, 1, 1) / sqrt 3 puts it at world z = 2.95 / sqrt
// 3, within 0.05 / sqrt 3 of that corner's z (sqrt 3), above every other corner of the box
// (at most 1 / sqrt 3). Rays straight down from world z = 3 onto points of the triangle
// (barycentric weights >= 0.1: clear of its edges), ending 0.05 past it (so that Embree
// tests the box over that segment only; a ray reaching into the box enters it anyway), must
// hit it at t = 3 - 2.95 / sqrt 3 (closed form), in both channels, with one cell and with
// the cell grid.
TEST_F(EmbreeTransform, RotatedClipBoxKeepsTheCornerOfItsBounds) {
  const double s3 = std::sqrt(3.0), s2 = std::sqrt(2.0), s6 = std::sqrt(6.0);
  // Rows e1, e2, e3 of the rotation (world = R object); glm's [column][row].
  const glm::dvec3 e[3] = {
      {1 / s2, -1 / s2, 0}, {1 / s6, 1 / s6, -2 / s6}, {1 / s3, 1 / s3, 1 / s3}};
  for (const bool cells : {false, true}) {
    SurfaceDesc desc;
    desc.polynomial = X() + Y() + Z() - Polynomial(2.95);
    desc.clip = ClipBox{glm::dvec3(-1.0), glm::dvec3(1.0)};
    desc.options.useCells = cells;
    desc.transform = glm::dmat4(1.0);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) desc.transform[c][r] = e[r][c];
    const SurfaceScene scene(device, desc);
    std::uniform_real_distribution<double> u(0.1, 1.0);
    const double expected = 3.0 - 2.95 / s3;
    for (int i = 0; i < 200; ++i) {
      glm::dvec3 w(u(rng), u(rng), u(rng));
      w /= w.x + w.y + w.z;
      if (std::min({w.x, w.y, w.z}) < 0.1) continue;
      const glm::dvec3 q = w.x * glm::dvec3(1.0, 1.0, 0.95) + w.y * glm::dvec3(1.0, 0.95, 1.0) +
                           w.z * glm::dvec3(0.95, 1.0, 1.0);
      const glm::dvec3 o(glm::dot(e[0], q), glm::dot(e[1], q), 3.0), d(0.0, 0.0, -1.0);
      const HitD hit = intersectD(scene, RayD{o, d, 0.0, expected + 0.05});
      ASSERT_TRUE(hit.hit) << i << " cells " << cells;
      EXPECT_NEAR(hit.t, expected, 1e-12) << i;
      const RTCRayHit rh =
          intersect1(scene, makeRay(glm::vec3(o), glm::vec3(d), 0.0f, float(expected + 0.05)));
      ASSERT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << i << " cells " << cells;
      EXPECT_NEAR(rh.ray.tfar, expected, 1e-6) << i;
    }
  }
}

// The world box of a clip sphere under the transform x -> A x + b is the ellipsoid's: half
// extent R |row_i(A)| along world axis i (worldBounds), which a sheared A tells apart from
// its columns. The plane z = 0 in the unit clip ball is the unit disc; under the shear x' = x
// + 2 y its world x reaches +-sqrt 5 (row (1, 2, 0)), not +-1 (column (1, 0, 0)). Rays straight
// down from world z = 3 onto points of the disc (radius up to 0.95) hit it at t = 3 (closed
// form), in both channels.
TEST_F(EmbreeTransform, ShearedClipSphereKeepsItsWorldExtent) {
  SurfaceDesc desc;
  desc.polynomial = Z();
  desc.clip = ClipSphere{glm::dvec3(0.0), 1.0};
  desc.transform = glm::dmat4(1.0);
  desc.transform[1][0] = 2.0;  // column y, row x: x' = x + 2 y
  const SurfaceScene scene(device, desc);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int wide = 0;
  for (int i = 0; i < 200; ++i) {
    const glm::dvec2 q(0.95 * u(rng), 0.95 * u(rng));
    if (glm::length(q) > 0.95) continue;
    wide += std::abs(q.x + 2.0 * q.y) > 1.1;
    const glm::dvec3 o(q.x + 2.0 * q.y, q.y, 3.0), d(0.0, 0.0, -1.0);
    const HitD hit = intersectD(scene, RayD{o, d, 0.0, 1e30});
    ASSERT_TRUE(hit.hit) << i << " at " << q.x << " " << q.y;
    EXPECT_NEAR(hit.t, 3.0, 1e-12) << i;
    const RTCRayHit rh = intersect1(scene, makeRay(glm::vec3(o), glm::vec3(d)));
    ASSERT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << i << " at " << q.x << " " << q.y;
    EXPECT_NEAR(rh.ray.tfar, 3.0, 1e-6) << i;
  }
  EXPECT_GT(wide, 30);  // rays outside the column's extent of +-1
}

}  // namespace
}  // namespace algray::test
