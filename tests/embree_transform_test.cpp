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

}  // namespace
}  // namespace algray::test
