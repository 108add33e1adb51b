// Cost per ray of the two Taylor restriction paths (taylor.h) for dense polynomials of
// degree 2 to 16:
//   BM_OriginExpansion : rays sharing an origin, g_n = H_n(d) from the cached expansion
//                        (with and without the error bound),
//   BM_RestrictToRay   : the direct per-ray restriction (nested Horner in R[s]),
//   BM_ExpandOrigin    : the one-off cost of expanding about a new origin.
// Run: build/tests/bench/taylor_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

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

void BM_RestrictToRay(benchmark::State& state) {
  const auto f = densePolynomial(static_cast<int>(state.range(0)));
  const auto dirs = directions(1024);
  size_t i = 0;
  for (auto _ : state) {
    auto g = algray::restrictToRay(f, kOrigin, dirs[i++ & 1023]);
    benchmark::DoNotOptimize(g);
  }
  state.counters["terms"] = Polynomial::termCount(f.degree());
}

void BM_ExpandOrigin(benchmark::State& state) {
  const auto f = densePolynomial(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    algray::OriginExpansion e(f, kOrigin);
    benchmark::DoNotOptimize(e);
  }
}

void degrees(benchmark::internal::Benchmark* b) {
  for (int d : {2, 3, 4, 6, 8, 10, 12, 16}) b->Args({d, 1});
}
void degreesNoError(benchmark::internal::Benchmark* b) {
  for (int d : {2, 3, 4, 6, 8, 10, 12, 16}) b->Args({d, 0});
}

BENCHMARK(BM_OriginExpansion)->Apply(degrees)->ArgNames({"degree", "bound"});
BENCHMARK(BM_OriginExpansion)->Apply(degreesNoError)->ArgNames({"degree", "bound"});
BENCHMARK(BM_RestrictToRay)->Apply(degrees)->ArgNames({"degree", "bound"});
BENCHMARK(BM_ExpandOrigin)->Apply(degrees)->ArgNames({"degree", "bound"});

}  // namespace

BENCHMARK_MAIN();
