#include "algray/taylor.h"

#include <algorithm>
#include <cmath>

#include "ray_horner.h"

namespace algray {

namespace {

// Nested Horner of f(p + s d) in R[s] (Taylor-mode automatic differentiation along the
// ray):  g = sum_i X^i sum_j Y^j sum_k c_ijk Z^k,  X = p.x + s d.x, ...
// on values and magnitudes (ray_horner.h).
// Cost: about m^4/24 + m^3/3 multiply-adds (twice) for degree m.
using ray_horner::hornerStep;
using ray_horner::mulLinear;
using ray_horner::Pair;

// Degree as a template parameter (Yuksel's cyPolynomial style): with a compile-time
// degree every loop bound is known and the compiler unrolls the small ones; kDynamic
// reads the degree at run time.
constexpr int kDynamic = -1;

template <int M>
void nestedHorner(const double* c, int mRuntime, const glm::dvec3& p, const glm::dvec3& d,
                  double* g, double* mag) {
  const int m = M == kDynamic ? mRuntime : M;
  const Pair px = {p.x, std::abs(p.x)}, py = {p.y, std::abs(p.y)}, pz = {p.z, std::abs(p.z)};
  const Pair dx = {d.x, std::abs(d.x)}, dy = {d.y, std::abs(d.y)}, dz = {d.z, std::abs(d.z)};
  Pair gx[kMaxDegree + 2], fy[kMaxDegree + 2], fz[kMaxDegree + 2];
  for (int r = 0; r <= m; ++r) gx[r] = Pair{0.0, 0.0};
  // While G (or F) is still zero its product with X (or Y) is zero too and is skipped:
  // the Horner chain then starts at the highest non-zero power, so a sparse f costs far
  // less than m^4 / 24 (a separable f = p(x) + q(y) + r(z), like Chmutov's, O(m^2)).
  bool gxZero = true;
  for (int i = m; i >= 0; --i) {
    // G <- G * X (degree m - i - 1 -> m - i).
    if (i < m && !gxZero) mulLinear(gx, m - i - 1, px, dx);
    for (int r = 0; r <= m - i; ++r) fy[r] = Pair{0.0, 0.0};
    bool fyZero = true;
    for (int j = m - i; j >= 0; --j) {
      // F <- F * Y (degree m - i - j - 1 -> m - i - j).
      if (j < m - i && !fyZero) mulLinear(fy, m - i - j - 1, py, dy);
      // H = sum_k c_ijk Z^k by Horner; leading zero coefficients are skipped, so sparse
      // columns cost nothing.
      int degH = -1;
      for (int k = m - i - j; k >= 0; --k) hornerStep(fz, degH, c[Polynomial::index(i, j, k)], pz, dz);
      for (int r = 0; r <= degH; ++r) fy[r] += fz[r];
      fyZero = fyZero && degH < 0;
    }
    if (fyZero) continue;
    for (int r = 0; r <= m - i; ++r) gx[r] += fy[r];
    gxZero = false;
  }
  for (int r = 0; r <= m; ++r) {
    g[r] = gx[r][0];
    mag[r] = gx[r][1];
  }
}

// H_n(d) for every n: the homogeneous blocks of `poly` evaluated at d (Eq. 4.4 of the
// seed paper: g_n = H_n(d)). Within block n the coefficients are ordered by (j + k, k),
// so with the triangle YZ[(j+k)(j+k+1)/2 + k] = d.y^j d.z^k, shared by all blocks,
//   H_n(d) = sum_{jk <= n} d.x^(n - jk) * <c_n segment jk, YZ segment jk>,
// two contiguous dot products per segment: about 2 flops per term.
void evaluateHomogeneousParts(const Polynomial& poly, const glm::dvec3& d, double* out) {
  const int m = poly.degree();
  double px[kMaxDegree + 1], py[kMaxDegree + 1], pz[kMaxDegree + 1];
  px[0] = py[0] = pz[0] = 1.0;
  for (int i = 1; i <= m; ++i) {
    px[i] = px[i - 1] * d.x;
    py[i] = py[i - 1] * d.y;
    pz[i] = pz[i - 1] * d.z;
  }
  double yz[(kMaxDegree + 1) * (kMaxDegree + 2) / 2];
  for (int jk = 0, idx = 0; jk <= m; ++jk)
    for (int k = 0; k <= jk; ++k) yz[idx++] = py[jk - k] * pz[k];
  const double* c = poly.coeffs().data();
  for (int n = 0; n <= m; ++n) {
    double sum = 0.0;
    const double* w = yz;
    for (int jk = 0; jk <= n; ++jk) {
      // Two accumulators break the dependency chain of the dot product.
      double s0 = 0.0, s1 = 0.0;
      int k = 0;
      for (; k + 1 <= jk; k += 2) {
        s0 += c[k] * w[k];
        s1 += c[k + 1] * w[k + 1];
      }
      if (k == jk) s0 += c[k] * w[k];
      sum += px[n - jk] * (s0 + s1);
      c += jk + 1;
      w += jk + 1;
    }
    out[n] = sum;
  }
}

}  // namespace

double RayPolynomial::evaluate(double s) const {
  double v = 0.0;
  for (int i = degree; i >= 0; --i) v = v * s + coeff[i];
  return v;
}

double RayPolynomial::evaluateWithBound(double s, double& bound) const {
  // Horner's rounding, gamma_{2n} sum |c_i||s|^i (Higham Eq. (5.3)), plus the propagated
  // coefficient errors sum err_i |s|^i; the last factor covers rounding of the bound.
  double v = 0.0, mag = 0.0, err = 0.0;
  const double as = std::abs(s);
  for (int i = degree; i >= 0; --i) {
    v = v * s + coeff[i];
    mag = mag * as + std::abs(coeff[i]);
    err = err * as + error[i];
  }
  bound = (gamma(2 * degree + 1) * mag + err) * (1.0 + gamma(2 * degree + 2));
  return v;
}

double closestParameter(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& c) {
  const double dd = glm::dot(d, d);
  return dd > 0.0 ? glm::dot(c - o, d) * inverseSquaredLength(dd) : 0.0;
}

RayPolynomial restrictToRay(const Polynomial& f, const glm::dvec3& o, const glm::dvec3& d,
                            double tShift) {
  RayPolynomial g;
  g.tShift = tShift;
  if (f.isZero()) return g;
  const glm::dvec3 p = tShift == 0.0 ? o : o + tShift * d;
  double mag[kMaxDegree + 1];
  const double* c = f.coeffs().data();
  switch (f.degree()) {  // measured in tests/bench/taylor_bench (BM_RestrictToRay)
    case 1: nestedHorner<1>(c, 1, p, d, g.coeff.data(), mag); break;
    case 2: nestedHorner<2>(c, 2, p, d, g.coeff.data(), mag); break;
    case 3: nestedHorner<3>(c, 3, p, d, g.coeff.data(), mag); break;
    case 4: nestedHorner<4>(c, 4, p, d, g.coeff.data(), mag); break;
    case 5: nestedHorner<5>(c, 5, p, d, g.coeff.data(), mag); break;
    case 6: nestedHorner<6>(c, 6, p, d, g.coeff.data(), mag); break;
    default: nestedHorner<kDynamic>(c, f.degree(), p, d, g.coeff.data(), mag); break;
  }
  // Every coefficient of g is reached through at most m linear-factor steps, each one
  // multiply and at most two additions, plus the coefficient itself: gamma_{3m+3} times
  // the same computation on absolute values bounds the rounding (Higham Sec. 5.1 applied
  // level by level). The abs computation itself rounds too: the final factor covers it.
  const int m = f.degree();
  const double factor = gamma(3 * m + 3) * (1.0 + gamma(3 * m + 3));
  g.degree = m;
  for (int i = 0; i <= m; ++i) g.error[i] = factor * mag[i];
  return g;
}

OriginExpansion::OriginExpansion(const Polynomial& f, const glm::dvec3& o)
    : origin_(o), shifted_(f.translate(o)) {
  // Error of the shift: three univariate Taylor shifts by synthetic division, each
  // componentwise within gamma_{2m} of the same shift applied to |c| by |o_axis|
  // (Higham Sec. 5.1); composed: gamma_{6m}. Then H_n(d) adds at most n + 1 + N_n
  // roundings per term (powers, products, summation over the N_n terms of block n).
  // Both fold into per-term weights w_m with |error of H_n(d)| <= sum_m w_m |d^m|.
  // Since |d^m| <= max|d_i|^n for every monomial of degree n, the per-block sums
  // W_n = sum_{m in block n} w_m give the rigorous bound W_n max|d_i|^n at O(1) per
  // coefficient (looser than sum w_m |d^m| by at most the block size, which only
  // matters for tangent decisions at the rounding level).
  const int m = shifted_.degree();
  if (m < 0) return;

  // Kernel choice by measurement (tests/bench/taylor_bench, BM_GalleryShifted): a term of
  // the dense segment dot products costs about 1.2-1.7 ns, a term of a sparse list about
  // 3.5 ns. Translation keeps symmetric and separable surfaces sparse (Chmutov-16 about a
  // camera: 49 of 969 terms) while general ones fill in (Barth decic: 225 of 286), so
  // the sparse list is used when it has under 40% of the dense terms.
  const int nonZero = shifted_.nonZeroCount();
  if (5 * nonZero < 2 * Polynomial::termCount(m)) {
    for (int n = 0; n <= m; ++n)
      forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
        const double c = shifted_.coeffs()[idx];
        if (c != 0.0) sparseTerms_.push_back({c, n, i, j, k});
      });
  }

  Polynomial absF;
  for (int n = 0; n <= f.degree(); ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      absF.setCoeff(i, j, k, std::abs(f.coeffs()[idx]));
    });
  const Polynomial absShift = absF.translate(glm::abs(o));
  const double shiftFactor = gamma(6 * m + 6) * (1.0 + gamma(6 * m + 6));
  for (int n = 0; n <= m; ++n) {
    const int blockSize = (n + 1) * (n + 2) / 2;
    const double evalFactor = gamma(n + 2 + blockSize);
    double w = 0.0;
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int) {
      w += shiftFactor * absShift.coeff(i, j, k) + evalFactor * std::abs(shifted_.coeff(i, j, k));
    });
    blockErrorWeight_[n] = w * (1.0 + gamma(blockSize + 2));
  }
}

RayPolynomial OriginExpansion::restrict(const glm::dvec3& d, bool withError) const {
  RayPolynomial g;
  restrict(d, g, withError);
  return g;
}

void OriginExpansion::restrict(const glm::dvec3& d, RayPolynomial& g, bool withError) const {
  g.degree = shifted_.degree();
  g.tShift = 0.0;
  if (g.degree < 0) return;
  std::fill_n(g.error.begin(), g.degree + 1, 0.0);
  if (sparseTerms_.empty()) {
    evaluateHomogeneousParts(shifted_, d, g.coeff.data());
  } else {
    double px[kMaxDegree + 1], py[kMaxDegree + 1], pz[kMaxDegree + 1];
    px[0] = py[0] = pz[0] = 1.0;
    for (int i = 1; i <= g.degree; ++i) {
      px[i] = px[i - 1] * d.x;
      py[i] = py[i - 1] * d.y;
      pz[i] = pz[i - 1] * d.z;
    }
    std::fill_n(g.coeff.begin(), g.degree + 1, 0.0);
    for (const SparseTerm& t : sparseTerms_) g.coeff[t.n] += t.c * px[t.i] * (py[t.j] * pz[t.k]);
  }
  if (withError) {
    const double dmax = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    double dn = 1.0;
    for (int n = 0; n <= g.degree; ++n, dn *= dmax)
      g.error[n] = blockErrorWeight_[n] * dn * (1.0 + gamma(n + 2));
  }
  while (g.degree > 0 && g.coeff[g.degree] == 0.0 && g.error[g.degree] == 0.0) --g.degree;
}

}  // namespace algray
