// Sturm-sequence solver, kept as the baseline that Yuksel's method is measured against
// (POV-Ray's approach: polysolve() in source/core/math/polynomialsolver.cpp builds the
// sequence, isolates roots by bisection on sign-variation counts and refines them with
// regula falsi). Sturm's theorem: for p0 = G, p1 = G', p_{k+1} = -rem(p_{k-1}, p_k), the
// number of distinct real roots in (a, b] is V(a) - V(b), V = sign variations of the
// sequence (Basu, Pollack, Roy, "Algorithms in Real Algebraic Geometry", Thm. 2.50).
//
// Here: the sequence in double with each member scaled to max|coefficient| = 1, a
// remainder is zero when all its coefficients are below gamma(2n) of the dividend's
// scale (then the last member is the numerical gcd and multiple roots count once);
// left-first bisection on counts isolates roots, a sign change of G on an isolating
// interval is refined by the same safeguarded Newton as Yuksel's solver, and an
// isolating interval without sign change (even multiplicity) is bisected on counts to
// the tolerance and reported as a tangent root. Depth and iterations are capped.
// The endpoint noise rules of roots_scan.h are applied by withEndRules around it.
// Known limit (tests/roots_test.cpp, TinyRootsRescale): the zero rule for remainders is
// relative to the interval's scale, so roots far below it (1e-40 in (-1, 1)) are lost
// with the remainder coefficients that carry them.
#include "roots_detail.h"
#include "roots_scan.h"

#include <algorithm>

namespace algray::roots_detail {
namespace {

struct SturmSequence {
  int size = 0;
  int deg[kMaxDegree + 1];
  double p[kMaxDegree + 1][kMaxDegree + 1];

  int variations(double x) const {
    int v = 0;
    bool havePrev = false, prevNeg = false;
    for (int k = 0; k < size; ++k) {
      const double f = horner(p[k], deg[k], x);
      if (f == 0) continue;
      const bool neg = f < 0;
      if (havePrev && neg != prevNeg) ++v;
      havePrev = true;
      prevNeg = neg;
    }
    return v;
  }
};

void normalize(double* a, int n) {
  double mx = 0;
  for (int i = 0; i <= n; ++i) mx = std::max(mx, std::abs(a[i]));
  if (mx == 0) return;
  int e = 0;
  std::frexp(mx, &e);
  // One multiplication by 2^-e per coefficient: rounded exactly as ldexp rounds (a single
  // correctly rounded operation), without a library call each.
  if (e > -1020 && e < 1020) {
    const double scale = std::ldexp(1.0, -e);
    for (int i = 0; i <= n; ++i) a[i] *= scale;
  } else {
    for (int i = 0; i <= n; ++i) a[i] = std::ldexp(a[i], -e);
  }
}

void build(const LocalPoly<double>& g, SturmSequence& s) {
  const int n = g.n;
  s.size = 2;
  s.deg[0] = n;
  copyCoeffs(g.c.data(), n + 1, s.p[0]);
  normalize(s.p[0], n);
  s.deg[1] = n - 1;
  derivative(s.p[0], n, s.p[1]);
  normalize(s.p[1], n - 1);
  const double zeroRel = gammaT<double>(2 * n);
  while (s.size <= n && s.deg[s.size - 1] > 0) {
    const double* b = s.p[s.size - 1];
    const int db = s.deg[s.size - 1];
    double r[kMaxDegree + 1];
    const int da = s.deg[s.size - 2];
    copyCoeffs(s.p[s.size - 2], da + 1, r);
    double big = 1;  // largest multiple of the divisor subtracted: the cancellation scale
    const double invLead = 1.0 / b[db];  // one division, not one per quotient term
    for (int k = da - db; k >= 0; --k) {
      const double q = r[db + k] * invLead;
      big = std::max(big, std::abs(q));
      for (int j = 0; j <= db; ++j) r[j + k] -= q * b[j];
    }
    // Remainder degree < db; coefficients at the rounding level of the division (both
    // operands are normalized to max 1, so the scale is the largest quotient term) are
    // zero.
    int dr = db - 1;
    while (dr >= 0 && std::abs(r[dr]) <= zeroRel * big) --dr;
    if (dr < 0) break;  // exact division: the last member is the gcd
    double* next = s.p[s.size];
    for (int j = 0; j <= dr; ++j) next[j] = -r[j];
    normalize(next, dr);
    s.deg[s.size] = dr;
    ++s.size;
  }
}

struct Interval {
  double a, b;
  int va, vb, depth;
};

int solveOpen(const LocalPoly<double>& g, Query q, double tol, LocalRoot<double>* out,
              int maxOut) {
  if (g.n < 1 || maxOut < 1) return 0;
  SturmSequence s;
  build(g, s);
  constexpr int kMaxDepth = 80;
  Interval stack[kMaxDepth + 2];
  int top = 0;
  stack[top++] = Interval{g.lo, g.hi, s.variations(g.lo), s.variations(g.hi), 0};
  int count = 0;
  const double* c = g.c.data();
  while (top > 0) {
    Interval iv = stack[--top];
    const int nRoots = iv.va - iv.vb;
    if (nRoots <= 0) continue;
    if (q == Query::Any) {
      out[count++] = LocalRoot<double>{iv.a + (iv.b - iv.a) / 2, false};
      return count;
    }
    const double fa = horner(c, g.n, iv.a), fb = horner(c, g.n, iv.b);
    const double width = iv.b - iv.a;
    const bool small =
        width <= std::max(tol, 4 * kUnit<double> * std::max(std::abs(iv.a), std::abs(iv.b)));
    if (nRoots == 1 && fa != 0 && fb != 0 && std::signbit(fa) != std::signbit(fb)) {
      out[count++] = LocalRoot<double>{
          newtonInBracket(c, g.noise.data(), g.n, iv.a, iv.b, fa, fb, tol), false};
    } else if (iv.depth >= kMaxDepth || small) {
      out[count++] = LocalRoot<double>{iv.a + width / 2, true};
    } else {
      double mid = bisectionPoint(iv.a, iv.b);  // in the exponent across binades
      if (!(mid > iv.a && mid < iv.b)) mid = iv.a + width / 2;
      const int vm = s.variations(mid);
      // Right half first onto the stack so that the left half is processed first.
      stack[top++] = Interval{mid, iv.b, vm, iv.vb, iv.depth + 1};
      stack[top++] = Interval{iv.a, mid, iv.va, vm, iv.depth + 1};
      continue;
    }
    if (q == Query::First || count >= maxOut) return count;
  }
  return count;
}

}  // namespace

int solveSturm(const LocalPoly<double>& g, Query q, double tol, LocalRoot<double>* out,
               int maxOut) {
  if (g.n < 1 || maxOut < 1) return 0;
  return withEndRules(g, q, out, maxOut,
                      [&](const LocalPoly<double>& inner, Query qq, LocalRoot<double>* o,
                          int m) { return solveOpen(inner, qq, tol, o, m); });
}

}  // namespace algray::roots_detail
