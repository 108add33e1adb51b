// Packets of 4, 8 and 16 rays through the quadric callbacks (issue 5): the SIMD packet
// path (quadric_packet.cpp) must give every lane the hit rtcIntersect1 / rtcOccluded1
// gives the same ray, bit for bit, and the host filter the same calls in the same order.
#include "algray/embree.h"
#include "embree_test_util.h"
// The adapter's private kernel, for the lanes' double results (the float hits above show
// only what survives the cast to float).
#include "../plugin/embree/quadric_path.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace algray::test {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Rejects every other candidate it sees (the count is reset before each comparison).
int filterCalls = 0;
void rejectEveryOther(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 && (filterCalls++ % 2) == 0) args->valid[i] = 0;
}

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

// Embree's SoA packets of width N, as a plain float array (the layout of RTCRayHitN).
template <unsigned N>
struct PacketOf;
template <>
struct PacketOf<4> {
  using RayHit = RTCRayHit4;
  using Ray = RTCRay4;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect4(v, s, c, r);
  }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded4(v, s, c, r);
  }
};
template <>
struct PacketOf<8> {
  using RayHit = RTCRayHit8;
  using Ray = RTCRay8;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect8(v, s, c, r);
  }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded8(v, s, c, r);
  }
};
template <>
struct PacketOf<16> {
  using RayHit = RTCRayHit16;
  using Ray = RTCRay16;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect16(v, s, c, r);
  }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded16(v, s, c, r);
  }
};

struct Case {
  const char* name;
  Polynomial f;
  ClipRegion clip;
  glm::dmat4 transform;
  // A singular point (world space) rays may leave from, rounded to float (the self-root
  // window of its lanes); NaN: none.
  glm::vec3 node{std::numeric_limits<float>::quiet_NaN()};
};

std::vector<Case> cases() {
  const Polynomial x = X(), y = Y(), z = Z();
  glm::dmat4 skew(1.0);
  skew[0][1] = 0.3;
  skew[1][2] = -0.2;
  skew[2][2] = 1.7;
  skew[3] = glm::dvec4(0.5, -0.25, 2.0, 1.0);
  const Polynomial ellipsoid = x * x + y * y * (1.0 / 0.5625) + z * z * 4.0 - Polynomial(1.0);
  return {
      {"sphere", spherePolynomial(1.0), ClipSphere{{0, 0, 0}, 1.2}, glm::dmat4(1.0)},
      {"ellipsoid", ellipsoid, ClipSphere{{0, 0, 0}, 1.2}, glm::dmat4(1.0)},
      {"ellipsoid skew", ellipsoid, ClipSphere{{0, 0, 0}, 1.2}, skew},
      {"ellipsoid off-centre", ellipsoid, ClipSphere{{0.4, 0.1, 0}, 1.0}, glm::dmat4(1.0)},
      {"hyperboloid", x * x + y * y - z * z - Polynomial(0.25), ClipSphere{{0, 0, 0}, 1.5},
       glm::dmat4(1.0)},
      {"hyperboloid box", x * x + y * y - z * z - Polynomial(0.25),
       ClipBox{{-1, -1.2, -0.8}, {1.1, 1, 1}}, glm::dmat4(1.0)},
      {"paraboloid skew", x * x + y * y - z, ClipSphere{{0.1, 0, 0.3}, 1.0}, skew},
      {"saddle", x * y + y * z + x * z - 0.2 * x + Polynomial(0.1), ClipSphere{{0, 0, 0}, 1.5},
       glm::dmat4(1.0)},
      {"cylinder", x * x + y * y - Polynomial(0.5), ClipSphere{{0, 0, 0}, 1.0}, glm::dmat4(1.0)},
      // Degree 1 takes the quadric path too (session 54; the general path before).
      {"plane skew", x + 0.5 * y - 0.2 * z - Polynomial(0.1), ClipSphere{{0, 0, 0}, 1.2}, skew},
      {"huge sphere", 1e200 * spherePolynomial(1.0), ClipSphere{{0, 0, 0}, 1.2}, glm::dmat4(1.0)},
      // A double plane: every hit's gradient is noise, so every lane takes the single-ray
      // normal (hit_normal.cpp; the lanes' slope test, quadric_packet_group.inc).
      {"double plane skew",
       (x + 0.5 * y - 0.2 * z - Polynomial(0.1)) * (x + 0.5 * y - 0.2 * z - Polynomial(0.1)),
       ClipSphere{{0, 0, 0}, 1.2}, skew},
      {"cone",
       (x - Polynomial(0.1)) * (x - Polynomial(0.1)) +
           (y - Polynomial(0.2)) * (y - Polynomial(0.2)) -
           (z - Polynomial(0.3)) * (z - Polynomial(0.3)),
       ClipSphere{{0, 0, 0}, 1.5}, glm::dmat4(1.0), glm::vec3(0.1f, 0.2f, 0.3f)},
  };
}

class EmbreePacket : public ::testing::Test {
 protected:
  Device device;
  std::mt19937 rng{4242};
  glm::vec3 randomDir() { return randomUnit(rng); }
  float uniform(float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng); }

  // Points of the case's surface outside its clip ball by 1 % of the radius (world space,
  // float), found by bisection of f on random chords: origins on the surface that the
  // self-root rule skips (restrictQuadricRay's far origins). None for bounded surfaces
  // inside the ball.
  std::vector<glm::vec3> outside;
  glm::vec3 node{std::numeric_limits<float>::quiet_NaN()};  // the case's (Case::node)
  void findOutsidePoints(const Case& c) {
    node = c.node;
    outside.clear();
    glm::dvec3 lo, hi;
    clipRegionBox(c.clip, lo, hi);
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const double radius = std::holds_alternative<ClipSphere>(c.clip) ? 0.5 * (hi.x - lo.x)
                                                                     : 0.5 * glm::length(hi - lo);
    for (int k = 0; k < 200 && outside.size() < 50; ++k) {
      const glm::dvec3 a = centre + 4.0 * radius * glm::dvec3(randomDir()),
                       b = centre + 1.5 * radius * glm::dvec3(randomDir());
      auto f = [&](double s) { return c.f.evaluate(a + s * (b - a)); };
      double s0 = 0.0;
      for (int i = 1; i <= 64; ++i) {
        const double s1 = i / 64.0;
        if ((f(s0) < 0.0) != (f(s1) < 0.0)) {
          double l = s0, h = s1;
          const bool negAtL = f(l) < 0.0;
          for (int j = 0; j < 80; ++j) ((f(0.5 * (l + h)) < 0.0) == negAtL ? l : h) = 0.5 * (l + h);
          const glm::dvec3 p = a + l * (b - a);
          if (glm::length(p - centre) > 1.01 * radius)
            outside.push_back(glm::vec3(c.transform * glm::dvec4(p, 1.0)));
        }
        s0 = s1;
      }
    }
  }

  // Rays of every kind the packet kernel decides or hands back: a camera's (shared eye,
  // near or very far), random ones, from inside, leaving the surface (tnear = 0, the
  // self-root rule; also from outside the clip ball; also nearly tangentially), grazing,
  // cut short by tfar or
  // starting beyond the hit, and
  // degenerate ones (zero or tiny direction, inverted or empty span). (No NaN or infinite
  // lanes: Embree 3 asserts on them before any user geometry sees them.)
  RTCRay randomRay(RTCScene scene, const glm::vec3& eye, float scale, const glm::mat4& world) {
    auto target = [&] {
      return glm::vec3(world * glm::vec4(uniform(-1.3f, 1.3f) * randomDir(), 1));
    };
    const int kind = std::uniform_int_distribution<int>(0, 14)(rng);
    glm::vec3 o = eye, d = target() - eye;
    float tnear = 0.0f, tfar = kInf;
    switch (kind) {
      case 0:
      case 1:
      case 2:
        break;  // the camera
      case 3:
        o = scale * randomDir();
        d = target() - o;
        break;
      case 4:
        o = glm::vec3(world * glm::vec4(0.2f * randomDir(), 1));
        d = randomDir();
        break;
      case 5:
      case 6: {  // leaving the surface from a hit of the camera
        RTCRayHit rh = intersect1(scene, makeRay(eye, d));
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
        o = eye + rh.ray.tfar * d;
        d = kind == 5 ? 3.0f * randomDir() - o : d;
        tfar = kind == 5 ? 1.0f : kInf;
        break;
      }
      case 7:
        tfar = uniform(0.0f, 1.2f);  // cut short, or starting beyond the first root
        tnear = uniform(0.0f, 0.9f);
        break;
      case 8:
        d = glm::vec3(0.0f);
        break;
      case 9:
        tnear = 5.0f;
        tfar = uniform(0.0f, 1.0f) < 0.5f ? 3.0f : 5.0f;
        break;
      case 10:  // a tiny direction, within Embree's rule: components of 1e-18 or more, or 0
        // (docs/embedding.md; below it Embree's single-ray traversal takes a component as
        // +1e-18, its packets otherwise, and the two see different boxes: the 1e-30 used
        // until session 57 met the surface only where its one box was the BVH's bare root
        // leaf, which Embree calls without a box test)
        d *= 0x1p-50f;
        for (int i = 0; i < 3; ++i)
          if (std::abs(d[i]) < 1e-18f) d[i] = 0.0f;
        break;
      case 13: {  // leaving a hit of the camera nearly tangentially (1e-4 .. 1e-2 rad)
        RTCRayHit rh = intersect1(scene, makeRay(eye, d));
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
        o = eye + rh.ray.tfar * d;
        const glm::vec3 n = glm::normalize(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
        const glm::vec3 along = glm::normalize(glm::cross(n, randomDir()));
        d = along + std::pow(10.0f, uniform(-4.0f, -2.0f)) * (uniform(0.0f, 1.0f) < 0.5f ? n : -n);
        break;
      }
      case 12:
        if (std::isnan(node.x)) break;  // else: leaving the case's singular point
        o = node;
        d = randomDir();
        break;
      case 11:
        if (outside.empty()) break;  // else: on the surface outside the clip ball, inwards
        o = outside[std::uniform_int_distribution<size_t>(0, outside.size() - 1)(rng)];
        d = target() - o;
        break;
      default:
        o = scale * randomDir();
        d = glm::cross(o, randomDir());  // grazing the clip region or missing
        break;
    }
    return makeRay(o, d, tnear, tfar).ray;
  }

  template <unsigned N>
  void compare(RTCScene scene, const glm::vec3& eye, float scale, const glm::mat4& world,
               int packets, int& lanes, int& hits) {
    using P = PacketOf<N>;
    // Where Embree traces every lane whatever the mask (embreeHonoursValidMask), inactive
    // lanes are also empty (tnear > tfar), as a portable host makes them.
    const bool emptyInactive = !embreeHonoursValidMask(device, N);
    for (int k = 0; k < packets; ++k) {
      alignas(64) typename P::RayHit rh{};
      alignas(64) typename P::Ray ray{};
      alignas(64) int valid[N];
      RTCRay singles[N];
      for (unsigned l = 0; l < N; ++l) {
        valid[l] = uniform(0.0f, 1.0f) < 0.8f ? -1 : 0;
        singles[l] = randomRay(scene, eye, scale, world);
        if (!valid[l] && emptyInactive) {
          singles[l].tnear = 1.0f;
          singles[l].tfar = 0.5f;
        }
        setPacketLane(rh.ray, l, singles[l]);
        setPacketLane(ray, l, singles[l]);
        rh.hit.geomID[l] = rh.hit.primID[l] = rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.Ng_x[l] = rh.hit.Ng_y[l] = rh.hit.Ng_z[l] = rh.hit.u[l] = rh.hit.v[l] = -7.0f;
      }
      // ---- Closest hit ------------------------------------------------------------------
      const typename P::RayHit before = rh;
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      filterCalls = 0;
      P::intersect(valid, scene, &context, &rh);
      const int packetFilterCalls = filterCalls;
      filterCalls = 0;
      for (unsigned l = 0; l < N; ++l) {
        SCOPED_TRACE(testing::Message() << "N " << N << " packet " << k << " lane " << l);
        if (!valid[l]) {
          EXPECT_EQ(bits(rh.ray.tfar[l]), bits(before.ray.tfar[l]));
          EXPECT_EQ(rh.hit.geomID[l], RTC_INVALID_GEOMETRY_ID);
          continue;
        }
        ++lanes;
        RTCRayHit one{};
        one.ray = singles[l];
        one.ray.id = l;
        one.hit.geomID = one.hit.primID = one.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        one.hit.Ng_x = one.hit.Ng_y = one.hit.Ng_z = one.hit.u = one.hit.v = -7.0f;
        one = intersect1(scene, one);
        hits += one.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        EXPECT_EQ(bits(rh.ray.tfar[l]), bits(one.ray.tfar));
        EXPECT_EQ(rh.hit.geomID[l], one.hit.geomID);
        EXPECT_EQ(rh.hit.primID[l], one.hit.primID);
        EXPECT_EQ(rh.hit.instID[0][l], one.hit.instID[0]);
        EXPECT_EQ(bits(rh.hit.Ng_x[l]), bits(one.hit.Ng_x));
        EXPECT_EQ(bits(rh.hit.Ng_y[l]), bits(one.hit.Ng_y));
        EXPECT_EQ(bits(rh.hit.Ng_z[l]), bits(one.hit.Ng_z));
        EXPECT_EQ(bits(rh.hit.u[l]), bits(one.hit.u));
        EXPECT_EQ(bits(rh.hit.v[l]), bits(one.hit.v));
      }
      EXPECT_EQ(packetFilterCalls, filterCalls) << "N " << N << " packet " << k;
      // ---- Occlusion ----------------------------------------------------------------------
      filterCalls = 0;
      P::occluded(valid, scene, &context, &ray);
      const int packetOcclusionCalls = filterCalls;
      filterCalls = 0;
      for (unsigned l = 0; l < N; ++l) {
        SCOPED_TRACE(testing::Message() << "occluded N " << N << " packet " << k << " lane " << l);
        if (!valid[l]) {
          EXPECT_EQ(bits(ray.tfar[l]), bits(singles[l].tfar));
          continue;
        }
        RTCRay one = singles[l];
        one.id = l;
        rtcOccluded1(scene, &context, &one);
        EXPECT_EQ(bits(ray.tfar[l]), bits(one.tfar));
      }
      EXPECT_EQ(packetOcclusionCalls, filterCalls) << "N " << N << " packet " << k;
    }
  }
};

// The adapter's record of a surface alone in its scene (the kernel-level tests below call
// the kernels on it directly).
const SurfaceData& surfaceData(const SurfaceScene& s) {
  return *static_cast<const SurfaceData*>(rtcGetGeometryUserData(s.geometry.geometry()));
}

TEST_F(EmbreePacket, QuadricPacketsMatchSingleRays) {
  int lanes = 0, hits = 0;
  for (const Case& c : cases()) {
    for (const bool filter : {false, true}) {
      SCOPED_TRACE(testing::Message() << c.name << " filter " << filter);
      SurfaceDesc desc{c.f, c.clip, c.transform, {}};
      desc.options.cellDepth = 0;  // one cell: the quadric callbacks
      SurfaceGeometry g(device, desc);
      ASSERT_EQ(g.primitiveCount(), 1u);
      findOutsidePoints(c);
      if (filter) {
        rtcSetGeometryIntersectFilterFunction(g.geometry(), &rejectEveryOther);
        rtcSetGeometryOccludedFilterFunction(g.geometry(), &rejectEveryOther);
        rtcCommitGeometry(g.geometry());
      }
      Scene scene(device);
      scene.attach(g.geometry());
      scene.commit();
      const glm::mat4 world(c.transform);
      // Eyes up to 1e5 radii: Embree tests the one cell's box since session 57 (the corner
      // point of embree_bridge.cpp), with a float slab test of error ~u |org| (its traversal
      // of user geometry is never the robust one), and from 1e7 radii its single rays and
      // its packets disagree on rays that cross the box by less than that (until then the
      // box was the BVH's bare root leaf, called for every ray).
      for (const float dist : {3.0f, 30.0f, 1e4f, 1e5f}) {
        const glm::vec3 eye = glm::vec3(world * glm::vec4(dist * randomDir(), 1));
        compare<4>(scene, eye, dist, world, 12, lanes, hits);
        compare<8>(scene, eye, dist, world, 12, lanes, hits);
        compare<16>(scene, eye, dist, world, 12, lanes, hits);
      }
      EXPECT_EQ(g.callbackErrors(), 0u);
    }
  }
  EXPECT_GT(lanes, 10000);
  EXPECT_GT(hits, 2000);
}

std::uint64_t bits(double f) { return std::bit_cast<std::uint64_t>(f); }

// Every root the kernels offer (walkRoots' accept function).
bool collectRoot(void* user, const KernelHit& hit) {
  static_cast<std::vector<KernelHit>*>(user)->push_back(hit);
  return false;
}

// The bridge hands float rays to the kernels with the origin's own error term deferred
// (KernelRay::orgErrorDeferred), added only where a test needs it: the kernels' answers
// must be those of the whole bound, bit for bit (the quadric path's span, restriction
// and first root; the generic walk's roots, points and gradients), for cameras near and
// far, rays leaving the surface inside and outside the clip ball, and transformed
// surfaces (whose bound has a host part too). The cubic takes the generic walk, the
// quadrics both (one cell: the quadric path; cells: the walk's quadric branch).
TEST_F(EmbreePacket, DeferredOriginErrorGivesTheWholeBoundsAnswers) {
  std::vector<Case> all = cases();
  const Polynomial x = X(), y = Y(), z = Z();
  all.push_back({"cubic", x * x * x + y * y * y + z * z * z - x * y * z - Polynomial(0.5),
                 ClipSphere{{0, 0, 0}, 1.5}, glm::dmat4(1.0)});
  int quadricRays = 0, rootsSeen = 0, shortcut = 0, covered = 0;
  for (const Case& c : all) {
    for (const int depth : {0, 2}) {
      SCOPED_TRACE(testing::Message() << c.name << " depth " << depth);
      SurfaceDesc desc{c.f, c.clip, c.transform, {}};
      desc.options.cellDepth = depth;
      const SurfaceScene scene(device, desc);
      const auto& data = surfaceData(scene);
      findOutsidePoints(c);
      const glm::mat4 world(c.transform);
      for (const float dist : {3.0f, 30.0f, 1e4f}) {
        const glm::vec3 eye = glm::vec3(world * glm::vec4(dist * randomDir(), 1));
        for (int k = 0; k < 150; ++k) {
          const RTCRay r = randomRay(scene, eye, dist, world);
          const glm::dvec3 o(r.org_x, r.org_y, r.org_z), d(r.dir_x, r.dir_y, r.dir_z);
          const KernelRay whole = hostObjectRay(data, o, d, r.tnear, r.tfar, 0x1p-24, 0.0);
          const KernelRay deferred = hostObjectRay(data, o, d, r.tnear, r.tfar, 0x1p-24, 0.0, true);
          ASSERT_TRUE(deferred.orgErrorDeferred);
          ASSERT_EQ(bits(wholeOrgError(data, deferred)), bits(whole.orgError));
          const glm::dvec3 oc = deferred.org - data.centre;
          shortcut += surelyOutsideClipBall(data, glm::dot(oc, oc), deferred);
          covered += data.quadricCellClip && glm::dot(oc, oc) <= data.quadricBox.coveredNear2;
          if (usesQuadricPath(data)) {
            ++quadricRays;
            QuadricSpan qw, qd;
            const bool fw = quadricSpan(data, whole, qw), fd = quadricSpan(data, deferred, qd);
            ASSERT_EQ(fw, fd);
            if (fw) {
              EXPECT_EQ(qw.g.degree, qd.g.degree);
              EXPECT_EQ(qw.g.selfRoot, qd.g.selfRoot);
              EXPECT_EQ(bits(qw.g.tShift), bits(qd.g.tShift));
              for (int i = 0; i < 3; ++i) {
                EXPECT_EQ(bits(qw.g.c[i]), bits(qd.g.c[i])) << "c" << i;
                EXPECT_EQ(bits(qw.g.err[i]), bits(qd.g.err[i])) << "err" << i;
              }
              EXPECT_EQ(bits(qw.slo), bits(qd.slo));
              EXPECT_EQ(bits(qw.shi), bits(qd.shi));
            }
            continue;
          }
          for (unsigned cell = 0; cell < data.cells.size(); ++cell) {
            std::vector<KernelHit> hw, hd;
            for (const bool occlusion : {false, true}) {
              hw.clear();
              hd.clear();
              algray::walkRoots(data, cell, whole, occlusion, &collectRoot, &hw);
              algray::walkRoots(data, cell, deferred, occlusion, &collectRoot, &hd);
              ASSERT_EQ(hw.size(), hd.size());
              rootsSeen += static_cast<int>(hw.size());
              for (size_t i = 0; i < hw.size(); ++i) {
                EXPECT_EQ(bits(hw[i].t), bits(hd[i].t));
                for (int a = 0; a < 3; ++a) {
                  EXPECT_EQ(bits(hw[i].point[a]), bits(hd[i].point[a]));
                  EXPECT_EQ(bits(hw[i].gradient[a]), bits(hd[i].gradient[a]));
                }
              }
            }
          }
        }
      }
    }
  }
  EXPECT_GT(quadricRays, 3000);
  EXPECT_GT(rootsSeen, 1000);
  EXPECT_GT(shortcut, 1000);
  EXPECT_GT(covered, 1000);  // quadricSpan's shortcut (QuadricBox::coveredNear2)
}

// The packet lanes' doubles against the scalar kernel's, bit for bit: the object-space
// ray (hostObjectRay), the span and restriction (quadricSpan), the first root (quadricRoot)
// and the float u, v at it (surfaceUVFloat), for every lane they decide.
TEST_F(EmbreePacket, PacketLanesMatchTheScalarKernel) {
  int decided = 0, roots = 0, uvs = 0, normals = 0, total = 0, nearDecided = 0, nearTotal = 0;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    SurfaceDesc desc{c.f, c.clip, c.transform, {}};
    desc.options.cellDepth = 0;
    const SurfaceScene scene(device, desc);
    const auto& data = surfaceData(scene);
    if (!usesQuadricPacket(data)) continue;
    findOutsidePoints(c);
    const glm::mat4 world(c.transform);
    for (const float dist : {3.0f, 30.0f, 1e4f}) {
      const glm::vec3 eye = glm::vec3(world * glm::vec4(dist * randomDir(), 1));
      for (int k = 0; k < 100; ++k) {
        QuadricPacket p;
        p.count = 2 + static_cast<unsigned>(uniform(0.0f, 14.99f));
        p.wantUV = k % 2 == 0;
        p.wantNormal = k % 3 != 0;
        for (unsigned l = 0; l < p.count; ++l) {
          const RTCRay r = randomRay(scene, eye, dist, world);
          p.ox[l] = r.org_x;
          p.oy[l] = r.org_y;
          p.oz[l] = r.org_z;
          p.dx[l] = r.dir_x;
          p.dy[l] = r.dir_y;
          p.dz[l] = r.dir_z;
          p.tnear[l] = r.tnear;
          p.tfar[l] = r.tfar;
        }
        quadricPacket(data, p);
        for (unsigned l = 0; l < p.count; ++l) {
          SCOPED_TRACE(testing::Message() << "dist " << dist << " packet " << k << " lane " << l);
          ++total;
          nearTotal += dist < 10.0f;
          const KernelRay kr =
              hostObjectRay(data, {p.ox[l], p.oy[l], p.oz[l]}, {p.dx[l], p.dy[l], p.dz[l]},
                            p.tnear[l], p.tfar[l], 0x1p-24, 0.0);
          QuadricSpan q;
          double s = 0.0;
          const bool found = quadricSpan(data, kr, q) && quadricRoot(q, q.slo, s) && s < q.shi;
          if (p.status[l] == QuadricPacket::kScalar) continue;
          ++decided;
          nearDecided += dist < 10.0f;
          ASSERT_EQ(p.status[l] == QuadricPacket::kRoot, found);
          if (!found) continue;
          ++roots;
          EXPECT_EQ(bits(p.s[l]), bits(s));
          EXPECT_EQ(bits(p.kox[l]), bits(kr.org.x));
          EXPECT_EQ(bits(p.koy[l]), bits(kr.org.y));
          EXPECT_EQ(bits(p.koz[l]), bits(kr.org.z));
          EXPECT_EQ(bits(p.kdx[l]), bits(kr.dir.x));
          EXPECT_EQ(bits(p.kdy[l]), bits(kr.dir.y));
          EXPECT_EQ(bits(p.kdz[l]), bits(kr.dir.z));
          EXPECT_EQ(bits(p.orgError[l]), bits(kr.orgError));
          EXPECT_EQ(p.degree[l], q.g.degree);
          EXPECT_EQ(bits(p.tShift[l]), bits(q.g.tShift));
          const double pc[3] = {p.c0[l], p.c1[l], p.c2[l]}, pe[3] = {p.e0[l], p.e1[l], p.e2[l]};
          for (int i = 0; i < 3; ++i) {
            EXPECT_EQ(bits(pc[i]), bits(q.g.c[i])) << "c" << i;
            EXPECT_EQ(bits(pe[i]), bits(q.g.err[i])) << "err" << i;
          }
          EXPECT_EQ(bits(p.slo[l]), bits(q.slo));
          EXPECT_EQ(bits(p.shi[l]), bits(q.shi));
          const double t = q.g.tShift + s;
          if (p.wantNormal && !std::isnan(p.nT[l])) {
            // The bridge's normal: the world-space gradient at the hit, cast to float.
            ++normals;
            EXPECT_EQ(bits(p.nT[l]), bits(t));
            const glm::dvec3 grad = data.quadric->gradient(kr.org + t * kr.dir);
            const glm::vec3 ng(data.identity ? grad : data.aInvT * grad);
            EXPECT_EQ(bits(p.nx[l]), bits(ng.x));
            EXPECT_EQ(bits(p.ny[l]), bits(ng.y));
            EXPECT_EQ(bits(p.nz[l]), bits(ng.z));
          }
          if (!p.wantUV || std::isnan(p.uvT[l])) continue;
          ++uvs;
          EXPECT_EQ(bits(p.uvT[l]), bits(t));
          float u, v;
          surfaceUVFloat(data, kr.org + t * kr.dir, u, v);
          EXPECT_EQ(bits(static_cast<float>(p.u[l])), bits(u));
          EXPECT_EQ(bits(static_cast<float>(p.v[l])), bits(v));
        }
      }
    }
  }
  EXPECT_GT(roots, 3000);
  EXPECT_GT(uvs, 1000);
  EXPECT_GT(normals, 1000);
  // Undecided: the degenerate kinds, far eyes outside the tight box's derivation, a last
  // lane alone in its vector; from a near eye most lanes are decided.
  EXPECT_GT(decided, total / 2);
  EXPECT_GT(nearDecided, 0.6 * nearTotal);
}

// The same rays with the packet kernel switched off (SurfaceOptions::packetSimd): the
// lane loop, which the comparison above checks against rtcIntersect1 as well.
// The origin window (a double ray whose host states orgError > 0: roots within twice it of
// the origin are the origin's, ray_roots.cpp deriveRayRoots and quadricLane) asks for the
// host's own bound: the object-space orgError of a transformed surface is never 0 (the map's
// rounding), and with it the window took hits 1.3-3.4 u |o| from origins with orgError 0
// (a transformed Whitney umbrella, 72 of 960 leaving rays; the review of session 47).
TEST_F(EmbreePacket, OnlyTheHostsOwnBoundOpensTheOriginWindow) {
  SurfaceDesc desc = sphereDesc(1.0, 1.6);
  desc.transform = glm::dmat4(1.0);
  desc.transform[1][1] = 0.01;
  desc.transform[3] = glm::dvec4(0.0, 300.0, 0.0, 1.0);
  for (const bool transformed : {false, true}) {
    const SurfaceScene scene(device, transformed ? desc : sphereDesc(1.0, 1.6));
    const SurfaceData& data = surfaceData(scene);
    const glm::dvec3 o = transformed ? glm::dvec3(0.0, 300.01, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 d(1.0, 0.0, 0.0);
    const double inf = std::numeric_limits<double>::infinity();
    SCOPED_TRACE(transformed);
    EXPECT_FALSE(hostObjectRay(data, o, d, 0.0, inf, kUnitRoundoff, 0.0).hostBound);
    EXPECT_TRUE(hostObjectRay(data, o, d, 0.0, inf, kUnitRoundoff, 1e-12).hostBound);
    EXPECT_FALSE(hostObjectRay(data, o, d, 0.0, inf, 0x1p-24, 1e-12).hostBound);  // a float ray
    EXPECT_GT(hostObjectRay(data, o, d, 0.0, inf, kUnitRoundoff, 0.0).orgError,
              transformed ? 0.0 : -1.0);
  }
}

TEST_F(EmbreePacket, PacketSwitchKeepsTheHits) {
  SurfaceDesc on = sphereDesc(1.0, 1.2), off = on;
  off.options.packetSimd = false;
  ScenePair pair(device, on, off);
  auto& [a, b, sa, sb] = pair;
  const glm::vec3 eye = 3.0f * randomDir();
  int hits = 0;
  for (int k = 0; k < 200; ++k) {
    alignas(32) RTCRayHit8 ra{};
    alignas(32) int valid[8];
    for (unsigned l = 0; l < 8; ++l) {
      valid[l] = -1;
      const glm::vec3 target(uniform(-1.2f, 1.2f), uniform(-1.2f, 1.2f), uniform(-1.2f, 1.2f));
      setPacketLane(ra.ray, l, makeRay(eye, target - eye).ray);
      ra.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCRayHit8 rb = ra;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect8(valid, sa, &context, &ra);
    rtcIntersect8(valid, sb, &context, &rb);
    for (unsigned l = 0; l < 8; ++l) {
      hits += ra.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID;
      EXPECT_EQ(bits(ra.ray.tfar[l]), bits(rb.ray.tfar[l]));
      EXPECT_EQ(bits(ra.hit.Ng_x[l]), bits(rb.hit.Ng_x[l]));
      EXPECT_EQ(bits(ra.hit.u[l]), bits(rb.hit.u[l]));
      EXPECT_EQ(bits(ra.hit.v[l]), bits(rb.hit.v[l]));
    }
  }
  EXPECT_GT(hits, 600);
}

}  // namespace
}  // namespace algray::test
