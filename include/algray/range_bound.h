#pragma once
// Guaranteed enclosures of the range of a polynomial over an axis-aligned box: the
// emptiness test behind the cells (cells.h).
//
// BoxPolynomial holds F(w) = f(c + h*w) for w in [-1, 1]^3 (componentwise product h*w)
// with interval coefficients that contain the exact coefficients of that re-scaled
// Taylor expansion. Two facts make it the right form:
//  * Centred (Taylor) form: on a box of half-width h about c the linear term dominates,
//    so the enclosure F(0) +- sum_{m != 0} |F_m| overestimates the true range by
//    O(h^2) only (Neumaier, "Interval Methods for Systems of Equations", Sec. 2.3;
//    Ratschek & Rokne, "Computer Methods for the Range of Functions", Ch. 2).
//  * Halving is exact in the re-scaled variable: the two halves of the box along axis a
//    are w_a -> +-1/2 + w_a/2, a Taylor shift by a power of two and a scaling by powers
//    of two. A child costs one univariate Taylor shift per column of the parent,
//    O(m^4/24) operations for degree m, and the box corners stay exact dyadics.
// Every coefficient operation is interval arithmetic (interval.h), so the enclosure is
// conservative including every rounding error of the construction. That arithmetic
// assumes gradual underflow: rangeOverBox, rangeOverInterval and buildCells (cells.h)
// clear flush-to-zero / denormals-are-zero for their duration (the caller's mode is
// restored); code calling BoxPolynomial directly must not run with them.
#include "algray/interval.h"
#include "algray/polynomial.h"

#include <span>
#include <vector>

namespace algray {

enum class RangeBound {
  Centred,    // BoxPolynomial::range()
  Bernstein,  // range(), then rangeBernstein() if the first does not exclude 0
};

// Index tables of the graded layout (polynomial.h) for one degree: for each axis, the
// monomials grouped in columns that share the other two exponents, ordered by the
// exponent of that axis. Shared (read-only) by all boxes of one build.
struct MonomialTables {
  explicit MonomialTables(int degree);  // throws Error outside 0..kMaxDegree
  int degree;
  int terms;
  std::vector<int> columnIndex[3];     // concatenated columns, exponent 0 first
  std::vector<int> columnStart[3];     // columnStart[a][c] .. columnStart[a][c + 1]
  std::vector<int> exponent[3];        // exponent[a][index] of axis a in monomial index
  std::vector<unsigned char> allEven;  // 1 if x^i y^j z^k >= 0 everywhere (i, j, k even)
  double halfPow[kMaxDegree + 1];      // 2^-e
  // Interval multiply-adds of one halving (BoxPolynomial::half): the unit of the build
  // cost model; and of one Bernstein enclosure (rangeBernstein).
  long splitCost() const;
  long bernsteinCost() const;
};

class BoxPolynomial {
 public:
  BoxPolynomial() = default;
  // F(w) = f(c + h*w); h must be >= 0 (it is the half-width, rounded up by the caller).
  // tables must describe f.degree() and outlive the result.
  BoxPolynomial(const Polynomial& f, const glm::dvec3& c, const glm::dvec3& h,
                const MonomialTables& tables);

  // The half of the box on side (-1: w_axis <= 0, +1: w_axis >= 0), re-scaled to [-1, 1]:
  // G(w) = F(w with w_axis -> side/2 + w_axis/2).
  BoxPolynomial half(int axis, int side) const;
  void half(int axis, int side, BoxPolynomial& out) const;
  // The sub-box centre + scale*w (centre in [-1, 1]^3, scale = 2^-splits per axis, both
  // exact dyadics) re-scaled to [-1, 1]^3: one Taylor shift per axis, as three halvings.
  void subBox(const glm::dvec3& centre, const int splits[3], BoxPolynomial& out) const;

  // Enclosure of {F(w) : w in [-1, 1]^3}: F(0) plus, per monomial, c * [0, 1] if all
  // exponents are even, else c * [-1, 1].
  Interval range() const;
  // True if 0 is provably outside the range (NaN bounds never prove emptiness).
  bool provablyNonZero() const;
  // Tighter and ~15-25x costlier: the tensor Bernstein coefficients of F on the box
  // (degree m per axis) enclose its range (Garloff, "Convergent bounds for the range of
  // multivariate polynomials", 1986; Farouki & Rajan 1987 for the univariate basis).
  // Power to Bernstein on [0, 1]: b_K = sum_{i <= K} C(K, i) / C(m, i) a_i per axis, after
  // w = 2t - 1. In interval arithmetic like the rest. O(m^4) with a constant ~3/2 vs
  // ~1/24 for a halving.
  Interval rangeBernstein() const;

  const std::vector<Interval>& coeffs() const { return coeffs_; }
  const MonomialTables& tables() const { return *tables_; }

 private:
  const MonomialTables* tables_ = nullptr;
  std::vector<Interval> coeffs_;  // graded layout, tables_->terms entries
};

// ---- Univariate: a ray's polynomial over a cell's span ----------------------------------
// Enclosure of {g(s) : lo <= s <= hi} for g(s) = sum c[i] s^i whose exact coefficients lie
// within err[i] of c[i] (err empty: c exact). Centred form about the midpoint m: the
// Taylor shift g(m + u) = sum b_k u^k in interval arithmetic (m(m+1)/2 interval
// multiply-adds for degree m), then b_0 + sum b_k [-r^k, r^k] ([0, r^k] for even k),
// r the half-width. Overestimates the true range by O(r^2): cheap and tight on the short
// spans of small cells, where it can prove "no root here" before a full root solve.
// Throws Error for more than kMaxDegree + 1 coefficients (as firstRoot, roots.h).
Interval rangeOverInterval(std::span<const double> c, std::span<const double> err, double lo,
                           double hi);
// True if g provably has no root in [lo, hi] (never for non-finite input). Throws Error for
// more than kMaxDegree + 1 coefficients, as rangeOverInterval.
inline bool provablyNoRoot(std::span<const double> c, std::span<const double> err, double lo,
                           double hi) {
  const Interval r = rangeOverInterval(c, err, lo, hi);
  return r.lower() > 0.0 || r.upper() < 0.0;
}

// Cheaper, looser test in O(m) plain double operations (three Horner loops, no interval
// arithmetic): with M(x) = sum (|c_i| + err_i) x^i, every s with |s - mid| <= r has
//   |g(s) - g(mid)| <= sum |c_i| |s^i - mid^i| <= M(|mid| + r) - M(|mid|)
// (|s^i - mid^i| <= (|mid| + r)^i - |mid|^i, expand both binomially). True if |g(mid)|
// exceeds that plus every rounding error (Higham's gamma bounds), i.e. no root in
// [lo, hi]. Loose where the coefficients cancel, which the centred form is not. Throws
// Error for more than kMaxDegree + 1 coefficients.
bool quickNoRoot(std::span<const double> c, std::span<const double> err, double lo, double hi);

// A half-width h >= max(hi - c, c - lo) (exact reals), 0 when lo == c == hi.
double halfWidth(double lo, double c, double hi);

// Enclosure of {f(p) : lo <= p <= hi} by the centred form above, or its intersection with
// the Bernstein enclosure (one box, no subdivision). For tests and diagnostics; throws
// Error on non-finite input or lo > hi.
Interval rangeOverBox(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
                      RangeBound bound = RangeBound::Centred);

}  // namespace algray
