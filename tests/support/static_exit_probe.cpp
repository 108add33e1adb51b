// A host that traces rays from a static destructor, after algray's own statics are gone
// (registered as the test EmbreeThreads.RaysFromStaticDestructorsHit): a new thread's first
// ray there needs per-thread state whose thread key was deleted with those statics
// (thread_heap.h), and missed. Exit code 0 when every ray hits the torus where the closed
// form says (the tube R = 1, r = 0.4 below x = 1, y = 0.01).
#include "algray/embree.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <thread>

namespace {

struct Host {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::unique_ptr<algray::SurfaceGeometry> torus;

  bool trace() const {
    const algray::RayD ray{
        {1.0, 0.01, -5.0}, {0, 0, 1}, 0.0, std::numeric_limits<double>::infinity(), 0.0};
    algray::HitD hit;
    algray::IntersectContext context;
    algray::initIntersectContext(&context, &ray, &hit, scene);
    RTCRayHit rh = algray::makeRayHit(context);
    rtcIntersect1(scene, &context.base, &rh);
    // The tube at x = 1, y = 0.01: z = -sqrt(0.16 - w^2), w = sqrt(1 + 1e-4) - 1.
    const double w = std::sqrt(1.0 + 1e-4) - 1.0, t = 5.0 - std::sqrt(0.16 - w * w);
    return hit.hit && std::abs(hit.t - t) < 1e-12;
  }
  ~Host() {
    if (!scene) return;
    bool onNewThread = false;
    std::thread([&] { onNewThread = trace(); }).join();
    const bool onThisThread = trace();
    std::printf("rays from a static destructor: new thread %s, this thread %s\n",
                onNewThread ? "hit" : "MISSED", onThisThread ? "hit" : "MISSED");
    std::fflush(stdout);
    if (!onNewThread || !onThisThread) std::_Exit(3);
  }
};
Host gHost;  // constructed before main, so destroyed after algray's function-local statics

}  // namespace

int main() {
  gHost.device = rtcNewDevice(nullptr);
  gHost.scene = rtcNewScene(gHost.device);
  gHost.torus = std::make_unique<algray::SurfaceGeometry>(
      gHost.device, "(x^2+y^2+z^2+0.84)^2 - 4*(x^2+y^2)", algray::ClipSphere{{0, 0, 0}, 1.5});
  rtcAttachGeometry(gHost.scene, gHost.torus->geometry());
  rtcCommitScene(gHost.scene);
  if (!gHost.trace()) return 2;
  bool onNewThread = false;
  std::thread([&] { onNewThread = gHost.trace(); }).join();
  return onNewThread ? 0 : 2;
}
