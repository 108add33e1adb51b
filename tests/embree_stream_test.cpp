// Embree's stream queries (rtcIntersect1M / NM / Np and their occlusion twins), as a
// renderer tracing in stream mode calls them: Embree regroups the stream into packets of
// its own width and hands them to algray's callbacks, so every ray must get the hit
// rtcIntersect1 gives it alone (and rtcOccluded1's answer), coherent or incoherent,
// with algray's surfaces of both paths (a quadric's, cells of a quartic) beside triangles.
#include "algray/embree.h"
#include "embree_test_util.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace algray::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A torus (cells: the generic walk), a sphere (one cell: the quadric path) and a quad under
// them, in one scene.
struct MixedScene {
  Device device;
  SurfaceGeometry torus{device, [] {
                          SurfaceDesc d;
                          d.polynomial = torusPolynomial(1.0, 0.35);
                          d.clip = ClipSphere{glm::dvec3(0.0), 1.5};
                          d.options.cellDepth = 3;  // cells: the generic walk
                          return d;
                        }()};
  SurfaceGeometry sphere{device, [] {
                           SurfaceDesc d = sphereDesc(0.5, 0.75);
                           d.transform =
                               glm::translate(glm::dmat4(1.0), glm::dvec3(2.0, 0.5, 0.25));
                           d.options.cellDepth = 0;  // one cell: the quadric callbacks
                           return d;
                         }()};
  Scene scene{device};
  MixedScene() {
    scene.attach(torus.geometry());
    scene.attach(sphere.geometry());
    const RTCGeometry quad = makeQuad(device, -0.5f, 4.0f);
    scene.attach(quad);
    rtcReleaseGeometry(quad);
    scene.commit();
  }
};

// Rays from eyes around the scene towards random points of it (an eighth miss), some
// with tnear past the first surface, some with a short tfar.
std::vector<RTCRayHit> streamRays(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<RTCRayHit> rays;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 eye(5.0f * u(rng), 5.0f * u(rng), 1.0f + 3.0f * std::abs(u(rng)));
    const glm::vec3 target(2.5f * u(rng), 1.5f * u(rng), 0.5f * u(rng));
    const float tnear = i % 7 == 3 ? 0.5f : 0.0f, tfar = i % 11 == 5 ? 0.7f : kInf;
    rays.push_back(makeRay(eye, glm::normalize(target - eye), tnear, tfar));
  }
  return rays;
}

void expectSameHit(const RTCRayHit& got, const RTCRayHit& want, int i) {
  SCOPED_TRACE(testing::Message() << "ray " << i);
  expectSameFloatHit(got, want);
}

class EmbreeStream : public testing::TestWithParam<RTCIntersectContextFlags> {
 protected:
  RTCIntersectContext context() const {
    RTCIntersectContext c;
    rtcInitIntersectContext(&c);
    c.flags = GetParam();
    return c;
  }
};

TEST_P(EmbreeStream, StreamsGiveEveryRayItsSingleRayHit) {
  MixedScene s;
  ASSERT_GT(s.torus.primitiveCount(), 1u);
  ASSERT_EQ(s.sphere.primitiveCount(), 1u);
  constexpr int kRays = 1000;  // not a multiple of any packet width
  const std::vector<RTCRayHit> rays = streamRays(kRays - 1, 17);
  std::vector<RTCRayHit> single = rays;
  int hits[3] = {0, 0, 0};
  for (RTCRayHit& r : single) {
    r = intersect1(s.scene, r);
    if (r.hit.geomID != RTC_INVALID_GEOMETRY_ID) ++hits[r.hit.geomID];
  }
  // Every kind of object is hit, and some rays miss.
  EXPECT_GT(hits[0], 50);
  EXPECT_GT(hits[1], 20);
  EXPECT_GT(hits[2], 50);
  EXPECT_LT(hits[0] + hits[1] + hits[2], kRays - 50);

  // ---- rtcIntersect1M: an array of RTCRayHit ----------------------------------------------
  std::vector<RTCRayHit> m = rays;
  RTCIntersectContext c = context();
  rtcIntersect1M(s.scene, &c, m.data(), static_cast<unsigned>(m.size()), sizeof(RTCRayHit));
  for (size_t i = 0; i < m.size(); ++i) expectSameHit(m[i], single[i], static_cast<int>(i));

  // ---- rtcIntersectNM: arrays of packets of 4, 8 and 16 -------------------------------------
  auto packets = [&]<class Packet>(Packet*, unsigned n) {
    const size_t count = (rays.size() + n - 1) / n;
    std::vector<Packet> p(count);
    // Lanes past the end get an empty span (tnear > tfar), which Embree skips.
    for (size_t k = 0; k < count * n; ++k) {
      float* f = reinterpret_cast<float*>(&p[k / n]);
      const RTCRayHit r = k < rays.size() ? rays[k] : makeRay({0, 0, 9}, {0, 0, 1}, 1.0f, 0.0f);
      RTCRayHitN* rh = reinterpret_cast<RTCRayHitN*>(f);
      const unsigned l = k % n;
      RTCRayN_org_x(RTCRayHitN_RayN(rh, n), n, l) = r.ray.org_x;
      RTCRayN_org_y(RTCRayHitN_RayN(rh, n), n, l) = r.ray.org_y;
      RTCRayN_org_z(RTCRayHitN_RayN(rh, n), n, l) = r.ray.org_z;
      RTCRayN_dir_x(RTCRayHitN_RayN(rh, n), n, l) = r.ray.dir_x;
      RTCRayN_dir_y(RTCRayHitN_RayN(rh, n), n, l) = r.ray.dir_y;
      RTCRayN_dir_z(RTCRayHitN_RayN(rh, n), n, l) = r.ray.dir_z;
      RTCRayN_tnear(RTCRayHitN_RayN(rh, n), n, l) = r.ray.tnear;
      RTCRayN_tfar(RTCRayHitN_RayN(rh, n), n, l) = r.ray.tfar;
      RTCRayN_mask(RTCRayHitN_RayN(rh, n), n, l) = ~0u;
      RTCRayN_time(RTCRayHitN_RayN(rh, n), n, l) = 0.0f;
      RTCRayN_flags(RTCRayHitN_RayN(rh, n), n, l) = 0;
      RTCHitN_geomID(RTCRayHitN_HitN(rh, n), n, l) = RTC_INVALID_GEOMETRY_ID;
      RTCHitN_primID(RTCRayHitN_HitN(rh, n), n, l) = RTC_INVALID_GEOMETRY_ID;
      RTCHitN_instID(RTCRayHitN_HitN(rh, n), n, l, 0) = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext pc = context();
    rtcIntersectNM(s.scene, &pc, reinterpret_cast<RTCRayHitN*>(p.data()), n,
                   static_cast<unsigned>(count), sizeof(Packet));
    for (size_t k = 0; k < rays.size(); ++k) {
      RTCRayHitN* rh = reinterpret_cast<RTCRayHitN*>(&p[k / n]);
      const unsigned l = k % n;
      RTCRayHit got = rays[k];
      got.ray.tfar = RTCRayN_tfar(RTCRayHitN_RayN(rh, n), n, l);
      got.hit.geomID = RTCHitN_geomID(RTCRayHitN_HitN(rh, n), n, l);
      got.hit.primID = RTCHitN_primID(RTCRayHitN_HitN(rh, n), n, l);
      got.hit.Ng_x = RTCHitN_Ng_x(RTCRayHitN_HitN(rh, n), n, l);
      got.hit.Ng_y = RTCHitN_Ng_y(RTCRayHitN_HitN(rh, n), n, l);
      got.hit.Ng_z = RTCHitN_Ng_z(RTCRayHitN_HitN(rh, n), n, l);
      got.hit.u = RTCHitN_u(RTCRayHitN_HitN(rh, n), n, l);
      got.hit.v = RTCHitN_v(RTCRayHitN_HitN(rh, n), n, l);
      SCOPED_TRACE(testing::Message() << "packets of " << n);
      expectSameHit(got, single[k], static_cast<int>(k));
    }
  };
  packets(static_cast<RTCRayHit4*>(nullptr), 4);
  packets(static_cast<RTCRayHit8*>(nullptr), 8);
  packets(static_cast<RTCRayHit16*>(nullptr), 16);

  // ---- rtcIntersectNp: one stream in structure-of-arrays form -------------------------------
  const size_t n = rays.size();
  std::vector<float> ox(n), oy(n), oz(n), dx(n), dy(n), dz(n), tn(n), tf(n), tm(n, 0.0f);
  std::vector<float> ngx(n), ngy(n), ngz(n), hu(n), hv(n);
  std::vector<unsigned> mask(n, ~0u), id(n, 0), flags(n, 0), geomID(n, RTC_INVALID_GEOMETRY_ID),
      primID(n, RTC_INVALID_GEOMETRY_ID), instID(n, RTC_INVALID_GEOMETRY_ID);
  for (size_t i = 0; i < n; ++i) {
    ox[i] = rays[i].ray.org_x;
    oy[i] = rays[i].ray.org_y;
    oz[i] = rays[i].ray.org_z;
    dx[i] = rays[i].ray.dir_x;
    dy[i] = rays[i].ray.dir_y;
    dz[i] = rays[i].ray.dir_z;
    tn[i] = rays[i].ray.tnear;
    tf[i] = rays[i].ray.tfar;
  }
  RTCRayHitNp np{};
  np.ray = {ox.data(), oy.data(), oz.data(), tn.data(),   dx.data(), dy.data(),
            dz.data(), tm.data(), tf.data(), mask.data(), id.data(), flags.data()};
  np.hit.Ng_x = ngx.data();
  np.hit.Ng_y = ngy.data();
  np.hit.Ng_z = ngz.data();
  np.hit.u = hu.data();
  np.hit.v = hv.data();
  np.hit.primID = primID.data();
  np.hit.geomID = geomID.data();
  for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l) np.hit.instID[l] = instID.data();
  RTCIntersectContext npc = context();
  rtcIntersectNp(s.scene, &npc, &np, static_cast<unsigned>(n));
  for (size_t i = 0; i < n; ++i) {
    RTCRayHit got = rays[i];
    got.ray.tfar = tf[i];
    got.hit = {ngx[i], ngy[i], ngz[i], hu[i], hv[i], primID[i], geomID[i], {instID[i]}};
    SCOPED_TRACE("rtcIntersectNp");
    expectSameHit(got, single[i], static_cast<int>(i));
  }

  // ---- rtcOccluded1M against rtcOccluded1 ---------------------------------------------------
  std::vector<RTCRay> shadow(n);
  int blocked = 0;
  for (size_t i = 0; i < n; ++i) shadow[i] = rays[i].ray;
  std::vector<RTCRay> shadowM = shadow;
  RTCIntersectContext oc = context();
  rtcOccluded1M(s.scene, &oc, shadowM.data(), static_cast<unsigned>(n), sizeof(RTCRay));
  for (size_t i = 0; i < n; ++i) {
    const bool want = occluded1(s.scene, shadow[i]);
    blocked += want;
    EXPECT_EQ(shadowM[i].tfar == -kInf, want) << "ray " << i;
  }
  EXPECT_EQ(blocked, hits[0] + hits[1] + hits[2]);
  EXPECT_EQ(s.torus.callbackErrors() + s.sphere.callbackErrors(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Flags, EmbreeStream,
                         testing::Values(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT,
                                         RTC_INTERSECT_CONTEXT_FLAG_COHERENT),
                         [](const testing::TestParamInfo<RTCIntersectContextFlags>& p) {
                           return p.param == RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                      ? std::string("Coherent")
                                      : std::string("Incoherent");
                         });

}  // namespace
}  // namespace algray::test
