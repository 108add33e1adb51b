#pragma once
// Small RAII helpers shared by the tests/embree_*_test.cpp suites.
#include "algray/embree.h"

#include <embree3/rtcore.h>
#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "support/float_values.h"

namespace algray::test {

inline Polynomial X() { return Polynomial::variable(0); }
inline Polynomial Y() { return Polynomial::variable(1); }
inline Polynomial Z() { return Polynomial::variable(2); }

// x^2 + y^2 + z^2 - r^2
inline Polynomial spherePolynomial(double r) {
  return X() * X() + Y() * Y() + Z() * Z() - Polynomial(r * r);
}
// (x^2 + y^2 + z^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2): torus about the z axis.
inline Polynomial torusPolynomial(double R, double r) {
  const Polynomial s = X() * X() + Y() * Y() + Z() * Z() + Polynomial(R * R - r * r);
  return s * s - 4.0 * R * R * (X() * X() + Y() * Y());
}

// The torus's gradient, directly.
inline glm::dvec3 torusGradient(glm::dvec3 p, double R, double r) {
  const double s = glm::dot(p, p) + R * R - r * r;
  return {4 * p.x * s - 8 * R * R * p.x, 4 * p.y * s - 8 * R * R * p.y, 4 * p.z * s};
}

// A float ray's origin (org) or direction as doubles.
inline glm::dvec3 asD(const RTCRayHit& rh, bool org) {
  return org ? glm::dvec3(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z)
             : glm::dvec3(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
}

// First root of |o + t d|^2 = r^2 with t > tnear, in long double (closed form, stable
// variant of the quadratic formula, Press et al., "Numerical Recipes", Sec. 5.6).
inline std::optional<long double> sphereRoot(glm::dvec3 o, glm::dvec3 d, long double r,
                                             long double tnear) {
  const long double a = (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z;
  const long double b =
      2 * ((long double)o.x * d.x + (long double)o.y * d.y + (long double)o.z * d.z);
  const long double c =
      (long double)o.x * o.x + (long double)o.y * o.y + (long double)o.z * o.z - r * r;
  const long double disc = b * b - 4 * a * c;
  if (disc < 0) return std::nullopt;
  const long double q = -0.5L * (b + (b < 0 ? -1 : 1) * std::sqrt(disc));
  long double t0 = q / a, t1 = c / q;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 > tnear) return t0;
  if (t1 > tnear) return t1;
  return std::nullopt;
}

// ALGRAY_TEST_EMBREE_CONFIG, if set, is the device's configuration string: the test
// command runs the Embree suites once more with "isa=sse2" (Embree's SSE2 traversal,
// triangle test and packet kernels), as a host on an older CPU or one that asks for it has.
struct Device {
  RTCDevice device = rtcNewDevice(std::getenv("ALGRAY_TEST_EMBREE_CONFIG"));
  ~Device() { rtcReleaseDevice(device); }
  operator RTCDevice() const { return device; }  // NOLINT
};

struct Scene {
  RTCScene scene;
  explicit Scene(RTCDevice device) : scene(rtcNewScene(device)) {}
  ~Scene() { rtcReleaseScene(scene); }
  unsigned attach(RTCGeometry g) { return rtcAttachGeometry(scene, g); }
  void commit() { rtcCommitScene(scene); }
  operator RTCScene() const { return scene; }  // NOLINT
};

// One surface alone in its committed scene (used where a scene is: it converts).
struct SurfaceScene {
  SurfaceGeometry geometry;
  Scene scene;
  SurfaceScene(RTCDevice device, const SurfaceDesc& desc) : geometry(device, desc), scene(device) {
    scene.attach(geometry.geometry());
    scene.commit();
  }
  operator RTCScene() const { return scene; }  // NOLINT
};

// One surface under two sets of options, each geometry alone in its committed scene: the
// A/B comparisons of options (a, sa) against (b, sb).
struct ScenePair {
  SurfaceGeometry a, b;
  Scene sa, sb;
  ScenePair(RTCDevice device, const SurfaceDesc& da, const SurfaceDesc& db)
      : a(device, da), b(device, db), sa(device), sb(device) {
    sa.attach(a.geometry());
    sb.attach(b.geometry());
    sa.commit();
    sb.commit();
  }
};

inline SurfaceDesc sphereDesc(double r, double clip, glm::dvec3 centre = glm::dvec3(0.0)) {
  SurfaceDesc desc;
  desc.polynomial = spherePolynomial(r);
  desc.clip = ClipSphere{centre, clip};
  return desc;
}

inline RTCRayHit makeRay(glm::vec3 o, glm::vec3 d, float tnear = 0.0f,
                         float tfar = std::numeric_limits<float>::infinity()) {
  RTCRayHit rh{};
  rh.ray.org_x = o.x;
  rh.ray.org_y = o.y;
  rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x;
  rh.ray.dir_y = d.y;
  rh.ray.dir_z = d.z;
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

inline RTCRayHit intersect1(RTCScene scene, RTCRayHit rh) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(scene, &context, &rh);
  return rh;
}

inline bool occluded1(RTCScene scene, RTCRay ray) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(scene, &context, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();
}

// Double-precision query through the algray context.
inline HitD intersectD(RTCScene scene, const RayD& ray, RTCRayHit* out = nullptr) {
  HitD hit;
  IntersectContext context;
  initIntersectContext(&context, &ray, &hit, scene);
  RTCRayHit rh = makeRayHit(context);
  rtcIntersect1(scene, &context.base, &rh);
  if (out) *out = rh;
  return hit;
}

// The fields of two float hit records a host reads, bit for bit (tfar's bits: a -0 or a NaN
// differs too).
inline void expectSameFloatHit(const RTCRayHit& a, const RTCRayHit& b) {
  EXPECT_EQ(a.hit.geomID, b.hit.geomID);
  EXPECT_EQ(std::bit_cast<std::uint32_t>(a.ray.tfar), std::bit_cast<std::uint32_t>(b.ray.tfar))
      << a.ray.tfar << " vs " << b.ray.tfar;
  EXPECT_EQ(a.hit.primID, b.hit.primID);
  EXPECT_EQ(a.hit.Ng_x, b.hit.Ng_x);
  EXPECT_EQ(a.hit.Ng_y, b.hit.Ng_y);
  EXPECT_EQ(a.hit.Ng_z, b.hit.Ng_z);
  EXPECT_EQ(a.hit.u, b.hit.u);
  EXPECT_EQ(a.hit.v, b.hit.v);
}

inline glm::vec3 hitNormal(const RTCRayHit& rh) {
  return glm::normalize(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
}

// A quad (two triangles) in the plane z = zPlane covering [-s, s]^2.
inline RTCGeometry makeQuad(RTCDevice device, float zPlane, float s) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4));
  const float verts[12] = {-s, -s, zPlane, s, -s, zPlane, s, s, zPlane, -s, s, zPlane};
  for (int i = 0; i < 12; ++i) v[i] = verts[i];
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 2));
  const unsigned tris[6] = {0, 1, 2, 0, 2, 3};
  for (int i = 0; i < 6; ++i) idx[i] = tris[i];
  rtcCommitGeometry(g);
  return g;
}

// A direction uniform on the unit sphere.
inline glm::vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> n;
  return glm::normalize(glm::vec3(n(rng), n(rng), n(rng)));
}

// Lane l of an Embree SoA ray packet (RTCRay4/8/16 or the ray of RTCRayHit4/8/16) set to
// the single ray `one`.
template <class R>
void setPacketLane(R& r, unsigned l, const RTCRay& one) {
  r.org_x[l] = one.org_x;
  r.org_y[l] = one.org_y;
  r.org_z[l] = one.org_z;
  r.dir_x[l] = one.dir_x;
  r.dir_y[l] = one.dir_y;
  r.dir_z[l] = one.dir_z;
  r.tnear[l] = one.tnear;
  r.tfar[l] = one.tfar;
  r.time[l] = 0.0f;
  r.mask[l] = ~0u;
  r.id[l] = l;
  r.flags[l] = 0;
}

// Whether an N-ray packet call of Embree leaves the lanes its valid mask switches off
// untouched. Embree 3.13 does so only where it traces N-wide packets natively; its fallback
// (16-wide on a host without AVX-512, 8- and 16-wide on an SSE-only one) traces every lane
// whose tnear <= tfar whatever the mask says, for its own triangles as for user geometry,
// which then receives those lanes as valid (seen on an AVX2-only AMD Zen 3 host; Embree's
// maintainers name the fallback in RenderKit/embree#520). Decided by Embree's own behaviour
// on a quad, so a packet test holds algray to exactly what Embree does for its own geometry;
// where the mask is ignored, a portable host also gives inactive lanes tnear > tfar.
template <int N, class RayHitN>
bool embreeHonoursValidMask(RTCDevice device, void (*intersect)(const int*, RTCScene,
                                                                RTCIntersectContext*, RayHitN*)) {
  Scene scene(device);
  const RTCGeometry quad = makeQuad(device, 0.0f, 1.0f);
  scene.attach(quad);
  rtcReleaseGeometry(quad);
  scene.commit();
  alignas(64) RayHitN rh{};
  alignas(64) int valid[N];
  for (int l = 0; l < N; ++l) {
    valid[l] = l % 2 == 0 ? -1 : 0;
    rh.ray.org_x[l] = -0.9f + 0.1f * static_cast<float>(l);
    rh.ray.org_z[l] = -1.0f;
    rh.ray.dir_z[l] = 1.0f;
    rh.ray.tfar[l] = std::numeric_limits<float>::infinity();
    rh.ray.mask[l] = ~0u;
    rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  intersect(valid, scene, &context, &rh);
  for (int l = 0; l < N; ++l)
    if (!valid[l] && rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID) return false;
  return true;
}

inline bool embreeHonoursValidMask(RTCDevice device, int n) {
  switch (n) {
    case 4:
      return embreeHonoursValidMask<4, RTCRayHit4>(device, &rtcIntersect4);
    case 8:
      return embreeHonoursValidMask<8, RTCRayHit8>(device, &rtcIntersect8);
    case 16:
      return embreeHonoursValidMask<16, RTCRayHit16>(device, &rtcIntersect16);
    default:
      return true;
  }
}

// A ray from o along d with no far end.
inline RayD unboundedRay(const glm::dvec3& o, const glm::dvec3& d) {
  RayD ray;
  ray.org = o;
  ray.dir = d;
  ray.tfar = std::numeric_limits<double>::infinity();
  return ray;
}

// A device and a seeded generator per test (the suites' fixture).
class EmbreeFixture : public ::testing::Test {
 protected:
  Device device;
  std::mt19937 rng{12345};
  glm::vec3 randomDir() { return randomUnit(rng); }
};

}  // namespace algray::test
