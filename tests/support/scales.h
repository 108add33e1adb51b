#pragma once
// Small references shared by the suites that sweep scales (taylor, horner_form, cells,
// embree_hits): random signed powers of ten, the monomials of a polynomial with given even
// axes, and the exact slab span of a ray in a box.
#include "algray/polynomial.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <random>

namespace algray::test {

// A random +-10^x with x uniform in [lo, hi] (two draws of U(0, 1): the sign, then x).
template <class Rng>
double signedPow10(Rng& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double sign = u(rng) < 0.5 ? -1.0 : 1.0;
  return sign * std::pow(10.0, lo + (hi - lo) * u(rng));
}

// The monomials x^i y^j z^k of degree <= maxDegree whose exponents are even on the axes of
// `mask` (bit a: axis a), in forEachMonomialOfDegree's order: the terms a random f with
// those even axes may have (HornerForm's evaluation and restriction on squared coordinates).
template <class Fn>
void forEachMonomialEvenOn(unsigned mask, int maxDegree, Fn&& fn) {
  for (int n = 0; n <= maxDegree; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int) {
      const int e[3] = {i, j, k};
      for (int a = 0; a < 3; ++a)
        if ((mask >> a & 1u) != 0 && e[a] % 2 != 0) return;
      fn(i, j, k);
    });
}

// The span [t0, t1] of o + t d inside [lo, hi] from t0 = tMin to t1 = tMax, in long double
// (Kay and Kajiya's slabs; a zero d_a leaves its slab alone: callers put o inside it).
inline void slabSpan(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo,
                     const glm::dvec3& hi, long double& t0, long double& t1) {
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) continue;
    long double ta = ((long double)lo[a] - o[a]) / d[a], tb = ((long double)hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
}

}  // namespace algray::test
