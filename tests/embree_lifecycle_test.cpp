// SurfaceGeometry's life as a host handles it: its description, moves, scenes it is
// attached to, detached from or disabled in.
#include "embree_test_util.h"

#include <gtest/gtest.h>

#include <utility>

namespace algray::test {
namespace {

class EmbreeLifecycle : public ::testing::Test {
 protected:
  Device device;
};

// desc() is the description the geometry was built from, so that a host can clone a
// surface from it. A sphere of radius 1 + 1.5e-6 lies just outside its clip sphere of
// radius 1 (beyond the 2^-20 by which the adapter widens every clip region): the clone
// must miss it as the original does.
TEST_F(EmbreeLifecycle, DescIsTheDescriptionGiven) {
  const ClipSphere sphereClip{{0.25, -0.5, 0.125}, 1.5};
  SurfaceGeometry s(device, sphereDesc(1.0, sphereClip.radius, sphereClip.center));
  const auto* clip = std::get_if<ClipSphere>(&s.desc().clip);
  ASSERT_NE(clip, nullptr);
  EXPECT_EQ(clip->center, sphereClip.center);
  EXPECT_EQ(clip->radius, sphereClip.radius);
  SurfaceDesc boxDesc = sphereDesc(1.0, 1.0);
  boxDesc.clip = ClipBox{{-1, -2, -3}, {1, 2, 3}};
  SurfaceGeometry b(device, boxDesc);
  const auto* box = std::get_if<ClipBox>(&b.desc().clip);
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(box->lo, glm::dvec3(-1, -2, -3));
  EXPECT_EQ(box->hi, glm::dvec3(1, 2, 3));

  SurfaceGeometry original(device, sphereDesc(1.0 + 1.5e-6, 1.0));
  SurfaceGeometry clone(device, original.desc());
  for (const SurfaceGeometry* g : {&original, &clone}) {
    Scene scene(device);
    scene.attach(g->geometry());
    scene.commit();
    EXPECT_EQ(intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1})).hit.geomID, RTC_INVALID_GEOMETRY_ID)
        << (g == &original ? "original" : "clone");
  }
}

TEST_F(EmbreeLifecycle, MovedFromGeometryIsEmpty) {
  SurfaceGeometry a(device, sphereDesc(1.0, 1.5));
  SurfaceGeometry b(std::move(a));
  EXPECT_EQ(a.geometry(), nullptr);  // NOLINT(bugprone-use-after-move): the moved-from state
  EXPECT_EQ(a.primitiveCount(), 0u);
  EXPECT_TRUE(a.desc().polynomial.isZero());
  EXPECT_EQ(b.desc().polynomial.degree(), 2);
}

// One geometry in two scenes (with different geomIDs), moved while attached, detached
// and attached again, disabled and enabled: each trace gives the closed-form hit t = 4 of
// the unit sphere from z = -5, under the scene's own geomID, or none while it is out.
TEST_F(EmbreeLifecycle, MovedSharedDetachedAndDisabledGeometryKeepsItsHits) {
  SurfaceGeometry sphere(device, sphereDesc(1.0, 1.5));
  Scene a(device), b(device);
  RTCGeometry quad = makeQuad(device, -3.0f, 0.5f);  // beside the ray below: b's geomID 0
  b.attach(quad);
  rtcReleaseGeometry(quad);
  const unsigned idA = a.attach(sphere.geometry()), idB = b.attach(sphere.geometry());
  ASSERT_NE(idA, idB);
  a.commit();
  b.commit();
  a.commit();  // twice: nothing changes
  auto expectHit = [](RTCScene scene, unsigned id) {
    const RTCRayHit rh = intersect1(scene, makeRay({0.75f, 0, -5}, {0, 0, 1}));
    EXPECT_EQ(rh.hit.geomID, id);
    if (id != RTC_INVALID_GEOMETRY_ID) {
      EXPECT_NEAR(rh.ray.tfar, 5.0f - std::sqrt(1.0f - 0.5625f), 1e-6f);
    }
  };
  expectHit(a, idA);
  expectHit(b, idB);
  SurfaceGeometry moved(std::move(sphere));
  expectHit(a, idA);
  rtcDetachGeometry(a, idA);
  a.commit();
  expectHit(a, RTC_INVALID_GEOMETRY_ID);
  expectHit(b, idB);
  const unsigned idA2 = a.attach(moved.geometry());
  a.commit();
  expectHit(a, idA2);
  rtcDisableGeometry(moved.geometry());
  a.commit();
  b.commit();
  expectHit(a, RTC_INVALID_GEOMETRY_ID);
  expectHit(b, RTC_INVALID_GEOMETRY_ID);
  rtcEnableGeometry(moved.geometry());
  a.commit();
  b.commit();
  SurfaceGeometry other(device, sphereDesc(2.0, 2.5));
  other = std::move(moved);
  expectHit(a, idA2);
  expectHit(b, idB);
  EXPECT_EQ(other.callbackErrors(), 0u);
}

}  // namespace
}  // namespace algray::test
