#pragma once
// A Polynomial precompiled for nested Horner schemes: f(p), grad f(p) and a rigorous
// rounding bound at one point (the adapter's self-root rule and Newton polish at every
// hit), and the layout taylor.h's direct restriction to a ray runs over
// (restrictToRay(const HornerForm&, ...)).
//
// Scheme: nested Horner, f = sum_i x^i sum_j y^j sum_k c_ijk z^k, evaluated innermost
// first (z-rows, then y within an x-block, then x), with the derivative recurrences of
// Horner's scheme (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed.,
// Sec. 5.1, Alg. 5.2) for the gradient and the same scheme over |c| and |x|, |y|, |z|
// for the bound. Only the box the polynomial occupies is stored: x-blocks up to the
// highest i, y-rows up to the highest j of that block, z-rows up to the highest k of the
// row. A separable surface (Chmutov: T(x) + T(y) + T(z)) then costs ~3(m+1) coefficients
// instead of the (m+1)(m+2)(m+3)/6 of the dense graded storage, with no sparse index.
//
// Even axes: when every exponent of x (y, z) is even, evaluate() runs the same scheme on
// F(X, y, z) = f(x, y, z), X = x^2, over F's own box (about half the blocks or rows or
// slots per even axis: Sarti's dodecic 84 instead of 167), with its own rigorous bound.
//
// Cost per evaluation: no heap allocation; 6 flops per stored coefficient, 8 per row,
// 10 per block. Measured against Polynomial::evaluateWithBound in
// tests/bench/polynomial_bench.cpp (BM_PointEval*).
#include "algray/polynomial.h"

#include <glm/vec3.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace algray {

class HornerForm {
 public:
  HornerForm() : HornerForm(Polynomial()) {}  // the zero polynomial
  explicit HornerForm(const Polynomial& f);

  int degree() const { return degree_; }
  // Stored coefficients (the Horner box, zeros inside it included).
  int coefficientCount() const { return static_cast<int>(slots_.size()); }

  // value, gradient, magnitude (sum |c| |x|^i |y|^j |z|^k, computed) and valueError with
  // |computed value - exact value| <= valueError whenever the result is finite, with
  // gradual underflow and with flush-to-zero / denormals-are-zero alike (derivation in
  // horner_form.cpp). Non-finite input gives a non-finite or NaN result. On an even axis
  // (evenAxes()) the scheme runs on the squared coordinate; its magnitude is then an upper
  // bound of that sum.
  Polynomial::Evaluation evaluate(const glm::dvec3& p) const;
  // f(p) by the compensated nested Horner scheme (error-free transformations, plain double
  // arithmetic, the same on every host): |result - f(p)| <= 2u |f(p)| + gamma(2m+6)^2 E(p)
  // + U(p), E = sum |c| |x|^i |y|^j |z|^k (Graillat, Langlois and Louvet, "Compensated
  // Horner Scheme", 2005, Thm. 3.1, with the nesting's extra steps;
  // tests/horner_form_test.cpp) and U the underflow term of compensatedBound, so
  // near a root it is exact to the square of evaluate()'s relative bound. About 27 flops
  // per stored coefficient against evaluate()'s 6, value only: for where evaluate()'s bound
  // is what limits a root (the adapter's polish and its settling of a first root).
  // Non-finite or beyond 2^995 in any partial value (the splitting constant's range): NaN.
  double valueCompensated(const glm::dvec3& p) const;
  // That bound for a compensated value v at p where evaluate() gave the magnitude E (an
  // upper bound of it on even axes, which only widens the bound), with gradual underflow
  // and with flush-to-zero / denormals-are-zero alike: U(p) counts 2^-1022 for every
  // operation of the scheme (the theorem assumes none underflows; x y^2 at (1e200,
  // 1e-160, 0) under FTZ gave 0 for 1e-120 with a bound of 2.9e-121), derivation at
  // valueCompensated in horner_form.cpp.
  double compensatedBound(double v, double magnitude, const glm::dvec3& p) const;
  // The axes a in which every monomial's exponent is even and some is not 0 (bit a set):
  // f(x, y, z) = F(x^2, y, z) etc., which evaluate() runs on a box of F (horner_form.cpp).
  unsigned evenAxes() const { return evenAxes_; }

  // A coefficient and its weight in the bound: |c| plus a floor that absorbs underflow.
  struct Slot {
    double c;
    double absC;
  };
  // The layout, for other nested schemes over the same box: x-blocks for i = topI down to
  // 0, each of blockRows()[b] y-rows (j descending to 0), each of rowLengths()[r] slots
  // (k descending to 0), all in evaluation order.
  std::span<const Slot> slots() const { return slots_; }
  std::span<const std::uint8_t> rowLengths() const { return rowLength_; }
  std::span<const std::uint8_t> blockRows() const { return groups_.blockRows; }

  // The slots' coefficients as (c, |c|), 16-byte aligned: the direct restriction to a ray
  // (taylor_box.cpp) runs value and magnitude as one SSE vector and loads a slot's pair in
  // one instruction (5-7 % faster per ray than forming it from c).
  struct alignas(16) SignedTerm {
    double c;
    double absC;  // |c| exactly, no floor
  };
  std::span<const SignedTerm> signedTerms() const { return signedTerms_; }
  // The same layout for F's box (evenAxes(): f(x, y, z) = F(x^2, y, z) etc.), which the
  // direct restriction runs on squared coordinates (taylor_box_even_kernels.inc): empty
  // when evenAxes() is 0.
  std::span<const SignedTerm> evenSignedTerms() const { return evenTerms_; }
  std::span<const std::uint8_t> evenRowLengths() const { return evenRowLength_; }
  std::span<const std::uint8_t> evenBlockRows() const { return reduced_.blockRows; }
  // Whether the direct restriction about p along d runs on F's box: some axis is even, the
  // degree is at least 4, and every component of p and d is +-0 or normal, those on an
  // even axis within [2^-400, 2^401) (their squares and 2 p_a d_a then normal and finite:
  // the derivation in taylor_box.cpp). Otherwise it runs f's own box. One predictable
  // branch when no axis is even. (Quadrics keep f's box: the sphere's 7 slots against F's
  // 4 measured 70.6 -> 73.6 ns on F's, the ellipsoid 70.2 -> 77.3; the torus 139 -> 95.)
  bool restrictsOnSquares(const glm::dvec3& p, const glm::dvec3& d) const {
    return restrictEven_ && reducedApplies(p) && reducedApplies(d);
  }
  // sum |c| over the slots, added in their order (the direct restriction's underflow
  // floor reads it, taylor.cpp).
  double absCoeffSum() const { return absCoeffSum_; }

 private:
  std::vector<Slot> slots_;                  // z-rows in evaluation order: i, j, k descending
  std::vector<SignedTerm> signedTerms_;      // the same order
  std::vector<std::uint8_t> rowLength_;      // per z-row, >= 1 (kMaxDegree + 1 fits)
  std::vector<SignedTerm> evenTerms_;        // F's box (restrictsOnSquares), same order
  std::vector<std::uint8_t> evenRowLength_;  // per z-row of F's box
  // The z-rows four at a time for evaluate() (see there): groups of rows of similar
  // length, longest first, each row padded at its start with slots (0, 0) to the group's
  // length; per position (c, absC) of the four rows, per group its length and its rows.
  // (32-byte aligned: the AVX2 kernel loads c and absC whole, never across a cache line.)
  struct alignas(32) GroupSlot {
    double c[4];
    double absC[4];
  };
  struct Groups {
    std::vector<GroupSlot> slots;
    std::vector<std::uint8_t> length;
    std::vector<std::uint16_t> rows;  // 4 per group (padding lanes: rows, a copy)
    std::vector<std::uint8_t> blockRows;
  };
  static void buildBox(const Polynomial& f, int m, std::vector<Slot>& slots,
                       std::vector<std::uint8_t>& rowLength, std::vector<std::uint8_t>& blockRows);
  static Groups buildGroups(std::span<const Slot> slots, std::span<const std::uint8_t> rowLength,
                            std::span<const std::uint8_t> blockRows);
  Groups groups_;  // the box above
  // The box of F, f(x, y, z) = F(x^2, y, z) on the even axes (evenAxes_): evaluate() only.
  Groups reduced_;
  unsigned evenAxes_ = 0;
  bool restrictEven_ = false;      // evenAxes_ != 0 and degree_ >= 4 (restrictsOnSquares)
  double reducedMagFactor_ = 0;    // magnitude = reducedMagFactor_ * computed E of F
  double reducedErrorFactor_ = 0;  // valueError = reducedErrorFactor_ * magnitude
  // Per axis, the biased exponent fields of a coordinate the reduced path takes:
  // [lo, lo + span] (or +-0).
  std::uint32_t reducedExpLo_[3] = {0, 0, 0};
  std::uint32_t reducedExpSpan_[3] = {0, 0, 0};
  bool reducedApplies(const glm::dvec3& p) const {
    // From the bits (under DAZ a subnormal compares equal to 0): each coordinate +-0 or
    // with its exponent field in its axis's range. NaN and inf (field 2047) never are.
    bool ok = true;
    for (int axis = 0; axis < 3; ++axis) {
      const std::uint64_t b = std::bit_cast<std::uint64_t>(p[axis]) << 1;  // without the sign
      const std::uint32_t field = static_cast<std::uint32_t>(b >> 53);
      ok &= b == 0 || field - reducedExpLo_[axis] <= reducedExpSpan_[axis];
    }
    return ok;
  }
  Polynomial::Evaluation evaluateReduced(const glm::dvec3& p) const;
  int degree_ = -1;
  int axisDegree_[3] = {0, 0, 0};  // f's degree in x, y, z (compensatedBound)
  double absCoeffSum_ = 0;
  double errorFactor_ = 0;  // valueError = errorFactor_ * magnitude
};

}  // namespace algray
