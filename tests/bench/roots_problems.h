#pragma once
// The shape of a random first-root problem of ray-tracing type, shared by
// roots_report.cpp (expanded in MPFR, with references), roots_bench.cpp and roots_ab.cpp
// (expanded in double, timing only): a few real roots along the ray (t in [0, 1]), the other roots
// complex pairs whose real parts spread over [-0.5, 1.5] and whose imaginary parts are
// log-uniform in [1e-3, 1] (near misses), any leading scale, and an interval that is a
// whole ray (a random piece of [0, 1] of length >= 0.1) or a ray's span in one cell
// (length 1% to 20%), the same in float and double.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <random>
#include <utility>
#include <vector>

#include "../support/float_values.h"

namespace algray::bench {

struct ProblemShape {
  std::vector<double> roots;                     // real roots
  std::vector<std::pair<double, double>> pairs;  // a +- b i
  double lead = 1;
  double lo = 0, hi = 1;
};

inline ProblemShape randomProblemShape(int degree, bool cell, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uni(0, 1);
  ProblemShape p;
  const int maxReal = std::min(degree, 6);
  int nReal = degree % 2 + 2 * static_cast<int>(uni(rng) * (maxReal / 2 + 1));
  if (nReal > maxReal) nReal -= 2;
  for (int i = 0; i < nReal; ++i) p.roots.push_back(uni(rng));
  for (int i = 0; i < (degree - nReal) / 2; ++i)
    p.pairs.emplace_back(-0.5 + 2 * uni(rng), std::pow(10.0, -3 + 3 * uni(rng)));
  p.lead = (uni(rng) < 0.5 ? -1 : 1) * std::pow(10.0, -3 + 6 * uni(rng));
  if (cell) {
    const double len = std::pow(10.0, -2 + 1.3 * uni(rng));
    p.lo = (1 - len) * uni(rng);
    p.hi = p.lo + len;
  } else {
    p.lo = 0.5 * uni(rng);
    p.hi = p.lo + 0.1 + (1 - p.lo - 0.1) * uni(rng);
  }
  p.lo = test::floatValue(p.lo);  // the same interval in both precisions (see floatValue)
  p.hi = test::floatValue(p.hi);
  return p;
}

// Coefficients (lowest first) of lead * prod(t - r) * prod((t - a)^2 + b^2), in double.
inline std::vector<double> expandInDouble(const ProblemShape& shape) {
  std::vector<double> p{shape.lead};
  auto mul = [&](std::initializer_list<double> f) {  // f lowest first
    std::vector<double> q(p.size() + f.size() - 1, 0.0);
    for (size_t i = 0; i < p.size(); ++i) {
      size_t j = 0;
      for (double fj : f) q[i + j++] += p[i] * fj;
    }
    p.swap(q);
  };
  for (double r : shape.roots) mul({-r, 1.0});
  for (auto [a, b] : shape.pairs) mul({a * a + b * b, -2 * a, 1.0});
  return p;
}

// The q-quantile of v (q = 0.5: the median, the upper one of an even count; 1: the largest).
inline double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
}

}  // namespace algray::bench
