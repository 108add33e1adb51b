// algray surfaces inside Embree instances, seen through the double-precision context:
// the HitD must describe the hit Embree reports, whichever scene level it comes from.
#include "embree_test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace algray::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

// An instance of `inner` translated by (0, 0, dz).
RTCGeometry translatedInstance(RTCDevice device, RTCScene inner, float dz) {
  RTCGeometry inst = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(inst, inner);
  const float xfm[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, dz};
  rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
  rtcCommitGeometry(inst);
  return inst;
}

// A unit sphere A at the origin in the top scene (geomID 0) and an instance of a scene
// holding another unit sphere B (also geomID 0 there), moved to z = -3. A ray along z at
// x = 0.6 meets B's near side at z = -3.8 and A's at z = -0.8 (closed form: the chord at
// x = 0.6 of a unit sphere ends at z = +-0.8).
TEST(EmbreeInstance, DoubleChannelHitIsTheInstancesWhenItIsCloser) {
  Device device;
  SurfaceDesc desc = sphereDesc(1.0, 1.5);
  desc.options.uv = true;
  SurfaceGeometry a(device, desc), b(device, desc);
  Scene inner(device);
  ASSERT_EQ(inner.attach(b.geometry()), 0u);
  inner.commit();
  Scene top(device);
  ASSERT_EQ(top.attach(a.geometry()), 0u);
  RTCGeometry inst = translatedInstance(device, inner, -3.0f);
  const unsigned instId = top.attach(inst);
  rtcReleaseGeometry(inst);
  top.commit();

  // Upwards from z = -10: B (t = 6.2) before A (t = 9.2).
  RTCRayHit rh;
  HitD hit = intersectD(top, RayD{{0.6, 0, -10}, {0, 0, 1}, 0, 100, 0}, &rh);
  ASSERT_EQ(rh.hit.instID[0], instId);
  EXPECT_NEAR(rh.ray.tfar, 6.2f, 1e-5f);
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.geomID, rh.hit.geomID);
  EXPECT_EQ(hit.instID, instId);
  EXPECT_NEAR(hit.t, 6.2, 1e-6);
  // In the instanced scene's space: B's gradient 2 (0.6, 0, -0.8), u = 0, v = acos(-0.8) / pi.
  EXPECT_NEAR(hit.Ng.x, 1.2, 1e-5);
  EXPECT_NEAR(hit.Ng.z, -1.6, 1e-5);
  EXPECT_NEAR(hit.u, 0.0, 1e-7);
  EXPECT_NEAR(hit.v, std::acos(-0.8) / kPi, 1e-6);

  // Downwards from z = +10: A (t = 9.2) before B: the top level's hit, no instance.
  hit = intersectD(top, RayD{{0.6, 0, 10}, {0, 0, -1}, 0, 100, 0}, &rh);
  ASSERT_EQ(rh.hit.instID[0], RTC_INVALID_GEOMETRY_ID);
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.instID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_NEAR(hit.t, 9.2, 1e-12);

  // A shadow ray ending (tfar = 7) before A: only the instance blocks it.
  HitD occ;
  const RayD shadow{{0.6, 0, -10}, {0, 0, 1}, 0, 7.0, 0};
  IntersectContext context;
  initIntersectContext(&context, &shadow, &occ, top);
  RTCRay ray = makeRayHit(context).ray;
  rtcOccluded1(top, &context.base, &ray);
  EXPECT_EQ(ray.tfar, -std::numeric_limits<float>::infinity());
  ASSERT_TRUE(occ.hit);
  EXPECT_EQ(occ.instID, instId);
  EXPECT_NEAR(occ.t, 6.2, 1e-6);
}

}  // namespace
}  // namespace algray::test
