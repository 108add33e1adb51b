// Closed forms for degrees 1 to 4, inside the same monotone-piece sweep as the iterative
// solvers (roots_scan.h), so that the tangent and endpoint rules are the same for every
// degree. The critical points come in closed form (degree 2: the vertex; degree 3: the
// quadratic G' by the cancellation-free formula of roots_detail.h; degree 4: the cubic G',
// whose own pieces are split by the quadratic G''), and each monotone piece with a sign
// change takes the closed-form root that lies inside it, polished by Newton on the
// original polynomial (newtonFrom: usually one evaluation, the iterate is then within the
// rounding level). A closed-form value outside its piece (rounding at a near-multiple
// root) falls back to the bracketed Newton of the other solvers, so the closed form only
// ever decides where Newton starts, never which roots exist. Before all this, the
// exclusion test of Yuksel's solver (rootFree below) ends most calls on short intervals.
//
// The cubic and quartic formulas follow the accuracy devices of Flocke (TOMS Algorithm
// 954, 2015) and Orellana and De Michele (TOMS Algorithm 1010, 2020), written anew:
//  * a power-of-two rescaling x = 2^k y of the monic polynomial when its coefficients
//    are so large or small that the powers in the formulas could overflow (Flocke Sec. 2);
//  * cubic: Viete's trigonometric form for three real roots, Cardano's with the sign
//    choice of Numerical Recipes (Press et al., 3rd ed., Eqs. 5.6.10-5.6.18) for one;
//    then the two smaller roots again from the largest one by Vieta's relations, taking
//    whichever of two formulas for their sum has the smaller rounding bound (the spirit
//    of Flocke's composite deflation);
//  * quartic: Descartes' factorisation into two quadratics through the largest root of
//    the resolvent cubic (Abramowitz and Stegun 3.8.3), then the quadratic coefficients
//    re-derived from Vieta's relations beta delta = d and alpha delta + beta gamma = c
//    where the direct formula cancels (the choice TOMS 1010 makes by its error estimates),
//    polished by Newton's method on the four factorisation equations (Strobach 2010;
//    TOMS 1010 Sec. 2.3), and each quadratic solved by the stable formula.
// Unpolished, these values are within 4.7 u cond of the MPFR references on every
// well-conditioned root of tests/roots_test.cpp (spreads {1, 1e-3, 1e-6, 1e-9} included)
// and lie outside their piece for 1 of ~2800 pieces; the Newton polish on G brings the
// worst case to 1.5 u cond.
//
// Measured against Yuksel's recursion at degrees 3 and 4 (roots_report, roots_bench;
// figures in roots.cpp's solveLocal): the same accuracy (each root is polished on G either
// way) and about the same speed, Yuksel ahead by 3-6% on whole rays and tied on cells:
// the transcendentals cost what the Newton steps they save do. RootMethod::Auto therefore
// uses the closed forms at degrees 1-2 only; RootMethod::ClosedForm uses them up to 4.
// Where they do better is range: roots near 1e-40 in (-1, 1) (tests/roots_test.cpp,
// RootsClosedForm.TinyRootsRescale), which Yuksel's recursion misses.
#include "roots_detail.h"
#include "roots_scan.h"

#include <algorithm>

namespace algray::roots_detail {
namespace {

template <class T>
constexpr T pow2c(int k) {
  T r = 1;
  for (; k > 0; --k) r *= 2;
  for (; k < 0; ++k) r /= 2;
  return r;
}
// Monic coefficients within [2^(emin/8), 2^(emax/8)] keep every power the formulas form (up
// to the 6th, R^2 and Q^3 of the resolvent) in range: no rescaling needed.
template <class T>
inline constexpr T kRangeHi = pow2c<T>(std::numeric_limits<T>::max_exponent / 8);
template <class T>
inline constexpr T kRangeLo = pow2c<T>(std::numeric_limits<T>::min_exponent / 8);

int ceilDiv(int x, int d) { return x >= 0 ? (x + d - 1) / d : -((-x) / d); }

// Rescales the monic x^n + m[n-1] x^(n-1) + ... + m[0] by x = 2^k y (exact) so that every
// |m[j]| <= 1 afterwards, when its range calls for it; returns k (roots are x = 2^k y).
template <class T>
int rescale(T* m, int n) {
  T big = 0;
  for (int j = 0; j < n; ++j) big = std::max(big, std::abs(m[j]));
  if ((big <= kRangeHi<T> && big >= kRangeLo<T>) || !(big > 0) || !std::isfinite(big)) return 0;
  int k = std::numeric_limits<int>::min();
  for (int j = 0; j < n; ++j)
    if (m[j] != 0) k = std::max(k, ceilDiv(std::ilogb(m[j]) + 1, n - j));
  for (int j = 0; j < n; ++j) m[j] = std::ldexp(m[j], -k * (n - j));
  return k;
}

template <class T>
void sortSmall(T* r, int n) {
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && r[j] < r[j - 1]; --j) std::swap(r[j], r[j - 1]);
}

template <class T>
void unscale(T* r, int n, int k) {
  if (k != 0)
    for (int i = 0; i < n; ++i) r[i] = std::ldexp(r[i], k);
}

// Real roots of x^3 + a x^2 + b x + c, sorted; 1 or 3 of them (a double root shows as one
// or as two close ones, as rounding falls: the sweep does not rely on them).
template <class T>
int monicCubicRoots(T a, T b, T c, T* r) {
  T m[3] = {c, b, a};
  const int k = rescale(m, 3);
  c = m[0], b = m[1], a = m[2];
  const T a3 = a / 3;
  const T Q = a3 * a3 - b / 3;                 // (a^2 - 3b) / 9
  const T R = (a3 * a3 - b / 2) * a3 + c / 2;  // (2a^3 - 9ab + 27c) / 54
  if (Q > 0 && R * R < Q * Q * Q) {
    // Three real roots, -2 sqrt(Q) cos((theta + 2 pi j) / 3) - a/3 with theta =
    // acos(R / Q^(3/2)); the +-2pi/3 angles by the addition theorem (one sin, one cos).
    const T sq = std::sqrt(Q);
    const T phi = std::acos(std::clamp(R / (Q * sq), T(-1), T(1))) / 3;
    const T cs = std::cos(phi), h = T(0.86602540378443864676) * std::sin(phi);
    r[0] = -2 * sq * cs - a3;
    r[1] = sq * (cs - 2 * h) - a3;
    r[2] = sq * (cs + 2 * h) - a3;
    // The extreme root of largest magnitude has no cancellation; the other two have an
    // absolute error of order u |big|. Re-derive them from their product -c / big and
    // their sum, either -a - big or (b + c / big) / big, whichever rounds less.
    const int iBig = std::abs(r[0]) > std::abs(r[2]) ? 0 : 2;
    const T big = r[iBig];
    if (big != 0) {
      const T prod = -c / big;
      const bool viaB =
          std::abs(b) + std::abs(prod) < (std::abs(a) + std::abs(big)) * std::abs(big);
      const T sum = viaB ? (b - prod) / big : -a - big;
      T u0, u1;
      if (quadraticRoots(T(1), -sum, prod, u0, u1) == 2) {
        r[iBig == 0 ? 1 : 0] = u0;
        r[iBig == 0 ? 2 : 1] = u1;
        sortSmall(r, 3);
      }
    }
    unscale(r, 3, k);
    return 3;
  }
  // One real root (or a double one): A = -sgn(R) cbrt(|R| + sqrt(R^2 - Q^3)), root
  // A + Q/A - a/3 (Numerical Recipes Eqs. 5.6.15-5.6.17).
  const T A = -std::copysign(std::cbrt(std::abs(R) + std::sqrt(R * R - Q * Q * Q)), R);
  T x = (A == 0 ? T(0) : A + Q / A) - a3;
  // A root much smaller than the shift a/3 lost digits to cancellation. x = -c / (x^2 + a x
  // + b) has the contraction factor ~|x| / |z| (z the complex pair), so one step of it
  // restores them cheaply.
  if (std::abs(x) < std::abs(a3)) {
    const T den = (x + a) * x + b;
    if (den != 0) x = -c / den;
  }
  r[0] = x;
  unscale(r, 1, k);
  return 1;
}

template <class T>
T det3(const T (&m)[3][3]) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// Newton's method on the factorisation x^4 + a x^3 + b x^2 + c x + d = (x^2 + f[0] x +
// f[1])(x^2 + f[2] x + f[3]), i.e. on the four equations f0 + f2 = a, f1 + f0 f2 + f3 = b,
// f0 f3 + f1 f2 = c, f1 f3 = d (Strobach, "The fast quartic solver", J. Comput. Appl.
// Math. 234, 2010; Orellana and De Michele, TOMS 1010, Sec. 2.3): the resolvent's root
// carries the rounding of the depressed coefficients, which leaves roots much smaller
// than the largest one (a spread such as {1, 1e-3, 1e-6, 1e-9}) with errors of order
// sqrt(u) relative to themselves; two or three steps restore full relative accuracy. Each
// residual is measured against the sum of its terms' magnitudes (its rounding scale), and
// a step is kept only while that relative residual falls.
template <class T>
void refineFactors(T a, T b, T c, T d, T (&f)[4]) {
  auto residual = [&](const T(&g)[4], T(&e)[4]) {
    e[0] = g[0] + g[2] - a;
    e[1] = g[1] + g[0] * g[2] + g[3] - b;
    e[2] = g[0] * g[3] + g[1] * g[2] - c;
    e[3] = g[1] * g[3] - d;
    const T s[4] = {std::abs(a) + std::abs(g[0]) + std::abs(g[2]),
                    std::abs(b) + std::abs(g[1]) + std::abs(g[0] * g[2]) + std::abs(g[3]),
                    std::abs(c) + std::abs(g[0] * g[3]) + std::abs(g[1] * g[2]),
                    std::abs(d) + std::abs(g[1] * g[3])};
    T worst = 0;
    for (int i = 0; i < 4; ++i)
      if (e[i] != 0) worst = std::max(worst, std::abs(e[i]) / s[i]);
    return worst;
  };
  T e[4];
  T err = residual(f, e);
  for (int it = 0; it < 4 && err > 4 * kUnit<T>; ++it) {
    // The Jacobian system J (d0, d1, d2, d3) = -e, with d2 = -e0 - d0 eliminated: a 3x3
    // system whose determinant is the resultant of the two quadratics (singular exactly
    // when they share a root, where no refinement is possible).
    const T r1 = -e[0];
    T m[3][3] = {{f[2] - f[0], 1, 1}, {f[3] - f[1], f[2], f[0]}, {0, f[3], f[1]}};
    const T rhs[3] = {-e[1] - f[0] * r1, -e[2] - f[1] * r1, -e[3]};
    const T det = det3(m);
    if (!(std::abs(det) > 0) || !std::isfinite(det)) return;
    T x[3];
    for (int j = 0; j < 3; ++j) {
      T mj[3][3];
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) mj[i][k] = k == j ? rhs[i] : m[i][k];
      x[j] = det3(mj) / det;
    }
    const T g[4] = {f[0] + x[0], f[1] + x[1], f[2] + r1 - x[0], f[3] + x[2]};
    T eg[4];
    const T errG = residual(g, eg);
    if (!(errG < err)) return;
    std::copy(g, g + 4, f);
    std::copy(eg, eg + 4, e);
    err = errG;
  }
}

// Real roots of x^4 + a x^3 + b x^2 + c x + d, sorted (0 to 4; double roots as above).
template <class T>
int monicQuarticRoots(T a, T b, T c, T d, T* r) {
  T m[4] = {d, c, b, a};
  const int k = rescale(m, 4);
  d = m[0], c = m[1], b = m[2], a = m[3];
  // Depressed quartic y^4 + p y^2 + q y + s, x = y - a/4.
  const T a4 = a / 4, a4sq = a4 * a4;
  const T p = b - 6 * a4sq;
  const T q = c - 2 * a4 * b + 8 * a4sq * a4;
  const T s = d - a4 * c + a4sq * b - 3 * a4sq * a4sq;
  // Resolvent z^3 + 2p z^2 + (p^2 - 4s) z - q^2 (z = the square of the y coefficient of the
  // factors (y^2 + w y + t)(y^2 - w y + v)); its roots' product q^2 >= 0 makes the largest
  // one non-negative.
  T z[3];
  const int nz = monicCubicRoots(2 * p, p * p - 4 * s, -q * q, z);
  const T z0 = z[nz - 1];
  int n = 0;
  if (z0 > 0) {
    const T w = std::sqrt(z0), qw = q / w;
    T t = (p + z0 - qw) / 2, v = (p + z0 + qw) / 2;
    // x^2 + alpha x + beta and x^2 + gamma x + delta (y = x + a/4).
    T alpha = 2 * a4 + w, gamma = 2 * a4 - w;
    T beta = a4sq + w * a4 + t, delta = a4sq - w * a4 + v;
    // Vieta: beta delta = d, the larger one (no cancellation) fixes the smaller.
    if (std::abs(beta) > std::abs(delta)) {
      if (beta != 0) delta = d / beta;
    } else if (delta != 0) {
      beta = d / delta;
    }
    // alpha + gamma = a and alpha delta + beta gamma = c: the one of larger magnitude
    // is free of cancellation; the other by the formula with the smaller rounding bound.
    if (std::abs(alpha) >= std::abs(gamma)) {
      const T viaC = (std::abs(c) + std::abs(alpha * delta)) / std::abs(beta);
      gamma = (beta != 0 && viaC < std::abs(a) + std::abs(alpha)) ? (c - alpha * delta) / beta
                                                                  : a - alpha;
    } else {
      const T viaC = (std::abs(c) + std::abs(beta * gamma)) / std::abs(delta);
      alpha = (delta != 0 && viaC < std::abs(a) + std::abs(gamma)) ? (c - beta * gamma) / delta
                                                                   : a - gamma;
    }
    T f[4] = {alpha, beta, gamma, delta};
    refineFactors(a, b, c, d, f);
    n += quadraticRoots(T(1), f[0], f[1], r[n], r[n + 1]);
    n += quadraticRoots(T(1), f[2], f[3], r[n], r[n + 1]);
  } else {
    // q = 0 up to rounding: biquadratic in y, y^2 = the roots of u^2 + p u + s.
    T u[2];
    if (quadraticRoots(T(1), p, s, u[0], u[1]) == 2)
      for (T ui : u)
        if (ui > 0) {
          const T y = std::sqrt(ui);
          r[n++] = -y - a4;
          r[n++] = y - a4;
        }
  }
  sortSmall(r, n);
  unscale(r, n, k);
  return n;
}

// The closed-form value inside the monotone piece (a, b) of p, polished by Newton on p; the
// bracketed Newton from the secant point when there is none.
template <class T, class D>
T polishedRoot(const T* p, const T* noise, D deg, const T* cand, int nCand, T a, T b, T fa, T fb,
               T tol) {
  for (int i = 0; i < nCand; ++i)
    if (cand[i] > a && cand[i] < b) return newtonFrom(p, noise, deg, a, b, fa, cand[i], tol);
  return newtonInBracket(p, noise, deg, a, b, fa, fb, tol);
}

// Roots of the quadratic p (degree 2, p[2] != 0) in (lo, hi), sorted.
template <class T>
int quadraticIn(const T* p, T lo, T hi, T* out) {
  T r0, r1;
  int k = 0;
  if (quadraticRoots(p[2], p[1], p[0], r0, r1) == 2) {
    if (r0 > lo && r0 < hi) out[k++] = r0;
    if (r1 > lo && r1 < hi && r1 != r0) out[k++] = r1;
  }
  return k;
}

// The exclusion test of Yuksel's solver (roots_yuksel.cpp, rootFreeOrder) for the first
// two orders, written out for the closed forms: with the Taylor coefficients t_j of G at
// the midpoint m of (lo, hi) and the radius r, for |v - m| <= r
//   |G(v)| >= |t_0| - sum_{j>=1} |t_j| r^j,   |G'(v)| >= |t_1| - sum_{j>=2} j |t_j| r^(j-1)
// (Taylor's theorem), minus the rounding of the shift, gamma(2n+2) times the same sums
// over the shift of |C|, and, for G itself, its noise bound. Returns 0 when G has no root
// (not even a noise-level one), 1 when G is monotone (no critical point), else 2. On a
// cell-sized interval most calls end here.
template <class T, class D>
int rootFree(const LocalPoly<T>& g, D deg) {
  const int n = deg;
  T t[kMaxDegree + 1], ta[kMaxDegree + 1];
  const T r = midpointTaylor(g, deg, t, ta);
  const T gShift = gammaT<T>(2 * n + 2);
  T rest0 = 0, err0 = 0, rest1 = 0, err1 = 0;
  for (int j = n; j >= 1; --j) {
    rest0 = (rest0 + std::abs(t[j])) * r;
    err0 = (err0 + ta[j]) * r;
  }
  for (int j = n; j >= 2; --j) {
    rest1 = (rest1 + j * std::abs(t[j])) * r;
    err1 = (err1 + j * ta[j]) * r;
  }
  const T noise = hornerAbs(g.noise.data(), deg, std::max(std::abs(g.lo), std::abs(g.hi)));
  if (std::abs(t[0]) > rest0 + gShift * (err0 + ta[0]) + noise) return 0;
  if (std::abs(t[1]) > rest1 + gShift * (err1 + ta[1])) return 1;
  return 2;
}

template <class T>
int solveCubic(const LocalPoly<T>& g, Query q, T tol, LocalRoot<T>* out, int maxOut) {
  const T* c = g.c.data();
  const int free = rootFree(g, Deg<3>{});
  if (free == 0) return 0;
  T d[3], crit[2];
  derivative(c, Deg<3>{}, d);  // the same critical points as Yuksel's recursion
  const int nCrit = free == 1 ? 0 : quadraticIn(d, g.lo, g.hi, crit);
  T roots[3];
  int nRoots = -1;  // the closed form is computed for the first piece that needs it
  auto piece = [&](T a, T b, T fa, T fb) {
    if (nRoots < 0) nRoots = monicCubicRoots(c[2] / c[3], c[1] / c[3], c[0] / c[3], roots);
    return polishedRoot(c, g.noise.data(), Deg<3>{}, roots, nRoots, a, b, fa, fb, tol);
  };
  return scanPieces(g, Deg<3>{}, crit, nCrit, q, piece, out, maxOut);
}

template <class T>
int solveQuartic(const LocalPoly<T>& g, Query q, T tol, LocalRoot<T>* out, int maxOut) {
  const T* c = g.c.data();
  // Critical points: the roots of the cubic G' / 4 in (lo, hi), found like G's own in
  // solveCubic, but as sign changes only (as in Yuksel's recursion: G is monotone through
  // a point where G' only touches zero).
  const int free = rootFree(g, Deg<4>{});
  if (free == 0) return 0;
  T d[4], dd[3], split[2], dNoise[4];
  derivative(c, Deg<4>{}, d);
  derivative(d, Deg<3>{}, dd);
  const int nSplit = free == 1 ? 0 : quadraticIn(dd, g.lo, g.hi, split);
  for (int i = 0; i <= 3; ++i) dNoise[i] = gammaT<T>(7) * std::abs(d[i]);
  T dRoots[3], crit[3];
  int nDRoots = -1, nCrit = 0;
  T xa = g.lo, fa = horner(d, Deg<3>{}, xa);
  for (int i = 0; i <= nSplit && free == 2; ++i) {
    const bool interior = i < nSplit;
    const T xb = interior ? split[i] : g.hi;
    const T fb = horner(d, Deg<3>{}, xb);
    if (fb == 0) {
      if (interior) crit[nCrit++] = xb;
    } else if (fa != 0 && signBit(fa) != signBit(fb)) {
      if (nDRoots < 0) nDRoots = monicCubicRoots(d[2] / d[3], d[1] / d[3], d[0] / d[3], dRoots);
      // To full precision whatever the tolerance, as in Yuksel's recursion (roots_yuksel.cpp,
      // solveDirect): a critical point off by the tolerance can put both ends of a pair of
      // roots on one side of it (the quartic with roots near 1e-56, 6e4 and 9e51 on (0,
      // 1.8e52] at relTolerance 1e-3 answered 9e51 until session 53).
      crit[nCrit++] = polishedRoot(d, dNoise, Deg<3>{}, dRoots, nDRoots, xa, xb, fa, fb, T(0));
    }
    xa = xb;
    fa = fb;
  }
  T roots[4];
  int nRoots = -1;
  auto piece = [&](T a, T b, T fa4, T fb4) {
    if (nRoots < 0)
      nRoots = monicQuarticRoots(c[3] / c[4], c[2] / c[4], c[1] / c[4], c[0] / c[4], roots);
    return polishedRoot(c, g.noise.data(), Deg<4>{}, roots, nRoots, a, b, fa4, fb4, tol);
  };
  return scanPieces(g, Deg<4>{}, crit, nCrit, q, piece, out, maxOut);
}

}  // namespace

template <class T>
int solveClosedForm(const LocalPoly<T>& g, Query q, T tol, LocalRoot<T>* out, int maxOut) {
  if (g.n < 1 || maxOut < 1) return 0;
  if (g.n > 4) return solveYuksel(g, q, tol, out, maxOut);
  const T* c = g.c.data();
  if (g.n >= 3 && q == Query::Any &&
      (g.n == 3 ? endpointsStraddle(g, Deg<3>{}) : endpointsStraddle(g, Deg<4>{}))) {
    out[0] = LocalRoot<T>{g.lo + (g.hi - g.lo) / 2, false};  // as solveYuksel does
    return 1;
  }
  if (g.n == 3) return solveCubic(g, q, tol, out, maxOut);
  if (g.n == 4) return solveQuartic(g, q, tol, out, maxOut);
  if (g.n == 1) {
    auto piece = [&](T a, T b, T fa, T fb) {
      const T r = -c[0] / c[1];
      return (r > a && r < b) ? r : newtonInBracket(c, g.noise.data(), Deg<1>{}, a, b, fa, fb, tol);
    };
    return scanPieces(g, Deg<1>{}, static_cast<const T*>(nullptr), 0, q, piece, out, maxOut);
  }
  // Degree 2: the vertex -c1 / (2 c2) splits the interval into two monotone pieces.
  T crit[1];
  const T vertex = -c[1] / (2 * c[2]);
  const int nCrit = (vertex > g.lo && vertex < g.hi) ? 1 : 0;
  crit[0] = vertex;
  T r[2];
  const int nr = quadraticRoots(c[2], c[1], c[0], r[0], r[1]);
  auto piece = [&](T a, T b, T fa, T fb) {
    for (int i = 0; i < nr; ++i)
      if (r[i] > a && r[i] < b) return r[i];
    return newtonInBracket(c, g.noise.data(), Deg<2>{}, a, b, fa, fb, tol);
  };
  return scanPieces(g, Deg<2>{}, crit, nCrit, q, piece, out, maxOut);
}

template int solveClosedForm<double>(const LocalPoly<double>&, Query, double, LocalRoot<double>*,
                                     int);
template int solveClosedForm<float>(const LocalPoly<float>&, Query, float, LocalRoot<float>*, int);

}  // namespace algray::roots_detail
