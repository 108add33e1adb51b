// Centred-form range enclosures over boxes (see range_bound.h for the method and its
// references).
#include "algray/range_bound.h"

#include "gradual_underflow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace algray {

namespace {

// ---- Univariate Taylor shift ---------------------------------------------------------
// a[0..n] := coefficients of p(x + delta), by repeated synthetic division (Horner's
// scheme applied n times; Knuth, TAOCP vol. 2, Sec. 4.6.4; von zur Gathen & Gerhard,
// "Fast algorithms for Taylor shifts and certain difference equations", 1997, method "H").
// In interval arithmetic each a[j] + delta a[j+1] is enclosed, so the result encloses the
// exact shift of every polynomial with coefficients in the inputs.
void taylorShift(Interval* a, int n, double delta) {
  for (int i = 0; i < n; ++i)
    for (int j = n - 1; j >= i; --j) a[j] += a[j + 1] * delta;
}

}  // namespace

// ---- Index tables ----------------------------------------------------------------------
// (A degree outside 0..kMaxDegree threw std::length_error from a vector's size, or worse.)
static int checkedDegree(int m) {
  if (m < 0 || m > kMaxDegree)
    throw Error("MonomialTables: degree " + std::to_string(m) + " outside 0.." +
                std::to_string(kMaxDegree));
  return m;
}

MonomialTables::MonomialTables(int m) : degree(checkedDegree(m)), terms(Polynomial::termCount(m)) {
  for (int e = 0; e <= kMaxDegree; ++e) halfPow[e] = std::ldexp(1.0, -e);
  for (auto& e : exponent) e.assign(terms, 0);
  allEven.assign(terms, 0);
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      exponent[0][idx] = i;
      exponent[1][idx] = j;
      exponent[2][idx] = k;
      allEven[idx] = (i % 2 == 0 && j % 2 == 0 && k % 2 == 0) ? 1 : 0;
    });
  // Columns: fix the two other exponents (p, q), run the exponent e of axis a upwards.
  for (int a = 0; a < 3; ++a) {
    for (int p = 0; p <= m; ++p)
      for (int q = 0; p + q <= m; ++q) {
        columnStart[a].push_back(static_cast<int>(columnIndex[a].size()));
        for (int e = 0; p + q + e <= m; ++e) {
          const int idx = a == 0   ? Polynomial::index(e, p, q)
                          : a == 1 ? Polynomial::index(p, e, q)
                                   : Polynomial::index(p, q, e);
          columnIndex[a].push_back(idx);
        }
      }
    columnStart[a].push_back(static_cast<int>(columnIndex[a].size()));
  }
}

long MonomialTables::splitCost() const {
  long cost = terms;  // the scaling by 2^-e
  for (std::size_t c = 0; c + 1 < columnStart[0].size(); ++c) {
    const long n = columnStart[0][c + 1] - columnStart[0][c] - 1;  // column degree
    cost += n * (n + 1) / 2;
  }
  return cost;
}

long MonomialTables::bernsteinCost() const {
  const long n1 = degree + 1;
  return 3 * n1 * n1 * n1 * (n1 + 1) / 2 + 3 * splitCost();  // conversion + the w = 2t - 1 step
}

// ---- BoxPolynomial ---------------------------------------------------------------------
BoxPolynomial::BoxPolynomial(const Polynomial& f, const glm::dvec3& c, const glm::dvec3& h,
                             const MonomialTables& tables)
    : tables_(&tables) {
  const MonomialTables& t = *tables_;
  coeffs_.assign(t.terms, Interval());
  const auto fc = f.coeffs();
  for (std::size_t i = 0; i < fc.size() && i < coeffs_.size(); ++i) coeffs_[i] = Interval(fc[i]);

  // Step 1: f(c + u), one axis at a time (the shift along x commutes with those along y, z).
  // Step 2: u = h*w, i.e. the coefficient of w_a^e gains h_a^e (powers enclosed upwards).
  std::vector<Interval> col(t.degree + 1);
  std::vector<Interval> hPow(t.degree + 1);
  for (int a = 0; a < 3; ++a) {
    hPow[0] = Interval(1.0);
    for (int e = 1; e <= t.degree; ++e) hPow[e] = hPow[e - 1] * h[a];
    for (std::size_t s = 0; s + 1 < t.columnStart[a].size(); ++s) {
      const int begin = t.columnStart[a][s], n = t.columnStart[a][s + 1] - begin - 1;
      for (int e = 0; e <= n; ++e) col[e] = coeffs_[t.columnIndex[a][begin + e]];
      if (c[a] != 0.0) taylorShift(col.data(), n, c[a]);
      for (int e = 0; e <= n; ++e) coeffs_[t.columnIndex[a][begin + e]] = col[e] * hPow[e];
    }
  }
}

void BoxPolynomial::half(int axis, int side, BoxPolynomial& out) const {
  const MonomialTables& t = *tables_;
  out.tables_ = tables_;
  out.coeffs_.resize(coeffs_.size());
  Interval col[kMaxDegree + 1];
  const double delta = side < 0 ? -0.5 : 0.5;
  for (std::size_t s = 0; s + 1 < t.columnStart[axis].size(); ++s) {
    const int begin = t.columnStart[axis][s], n = t.columnStart[axis][s + 1] - begin - 1;
    const int* idx = t.columnIndex[axis].data() + begin;
    for (int e = 0; e <= n; ++e) col[e] = coeffs_[idx[e]];
    taylorShift(col, n, delta);
    // 2^-e is exact; the product only rounds on underflow, and Interval widens anyway.
    out.coeffs_[idx[0]] = col[0];
    for (int e = 1; e <= n; ++e) out.coeffs_[idx[e]] = col[e] * t.halfPow[e];
  }
}

void BoxPolynomial::subBox(const glm::dvec3& centre, const int splits[3],
                           BoxPolynomial& out) const {
  const MonomialTables& t = *tables_;
  out.tables_ = tables_;
  out.coeffs_ = coeffs_;
  Interval col[kMaxDegree + 1];
  for (int a = 0; a < 3; ++a) {
    if (centre[a] == 0.0 && splits[a] == 0) continue;
    for (std::size_t s = 0; s + 1 < t.columnStart[a].size(); ++s) {
      const int begin = t.columnStart[a][s], n = t.columnStart[a][s + 1] - begin - 1;
      const int* idx = t.columnIndex[a].data() + begin;
      for (int e = 0; e <= n; ++e) col[e] = out.coeffs_[idx[e]];
      if (centre[a] != 0.0) taylorShift(col, n, centre[a]);
      for (int e = 0; e <= n; ++e) {
        // 2^-(e splits) in factors of at most 2^-1000: beyond 2^-1074 the power itself
        // would round to 0 and make the product an exact 0, although the coefficient times
        // it need not even be subnormal (h^40 of a large box times 2^-1160 is ~1e-81).
        // (One product at least, as before, when the power is a normal double.)
        Interval scaled = col[e];
        int left = e * splits[a];
        do {
          const int step = std::min(left, 1000);
          scaled = scaled * std::ldexp(1.0, -step);
          left -= step;
        } while (left > 0);
        out.coeffs_[idx[e]] = scaled;
      }
    }
  }
}

BoxPolynomial BoxPolynomial::half(int axis, int side) const {
  BoxPolynomial out;
  half(axis, side, out);
  return out;
}

Interval BoxPolynomial::range() const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (coeffs_.empty()) return Interval(0.0);
  const MonomialTables& t = *tables_;
  double lo = coeffs_[0].lower(), hi = coeffs_[0].upper();
  for (std::size_t i = 1; i < coeffs_.size(); ++i) {
    const Interval& c = coeffs_[i];
    // A non-finite coefficient (overflow) proves nothing: the whole line.
    if (!c.isFinite()) return Interval(-kInf, kInf);
    if (t.allEven[i]) {  // monomial in [0, 1]
      lo = nextDown(lo + std::min(0.0, c.lower()));
      hi = nextUp(hi + std::max(0.0, c.upper()));
    } else {  // monomial in [-1, 1]
      const double m = c.magnitude();
      lo = nextDown(lo - m);
      hi = nextUp(hi + m);
    }
  }
  if (std::isnan(lo) || std::isnan(hi)) return Interval(-kInf, kInf);
  return Interval(lo, hi);
}

Interval BoxPolynomial::rangeBernstein() const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const MonomialTables& t = *tables_;
  const int m = t.degree;
  if (m <= 0 || coeffs_.empty()) return range();
  for (const Interval& c : coeffs_)
    if (!c.isFinite()) return Interval(-kInf, kInf);
  // ---- Step 1: w = 2t - 1 per axis (shift by -1, then the coefficient of t^e gains 2^e).
  std::vector<Interval> a = coeffs_;
  Interval col[kMaxDegree + 1];
  for (int ax = 0; ax < 3; ++ax)
    for (std::size_t s = 0; s + 1 < t.columnStart[ax].size(); ++s) {
      const int begin = t.columnStart[ax][s], n = t.columnStart[ax][s + 1] - begin - 1;
      const int* idx = t.columnIndex[ax].data() + begin;
      for (int e = 0; e <= n; ++e) col[e] = a[idx[e]];
      taylorShift(col, n, -1.0);
      for (int e = 0; e <= n; ++e) a[idx[e]] = col[e] * std::ldexp(1.0, e);
    }
  // ---- Step 2: the tensor cube (m+1)^3, zero beyond total degree m.
  const int n1 = m + 1;
  std::vector<Interval> cube(static_cast<std::size_t>(n1) * n1 * n1);
  auto at = [&](int i, int j, int k) -> Interval& {
    return cube[(static_cast<std::size_t>(i) * n1 + j) * n1 + k];
  };
  for (int i = 0; i <= m; ++i)
    for (int j = 0; i + j <= m; ++j)
      for (int k = 0; i + j + k <= m; ++k) at(i, j, k) = a[Polynomial::index(i, j, k)];
  // ---- Step 3: power -> Bernstein along each axis; ratios C(K, i) / C(m, i) enclosed
  // (binomials up to C(40, 20) ~ 1.4e11 are exact doubles; the quotient is widened).
  std::vector<Interval> ratio(static_cast<std::size_t>(n1) * n1);
  {
    std::vector<double> binom(static_cast<std::size_t>(n1) * n1, 0.0);
    for (int r = 0; r <= m; ++r) {
      binom[r * n1] = 1.0;
      for (int q = 1; q <= r; ++q)  // Pascal's rule, exact for m <= 40
        binom[r * n1 + q] = binom[(r - 1) * n1 + q - 1] + (q < r ? binom[(r - 1) * n1 + q] : 0.0);
    }
    for (int K = 0; K <= m; ++K)
      for (int i = 0; i <= K; ++i)
        ratio[K * n1 + i] = Interval::fromValueAndError(binom[K * n1 + i] / binom[m * n1 + i], 0.0);
  }
  Interval line[kMaxDegree + 1];
  for (int ax = 0; ax < 3; ++ax)
    for (int p = 0; p <= m; ++p)
      for (int q = 0; q <= m; ++q) {
        auto ref = [&](int e) -> Interval& {
          return ax == 0 ? at(e, p, q) : ax == 1 ? at(p, e, q) : at(p, q, e);
        };
        for (int e = 0; e <= m; ++e) line[e] = ref(e);
        for (int K = m; K >= 0; --K) {
          Interval b = line[0];  // ratio[K][0] = 1
          for (int i = 1; i <= K; ++i) b += line[i] * ratio[K * n1 + i];
          ref(K) = b;
        }
      }
  double lo = kInf, hi = -kInf;
  for (const Interval& b : cube) {
    if (std::isnan(b.lower()) || std::isnan(b.upper())) return Interval(-kInf, kInf);
    lo = std::min(lo, b.lower());
    hi = std::max(hi, b.upper());
  }
  if (std::isnan(lo) || std::isnan(hi)) return Interval(-kInf, kInf);
  return Interval(lo, hi);
}

bool BoxPolynomial::provablyNonZero() const {
  const Interval r = range();
  return r.lower() > 0.0 || r.upper() < 0.0;
}

// ---- One box ---------------------------------------------------------------------------
double halfWidth(double lo, double c, double hi) {
  // x - y == 0 exactly iff x == y (gradual underflow), so a flat axis keeps h = 0 and
  // is never split; otherwise one ulp up covers the rounding of the subtraction.
  const double h = std::max(hi - c, c - lo);
  return h > 0 ? nextUp(h) : 0.0;
}

Interval rangeOverBox(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
                      RangeBound bound) {
  const GradualUnderflow gradual;  // interval arithmetic (gradual_underflow.h)
  if (!f.isFinite()) throw Error("rangeOverBox: polynomial has non-finite coefficients");
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]))
      throw Error("rangeOverBox: non-finite box bound on axis " + std::to_string(a));
    if (lo[a] > hi[a])
      throw Error("rangeOverBox: empty box (lo > hi) on axis " + std::to_string(a));
  }
  glm::dvec3 c, h;
  for (int a = 0; a < 3; ++a) {
    c[a] = 0.5 * lo[a] + 0.5 * hi[a];
    h[a] = halfWidth(lo[a], c[a], hi[a]);
  }
  const MonomialTables tables(std::max(f.degree(), 0));
  const BoxPolynomial box(f, c, h, tables);
  const Interval r = box.range();
  if (bound == RangeBound::Centred) return r;
  // Both enclose the range: so does their intersection (non-empty: it holds the range).
  const Interval b = box.rangeBernstein();
  return Interval(std::max(r.lower(), b.lower()), std::min(r.upper(), b.upper()));
}

// ---- Univariate ------------------------------------------------------------------------
namespace {
// Beyond degree 40 the terms above it were dropped without a word (s^41 - 1 on [0, 2]:
// "no root"); refused as firstRoot refuses it.
void checkDegree(std::span<const double> c, const char* where) {
  if (c.size() > static_cast<std::size_t>(kMaxDegree + 1)) [[unlikely]]
    throw Error(std::string(where) + ": " + std::to_string(c.size()) +
                " coefficients, more than degree kMaxDegree = " + std::to_string(kMaxDegree) +
                " allows");
}
}  // namespace

Interval rangeOverInterval(std::span<const double> c, std::span<const double> err, double lo,
                           double hi) {
  checkDegree(c, "rangeOverInterval");
  const GradualUnderflow gradual;  // interval arithmetic (gradual_underflow.h)
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const Interval whole(-kInf, kInf);
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) return whole;  // also NaN
  const int n = static_cast<int>(std::min<std::size_t>(c.size(), kMaxDegree + 1)) - 1;
  if (n < 0) return Interval(0.0);
  Interval b[kMaxDegree + 1];
  for (int i = 0; i <= n; ++i) {
    const double e = i < static_cast<int>(err.size()) ? err[i] : 0.0;
    if (!std::isfinite(c[i]) || !std::isfinite(e)) return whole;
    b[i] = e > 0 ? Interval::fromValueAndError(c[i], e) : Interval(c[i]);
  }
  const double mid = 0.5 * lo + 0.5 * hi;
  const double r = halfWidth(lo, mid, hi);
  if (mid != 0.0) taylorShift(b, n, mid);
  // b_0 + sum_k b_k u^k, u in [-r, r]: u^k in [0, r^k] (k even) or [-r^k, r^k] (k odd).
  double rk = 1.0, loSum = b[0].lower(), hiSum = b[0].upper();
  for (int k = 1; k <= n; ++k) {
    rk = nextUp(rk * r);
    const Interval term =
        k % 2 == 0 ? b[k] * Interval(0.0, rk) : Interval(-b[k].magnitude(), b[k].magnitude()) * rk;
    loSum = nextDown(loSum + term.lower());
    hiSum = nextUp(hiSum + term.upper());
  }
  if (std::isnan(loSum) || std::isnan(hiSum)) return whole;
  return Interval(loSum, hiSum);
}

bool quickNoRoot(std::span<const double> c, std::span<const double> err, double lo, double hi) {
  checkDegree(c, "quickNoRoot");
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) return false;
  const int n = static_cast<int>(std::min<std::size_t>(c.size(), kMaxDegree + 1)) - 1;
  if (n < 0) return false;  // the zero polynomial vanishes everywhere
  const double mid = 0.5 * lo + 0.5 * hi;
  const double r = halfWidth(lo, mid, hi);
  const double x0 = std::abs(mid), x1 = nextUp(x0 + r);
  // v = g(mid); a = M(x1), b = M(x0) on the exact |c_i| + err_i; e = sum err_i x0^i;
  // w = sum_{i < n} max(1, x1)^i, the underflow weight below.
  const double xw = std::max(1.0, x1);
  double v = 0, a = 0, b = 0, e = 0, w = 0;
  for (int i = n; i >= 0; --i) {
    const double ei = i < static_cast<int>(err.size()) ? err[i] : 0.0;
    const double m = std::abs(c[i]) + ei;  // rounded: covered by the gamma factors below
    v = v * mid + c[i];
    a = a * x1 + m;
    b = b * x0 + m;
    e = e * x0 + ei;
    if (i > 0) w = w * xw + 1.0;
  }
  // Each Horner result of non-negative terms is within gamma(2n + 2) relatively of the
  // exact one (Higham Eq. (5.3), one more rounding for |c_i| + err_i); the signed v is
  // within gamma(2n) M(x0) of g(mid) plus the coefficient errors e.
  // Underflow (Higham Eq. (2.8)): a product may also err by an absolute 2^-1075, which no
  // relative gamma covers (g = 2^-1074 (8 s - 7) on [0.86, 2.56] has the root 7/8, yet
  // its subnormal values once "proved" none). Step i's error reaches the result times
  // |t|^i <= max(1, x1)^i for each of the four schemes, so all of them together err by at
  // most 4 * 2^-1075 w (1 + g) absolutely, and the few operations of the bound itself by
  // a handful of 2^-1075 more: 3 * 2^-1074 (w + 2) covers both. Threads that flush
  // subnormal results to zero (Embree's and TBB's workers set FTZ/DAZ) err by up to
  // 2^-1022 per operation instead, so the same count is taken in units of 2^-1022: still
  // far below any normal value the test compares.
  const double g = gamma(2 * n + 2);
  const double underflow = 3.0 * std::numeric_limits<double>::min() * (w + 2.0);
  const double bound = (1 + g) * a - (1 - g) * b + g * b + (1 + g) * e + underflow;
  // The bound's own few operations: one more relative gamma(4).
  return std::abs(v) > bound * (1 + gamma(4));  // false for NaN
}

}  // namespace algray
