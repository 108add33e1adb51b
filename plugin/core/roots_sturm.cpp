// Sturm-sequence solver, kept as the baseline that Yuksel's method is measured against
// (POV-Ray's approach: polysolve() in source/core/math/polynomialsolver.cpp builds the
// sequence, isolates roots by bisection on sign-variation counts and refines them with
// regula falsi). Sturm's theorem: for p0 = G, p1 = G', p_{k+1} = -rem(p_{k-1}, p_k), the
// number of distinct real roots in (a, b] is V(a) - V(b), V = sign variations of the
// sequence (Basu, Pollack, Roy, "Algorithms in Real Algebraic Geometry", Thm. 2.50).
//
// Here: the sequence in double with each member scaled to max|coefficient| = 1, a
// remainder coefficient is zero when it is below gamma(2n) of the terms that entered it
// (build(): the rule is per coefficient), and a remainder that is zero throughout ends
// the sequence (then the last member is the numerical gcd and multiple roots count once);
// left-first bisection on counts isolates roots, a sign change of G on an isolating
// interval is refined by the same safeguarded Newton as Yuksel's solver (then checked to
// be that sign change, rootInBracket), and an isolating interval without sign change
// (even multiplicity) is bisected on counts to the tolerance and reported as a tangent
// root. Depth and iterations are capped.
// The endpoint noise rules of roots_scan.h are applied by withEndRules around it.
// Known limit (tests/roots_test.cpp, TinyRootsRescale): roots far below the interval's
// scale (1e-40 in (-1, 1)) are lost with the remainder coefficients that carry them, and
// with them the counts can go wrong elsewhere (session 41: roots 2e-13 and 4e-10 on
// (-0.087, 0.137] at degree 19, and the clear root -0.0332 went uncounted). Above degree
// 20 the sequence in double also loses roots of conditioning 1e8 and more (a degree-30
// problem's first roots of cond 5e8 and 1e11; one miss in 2000 problems at degrees 30 and
// 40 in roots_report).
#include "roots_detail.h"
#include "roots_scan.h"

#include <algorithm>

namespace algray::roots_detail {
namespace {

struct SturmSequence {
  int size = 0;
  int deg[kMaxDegree + 1];
  double p[kMaxDegree + 1][kMaxDegree + 1];

  // The count without branches on the members' signs: they are as unpredictable as the
  // roots, and GCC 12 compiled the branchy form (`if (f == 0) continue;` ...) to jumps,
  // which left its Sturm solver 1.2x slower than Clang 14's build of the same source.
  // Measured (session 40, roots_report, Intel host, two interleaved runs): Sturm on whole
  // rays of degree 6 487-493 -> 413-424 ns, 12 1169-1177 -> 953-1011, cells 0.81-0.88x;
  // the same counts (a zero member is skipped, a NaN counts as positive, as before).
  int variations(double x) const {
    int v = 0;
    bool havePrev = false, prevNeg = false;
    for (int k = 0; k < size; ++k) {
      const double f = horner(p[k], deg[k], x);
      const bool nonZero = f != 0, neg = f < 0;
      v += nonZero & havePrev & (neg != prevNeg);
      havePrev |= nonZero;
      prevNeg = nonZero ? neg : prevNeg;
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

// The zero rule, per coefficient. A remainder coefficient r_j = a_j - sum_k q_k b_{j-k}
// computed in double is off by up to gamma(m) acc_j, acc_j = |a_j| + sum_k |q_k b_{j-k}|
// after m operations (Higham, "Accuracy and Stability of Numerical Algorithms", Sec. 3.1;
// gamma(2n) leaves room for the error the members bring along). The rule was one
// threshold for the whole remainder, gamma(2n) times its largest quotient term (members
// scaled to max 1), which is the acc_j of the largest coefficients only: where the
// polynomial's values on the interval are far below its coefficients, true remainder
// coefficients sit below it and were dropped, and with them the root.
//  * -1 + s + ... + s^40 on [0, 2]: graded coefficients (4^(j-40) in the local frame); the
//    low coefficients of the third member, which decide its sign near the root v = 1/8,
//    are ~1e-22 and its successor was dropped: V(lo) = V(hi), no root.
//  * (1.1 - s)^32 - 1 on [-1.4, 1.6]: G = K (0.55 - v)^32 - K 2^-32, so the remainder of G
//    by G' is the constant -K 2^-32, ~8e-16 against coefficients up to 0.7, but 4 % of its
//    own acc_0: the sequence stopped at G' (taken as the gcd), no root.
//  (tests/roots_test.cpp, RootsComparison.SturmZeroRuleGradedCoefficients and
//  SturmZeroRuleNearPower.)
// A fuller running error bound (also the errors each member inherits, Higham Sec. 3.3)
// was tried: its first-order worst case grows along the sequence and zeroed the last
// members of ordinary degree-12 problems, which then lost roots; the members' actual
// errors stay far below it.
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
    const double* a = s.p[s.size - 2];
    const int da = s.deg[s.size - 2];
    double r[kMaxDegree + 1], q[kMaxDegree + 1];
    copyCoeffs(a, da + 1, r);
    const double invLead = 1.0 / b[db];  // one division, not one per quotient term
    for (int k = da - db; k >= 0; --k) {
      q[k] = r[db + k] * invLead;
      for (int j = 0; j < db; ++j) r[j + k] -= q[k] * b[j];  // (r[db + k] is not read again)
    }
    // Remainder degree < db; leading coefficients at the rounding level of their own terms
    // are zero. (acc_j only where tested, from the quotient: usually the top one only.)
    auto acc = [&](int j) {
      double sum = std::abs(a[j]);
      for (int k = std::max(0, j - db); k <= std::min(da - db, j); ++k)
        sum += std::abs(q[k] * b[j - k]);
      return sum;
    };
    int dr = db - 1;
    while (dr >= 0 && std::abs(r[dr]) <= zeroRel * acc(dr)) --dr;
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
  double fa, fb;  // G(a), G(b): each evaluated once, where the interval is split
  int va, vb, depth;
};

// The root of G in (a, b), where the counts found exactly one and G(a), G(b) have
// opposite signs: the safeguarded Newton of roots_detail.h, then a check that it is the
// bracket's sign change. The counts isolate real roots, not extrema: between a and b G
// may dip to its noise level without a root (a complex pair near the axis), and there
// the computed signs are rounding noise. Newton's bracket follows the sign of each
// iterate, so a noise-level iterate of fa's sign in the dip cut the root off, and the
// iteration stopped at noise level in the dip: 0.7134 was reported for the first root
// 0.6120 (cond 4e8) of a degree-30 problem of roots_report, G within noise around 0.708
// (tests/roots_test.cpp, RootsComparison.SturmBracketWithANoiseLevelDip).
// The answer r is the sign change only if G keeps fa's sign up to the clear point just
// before r's noise region (leaveNoise, roots_scan.h); else the root lies before that
// point, which becomes b. (Cost: usually one evaluation of G and its bound at r - 2 ulp.)
double rootInBracket(const LocalPoly<double>& g, double a, double b, double fa, double fb,
                     double tol) {
  const double* c = g.c.data();
  for (int tries = 0;; ++tries) {
    const double r = newtonInBracket(c, g.noise.data(), g.n, a, b, fa, fb, tol);
    if (tries == 4) return r;  // bounded work; each try cut off a dip
    // leaveNoise's first step inline, keeping the value (the usual case: r is a simple
    // root, its noise region a few ulps wide); the full search only where it is wider.
    double before = r - 2 * kUnit<double> * std::abs(r);
    double fBefore = before > a ? horner(c, g.n, before) : 0.0;
    if (!(before > a) || !(std::abs(fBefore) > hornerAbs(g.noise.data(), g.n, before))) {
      before = leaveNoise(g, r, a);
      if (!(before > a)) return r;
      fBefore = horner(c, g.n, before);
    }
    if (std::signbit(fBefore) == std::signbit(fa)) return r;
    b = before;
    fb = fBefore;
  }
}

int solveOpen(const LocalPoly<double>& g, Query q, double tol, LocalRoot<double>* out, int maxOut) {
  if (g.n < 1 || maxOut < 1) return 0;
  SturmSequence s;
  build(g, s);
  constexpr int kMaxDepth = 80;
  Interval stack[kMaxDepth + 2];
  int top = 0;
  const double* c = g.c.data();
  stack[top++] = Interval{g.lo,
                          g.hi,
                          horner(c, g.n, g.lo),
                          horner(c, g.n, g.hi),
                          s.variations(g.lo),
                          s.variations(g.hi),
                          0};
  int count = 0;
  while (top > 0) {
    Interval iv = stack[--top];
    const int nRoots = iv.va - iv.vb;
    if (nRoots <= 0) continue;
    if (q == Query::Any) {
      out[count++] = LocalRoot<double>{iv.a + (iv.b - iv.a) / 2, false};
      return count;
    }
    const double fa = iv.fa, fb = iv.fb;
    const double width = iv.b - iv.a;
    const bool small =
        width <= std::max(tol, 4 * kUnit<double> * std::max(std::abs(iv.a), std::abs(iv.b)));
    if (nRoots == 1 && fa != 0 && fb != 0 && std::signbit(fa) != std::signbit(fb)) {
      out[count++] = LocalRoot<double>{rootInBracket(g, iv.a, iv.b, fa, fb, tol), false};
    } else if (iv.depth >= kMaxDepth || small) {
      // A root without a sign change: reported only by the noise rule (|G| within its
      // rounding bound), as the other solvers' tangent roots are. At degrees 30-40 the
      // double-precision counts can be off, and a count of one where G is clearly away
      // from zero reported a point that is no root (roots_report's "false" answers: 1-2 of
      // 400 whole rays at degrees 30 and 40).
      const double mid = iv.a + width / 2;
      if (!(std::abs(horner(c, g.n, mid)) <= hornerAbs(g.noise.data(), g.n, mid))) continue;
      out[count++] = LocalRoot<double>{mid, true};
    } else {
      double mid = bisectionPoint(iv.a, iv.b);  // in the exponent across binades
      if (!(mid > iv.a && mid < iv.b)) mid = iv.a + width / 2;
      const int vm = s.variations(mid);
      const double fm = horner(c, g.n, mid);
      // Right half first onto the stack so that the left half is processed first.
      stack[top++] = Interval{mid, iv.b, fm, iv.fb, vm, iv.vb, iv.depth + 1};
      stack[top++] = Interval{iv.a, mid, iv.fa, fm, iv.va, vm, iv.depth + 1};
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
                      [&](const LocalPoly<double>& inner, Query qq, LocalRoot<double>* o, int m) {
                        return solveOpen(inner, qq, tol, o, m);
                      });
}

}  // namespace algray::roots_detail
