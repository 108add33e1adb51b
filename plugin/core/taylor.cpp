#include "algray/taylor.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

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
      for (int k = m - i - j; k >= 0; --k)
        hornerStep(fz, degH, c[Polynomial::index(i, j, k)], pz, dz);
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

// Polynomial::translate's three Taylor shifts on magnitudes: |f| shifted by a = |o| >= 0
// with phi added to every coefficient slot first and to every result of the synthetic
// division (c_i <- c_i + a c_(i+1) + phi); graded layout of f's degree.
std::vector<double> flooredAbsShift(const Polynomial& f, const glm::dvec3& a, double phi) {
  const int m = f.degree(), s = m + 1;
  std::vector<double> cube(static_cast<std::size_t>(s) * s * s, 0.0);
  auto at = [&](int i, int j, int k) -> double& {
    return cube[(static_cast<std::size_t>(i) * s + j) * s + k];
  };
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(
        n, [&](int i, int j, int k, int idx) { at(i, j, k) = std::abs(f.coeffs()[idx]) + phi; });
  auto shift = [phi](double* c, int deg, std::ptrdiff_t stride, double x) {
    for (int k = 0; k < deg; ++k)
      for (int i = deg - 1; i >= k; --i)
        c[i * stride] = c[i * stride] + x * c[(i + 1) * stride] + phi;
  };
  for (int j = 0; j <= m; ++j)
    for (int k = 0; j + k <= m; ++k)
      if (a.x != 0.0) shift(&at(0, j, k), m - j - k, static_cast<std::ptrdiff_t>(s) * s, a.x);
  for (int i = 0; i <= m; ++i)
    for (int k = 0; i + k <= m; ++k)
      if (a.y != 0.0) shift(&at(i, 0, k), m - i - k, s, a.y);
  for (int i = 0; i <= m; ++i)
    for (int j = 0; i + j <= m; ++j)
      if (a.z != 0.0) shift(&at(i, j, 0), m - i - j, 1, a.z);
  std::vector<double> out(Polynomial::termCount(m));
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) { out[idx] = at(i, j, k); });
  return out;
}

// sum |c| over f's coefficients in the order of HornerForm's box (i, j, k descending), so
// that both direct paths take the same bound (HornerForm::absCoeffSum adds its slots in
// that order).
double absSumInBoxOrder(const Polynomial& f) {
  double sum = 0.0;
  const int m = f.degree();
  for (int i = m; i >= 0; --i)
    for (int j = m - i; j >= 0; --j)
      for (int k = m - i - j; k >= 0; --k) sum += std::abs(f.coeff(i, j, k));
  return sum;
}

}  // namespace

namespace {
// RayPolynomial's fields are public: a degree beyond its arrays read past them (session 45
// stated the range; one compare per evaluation checks it).
[[noreturn, gnu::noinline, gnu::cold]] void throwRayDegree(int degree) {
  throw Error("RayPolynomial: degree " + std::to_string(degree) +
              " beyond kMaxDegree = " + std::to_string(kMaxDegree));
}
}  // namespace

double RayPolynomial::evaluate(double s) const {
  if (degree > kMaxDegree) [[unlikely]]
    throwRayDegree(degree);
  double v = 0.0;
  for (int i = degree; i >= 0; --i) v = v * s + coeff[i];
  return v;
}

namespace {

// RayPolynomial::evaluateWithBound, with g'(s) from the same pass where kSlope (off the
// value's dependency chain, but not free: the plain form skips it).
template <bool kSlope>
double evaluateRay(const RayPolynomial& g, double s, double& bound, double& slope) {
  // Horner's rounding, gamma_{2n} sum |c_i||s|^i (Higham Eq. (5.3)), plus the propagated
  // coefficient errors sum err_i |s|^i; the last factor covers rounding of the bound.
  // Underflow (see restrictToRay below): each step's product and sum may also err by an
  // absolute eta < 2^-1022 (flush-to-zero), which reaches v times |s|^i for the i steps
  // after it, and the magnitudes' and errors' own steps lose as much: 4 * 2^-1022 w,
  // w = sum_i max(1, |s|)^i, covers them (the bound's small terms flushed to 0 before:
  // 1e-300 s at s = 1e-6 had the bound 0).
  if (g.degree > kMaxDegree) [[unlikely]]
    throwRayDegree(g.degree);
  double v = 0.0, mag = 0.0, err = 0.0, w = 0.0;
  const double as = std::abs(s), aw = std::max(1.0, as);
  slope = 0.0;
  for (int i = g.degree; i >= 0; --i) {
    if constexpr (kSlope) slope = slope * s + v;
    v = v * s + g.coeff[i];
    mag = mag * as + std::abs(g.coeff[i]);
    err = err * as + g.error[i];
    w = w * aw + 1.0;
  }
  bound = (gamma(2 * g.degree + 1) * mag + err + 4.0 * std::numeric_limits<double>::min() * w) *
          (1.0 + gamma(2 * g.degree + 2));
  return v;
}

}  // namespace

double RayPolynomial::evaluateWithBound(double s, double& bound) const {
  double slope;
  return evaluateRay<false>(*this, s, bound, slope);
}

double RayPolynomial::evaluateWithBound(double s, double& bound, double& slope) const {
  return evaluateRay<true>(*this, s, bound, slope);
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
    case 1:
      nestedHorner<1>(c, 1, p, d, g.coeff.data(), mag);
      break;
    case 2:
      nestedHorner<2>(c, 2, p, d, g.coeff.data(), mag);
      break;
    case 3:
      nestedHorner<3>(c, 3, p, d, g.coeff.data(), mag);
      break;
    case 4:
      nestedHorner<4>(c, 4, p, d, g.coeff.data(), mag);
      break;
    case 5:
      nestedHorner<5>(c, 5, p, d, g.coeff.data(), mag);
      break;
    case 6:
      nestedHorner<6>(c, 6, p, d, g.coeff.data(), mag);
      break;
    default:
      nestedHorner<kDynamic>(c, f.degree(), p, d, g.coeff.data(), mag);
      break;
  }
  // Every coefficient of g is reached through at most m linear-factor steps, each one
  // multiply and at most two additions, plus the coefficient itself: gamma_{3m+3} times
  // the same computation on absolute values bounds the rounding (Higham Sec. 5.1 applied
  // level by level). The abs computation itself rounds too: the final factor covers it.
  //
  // Underflow. The relative model above misses the absolute error eta of a result below
  // double's normal range (Higham Eq. (2.8)): |eta| <= 2^-1075 for a product with gradual
  // underflow, and |eta| < 2^-1022 for any product or sum where flush-to-zero is on
  // (Embree's and TBB's worker threads set FTZ and DAZ), where a subnormal operand also
  // reads as 0. Coefficients ~1e-300 times small powers of the ray lost every digit with
  // a bound 15 orders of magnitude too small. Every operation here multiplies by a
  // constant (p_a or d_a) or adds, so g is linear in the coefficients and in the etas:
  // each eta reaches g_r through the operations after it, i.e. times a coefficient of a
  // product of k linear factors (|p_a| + s |d_a|) <= (P + s D), P = max(1, |p_a|),
  // D = max(1, |d_a|), entering at a position r0 no higher than its accumulator's degree,
  // which plus k is at most m (every path ends in a monomial of degree <= m). Reaching r
  // takes l = r - r0 of the factors' s-terms and k - l <= m - r of their constants:
  // at most C(m, r) P^(m-r) D^r, times (1 + gamma) for the roundings after it.
  // The operations: at most 4m + 3 per Horner step (a step multiplies an accumulator of
  // degree <= m by a linear factor and adds), and at most termCount(m) + (m+1)(m+2)/2 +
  // (m+1) <= termCount(m + 1) steps (slots, rows, blocks), so N <= 4(m+2) termCount(m+1),
  // each eta < 2^-1022 (a subnormal coefficient read as 0 is one more per slot). The
  // magnitudes' own etas make mag smaller by the same kind of amount times the factor
  // above, < 1/2. So 4 N C(m, r) P^(m-r) D^r 2^-1022 bounds them all, with P, D rounded
  // up to powers of two 2^a, 2^b: one product per coefficient, from a, b computed once
  // per restriction (ray_horner.h, UnderflowFloor), never overflowing before the true
  // floor does.
  // A subnormal component of p or d reads as 0 under DAZ: the computation is then that
  // of a ray moved by eps < 2^-1022 per component, whose restriction differs from p's by
  // at most m sum|c| 2^-1022 C(m, r) P^(m-r) D^r (the difference of the products of
  // factors telescopes into at most m terms, each a factor (eps_p + s eps_d) times m - 1
  // others; the coefficient r of (1 + s)(P + s D)^(n-1) is at most C(n, r) P^(n-r) D^r).
  // The floor's weight is 8 N, which covers that term too (doubled) while
  // 2 m sum|c| <= 4 N (every polynomial the adapter scales to a largest coefficient in
  // [1, 2)); a larger sum|c| adds it explicitly when a component is subnormal.
  // Measured (tests/bench/taylor_bench, BM_GalleryDirect, HornerForm path, CPU medians):
  // 4-8 ns per restriction, the same for every degree (sphere 40 -> 46, torus 68 -> 75,
  // Barth's decic 231 -> 243 ns).
  const int m = f.degree();
  const double factor = ray_horner::kRestrictFactor[m];
  ray_horner::UnderflowFloor floor;
  ray_horner::initUnderflowFloor(floor, m, p, d, absSumInBoxOrder(f));
  g.degree = m;
  for (int i = 0; i <= m; ++i)
    g.error[i] = ray_horner::boundOrInfinity(factor * mag[i] + floor.at(i));
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

  // The shift of |f| by |o| on magnitudes, with a floor phi added at every slot and
  // operation: an absolute error eta < 2^-1022 of an operation of the shift (underflow;
  // see restrictToRay above) travels from its slot like a coefficient placed there, so
  // shiftFactor * phi >= 8 * 2^-1022 covers the etas of the operation (a product and a
  // sum), a subnormal coefficient read as 0 (DAZ) and the magnitudes' own etas (phi far
  // above them). phi is 2^-966 / (6m + 6) or so: it matters only for polynomials whose
  // values are all near double's underflow threshold.
  const double shiftFactor = gamma(6 * m + 6) * (1.0 + gamma(6 * m + 6));
  const double phi = 8.0 * std::numeric_limits<double>::min() / shiftFactor;
  const std::vector<double> absShift = flooredAbsShift(f, glm::abs(o), phi);
  // A subnormal component of o reads as 0 under DAZ (translate() then skips that axis):
  // f(o' + u) for o' within eps < 2^-1022 of o per component, whose coefficients differ
  // from f(o + u)'s by at most m sum|c| 2^-1022 (2 max(1, |o_a|))^m in all (telescoped as
  // in restrictToRay's floor), doubled, added to every block's weight in that case only.
  double subnormalShift = 0.0;
  if (ray_horner::hasSubnormal(o)) {
    double absSum = 0.0;
    for (const double c : f.coeffs()) absSum += std::abs(c);
    const double om = std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z)});
    subnormalShift =
        2.0 * m * absSum * ray_horner::pow2(m * (ray_horner::ceilExponent(om) + 1) - 1022);
  }
  for (int n = 0; n <= m; ++n) {
    const int blockSize = (n + 1) * (n + 2) / 2;
    const double evalFactor = gamma(n + 2 + blockSize);
    double w = 0.0, s = 0.0;
    forEachMonomialOfDegree(n, [&](int, int, int, int idx) {
      const double c = std::abs(shifted_.coeffs()[idx]);
      w += shiftFactor * absShift[idx] + evalFactor * c;
      s += c;
    });
    blockErrorWeight_[n] = (w + subnormalShift) * (1.0 + gamma(blockSize + 2));
    // Underflow in H_n(d) (restrict below): with D = max(1, max|d_i|), a power of a
    // component errs by at most e eta D^(e-1) after e products, so a term c d^alpha by
    // (n + 1) |c| eta D^n beyond its relative error, and each product c w, each sum and a
    // shifted coefficient read as 0 add an eta times at most D^n; the bound's own
    // W_n max|d_i|^n loses at most n W_n eta D^n when the power underflows. With eta <
    // 2^-1022 and a factor 2 for the roundings: F_n 2^-1022 D^n, F_n below.
    blockFloorWeight_[n] = 2.0 * ((n + 2) * (s + blockErrorWeight_[n]) + 4.0 * (blockSize + n + 1));
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
    // The floor's D^n as 2^(b n) >= D^n, one exact power of two per block (no overflow
    // before the floor's own). A coefficient that overflowed (its terms' sum, or a power
    // of d) has no finite bound, though W_n max|d_i|^n may still be finite.
    const double dmax = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    const int b = ray_horner::ceilExponent(dmax);
    double dn = 1.0;
    for (int n = 0; n <= g.degree; ++n, dn *= dmax) {
      const double e = blockErrorWeight_[n] * dn * (1.0 + gamma(n + 2)) +
                       blockFloorWeight_[n] * ray_horner::pow2(b * n - 1022);
      g.error[n] = std::isfinite(g.coeff[n]) ? ray_horner::boundOrInfinity(e) : HUGE_VAL;
    }
  }
  while (g.degree > 0 && g.coeff[g.degree] == 0.0 && g.error[g.degree] == 0.0) --g.degree;
}

}  // namespace algray
