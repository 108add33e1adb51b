#pragma once
// A value of the equation language with a running rounding-error bound, so that the
// parser can tell rounding junk from real coefficients (the pruning rule below).
//
// Every value V carries, next to its computed coefficients v_i, a magnitude M_i >= |v_i|,
// a count k of rounding steps and an underflow term A_i >= 0 such that the exact
// coefficient (the one the same expression has in real arithmetic on the same literals)
// satisfies
//
//     |v_i - exact_i| <= gamma_k * M_i + A_i,        gamma_k = k u / (1 - k u).
//
// A_i is the absolute part of the model fl(a op b) = (a op b)(1 + d) + h of Higham
// Sec. 2.1: a product, quotient or literal whose result is below 2^-1022 in magnitude
// (or a non-zero exact result rounded to 0) errs by up to 2^-1075 beyond its relative
// error (2^-1074 for libm's pow, exp, ...; the code adds 2^-1074, 2^-1075 is no double;
// sums have no such term: a subnormal sum is exact). A is carried through later operations
// like the relative terms (first order):
//   a * b    A = Ma Ab + Aa Mb + Aa Ab (convolutions for polynomials) + the floors
//   a / d    A = 4 (Aa + Ma Ad / |d|) / |d| + the floors (the parser requires 4 Ad < |d|)
//   a +- b   A = Aa + Ab
//   f(c)     A = |f'(c)| Ac (sqrt, log: their exact increments) + the floor; c^e likewise
// Without it a coefficient lost to underflow and scaled back up (x*1e-170*1e-170*1e300)
// looked exact: the parser refuses a value it swallows (underflowLoss below).
//
// M is an error weight. For sums it is the "absolute" expansion of Higham, "Accuracy and
// Stability of Numerical Algorithms", 2nd ed., Sec. 3.1-3.3 (the same sum with |.| of every
// term, so M_i bounds every partial sum that fed v_i); for products it follows
// d(ab) = da b + a db + da db, so that a value's cancellation enters a product once and not
// to the power of the number of factors. The rules (first order in u except the products'
// own second-order term; the factor 2 of the pruning rule covers the rest):
//   literal, pi, e, parameter   k = 1 (one rounding to double), M = |v|
//   a +- b                      k = max(ka, kb) + 1,  M = Ma + Mb          (Lemma 3.3)
//   a * b (b a constant)        k = ka + kb + 1,      M = Ma |b| + |a| Mb + g Ma Mb
//   a * b (polynomials)         k = ka + kb + m,      M = Ma * |b| + |a| * Mb + g Ma * Mb
//                               m = min(non-zeros of a, b): the longest convolution sum
//                               (recursive summation of m products, Higham Eq. (3.4));
//                               g = min(gamma_ka, gamma_kb); an exact factor (k = 0) drops
//                               the terms of its error
//   a / d (d a constant)        k = ka + kd + 1,      M = Ma * rho_d / |d|, rho_d = Md/|d|
//   a^n (repeated products)     k and M from the product rule applied n-1 times
//   c^e (constants, libm pow)   k = max(kc, ke) + 2,
//                               M = |c^e| (max(1, |e|) rho_c + |ln|c|| Me + 1)
//   f(c) for sqrt, sin, ...     k = kc + 2 (libm within 1 ulp), M = |f(c)| + s Mc, s the
//                               largest |f'| within the argument's error 2 gamma_kc Mc + Ac;
//                               a pole or the domain's edge within it: no correct digit
// The factors of powers, functions and divisors stay in M, which is per coefficient: the
// count k is shared by every term of a sum. Until session 52 a product's M was Ma Mb (the
// absolute expansion throughout), and (x + 3^2)^40 lost 22 of its 41 coefficients to the
// pruning rule, (x + 2 - 1)^40 13, (x + exp(3))^40 18; functions took the slope at c alone.
//
// Pruning rule (applied after every operation that can cancel: *, /, ^, functions, and
// once at the end of each chain a1 +- a2 +- ... +- an):
//     a coefficient with |v_i| <= 2 gamma_k M_i is pure rounding junk: it is set to 0.
// Its exact value is then at most 3 gamma_k M_i in magnitude, so M_i is multiplied by 3 to
// keep the invariant, and M is truncated to the degree that remains (a pruned top block is
// declared zero). Example: (x+0.1)^2 - x^2 - 0.2*x - 0.01 prunes to exactly 0, while
// (x+1e-8)^3 - x^3 keeps 3e-8 x^2, 3e-16 x and 1e-24 (each is its own magnitude).
#include "algray/polynomial.h"

#include <cstdint>
#include <string_view>

namespace algray::detail {

struct TrackedValue {
  // True when the expression mentions x, y or z (decided by the syntax, not by the
  // value: x - x is still a polynomial and cannot be a divisor or an exponent).
  bool hasVariables = false;
  // A single term value * x^e0 y^e1 z^e2 kept sparse (hasVariables is true, poly and
  // polyMagnitude are unused): typed monomials like 3*x^2*y cost O(1) instead of a dense
  // block each; materialize() turns it into the dense form when it meets a polynomial.
  bool monomial = false;
  int exponents[3] = {0, 0, 0};
  double value = 0.0;  // when !hasVariables, or the coefficient of a monomial
  double magnitude = 0.0;
  Polynomial poly;  // when hasVariables and !monomial
  Polynomial polyMagnitude;
  std::int64_t roundings = 0;
  // The underflow term A above: of value (a constant or monomial) or per coefficient.
  double underflow = 0.0;
  Polynomial polyUnderflow;

  static TrackedValue constant(double v, std::int64_t roundings = 1);
  // A decimal literal rounded to v; `nonZero` when its digits are not all 0 (1e-400 is).
  static TrackedValue literal(double v, bool nonZero);
  static TrackedValue variable(int axis);

  int degree() const {
    if (monomial) return value != 0.0 ? exponents[0] + exponents[1] + exponents[2] : -1;
    return hasVariables ? poly.degree() : (value != 0.0 ? 0 : -1);
  }
  // A monomial becomes a dense polynomial (no-op otherwise).
  void materialize();
  bool isFinite() const;  // every value and every bound
  // Every value, where isFinite() is not: a value within ~1000x of the largest double, whose
  // bound (M above) overflowed first.
  bool valuesFinite() const;
  // The constant a polynomial reduces to when its degree is <= 0.
  TrackedValue asConstant() const;
  Polynomial toPolynomial() const;
};

double gammaOf(std::int64_t k);

TrackedValue negate(TrackedValue a);
TrackedValue add(const TrackedValue& a, const TrackedValue& b, bool subtract);
// acc +-= b without pruning (for a chain a1 + a2 + ... + an, which the parser prunes once
// at its end: O(size of b) per term instead of O(size of acc)).
void accumulate(TrackedValue& acc, const TrackedValue& b, bool subtract);
TrackedValue multiply(const TrackedValue& a, const TrackedValue& b);
// d must be a constant with a non-zero value (the parser checks).
TrackedValue divide(const TrackedValue& a, const TrackedValue& d);
// a^n for a polynomial a and an integer n >= 0 (the parser checks the degree first).
TrackedValue integerPower(const TrackedValue& a, int n);
// The constant c as a polynomial of degree <= 0 with the same bound.
TrackedValue promoted(const TrackedValue& c);
// The outcome of folding a function or a power of constants (the fold rule below).
enum class Fold {
  ok,            // result holds the value, pruned as usual (it may be non-finite)
  undetermined,  // the bound swallows a value that cannot be rounding junk of a zero:
                 // result holds the unpruned value, the parser reports it
  unknownFunction,
};

// Fold rule. The bound of a fold f(c) is first order: gamma_k (|f(c)| + |f'(c)| Mc). Pruning
// it to 0 claims that the exact value is a zero of f blurred by rounding; that holds when
// f has zeros with unit slope (sin, cos, tan and log all have |f'| = 1 at every zero) and
// the bound is at the rounding level of the argument: |f'(c)| <= 2 (the slope of a
// nearby zero, up to the factor 2 the pruning rule keeps for second-order terms) and
// 2 gamma_k Mc <= 1 (the argument is known to within a radian, or a factor e for log, so
// f is close to its tangent there). sin(pi), cos(pi/2), tan(pi) qualify. Otherwise the
// large bound is not rounding junk but a sign that the value has no correct digit: a
// pole within the argument's rounding (tan(pi/2): |f'| = tan^2 ~ 1e32), an argument whose
// error spans several periods (sin(1e17)), or a function without zeros (exp, c^e with
// c != 0: any perturbation of a non-zero base keeps the power non-zero) whose relative
// error has reached 100 % (1.0000000000000002^1e16). Those are Fold::undetermined.

// c^e for constants; may be non-finite (the parser checks).
Fold constantPower(const TrackedValue& c, const TrackedValue& e, TrackedValue& result);
// f(c) for f in sqrt, sin, cos, tan, exp, log (ln), abs; c constant. The result may be
// non-finite (the parser checks).
Fold applyFunction(std::string_view name, const TrackedValue& c, TrackedValue& result);
bool isFunctionName(std::string_view name);

// The pruning rule above, in place. It leaves A alone: a coefficient pruned to 0 keeps
// its underflow term (a lost value is not junk of a zero).
void prune(TrackedValue& v);

// Underflow rule: the largest A_i of a coefficient lost to underflow, 0 if there is none.
// A coefficient is lost when A swallows it (|v_i| <= A_i) beyond the pruning rule's reach
// (A_i > 2 gamma_k M_i) and beyond the floor of the double format (A_i > 2^-1022: an
// underflow to 0 or a subnormal of a value that stays that small is the nearest double,
// x*1e-170*1e-170 is 0). The parser reports it where it happens: x*1e-170*1e-170*1e300
// at the last '*', whose exact coefficient 1e-40 would have been a silent 0.
double underflowLoss(const TrackedValue& v);

}  // namespace algray::detail
