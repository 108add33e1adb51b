#pragma once
// The top-level sweep shared by the critical-point solvers (Yuksel, closed forms): given
// the sorted critical points x_1 < ... < x_k of G in (lo, hi), G is monotone on each piece
// of lo = x_0 < x_1 < ... < x_k < x_{k+1} = hi, so a piece whose ends have opposite signs
// holds exactly one root and any other piece none (Yuksel, "High-Performance Polynomial
// Solver with Error Bounds", HPG 2022, Sec. 3).
//
// Rounding noise is handled at the piece ends. A point x_i is "zero" when
// |G(x_i)| <= noise(x_i), the bound of LocalPoly (caller's coefficient error + mapping +
// Horner rounding). Consecutive zero points form a cluster, which is one root:
//  * a cluster at an interior critical point is the tangent (even-multiplicity) rule: the
//    data cannot tell whether G touches zero there, so the extremum is reported as a
//    root. Trade-off: a near miss whose minimum |G| is below the bound (a ray passing
//    within about sqrt(noise / G'') of the surface) is reported as a grazing hit; a
//    real tangent hit is never lost. Without the rule, a grazing ray hits or misses by
//    the sign of rounding errors, which shows as speckle on silhouettes.
//  * a cluster that contains x_0 = lo is the root at lo (a ray's own origin, or the
//    previous root when the caller asks for the next one with lo = previous root): it is
//    NOT reported, so repeated calls never return the same root twice, tangent or not;
//    unless g.closedLo (lo bounds a region): then it is reported like an interior one.
//  * a cluster that contains x_{k+1} = hi but no interior point is a root within noise of
//    hi: it is reported (at hi), so two intervals sharing an endpoint report a root on it
//    exactly once (the left one reports it, the right one excludes it as its lo).
// A sign change between two non-zero points gives a simple root, refined by `piece`.
//
// A cluster does not always hold the piece's root: the noise bound grows with |v| (on a
// long span at degree 30-40 it reaches |G| over a third of the interval), so a monotone
// piece can run from a clearly non-zero end into a noise-level one with its simple,
// well-conditioned root far from that end ((1.1 - s)^33 - 1 on [-1.4, 1.6]: the root 0.1
// was lost and hi reported). Where the noise shrinks into the piece, the sweep therefore
// looks for a clearly non-zero point of the other sign between the cluster and the
// piece's clear end (clearCrossing); one found proves a root there (the bounds are
// rigorous), which is reported as a simple root beside the cluster.
//
// The noise-before query (LocalPoly::window > 0, RootOptions::noiseBefore; Query::First):
// the tangent rule looks at critical points, but a monotone piece can come within G's noise
// bound away from its ends and its root too, on a shelf where G' is small but not zero and
// the exact function (within the coefficients' errors of G) may cross zero twice. At degree
// 40 with terms of 1e135 a piece from a clear end at 0.689 to its root at 0.693634 had G
// within its noise over [0.6908, 0.6935], where the surface's f had two roots (session 32's
// open case; the hit was f's third root). noiseBefore reports such a stretch (see there).
#include "roots_detail.h"

namespace algray::roots_detail {

// The rest of noiseBefore past its first test, out of line (rare: where G at y = r - window
// is within its noise or below the noise bound at the piece's clear end a). G(y) = f,
// noise bound n.
template <class T, class D>
[[gnu::noinline, gnu::cold]] T noiseWalk(const LocalPoly<T>& g, D deg, T a, T fa, T na, T r, T y,
                                         T f, T n, bool& noisy) {
  const bool neg = signBit(fa);
  auto clear = [&] { return std::abs(f) > n && signBit(f) == neg; };  // of fa's sign
  auto clearAt = [&](T x) {  // G and its bound at x into f, n
    hornerNoise(g.c.data(), g.noise.data(), deg, x, f, n);
    return clear();
  };
  T c = y;  // the walk's target, clear of fa's sign
  if (!clear()) {
    // The root's own noise region reaches y: it is reported (noisy), and the walk goes to
    // the last clear point before it (steps doubling back; one of the other sign proves a
    // root there, which is reported).
    noisy = true;
    for (T step = 2 * g.window;; step *= 2) {
      c = y - step;
      if (!(c > a)) return r;  // within noise back to a: the caller looks behind it all
      if (clearAt(c)) break;
      if (std::abs(f) > n) return c;
    }
  }
  T p = a, np = na, step = (c - a) / 2;
  for (int it = 0; it < 64; ++it) {
    const T q = std::min(p + step, c);
    if (!(q > p)) break;
    if (!clearAt(q)) {
      noisy = true;
      return q;
    }
    if (std::abs(f) > std::max(np, n)) {
      if (q == c) return r;
      p = q;
      np = n;
      step *= 2;
    } else {
      step /= 2;
    }
  }
  noisy = true;  // not proved within the cap: the caller looks
  return r;
}

// Whether G at y is within its noise bound or not of fa's sign (false for y <= a).
template <class T, class D>
bool noiseAt(const LocalPoly<T>& g, D deg, T fa, T y, T a) {
  if (!(y > a)) return false;
  T f, n;
  hornerNoise(g.c.data(), g.noise.data(), deg, y, f, n);
  return !(std::abs(f) > n) || signBit(f) != signBit(fa);
}

// Whether G, monotone on [a, r] with its root at r and clear of its noise at a (value fa,
// noise bound na), comes within its noise bound in [a, r - window]. The proof: on [p, q]
// inside the piece |G| >= |G(q)| (G moves towards 0 up to r) and the noise bound, a
// polynomial in |v| with non-negative coefficients, is at most its larger end value, so
// [p, q] is clear where |G(q)| > max(noise(p), noise(q)) with G(q) of G(a)'s sign. One
// evaluation at y = r - window settles the common case, [a, y] at once; else a walk from a
// (steps doubling after a proof, halving after a failure) proves [a, y] or meets a point
// within noise. Within the window the root's own noise region is its accuracy, the
// caller's to judge; where that region reaches past y, the walk proves the stretch before
// it. Returns r with noisy = false (clear), r with noisy = true (the root's noise region
// wider than the window, or not proved within the walk's cap), or a point within noise
// before the root's own region with noisy = true (a root of the exact function may lie
// before it: the caller looks there).
template <class T, class D>
T noiseBefore(const LocalPoly<T>& g, D deg, T a, T fa, T na, T r, bool& noisy) {
  noisy = false;
  const T y = r - g.window;
  if (!(y > a)) return r;
  T f, n;
  hornerNoise(g.c.data(), g.noise.data(), deg, y, f, n);
  if (std::abs(f) > std::max(na, n) && signBit(f) == signBit(fa)) return r;
  return noiseWalk(g, deg, a, fa, na, r, y, f, n, noisy);
}

// clearCrossing of roots_detail.h on G.
template <class T, class D>
bool clearCrossing(const LocalPoly<T>& g, D deg, T clear, T fClear, T noisy, T& m, T& fm) {
  return clearCrossing(g.c.data(), g.noise.data(), deg, clear, fClear, noisy, m, fm);
}

template <class T, class D, class Piece>
int scanPieces(const LocalPoly<T>& g, D deg, const T* crit, int nCrit, Query q, Piece&& piece,
               LocalRoot<T>* out, int maxOut) {
  int count = 0;
  auto emit = [&](T v, bool tangent) {
    if (count < maxOut) out[count++] = LocalRoot<T>{v, tangent};
    return q == Query::All && count < maxOut;  // keep going?
  };
  // The root of the monotone piece [a, b] whose end a is clear of noise (na: its bound),
  // with the noise-before query where asked.
  auto emitChecked = [&](T a, T fa, T na, T b, T fb) {
    if (q == Query::Any) return emit(a + (b - a) / 2, false);
    const T r = piece(a, b, fa, fb);
    bool noisy = false;
    const T v = g.window > 0 ? noiseBefore(g, deg, a, fa, na, r, noisy) : r;
    return emit(v, noisy);
  };

  T xPrev = g.lo, fPrev, nPrev;
  hornerNoise(g.c.data(), g.noise.data(), deg, xPrev, fPrev, nPrev);
  bool zPrev = std::abs(fPrev) <= nPrev;
  // Open cluster state.
  bool inCluster = zPrev, clusterAtLo = zPrev, clusterHasInterior = false;
  T best = xPrev, bestAbs = std::abs(fPrev);

  for (int i = 0; i <= nCrit; ++i) {
    const bool interior = i < nCrit;
    const T x = interior ? crit[i] : g.hi;
    T f, nx;
    hornerNoise(g.c.data(), g.noise.data(), deg, x, f, nx);
    const bool z = std::abs(f) <= nx;
    T m, fm;
    if (z && !inCluster && clearCrossing(g, deg, xPrev, fPrev, x, m, fm)) {
      // Into a cluster: the piece's root lies clearly before it, in (xPrev, m).
      if (!emitChecked(xPrev, fPrev, nPrev, m, fm)) return count;
    }
    if (z) {
      if (!inCluster) {
        inCluster = true;
        clusterAtLo = false;
        clusterHasInterior = false;
        bestAbs = std::numeric_limits<T>::infinity();
      }
      if (interior && (!clusterHasInterior || std::abs(f) < bestAbs)) {
        best = x;
        bestAbs = std::abs(f);
        clusterHasInterior = true;
      } else if (!interior && !clusterHasInterior) {
        best = x;  // only hi itself: a root within noise of hi
      }
    } else {
      if (inCluster) {
        inCluster = false;
        if ((!clusterAtLo || g.closedLo) && !emit(best, true)) return count;
        // Out of a cluster: the piece's root may lie clearly after it, in (m, x).
        if (clearCrossing(g, deg, x, f, xPrev, m, fm) &&
            !emitChecked(m, fm, g.window > 0 ? hornerAbs(g.noise.data(), deg, m) : T(0), x, f))
          return count;
      } else if (!zPrev && signBit(f) != signBit(fPrev)) {
        if (!emitChecked(xPrev, fPrev, nPrev, x, f)) return count;
      }
    }
    xPrev = x;
    fPrev = f;
    nPrev = nx;
    zPrev = z;
  }
  if (inCluster && (!clusterAtLo || g.closedLo)) emit(best, true);
  return count;
}

// True when G(lo) and G(hi) are both clearly non-zero with opposite signs: a root exists
// and the occlusion query can answer without any critical point.
template <class T, class D>
bool endpointsStraddle(const LocalPoly<T>& g, D deg) {
  const T fa = horner(g.c.data(), deg, g.lo), fb = horner(g.c.data(), deg, g.hi);
  return signBit(fa) != signBit(fb) && std::abs(fa) > hornerAbs(g.noise.data(), deg, g.lo) &&
         std::abs(fb) > hornerAbs(g.noise.data(), deg, g.hi);
}

}  // namespace algray::roots_detail

namespace algray::roots_detail {

// The endpoint rules above for the comparison solvers (Sturm, Bernstein), which find the
// roots in the open interval without critical points and, near a root on an end, would
// count it by the sign of rounding errors. They run unchanged unless G(lo) or G(hi) is
// within noise; then that end is first moved inwards to the nearest point where G is
// clearly non-zero (steps doubling from 2 ulp: the noise region of a simple root is a
// few ulps wide), the solver runs on what is left, and the cut-off part is the root at lo
// (not reported) or within noise of hi (reported as hi), as in scanPieces. Approximation:
// a separate root within twice the noise region's width of a noise-level end merges with
// it (scanPieces tells them apart by the extremum between them).
// A step that would reach `to` is replaced by halving what is left of the way there: the
// noise region of an end can cover most of the interval (the bound grows with |v|: at
// degree 40, a root at hi = 0.93 had G within noise down to below hi - 1/4, and the next
// step, hi - 1/2, passed lo = 0.45), and giving up there took the whole interval for the
// end's cluster and lost the clear root 0.49 (tests/roots_test.cpp,
// RootsComparison.NoiseRegionOverMostOfTheInterval).
template <class T>
T leaveNoise(const LocalPoly<T>& g, T x, T to) {
  const T dir = to > x ? T(1) : T(-1);
  T step = std::max(2 * kUnit<T> * std::abs(x), std::numeric_limits<T>::min());
  T last = x;  // the last point tried: within noise
  for (int i = 0; i < 2 * std::numeric_limits<T>::max_exponent + 8; ++i, step *= 2) {
    T y = x + dir * step;
    if (!(dir * (to - y) > 0)) y = last + (to - last) / 2;
    if (y == last || y == to) return to;
    if (std::abs(horner(g.c.data(), g.n, y)) > hornerAbs(g.noise.data(), g.n, y)) return y;
    last = y;
  }
  return to;
}

template <class T, class Solve>
int withEndRules(const LocalPoly<T>& g, Query q, LocalRoot<T>* out, int maxOut, Solve&& solve) {
  auto isZero = [&](T x) {
    return std::abs(horner(g.c.data(), g.n, x)) <= hornerAbs(g.noise.data(), g.n, x);
  };
  const bool zLo = isZero(g.lo), zHi = isZero(g.hi);
  if (!zLo && !zHi) return solve(g, q, out, maxOut);
  LocalPoly<T> inner = g;
  inner.closedLo = false;  // its lo, if moved, is not the region's
  // The doubling steps of leaveNoise can jump over a clear stretch of the other sign
  // within a wide noise region (root near hi = 0.93 at degree 40: from hi - 1/4, within
  // noise, to 0.467, clear, over the root 0.493 and the clear stretch after it): as in
  // scanPieces, a clear point of the other sign between the new end and the noisy one
  // (clearCrossing) proves a root there, and the end moves on to that point.
  T m, fm;
  if (zLo) {
    inner.lo = leaveNoise(g, g.lo, g.hi);
    if (inner.lo < g.hi &&
        clearCrossing(g, g.n, inner.lo, horner(g.c.data(), g.n, inner.lo), g.lo, m, fm))
      inner.lo = m;
  }
  if (zHi) {
    inner.hi = leaveNoise(g, g.hi, inner.lo);
    if (inner.hi > inner.lo &&
        clearCrossing(g, g.n, inner.hi, horner(g.c.data(), g.n, inner.hi), g.hi, m, fm))
      inner.hi = m;
  }
  if (!(inner.lo < inner.hi)) {        // G within noise all the way: one cluster
    if (zLo && !g.closedLo) return 0;  // ... containing lo
    out[0] = LocalRoot<T>{zLo ? g.lo : g.hi, true};
    return 1;
  }
  int count = 0;
  if (zLo && g.closedLo) {  // the cut-off part at lo is a root there
    out[count++] = LocalRoot<T>{g.lo, true};
    if (q != Query::All || count >= maxOut) return count;
  }
  count += solve(inner, q, out + count, maxOut - count);
  if (zHi && count < (q == Query::All ? maxOut : 1)) out[count++] = LocalRoot<T>{g.hi, true};
  return count;
}

}  // namespace algray::roots_detail
