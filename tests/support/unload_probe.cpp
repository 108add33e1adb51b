// A plugin for tests/embree_threads_test.cpp that links algray into itself: it traces a
// torus's rays through the per-thread state whose thread keys algray makes (the origin
// cache, the double channel's offered roots), and the test unloads it while the thread
// that traced lives on.
#include "algray/embree.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>

// The hit t of the ray from (0, -3, 0.2) along +y through the torus R = 1, r = 0.4 (2 -
// sqrt(0.12)): three float rays from one origin (the cache's path), then the double channel.
extern "C" __attribute__((visibility("default"))) double algrayProbeTrace() {
  RTCDevice device = rtcNewDevice(nullptr);
  double t = -1.0;
  {
    algray::SurfaceOptions options;
    options.originCache = true;
    options.cellDepth = 2;
    const algray::SurfaceGeometry torus(device, "(x^2+y^2+z^2+0.84)^2 - 4*(x^2+y^2)",
                                        algray::ClipSphere{{0, 0, 0}, 1.6}, {}, glm::dmat4(1.0),
                                        options);
    RTCScene scene = rtcNewScene(device);
    rtcAttachGeometry(scene, torus.geometry());
    rtcCommitScene(scene);
    for (int i = 0; i < 3; ++i) {
      RTCRayHit rh{};
      rh.ray.org_y = -3.0f;
      rh.ray.org_z = 0.2f;
      rh.ray.dir_y = 1.0f;
      rh.ray.tfar = std::numeric_limits<float>::infinity();
      rh.ray.mask = ~0u;
      rh.hit.geomID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      rtcIntersect1(scene, &context, &rh);
    }
    const algray::RayD ray{
        {0.0, -3.0, 0.2}, {0.0, 1.0, 0.0}, 0.0, std::numeric_limits<double>::infinity(), 0.0};
    algray::HitD hit;
    algray::IntersectContext context;
    algray::initIntersectContext(&context, &ray, &hit, scene);
    RTCRayHit rh = algray::makeRayHit(context);
    rtcIntersect1(scene, &context.base, &rh);
    if (hit.hit) t = hit.t;
    rtcReleaseScene(scene);
  }
  rtcReleaseDevice(device);
  return t;
}
