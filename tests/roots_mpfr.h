#pragma once
// High-precision references for the root solver (tests/roots_test.cpp and
// tests/bench/roots_report.cpp). Independent of the solver: MPFR at 256 bits.
//  * expand(): the product of known linear and quadratic factors, expanded in MPFR and
//    rounded to double, so the test polynomial is exactly representable.
//  * refine(): a root of that *rounded* polynomial (its coefficients are exact doubles),
//    found by MPFR Newton from a known root and certified by a sign change of the exact
//    value across a tiny bracket (so it is a real root, not a stall near a complex pair).
//  * conditioning(): sum |c_i| |r|^i / |g'(r)|, the factor that turns the unit roundoff
//    into the root error that rounding of the coefficients can cause (Higham, Sec. 26.2,
//    first-order perturbation of a simple root).
#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace algray::test {

inline constexpr mpfr_prec_t kRefBits = 256;

class Mp {
 public:
  Mp() {
    mpfr_init2(v_, kRefBits);
    mpfr_set_zero(v_, 1);
  }
  explicit Mp(double x) {
    mpfr_init2(v_, kRefBits);
    mpfr_set_d(v_, x, MPFR_RNDN);
  }
  Mp(const Mp& o) {
    mpfr_init2(v_, kRefBits);
    mpfr_set(v_, o.v_, MPFR_RNDN);
  }
  Mp& operator=(const Mp& o) {
    mpfr_set(v_, o.v_, MPFR_RNDN);
    return *this;
  }
  ~Mp() { mpfr_clear(v_); }
  mpfr_ptr get() { return v_; }
  mpfr_srcptr get() const { return v_; }
  double toDouble() const { return mpfr_get_d(v_, MPFR_RNDN); }

 private:
  mpfr_t v_;
};

// Coefficients (lowest first) of lead * prod (x - r) * prod ((x - a)^2 + b^2), rounded to
// double from a 256-bit expansion.
inline std::vector<double> expand(const std::vector<double>& realRoots,
                                  const std::vector<std::pair<double, double>>& complexPairs,
                                  double lead = 1.0) {
  std::vector<Mp> p(1, Mp(lead));
  auto mulFactor = [&](const std::vector<Mp>& f) {  // f lowest first
    std::vector<Mp> q(p.size() + f.size() - 1);
    Mp t;
    for (size_t i = 0; i < p.size(); ++i)
      for (size_t j = 0; j < f.size(); ++j) {
        mpfr_mul(t.get(), p[i].get(), f[j].get(), MPFR_RNDN);
        mpfr_add(q[i + j].get(), q[i + j].get(), t.get(), MPFR_RNDN);
      }
    p = q;
  };
  for (double r : realRoots) {
    Mp negR(r);
    mpfr_neg(negR.get(), negR.get(), MPFR_RNDN);
    mulFactor({negR, Mp(1.0)});
  }
  for (auto [a, b] : complexPairs) {
    Mp ma(a), mb(b), c0, c1;
    mpfr_mul(c0.get(), ma.get(), ma.get(), MPFR_RNDN);
    mpfr_mul(mb.get(), mb.get(), mb.get(), MPFR_RNDN);
    mpfr_add(c0.get(), c0.get(), mb.get(), MPFR_RNDN);  // a^2 + b^2
    mpfr_mul_si(c1.get(), ma.get(), -2, MPFR_RNDN);     // -2a
    mulFactor({c0, c1, Mp(1.0)});
  }
  std::vector<double> c;
  for (auto& x : p) c.push_back(x.toDouble());
  return c;
}

// Value and derivative of the double-coefficient polynomial at x, in MPFR.
inline void evaluate(const std::vector<double>& c, const Mp& x, Mp& f, Mp& df) {
  mpfr_set_zero(f.get(), 1);
  mpfr_set_zero(df.get(), 1);
  for (size_t i = c.size(); i-- > 0;) {
    mpfr_mul(df.get(), df.get(), x.get(), MPFR_RNDN);
    mpfr_add(df.get(), df.get(), f.get(), MPFR_RNDN);
    mpfr_mul(f.get(), f.get(), x.get(), MPFR_RNDN);
    mpfr_add_d(f.get(), f.get(), c[i], MPFR_RNDN);
  }
}

inline int signAt(const std::vector<double>& c, const Mp& x) {
  Mp f, df;
  evaluate(c, x, f, df);
  return mpfr_sgn(f.get());
}

// A certified real root of the rounded polynomial near `start` (Newton in MPFR), or none.
struct RefRoot {
  double value;         // rounded to double
  double conditioning;  // sum |c_i| |r|^i / |g'(r)|
  double rest = 0;      // the root minus value, rounded: value + rest is it to ~2^-106
};

// |answer - root| against the root itself, not its rounding to double: a double answer
// next to `value` may be the nearer one to the root, and `value`'s own half ulp is not the
// answer's error (answer - value is exact where they are within a factor 2, Sterbenz).
inline double rootError(double answer, const RefRoot& r) {
  return std::abs((answer - r.value) - r.rest);
}

inline std::optional<RefRoot> refine(const std::vector<double>& c, double start) {
  Mp x(start), f, df, step;
  bool converged = false;
  for (int it = 0; it < 400; ++it) {
    evaluate(c, x, f, df);
    if (mpfr_zero_p(f.get())) {
      converged = true;
      break;
    }
    if (mpfr_zero_p(df.get())) return std::nullopt;
    mpfr_div(step.get(), f.get(), df.get(), MPFR_RNDN);
    mpfr_sub(x.get(), x.get(), step.get(), MPFR_RNDN);
    // |step| <= 2^-200 |x| (relative: with max(1, |x|), as until session 52, a root near
    // 1e-114 stopped after one step, 2^-106 off, and failed the certification below)
    if (mpfr_zero_p(step.get()) ||
        (!mpfr_zero_p(x.get()) && mpfr_get_exp(step.get()) < mpfr_get_exp(x.get()) - 200)) {
      converged = true;
      break;
    }
  }
  if (!converged) return std::nullopt;
  // Certify a sign change across x (1 -+ 2^-150) (or +-2^-150 at x = 0).
  Mp eps, lo, hi;
  if (mpfr_zero_p(x.get()))
    mpfr_set_d(eps.get(), std::ldexp(1.0, -150), MPFR_RNDN);
  else {
    mpfr_abs(eps.get(), x.get(), MPFR_RNDN);
    mpfr_mul_2si(eps.get(), eps.get(), -150, MPFR_RNDN);
  }
  mpfr_sub(lo.get(), x.get(), eps.get(), MPFR_RNDN);
  mpfr_add(hi.get(), x.get(), eps.get(), MPFR_RNDN);
  if (signAt(c, lo) * signAt(c, hi) >= 0) return std::nullopt;
  // Conditioning.
  Mp sum, ax, pw(1.0), t;
  mpfr_abs(ax.get(), x.get(), MPFR_RNDN);
  for (double ci : c) {
    mpfr_mul_d(t.get(), pw.get(), std::abs(ci), MPFR_RNDN);
    mpfr_add(sum.get(), sum.get(), t.get(), MPFR_RNDN);
    mpfr_mul(pw.get(), pw.get(), ax.get(), MPFR_RNDN);
  }
  evaluate(c, x, f, df);
  mpfr_abs(df.get(), df.get(), MPFR_RNDN);
  mpfr_div(sum.get(), sum.get(), df.get(), MPFR_RNDN);
  const double value = x.toDouble();
  Mp rest;
  mpfr_sub_d(rest.get(), x.get(), value, MPFR_RNDN);
  return RefRoot{value, sum.toDouble(), rest.toDouble()};
}

// All certified real roots in (lo, hi) reached by Newton from the given starts, sorted,
// duplicates (same double) removed.
inline std::vector<RefRoot> refineAll(const std::vector<double>& c,
                                      const std::vector<double>& starts, double lo, double hi) {
  std::vector<RefRoot> out;
  for (double s : starts) {
    auto r = refine(c, s);
    if (r && r->value > lo && r->value < hi) out.push_back(*r);
  }
  std::sort(out.begin(), out.end(), [](auto& a, auto& b) { return a.value < b.value; });
  out.erase(
      std::unique(out.begin(), out.end(), [](auto& a, auto& b) { return a.value == b.value; }),
      out.end());
  return out;
}

// Higham's gamma_n = n u / (1 - n u) for the unit roundoff u of the precision solved (float's
// or double's; polynomial.h's gamma is double's): the scale relativeResidual is compared with.
inline double gammaOfUnit(int n, double u) { return n * u / (1 - n * u); }

// |g(x)| in MPFR relative to sum |c_i| |x|^i: how much of a root x is, for the data.
inline double relativeResidual(const std::vector<double>& c, double x) {
  Mp mx(x), f, df, sum, pw(1.0), t, ax;
  evaluate(c, mx, f, df);
  mpfr_abs(ax.get(), mx.get(), MPFR_RNDN);
  for (double ci : c) {
    mpfr_mul_d(t.get(), pw.get(), std::abs(ci), MPFR_RNDN);
    mpfr_add(sum.get(), sum.get(), t.get(), MPFR_RNDN);
    mpfr_mul(pw.get(), pw.get(), ax.get(), MPFR_RNDN);
  }
  mpfr_abs(f.get(), f.get(), MPFR_RNDN);
  if (mpfr_zero_p(sum.get())) return 0;
  mpfr_div(f.get(), f.get(), sum.get(), MPFR_RNDN);
  return f.toDouble();
}

}  // namespace algray::test
