#include "render.h"

#include "integrator.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <thread>

namespace algray::render {

void Image::resize(int w, int h) {
  width = w;
  height = h;
  auto n = static_cast<size_t>(w) * h;
  color.assign(n, glm::vec3(0.0f));
  depth.assign(n, 0.0f);
  normal.assign(n, glm::vec3(0.0f));
  albedo.assign(n, glm::vec3(0.0f));
  id.assign(n, 0.0f);
  overflow.assign(n, 0.0);
}

namespace {

constexpr int kTile = 16;

// seen[geomID] = 1 for every geometry a camera ray hit first or saw through glass.
void markSeen(std::vector<std::uint8_t>& seen, unsigned idPlusOne) {
  if (idPlusOne == 0) return;
  if (seen.size() < idPlusOne) seen.resize(idPlusOne, 0);
  seen[idPlusOne - 1] = 1;
}

void renderPixel(const Scene& scene, const Camera& camera, Image& image, int x, int y,
                 RayCounter& counter, std::vector<std::uint8_t>& seen) {
  const RenderSettings& s = scene.desc().settings;
  auto pixel = static_cast<size_t>(y) * image.width + x;
  Rng rng(pixel, s.seed);
  glm::dvec3 sum(0.0), normal(0.0), albedo(0.0);
  // Depth and id are not averaged: a mean of two surfaces' distances (or of a distance
  // and a miss's 0) is a depth no surface in the pixel has. Both come from one sample,
  // the one whose camera ray hit nearest (a z-buffer's choice); 0 and 0 if none hit.
  double depth = 0, id = 0;
  for (int i = 0; i < s.spp; ++i) {
    // One sample per pixel looks through the pixel centre (comparable with POV-Ray).
    glm::dvec2 jitter = rng.uniform2();
    if (s.spp == 1) jitter = {0.5, 0.5};
    glm::dvec2 lens = rng.uniform2();
    CameraRay ray = camera.generateRay({x + jitter.x, y + jitter.y}, lens);
    SampleAov aov;
    glm::dvec3 L = s.integrator == IntegratorType::Path ? tracePath(scene, ray, rng, aov, counter)
                   : s.integrator == IntegratorType::Surfer
                       ? traceSurfer(scene, ray, rng, aov, counter)
                       : traceDirect(scene, ray, rng, aov, counter);
    // A non-finite sample (should not happen) must not poison the pixel.
    if (std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z)) sum += L;
    if (aov.id > 0 && (id == 0 || aov.depth < depth)) depth = aov.depth, id = aov.id;
    markSeen(seen, static_cast<unsigned>(aov.id));
    markSeen(seen, aov.seenThrough);
    normal += aov.normal;
    albedo += aov.albedo;
  }
  double inv = 1.0 / s.spp;
  const glm::dvec3 mean = sum * inv;
  image.color[pixel] = glm::vec3(mean);
  // Beyond float the pixel holds inf (render() reports it): the mean, not inf, is the
  // message's value.
  const glm::vec3& c = image.color[pixel];
  if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
    image.overflow[pixel] = std::max({mean.x, mean.y, mean.z});
  image.depth[pixel] = static_cast<float>(depth);
  double nl = std::sqrt(normal.x * normal.x + normal.y * normal.y + normal.z * normal.z);
  image.normal[pixel] = nl > 0 ? glm::vec3(normal / nl) : glm::vec3(0.0f);
  image.albedo[pixel] = glm::vec3(albedo * inv);
  image.id[pixel] = static_cast<float>(id);
}

// "[#####.....]  42%  1.2 Mrays/s  ETA 3s" on one terminal line.
void drawProgress(int done, int total, double seconds, std::uint64_t rays) {
  const int width = 30;
  int filled = total > 0 ? done * width / total : width;
  char bar[width + 1];
  for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
  bar[width] = 0;
  double rate = seconds > 0 ? rays / seconds : 0;
  double eta = done > 0 ? seconds * (total - done) / done : 0;
  std::fprintf(stderr, "\r[%s] %3d%%  %6.2f Mrays/s  ETA %4.0fs ", bar,
               total ? 100 * done / total : 100, rate * 1e-6, eta);
  std::fflush(stderr);
}

}  // namespace

RenderStats render(const Scene& scene, Image& image, const RenderOptions& options) {
  const RenderSettings& s = scene.desc().settings;
  image.resize(s.width, s.height);
  Camera camera(scene.desc().camera, s.width, s.height);
  int tilesX = (s.width + kTile - 1) / kTile, tilesY = (s.height + kTile - 1) / kTile;
  RenderStats stats;
  stats.tilesTotal = tilesX * tilesY;

  std::unique_ptr<tbb::global_control> limit;
  if (s.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  static_cast<size_t>(s.threads));
  tbb::enumerable_thread_specific<RayCounter> counters;
  tbb::enumerable_thread_specific<std::vector<std::uint8_t>> seenSets;
  std::atomic<int> tilesDone{0};
  // The progress bar's ray count, published per pixel: the monitor reads this, not the
  // threads' counters (a plain integer another thread writes, and an
  // enumerable_thread_specific that local() may grow while it is iterated: data races).
  std::atomic<std::uint64_t> raysSoFar{0};
  std::atomic<bool> interrupted{false};
  auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };

  // ---- Progress monitor: a thread that redraws the bar five times a second ----------
  std::mutex mutex;
  std::condition_variable wake;
  bool finished = false;
  std::thread monitor;
  if (options.progress) {
    monitor = std::thread([&] {
      std::unique_lock lock(mutex);
      while (!wake.wait_for(lock, std::chrono::milliseconds(200), [&] { return finished; })) {
        const std::uint64_t rays = raysSoFar.load(std::memory_order_relaxed);
        drawProgress(tilesDone.load(), stats.tilesTotal, elapsed(), rays);
      }
    });
  }

  // ---- Tiles ---------------------------------------------------------------------------
  tbb::parallel_for(
      tbb::blocked_range<int>(0, stats.tilesTotal, 1),
      [&](const tbb::blocked_range<int>& range) {
        RayCounter& counter = counters.local();
        std::vector<std::uint8_t>& seen = seenSets.local();
        for (int tile = range.begin(); tile != range.end(); ++tile) {
          if (options.cancel && options.cancel->load(std::memory_order_relaxed)) {
            interrupted = true;
            return;
          }
          int x0 = (tile % tilesX) * kTile, y0 = (tile / tilesX) * kTile;
          // Checked per pixel too: one tile at a high spp took minutes, and Ctrl-C waited
          // for it (a 16x16 image at --spp 1048576 ran on for 10 minutes after Ctrl-C).
          for (int y = y0; y < std::min(y0 + kTile, s.height); ++y)
            for (int x = x0; x < std::min(x0 + kTile, s.width); ++x) {
              if (options.cancel && options.cancel->load(std::memory_order_relaxed)) {
                interrupted = true;
                return;
              }
              const std::uint64_t before = counter.rays;
              renderPixel(scene, camera, image, x, y, counter, seen);
              raysSoFar.fetch_add(counter.rays - before, std::memory_order_relaxed);
            }
          ++tilesDone;
        }
      },
      tbb::simple_partitioner());

  if (monitor.joinable()) {
    {
      std::lock_guard lock(mutex);
      finished = true;
    }
    wake.notify_all();
    monitor.join();
  }
  stats.seconds = elapsed();
  for (const RayCounter& c : counters) stats.rays += c.rays;
  for (const std::vector<std::uint8_t>& seen : seenSets) {
    if (stats.seen.size() < seen.size()) stats.seen.resize(seen.size(), false);
    for (size_t i = 0; i < seen.size(); ++i)
      if (seen[i]) stats.seen[i] = true;
  }
  stats.tilesDone = tilesDone.load();
  stats.interrupted = interrupted.load();
  for (size_t i = 0; i < image.overflow.size(); ++i)
    if (image.overflow[i] != 0.0 && stats.overflowPixels++ == 0) {
      stats.overflowX = static_cast<int>(i % s.width);
      stats.overflowY = static_cast<int>(i / s.width);
      stats.overflowValue = image.overflow[i];
    }
  if (options.progress) {
    drawProgress(stats.tilesDone, stats.tilesTotal, stats.seconds, stats.rays);
    std::fputc('\n', stderr);
  }
  return stats;
}

}  // namespace algray::render
