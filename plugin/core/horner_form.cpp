#include "algray/horner_form.h"

#include <algorithm>
#include <cmath>

#include "ray_horner.h"

namespace algray {

namespace {

// Error bound of the nested Horner scheme (Higham, Sec. 5.1 applied per level).
//
// One level, q_K = c_K, q_k = fl(fl(t q_{k+1}) + c_k): c_k enters with one rounding (the
// addition) and then goes through k multiply-add steps, so the computed q_0 is
// sum_k c_k (1 + theta_{2k+1}) t^k (Higham, Lemma 3.1 and Eq. (5.3)). The code starts
// from q = 0 (0 * t + c_K is exact for finite t), which changes nothing.
// Nested: a z-row value Q_ij is the coefficient of the y-level, the block value P_i the
// coefficient of the x-level, so c_ijk collects at most (2k+1) + (2j+1) + (2i+1) <= 2m+3
// roundings and
//   |computed f - f| <= gamma_{2m+3} E,   E = sum |c_ijk| |x|^i |y|^j |z|^k.
// E is computed by the same scheme over |c|, |x|, |y|, |z|: all terms non-negative, so
// the computed Ê >= (1 - gamma_{2m+3}) E and the bound is gamma/(1 - gamma) * Ê. The
// factor kSlack = 1 + 2^-40 covers the few roundings of that constant and of the final
// product (each <= u = 2^-53) and the underflow term of Ê below (<= (2m+3) 2^-75).
//
// Underflow (Higham, Eq. (2.8)): a product may also err by an absolute eta <= 2^-1075
// (sums of doubles are exact when subnormal). Each such eta is added at a coefficient
// slot (i, j, k) of the box (at most 3 per slot: one per level) and then travels the path
// of that slot's coefficient, so it is covered by adding kUnderflowFloor to |c| in every
// stored slot. With flush-to-zero (Embree's and TBB's worker threads) every product and
// sum below 2^-1022 becomes 0, an eta < 2^-1022, two per level, and a subnormal
// coefficient reads as 0 (DAZ): 7 * 2^-1022 (1 + gamma) per slot, which gamma_3
// kUnderflowFloor covers from 2^-968 on. 2^-966 changes E only for polynomials whose every
// value is below ~1e-285. (2^-1000 covered gradual underflow only: random polynomials
// with coefficients near 1e250 at points near 1e-120 broke their bound under FTZ.)
constexpr double kUnderflowFloor = 0x1p-966;
constexpr double kSlack = 1.0 + 0x1p-40;

}  // namespace

HornerForm::HornerForm(const Polynomial& f) : degree_(f.degree()) {
  // The zero polynomial is stored as one zero coefficient, so that it too turns a
  // non-finite point into NaN (0 * inf) instead of a clean 0.
  const int m = std::max(degree_, 0);
  const double g = gamma(2 * m + 3);
  errorFactor_ = g / (1.0 - g) * kSlack;
  // Highest i with a non-zero block, highest j per block, highest k per row: the box.
  int topI = 0;
  for (int i = 0; i <= m; ++i)
    for (int j = 0; i + j <= m; ++j)
      for (int k = 0; i + j + k <= m; ++k)
        if (f.coeff(i, j, k) != 0.0) topI = std::max(topI, i);
  for (int i = topI; i >= 0; --i) {
    int topJ = 0;
    for (int j = 0; i + j <= m; ++j)
      for (int k = 0; i + j + k <= m; ++k)
        if (f.coeff(i, j, k) != 0.0) topJ = std::max(topJ, j);
    // Every block keeps at least one row and every row one slot (possibly a zero
    // coefficient): the multiplication by x (or y) that passes it can underflow, and its
    // slot must carry kUnderflowFloor.
    blockRows_.push_back(static_cast<std::uint8_t>(topJ + 1));
    for (int j = topJ; j >= 0; --j) {
      int topK = 0;
      for (int k = 0; i + j + k <= m; ++k)
        if (f.coeff(i, j, k) != 0.0) topK = k;
      rowLength_.push_back(static_cast<std::uint8_t>(topK + 1));
      for (int k = topK; k >= 0; --k) {
        const double c = f.coeff(i, j, k);
        slots_.push_back({c, std::abs(c) + kUnderflowFloor});
        signedTerms_.push_back({c, std::abs(c)});
        absCoeffSum_ += std::abs(c);
      }
    }
  }
}

Polynomial::Evaluation HornerForm::evaluate(const glm::dvec3& p) const {
  Polynomial::Evaluation e;
  const double x = p.x, y = p.y, z = p.z;
  const double ax = std::abs(x), ay = std::abs(y), az = std::abs(z);
  const Slot* s = slots_.data();
  const std::uint8_t* len = rowLength_.data();
  // Horner with derivatives: (v, dv) <- (v t + c, dv t + v) is v(t) and v'(t) of the level
  // polynomial (Higham, Alg. 5.2 with k = 1); the y- and z-derivatives of the inner levels
  // are carried as coefficients of the outer ones. The *a variables run the bound's scheme.
  double f = 0.0, fx = 0.0, fy = 0.0, fz = 0.0, fa = 0.0;
  for (const std::uint8_t rows : blockRows_) {
    double b = 0.0, by = 0.0, bz = 0.0, ba = 0.0;
    for (int r = 0; r < rows; ++r) {
      double q = 0.0, qz = 0.0, qa = 0.0;
      for (const Slot* end = s + *len++; s != end; ++s) {
        qz = qz * z + q;
        q = q * z + s->c;
        qa = qa * az + s->absC;
      }
      by = by * y + b;
      b = b * y + q;
      bz = bz * y + qz;
      ba = ba * ay + qa;
    }
    fx = fx * x + f;
    f = f * x + b;
    fy = fy * x + by;
    fz = fz * x + bz;
    fa = fa * ax + ba;
  }
  e.value = f;
  e.gradient = {fx, fy, fz};
  e.magnitude = fa;
  e.valueError = errorFactor_ * fa;
  // A subnormal coordinate reads as 0 under DAZ, in the value and in the magnitudes: the
  // result is f at a point moved by eps < 2^-1022 per coordinate, which differs from
  // f(p) by at most m sum|c| 2^-1022 max(1, |p_i|)^(m-1) (telescoped over the factors of
  // each monomial, as taylor.cpp's floor): added, doubled, in that case only.
  if (ray_horner::hasSubnormal(p)) [[unlikely]] {
    const int a = ray_horner::ceilExponent(std::max({ax, ay, az}));
    const int m = std::max(degree_, 1);
    e.valueError += 2.0 * m * absCoeffSum_ * ray_horner::pow2(a * (m - 1) - 1022);
  }
  return e;
}

}  // namespace algray
