// Host-facing behaviour through Embree: filters (geometry and context), instancing,
// packets (rtcIntersect4/8/16 and rtcOccluded4/8/16 against rtcIntersect1).
#include "embree_test_util.h"

#include <gtest/gtest.h>

#include <memory>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string_view>
#include <thread>
#include <vector>

namespace algray::test {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();

// Rejects the first `rejectCount` candidates it sees (a counter in the geometry's or the
// context's user data), records the t of every candidate.
struct FilterLog {
  int rejectCount = 1;
  int calls = 0;
  std::vector<float> seenT;
};
FilterLog* gLog = nullptr;

void rejectingFilter(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    gLog->seenT.push_back(RTCRayN_tfar(args->ray, args->N, i));
    if (gLog->calls++ < gLog->rejectCount) args->valid[i] = 0;
  }
}

// A surface with rejectingFilter, alone in its committed scene.
struct FilteredSurface {
  SurfaceGeometry geometry;
  Scene scene;
  FilteredSurface(RTCDevice device, const SurfaceDesc& desc)
      : geometry(device, desc), scene(device) {
    rtcSetGeometryIntersectFilterFunction(geometry.geometry(), &rejectingFilter);
    rtcCommitGeometry(geometry.geometry());
    scene.attach(geometry.geometry());
    scene.commit();
  }
};

class EmbreeFilter : public ::testing::Test {
 protected:
  Device device;
  FilterLog log;
  void SetUp() override { gLog = &log; }
  void TearDown() override { gLog = nullptr; }
};

class EmbreeFilterCells : public EmbreeFilter, public ::testing::WithParamInterface<bool> {};

// Far rays through a grid edge of depth-3 cells over [-1, 1]^3: through the points
// (delta, delta, 0.1) on (or 1e-7..1e-4 off) the grid lines x = y = 0, from `dist` away
// along three directions, so each crosses the plane z = 0.1 at t = dist (closed form).
// The float ray Embree traverses with passes up to u_float |o| beside the double one
// there, so the cells around a root's owner may claim it as an orphan (claimsRoot).
// A plane (or any surface) in depth-3 cells over [-1, 1]^3, the grid of gridEdgeRays.
SurfaceDesc inDepth3Cells(std::string_view equation) {
  SurfaceDesc desc;
  desc.polynomial = parsePolynomial(equation);
  desc.clip = ClipBox{glm::dvec3(-1.0), glm::dvec3(1.0)};
  desc.options.cellDepth = 3;
  return desc;
}
struct GridEdgeRay {
  RayD ray;
  double delta, dist;
};
std::vector<GridEdgeRay> gridEdgeRays(std::initializer_list<double> dists) {
  std::vector<GridEdgeRay> rays;
  for (const double delta : {0.0, 1e-7, 1e-5, 1e-4})
    for (const double dist : dists)
      for (const glm::dvec3& dir :
           {glm::dvec3(1, -1, 0.5), glm::dvec3(-0.3, 0.7, -1), glm::dvec3(0.2, 0.1, 1)}) {
        const glm::dvec3 d = glm::normalize(dir), p(delta, delta, 0.1);
        rays.push_back({RayD{p - dist * d, d, 0.0, 1e30}, delta, dist});
      }
  return rays;
}

// With cells (the default) the two roots come from different primitives and the axis
// ray runs inside cell faces, where four cells touch it: each root must still be offered
// exactly once. Without cells both come from one callback.
TEST_P(EmbreeFilterCells, GeometryFilterRejectingFirstHitGetsSecondRoot) {
  SurfaceDesc desc = sphereDesc(1.0, 1.5);
  desc.options.useCells = GetParam();
  SurfaceGeometry sphere(device, desc);
  rtcSetGeometryIntersectFilterFunction(sphere.geometry(), &rejectingFilter);
  rtcSetGeometryOccludedFilterFunction(sphere.geometry(), &rejectingFilter);
  rtcCommitGeometry(sphere.geometry());
  Scene scene(device);
  scene.attach(sphere.geometry());
  scene.commit();
  RTCRayHit rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}));
  ASSERT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_FLOAT_EQ(rh.ray.tfar, 6.0f);  // far side
  EXPECT_GT(rh.hit.Ng_z, 0.0f);
  ASSERT_EQ(log.seenT.size(), 2u);
  EXPECT_FLOAT_EQ(log.seenT[0], 4.0f);  // candidates offered in order
  EXPECT_FLOAT_EQ(log.seenT[1], 6.0f);
  // Rejecting both: miss, tfar untouched.
  log = FilterLog{2, 0, {}};
  rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}));
  EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_EQ(rh.ray.tfar, kInfF);
  // Occlusion: the first candidate rejected, the second accepted.
  log = FilterLog{1, 0, {}};
  EXPECT_TRUE(occluded1(scene, makeRay({0, 0, -5}, {0, 0, 1}).ray));
  EXPECT_EQ(log.calls, 2);
  log = FilterLog{2, 0, {}};
  EXPECT_FALSE(occluded1(scene, makeRay({0, 0, -5}, {0, 0, 1}).ray));
  EXPECT_EQ(log.calls, 2);
  // A ray off the faces, oblique: still each root once.
  log = FilterLog{5, 0, {}};
  rh = intersect1(scene, makeRay({0.1f, 0.2f, -5}, {0.01f, -0.02f, 1}));
  EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_EQ(log.calls, 2);
}

INSTANTIATE_TEST_SUITE_P(Cells, EmbreeFilterCells, ::testing::Bool());

// A filter rejecting everything sees every root along the ray exactly once, with or
// without cells (cells overlap by rounding; each root has one owner). Rays are aimed at
// cell faces and edges (coordinates on the dyadic grid) as well as at random points.
TEST_F(EmbreeFilter, EveryRootOfferedOnceAcrossCells) {
  std::vector<std::vector<float>> seen[2];
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.5f, 1.5f);
  std::vector<RTCRayHit> rays;
  for (int i = 0; i < 300; ++i) {
    const bool onGrid = i % 3 == 0;
    const float x = onGrid ? 0.25f * std::round(4 * u(rng)) : u(rng);
    const float y = onGrid ? 0.125f * std::round(8 * u(rng)) : u(rng);
    rays.push_back(onGrid ? makeRay({x, y, -4}, {0, 0, 1})
                          : makeRay({x, y, -4}, {0.2f * u(rng), 0.1f * u(rng), 1}));
    rays.push_back(makeRay({-4, x, y}, {1, 0, 0}));
  }
  for (int cells = 0; cells < 2; ++cells) {
    SurfaceDesc desc;
    desc.polynomial = torusPolynomial(1.0, 0.4);
    desc.clip = ClipSphere{{0, 0, 0}, 1.6};
    desc.options.useCells = cells == 1;
    FilteredSurface torus(device, desc);
    for (const RTCRayHit& r : rays) {
      log = FilterLog{1 << 30, 0, {}};
      intersect1(torus.scene, r);
      std::sort(log.seenT.begin(), log.seenT.end());
      seen[cells].push_back(log.seenT);
    }
  }
  int total = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(seen[0][i].size(), seen[1][i].size())
        << "ray " << i << " " << rays[i].ray.org_x << " " << rays[i].ray.org_y << " "
        << rays[i].ray.org_z << " d " << rays[i].ray.dir_x << " " << rays[i].ray.dir_y << " "
        << rays[i].ray.dir_z << " t " << (seen[1][i].empty() ? 0.f : seen[1][i][0]) << " "
        << (seen[1][i].size() > 1 ? seen[1][i][1] : 0.f);
    for (size_t k = 0; k < seen[0][i].size(); ++k)
      EXPECT_NEAR(seen[0][i][k], seen[1][i][k], 1e-5f) << i;
    total += static_cast<int>(seen[0][i].size());
  }
  // Enough roots to mean something: 530 here, 496 and 456 on two other draws of the rays
  // (session 39; the bound was 500, which both missed).
  std::printf("roots offered: %d on %zu rays\n", total, rays.size());
  EXPECT_GT(total, 300);
}

// Planes lying on cell faces (x = 0, z = 0.25 on the grid of a depth-3 octree of
// [-1, 1]^3, the pair xy = 0, the diagonal x + y = 0): every crossing is offered once, in
// the float channel (filter) and found in the double one, with and without cells. Rays
// aim at random points of the faces. Before session 6 a root on a face could fall
// between the spans of both cells (its rounding is relative to the re-centring point,
// the span's widening relative to t at the face): 2 of 15,000 such rays missed x = 0.
TEST_F(EmbreeFilter, PlanesOnCellFacesOfferedOnce) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::vector<RayD> rays;
  for (int i = 0; i < 3000; ++i) {
    const glm::dvec3 o(u(rng), u(rng), u(rng));
    glm::dvec3 target(u(rng) / 3, u(rng) / 3, u(rng) / 3);
    (i % 2 ? target.x : target.z) = i % 2 ? 0.0 : 0.25;
    // Exactly representable in float, so both channels trace the same line.
    const glm::dvec3 d = floatValues(target - o);
    rays.push_back(RayD{floatValues(o), d, 0.0, kInfF});
  }
  for (const char* equation : {"x", "z - 0.25", "x*y", "x + y"}) {
    std::vector<size_t> offers[2];
    std::vector<double> firstT[2];
    for (int cells = 0; cells < 2; ++cells) {
      SurfaceDesc desc;
      desc.polynomial = parsePolynomial(equation);
      desc.clip = ClipBox{glm::dvec3(-1.0), glm::dvec3(1.0)};
      desc.options.cellDepth = cells == 1 ? 3 : 0;
      FilteredSurface g(device, desc);
      ASSERT_EQ(g.geometry.primitiveCount() > 1, cells == 1) << equation;
      for (const RayD& r : rays) {
        log = FilterLog{1 << 30, 0, {}};
        intersect1(g.scene, makeRayHit(r));
        offers[cells].push_back(log.seenT.size());
      }
      rtcSetGeometryIntersectFilterFunction(g.geometry.geometry(), nullptr);
      rtcCommitGeometry(g.geometry.geometry());
      g.scene.commit();
      for (const RayD& r : rays) {
        const HitD hit = intersectD(g.scene, r);
        firstT[cells].push_back(hit.hit ? hit.t : -1.0);
      }
      EXPECT_EQ(g.geometry.callbackErrors(), 0u);
    }
    int crossings = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      ASSERT_EQ(offers[0][i], offers[1][i]) << equation << " ray " << i;
      ASSERT_EQ(firstT[0][i] >= 0.0, firstT[1][i] >= 0.0) << equation << " ray " << i;
      EXPECT_NEAR(firstT[0][i], firstT[1][i], 1e-12 * std::max(1.0, firstT[0][i]))
          << equation << " ray " << i;
      crossings += static_cast<int>(offers[0][i]);
      // The plane x = 0 in closed form (away from the box's edges).
      if (std::string_view(equation) == "x") {
        const RayD& r = rays[i];
        const double t = -r.org.x / r.dir.x;
        const glm::dvec3 p = r.org + t * r.dir;
        const double edge = std::min(1.0 - std::abs(p.y), 1.0 - std::abs(p.z));
        if (std::abs(edge) > 1e-9) {
          ASSERT_EQ(firstT[1][i] >= 0.0, t > 0.0 && edge > 0.0) << "ray " << i;
          if (firstT[1][i] >= 0.0) {
            EXPECT_NEAR(firstT[1][i], t, 1e-12 * t) << "ray " << i;
          }
        }
      }
    }
    EXPECT_GT(crossings, 1000) << equation;
  }
}

// The double channel from far away, through a grid edge: the float ray Embree traverses
// with passes up to u_float |o| beside the double one, so the owner cell of a root may not
// surely be reached and the cells around it claim it as an orphan (claimsRoot). Every
// root must still reach the host's filter once per trace. The plane z = 0.1 in depth-3
// cells, rays through points on the grid lines x = y = 0 (and 1e-7..1e-4 off them) from
// 10 to 1000 box radii: one crossing each, closed form. Before the offered-roots mask a
// rejecting filter saw it up to 7 times.
TEST_F(EmbreeFilter, DoubleChannelOffersAnOrphanRootOnce) {
  FilteredSurface g(device, inDepth3Cells("z - 0.1"));
  rtcSetGeometryOccludedFilterFunction(g.geometry.geometry(), &rejectingFilter);
  rtcCommitGeometry(g.geometry.geometry());
  g.scene.commit();
  ASSERT_GT(g.geometry.primitiveCount(), 1u);
  int rays = 0;
  for (const auto& [ray, delta, dist] : gridEdgeRays({10.0, 100.0, 1000.0}))
    for (const bool occlusion : {false, true}) {
      log = FilterLog{1 << 30, 0, {}};  // reject every candidate
      HitD hit;
      IntersectContext context;
      initIntersectContext(&context, &ray, &hit, g.scene);
      RTCRayHit rh = makeRayHit(ray, g.scene);
      if (occlusion)
        rtcOccluded1(g.scene, &context.base, &rh.ray);
      else
        rtcIntersect1(g.scene, &context.base, &rh);
      ASSERT_EQ(log.seenT.size(), 1u)
          << "delta " << delta << " dist " << dist << " occlusion " << occlusion;
      EXPECT_FALSE(hit.hit);
      ++rays;
    }
  EXPECT_EQ(rays, 72);
  EXPECT_EQ(g.geometry.callbackErrors(), 0u);
}

// An IntersectContext traced twice for the same ray (as Embree's own contexts are reused):
// every trace gets the first root again. A torus (the generic walk) hit along x
// at y = 0.1, z = 0.05 from x = -5: closed form t = 5 - sqrt((R + sqrt(r^2 - z^2))^2 - y^2).
// (The offered-roots mask, kept by the context's trace id, gave the next root each time.)
TEST_F(EmbreeFilter, ReusedContextFindsTheFirstRootAgain) {
  for (const int depth : {-1, 2}) {  // one cell (automatic), a grid of them
    SCOPED_TRACE(testing::Message() << "cell depth " << depth);
    SurfaceDesc desc;
    desc.polynomial = torusPolynomial(1.0, 0.4);
    desc.clip = ClipSphere{{0, 0, 0}, 1.6};
    desc.options.cellDepth = depth;
    const SurfaceScene scene(device, desc);
    const double rho = 1.0 + std::sqrt(0.16 - 0.05 * 0.05);
    const double first = 5.0 - std::sqrt(rho * rho - 0.01);
    const RayD ray{{-5, 0.1, 0.05}, {1, 0, 0}, 0, 100, 0};
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &ray, &hit, scene);
    for (int trace = 0; trace < 4; ++trace) {  // as many as the ray has roots
      hit = HitD{};
      RTCRayHit rh = makeRayHit(context);
      rtcIntersect1(scene, &context.base, &rh);
      ASSERT_TRUE(hit.hit) << "trace " << trace;
      EXPECT_NEAR(hit.t, first, 1e-12) << "trace " << trace;
    }
    hit = HitD{};  // (the HitD is the trace's running closest hit: reset, as above)
    RTCRay shadow = makeRayHit(context).ray;  // any of the roots occludes
    rtcOccluded1(scene, &context.base, &shadow);
    EXPECT_EQ(shadow.tfar, -kInfF);
    EXPECT_TRUE(hit.hit);
  }
}

// Contexts initialised on other threads than the one tracing them (a wavefront renderer's
// batches): two contexts of the same far ray through a grid edge, each made on a thread
// of its own, traced one after the other, both hit the plane z = 0.1 at t = dist (closed
// form). With a trace id counted per thread both had id 1, and the second trace skipped
// the orphan root the first had offered (24 of these 60 rays missed).
TEST_F(EmbreeFilter, ContextsMadeOnOtherThreadsFindTheirRoots) {
  const SurfaceScene scene(device, inDepth3Cells("z - 0.1"));
  for (const auto& [ray, delta, dist] : gridEdgeRays({10.0, 100.0, 1000.0, 1e4, 1e5})) {
    HitD hits[2];
    IntersectContext contexts[2];
    for (int k = 0; k < 2; ++k)
      std::thread([&, k, r = &ray] {
        initIntersectContext(&contexts[k], r, &hits[k], scene);
      }).join();
    for (int k = 0; k < 2; ++k) {
      RTCRayHit rh = makeRayHit(contexts[k]);
      rtcIntersect1(scene, &contexts[k].base, &rh);
      ASSERT_TRUE(hits[k].hit) << "context " << k << " delta " << delta << " dist " << dist;
      EXPECT_NEAR(hits[k].t, dist, 1e-12 * dist);
    }
  }
}

// A context reused for the same ray through a grid edge, where the plane's root is offered
// by a shared claim (the orphan rule): every trace, and an occlusion query after them,
// finds it again at t = dist. (The offered-roots marks, kept by the context's trace id,
// were the first trace's: every cell skipped the root from the second trace on, on 13 of
// these 60 rays.)
TEST_F(EmbreeFilter, ReusedContextFindsAGridEdgeRootAgain) {
  const SurfaceScene scene(device, inDepth3Cells("z - 0.1"));
  for (const auto& [ray, delta, dist] : gridEdgeRays({10.0, 100.0, 1000.0, 1e4, 1e5})) {
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &ray, &hit, scene);
    for (int trace = 0; trace < 3; ++trace) {
      hit = HitD{};
      RTCRayHit rh = makeRayHit(context);
      rtcIntersect1(scene, &context.base, &rh);
      EXPECT_TRUE(hit.hit) << "trace " << trace << " delta " << delta << " dist " << dist;
      if (hit.hit) {
        EXPECT_NEAR(hit.t, dist, 1e-12 * dist);
      }
    }
    hit = HitD{};
    RTCRay shadow = makeRayHit(context).ray;
    rtcOccluded1(scene, &context.base, &shadow);
    EXPECT_EQ(shadow.tfar, -kInfF) << "delta " << delta << " dist " << dist;
  }
}

// Offers (geomID per candidate) seen by a filter that rejects every candidate.
std::vector<unsigned> gOffers;
void rejectAndLogGeometry(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0) {
      gOffers.push_back(RTCHitN_geomID(args->hit, args->N, i));
      args->valid[i] = 0;
    }
}

// The orphan roots of DoubleChannelOffersAnOrphanRootOnce with two more planes in the
// scene (z = -0.3, x = 0.2), whose cells Embree visits between the first plane's: every
// plane's root still reaches the filter at most once per trace, the first plane's
// exactly once. (With the offered-roots mask in the per-thread root record, which the
// other planes' cells replaced, the first plane's root was offered up to 4 times, on 18
// of these 60 rays.)
TEST_F(EmbreeFilter, OrphanRootsOfferedOnceAmongSeveralSurfaces) {
  SurfaceDesc desc;
  desc.clip = ClipBox{glm::dvec3(-1.0), glm::dvec3(1.0)};
  desc.options.cellDepth = 3;
  std::vector<std::unique_ptr<SurfaceGeometry>> planes;
  Scene scene(device);
  for (const char* equation : {"z - 0.1", "z + 0.3", "x - 0.2"}) {
    desc.polynomial = parsePolynomial(equation);
    planes.push_back(std::make_unique<SurfaceGeometry>(device, desc));
    rtcSetGeometryIntersectFilterFunction(planes.back()->geometry(), &rejectAndLogGeometry);
    rtcCommitGeometry(planes.back()->geometry());
    scene.attach(planes.back()->geometry());
  }
  scene.commit();
  for (const auto& [ray, delta, dist] : gridEdgeRays({10.0, 100.0, 1000.0, 1e4, 1e5})) {
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &ray, &hit, scene);
    RTCRayHit rh = makeRayHit(context);
    gOffers.clear();
    rtcIntersect1(scene, &context.base, &rh);
    for (unsigned id = 0; id < 3; ++id)
      EXPECT_LE(std::count(gOffers.begin(), gOffers.end(), id), 1)
          << "plane " << id << " delta " << delta << " dist " << dist;
    EXPECT_EQ(std::count(gOffers.begin(), gOffers.end(), 0u), 1)
        << "delta " << delta << " dist " << dist;
  }
}

// The same with 40 planes z = 0.1 + k / 1000 in the same grid: each plane's root reaches
// the filter exactly once per trace. (The offered-roots table held 16 entries, evicted in
// turn: with 17 planes or more a plane's root was offered twice on 25 of 96 traces.)
TEST_F(EmbreeFilter, OrphanRootsOfferedOnceAmongFortySurfaces) {
  SurfaceDesc desc;
  desc.clip = ClipBox{glm::dvec3(-1.0), glm::dvec3(1.0)};
  desc.options.cellDepth = 3;
  constexpr unsigned kPlanes = 40;
  std::vector<std::unique_ptr<SurfaceGeometry>> planes;
  Scene scene(device);
  for (unsigned k = 0; k < kPlanes; ++k) {
    desc.polynomial = Z() - Polynomial(0.1 + 0.001 * k);
    planes.push_back(std::make_unique<SurfaceGeometry>(device, desc));
    rtcSetGeometryIntersectFilterFunction(planes.back()->geometry(), &rejectAndLogGeometry);
    rtcSetGeometryOccludedFilterFunction(planes.back()->geometry(), &rejectAndLogGeometry);
    rtcCommitGeometry(planes.back()->geometry());
    scene.attach(planes.back()->geometry());
  }
  scene.commit();
  for (const auto& [ray, delta, dist] : gridEdgeRays({10.0, 100.0, 1000.0, 1e4}))
    for (const bool occlusion : {false, true}) {
      HitD hit;
      IntersectContext context;
      initIntersectContext(&context, &ray, &hit, scene);
      RTCRayHit rh = makeRayHit(context);
      gOffers.clear();
      if (occlusion)
        rtcOccluded1(scene, &context.base, &rh.ray);
      else
        rtcIntersect1(scene, &context.base, &rh);
      for (unsigned id = 0; id < kPlanes; ++id)
        EXPECT_EQ(std::count(gOffers.begin(), gOffers.end(), id), 1)
            << "plane " << id << " delta " << delta << " dist " << dist << " occlusion "
            << occlusion;
    }
}

// The offered-roots mask belongs to one surface's roots: in the same trace another
// surface's root with the same index must still be offered. A quartic blob inside a
// torus's hole, seen from the torus's centre: the blob's first root, t = 0.7 (closed
// form: (x - 1)^4 = 0.0081), not its second; and behind a torus whose filter rejects every
// root, the surface x = 5 at t = 15, in both queries. (The mask kept across surfaces
// reported t = 1.3 and no hit at all.)
TEST_F(EmbreeFilter, OfferedRootsAreOneSurfacesOwn) {
  const auto add = [&](Scene& scene, const char* equation, glm::dvec3 centre, double radius) {
    SurfaceDesc desc;
    desc.polynomial = parsePolynomial(equation);
    desc.clip = ClipSphere{centre, radius};
    auto g = std::make_unique<SurfaceGeometry>(device, desc);
    scene.attach(g->geometry());
    return g;
  };
  {
    Scene scene(device);
    const auto torus = add(scene, "(x^2+y^2+z^2+8)^2 - 36*(x^2+y^2)", {0, 0, 0}, 4.5);
    const auto blob = add(scene, "(x-1)^4 + y^4 + z^4 - 0.0081", {1, 0, 0}, 0.5);
    scene.commit();
    const HitD hit = intersectD(scene, RayD{{0, 0, 0}, {1, 0, 0}, 0.0, kInfF});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 0.7, 1e-12);
    EXPECT_EQ(hit.geomID, 1u);
  }
  {
    Scene scene(device);
    const auto torus = add(scene, "(x^2+y^2+z^2+8)^2 - 36*(x^2+y^2)", {0, 0, 0}, 4.5);
    rtcSetGeometryIntersectFilterFunction(torus->geometry(), &rejectingFilter);
    rtcSetGeometryOccludedFilterFunction(torus->geometry(), &rejectingFilter);
    rtcCommitGeometry(torus->geometry());
    const auto wall = add(scene, "x - 5 + 0.01*(y^4 + z^4)", {5, 0, 0}, 1.0);
    scene.commit();
    log = FilterLog{1 << 30, 0, {}};
    const RayD ray{{-10, 0, 0}, {1, 0, 0}, 0.0, kInfF};
    const HitD hit = intersectD(scene, ray);
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 15.0, 1e-12);
    EXPECT_EQ(hit.geomID, 1u);
    EXPECT_EQ(log.seenT.size(), 4u);  // the torus's four roots, each once
    log = FilterLog{1 << 30, 0, {}};
    HitD occ;
    IntersectContext context;
    initIntersectContext(&context, &ray, &occ, scene);
    RTCRayHit rh = makeRayHit(context);
    rtcOccluded1(scene, &context.base, &rh.ray);
    EXPECT_EQ(rh.ray.tfar, -kInfF);
    EXPECT_TRUE(occ.hit);
    EXPECT_NEAR(occ.t, 15.0, 1e-12);
  }
}

TEST_F(EmbreeFilter, TorusFilterWalksAllFourRoots) {
  SurfaceDesc desc;
  desc.polynomial = torusPolynomial(1.0, 0.4);
  desc.clip = ClipSphere{{0, 0, 0}, 1.6};
  desc.options.useCells = false;
  FilteredSurface torus(device, desc);
  log = FilterLog{3, 0, {}};
  RTCRayHit rh = intersect1(torus.scene, makeRay({-5, 0, 0}, {1, 0, 0}));
  ASSERT_EQ(log.seenT.size(), 4u);
  const float expected[4] = {3.6f, 4.4f, 5.6f, 6.4f};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(log.seenT[i], expected[i], 1e-6f);
  EXPECT_NEAR(rh.ray.tfar, 6.4f, 1e-6f);
}

// With SurfaceOptions::uv on, an occlusion filter sees the u, v an intersection filter sees
// for the same root (an alpha-textured shadow reads them there, as Embree's triangles give
// them), both within float rounding of the sphere's spherical coordinates (closed form);
// Ng stays zero (occlusion computes no normal). Float rays and the double channel. (Every
// occlusion candidate had u = v = 0.)
struct UvLog {
  std::vector<glm::vec2> uv;
  std::vector<glm::vec3> ng;
};
UvLog* gUv = nullptr;
void uvFilter(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    gUv->uv.emplace_back(RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
    gUv->ng.emplace_back(RTCHitN_Ng_x(args->hit, args->N, i), RTCHitN_Ng_y(args->hit, args->N, i),
                         RTCHitN_Ng_z(args->hit, args->N, i));
  }
}

TEST_F(EmbreeFilter, OcclusionFiltersSeeTheIntersectionsUv) {
  SurfaceDesc desc = sphereDesc(1.0, 1.5);
  desc.options.uv = true;
  SurfaceGeometry sphere(device, desc);
  rtcSetGeometryIntersectFilterFunction(sphere.geometry(), &uvFilter);
  rtcSetGeometryOccludedFilterFunction(sphere.geometry(), &uvFilter);
  rtcCommitGeometry(sphere.geometry());
  Scene scene(device);
  scene.attach(sphere.geometry());
  scene.commit();
  std::mt19937 gen(4404);
  std::uniform_real_distribution<float> uniform(-0.9f, 0.9f);
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    const glm::vec3 target(uniform(gen), uniform(gen), uniform(gen));
    const glm::vec3 o = 4.0f * randomUnit(gen);
    const glm::vec3 d = glm::normalize(target - o);
    for (const bool doubleChannel : {false, true}) {
      UvLog hitLog, shadowLog;
      RayD rayD{glm::dvec3(o), glm::dvec3(d), 0, kInfF, 0};
      gUv = &hitLog;
      RTCRayHit rh = makeRay(o, d);
      if (doubleChannel) {
        intersectD(scene, rayD, &rh);
      } else {
        rh = intersect1(scene, rh);
      }
      gUv = &shadowLog;
      if (doubleChannel) {
        HitD hit;
        IntersectContext context;
        initIntersectContext(&context, &rayD, &hit, scene);
        RTCRayHit shadow = makeRayHit(context);
        rtcOccluded1(scene, &context.base, &shadow.ray);
      } else {
        occluded1(scene, makeRay(o, d).ray);
      }
      gUv = nullptr;
      if (hitLog.uv.empty()) continue;
      ASSERT_FALSE(shadowLog.uv.empty());
      EXPECT_EQ(shadowLog.uv[0], hitLog.uv[0]) << k << " " << doubleChannel;
      EXPECT_EQ(shadowLog.ng[0], glm::vec3(0.0f));
      const glm::dvec3 p = glm::dvec3(o) + double(rh.ray.tfar) * glm::dvec3(d);
      double u = std::atan2(p.y, p.x) / (2 * M_PI);
      if (u < 0) u += 1;
      const double v = std::acos(std::clamp(p.z / glm::length(p), -1.0, 1.0)) / M_PI;
      EXPECT_NEAR(hitLog.uv[0].x, u, 1e-5) << k;
      EXPECT_NEAR(hitLog.uv[0].y, v, 1e-5) << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
}

TEST_F(EmbreeFilter, ContextFilterIsChainedThroughAlgrayContext) {
  SurfaceGeometry sphere(device, sphereDesc(1.0, 1.5));
  Scene scene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  scene.attach(sphere.geometry());
  scene.commit();
  RayD ray{{0, 0, -5}, {0, 0, 1}, 0, 100, 0};
  HitD hit;
  IntersectContext context;
  initIntersectContext(&context, &ray, &hit);
  context.hostFilter = &rejectingFilter;
  RTCRayHit rh = makeRayHit(ray);
  log = FilterLog{1, 0, {}};
  rtcIntersect1(scene, &context.base, &rh);
  EXPECT_EQ(log.calls, 2);  // the host's context filter ran once per root, rejected the first
  ASSERT_TRUE(hit.hit);
  EXPECT_DOUBLE_EQ(hit.t, 6.0);
  EXPECT_FLOAT_EQ(rh.ray.tfar, 6.0f);
  // A plain context on the same scene: no chaining needed, no crash.
  rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}));
  EXPECT_FLOAT_EQ(rh.ray.tfar, 4.0f);
}

// The same chaining for a hit on another geometry type: the algray context's own filter
// (the bridge's marker filter) must hand a triangle's candidate to the host's context
// filter too, whose rejection then holds (with the hand-over dropped, the quad's hit was
// reported without the host filter ever running: the mutation audit of session 55).
TEST_F(EmbreeFilter, ContextFilterIsChainedForOtherGeometryTypes) {
  Scene scene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  RTCGeometry quad = makeQuad(device, 0.0f, 2.0f);  // the plane z = 0, |x|, |y| <= 2
  scene.attach(quad);
  rtcReleaseGeometry(quad);
  scene.commit();
  for (const int rejects : {1, 0}) {
    RayD ray{{0.5, -0.25, -5}, {0, 0, 1}, 0, 100, 0};
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &ray, &hit);
    context.hostFilter = &rejectingFilter;
    RTCRayHit rh = makeRayHit(ray);
    log = FilterLog{rejects, 0, {}};
    rtcIntersect1(scene, &context.base, &rh);
    EXPECT_EQ(log.calls, 1) << rejects;
    if (rejects == 1) {
      EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
    } else {
      EXPECT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
      EXPECT_FLOAT_EQ(rh.ray.tfar, 5.0f);
    }
  }
}

// A host filter that throws (the first call only): the adapter counts it as a miss of
// that surface. The ray must then go on as if the surface were not there: its far end
// kept (so the unit sphere B behind, centred at z = 5, is hit at t = 9 from z = -5), and
// an algray context still algray's for the rest of the trace (B's HitD written).
void throwOnce(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] != 0 && gLog->calls++ == 0) throw std::runtime_error("host filter");
}

TEST_F(EmbreeFilter, ThrowingHostFilterCountsAsAMiss) {
  for (const bool quadricCallbacks : {true, false}) {
    SCOPED_TRACE(quadricCallbacks ? "quadric callbacks" : "generic walk");
    SurfaceDesc desc = sphereDesc(1.0, 1.5);
    desc.options.quadricCallbacks = quadricCallbacks;
    SurfaceGeometry a(device, desc);
    rtcSetGeometryIntersectFilterFunction(a.geometry(), &throwOnce);
    rtcSetGeometryOccludedFilterFunction(a.geometry(), &throwOnce);
    rtcCommitGeometry(a.geometry());
    desc.transform[3] = glm::dvec4(0, 0, 5, 1);
    SurfaceGeometry b(device, desc);
    Scene scene(device);
    scene.attach(a.geometry());
    const unsigned bId = scene.attach(b.geometry());
    scene.commit();

    log = FilterLog{};
    const RTCRayHit rh = intersect1(scene, makeRay({0, 0, -5}, {0, 0, 1}));
    EXPECT_EQ(rh.hit.geomID, bId);
    EXPECT_FLOAT_EQ(rh.ray.tfar, 9.0f);
    EXPECT_EQ(a.callbackErrors(), 1u);

    log = FilterLog{};
    RTCRay shadow = makeRay({0, 0, -5}, {0, 0, 1}, 0.0f, 8.0f).ray;  // ends before B
    EXPECT_FALSE(occluded1(scene, shadow));

    log = FilterLog{};
    const RayD ray{{0, 0, -5}, {0, 0, 1}, 0, 100, 0};
    HitD hit;
    IntersectContext context;
    initIntersectContext(&context, &ray, &hit, scene);
    RTCRayHit drh = makeRayHit(context);
    rtcIntersect1(scene, &context.base, &drh);
    EXPECT_EQ(drh.hit.geomID, bId);
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.geomID, bId);
    EXPECT_DOUBLE_EQ(hit.t, 9.0);
    EXPECT_NE(context.base.filter, nullptr);  // still recognised as algray's
  }
}

TEST_F(EmbreeFilter, InstancesWithTransforms) {
  SurfaceGeometry sphere(device, sphereDesc(1.0, 1.5));
  Scene inner(device);
  const unsigned innerId = inner.attach(sphere.geometry());
  inner.commit();
  Scene top(device);
  // Two instances: scaled by 2 at x = -10, and translated to x = +10.
  std::vector<unsigned> instIds;
  const float xfms[2][12] = {{2, 0, 0, 0, 2, 0, 0, 0, 2, -10, 0, 0},
                             {1, 0, 0, 0, 1, 0, 0, 0, 1, 10, 0, 0}};
  for (const auto& xfm : xfms) {
    RTCGeometry inst = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, inner);
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    rtcCommitGeometry(inst);
    instIds.push_back(top.attach(inst));
    rtcReleaseGeometry(inst);
  }
  top.commit();
  RTCRayHit rh = intersect1(top, makeRay({-10, 0, -10}, {0, 0, 1}));
  EXPECT_EQ(rh.hit.instID[0], instIds[0]);
  EXPECT_EQ(rh.hit.geomID, innerId);
  EXPECT_FLOAT_EQ(rh.ray.tfar, 8.0f);  // radius 2 after scaling
  EXPECT_NEAR(hitNormal(rh).z, -1.0f, 1e-6f);
  // Oblique: Ng is in the instanced scene's (object) space: the unit-sphere normal.
  rh = intersect1(top, makeRay({10.6f, 0, -10}, {0, 0, 1}));
  EXPECT_EQ(rh.hit.instID[0], instIds[1]);
  const float z = -std::sqrt(1.0f - 0.36f);
  EXPECT_NEAR(rh.ray.tfar, 10.0f + z, 1e-5f);
  const glm::vec3 n = hitNormal(rh);
  EXPECT_NEAR(n.x, 0.6f, 1e-5f);
  EXPECT_NEAR(n.z, z, 1e-5f);
  RTCRay shadow = makeRay({-10, 0, -10}, {0, 0, 1}).ray;
  EXPECT_TRUE(occluded1(top, shadow));
  shadow = makeRay({0, 0, -10}, {0, 0, 1}).ray;
  EXPECT_FALSE(occluded1(top, shadow));
  // The double context inside an instance falls back to the float ray (still correct).
  RayD ray{{-10, 0, -10}, {0, 0, 1}, 0, 100, 0};
  RTCRayHit out;
  intersectD(top, ray, &out);
  EXPECT_FLOAT_EQ(out.ray.tfar, 8.0f);
  EXPECT_EQ(out.hit.instID[0], instIds[0]);
}

// Packets: rtcIntersectN / rtcOccludedN against rtcIntersect1 on the same rays, with
// some lanes switched off by the valid mask.
template <int N, class RayHitN, class RayN>
void checkPackets(RTCDevice device, RTCScene scene, std::mt19937& rng) {
  // Inactive lanes also empty where Embree ignores the mask (embreeHonoursValidMask).
  const bool emptyInactive = !embreeHonoursValidMask(device, N);
  std::normal_distribution<float> g;
  std::uniform_real_distribution<float> u(-1.4f, 1.4f);
  for (int round = 0; round < 20; ++round) {
    alignas(64) RayHitN packet{};
    alignas(64) RayN shadow{};
    alignas(64) int valid[N];
    std::vector<RTCRayHit> singles;
    for (int i = 0; i < N; ++i) {
      const glm::vec3 o = 4.0f * glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
      const glm::vec3 d = glm::vec3(u(rng), u(rng), u(rng)) - o;
      valid[i] = (i % 5 == 4) ? 0 : -1;
      const float tfar = !valid[i] && emptyInactive ? -1.0f : i % 3 == 0 ? 3.5f : kInfF;
      const RTCRayHit one = makeRay(o, d, 0.0f, tfar);
      singles.push_back(one);
      packet.ray.org_x[i] = shadow.org_x[i] = o.x;
      packet.ray.org_y[i] = shadow.org_y[i] = o.y;
      packet.ray.org_z[i] = shadow.org_z[i] = o.z;
      packet.ray.dir_x[i] = shadow.dir_x[i] = d.x;
      packet.ray.dir_y[i] = shadow.dir_y[i] = d.y;
      packet.ray.dir_z[i] = shadow.dir_z[i] = d.z;
      packet.ray.tnear[i] = shadow.tnear[i] = 0.0f;
      packet.ray.tfar[i] = shadow.tfar[i] = one.ray.tfar;
      packet.ray.mask[i] = shadow.mask[i] = ~0u;
      packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if constexpr (N == 4) {
      rtcIntersect4(valid, scene, &context, &packet);
      rtcOccluded4(valid, scene, &context, &shadow);
    } else if constexpr (N == 8) {
      rtcIntersect8(valid, scene, &context, &packet);
      rtcOccluded8(valid, scene, &context, &shadow);
    } else {
      rtcIntersect16(valid, scene, &context, &packet);
      rtcOccluded16(valid, scene, &context, &shadow);
    }
    for (int i = 0; i < N; ++i) {
      if (!valid[i]) {
        EXPECT_EQ(packet.hit.geomID[i], RTC_INVALID_GEOMETRY_ID);
        continue;
      }
      const RTCRayHit one = intersect1(scene, singles[i]);
      EXPECT_EQ(packet.hit.geomID[i], one.hit.geomID) << N << " lane " << i;
      EXPECT_EQ(packet.ray.tfar[i], one.ray.tfar) << N << " lane " << i;
      if (one.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        EXPECT_EQ(packet.hit.Ng_x[i], one.hit.Ng_x);
        EXPECT_EQ(packet.hit.u[i], one.hit.u);
        EXPECT_EQ(packet.hit.primID[i], one.hit.primID);
      }
      EXPECT_EQ(shadow.tfar[i] == -kInfF, occluded1(scene, singles[i].ray)) << N << " lane " << i;
    }
  }
}

TEST_F(EmbreeFilter, PacketsAgreeWithSingleRays) {
  SurfaceDesc desc;
  desc.polynomial = torusPolynomial(1.0, 0.4);
  desc.clip = ClipSphere{{0, 0, 0}, 1.6};
  SurfaceGeometry torus(device, desc);
  SurfaceGeometry sphere(device, sphereDesc(0.3, 0.5));
  Scene scene(device);
  scene.attach(torus.geometry());
  scene.attach(sphere.geometry());
  scene.commit();
  std::mt19937 rng(7);
  checkPackets<4, RTCRayHit4, RTCRay4>(device, scene, rng);
  checkPackets<8, RTCRayHit8, RTCRay8>(device, scene, rng);
  checkPackets<16, RTCRayHit16, RTCRay16>(device, scene, rng);
  EXPECT_EQ(torus.callbackErrors(), 0u);
}

TEST_F(EmbreeFilter, ThreadsShareOneSurface) {
  for (const bool originCache : {false, true}) {
    SCOPED_TRACE(originCache ? "origin cache" : "default");
    SurfaceDesc desc;
    desc.polynomial = torusPolynomial(1.0, 0.4);
    desc.clip = ClipSphere{{0, 0, 0}, 1.6};
    desc.options.originCache = originCache;  // the per-thread expansions too
    const SurfaceScene scene(device, desc);
    // Reference single-threaded, then 4 threads over the same rays (the per-thread caches
    // must not leak between threads).
    std::vector<RTCRayHit> rays;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.4f, 1.4f);
    for (int i = 0; i < 400; ++i)
      rays.push_back(makeRay({0.1f * (i % 4), 0, -4}, glm::vec3(u(rng), u(rng), 4.0f)));
    std::vector<float> ref;
    for (const auto& r : rays) ref.push_back(intersect1(scene, r).ray.tfar);
    std::atomic<int> mismatches{0};
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
      threads.emplace_back([&, k] {
        for (size_t i = k; i < rays.size() * 4; i += 4) {
          const size_t j = (i * 7) % rays.size();
          if (intersect1(scene, rays[j]).ray.tfar != ref[j]) ++mismatches;
        }
      });
    for (auto& t : threads) t.join();
    EXPECT_EQ(mismatches.load(), 0);
  }
}

}  // namespace
}  // namespace algray::test
