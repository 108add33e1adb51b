#include "algray/taylor.h"

#include <cmath>

namespace algray {

namespace {

// Multiplies the univariate polynomial q (degree deg) by the linear factor (a + b s) in
// place and adds c to the constant term: one step of Horner's scheme in R[s].
inline void hornerStep(double* q, int& deg, double a, double b, double c) {
  if (deg < 0) {
    q[0] = c;
    deg = 0;
    return;
  }
  q[deg + 1] = b * q[deg];
  for (int r = deg; r >= 1; --r) q[r] = a * q[r] + b * q[r - 1];
  q[0] = a * q[0] + c;
  ++deg;
}

// Adds (q, degQ) into (acc, degAcc).
inline void addInto(double* acc, int& degAcc, const double* q, int degQ) {
  for (int r = degAcc + 1; r <= degQ; ++r) acc[r] = 0.0;
  for (int r = 0; r <= degQ; ++r) acc[r] += q[r];
  if (degQ > degAcc) degAcc = degQ;
}

// Nested Horner of f(p + s d) in R[s]:
//   g = sum_i X^i sum_j Y^j sum_k c_ijk Z^k,  X = p.x + s d.x, ...
// With absolute = true every input is replaced by its absolute value, which yields the
// coefficients of |f|(|p| + s |d|): the magnitudes the rounding-error bound scales.
void nestedHorner(const Polynomial& f, const glm::dvec3& p, const glm::dvec3& d, bool absolute,
                  double* g, int& degG) {
  const int m = f.degree();
  auto val = [absolute](double v) { return absolute ? std::abs(v) : v; };
  const glm::dvec3 pp{val(p.x), val(p.y), val(p.z)}, dd{val(d.x), val(d.y), val(d.z)};
  double fy[kMaxDegree + 2], fz[kMaxDegree + 2];
  degG = -1;
  for (int i = m; i >= 0; --i) {
    int degY = -1;
    for (int j = m - i; j >= 0; --j) {
      int degZ = -1;
      for (int k = m - i - j; k >= 0; --k) hornerStep(fz, degZ, pp.z, dd.z, val(f.coeff(i, j, k)));
      if (degY < 0) {
        for (int r = 0; r <= degZ; ++r) fy[r] = fz[r];
        degY = degZ;
      } else {
        hornerStep(fy, degY, pp.y, dd.y, 0.0);
        addInto(fy, degY, fz, degZ);
      }
    }
    if (degG < 0) {
      for (int r = 0; r <= degY; ++r) g[r] = fy[r];
      degG = degY;
    } else {
      hornerStep(g, degG, pp.x, dd.x, 0.0);
      addInto(g, degG, fy, degY);
    }
  }
}

// H_n(d) for every n: the homogeneous blocks of `poly` evaluated at d.
void evaluateHomogeneousParts(const Polynomial& poly, const glm::dvec3& d, double* out) {
  const int m = poly.degree();
  double px[kMaxDegree + 1], py[kMaxDegree + 1], pz[kMaxDegree + 1];
  px[0] = py[0] = pz[0] = 1.0;
  for (int i = 1; i <= m; ++i) {
    px[i] = px[i - 1] * d.x;
    py[i] = py[i - 1] * d.y;
    pz[i] = pz[i - 1] * d.z;
  }
  const double* c = poly.coeffs().data();
  for (int n = 0; n <= m; ++n) {
    double sum = 0.0;
    for (int jk = 0; jk <= n; ++jk) {
      const double xi = px[n - jk];
      for (int k = 0; k <= jk; ++k) sum += *c++ * (xi * (py[jk - k] * pz[k]));
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
  return dd > 0.0 ? glm::dot(c - o, d) / dd : 0.0;
}

RayPolynomial restrictToRay(const Polynomial& f, const glm::dvec3& o, const glm::dvec3& d,
                            double tShift) {
  RayPolynomial g;
  g.tShift = tShift;
  if (f.isZero()) return g;
  const glm::dvec3 p = tShift == 0.0 ? o : o + tShift * d;
  int deg = -1, degAbs = -1;
  nestedHorner(f, p, d, false, g.coeff.data(), deg);
  double mag[kMaxDegree + 2];
  nestedHorner(f, p, d, true, mag, degAbs);
  // Every coefficient of g is reached through at most m linear-factor steps, each one
  // multiply and at most two additions, plus the coefficient itself: gamma_{3m+3} times
  // the same computation on absolute values bounds the rounding (Higham Sec. 5.1 applied
  // level by level). The abs computation itself rounds too: the final factor covers it.
  const int m = f.degree();
  const double factor = gamma(3 * m + 3) * (1.0 + gamma(3 * m + 3));
  g.degree = deg;
  for (int i = 0; i <= deg; ++i) g.error[i] = factor * mag[i];
  return g;
}

OriginExpansion::OriginExpansion(const Polynomial& f, const glm::dvec3& o)
    : origin_(o), shifted_(f.translate(o)) {
  // Error of the shift: three univariate Taylor shifts by synthetic division, each
  // componentwise within gamma_{2m} of the same shift applied to |c| by |o_axis|
  // (Higham Sec. 5.1); composed: gamma_{6m}. Then H_n(d) adds at most n + 1 + N_n
  // roundings per term (powers, product, summation over the N_n terms of the block).
  // errorWeights_ folds both into one polynomial evaluated at |d| per ray.
  const int m = shifted_.degree();
  if (m < 0) return;
  Polynomial absF;
  for (int n = 0; n <= f.degree(); ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      absF.setCoeff(i, j, k, std::abs(f.coeffs()[idx]));
    });
  const Polynomial absShift = absF.translate(glm::abs(o));
  const double shiftFactor = gamma(6 * m + 6) * (1.0 + gamma(6 * m + 6));
  for (int n = 0; n <= absShift.degree(); ++n) {
    const int blockSize = (n + 1) * (n + 2) / 2;
    const double evalFactor = gamma(n + 2 + blockSize);
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      const double w = shiftFactor * absShift.coeffs()[idx] +
                       evalFactor * std::abs(shifted_.coeff(i, j, k));
      errorWeights_.setCoeff(i, j, k, w * (1.0 + gamma(2 * m + 8)));
    });
  }
}

RayPolynomial OriginExpansion::restrict(const glm::dvec3& d, bool withError) const {
  RayPolynomial g;
  g.degree = shifted_.degree();
  if (g.degree < 0) return g;
  evaluateHomogeneousParts(shifted_, d, g.coeff.data());
  if (withError && !errorWeights_.isZero()) {
    double e[kMaxDegree + 1] = {};
    evaluateHomogeneousParts(errorWeights_, glm::abs(d), e);
    for (int n = 0; n <= errorWeights_.degree(); ++n) g.error[n] = e[n];
  }
  while (g.degree > 0 && g.coeff[g.degree] == 0.0 && g.error[g.degree] == 0.0) --g.degree;
  return g;
}

}  // namespace algray
