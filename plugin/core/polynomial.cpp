#include "algray/polynomial.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

#include "ray_horner.h"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace algray {

namespace {

void checkDegree(int n) {
  if (n > kMaxDegree)
    throw Error("polynomial degree " + std::to_string(n) + " exceeds the limit " +
                std::to_string(kMaxDegree));
}

// Powers p^0..p^n of one coordinate.
void powers(double p, int n, double* out) {
  out[0] = 1.0;
  for (int i = 1; i <= n; ++i) out[i] = out[i - 1] * p;
}

// Degree-m univariate Taylor shift q(x) -> q(x + a) in place, by repeated synthetic
// division (Horner's scheme applied m times, Knuth TAOCP vol. 2, 4.6.4). c holds
// c[0..m] with stride `stride`.
void taylorShift(double* c, int m, std::ptrdiff_t stride, double a) {
  for (int k = 0; k < m; ++k)
    for (int i = m - 1; i >= k; --i) c[i * stride] += a * c[(i + 1) * stride];
}

}  // namespace

Polynomial::Polynomial(double constant) {
  if (constant != 0.0) {
    degree_ = 0;
    coeffs_.assign(1, constant);
  }
}

namespace {
void checkAxis(int axis) {
  if (axis < 0 || axis > 2)
    throw Error("axis " + std::to_string(axis) + " is not 0, 1 or 2 (x, y, z)");
}
}  // namespace

Polynomial Polynomial::variable(int axis) {
  checkAxis(axis);
  Polynomial p;
  p.setCoeff(axis == 0, axis == 1, axis == 2, 1.0);
  return p;
}

double Polynomial::coeff(int i, int j, int k) const {
  if (i < 0 || j < 0 || k < 0 || i + j + k > degree_) return 0.0;
  return coeffs_[index(i, j, k)];
}

void Polynomial::setCoeff(int i, int j, int k, double value) {
  // (coeff() reads negative exponents as 0; a write there would land outside the storage.)
  if (i < 0 || j < 0 || k < 0)
    throw Error("negative exponent in setCoeff(" + std::to_string(i) + ", " + std::to_string(j) +
                ", " + std::to_string(k) + ")");
  const int n = i + j + k;
  checkDegree(n);
  if (n > degree_) {
    if (value == 0.0) return;
    resizeToDegree(n);
  }
  coeffs_[index(i, j, k)] = value;
  if (value == 0.0 && n == degree_) trim();
}

std::span<const double> Polynomial::homogeneousPart(int n) const {
  if (n < 0 || n > degree_) return {};
  return std::span<const double>(coeffs_).subspan(blockStart(n), (n + 1) * (n + 2) / 2);
}

void Polynomial::resizeToDegree(int n) {
  coeffs_.resize(termCount(n), 0.0);
  degree_ = std::max(degree_, n);
}

void Polynomial::trim() {
  while (degree_ >= 0) {
    auto block = homogeneousPart(degree_);
    if (std::any_of(block.begin(), block.end(), [](double c) { return c != 0.0; })) break;
    --degree_;
  }
  coeffs_.resize(degree_ < 0 ? 0 : termCount(degree_));
}

Polynomial& Polynomial::operator+=(const Polynomial& other) {
  if (other.degree_ > degree_) resizeToDegree(other.degree_);
  for (size_t m = 0; m < other.coeffs_.size(); ++m) coeffs_[m] += other.coeffs_[m];
  trim();
  return *this;
}

Polynomial& Polynomial::operator-=(const Polynomial& other) {
  if (other.degree_ > degree_) resizeToDegree(other.degree_);
  for (size_t m = 0; m < other.coeffs_.size(); ++m) coeffs_[m] -= other.coeffs_[m];
  trim();
  return *this;
}

Polynomial& Polynomial::operator*=(double s) {
  for (double& c : coeffs_) c *= s;
  trim();
  return *this;
}

Polynomial operator*(const Polynomial& a, const Polynomial& b) {
  Polynomial r;
  if (a.isZero() || b.isZero()) return r;
  checkDegree(a.degree_ + b.degree_);
  r.resizeToDegree(a.degree_ + b.degree_);
  // Walk the non-zero terms of a against the non-zero terms of b: sparse inputs cost
  // what their non-zero terms cost even in dense storage.
  struct Term {
    int i, j, k;
    double c;
  };
  auto nonZero = [](const Polynomial& p) {
    std::vector<Term> t;
    for (int n = 0; n <= p.degree_; ++n)
      forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
        if (p.coeffs_[idx] != 0.0) t.push_back({i, j, k, p.coeffs_[idx]});
      });
    return t;
  };
  const auto ta = nonZero(a), tb = nonZero(b);
  for (const Term& s : ta)
    for (const Term& t : tb)
      r.coeffs_[Polynomial::index(s.i + t.i, s.j + t.j, s.k + t.k)] += s.c * t.c;
  r.trim();
  return r;
}

Polynomial Polynomial::pow(int exponent) const {
  if (exponent < 0) throw Error("negative exponent of a polynomial");
  if (exponent == 0) return Polynomial(1.0);
  // A constant's power is a number (the loop below would run `exponent` times); the
  // degree check in 64 bits (degree * exponent overflows int for exponents near 2^31).
  if (degree_ <= 0) return isZero() ? Polynomial() : Polynomial(std::pow(coeffs_[0], exponent));
  if (static_cast<long long>(degree_) * exponent > kMaxDegree)
    throw Error("polynomial degree " + std::to_string(static_cast<long long>(degree_) * exponent) +
                " exceeds the limit " + std::to_string(kMaxDegree));
  // Repeated multiplication by the base rather than binary powering: the product skips
  // zero terms, so multiplying by a sparse base costs nnz(acc) * nnz(base), whereas
  // squaring multiplies two dense intermediates. Measured in polynomial_bench
  // ((x+y+z+1)^40: 3.2 ms repeated vs 6.9 ms binary).
  Polynomial result = *this;
  for (int e = 1; e < exponent; ++e) result = result * *this;
  return result;
}

Polynomial Polynomial::derivative(int axis) const {
  checkAxis(axis);
  Polynomial r;
  if (degree_ <= 0) return r;
  r.resizeToDegree(degree_ - 1);
  for (int n = 1; n <= degree_; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      const int e = axis == 0 ? i : axis == 1 ? j : k;
      if (e == 0) return;
      r.coeffs_[index(i - (axis == 0), j - (axis == 1), k - (axis == 2))] = e * coeffs_[idx];
    });
  r.trim();
  return r;
}

Polynomial Polynomial::translate(const glm::dvec3& o) const {
  // f(o + u) by three univariate Taylor shifts, one per axis: for each fixed pair of
  // the other two exponents the polynomial in one variable is shifted in place. Cost
  // O(m^4) for degree m (versus O(m^6) for a general affine composition).
  if (degree_ <= 0) return *this;
  const int m = degree_;
  // Work in a cube array c[i][j][k] (i, j, k <= m) to make each shift a strided line.
  const int s = m + 1;
  std::vector<double> cube(static_cast<size_t>(s) * s * s, 0.0);
  auto at = [&](int i, int j, int k) -> double& {
    return cube[(static_cast<size_t>(i) * s + j) * s + k];
  };
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) { at(i, j, k) = coeffs_[idx]; });
  for (int j = 0; j <= m; ++j)
    for (int k = 0; j + k <= m; ++k)
      if (o.x != 0.0) taylorShift(&at(0, j, k), m - j - k, static_cast<std::ptrdiff_t>(s) * s, o.x);
  for (int i = 0; i <= m; ++i)
    for (int k = 0; i + k <= m; ++k)
      if (o.y != 0.0) taylorShift(&at(i, 0, k), m - i - k, s, o.y);
  for (int i = 0; i <= m; ++i)
    for (int j = 0; i + j <= m; ++j)
      if (o.z != 0.0) taylorShift(&at(i, j, 0), m - i - j, 1, o.z);
  Polynomial r;
  r.resizeToDegree(m);
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) { r.coeffs_[idx] = at(i, j, k); });
  r.trim();
  return r;
}

Polynomial Polynomial::composeAffine(const glm::dmat3& a, const glm::dvec3& b) const {
  if (a == glm::dmat3(1.0)) return translate(b);
  // Nested Horner in the ring of polynomials: f = sum_i X^i sum_j Y^j sum_k c_ijk Z^k with
  // X, Y, Z the affine images (row r of A p + b; glm is column-major, so a[c][r]).
  Polynomial lin[3];
  for (int r = 0; r < 3; ++r) {
    lin[r] = Polynomial(b[r]);
    for (int c = 0; c < 3; ++c) lin[r] += a[c][r] * variable(c);
  }
  const int m = degree_;
  Polynomial fx;
  for (int i = m; i >= 0; --i) {
    Polynomial fy;
    for (int j = m - i; j >= 0; --j) {
      Polynomial fz;
      for (int k = m - i - j; k >= 0; --k) fz = fz * lin[2] + Polynomial(coeff(i, j, k));
      fy = fy * lin[1] + fz;
    }
    fx = fx * lin[0] + fy;
  }
  return fx;
}

double Polynomial::evaluate(const glm::dvec3& p) const { return evaluateWithBound(p).value; }

glm::dvec3 Polynomial::gradient(const glm::dvec3& p) const { return evaluateWithBound(p).gradient; }

namespace {

// Whether denormals-are-zero is on (MXCSR bit 6; elsewhere assumed, which only costs time).
bool denormalsAreZero() {
#if defined(__SSE__)
  return (_mm_getcsr() & 0x40u) != 0;
#else
  return true;
#endif
}

}  // namespace

Polynomial::Evaluation Polynomial::evaluateWithBound(const glm::dvec3& p) const {
  Evaluation e;
  if (degree_ < 0) return e;
  const int m = degree_;
  double px[kMaxDegree + 1], py[kMaxDegree + 1], pz[kMaxDegree + 1];
  powers(p.x, m, px);
  powers(p.y, m, py);
  powers(p.z, m, pz);
  // Underflow (Higham, Eq. (2.8)): a product may also err by an absolute 2^-1075, which
  // the relative gamma below does not cover, and the later factors (a coefficient up to
  // 1e308) amplify it: 1e300 x^2 at x = 1e-170 lost every digit with a bound of 0. So
  // the bound runs each product on magnitudes plus kFloor (as HornerForm does): gamma_1
  // kFloor absorbs the absolute error of that product wherever it travels, 2^-1022 where
  // flush-to-zero is on (Embree's and TBB's workers): kFloor = 2^-966 (horner_form.cpp).
  // kFloor changes the bound only where the terms are below ~1e-285.
  constexpr double kFloor = 0x1p-966;
  double fx[kMaxDegree + 1], fy[kMaxDegree + 1], fz[kMaxDegree + 1];
  fx[0] = fy[0] = fz[0] = 1.0;
  for (int i = 1; i <= m; ++i) {
    fx[i] = fx[i - 1] * std::abs(p.x) + kFloor;
    fy[i] = fy[i - 1] * std::abs(p.y) + kFloor;
    fz[i] = fz[i - 1] * std::abs(p.z) + kFloor;
  }
  double sumAbsPartial = 0.0, floored = 0.0;
  int terms = 0;
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      const double c = coeffs_[idx];
      if (c == 0.0) return;
      const double yz = py[j] * pz[k];
      const double t = c * px[i] * yz;
      e.value += t;
      e.magnitude += std::abs(t);
      floored += (std::abs(c) * fx[i] + kFloor) * (fy[j] * fz[k] + kFloor) + kFloor;
      sumAbsPartial += std::abs(e.value);
      ++terms;
      if (i) e.gradient.x += c * i * px[i - 1] * yz;
      if (j) e.gradient.y += c * j * px[i] * py[j - 1] * pz[k];
      if (k) e.gradient.z += c * k * px[i] * py[j] * pz[k - 1];
    });
  // Each term is a product of at most m + 2 rounded factors (powers and the coefficient):
  // relative error gamma_{m+2} of the floored magnitude (which is >= |term|). Recursive
  // summation adds u |partial sum| per addition (running error bound, Higham Sec. 3.1;
  // sums are exact when they underflow). The final (1 + 2u) covers the rounding of the
  // bound itself.
  // Under flush-to-zero a partial sum below 2^-1022 becomes 0 too: one 2^-1022 per
  // addition, doubled for the bound's own sums.
  // Under DAZ a subnormal coefficient compares equal to 0 above and its term is lost: up
  // to 2^-1022 fx fy fz, which no relative bound covers (1e-310 x^3 at x = 1e50: 1e-160
  // with a bound of 0 until session 43). Added, once more 2^-1022 in case that product
  // flushes and doubled for the bound's own roundings, from a second pass over the
  // coefficients' bits that runs only with DAZ on (in the loop above it cost 5-7 % of the
  // sphere's evaluation, polynomial_bench BM_EvalOld).
  double flushed = 0.0;
  if (denormalsAreZero()) [[unlikely]]
    for (int n = 0; n <= m; ++n)
      forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
        const std::uint64_t bits = std::bit_cast<std::uint64_t>(coeffs_[idx]) << 1;
        if (bits != 0 && bits < std::uint64_t{1} << 53) flushed += fx[i] * (fy[j] * fz[k]);
      });
  e.valueError =
      (gamma(m + 2) * floored + kUnitRoundoff * sumAbsPartial +
       2.0 * terms * std::numeric_limits<double>::min() +
       (flushed > 0.0 ? 2.0 * (flushed + 1.0) * std::numeric_limits<double>::min() : 0.0)) *
      (1.0 + 2.0 * kUnitRoundoff);
  // A subnormal coordinate reads as 0 under DAZ: f at a point moved by eps < 2^-1022
  // per coordinate, within m sum|c| 2^-1022 max(1, |p_i|)^(m-1) of f(p) (see
  // HornerForm::evaluate); added, doubled, in that case only.
  if (ray_horner::hasSubnormal(p)) [[unlikely]] {
    double absSum = 0.0;
    for (const double c : coeffs_) absSum += std::abs(c);
    const int a = ray_horner::ceilExponent(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
    const int n = std::max(m, 1);
    e.valueError += 2.0 * n * absSum * ray_horner::pow2(a * (n - 1) - 1022);
  }
  return e;
}

double Polynomial::maxAbsCoeff() const {
  double m = 0.0;
  for (double c : coeffs_) m = std::max(m, std::abs(c));
  return m;
}

bool Polynomial::isFinite() const {
  return std::all_of(coeffs_.begin(), coeffs_.end(), [](double c) { return std::isfinite(c); });
}

int Polynomial::pruneBelow(std::span<const double> threshold) {
  int removed = 0;
  for (size_t m = 0; m < coeffs_.size() && m < threshold.size(); ++m)
    if (coeffs_[m] != 0.0 && std::abs(coeffs_[m]) <= threshold[m]) {
      coeffs_[m] = 0.0;
      ++removed;
    }
  trim();
  return removed;
}

int Polynomial::nonZeroCount() const {
  return static_cast<int>(
      std::count_if(coeffs_.begin(), coeffs_.end(), [](double c) { return c != 0.0; }));
}

std::string Polynomial::toString() const {
  if (degree_ < 0) return "0";
  std::string out;
  char buf[64];
  for (int n = degree_; n >= 0; --n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      const double c = coeffs_[idx];
      if (c == 0.0) return;
      std::snprintf(buf, sizeof buf, "%.17g", std::abs(c));
      out += out.empty() ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + ");
      out += buf;
      const int e[3] = {i, j, k};
      for (int a = 0; a < 3; ++a) {
        if (!e[a]) continue;
        out += '*';
        out += "xyz"[a];
        if (e[a] > 1) {
          out += '^';
          out += std::to_string(e[a]);
        }
      }
    });
  return out;
}

}  // namespace algray
