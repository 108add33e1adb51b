// Bernstein/Descartes subdivision, the second comparison solver. On [0, 1] the number of
// sign variations of the Bernstein coefficients bounds the number of roots and has the
// same parity (Descartes' rule in Bernstein form; Lane and Riesenfeld, "Bounds on a
// polynomial", BIT 21, 1981): 0 variations means no root, 1 means exactly one simple
// root. Otherwise de Casteljau splits the interval in half (Farin, "Curves and Surfaces
// for CAGD", Sec. 4.2) and the halves are examined left first, so the first root found
// is the first root. A one-variation interval on which G changes sign is refined by the
// same safeguarded Newton as the other solvers; an interval that keeps several
// variations down to the depth cap or to the tolerance is a cluster or a multiple root
// and its midpoint is reported as a tangent root.
// The endpoint noise rules of roots_scan.h are applied by withEndRules around it.
#include "roots_detail.h"
#include "roots_scan.h"

#include <algorithm>

namespace algray::roots_detail {
namespace {

constexpr int kMaxDepth = 60;

struct Node {
  double b[kMaxDegree + 1];
  double u0, u1;
  int depth;
};

int signVariations(const double* b, int n) {
  int v = 0;
  bool havePrev = false, prevNeg = false;
  for (int i = 0; i <= n; ++i) {
    if (b[i] == 0) continue;
    const bool neg = b[i] < 0;
    if (havePrev && neg != prevNeg) ++v;
    havePrev = true;
    prevNeg = neg;
  }
  return v;
}

// Power form to Bernstein form on u in [0, 1], v = lo + (hi - lo) u, by Horner's rule
// carried out in the Bernstein basis: G = c_0 + v (c_1 + v (c_2 + ...)), where a
// degree-k polynomial with coefficients b_0..b_k times v (Bernstein coefficients lo, hi
// on the interval) has the degree-(k+1) coefficients
//   b'_i = ((k + 1 - i) lo b_i + i hi b_{i-1}) / (k + 1)
// (the product rule of Farouki and Rajan, "Algorithms for polynomials in Bernstein
// form", CAGD 5, 1988, Sec. 3; the blossom of v^j at lo^(n-i) hi^i, Ramshaw's blossoming
// principle), and adding c_j adds it to every coefficient (the b_i of 1 are all 1).
// Every step mixes values of magnitude <= max(|lo|, |hi|) = M <= 1 (the coefficients of
// the same recursion on |c|, |lo|, |hi| are those of sum |c_j| v^j on [|lo|, |hi|], each
// <= sum |c_j| M^j), so with 7 roundings a step the b_i are accurate to gamma(7n)
// sum |c_j| M^j: a few times the noise of one evaluation of G at the interval's far end.
// (Also cheaper: n^2 / 2 such steps, where the change of basis below took a division per
// term.) Test: tests/roots_test.cpp, RootsComparison.BernsteinBasisOnAWideInterval.
// It replaced a Taylor shift to lo, a scaling by w^j (w = hi - lo) and the change of
// basis b_i = sum_{j <= i} C(i, j) / C(n, j) a_j (Farin, "Curves and Surfaces for CAGD",
// Sec. 5.x), whose intermediate coefficients are those of G on [lo, lo + w] in powers of
// u: their magnitudes sum to sum |c_j| (|lo| + w)^j, up to 3^n times the above (w up to 2
// in the local frame). (1 - s)^35 - 1 on [-1.5, 1.5] (v = s / 2: G = (1 - 2v)^35 - 1,
// (|lo| + w)^35 ~ 5.5^35 ~ 1e26 against 2.5^35 ~ 1e14) got Bernstein coefficients wrong
// by ~1e10 where G is ~1e3 and reported the non-root -0.2567 as a tangent root.
void toBernstein(const LocalPoly<double>& g, double* b) {
  const int n = g.n;
  const double lo = g.lo, hi = g.hi;
  const double* c = g.c.data();
  b[0] = c[n];                   // degree 0
  for (int k = 0; k < n; ++k) {  // b holds degree k: times v, plus c[n - k - 1]
    const double inv = 1.0 / (k + 1), add = c[n - k - 1];
    b[k + 1] = hi * b[k] + add;
    for (int i = k; i >= 1; --i) b[i] = ((k + 1 - i) * lo * b[i] + i * hi * b[i - 1]) * inv + add;
    b[0] = lo * b[0] + add;
  }
}

// de Casteljau at the dyadic ratio f: left into l, right into r.
void split(const double* b, int n, double f, double* l, double* r) {
  double t[kMaxDegree + 1];
  copyCoeffs(b, n + 1, t);
  const double e = 1 - f;  // exact for the ratios used
  l[0] = t[0];
  r[n] = t[n];
  for (int k = 1; k <= n; ++k) {
    for (int i = 0; i <= n - k; ++i) t[i] = e * t[i] + f * t[i + 1];
    l[k] = t[0];
    r[n - k] = t[n - k];
  }
}

int solveOpen(const LocalPoly<double>& g, Query q, double tol, LocalRoot<double>* out, int maxOut) {
  if (g.n < 1 || maxOut < 1) return 0;
  const int n = g.n;
  Node stack[kMaxDepth + 2];
  int top = 0;
  toBernstein(g, stack[0].b);
  stack[0].u0 = 0;
  stack[0].u1 = 1;
  stack[0].depth = 0;
  top = 1;
  int count = 0;
  const double* c = g.c.data();
  while (top > 0) {
    Node& nd = stack[top - 1];
    const int v = signVariations(nd.b, n);
    if (v == 0) {
      --top;
      continue;
    }
    const double va = g.lo + (g.hi - g.lo) * nd.u0, vb = g.lo + (g.hi - g.lo) * nd.u1;
    const double width = vb - va;
    if (v == 1 || q == Query::Any) {
      if (q == Query::Any && v % 2 == 1) {
        out[count++] = LocalRoot<double>{va + width / 2, false};
        return count;
      }
      const double fa = horner(c, n, va), fb = horner(c, n, vb);
      if (v == 1 && fa != 0 && fb != 0 && std::signbit(fa) != std::signbit(fb)) {
        out[count++] =
            LocalRoot<double>{newtonInBracket(c, g.noise.data(), n, va, vb, fa, fb, tol), false};
        --top;
        if (q != Query::All || count >= maxOut) return count;
        continue;
      }
    }
    const bool small =
        width <= std::max(tol, 4 * kUnit<double> * std::max(std::abs(va), std::abs(vb)));
    if (nd.depth >= kMaxDepth || small) {
      out[count++] = LocalRoot<double>{va + width / 2, true};
      --top;
      if (q != Query::All || count >= maxOut) return count;
      continue;
    }
    // Replace the node by its right half and push the left half on top.
    Node& right = nd;
    Node& left = stack[top];
    // Split at the middle unless G is within its noise there: a root at a split point is
    // an end of both halves, where the one-variation bracket's Newton converged to it
    // from the left half (not monotone there: the half's own root was lost) and the right
    // half reported it again ((s - 0.1)(s - 0.5)(s - 0.9) on (0, 1) gave 0.5 twice and no
    // 0.1). The same off-centre ratios as the subdivision of roots_subdivide.h.
    double f = 0.5;
    for (const double ratio : {0.5, 0.4375, 0.5625, 0.375, 0.625}) {
      const double vm = g.lo + (g.hi - g.lo) * (nd.u0 + (nd.u1 - nd.u0) * ratio);
      if (std::abs(horner(c, n, vm)) > hornerAbs(g.noise.data(), n, vm)) {
        f = ratio;
        break;
      }
    }
    double l[kMaxDegree + 1], r[kMaxDegree + 1];
    split(nd.b, n, f, l, r);
    const double mid = nd.u0 + (nd.u1 - nd.u0) * f;
    copyCoeffs(l, n + 1, left.b);
    left.u0 = nd.u0;
    left.u1 = mid;
    left.depth = nd.depth + 1;
    copyCoeffs(r, n + 1, right.b);
    right.u0 = mid;
    right.depth = left.depth;
    ++top;
  }
  return count;
}

}  // namespace

int solveBernstein(const LocalPoly<double>& g, Query q, double tol, LocalRoot<double>* out,
                   int maxOut) {
  if (g.n < 1 || maxOut < 1) return 0;
  return withEndRules(g, q, out, maxOut,
                      [&](const LocalPoly<double>& inner, Query qq, LocalRoot<double>* o, int m) {
                        return solveOpen(inner, qq, tol, o, m);
                      });
}

}  // namespace algray::roots_detail
