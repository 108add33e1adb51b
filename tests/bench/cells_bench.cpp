// Cells (cells.h): build time and cell counts per gallery surface and depth, and what
// the cells buy at render time. Counters:
//   BM_BuildCells/<surface>/<depth>   (depth -1: automatic, as buildCells chooses it)
//     cells        cells returned
//     tested       range enclosures evaluated
//     kept_vol     kept volume / clip-box volume (the empty space the BVH skips is 1 - it)
//     depth        level returned
//   BM_BuildCells/<surface>/bernstein-<depth>   the same with RangeBound::Bernstein
//   BM_TraceCells/<surface>/<depth>   (depth -2: no cells, one primitive for the clip ball;
//                                      -1: the adapter's automatic choice)
//     one Embree rtcIntersect1 per ray, single thread, plain float rays: 48x48 primary
//     rays of a camera at 3 clip radii and 2048 random rays inside the clip ball;
//     rays and hits (so that configurations can be checked to agree).
//   BM_TraceCells/<surface>@3R/<depth>   the same in a clip ball of 3x the radius.
//   BM_KernelCells/<surface>/<depth>/<mode>   the per-ray work of the adapter's kernel
//     without Embree, on the same rays (double): restriction g precomputed per ray (it is
//     shared by the cells), then mode 0: firstRoot on the whole clip-ball span (no cells);
//     mode 1: firstRoot on each crossed cell's span in order of entry until a root;
//     mode 2: as 1, but a cell whose span provably has no root (provablyNoRoot, the
//     univariate centred form of range_bound.h) is skipped without a solve; mode 3: the
//     same with the O(m) quickNoRoot test.
//     Counters: solves and exclusions per ray.
// Run the depths of one surface side by side (the machine is noisy): ratios within one
// run are the figures to quote (docs/cells-summary.md).
#include "algray/cells.h"
#include "algray/embree.h"
#include "algray/gallery.h"
#include "algray/range_bound.h"
#include "algray/roots.h"
#include "algray/taylor.h"

#include <benchmark/benchmark.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "float_ray.h"

namespace algray {
namespace {

// ---- Build -------------------------------------------------------------------------------
void buildCellsBench(benchmark::State& state, const GallerySurface* s, int depth,
                     RangeBound bound) {
  const Polynomial f = s->build();
  const double r = s->clipRadius;
  CellStats stats;
  std::size_t cells = 0;
  for (auto _ : state) {
    const auto out = buildCells(f, glm::dvec3(-r), glm::dvec3(r), CellSphere{glm::dvec3(0.0), r},
                                {.depth = depth, .bound = bound}, &stats);
    cells = out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["cells"] = static_cast<double>(cells);
  state.counters["tested"] = static_cast<double>(stats.boxesTested);
  state.counters["depth"] = stats.depth;
  state.counters["kept_vol"] =
      stats.keptVolumeFraction.empty() ? 0.0 : stats.keptVolumeFraction[stats.depth];
  state.counters["degree"] = f.degree();
}

// ---- Trace -------------------------------------------------------------------------------
struct Rays {
  std::vector<RTCRayHit> rays;
};

Rays makeRays(double r) {
  Rays out;
  auto add = [&](glm::dvec3 o, glm::dvec3 d) {
    out.rays.push_back(
        bench::plainFloatRay(RayD{o, d, 0.0, std::numeric_limits<double>::infinity(), 0.0}));
  };
  // A camera at distance 3r on a skew direction, field of view just covering the ball.
  const glm::dvec3 eye = 3.0 * r * glm::normalize(glm::dvec3(0.6, -0.7, 0.4));
  const glm::dvec3 w = glm::normalize(-eye), u = glm::normalize(glm::cross(w, glm::dvec3(0, 0, 1))),
                   v = glm::cross(u, w);
  const int n = 48;
  const double half = std::tan(std::asin(1.0 / 3.0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = (2.0 * (i + 0.5) / n - 1.0) * half, y = (2.0 * (j + 0.5) / n - 1.0) * half;
      add(eye, glm::normalize(w + x * u + y * v));
    }
  // Random chords of the ball (secondary-ray-like: start inside, any direction).
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  for (int k = 0; k < 2048; ++k) {
    glm::dvec3 o(g(rng), g(rng), g(rng)), d(g(rng), g(rng), g(rng));
    o *= 0.9 * r * std::cbrt(std::uniform_real_distribution<double>(0, 1)(rng)) / glm::length(o);
    add(o, glm::normalize(d));
  }
  return out;
}

void traceCellsBench(benchmark::State& state, const GallerySurface* s, int depth,
                     double clipScale) {
  RTCDevice device = rtcNewDevice("threads=1");
  RTCScene scene = rtcNewScene(device);
  SurfaceDesc desc;
  desc.polynomial = s->build();
  desc.clip = ClipSphere{glm::dvec3(0.0), clipScale * s->clipRadius};
  desc.options.useCells = depth != -2;
  desc.options.cellDepth = depth < 0 ? -1 : depth;
  const auto t0 = std::chrono::steady_clock::now();
  SurfaceGeometry geometry(device, desc);
  const double buildSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rtcAttachGeometry(scene, geometry.geometry());
  rtcCommitScene(scene);
  const Rays rays = makeRays(clipScale * s->clipRadius);
  long hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (RTCRayHit rh : rays.rays) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      rtcIntersect1(scene, &context, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
  }
  state.counters["rays"] = static_cast<double>(rays.rays.size());
  state.counters["hits"] = static_cast<double>(hits);
  state.counters["cells"] = geometry.primitiveCount();
  state.counters["build_ms"] = buildSeconds * 1e3;
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
}

// ---- Kernel without Embree ---------------------------------------------------------------
struct KernelRay {
  RayPolynomial g;
  double r0 = 0, r1 = 0;                         // clip-ball span
  std::vector<std::pair<double, double>> spans;  // crossed cells, by entry
};

void kernelCellsBench(benchmark::State& state, const GallerySurface* s, int depth, int mode) {
  const Polynomial f = s->build();
  const double R = s->clipRadius;
  const auto cells = mode == 0 ? std::vector<Cell>{}
                               : buildCells(f, glm::dvec3(-R), glm::dvec3(R),
                                            CellSphere{glm::dvec3(0.0), R}, {.depth = depth});
  std::vector<KernelRay> rays;
  for (const RTCRayHit& rh : makeRays(R).rays) {
    const glm::dvec3 o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z),
        d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    // Ball span: |o + t d|^2 = R^2.
    const double b = glm::dot(o, d) / glm::dot(d, d), c = (glm::dot(o, o) - R * R) / glm::dot(d, d);
    const double disc = b * b - c;
    if (!(disc > 0)) continue;
    KernelRay k;
    k.r0 = std::max(0.0, -b - std::sqrt(disc));
    k.r1 = -b + std::sqrt(disc);
    if (!(k.r0 < k.r1)) continue;
    k.g = restrictToRay(f, o, d, std::clamp(closestParameter(o, d, glm::dvec3(0.0)), k.r0, k.r1));
    for (const Cell& cell : cells)
      if (auto sp = clipRayToBox(o, d, cell.lo, cell.hi, k.r0, k.r1))
        k.spans.emplace_back(sp->t0, sp->t1);
    std::sort(k.spans.begin(), k.spans.end());
    rays.push_back(std::move(k));
  }
  long solves = 0, excluded = 0, hits = 0;
  for (auto _ : state) {
    solves = excluded = hits = 0;
    for (const KernelRay& k : rays) {
      const std::span<const double> c(k.g.coeff.data(), k.g.degree + 1),
          e(k.g.error.data(), k.g.degree + 1);
      if (mode == 0) {
        ++solves;
        hits += firstRoot(c, e, k.r0 - k.g.tShift, k.r1 - k.g.tShift).has_value();
        continue;
      }
      for (const auto& [t0, t1] : k.spans) {
        const double s0 = t0 - k.g.tShift, s1 = t1 - k.g.tShift;
        if ((mode == 2 && provablyNoRoot(c, e, s0, s1)) ||
            (mode == 3 && quickNoRoot(c, e, s0, s1))) {
          ++excluded;
          continue;
        }
        ++solves;
        if (firstRoot(c, e, s0, s1)) {
          ++hits;
          break;
        }
      }
    }
  }
  const double n = static_cast<double>(rays.size());
  state.counters["solves_per_ray"] = static_cast<double>(solves) / n;
  state.counters["excluded_per_ray"] = static_cast<double>(excluded) / n;
  state.counters["hits"] = static_cast<double>(hits);
  state.counters["cells"] = static_cast<double>(cells.size());
  state.counters["rays"] = n;
}

int registerAll() {
  for (const GallerySurface& s : gallery()) {
    const int degree = s.build().degree();
    const int maxDepth = degree <= 6 ? 6 : degree <= 8 ? 5 : 4;
    for (int depth = 0; depth <= maxDepth; ++depth)
      benchmark::RegisterBenchmark(
          ("BM_BuildCells/" + std::string(s.name) + "/" + std::to_string(depth)).c_str(),
          buildCellsBench, &s, depth, RangeBound::Centred)
          ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_BuildCells/" + std::string(s.name) + "/auto").c_str(),
                                 buildCellsBench, &s, -1, RangeBound::Centred)
        ->Unit(benchmark::kMillisecond);
    // The Bernstein test side by side at the depths where the centred form is loose.
    for (int depth = 3; depth <= (degree <= 8 ? 4 : 3); ++depth)
      benchmark::RegisterBenchmark(
          ("BM_BuildCells/" + std::string(s.name) + "/bernstein-" + std::to_string(depth)).c_str(),
          buildCellsBench, &s, depth, RangeBound::Bernstein)
          ->Unit(benchmark::kMillisecond);
  }
  for (const GallerySurface& s : gallery()) {
    const int degree = s.build().degree();
    const int maxDepth = degree <= 6 ? 6 : degree <= 8 ? 5 : 4;
    for (int depth = -2; depth <= maxDepth; ++depth) {
      const std::string tag = depth == -2 ? "none" : depth == -1 ? "auto" : std::to_string(depth);
      benchmark::RegisterBenchmark(("BM_TraceCells/" + std::string(s.name) + "/" + tag).c_str(),
                                   traceCellsBench, &s, depth, 1.0)
          ->Unit(benchmark::kMillisecond);
    }
  }
  // A clip ball 3x the gallery's (27x the volume): most of it is empty space, the case
  // cells are for.
  for (const char* name : {"sphere", "torus", "barth-sextic", "chmutov-8", "barth-decic"})
    if (const GallerySurface* s = findGallerySurface(name))
      for (int depth = -2; depth <= (s->build().degree() <= 6 ? 6 : 5); ++depth) {
        const std::string tag = depth == -2 ? "none" : depth == -1 ? "auto" : std::to_string(depth);
        benchmark::RegisterBenchmark(("BM_TraceCells/" + std::string(name) + "@3R/" + tag).c_str(),
                                     traceCellsBench, s, depth, 3.0)
            ->Unit(benchmark::kMillisecond);
      }
  for (const GallerySurface& s : gallery()) {
    benchmark::RegisterBenchmark(("BM_KernelCells/" + std::string(s.name) + "/none").c_str(),
                                 kernelCellsBench, &s, 0, 0)
        ->Unit(benchmark::kMillisecond);
    const int maxDepth = s.build().degree() <= 8 ? 5 : 4;
    for (int depth = 2; depth <= maxDepth; ++depth)
      for (int mode = 1; mode <= 3; ++mode)
        benchmark::RegisterBenchmark(
            ("BM_KernelCells/" + std::string(s.name) + "/" + std::to_string(depth) +
             (mode == 1   ? "/solve"
              : mode == 2 ? "/centred"
                          : "/quick"))
                .c_str(),
            kernelCellsBench, &s, depth, mode)
            ->Unit(benchmark::kMillisecond);
  }
  return 0;
}

}  // namespace
}  // namespace algray

int main(int argc, char** argv) {
  algray::registerAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
