#pragma once
// A minimal RAII wrapper of an MPFR number for high-precision references in tests and
// benchmarks (independent of everything algray computes in double).
#include <mpfr.h>

#include <utility>

namespace algray::test {

class Mp {
 public:
  static constexpr mpfr_prec_t kPrecision = 320;

  Mp() { mpfr_init2(v_, kPrecision), mpfr_set_zero(v_, 1); }
  Mp(double x) { mpfr_init2(v_, kPrecision), mpfr_set_d(v_, x, MPFR_RNDN); }  // NOLINT
  Mp(const Mp& o) { mpfr_init2(v_, kPrecision), mpfr_set(v_, o.v_, MPFR_RNDN); }
  Mp& operator=(const Mp& o) {
    mpfr_set(v_, o.v_, MPFR_RNDN);
    return *this;
  }
  ~Mp() { mpfr_clear(v_); }

  double toDouble() const { return mpfr_get_d(v_, MPFR_RNDN); }
  mpfr_ptr get() { return v_; }
  mpfr_srcptr get() const { return v_; }

  friend Mp operator+(const Mp& a, const Mp& b) { return op(mpfr_add, a, b); }
  friend Mp operator-(const Mp& a, const Mp& b) { return op(mpfr_sub, a, b); }
  friend Mp operator*(const Mp& a, const Mp& b) { return op(mpfr_mul, a, b); }
  friend Mp operator/(const Mp& a, const Mp& b) { return op(mpfr_div, a, b); }
  Mp& operator+=(const Mp& b) { return *this = *this + b; }
  Mp& operator*=(const Mp& b) { return *this = *this * b; }
  friend Mp abs(const Mp& a) {
    Mp r;
    mpfr_abs(r.v_, a.v_, MPFR_RNDN);
    return r;
  }

 private:
  template <class F>
  static Mp op(F f, const Mp& a, const Mp& b) {
    Mp r;
    f(r.v_, a.v_, b.v_, MPFR_RNDN);
    return r;
  }
  mpfr_t v_;
};

}  // namespace algray::test
