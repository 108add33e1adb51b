// Cost of one firstRoot call (roots.h) per method and degree, on random first-root
// problems of ray-tracing shape: g(t) = lead * prod(t - r_i) * prod((t - a)^2 + b^2) with
// a few real roots r_i in [0, 1] and the rest complex pairs (real parts in [-0.5, 1.5],
// imaginary parts log-uniform in [1e-3, 1]: near misses), on a "ray" interval (a random
// piece of [0, 1] of length >= 0.1) or a "cell" interval (length 1% to 20%: a ray's span
// in one cell of the plugin's grid). The problems are expanded in double (this measures
// speed; tests/bench/roots_report.cpp measures accuracy against MPFR) and generated once
// per benchmark with a fixed seed, outside the timing loop; each iteration solves the
// next problem of a pool of kPool.
//
// Run: build/tests/bench/roots_bench --benchmark_filter='degree:(3|4)/'
//        --benchmark_counters_tabular=true
// ClosedForm is registered for degrees 2-4 only: above it is Yuksel's recursion (roots.h).
// BM_GalleryRays: the same query on real ray polynomials of the gallery surfaces (below).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "algray/gallery.h"
#include "algray/roots.h"
#include "algray/taylor.h"

#include <glm/geometric.hpp>
#include <string>

#include "roots_problems.h"

namespace {

using algray::RootMethod;

constexpr int kPool = 256;

struct Problem {
  std::vector<double> c;
  std::vector<float> cf;
  double lo, hi;
};

std::vector<Problem> makeProblems(int degree, bool cell) {
  std::mt19937_64 rng(1000 * degree + cell);  // fixed seed per benchmark
  std::vector<Problem> out(kPool);
  for (Problem& p : out) {
    const algray::bench::ProblemShape shape = algray::bench::randomProblemShape(degree, cell, rng);
    p.c = algray::bench::expandInDouble(shape);
    p.cf.assign(p.c.begin(), p.c.end());
    p.lo = shape.lo;
    p.hi = shape.hi;
  }
  return out;
}

// range(0): degree, range(1): 0 ray / 1 cell.
template <RootMethod M, bool Float>
void BM_FirstRoot(benchmark::State& state) {
  const auto problems = makeProblems(static_cast<int>(state.range(0)), state.range(1) != 0);
  algray::RootOptions o;
  o.method = M;
  size_t i = 0;
  int found = 0;
  for (auto _ : state) {
    const Problem& p = problems[i++ % kPool];
    if constexpr (Float) {
      auto r = algray::firstRoot(std::span<const float>(p.cf), {}, static_cast<float>(p.lo),
                                 static_cast<float>(p.hi), o);
      benchmark::DoNotOptimize(r);
      found += r.has_value();
    } else {
      auto r = algray::firstRoot(p.c, {}, p.lo, p.hi, o);
      benchmark::DoNotOptimize(r);
      found += r.has_value();
    }
  }
  // Share of problems with a root: the same for every method up to tangent decisions.
  state.counters["hit"] = benchmark::Counter(found, benchmark::Counter::kAvgIterations);
}

// Real ray polynomials: the primary rays of a 64 x 64 pinhole camera 3 clip radii from a
// gallery surface's centre, framing its clip sphere (the shape of speed_report's camera),
// restricted as the plugin does for rays with distinct origins (re-centred at the point
// closest to the centre, taylor.h), with their rounding bounds, on the clip-sphere span.
// Only rays that cross the clip sphere are kept.
struct RayProblem {
  algray::RayPolynomial g;
  double lo, hi;
};

std::vector<RayProblem> galleryRays(const algray::GallerySurface& surface) {
  const algray::HornerForm f(surface.build());
  const double r = surface.clipRadius;
  const glm::dvec3 eye = 3.0 * r * glm::normalize(glm::dvec3(1.0, -1.6, 0.9));
  const glm::dvec3 forward = -glm::normalize(eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 0, 1)));
  const glm::dvec3 up = glm::cross(right, forward);
  std::vector<RayProblem> out;
  constexpr int kSide = 64;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const double px = (2.0 * (x + 0.5) / kSide - 1.0) * 0.37,
                   py = (1.0 - 2.0 * (y + 0.5) / kSide) * 0.37;
      const glm::dvec3 d = glm::normalize(forward + px * right + py * up);
      const double tc = -glm::dot(eye, d), h2 = r * r - glm::dot(eye + tc * d, eye + tc * d);
      if (!(h2 > 0.0)) continue;
      const double t0 = tc - std::sqrt(h2), t1 = tc + std::sqrt(h2);
      out.push_back({algray::restrictToRay(f, eye, d, tc), t0 - tc, t1 - tc});
    }
  return out;
}

// range(0): index into algray::gallery().
template <RootMethod M>
void BM_GalleryRays(benchmark::State& state) {
  const algray::GallerySurface& surface = algray::gallery()[static_cast<size_t>(state.range(0))];
  const std::vector<RayProblem> problems = galleryRays(surface);
  state.SetLabel(std::string(surface.name));
  algray::RootOptions o;
  o.method = M;
  size_t i = 0;
  int found = 0;
  for (auto _ : state) {
    const RayProblem& p = problems[i++ % problems.size()];
    const auto n = static_cast<size_t>(p.g.degree + 1);
    auto root = algray::firstRoot(std::span<const double>(p.g.coeff.data(), n),
                                  std::span<const double>(p.g.error.data(), n), p.lo, p.hi, o);
    benchmark::DoNotOptimize(root);
    found += root.has_value();
  }
  state.counters["hit"] = benchmark::Counter(found, benchmark::Counter::kAvgIterations);
}

void gallerySurfaces(benchmark::internal::Benchmark* b) {
  for (size_t k = 0; k < algray::gallery().size(); ++k)
    if (algray::gallery()[k].build().degree() >= 3) b->Arg(static_cast<int>(k));
}

void degrees(benchmark::internal::Benchmark* b) {
  for (int family : {0, 1}) {
    for (int d = 2; d <= 20; ++d) b->Args({d, family});
    b->Args({30, family});
    b->Args({40, family});
  }
}

void closedFormDegrees(benchmark::internal::Benchmark* b) {
  for (int family : {0, 1})
    for (int d = 2; d <= 4; ++d) b->Args({d, family});
}

}  // namespace

BENCHMARK(BM_FirstRoot<RootMethod::Auto, false>)->Apply(degrees)->ArgNames({"degree", "cell"});
BENCHMARK(BM_FirstRoot<RootMethod::ClosedForm, false>)
    ->Apply(closedFormDegrees)
    ->ArgNames({"degree", "cell"});
BENCHMARK(BM_FirstRoot<RootMethod::Yuksel, false>)->Apply(degrees)->ArgNames({"degree", "cell"});
BENCHMARK(BM_FirstRoot<RootMethod::Sturm, false>)->Apply(degrees)->ArgNames({"degree", "cell"});
BENCHMARK(BM_FirstRoot<RootMethod::Bernstein, false>)->Apply(degrees)->ArgNames({"degree", "cell"});
BENCHMARK(BM_FirstRoot<RootMethod::Auto, true>)->Apply(degrees)->ArgNames({"degree", "cell"});
BENCHMARK(BM_GalleryRays<RootMethod::Auto>)->Apply(gallerySurfaces)->ArgName("surface");
BENCHMARK(BM_GalleryRays<RootMethod::Sturm>)->Apply(gallerySurfaces)->ArgName("surface");
BENCHMARK(BM_GalleryRays<RootMethod::Bernstein>)->Apply(gallerySurfaces)->ArgName("surface");

BENCHMARK_MAIN();
