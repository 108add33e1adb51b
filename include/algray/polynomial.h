#pragma once
// A trivariate polynomial f(x, y, z) of total degree <= kMaxDegree, the model of an
// algebraic surface f = 0.
//
// Storage: dense, graded by total degree. The coefficient of x^i y^j z^k lives at
//   index(i, j, k) = T(n) + (j + k)(j + k + 1)/2 + k,   n = i + j + k,  T(n) = n(n+1)(n+2)/6,
// so every homogeneous part H_n is one contiguous block. Why dense and not sparse:
//  * The hot operation of the library is the Taylor restriction about a ray origin o
//    (taylor.h). Translating f to o fills in every lower-degree monomial, so the shifted
//    polynomial is dense whatever f was, and its homogeneous blocks are exactly what the
//    per-ray evaluation walks (Eq. 4.4 of the seed paper: g_n = H_n(d)).
//  * The classic surfaces are small in dense form (degree 12: 455 terms, 3.6 KiB).
//  * Products and powers skip zero coefficients, so sparse inputs (Chmutov) cost what
//    their non-zero terms cost; tests/bench/polynomial_bench.cpp measures the parser-style
//    workload in this layout.
// C++20 (std::span, std::bit_cast, concepts): older dialects fail here, by name, not deep
// inside a header (a C++17 consumer's first error was polynomial.h's std::span).
#if __cplusplus < 202002L
#error "algray needs C++20 (-std=c++20; CMake consumers get it from algray::algray)"
#endif

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace algray {

// The largest total degree accepted anywhere in the library.
inline constexpr int kMaxDegree = 40;

// Unit roundoff of double and the classic gamma_n = n u / (1 - n u) of Higham,
// "Accuracy and Stability of Numerical Algorithms", 2nd ed., Eq. (3.8).
inline constexpr double kUnitRoundoff = 0x1p-53;
constexpr double gamma(int n) { return n * kUnitRoundoff / (1.0 - n * kUnitRoundoff); }

// Base of every error algray throws; callers (and the Embree boundary) catch this type.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Polynomial {
 public:
  // Number of monomials of total degree <= n, and where the block of degree n starts.
  static constexpr int termCount(int n) { return (n + 1) * (n + 2) * (n + 3) / 6; }
  static constexpr int blockStart(int n) { return n * (n + 1) * (n + 2) / 6; }
  static constexpr int index(int i, int j, int k) {
    return blockStart(i + j + k) + (j + k) * (j + k + 1) / 2 + k;
  }

  Polynomial() = default;  // the zero polynomial
  explicit Polynomial(double constant);
  // The coordinate function x (axis 0), y (axis 1) or z (axis 2).
  static Polynomial variable(int axis);

  // Highest total degree with a non-zero coefficient; -1 for the zero polynomial.
  int degree() const { return degree_; }
  bool isZero() const { return degree_ < 0; }

  double coeff(int i, int j, int k) const;
  // Sets a coefficient, growing the storage; throws Error beyond kMaxDegree.
  void setCoeff(int i, int j, int k, double value);
  // All coefficients in graded order, termCount(degree()) of them.
  std::span<const double> coeffs() const { return coeffs_; }
  // The homogeneous part of degree n (n <= degree()), (n+1)(n+2)/2 coefficients.
  std::span<const double> homogeneousPart(int n) const;

  Polynomial& operator+=(const Polynomial& other);
  Polynomial& operator-=(const Polynomial& other);
  Polynomial& operator*=(double s);
  friend Polynomial operator+(Polynomial a, const Polynomial& b) { return a += b; }
  friend Polynomial operator-(Polynomial a, const Polynomial& b) { return a -= b; }
  friend Polynomial operator*(Polynomial a, double s) { return a *= s; }
  friend Polynomial operator*(double s, Polynomial a) { return a *= s; }
  friend Polynomial operator-(Polynomial a) { return a *= -1.0; }
  friend Polynomial operator*(const Polynomial& a, const Polynomial& b);
  // Throws Error when the result would exceed kMaxDegree.
  Polynomial pow(int exponent) const;

  // Partial derivative along axis 0, 1 or 2.
  Polynomial derivative(int axis) const;
  // p -> f(A p + b): rotation, scale and translation of the argument. Used to place a
  // surface in the world (f_world(p) = f(M^-1 p)) and to re-centre.
  Polynomial composeAffine(const glm::dmat3& a, const glm::dvec3& b) const;
  // u -> f(o + u): the Taylor expansion about o, i.e. all derivative tensors
  // D^n f(o)/n! (the homogeneous parts of the result). Exact up to rounding: three
  // Taylor shifts by synthetic division, componentwise within gamma_{6m} of the same shift
  // of |f| by |o| wherever no operation's result falls below 2^-1022 in magnitude. That
  // relative bound excludes underflow: such a result errs by an absolute amount more (up to
  // 2^-1075 with gradual underflow, 2^-1022 under flush-to-zero; under denormals-are-zero a
  // subnormal coefficient or component of o reads as 0), which the later steps scale like a
  // coefficient placed at its slot, so for subnormal data the error exceeds gamma_{6m} times
  // the shift of |f| by any factor (-3e-310 y z^2 about (0, 0, -0.237): the y coefficient,
  // -1.69e-311, by 75 times). OriginExpansion (taylor.cpp), which uses this bound, covers
  // both with a floor: its shift of |f| adds 8 * 2^-1022 / gamma_{6m+6} at every slot and
  // operation, and a subnormal o's own term (tests/taylor_test.cpp).
  Polynomial translate(const glm::dvec3& o) const;

  double evaluate(const glm::dvec3& p) const;
  glm::dvec3 gradient(const glm::dvec3& p) const;

  struct Evaluation {
    double value = 0;
    glm::dvec3 gradient{0.0};
    // |computed value - exact value| <= valueError, by a running error analysis
    // (Higham, Sec. 3.1 and 5.1): gamma_{n+2} sum|terms| for the monomial products plus
    // u sum|partial sums| for the summation; evaluateWithBound adds the underflow floors
    // that keep it with gradual underflow and with flush-to-zero / denormals-are-zero alike
    // (subnormal coefficients and coordinates included; polynomial.cpp).
    double valueError = 0;
    // sum over terms of |c x^i y^j z^k|: the scale a relative tolerance refers to.
    double magnitude = 0;
  };
  Evaluation evaluateWithBound(const glm::dvec3& p) const;

  double maxAbsCoeff() const;
  bool isFinite() const;
  // Sets to zero every coefficient c with |c| <= threshold[index] and trims the degree.
  // Returns how many non-zero coefficients were removed.
  int pruneBelow(std::span<const double> threshold);
  // Number of non-zero coefficients.
  int nonZeroCount() const;

  // Text the parser reads back to the same coefficients (%.17g literals).
  std::string toString() const;

  friend bool operator==(const Polynomial& a, const Polynomial& b) {
    return a.degree_ == b.degree_ && a.coeffs_ == b.coeffs_;
  }

 private:
  void resizeToDegree(int n);  // storage for degree n, keeping coefficients
  void trim();                 // drop trailing all-zero blocks

  int degree_ = -1;
  std::vector<double> coeffs_;
};

// Calls fn(i, j, k, index) for every monomial of total degree n in storage order.
template <class Fn>
constexpr void forEachMonomialOfDegree(int n, Fn&& fn) {
  int idx = Polynomial::blockStart(n);
  for (int jk = 0; jk <= n; ++jk)
    for (int k = 0; k <= jk; ++k) fn(n - jk, jk - k, k, idx++);
}

}  // namespace algray
