// The parser-style workload on dense graded storage (polynomial.h, parser.h, gallery.h):
//   BM_ParseJsurf      : parse each real SURFER equation (../shared/gallery/jsurf), the
//                        time per parse with rounding-bound tracking and pruning,
//   BM_ParseFactored   : parse the factored definition of a classic surface, side by side
//   BM_BuildGallery      with building the same polynomial by plain Polynomial arithmetic
//                        (the ratio is the cost of the bound tracking),
//   BM_ParseExpanded   : parse the expanded toString() text of a gallery surface (and of a
//                        dense degree-40 polynomial, every one of its 12341 terms),
//   BM_PowBinary       : (x+y+z+1)^n by Polynomial::pow (binary powering) and
//   BM_PowRepeated       by n-1 products with the base (the order the parser uses),
//   BM_MultiplyDense   : product of two dense random polynomials of degree d,
//   BM_EvalOld         : value, gradient and rounding bound at a point by
//   BM_EvalNew           Polynomial::evaluateWithBound (monomial loop) and by
//                        HornerForm::evaluate (nested Horner), side by side per gallery
//                        surface and dense degree; ns per evaluation over 256 points in
//                        the clip ball (the ratio old/new is the speed-up).
// Run: build/tests/bench/polynomial_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "algray/gallery.h"
#include "algray/horner_form.h"
#include "algray/jsurf.h"
#include "algray/parser.h"

namespace {

using algray::Polynomial;

Polynomial densePolynomial(int degree, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> c(-1.0, 1.0);
  Polynomial f;
  for (int n = 0; n <= degree; ++n)
    algray::forEachMonomialOfDegree(n,
                                    [&](int i, int j, int k, int) { f.setCoeff(i, j, k, c(rng)); });
  return f;
}

void parseBenchmark(benchmark::State& state, const std::string& text,
                    const algray::ParseOptions& options) {
  Polynomial f;
  for (auto _ : state) {
    f = algray::parsePolynomial(text, options);
    benchmark::DoNotOptimize(f);
  }
  state.counters["degree"] = f.degree();
  state.counters["terms"] = f.nonZeroCount();
  state.counters["chars"] = static_cast<double>(text.size());
}

// Factored definitions, the way people type them (same formulas as gallery.cpp).
struct Factored {
  const char* gallery;
  const char* text;
};
const Factored kFactored[] = {
    {"torus", "(x^2+y^2+z^2+1-0.16)^2 - 4*(x^2+y^2)"},
    {"kummer-quartic",
     "(x^2+y^2+z^2-1.69)^2 - "
     "(3*1.69-1)/(3-1.69)*(1-z-sqrt(2)*x)*(1-z+sqrt(2)*x)*(1+z+sqrt(2)*y)*(1+z-sqrt(2)*y)"},
    {"barth-sextic",
     "4*(((1+sqrt(5))/2)^2*x^2-y^2)*(((1+sqrt(5))/2)^2*y^2-z^2)*(((1+sqrt(5))/2)^2*z^2-x^2)"
     " - (1+2*(1+sqrt(5))/2)*(x^2+y^2+z^2-1)^2"},
    {"heart", "(x^2+9/4*y^2+z^2-1)^3 - x^2*z^3 - 9/80*y^2*z^3"},
    {"endrass-octic",
     "64*(x^2-1)*(y^2-1)*((x+y)^2-2)*((x-y)^2-2) - (-4*(1+sqrt(2))*(x^2+y^2)^2 + "
     "(8*(2+sqrt(2))*z^2 + "
     "2*(2+7*sqrt(2)))*(x^2+y^2) - 16*z^4 + 8*(1-2*sqrt(2))*z^2 - (1+12*sqrt(2)))^2"},
};

void BM_BuildGallery(benchmark::State& state, const algray::GallerySurface* s) {
  Polynomial f;
  for (auto _ : state) {
    f = s->build();
    benchmark::DoNotOptimize(f);
  }
  state.counters["degree"] = f.degree();
  state.counters["terms"] = f.nonZeroCount();
}

void BM_PowBinary(benchmark::State& state) {
  const Polynomial base = algray::parsePolynomial("x+y+z+1");
  const int n = static_cast<int>(state.range(0));
  for (auto _ : state) {
    Polynomial p = base.pow(n);
    benchmark::DoNotOptimize(p);
  }
  state.counters["terms"] = Polynomial::termCount(n);
}

void BM_PowRepeated(benchmark::State& state) {
  const Polynomial base = algray::parsePolynomial("x+y+z+1");
  const int n = static_cast<int>(state.range(0));
  for (auto _ : state) {
    Polynomial p = base;
    for (int i = 1; i < n; ++i) p = p * base;
    benchmark::DoNotOptimize(p);
  }
  state.counters["terms"] = Polynomial::termCount(n);
}

void BM_MultiplyDense(benchmark::State& state) {
  const int d = static_cast<int>(state.range(0));
  const Polynomial a = densePolynomial(d, 1), b = densePolynomial(d, 2);
  for (auto _ : state) {
    Polynomial p = a * b;
    benchmark::DoNotOptimize(p);
  }
  state.counters["terms_in"] = Polynomial::termCount(d);
}

// Points uniform in the cube around the clip ball, where the adapter evaluates (hits and
// shadow-ray origins); the cost of either scheme does not depend on the point.
std::vector<glm::dvec3> evalPoints(double radius) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-radius, radius);
  std::vector<glm::dvec3> pts(256);
  for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
  return pts;
}

template <class Eval>
void evalBenchmark(benchmark::State& state, const Polynomial& f, double radius, Eval eval) {
  const auto pts = evalPoints(radius);
  size_t i = 0;
  for (auto _ : state) {
    const Polynomial::Evaluation e = eval(pts[i++ & 255]);
    benchmark::DoNotOptimize(e);
  }
  state.counters["degree"] = f.degree();
  state.counters["terms"] = f.nonZeroCount();
}

void BM_EvalOld(benchmark::State& state, const Polynomial& f, double radius) {
  evalBenchmark(state, f, radius, [&](const glm::dvec3& p) { return f.evaluateWithBound(p); });
}

void BM_EvalNew(benchmark::State& state, const Polynomial& f, double radius) {
  const algray::HornerForm ev(f);
  evalBenchmark(state, f, radius, [&](const glm::dvec3& p) { return ev.evaluate(p); });
  state.counters["stored"] = ev.coefficientCount();
}

BENCHMARK(BM_PowBinary)->Arg(5)->Arg(10)->Arg(20)->Arg(40)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PowRepeated)->Arg(5)->Arg(10)->Arg(20)->Arg(40)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MultiplyDense)->Arg(4)->Arg(8)->Arg(12)->Arg(20)->Unit(benchmark::kMicrosecond);

void registerDynamic() {
  // Point evaluation, old and new side by side (registered in pairs, run in this order).
  for (const char* name :
       {"sphere", "torus", "kummer-quartic", "barth-sextic", "chmutov-8", "chmutov-12",
        "chmutov-16", "endrass-octic", "barth-decic", "sarti-dodecic"}) {
    const algray::GallerySurface* s = algray::findGallerySurface(name);
    const Polynomial f = s->build();
    const std::string suffix = std::string("/") + name;
    benchmark::RegisterBenchmark(("BM_EvalOld" + suffix).c_str(), BM_EvalOld, f, s->clipRadius);
    benchmark::RegisterBenchmark(("BM_EvalNew" + suffix).c_str(), BM_EvalNew, f, s->clipRadius);
  }
  for (const int degree : {10, 20, 40}) {
    const Polynomial f = densePolynomial(degree, 3);
    const std::string name = "dense-" + std::to_string(degree);
    benchmark::RegisterBenchmark(("BM_EvalOld/" + name).c_str(), BM_EvalOld, f, 1.0);
    benchmark::RegisterBenchmark(("BM_EvalNew/" + name).c_str(), BM_EvalNew, f, 1.0);
  }
  // Real SURFER files: the equation with its parameters.
  const std::filesystem::path dir = ALGRAY_SHARED_DIR "/gallery/jsurf";
  if (std::filesystem::is_directory(dir)) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().extension() == ".jsurf") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& path : files) {
      const auto file = algray::JsurfFile::read(path);
      algray::ParseOptions options;
      options.parameters = file.parameters();
      benchmark::RegisterBenchmark(("BM_ParseJsurf/" + path.stem().string()).c_str(),
                                   parseBenchmark, file.get("surface_equation").value_or("0"),
                                   options)
          ->Unit(benchmark::kMicrosecond);
    }
  }
  for (const Factored& f : kFactored) {
    benchmark::RegisterBenchmark((std::string("BM_ParseFactored/") + f.gallery).c_str(),
                                 parseBenchmark, std::string(f.text), algray::ParseOptions{})
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((std::string("BM_BuildGallery/") + f.gallery).c_str(),
                                 BM_BuildGallery, algray::findGallerySurface(f.gallery))
        ->Unit(benchmark::kMicrosecond);
  }
  for (const char* name : {"barth-sextic", "endrass-octic", "chmutov-12", "chmutov-16"})
    benchmark::RegisterBenchmark((std::string("BM_ParseExpanded/") + name).c_str(), parseBenchmark,
                                 algray::findGallerySurface(name)->build().toString(),
                                 algray::ParseOptions{})
        ->Unit(benchmark::kMicrosecond);
  // The largest input the parser takes: every term of degree <= 40 (docs/equations.md).
  benchmark::RegisterBenchmark("BM_ParseExpanded/dense-40", parseBenchmark,
                               densePolynomial(40, 5).toString(), algray::ParseOptions{})
      ->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv) {
  registerDynamic();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
