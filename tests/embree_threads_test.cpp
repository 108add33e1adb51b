// The intersector's per-thread state and a host's threads: a thread's first ray must not
// wait for a dlopen running on another thread (ray_roots.cpp, threadOriginCache).
// A C++ thread_local with a destructor registers it through __cxa_thread_atexit, which
// takes the dynamic loader's lock; algray-render loads OpenImageIO on a second thread while
// it renders, and its render thread stood still for the whole load.
//
// The test holds the loader's lock on purpose: it dlopens a library whose constructor
// (run under that lock) waits for a second thread to trace its first rays through a torus
// (degree 4: the origin cache's path) and then returns. If the second thread had to take
// the lock, the two would wait for each other until the constructor gives up (after
// kPatience, a deadlock breaker, not a timing target) and the test fails.
#include "algray/embree.h"
#include "algray/gallery.h"

#include <gtest/gtest.h>

#include <dlfcn.h>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <random>
#include <thread>

#include "embree_test_util.h"

namespace {

constexpr auto kPatience = std::chrono::seconds(10);

std::mutex gMutex;
std::condition_variable gChanged;
bool gInsideDlopen = false, gTraced = false, gGaveUp = false;

}  // namespace

// Called by tests/support/loader_lock_probe.cpp's constructor, inside dlopen.
extern "C" __attribute__((visibility("default"))) void algrayTestInsideDlopen() {
  std::unique_lock lock(gMutex);
  gInsideDlopen = true;
  gChanged.notify_all();
  gGaveUp = !gChanged.wait_for(lock, kPatience, [] { return gTraced; });
}

namespace algray::test {
namespace {

TEST(EmbreeThreads, FirstRayOfAThreadDoesNotWaitForTheLoader) {
  Device device;
  SurfaceDesc desc;
  desc.polynomial = torusPolynomial(1.0, 0.4);
  desc.clip = ClipSphere{{0, 0, 0}, 1.6};
  desc.options.originCache = true;  // the per-thread state under test (off by default)
  const SurfaceScene scene(device, desc);

  // The tracing thread exists before the loader's lock is taken (creating a thread needs
  // it too), then waits until the constructor holds it.
  float tfar[3] = {0, 0, 0};
  std::thread tracer([&] {
    {
      std::unique_lock lock(gMutex);
      gChanged.wait(lock, [] { return gInsideDlopen; });
    }
    for (float& t : tfar)
      t = intersect1(scene, makeRay({0.0f, -3.0f, 0.2f}, {0.0f, 1.0f, 0.0f})).ray.tfar;
    std::lock_guard lock(gMutex);
    gTraced = true;
    gChanged.notify_all();
  });
  void* handle = dlopen(ALGRAY_LOADER_LOCK_PROBE, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << dlerror();
  tracer.join();
  dlclose(handle);
  EXPECT_TRUE(gTraced);
  EXPECT_FALSE(gGaveUp) << "the tracing thread waited for the dynamic loader's lock";
  // The rays meet the tube where (|y| - 1)^2 + 0.2^2 = 0.4^2, y = -1 - sqrt(0.12): t = 2 -
  // sqrt(0.12) (the first ray fills the cache's pending slot, the second builds the
  // expansion, the third uses it).
  for (const float t : tfar) EXPECT_NEAR(t, 2.0 - std::sqrt(0.12), 1e-5);
  EXPECT_EQ(scene.geometry.callbackErrors(), 0u);
}

// A host's own thread key, made after algray's per-thread state, whose destructor traces
// rays at the thread's exit, after algray's key freed that state (POSIX runs them in no
// set order): the rays hit the torus as before (t = 2 - sqrt(0.12), as above), through the
// origin cache (three rays from one origin) and the double channel's offered roots. The
// cache's thread_local pointer outlived the cache (a use after free, seen by the
// AddressSanitizer build; thread_heap.h).
pthread_key_t gHostKey;
const RTCScene* gExitScene = nullptr;
float gExitT[3] = {0, 0, 0};
double gExitTD = 0;
void traceAtThreadExit(void*) {
  for (float& t : gExitT)
    t = intersect1(*gExitScene, makeRay({0.0f, -3.0f, 0.2f}, {0.0f, 1.0f, 0.0f})).ray.tfar;
  const RayD ray{
      {0.0, -3.0, 0.2}, {0.0, 1.0, 0.0}, 0.0, std::numeric_limits<double>::infinity(), 0.0};
  gExitTD = intersectD(*gExitScene, ray).t;
}

TEST(EmbreeThreads, RaysTracedAtThreadExitFindTheirHits) {
  Device device;
  SurfaceDesc desc;
  desc.polynomial = torusPolynomial(1.0, 0.4);
  desc.clip = ClipSphere{{0, 0, 0}, 1.6};
  desc.options.originCache = true;
  desc.options.cellDepth = 2;
  const SurfaceScene scene(device, desc);
  const RTCScene sceneHandle = scene;
  gExitScene = &sceneHandle;
  std::thread([&] {
    intersect1(scene, makeRay({0.0f, -3.0f, 0.2f}, {0.0f, 1.0f, 0.0f}));  // algray's keys
    intersectD(
        scene,
        RayD{{0.0, -3.0, 0.2}, {0.0, 1.0, 0.0}, 0.0, std::numeric_limits<double>::infinity(), 0.0});
    ASSERT_EQ(pthread_key_create(&gHostKey, &traceAtThreadExit), 0);
    pthread_setspecific(gHostKey, &gHostKey);
  }).join();
  pthread_key_delete(gHostKey);
  for (const float t : gExitT) EXPECT_NEAR(t, 2.0 - std::sqrt(0.12), 1e-5);
  EXPECT_NEAR(gExitTD, 2.0 - std::sqrt(0.12), 1e-12);
  EXPECT_EQ(scene.geometry.callbackErrors(), 0u);
}

// A host unloads a plugin that links algray into itself while a thread that traced rays
// through it lives on: at that thread's exit no destructor of the unloaded plugin may run
// (algray's thread keys are deleted with the plugin's statics). Before, the thread crashed
// at its exit in code no longer mapped (a Clang build; GCC's unique symbols keep the plugin
// loaded, so there the test cannot tell).
TEST(EmbreeThreads, ThreadsOutliveAnUnloadedPlugin) {
  void* handle = dlopen(ALGRAY_UNLOAD_PROBE, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << dlerror();
  using Trace = double (*)();
  const auto trace = reinterpret_cast<Trace>(dlsym(handle, "algrayProbeTrace"));
  ASSERT_NE(trace, nullptr) << dlerror();
  std::mutex mutex;
  std::condition_variable changed;
  bool traced = false, unloaded = false;
  double t = 0.0;
  std::thread worker([&] {
    t = trace();
    std::unique_lock lock(mutex);
    traced = true;
    changed.notify_all();
    changed.wait(lock, [&] { return unloaded; });
  });  // exits after the dlclose
  {
    std::unique_lock lock(mutex);
    changed.wait(lock, [&] { return traced; });
  }
  dlclose(handle);
  {
    std::lock_guard lock(mutex);
    unloaded = true;
    changed.notify_all();
  }
  worker.join();
  EXPECT_NEAR(t, 2.0 - std::sqrt(0.12), 1e-12);
}

// Embree's and TBB's worker threads (and a host's tbb::parallel_for beside Embree, as in
// algray-render and algray-query) run with flush-to-zero and denormals-are-zero, where a
// result below double's normal range becomes 0 instead of a subnormal. Every gallery
// surface's hits are the same bit for bit either way: double channel, rays from near the
// centre and from 3 radii, a quarter of them nearly level (d_z 1e-12 of the others: tiny
// powers of the direction in the restriction).
TEST(EmbreeThreads, FlushToZeroChangesNoGalleryHit) {
#if defined(__SSE__)
  Device device;
  const unsigned saved = _mm_getcsr();
  for (const GallerySurface& s : gallery()) {
    SurfaceDesc desc;
    desc.polynomial = s.build();
    desc.clip = ClipSphere{glm::dvec3(0.0), s.clipRadius};
    const SurfaceScene scene(device, desc);
    std::mt19937 gen(1);
    std::normal_distribution<double> gauss;
    int hits = 0;
    for (int i = 0; i < 1000; ++i) {
      glm::dvec3 o(gauss(gen), gauss(gen), gauss(gen)), d(gauss(gen), gauss(gen), gauss(gen));
      o *= s.clipRadius * (i % 2 ? 3.0 : 0.3);
      if (i % 4 == 1) d.z *= 1e-12;
      const RayD ray{o, d, 0.0, std::numeric_limits<double>::infinity()};
      _mm_setcsr(saved & ~0x8040u);  // gradual underflow
      const HitD gradual = intersectD(scene, ray);
      _mm_setcsr(saved | 0x8040u);  // FTZ (bit 15) | DAZ (bit 6)
      const HitD flushed = intersectD(scene, ray);
      _mm_setcsr(saved);
      ASSERT_EQ(flushed.hit, gradual.hit) << s.name << " ray " << i;
      hits += gradual.hit;
      if (gradual.hit) {
        EXPECT_EQ(flushed.t, gradual.t) << s.name << " ray " << i;
      }
    }
    EXPECT_GT(hits, 100) << s.name;
  }
#else
  GTEST_SKIP() << "no SSE control register";
#endif
}

}  // namespace
}  // namespace algray::test
