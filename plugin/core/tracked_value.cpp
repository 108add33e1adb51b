#include "tracked_value.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace algray::detail {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinNormal = 0x1p-1022;
// The absolute underflow error of one result: 2^-1075 for a correctly rounded operation,
// 2^-1074 for libm (within one ulp); 2^-1075 is no double, so both use 2^-1074.
constexpr double kFloor = 0x1p-1074;

// The floor of one rounded result r of an operation whose exact result is non-zero.
double floorOf(double r) { return std::abs(r) < kMinNormal ? kFloor : 0.0; }

// The floor of p = fl(a b): none where the product is exact, so that x*1e-323 (a product by
// 1) does not double the literal's own floor. Exactness is decided where it can be: the
// smaller factor scaled by 2^600 makes the product normal, its rounding error exact (fma).
double productFloor(double a, double b, double p) {
  if (a == 0.0 || b == 0.0 || std::abs(p) >= kMinNormal) return 0.0;
  if (std::abs(a) > std::abs(b)) std::swap(a, b);
  const double scaled = std::ldexp(a, 600), q = scaled * b;
  const bool exact = q != 0.0 && std::fma(scaled, b, -q) == 0.0 && std::ldexp(p, 600) == q;
  return exact ? 0.0 : kFloor;
}

// Coefficientwise: the floor of every coefficient of `out` = `in` times s (or divided by s,
// `divided`: a floor wherever the quotient is below 2^-1022).
Polynomial floorsWhere(const Polynomial& in, const Polynomial& out, double s, bool divided) {
  Polynomial r;
  const auto c = in.coeffs(), o = out.coeffs();
  for (int n = in.degree(); n >= 0; --n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      const double v = idx < static_cast<int>(o.size()) ? o[idx] : 0.0;
      const double f = divided ? (c[idx] != 0.0 ? floorOf(v) : 0.0) : productFloor(c[idx], s, v);
      if (f != 0.0) r.setCoeff(i, j, k, f);
    });
  return r;
}

// x y for x, y >= 0, rounded up where it underflows: a bound that underflowed to 0 would
// claim an exact value (x*1e-330*3e-65*1e300 lost its x that way).
double mulUp(double x, double y) {
  const double p = x * y;
  return p + productFloor(x, y, p);
}

double minAbsNonZero(const Polynomial& p) {
  double m = kInf;
  for (const double c : p.coeffs())
    if (c != 0.0) m = std::min(m, std::abs(c));
  return m;
}

// The floors of a * b (Polynomial's operator* rounds every product of non-zero
// coefficients once): a floor for each inexact product below 2^-1022, at its monomial. The common
// case, no product that small, costs one scan of each.
Polynomial productFloors(const Polynomial& a, const Polynomial& b) {
  if (a.isZero() || b.isZero() || minAbsNonZero(a) * minAbsNonZero(b) >= kMinNormal) return {};
  std::vector<double> f(Polynomial::termCount(a.degree() + b.degree()), 0.0);
  const auto ca = a.coeffs(), cb = b.coeffs();
  for (int na = 0; na <= a.degree(); ++na)
    forEachMonomialOfDegree(na, [&](int i, int j, int k, int ia) {
      if (ca[ia] == 0.0) return;
      for (int nb = 0; nb <= b.degree(); ++nb)
        forEachMonomialOfDegree(nb, [&](int p, int q, int r, int ib) {
          if (cb[ib] != 0.0)
            f[Polynomial::index(i + p, j + q, k + r)] +=
                productFloor(ca[ia], cb[ib], ca[ia] * cb[ib]);
        });
    });
  Polynomial r;
  for (int n = a.degree() + b.degree(); n >= 0; --n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      if (f[idx] != 0.0) r.setCoeff(i, j, k, f[idx]);
    });
  return r;
}

// p q for p, q >= 0 coefficientwise, rounded up where a product underflows (mulUp).
Polynomial productUp(const Polynomial& p, const Polynomial& q) {
  return p * q + productFloors(p, q);
}

// Ma Ab + Aa Mb + Aa Ab: how the underflow terms of the factors carry into a product.
Polynomial carriedUnderflow(const Polynomial& ma, const Polynomial& aa, const Polynomial& mb,
                            const Polynomial& ab) {
  Polynomial r;
  if (!ab.isZero()) r += productUp(ma, ab);
  if (!aa.isZero()) r += productUp(aa, mb);
  if (!aa.isZero() && !ab.isZero()) r += productUp(aa, ab);
  return r;
}

// Saturating sum of rounding counts (absurd inputs cannot wrap around).
std::int64_t addCounts(std::int64_t a, std::int64_t b) {
  constexpr std::int64_t kCap = std::int64_t{1} << 50;
  return std::min(kCap, a + b);
}

// Relative condition of a constant: Mc / |c| >= 1 (how much its cancellations amplify
// the relative rounding error).
double conditionOf(const TrackedValue& c) {
  return c.value != 0.0 ? std::max(1.0, c.magnitude / std::abs(c.value)) : 1.0;
}

// The fold rule of tracked_value.h applied to r = f(c): `zeroLike` says that f has zeros
// with unit slope and the slope at c is at most 2; `argumentError` is 2 gamma_k Mc.
Fold pruneFold(TrackedValue& r, bool zeroLike, double argumentError) {
  const double g2 = 2.0 * gammaOf(r.roundings);
  const bool swallowed =
      r.value != 0.0 && std::isfinite(r.magnitude) && std::abs(r.value) <= g2 * r.magnitude;
  if (swallowed && !(zeroLike && argumentError <= 1.0)) return Fold::undetermined;
  prune(r);
  return Fold::ok;
}

}  // namespace

TrackedValue promoted(const TrackedValue& c) {
  if (c.hasVariables) return c;
  TrackedValue p = c;
  p.hasVariables = true;
  p.poly = Polynomial(c.value);
  p.polyMagnitude = Polynomial(c.magnitude);
  p.polyUnderflow = Polynomial(c.underflow);
  p.underflow = 0.0;
  return p;
}

double gammaOf(std::int64_t k) {
  const double ku = static_cast<double>(k) * kUnitRoundoff;
  return ku < 0.5 ? ku / (1.0 - ku) : kInf;
}

TrackedValue TrackedValue::constant(double v, std::int64_t roundings) {
  TrackedValue t;
  t.value = v;
  t.magnitude = std::abs(v);
  t.roundings = roundings;
  return t;
}

TrackedValue TrackedValue::literal(double v, bool nonZero) {
  TrackedValue t = constant(v);
  if (nonZero) t.underflow = floorOf(v);
  return t;
}

TrackedValue TrackedValue::variable(int axis) {
  TrackedValue t;
  t.hasVariables = true;
  t.monomial = true;
  t.exponents[axis] = 1;
  t.value = t.magnitude = 1.0;
  return t;
}

void TrackedValue::materialize() {
  if (!monomial) return;
  monomial = false;
  poly = Polynomial();
  polyMagnitude = Polynomial();
  if (value != 0.0) poly.setCoeff(exponents[0], exponents[1], exponents[2], value);
  if (magnitude != 0.0 && value != 0.0)
    polyMagnitude.setCoeff(exponents[0], exponents[1], exponents[2], magnitude);
  polyUnderflow = Polynomial();
  if (underflow != 0.0) polyUnderflow.setCoeff(exponents[0], exponents[1], exponents[2], underflow);
  value = magnitude = underflow = 0.0;
}

Polynomial TrackedValue::toPolynomial() const {
  if (!hasVariables) return Polynomial(value);
  if (!monomial) return poly;
  TrackedValue copy = *this;
  copy.materialize();
  return copy.poly;
}

bool TrackedValue::isFinite() const {
  if (!hasVariables || monomial)
    return std::isfinite(value) && std::isfinite(magnitude) && std::isfinite(underflow);
  return poly.isFinite() && polyMagnitude.isFinite() && polyUnderflow.isFinite();
}

bool TrackedValue::valuesFinite() const {
  if (!hasVariables || monomial) return std::isfinite(value);
  return poly.isFinite();
}

TrackedValue TrackedValue::asConstant() const {
  if (!hasVariables) return *this;
  TrackedValue c;
  if (monomial) {
    const bool constantTerm = exponents[0] + exponents[1] + exponents[2] == 0;
    c.value = constantTerm ? value : 0.0;
    c.magnitude = constantTerm ? magnitude : 0.0;
    c.underflow = constantTerm ? underflow : 0.0;
    c.roundings = roundings;
    return c;
  }
  c.value = poly.coeff(0, 0, 0);
  c.magnitude = polyMagnitude.coeff(0, 0, 0);
  c.underflow = polyUnderflow.coeff(0, 0, 0);
  c.roundings = roundings;
  return c;
}

TrackedValue negate(TrackedValue a) {
  if (a.hasVariables && !a.monomial)
    a.poly *= -1.0;
  else
    a.value = -a.value;
  return a;
}

TrackedValue add(const TrackedValue& a, const TrackedValue& b, bool subtract) {
  TrackedValue r = a;
  accumulate(r, b, subtract);
  prune(r);
  return r;
}

void accumulate(TrackedValue& acc, const TrackedValue& b, bool subtract) {
  acc.roundings = addCounts(std::max(acc.roundings, b.roundings), 1);
  if (!acc.hasVariables && !b.hasVariables) {
    acc.value = subtract ? acc.value - b.value : acc.value + b.value;
    acc.magnitude += b.magnitude;
    acc.underflow += b.underflow;
    return;
  }
  if (!acc.hasVariables) acc = promoted(acc);
  acc.materialize();
  if (b.monomial) {
    // One coefficient changes: O(1) unless the storage grows.
    const int i = b.exponents[0], j = b.exponents[1], k = b.exponents[2];
    if (b.value != 0.0)
      acc.poly.setCoeff(i, j, k, acc.poly.coeff(i, j, k) + (subtract ? -b.value : b.value));
    if (b.value != 0.0)
      acc.polyMagnitude.setCoeff(i, j, k, acc.polyMagnitude.coeff(i, j, k) + b.magnitude);
    if (b.underflow != 0.0)
      acc.polyUnderflow.setCoeff(i, j, k, acc.polyUnderflow.coeff(i, j, k) + b.underflow);
  } else if (b.hasVariables) {
    if (subtract)
      acc.poly -= b.poly;
    else
      acc.poly += b.poly;
    acc.polyMagnitude += b.polyMagnitude;
    if (!b.polyUnderflow.isZero()) acc.polyUnderflow += b.polyUnderflow;
  } else {
    acc.poly += Polynomial(subtract ? -b.value : b.value);
    acc.polyMagnitude += Polynomial(b.magnitude);
    if (b.underflow != 0.0) acc.polyUnderflow += Polynomial(b.underflow);
  }
}

namespace {

// The magnitude of a product by the rule of tracked_value.h: with exact values a + da,
// b + db, |da| <= gamma_ka Ma, |db| <= gamma_kb Mb, the product errs by at most
// gamma_ka Ma |b| + gamma_kb |a| Mb + gamma_ka gamma_kb Ma Mb + its own rounding, all
// within gamma_(ka + kb + m) (Ma |b| + |a| Mb + min(gamma_ka, gamma_kb) Ma Mb): the
// rounding folds into a term, |a||b| <= Ma |b|, and an exact factor (k = 0) drops the
// terms of its error. (The second-order term is what is left where both values lost every
// digit: (1e17 + 1 - 1e17)^2 is 0 computed, 1 exact.)
double secondOrder(std::int64_t ka, std::int64_t kb) { return std::min(gammaOf(ka), gammaOf(kb)); }

double productMagnitude(const TrackedValue& a, const TrackedValue& b) {
  if (a.roundings == 0) return std::abs(a.value) * b.magnitude;
  if (b.roundings == 0) return a.magnitude * std::abs(b.value);
  return a.magnitude * std::abs(b.value) + std::abs(a.value) * b.magnitude +
         secondOrder(a.roundings, b.roundings) * (a.magnitude * b.magnitude);
}

// The same for polynomials (convolutions).
Polynomial productMagnitude(const Polynomial& a, const Polynomial& ma, std::int64_t ka,
                            const Polynomial& b, const Polynomial& mb, std::int64_t kb);

Polynomial absolute(const Polynomial& p) {
  Polynomial r;
  const auto c = p.coeffs();
  for (int n = p.degree(); n >= 0; --n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      if (c[idx] != 0.0) r.setCoeff(i, j, k, std::abs(c[idx]));
    });
  return r;
}

Polynomial productMagnitude(const Polynomial& a, const Polynomial& ma, std::int64_t ka,
                            const Polynomial& b, const Polynomial& mb, std::int64_t kb) {
  if (ka == 0) return absolute(a) * mb;
  if (kb == 0) return ma * absolute(b);
  return ma * absolute(b) + absolute(a) * mb + (ma * mb) * secondOrder(ka, kb);
}

// A of the product of two constants or monomials whose rounded product is r.
double scalarProductUnderflow(const TrackedValue& a, const TrackedValue& b, double r) {
  if (a.underflow == 0.0 && b.underflow == 0.0) [[likely]]
    return productFloor(a.value, b.value, r);
  const double carried = mulUp(a.magnitude, b.underflow) + mulUp(a.underflow, b.magnitude) +
                         mulUp(a.underflow, b.underflow);
  return carried + productFloor(a.value, b.value, r);
}

// acc = base^n (acc holds base on entry) for the value, magnitude and underflow term of a
// constant or monomial, by n - 1 products; the caller counts the roundings. Without an
// underflow term and with base and result normal no step underflowed (|base^s| is
// monotone in s), so the products alone do (tracking A in every step doubled the time
// of parsing dense expanded text).
void scalarPower(TrackedValue& acc, const TrackedValue& base, int n) {
  for (int s = 1; s < n; ++s) acc.magnitude = productMagnitude(acc, base), acc.value *= base.value;
  if (base.underflow == 0.0 && std::abs(base.value) >= kMinNormal &&
      std::abs(acc.value) >= kMinNormal) [[likely]]
    return;
  acc.value = base.value, acc.magnitude = base.magnitude, acc.underflow = base.underflow;
  for (int s = 1; s < n; ++s) {
    const double product = acc.value * base.value;
    acc.underflow = scalarProductUnderflow(acc, base, product);
    acc.magnitude = productMagnitude(acc, base);
    acc.value = product;
  }
}

}  // namespace

TrackedValue multiply(const TrackedValue& a, const TrackedValue& b) {
  TrackedValue r;
  const bool aSparse = !a.hasVariables || a.monomial, bSparse = !b.hasVariables || b.monomial;
  if ((a.monomial || b.monomial) && aSparse && bSparse) {
    // Monomial times monomial or constant: one product, no cancellation, no pruning.
    r.hasVariables = r.monomial = true;
    for (int axis = 0; axis < 3; ++axis)
      r.exponents[axis] =
          (a.monomial ? a.exponents[axis] : 0) + (b.monomial ? b.exponents[axis] : 0);
    r.value = a.value * b.value;
    r.magnitude = productMagnitude(a, b);
    r.underflow = scalarProductUnderflow(a, b, r.value);
    r.roundings = addCounts(addCounts(a.roundings, b.roundings), 1);
    return r;
  }
  if (a.monomial || b.monomial) {
    TrackedValue da = a, db = b;
    da.materialize();
    db.materialize();
    return multiply(da, db);
  }
  if (!a.hasVariables && !b.hasVariables) {
    r.value = a.value * b.value;
    r.magnitude = productMagnitude(a, b);
    r.underflow = scalarProductUnderflow(a, b, r.value);
    r.roundings = addCounts(addCounts(a.roundings, b.roundings), 1);
  } else if (!a.hasVariables || !b.hasVariables) {
    const TrackedValue& c = a.hasVariables ? b : a;
    const TrackedValue& p = a.hasVariables ? a : b;
    r.hasVariables = true;
    r.poly = p.poly * c.value;
    r.polyMagnitude = productMagnitude(p.poly, p.polyMagnitude, p.roundings, Polynomial(c.value),
                                       Polynomial(c.magnitude), c.roundings);
    r.polyUnderflow = carriedUnderflow(p.polyMagnitude, p.polyUnderflow, Polynomial(c.magnitude),
                                       Polynomial(c.underflow));
    if (c.value != 0.0) r.polyUnderflow += floorsWhere(p.poly, r.poly, c.value, false);
    r.roundings = addCounts(addCounts(a.roundings, b.roundings), 1);
  } else {
    r.hasVariables = true;
    const int m = std::min(a.poly.nonZeroCount(), b.poly.nonZeroCount());
    r.poly = a.poly * b.poly;
    r.polyMagnitude = productMagnitude(a.poly, a.polyMagnitude, a.roundings, b.poly,
                                       b.polyMagnitude, b.roundings);
    r.polyUnderflow =
        carriedUnderflow(a.polyMagnitude, a.polyUnderflow, b.polyMagnitude, b.polyUnderflow);
    r.polyUnderflow += productFloors(a.poly, b.poly);
    r.roundings = addCounts(addCounts(a.roundings, b.roundings), std::max(m, 1));
  }
  prune(r);
  return r;
}

TrackedValue divide(const TrackedValue& a, const TrackedValue& d) {
  // Division is coefficient by coefficient (one correctly rounded quotient each), so that
  // x/3 has the same coefficient as 1/3. The magnitude rule: q = a/d with d perturbed by
  // gamma_kd Md gives |dq| <= |da|/|d| + |a| gamma_kd rho_d / |d| + u|q|.
  TrackedValue r;
  const double scale = conditionOf(d) / std::abs(d.value);
  // A 4 Ad < |d| and gamma_kd Md < |d| / 2 (the pruning rule) keep |exact d| > |d| / 4.
  const double carry = 4.0 / std::abs(d.value);
  const double carryMagnitude = mulUp(carry, mulUp(d.underflow, 1.0 / std::abs(d.value)));
  r.roundings = addCounts(addCounts(a.roundings, d.roundings), 1);
  if (!a.hasVariables || a.monomial) {
    r = a;
    r.roundings = addCounts(addCounts(a.roundings, d.roundings), 1);
    r.value = a.value / d.value;
    r.magnitude = a.magnitude * scale;
    r.underflow = mulUp(carry, a.underflow) + mulUp(carryMagnitude, a.magnitude) +
                  (a.value != 0.0 ? floorOf(r.value) : 0.0);
  } else {
    r.hasVariables = true;
    const auto c = a.poly.coeffs();
    std::vector<double> q(c.size());
    for (size_t i = 0; i < c.size(); ++i) q[i] = c[i] / d.value;
    for (int n = a.poly.degree(); n >= 0; --n)
      forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
        if (q[idx] != 0.0) r.poly.setCoeff(i, j, k, q[idx]);
      });
    r.polyMagnitude = a.polyMagnitude * scale;
    if (!a.polyUnderflow.isZero()) r.polyUnderflow += productUp(a.polyUnderflow, Polynomial(carry));
    if (d.underflow != 0.0)
      r.polyUnderflow += productUp(a.polyMagnitude, Polynomial(carryMagnitude));
    r.polyUnderflow += floorsWhere(a.poly, r.poly, d.value, true);
  }
  prune(r);
  return r;
}

TrackedValue integerPower(const TrackedValue& a, int n) {
  if (n == 0) {  // x^0 = 1, still "an expression in x, y, z" for the syntactic rules
    const TrackedValue one = TrackedValue::constant(1.0, 0);
    return a.hasVariables ? promoted(one) : one;
  }
  if (!a.hasVariables || a.degree() <= 0) {
    // A constant (or a polynomial that reduced to one): exact repeated products would be
    // slow for x^0*... ^1000000; pow is within one ulp. (The parser folds constant powers
    // itself and reports Fold::undetermined; here the unpruned value is kept.)
    TrackedValue c;
    constantPower(a.asConstant(), TrackedValue::constant(n, 0), c);
    if (!a.hasVariables) return c;
    return promoted(c);
  }
  if (a.monomial) {
    // c x^i y^j z^k: its power is one term, c^n by the same n - 1 products the general
    // loop would do, without expanding anything.
    TrackedValue r = a;
    for (int axis = 0; axis < 3; ++axis) r.exponents[axis] = n * a.exponents[axis];
    scalarPower(r, a, n);
    r.roundings = addCounts(static_cast<std::int64_t>(n) * a.roundings, n - 1);
    return r;
  }
  if (a.poly.nonZeroCount() == 1) {
    // A monomial c x^i y^j z^k: its power is one term, c^n by the same n - 1 products
    // the general loop would do, without expanding anything.
    int e[3] = {0, 0, 0};
    double coefficient = 0.0, magnitude = 0.0;
    const int d = a.poly.degree();
    forEachMonomialOfDegree(d, [&](int i, int j, int k, int idx) {
      if (a.poly.coeffs()[idx] != 0.0) {
        e[0] = i, e[1] = j, e[2] = k;
        coefficient = a.poly.coeffs()[idx];
        magnitude = a.polyMagnitude.coeffs()[idx];
      }
    });
    const double underflow = a.polyUnderflow.coeff(e[0], e[1], e[2]);
    // (Not when another coefficient carries an underflow term: it is no zero.)
    if (coefficient != 0.0 && a.polyUnderflow.nonZeroCount() == (underflow != 0.0)) {
      TrackedValue r;
      r.hasVariables = true;
      TrackedValue base = TrackedValue::constant(coefficient);
      base.magnitude = magnitude;
      base.underflow = underflow;
      TrackedValue c = base;
      scalarPower(c, base, n);
      r.poly.setCoeff(n * e[0], n * e[1], n * e[2], c.value);
      r.polyMagnitude.setCoeff(n * e[0], n * e[1], n * e[2], c.magnitude);
      r.polyUnderflow.setCoeff(n * e[0], n * e[1], n * e[2], c.underflow);
      r.roundings = addCounts(static_cast<std::int64_t>(n) * a.roundings, n - 1);
      return r;
    }
  }
  // Repeated multiplication by the base, so that every step sums at most nnz(base)
  // products: k grows by kBase + nnz(base) per step (the product rule above).
  const std::int64_t step = addCounts(a.roundings, std::max(a.poly.nonZeroCount(), 1));
  TrackedValue r = a;
  // The underflow terms by the product rule, step by step, once one appears (they need
  // the magnitude of every step; without them the magnitude is one pow at the end).
  bool underflows = !a.polyUnderflow.isZero();
  Polynomial magnitude = a.polyMagnitude;  // MA^i >= |r|, for the underflow terms
  Polynomial weight = a.polyMagnitude;     // M of r by the product rule
  for (int i = 1; i < n; ++i) {
    Polynomial floors = productFloors(r.poly, a.poly);
    if (!underflows && !floors.isZero()) {
      underflows = true;
      magnitude = a.polyMagnitude.pow(i);
    }
    if (underflows) {
      r.polyUnderflow =
          carriedUnderflow(magnitude, r.polyUnderflow, a.polyMagnitude, a.polyUnderflow) + floors;
      magnitude = magnitude * a.polyMagnitude;
    }
    weight = productMagnitude(r.poly, weight, r.roundings, a.poly, a.polyMagnitude, a.roundings);
    r.poly = r.poly * a.poly;
    r.roundings = addCounts(r.roundings, step);
  }
  r.polyMagnitude = weight;
  prune(r);
  return r;
}

Fold constantPower(const TrackedValue& c, const TrackedValue& e, TrackedValue& r) {
  r = TrackedValue{};
  r.value = std::pow(c.value, e.value);
  r.roundings = addCounts(std::max(c.roundings, e.roundings), 2);
  if (c.value == 0.0) {
    // 0^e: the exact base is at most gamma_kc Mc, its power at most (gamma_kc Mc)^e.
    if (e.value == 0.0)
      r.magnitude = 1.0;
    else if (e.value >= 1.0)
      r.magnitude = std::pow(c.magnitude, e.value);
    else
      r.magnitude = std::pow(c.magnitude, e.value) * std::pow(gammaOf(c.roundings), e.value - 1.0);
    if (!std::isfinite(r.magnitude)) r.magnitude = std::abs(r.value);
    // A base lost to underflow is at most gamma_kc Mc + Ac: so is its power (e > 0).
    if (c.underflow != 0.0 && e.value != 0.0)
      r.underflow = std::pow(gammaOf(c.roundings) * c.magnitude + c.underflow, e.value);
    return Fold::ok;
  }
  // d(c^e)/(c^e) = e dc/c + ln|c| de: relative error |e| gamma_kc rho_c + |ln c| gamma_ke Me.
  // (The factors stay in M, which is per value: the count k is shared by every term of a
  // sum, and a factor moved into it, as tried in session 52, swallowed the other terms.)
  const double logc = std::abs(std::log(std::abs(c.value)));
  r.magnitude = std::abs(r.value) *
                (std::max(1.0, std::abs(e.value)) * conditionOf(c) + logc * e.magnitude + 1.0);
  // Underflow terms: a base within a relative rho = Ac/|c| moves c^e by at most
  // (1 - rho)^-|e| - 1 relatively (both directions); beyond rho = 1/2 the base may be near
  // 0 and |c'^e - c^e| <= 2 (|c| + Ac)^e (e > 0) or is unbounded (e < 0). The exponent's
  // Ae moves it by |c^e ln c| Ae.
  const double rho = c.underflow / std::abs(c.value), power = std::abs(r.value);
  double baseShift = 0.0;
  if (rho > 0.0 && rho < 0.5)
    baseShift = mulUp(power, std::expm1(-std::abs(e.value) * std::log1p(-rho)));
  else if (rho > 0.0 && e.value != 0.0)
    baseShift = e.value > 0.0 ? 2.0 * std::pow(std::abs(c.value) + c.underflow, e.value) : kInf;
  r.underflow = baseShift + mulUp(mulUp(power, logc), e.underflow) + floorOf(r.value);
  // A power of a non-zero base has no zeros: a value within its bound has lost every digit.
  return pruneFold(r, /*zeroLike=*/false, 0.0);
}

bool isFunctionName(std::string_view name) {
  return name == "sqrt" || name == "sin" || name == "cos" || name == "tan" || name == "exp" ||
         name == "log" || name == "ln" || name == "abs";
}

Fold applyFunction(std::string_view name, const TrackedValue& c, TrackedValue& r) {
  const double x = c.value, mx = c.magnitude;
  r = TrackedValue{};
  r.roundings = addCounts(c.roundings, 2);
  double slope = 0.0;  // |f'(x)|
  if (name == "sqrt") {
    r.value = std::sqrt(x);
    if (x == 0.0) {
      // sqrt is not Lipschitz at 0: the exact argument is at most gamma_k Mc, its root at
      // most sqrt(gamma_k Mc) = gamma_k * sqrt(Mc / gamma_k).
      const double g = gammaOf(c.roundings);
      r.magnitude = g > 0.0 ? std::sqrt(mx / g) : 0.0;
      r.underflow = std::sqrt(c.underflow);  // sqrt(a + b) <= sqrt(a) + sqrt(b)
      return Fold::ok;
    }
    slope = 0.5 / r.value;
  } else if (name == "sin") {
    r.value = std::sin(x);
    slope = std::abs(std::cos(x));
  } else if (name == "cos") {
    r.value = std::cos(x);
    slope = std::abs(std::sin(x));
  } else if (name == "tan") {
    r.value = std::tan(x);
    slope = 1.0 + r.value * r.value;
  } else if (name == "exp") {
    r.value = std::exp(x);
    slope = r.value;
  } else if (name == "log" || name == "ln") {
    r.value = std::log(x);
    slope = 1.0 / std::abs(x);
  } else if (name == "abs") {
    r.value = std::abs(x);
    r.magnitude = mx;
    r.underflow = c.underflow;
    r.roundings = c.roundings;
    return Fold::ok;
  } else {
    return Fold::unknownFunction;
  }
  // The slope's largest value within the argument's error delta = 2 gamma_kc Mc + Ac (the
  // factor 2 of the pruning rule), not the slope at c alone, which a first-order bound
  // would take: cos has slope 0 at 0, and an argument known to a radian or worse gave cos a
  // confident 1 (cos(3e14*pi - (3e14*pi - 3.4822)) read cos(0) = 1, exact -0.94; session
  // 52's review). Where delta reaches a pole or the edge of the domain, or spans a radian
  // (sin, cos, tan) or a factor e (exp), the value has no correct digit (sin(pi/2 + (1e17
  // + 1 - 1e17)) read 0: its argument, pruned to 0, was 0 +- 800).
  const bool isLog = name == "log" || name == "ln";
  const double delta = 2.0 * gammaOf(c.roundings) * mx + c.underflow;
  bool determined = true;
  if (name == "sin" || name == "cos") {
    determined = delta <= 1.0;
    slope = std::min(1.0, slope + delta);
  } else if (name == "tan") {
    const double angle = std::atan(std::abs(r.value));  // x's distance from a multiple of pi
    determined = delta <= 1.0 && angle + delta < 0.5 * std::numbers::pi;
    const double t = std::tan(angle + delta);
    if (determined) slope = std::max(slope, 1.0 + t * t);
  } else if (name == "exp") {
    determined = delta <= 1.0;
    slope = r.value * std::exp(std::min(delta, 1.0));
  } else if (isLog && x > 0.0) {
    determined = delta < 0.5 * x;
  } else if (name == "sqrt" && x > 0.0) {
    determined = delta < 0.5 * x;
    if (determined) slope = 0.5 / std::sqrt(x - delta);
  }
  // log's slope 1/|x| overflows for a subnormal x, where Mx / |x|, about 1, does not.
  const double spread = isLog ? mx / (x > 0.0 && determined ? x - delta : std::abs(x)) : slope * mx;
  r.magnitude = std::abs(r.value) + spread;
  if (!determined) return Fold::undetermined;
  // The argument's underflow term to first order, except where the slope blows up within
  // it: sqrt moves by at most min(sqrt(Ac), Ac / sqrt(x)), log by -log1p(-Ac/|x|).
  double shift = mulUp(slope, c.underflow);
  if (c.underflow != 0.0 && name == "sqrt")
    shift = std::min(std::sqrt(c.underflow), c.underflow / r.value);
  else if (c.underflow != 0.0 && (name == "log" || name == "ln"))
    shift = c.underflow < std::abs(x) ? -std::log1p(-c.underflow / std::abs(x)) : kInf;
  r.underflow = shift + floorOf(r.value);
  // sqrt's only zero is at 0 (handled above; elsewhere it is pruned like any function whose
  // argument is tiny but real); exp has none.
  const bool hasUnitSlopeZeros = name != "exp";
  return pruneFold(r, hasUnitSlopeZeros && slope <= 2.0, 2.0 * gammaOf(c.roundings) * mx);
}

void prune(TrackedValue& v) {
  // Non-finite values are left alone for the caller to report (an infinite magnitude
  // must not sweep an overflowed expansion under the carpet).
  const double g2 = 2.0 * gammaOf(v.roundings);
  if (!v.hasVariables || v.monomial) {
    if (v.value != 0.0 && std::isfinite(v.magnitude) && std::abs(v.value) <= g2 * v.magnitude) {
      v.value = 0.0;
      v.magnitude *= 3.0;
    }
    return;
  }
  const auto c = v.poly.coeffs();
  const auto m = v.polyMagnitude.coeffs();
  std::vector<double> threshold(c.size());
  bool any = false;
  for (size_t i = 0; i < c.size(); ++i) {
    threshold[i] = i < m.size() && std::isfinite(m[i]) ? g2 * m[i] : -1.0;
    any = any || (c[i] != 0.0 && std::abs(c[i]) <= threshold[i]);
  }
  if (any) {
    // Inflate M where a coefficient is dropped (|exact| <= 3 gamma_k M there).
    for (int n = v.poly.degree(); n >= 0; --n)
      forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
        if (c[idx] != 0.0 && std::abs(c[idx]) <= threshold[idx])
          v.polyMagnitude.setCoeff(i, j, k, 3.0 * m[idx]);
      });
    v.poly.pruneBelow(threshold);
  }
  // Magnitudes above the degree that remains belong to coefficients declared zero.
  const int kept = Polynomial::termCount(v.poly.degree());
  const auto mm = v.polyMagnitude.coeffs();
  if (static_cast<int>(mm.size()) > kept) {
    std::vector<double> cut(mm.size(), -1.0);
    std::fill(cut.begin() + kept, cut.end(), kInf);
    v.polyMagnitude.pruneBelow(cut);
  }
}

double underflowLoss(const TrackedValue& v) {
  if (!v.hasVariables || v.monomial) {
    if (!(v.underflow > kMinNormal)) return 0.0;
  } else if (v.polyUnderflow.isZero()) {
    return 0.0;
  }
  const double g2 = 2.0 * gammaOf(v.roundings);
  auto lost = [&](double value, double magnitude, double underflow) {
    return underflow > kMinNormal && underflow > g2 * magnitude && std::abs(value) <= underflow;
  };
  if (!v.hasVariables || v.monomial)
    return lost(v.value, v.magnitude, v.underflow) ? v.underflow : 0.0;
  double loss = 0.0;
  const auto c = v.poly.coeffs(), m = v.polyMagnitude.coeffs(), a = v.polyUnderflow.coeffs();
  for (size_t i = 0; i < a.size(); ++i)
    if (lost(i < c.size() ? c[i] : 0.0, i < m.size() ? m[i] : 0.0, a[i]))
      loss = std::max(loss, a[i]);
  return loss;
}

}  // namespace algray::detail
