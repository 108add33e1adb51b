#pragma once
// Taylor restriction of a surface to a ray (the seed paper's central identity):
//   g(t) = f(o + t d) = sum_{n <= m} t^n / n! (d . grad)^n f(o) = sum_n t^n H_n(d),
// where H_n is the homogeneous part of degree n of the shifted polynomial u -> f(o + u).
// Two paths:
//  (1) OriginExpansion: shift f to o once (all derivative tensors at o); then each ray
//      from o costs one evaluation of the homogeneous parts at d, O(#terms). This is the
//      path for rays sharing an origin (a camera's primary rays).
//  (2) restrictToRay: a direct per-ray restriction for arbitrary origins, by nested
//      Horner in the ring of univariate polynomials.
// Both return coefficients with a componentwise rounding-error bound the solver uses to
// decide tangent roots (roots.h).
#include "algray/horner_form.h"
#include "algray/polynomial.h"

#include <array>
#include <cmath>
#include <vector>

namespace algray {

// g(s) = sum_{i <= degree} coeff[i] s^i, where the ray parameter is t = tShift + s.
// error[i] bounds |coeff[i] - exact coefficient| for the given (double) expansion point,
// with gradual underflow and with flush-to-zero and denormals-are-zero alike (a floor of
// order 2^-1022 times the powers of the ray that follow an underflow, taylor.cpp); it is
// +inf where coeff[i] is not finite or the bound's own magnitudes overflowed.
struct RayPolynomial {
  int degree = -1;  // -1 .. kMaxDegree (the arrays' size; beyond it evaluate throws Error)
  double tShift = 0;
  std::array<double, kMaxDegree + 1> coeff{};
  std::array<double, kMaxDegree + 1> error{};

  // Value of g at s and a bound on |computed - exact| (coefficient error plus Horner
  // rounding, Higham Eq. (5.3)).
  double evaluate(double s) const;
  double evaluateWithBound(double s, double& bound) const;
  // The same, and g'(s) from the same Horner pass (unbounded: for step sizes).
  double evaluateWithBound(double s, double& bound, double& slope) const;
};

// 1 / dd for dd = |d|^2 > 0, as closestParameter and the adapter's clip chord take it.
// Hosts pass unit directions (float-normalised ones have |dd - 1| ~ 2^-23); for
// |dd - 1| <= 2^-20, 2 - dd (one Newton step for 1 / dd from 1) is within a relative
// (1 - dd)^2 <= 2^-40 of it and keeps a division off a camera ray's critical path (the
// quadric path: 3.5 of 62 ns a ray, measured). Other directions divide.
inline double inverseSquaredLength(double dd) {
  return std::abs(dd - 1.0) <= 0x1p-20 ? 2.0 - dd : 1.0 / dd;
}

// Parameter of the point of the line o + t d closest to c, as dot(c - o, d) times
// inverseSquaredLength(|d|^2): that factor is within a relative 2^-40 of 1 / |d|^2, but the
// dot product is rounded like any other (within gamma_4 sum |(c - o)_a d_a|), which is no
// relative bound where it cancels (c - o nearly orthogonal to d: the result may be off by
// far more than 2^-40 of itself). It is only an expansion point, which any t serves
// (restrictToRay's bounds hold about the point o + tShift d it forms, whatever tShift): the
// natural one when o is far from the clip region (re-centring avoids the cancellation of
// |o|^m-sized terms when evaluating near the surface), closer the better.
double closestParameter(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& c);

// Path (2): coefficients of g(s) = f(o + (tShift + s) d). Cost O(m^4) for a dense f of
// degree m, less for sparse ones.
RayPolynomial restrictToRay(const Polynomial& f, const glm::dvec3& o, const glm::dvec3& d,
                            double tShift = 0.0);
// The same over f's precompiled Horner box: only the box f occupies is visited (a separable
// f, Chmutov's, costs O(m^2) instead of O(m^4)), with identical coefficients and bound; where
// f has even axes and the ray's components are in range (HornerForm::restrictsOnSquares),
// over the smaller box of F, f(x, y, z) = F(x^2, y, z) etc., with quadratic steps: other
// roundings, within a bound of the same form (taylor_box.cpp, "Even axes").
RayPolynomial restrictToRay(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d,
                            double tShift = 0.0);
// The same into an existing record (a per-thread one on the adapter's path: returning the
// 672-byte record by value cost a block copy per ray). Entries above g.degree are left
// as they were.
void restrictToRay(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double tShift,
                   RayPolynomial& g);

// The part of the direct restriction's bound that covers underflow (taylor.cpp,
// "Underflow"): floor[r] for r = 0..f.degree(), which restrictToRay adds to the rounding
// bound of coefficient r, for the expansion point p = o + tShift d as it forms it. For the
// tests' reference of the kernels.
std::array<double, kMaxDegree + 1> restrictionUnderflowFloor(const HornerForm& f,
                                                             const glm::dvec3& p,
                                                             const glm::dvec3& d);

// Path (1): f expanded about o once; restrict(d) for every ray from o.
class OriginExpansion {
 public:
  OriginExpansion() = default;
  OriginExpansion(const Polynomial& f, const glm::dvec3& o);

  const glm::dvec3& origin() const { return origin_; }
  const Polynomial& shifted() const { return shifted_; }
  int degree() const { return shifted_.degree(); }

  // Coefficients of g(t) = f(o + t d) (tShift = 0): coeff[n] = H_n(d). With
  // withError = false the error array is left zero (saves half the work when the caller
  // does not need tangent decisions).
  RayPolynomial restrict(const glm::dvec3& d, bool withError = true) const;
  // The same into g, writing only entries 0..degree() (a per-ray hot path: no 2 x 41
  // zeroed doubles and no copy); the entries above g.degree keep what they held.
  void restrict(const glm::dvec3& d, RayPolynomial& g, bool withError = true) const;

 private:
  glm::dvec3 origin_{0.0};
  Polynomial shifted_;
  // Non-zero terms of shifted_, used instead of the dense kernel when few (taylor.cpp).
  struct SparseTerm {
    double c;
    int n, i, j, k;
  };
  std::vector<SparseTerm> sparseTerms_;
  // Per homogeneous block n: W_n with |error of H_n(d)| <= W_n max|d_i|^n plus the
  // underflow floor F_n 2^-1022 max(1, max|d_i|)^n (taylor.cpp).
  std::array<double, kMaxDegree + 1> blockErrorWeight_{};
  std::array<double, kMaxDegree + 1> blockFloorWeight_{};
};

}  // namespace algray
