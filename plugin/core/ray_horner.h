#pragma once
// Private building blocks of the direct restriction to a ray (taylor.cpp, taylor_box.cpp):
// nested Horner of f(p + s d) in R[s]. Not installed.
//
// Each step multiplies a univariate polynomial by a linear factor (a + b s) and adds the
// next term. The same steps run on absolute values in the same loops, giving the
// coefficients of |f|(|p| + s |d|), the magnitudes the error bound scales: two independent
// dependency chains, so the second one is nearly free on a pipelined core.
//
// A (value, magnitude) pair is one 2-lane vector (GCC/Clang vector extension): both chains
// advance in one SIMD operation and every load matches the width of the store that wrote
// it. (With separate scalar arrays the compiler vectorised the additions, and 16-byte
// loads of two 8-byte stores defeated store forwarding: a 3x slowdown, found by perf.)
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include "algray/polynomial.h"

namespace algray::ray_horner {

typedef double Pair __attribute__((vector_size(16)));

// A coefficient on both chains.
inline Pair term(double c) { return Pair{c, std::abs(c)}; }

// q <- q * (p + d s) on both chains; q has degree deg >= 0 before the call.
inline void mulLinear(Pair* q, int deg, Pair p, Pair d) {
  q[deg + 1] = d * q[deg];
  for (int r = deg; r >= 1; --r) q[r] = p * q[r] + d * q[r - 1];
  q[0] = p * q[0];
}

// H <- H * (p + d s) + c on both chains, H of degree degH (-1: still zero, and then a zero
// c is skipped, so leading zero coefficients of a sparse column cost nothing).
inline void hornerStep(Pair* h, int& degH, double c, Pair p, Pair d) {
  if (degH < 0 && c == 0.0) return;
  if (degH < 0) {
    h[0] = term(c);
  } else {
    mulLinear(h, degH, p, d);
    h[0] += term(c);
  }
  ++degH;
}

// The relative bound's factor gamma_{3m+3} (1 + gamma_{3m+3}) of the direct restriction
// (taylor.cpp) for every degree m, folded at compile time: gamma's division per call sat
// on the path to the bound's stores once the underflow floor below joined them
// (BM_GalleryDirect's sphere: 15 % of its samples on that division; same bits).
inline constexpr auto kRestrictFactor = [] {
  std::array<double, kMaxDegree + 1> f{};
  for (int m = 0; m <= kMaxDegree; ++m) f[m] = gamma(3 * m + 3) * (1.0 + gamma(3 * m + 3));
  return f;
}();

// ---- Underflow floor of the bound (derivation: taylor.cpp, "Underflow") ------------------
// The smallest e >= 0 with 2^e > max(1, x) for x >= 0, from the biased exponent field E
// (x < 2^(E - 1022)); 1025 for inf or NaN.
inline int ceilExponent(double x) {
  return std::max(0, static_cast<int>(std::bit_cast<std::uint64_t>(x) >> 52) - 1022);
}

// Whether a component is subnormal (non-zero with a zero exponent field), from its bits:
// under DAZ a subnormal compares equal to 0.
inline bool hasSubnormal(const glm::dvec3& v) {
  bool any = false;
  for (int a = 0; a < 3; ++a) {
    const std::uint64_t b = std::bit_cast<std::uint64_t>(v[a]) << 1;  // without the sign
    any |= b - 1 < (std::uint64_t{1} << 53) - 1;
  }
  return any;
}

// 2^e for e >= -1022 (a normal double, exact), +inf from e = 1024 on.
inline double pow2(int e) {
  return std::bit_cast<double>(static_cast<std::uint64_t>(std::min(e, 1024) + 1023) << 52);
}

// Binomial coefficients C(m, r), m <= kMaxDegree (exact doubles: C(40, 20) < 2^38).
inline constexpr auto kBinomial = [] {
  std::array<std::array<double, kMaxDegree + 1>, kMaxDegree + 1> c{};
  for (int m = 0; m <= kMaxDegree; ++m) {
    c[m][0] = 1.0;
    for (int r = 1; r <= m; ++r) c[m][r] = c[m - 1][r - 1] + (r < m ? c[m - 1][r] : 0.0);
  }
  return c;
}();

// The floor's weight w_m C(m, r), w_m = 32 (m + 2) termCount(m + 1) (taylor.cpp: twice the
// operations' term, so that it also covers the term of a subnormal p or d component
// whenever 2 m sum|c| <= 16 (m + 2) termCount(m + 1), kFloorAbsSumLimit[m]).
inline constexpr auto kFloorWeight = [] {
  std::array<std::array<double, kMaxDegree + 1>, kMaxDegree + 1> w{};
  for (int m = 0; m <= kMaxDegree; ++m)
    for (int r = 0; r <= m; ++r)
      w[m][r] = 32.0 * (m + 2) * Polynomial::termCount(m + 1) * kBinomial[m][r];
  return w;
}();
inline constexpr auto kFloorAbsSumLimit = [] {
  std::array<double, kMaxDegree + 1> a{};
  for (int m = 1; m <= kMaxDegree; ++m) a[m] = 8.0 * (m + 2) * Polynomial::termCount(m + 1) / m;
  a[0] = HUGE_VAL;  // no term at degree 0
  return a;
}();

// A bound as computed, or +inf where it is NaN: magnitudes are never negative, so NaN
// comes from inf * 0 (an overflowed magnitude times a zero factor), which bounds nothing.
// (One minsd: NaN < inf is false.)
inline double boundOrInfinity(double e) { return e < HUGE_VAL ? e : HUGE_VAL; }

// The floor of the direct restriction of a degree-m f (absSum = sum |c| over its
// coefficients) about p along d: what taylor.cpp's "Underflow" adds to the relative bound
// of coefficient r is at(r) >= w_m C(m, r) 2^(a (m - r) + b r - 1022) with 2^a > P,
// 2^b > D. Usually as w_m C(m, r) 2^(max(a, b) m - 1022), a table row times one power of
// two (an upper bound of each term: the coefficients' loop stays one multiply-add per
// coefficient and vectorises; the exact powers per r cost the gallery's restrictions 5-7
// ns each, BM_GalleryDirect). That is at most 2^(|a - b| m) times the exact floor, so it
// is taken while that factor is at most 2^64 or the floor itself at most 2^-800; beyond
// (a far point along a tiny direction, a power beyond double's range, or a large sum|c|
// with a subnormal component) the exact form is precomputed.
struct UnderflowFloor {
  const double* weight;
  double scale;
  double at(int r) const { return weight[r] * scale; }
  double general[kMaxDegree + 1];  // the rare inputs' floors (then scale = 1)
};
inline void initUnderflowFloor(UnderflowFloor& f, int m, const glm::dvec3& p, const glm::dvec3& d,
                               double absSum) {
  const double pm = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  const double dm = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  const int a = ceilExponent(pm), b = ceilExponent(dm);
  const int top = std::max(a, b) * m, spread = std::abs(a - b) * m;
  f.weight = kFloorWeight[m].data();
  f.scale = pow2(top - 1022);
  const bool subnormal = absSum > kFloorAbsSumLimit[m] && (hasSubnormal(p) || hasSubnormal(d));
  if ((spread <= 64 || top <= 222) && top <= 2045 && !subnormal) [[likely]]
    return;
  // NaN components (max drops them) leave NaN magnitudes, which the bound maps to inf.
  const double extra = subnormal ? 1.0 + 2.0 * m * absSum / kFloorWeight[m][0] : 1.0;
  for (int r = 0; r <= m; ++r)
    f.general[r] = kFloorWeight[m][r] * extra * pow2(a * (m - r) + b * r - 1022);
  f.weight = f.general;
  f.scale = 1.0;
}

}  // namespace algray::ray_horner
