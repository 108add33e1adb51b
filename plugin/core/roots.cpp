// Public entry points of roots.h: input checks, the map to the local frame
// (roots_frame.h) and back, the pieces of a wide dynamic range, the dispatch by method and
// degree.
#include "algray/roots.h"

#include "roots_detail.h"
#include "roots_frame.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <sstream>
#include <string>
#include <utility>

namespace algray {
namespace {

using roots_detail::exponentOf;
using roots_detail::Frame;
using roots_detail::gammaT;
using roots_detail::LocalPoly;
using roots_detail::LocalRoot;
using roots_detail::Query;
using roots_detail::rangeSplit;
using roots_detail::scale2;
using roots_detail::toCaller;
using roots_detail::toLocal;

[[noreturn, gnu::cold, gnu::noinline]] void throwSizeError(size_t nc, size_t nerr,
                                                           const char* where) {
  if (nc > static_cast<size_t>(kMaxDegree + 1))
    throw Error(std::string(where) + ": " + std::to_string(nc) +
                " coefficients, more than degree kMaxDegree = " + std::to_string(kMaxDegree) +
                " allows");
  throw Error(std::string(where) + ": error bound has " + std::to_string(nerr) + " entries for " +
              std::to_string(nc) + " coefficients");
}

// A method outside the enumeration, or a tolerance that is NaN, negative or above 1 (the
// whole interval), was taken for the default until session 46: a caller's mistake then
// solved something else than asked, silently.
[[noreturn, gnu::noinline, gnu::cold]] void throwOptionsError(const RootOptions& o,
                                                              const char* where) {
  if (!validRootMethod(o.method))
    throw Error(std::string(where) + ": RootOptions::method " +
                std::to_string(static_cast<int>(o.method)) + " is not a RootMethod");
  std::ostringstream os;
  os << where << ": RootOptions::relTolerance must be in [0, 1], got " << o.relTolerance;
  throw Error(os.str());
}

// The message building stays out of line: this runs on every ray.
template <class T>
void checkArguments(std::span<const T> c, std::span<const T> err, const RootOptions& o,
                    const char* where) {
  if (c.size() > static_cast<size_t>(kMaxDegree + 1) || (!err.empty() && err.size() != c.size()))
    throwSizeError(c.size(), err.size(), where);
  if (!validRootMethod(o.method) || !validRelTolerance(o.relTolerance)) throwOptionsError(o, where);
}

// piece(a, b, options) on the pieces of (lo, hi] at -split and split in increasing order,
// (lo, -split], (-split, split], (split, hi], each where it is not empty, with closedLo on
// the first only (a split point is the previous piece's hi), until one returns true.
template <class T, class Piece>
bool forEachPiece(T lo, T hi, T split, const RootOptions& o, Piece&& piece) {
  const T cuts[3] = {-split, split, hi};
  T a = lo;
  bool first = true;
  for (const T cut : cuts) {
    const T b = std::min(cut, hi);
    if (!(b > a)) continue;
    RootOptions oi = o;
    oi.closedLo = o.closedLo && first;
    if (piece(a, b, oi)) return true;
    first = false;
    a = b;
  }
  return false;
}

template <class T>
int solveLocal(const LocalPoly<T>& g, Query q, const RootOptions& o, LocalRoot<T>* out,
               int maxOut) {
  const T tol = static_cast<T>(std::max(0.0, o.relTolerance)) * (g.hi - g.lo);
  switch (o.method) {
    case RootMethod::Sturm:
      if constexpr (std::is_same_v<T, double>)
        return roots_detail::solveSturm(g, q, tol, out, maxOut);
      break;
    case RootMethod::Bernstein:
      if constexpr (std::is_same_v<T, double>)
        return roots_detail::solveBernstein(g, q, tol, out, maxOut);
      break;
    case RootMethod::Yuksel:
      return roots_detail::solveYuksel(g, q, tol, out, maxOut);
    case RootMethod::ClosedForm:  // closed forms at degrees 1-4 always, Yuksel above
      return roots_detail::solveClosedForm(g, q, tol, out, maxOut);
    case RootMethod::Auto:
      break;
  }
  // Auto: the closed forms at degrees 1-2, Yuksel's recursion from degree 3 on. At 3 and 4
  // both are equally accurate and about equally fast, Yuksel by a hair (measured: double
  // firstRoot, 2-core 2 GHz Xeon shared with other builds; roots_report --degrees 3,4
  // --problems 3000, three runs, ns ClosedForm vs Yuksel):
  //   ray  degree 3: 249, 245, 243 vs 242, 235, 235   degree 4: 338, 355, 360 vs 326, 335, 348
  //   cell degree 3: 138, 124, 139 vs 140, 123, 134   degree 4: 169, 164, 116 vs 166, 167, 108
  // errors p99 / max in u cond: ray 1.43 / 1.94 vs 1.32 / 1.87 (degree 3), 1.30 / 1.38 vs
  // 1.25 / 1.38 (degree 4), cell <= 1.16 either; no misses, no false hits. The full run
  // (400 problems per degree): ray 206 vs 191, 244 vs 219; cell 148 vs 146, 161 vs 155.
  // roots_bench (5 interleaved repetitions x 3, median): ray 235 vs 208, 382 vs 353; cell
  // 149 vs 137, 190 vs 176. The closed forms' transcendentals (acos + sin + cos, or cbrt)
  // cost about what the 3-4 Newton steps they save do, and both share the exclusion test
  // that ends most cell-sized calls. Float has no Sturm/Bernstein variant and lands here.
  // (Degrees above 4 call solveYuksel here too, not through solveClosedForm, which passes
  // them on: its prologue, set up for the closed forms before the degree test, cost every
  // solve ~32 instructions, 3.5 % of a degree-6 cell; callgrind, session 22.)
  if (g.n >= 3) return roots_detail::solveYuksel(g, q, tol, out, maxOut);
  return roots_detail::solveClosedForm(g, q, tol, out, maxOut);
}

// ---- Exact roots at 0 -----------------------------------------------------------------
// With c_0 .. c_{k-1} exactly zero and no error on them, g(s) = s^k h(s) exactly: g's
// roots are 0 and h's, and h is solved on its own. In one frame G's values between 0 and a
// root of h far below the interval's scale underflow (s^2 - 2^-540 s on (-0.5, 1]: |G| ~
// 2^-1080 between the roots, below the subnormal range in any frame with max |C_j| in
// [1, 2)), so the two roots merged; h's frame keeps them apart. The noise rules keep their
// meaning: |g(s)| <= N_g(s) = |s|^k N_h(s) exactly where |h(s)| <= N_h(s), with h's
// (smaller) Horner count in N_h. Returns k, or 0 where the rule does not apply: no exact
// zero at the bottom, the zero polynomial, or non-finite input or interval (those keep
// the general path's "no root").
template <class T>
int exactZeroOrder(std::span<const T> c, std::span<const T> err, T lo, T hi) {
  const int size = static_cast<int>(c.size());
  int k = 0;
  while (k < size && c[k] == 0 && (err.empty() || err[k] == 0)) ++k;
  if (k == 0 || k == size || !(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) return 0;
  for (int j = k; j < size; ++j)
    if (!std::isfinite(c[j]) || (!err.empty() && !std::isfinite(err[j]))) return 0;
  return k;
}

// Whether the root 0 of s^k is in the interval: (lo, hi], or [lo, hi] with closedLo.
template <class T>
bool zeroInside(T lo, T hi, bool closedLo) {
  return (closedLo ? lo <= 0 : lo < 0) && 0 <= hi;
}

template <class T>
std::span<const T> withoutFirst(std::span<const T> s, int k) {
  return s.empty() ? s : s.subspan(static_cast<size_t>(k));
}

// The general path: one frame for the whole polynomial, or, where toLocal had to clamp a
// coefficient and one frame cannot hold the interval (rangeSplit), the pieces of
// forEachPiece in increasing order, each by the general path again. The pieces' path is
// out of line and cold, the common one keeps a test of Frame::clamped (callgrind, session
// 26: a degree-6 cell 930 -> 950 instructions, as with the pieces written inline;
// interleaved times within noise).
// atNoise, where given, receives whether the root came from the noise rules (a tangent
// root or an end within noise: LocalRoot::tangent) rather than from a sign change.
template <class T>
bool firstRootInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, T& root,
                      const RootOptions& o, bool* atNoise);

template <class T>
bool firstRootOf(LocalPoly<T>& g, const Frame<T>& fr, T& root, const RootOptions& o,
                 bool* atNoise) {
  g.closedLo = o.closedLo;
  if (atNoise && o.noiseBefore) g.window = T(0x1p-20) * (g.hi - g.lo);
  LocalRoot<T> r[1];
  if (solveLocal(g, Query::First, o, r, 1) == 0) return false;
  root = toCaller(fr, g, r[0]);
  if (atNoise) *atNoise = r[0].tangent;
  return true;
}

template <class T>
[[gnu::noinline, gnu::cold]] bool firstRootClamped(std::span<const T> c, std::span<const T> err,
                                                   LocalPoly<T>& g, const Frame<T>& fr, T& root,
                                                   const RootOptions& o, bool* atNoise) {
  T split;
  if (!rangeSplit(c, fr, split)) return firstRootOf(g, fr, root, o, atNoise);
  return forEachPiece(fr.lo, fr.hi, split, o, [&](T a, T b, const RootOptions& oi) {
    return firstRootInFrame(c, err, a, b, root, oi, atNoise);
  });
}

template <class T>
bool firstRootInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, T& root,
                      const RootOptions& o, bool* atNoise) {
  LocalPoly<T> g;
  Frame<T> fr;
  if (!toLocal(c, err, lo, hi, g, fr)) return false;
  if (fr.clamped) [[unlikely]]
    return firstRootClamped(c, err, g, fr, root, o, atNoise);
  return firstRootOf(g, fr, root, o, atNoise);
}

template <class T>
bool hasRootInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, const RootOptions& o);

template <class T>
bool hasRootOf(LocalPoly<T>& g, const RootOptions& o) {
  g.closedLo = o.closedLo;
  LocalRoot<T> r[1];
  return solveLocal(g, Query::Any, o, r, 1) > 0;
}

template <class T>
[[gnu::noinline, gnu::cold]] bool hasRootClamped(std::span<const T> c, std::span<const T> err,
                                                 LocalPoly<T>& g, const Frame<T>& fr,
                                                 const RootOptions& o) {
  T split;
  if (!rangeSplit(c, fr, split)) return hasRootOf(g, o);
  return forEachPiece(fr.lo, fr.hi, split, o, [&](T a, T b, const RootOptions& oi) {
    return hasRootInFrame(c, err, a, b, oi);
  });
}

template <class T>
bool hasRootInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi,
                    const RootOptions& o) {
  LocalPoly<T> g;
  Frame<T> fr;
  if (!toLocal(c, err, lo, hi, g, fr)) return false;
  if (fr.clamped) [[unlikely]]
    return hasRootClamped(c, err, g, fr, o);
  return hasRootOf(g, o);
}

template <class T>
int allRootsInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, std::span<T> out,
                    const RootOptions& options);

template <class T>
int allRootsOf(LocalPoly<T>& g, const Frame<T>& fr, std::span<T> out, const RootOptions& options) {
  g.closedLo = options.closedLo;
  LocalRoot<T> r[kMaxDegree + 1];
  const int maxOut = static_cast<int>(std::min<size_t>(out.size(), kMaxDegree + 1));
  const int k = solveLocal(g, Query::All, options, r, maxOut);
  // The sweep returns roots in increasing order; the clamping into (lo, hi] could merge
  // two of them: keep the output strictly increasing.
  int m = 0;
  for (int i = 0; i < k; ++i) {
    const T s = toCaller(fr, g, r[i]);
    if (m > 0 && s <= out[m - 1]) continue;
    out[m++] = s;
  }
  return m;
}

template <class T>
[[gnu::noinline, gnu::cold]] int allRootsClamped(std::span<const T> c, std::span<const T> err,
                                                 LocalPoly<T>& g, const Frame<T>& fr,
                                                 std::span<T> out, const RootOptions& options) {
  T split;
  if (!rangeSplit(c, fr, split)) return allRootsOf(g, fr, out, options);
  int m = 0;
  forEachPiece(fr.lo, fr.hi, split, options, [&](T a, T b, const RootOptions& oi) {
    const int mi = allRootsInFrame(c, err, a, b, out.subspan(m), oi);
    int w = m;  // strictly increasing across the split points too
    for (int j = 0; j < mi; ++j)
      if (w == 0 || out[m + j] > out[w - 1]) out[w++] = out[m + j];
    m = w;
    return m == static_cast<int>(out.size());  // full
  });
  return m;
}

template <class T>
int allRootsInFrame(std::span<const T> c, std::span<const T> err, T lo, T hi, std::span<T> out,
                    const RootOptions& options) {
  LocalPoly<T> g;
  Frame<T> fr;
  if (!toLocal(c, err, lo, hi, g, fr)) return 0;
  if (fr.clamped) [[unlikely]]
    return allRootsClamped(c, err, g, fr, out, options);
  return allRootsOf(g, fr, out, options);
}

// g = s^k h: 0 and h's roots (h(0) = c_k != 0, so h takes the general path). Out of line:
// only c_0 == 0 comes here, and the common path keeps one comparison.
template <class T>
[[gnu::noinline]] bool firstRootFactored(std::span<const T> c, std::span<const T> err, T lo, T hi,
                                         T& root, const RootOptions& o, bool* atNoise) {
  const int k = exactZeroOrder(c, err, lo, hi);
  if (k == 0) return firstRootInFrame(c, err, lo, hi, root, o, atNoise);
  T r;
  const bool found = firstRootInFrame(c.subspan(k), withoutFirst(err, k), lo, hi, r, o, atNoise);
  if (zeroInside(lo, hi, o.closedLo) && !(found && r < 0)) {
    root = 0;  // exact
    if (atNoise) *atNoise = false;
    return true;
  }
  if (found) root = r;
  return found;
}

template <class T>
[[gnu::noinline]] bool hasRootFactored(std::span<const T> c, std::span<const T> err, T lo, T hi,
                                       const RootOptions& o) {
  const int k = exactZeroOrder(c, err, lo, hi);
  if (k == 0) return hasRootInFrame(c, err, lo, hi, o);
  return zeroInside(lo, hi, o.closedLo) ||
         hasRootInFrame(c.subspan(k), withoutFirst(err, k), lo, hi, o);
}

template <class T>
[[gnu::noinline]] int allRootsFactored(std::span<const T> c, std::span<const T> err, T lo, T hi,
                                       std::span<T> out, const RootOptions& options) {
  const int k = exactZeroOrder(c, err, lo, hi);
  if (k == 0) return allRootsInFrame(c, err, lo, hi, out, options);
  // h's roots in order, with 0 put in its place (a root of h within its noise bound of 0
  // may come back as 0 itself: reported once).
  const int maxOut = static_cast<int>(std::min<size_t>(out.size(), kMaxDegree + 1));
  T h[kMaxDegree + 1];
  const int nh =
      allRootsInFrame(c.subspan(k), withoutFirst(err, k), lo, hi, std::span<T>(h, maxOut), options);
  bool zeroPending = zeroInside(lo, hi, options.closedLo);
  int m = 0;
  for (int i = 0; i < nh && m < maxOut; ++i) {
    if (zeroPending && h[i] >= 0) {
      out[m++] = 0;
      zeroPending = false;
      if (h[i] == 0 || m == maxOut) continue;
    }
    out[m++] = h[i];
  }
  if (zeroPending && m < maxOut) out[m++] = 0;
  return m;
}

template <class T>
bool firstRootT(std::span<const T> c, std::span<const T> err, T lo, T hi, T& root,
                const RootOptions& o, bool* atNoise = nullptr) {
  checkArguments(c, err, o, "firstRoot");
  if (!c.empty() && c[0] == 0) return firstRootFactored(c, err, lo, hi, root, o, atNoise);
  return firstRootInFrame(c, err, lo, hi, root, o, atNoise);
}

template <class T>
bool hasRootT(std::span<const T> c, std::span<const T> err, T lo, T hi, const RootOptions& o) {
  checkArguments(c, err, o, "hasRoot");
  if (!c.empty() && c[0] == 0) return hasRootFactored(c, err, lo, hi, o);
  return hasRootInFrame(c, err, lo, hi, o);
}

template <class T>
int allRootsT(std::span<const T> c, std::span<const T> err, T lo, T hi, std::span<T> out,
              const RootOptions& options) {
  checkArguments(c, err, options, "allRoots");
  if (out.empty()) return 0;
  if (!c.empty() && c[0] == 0) return allRootsFactored(c, err, lo, hi, out, options);
  return allRootsInFrame(c, err, lo, hi, out, options);
}

}  // namespace

bool solveFirstRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
                    double& root, const RootOptions& options) {
  return firstRootT(c, err, lo, hi, root, options);
}

bool solveFirstRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
                    double& root, bool& atNoise, const RootOptions& options) {
  return firstRootT(c, err, lo, hi, root, options, &atNoise);
}

bool hasRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
             const RootOptions& options) {
  return hasRootT(c, err, lo, hi, options);
}

int allRoots(std::span<const double> c, std::span<const double> err, double lo, double hi,
             std::span<double> out, const RootOptions& options) {
  return allRootsT(c, err, lo, hi, out, options);
}

bool solveFirstRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
                    float& root, const RootOptions& options) {
  return firstRootT(c, err, lo, hi, root, options);
}

bool solveFirstRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
                    float& root, bool& atNoise, const RootOptions& options) {
  return firstRootT(c, err, lo, hi, root, options, &atNoise);
}

bool hasRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
             const RootOptions& options) {
  return hasRootT(c, err, lo, hi, options);
}

int allRoots(std::span<const float> c, std::span<const float> err, float lo, float hi,
             std::span<float> out, const RootOptions& options) {
  return allRootsT(c, err, lo, hi, out, options);
}

}  // namespace algray
