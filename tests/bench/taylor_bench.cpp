// Cost per ray of the two Taylor restriction paths (taylor.h) for dense polynomials of
// degree 2 to 16:
//   BM_OriginExpansion : rays sharing an origin, g_n = H_n(d) from the cached expansion
//                        (with and without the error bound),
//   BM_RestrictToRay   : the direct per-ray restriction (nested Horner in R[s]),
//   BM_RestrictToRayBox: the same over the HornerForm (the adapter's path),
//   BM_ExpandOrigin    : the one-off cost of expanding about a new origin.
// Run: build/tests/bench/taylor_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <string>
#include <vector>

#include "algray/gallery.h"
#include "algray/taylor.h"

namespace {

using algray::forEachMonomialOfDegree;
using algray::Polynomial;

Polynomial densePolynomial(int degree) {
  std::mt19937_64 rng(degree);
  std::uniform_real_distribution<double> c(-1.0, 1.0);
  Polynomial f;
  for (int n = 0; n <= degree; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int) { f.setCoeff(i, j, k, c(rng)); });
  return f;
}

std::vector<glm::dvec3> directions(int count) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n;
  std::vector<glm::dvec3> d(count);
  for (auto& v : d) v = glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
  return d;
}

const glm::dvec3 kOrigin{0.3, -2.5, 1.7};

void BM_OriginExpansion(benchmark::State& state) {
  const auto f = densePolynomial(static_cast<int>(state.range(0)));
  const bool withError = state.range(1) != 0;
  const algray::OriginExpansion expansion(f, kOrigin);
  const auto dirs = directions(1024);
  size_t i = 0;
  for (auto _ : state) {
    auto g = expansion.restrict(dirs[i++ & 1023], withError);
    benchmark::DoNotOptimize(g);
  }
  state.counters["terms"] = Polynomial::termCount(f.degree());
}

// The direct restriction from f itself (Form = Polynomial) or from its HornerForm (the
// adapter's path; taylor_box.cpp).
template <class Form>
void restrictToRayLoop(benchmark::State& state) {
  const auto f = densePolynomial(static_cast<int>(state.range(0)));
  const Form form(f);
  const auto dirs = directions(1024);
  size_t i = 0;
  for (auto _ : state) {
    auto g = algray::restrictToRay(form, kOrigin, dirs[i++ & 1023]);
    benchmark::DoNotOptimize(g);
  }
  state.counters["terms"] = Polynomial::termCount(f.degree());
}
void BM_RestrictToRay(benchmark::State& state) { restrictToRayLoop<Polynomial>(state); }
void BM_RestrictToRayBox(benchmark::State& state) { restrictToRayLoop<algray::HornerForm>(state); }

void BM_ExpandOrigin(benchmark::State& state) {
  const auto f = densePolynomial(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    algray::OriginExpansion e(f, kOrigin);
    benchmark::DoNotOptimize(e);
  }
}

// Storage choice (polynomial.h): the shifted polynomial about a camera origin, evaluated
// per ray, by the library (dense segment dot products, or its own sparse list when the
// shifted polynomial has few terms) versus a plain sparse list of non-zero terms. Counters
// show how much translation fills in: the gallery's sparse surfaces become dense.
struct SparseTerm {
  int i, j, k;
  double c;
};

void BM_GalleryShifted(benchmark::State& state, const algray::GallerySurface* surface, bool dense) {
  const Polynomial f = surface->build();
  const glm::dvec3 camera = glm::dvec3(0.6, -0.8, 2.5) * surface->clipRadius;
  const algray::OriginExpansion expansion(f, camera);
  const Polynomial& shifted = expansion.shifted();
  std::vector<SparseTerm> terms;
  for (int n = 0; n <= shifted.degree(); ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      if (shifted.coeffs()[idx] != 0.0) terms.push_back({i, j, k, shifted.coeffs()[idx]});
    });
  const auto dirs = directions(1024);
  size_t r = 0;
  for (auto _ : state) {
    const glm::dvec3 d = dirs[r++ & 1023];
    if (dense) {
      auto g = expansion.restrict(d, false);
      benchmark::DoNotOptimize(g);
    } else {
      double px[algray::kMaxDegree + 1], py[algray::kMaxDegree + 1], pz[algray::kMaxDegree + 1];
      px[0] = py[0] = pz[0] = 1.0;
      for (int e = 1; e <= shifted.degree(); ++e) {
        px[e] = px[e - 1] * d.x;
        py[e] = py[e - 1] * d.y;
        pz[e] = pz[e - 1] * d.z;
      }
      std::array<double, algray::kMaxDegree + 1> g{};
      for (const SparseTerm& t : terms) g[t.i + t.j + t.k] += t.c * px[t.i] * py[t.j] * pz[t.k];
      benchmark::DoNotOptimize(g);
    }
  }
  state.counters["terms_f"] = f.nonZeroCount();
  state.counters["terms_shifted"] = shifted.nonZeroCount();
  state.counters["dense_terms"] = Polynomial::termCount(shifted.degree());
}

// The direct restriction (rays with distinct origins: shadow and bounce rays, and every
// ray of a camera too far for the origin cache) of a gallery surface, from its dense
// graded Polynomial or from its precompiled HornerForm (the adapter's path): the same
// coefficients bit for bit (tests/taylor_test.cpp), only the box f occupies visited.
void BM_GalleryDirect(benchmark::State& state, const algray::GallerySurface* surface, bool box) {
  const Polynomial f = surface->build();
  const algray::HornerForm horner(f);
  const glm::dvec3 o = glm::dvec3(0.6, -0.8, 2.5) * surface->clipRadius;
  const auto dirs = directions(1024);
  size_t r = 0;
  for (auto _ : state) {
    const glm::dvec3 d = dirs[r++ & 1023];
    const double tShift = algray::closestParameter(o, d, glm::dvec3(0.0));
    auto g =
        box ? algray::restrictToRay(horner, o, d, tShift) : algray::restrictToRay(f, o, d, tShift);
    benchmark::DoNotOptimize(g);
  }
  state.counters["terms_f"] = f.nonZeroCount();
  state.counters["box_slots"] = horner.coefficientCount();
}

const bool kGalleryRegistered = [] {
  for (const algray::GallerySurface& s : algray::gallery()) {
    benchmark::RegisterBenchmark(("BM_GalleryDirect/polynomial/" + std::string(s.name)).c_str(),
                                 BM_GalleryDirect, &s, false);
    benchmark::RegisterBenchmark(("BM_GalleryDirect/horner-box/" + std::string(s.name)).c_str(),
                                 BM_GalleryDirect, &s, true);
    benchmark::RegisterBenchmark(("BM_GalleryShifted/library/" + std::string(s.name)).c_str(),
                                 BM_GalleryShifted, &s, true);
    benchmark::RegisterBenchmark(("BM_GalleryShifted/sparse-list/" + std::string(s.name)).c_str(),
                                 BM_GalleryShifted, &s, false);
  }
  return true;
}();

void degrees(benchmark::internal::Benchmark* b) {
  for (int d : {2, 3, 4, 6, 8, 10, 12, 16}) b->Args({d, 1});
}
void degreesNoError(benchmark::internal::Benchmark* b) {
  for (int d : {2, 3, 4, 6, 8, 10, 12, 16}) b->Args({d, 0});
}

BENCHMARK(BM_OriginExpansion)->Apply(degrees)->ArgNames({"degree", "bound"});
BENCHMARK(BM_OriginExpansion)->Apply(degreesNoError)->ArgNames({"degree", "bound"});
BENCHMARK(BM_RestrictToRay)->Apply(degrees)->ArgNames({"degree", "bound"});
BENCHMARK(BM_RestrictToRayBox)->Apply(degrees)->ArgNames({"degree", "bound"});
BENCHMARK(BM_ExpandOrigin)->Apply(degrees)->ArgNames({"degree", "bound"});

}  // namespace

BENCHMARK_MAIN();
