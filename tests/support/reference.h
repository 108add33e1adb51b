#pragma once
// High-precision reference for one ray against an algebraic surface, independent of
// everything algray computes (no Taylor restriction, no solver, no cells of the library):
//
//   1. clip: the ray's span inside the clip sphere, solved in MPFR;
//   2. restrict: h(s) = f(p + s q), p = o + lo d, q = (hi - lo) d, s in (0, 1), with every
//      monomial expanded in 320-bit arithmetic (o, d, the coefficients of f are exact
//      doubles, so h is f's restriction to the *given* double ray up to 2^-320);
//   3. isolate: all roots of h in (0, 1) by recursive derivatives: the roots of h^(k+1)
//      split (0, 1) into pieces where h^(k) is monotone, so each piece holds at most one
//      root, found by bisection (Collins & Loos' derivative sequence idea, the same
//      principle as Yuksel's HPG 2022 solver, but exhaustive and in MPFR);
//   4. classify: the first root is *well-conditioned* when a perturbation of f far larger
//      than double rounding cannot move it much or create an earlier root:
//        cond = u * S(x) / |d f(x)/dt| * |d| / R < kCondLimit,   S(x) = sum |c_a x^a|,
//      (first-order perturbation of a simple root, Higham, "Accuracy and Stability of
//      Numerical Algorithms", Sec. 26.2, applied to the evaluation of f at the hit point x,
//      so it does not depend on where the ray starts), no other root within kMargin R,
//      no local extremum of h before it whose value a perturbation of f by kTangent S or
//      of the point by 1e4 u |o + t d| could bring to zero (a near-tangency that such a
//      perturbation turns into a hit), not within kEndMargin R of a span end. A miss is
//      well-conditioned when no extremum or span end is that close to 0.
//
// Used by tests/stress_test.cpp and tests/bench/intersector_report.cpp; genuineReentry
// (below) by tests/embree_shadow_test.cpp and tests/bench/accuracy_report.cpp.
#include "algray/polynomial.h"

#include <mpfr.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace algray::test {

inline constexpr mpfr_prec_t kRefBits = 320;

// An MPFR number with in-place operations only (the reference evaluates many thousand
// polynomials: no temporaries in the loops).
class MpNum {
 public:
  MpNum() { mpfr_init2(v_, kRefBits), mpfr_set_zero(v_, 1); }
  explicit MpNum(double x) { mpfr_init2(v_, kRefBits), mpfr_set_d(v_, x, MPFR_RNDN); }
  MpNum(const MpNum& o) { mpfr_init2(v_, kRefBits), mpfr_set(v_, o.v_, MPFR_RNDN); }
  MpNum& operator=(const MpNum& o) {
    mpfr_set(v_, o.v_, MPFR_RNDN);
    return *this;
  }
  ~MpNum() { mpfr_clear(v_); }
  mpfr_ptr get() { return v_; }
  mpfr_srcptr get() const { return v_; }
  double toDouble() const { return mpfr_get_d(v_, MPFR_RNDN); }
  int sign() const { return mpfr_sgn(v_); }

 private:
  mpfr_t v_;
};
using MpPoly = std::vector<MpNum>;  // lowest coefficient first

// ---- Restriction ------------------------------------------------------------------------
// Coefficients of (a + s b)^e for e = 0..m, as rows of binomial terms.
inline std::vector<MpPoly> linearPowers(const MpNum& a, const MpNum& b, int m) {
  std::vector<MpPoly> pw(m + 1);
  pw[0].assign(1, MpNum(1.0));
  MpNum t;
  for (int e = 1; e <= m; ++e) {
    pw[e].assign(e + 1, MpNum());
    for (int r = 0; r < e; ++r) {
      mpfr_mul(t.get(), pw[e - 1][r].get(), a.get(), MPFR_RNDN);
      mpfr_add(pw[e][r].get(), pw[e][r].get(), t.get(), MPFR_RNDN);
      mpfr_mul(t.get(), pw[e - 1][r].get(), b.get(), MPFR_RNDN);
      mpfr_add(pw[e][r + 1].get(), pw[e][r + 1].get(), t.get(), MPFR_RNDN);
    }
  }
  return pw;
}

// h(s) = f(p + s q). Terms are grouped by (j, k): A_jk(s) = sum_i c_ijk (p_x + s q_x)^i,
// then h += A_jk * (p_y + s q_y)^j (p_z + s q_z)^k.
inline MpPoly restrictMp(const Polynomial& f, const MpNum p[3], const MpNum q[3]) {
  const int m = f.degree();
  MpPoly h(std::max(m, 0) + 1);
  if (m < 0) return h;
  const auto px = linearPowers(p[0], q[0], m), py = linearPowers(p[1], q[1], m),
             pz = linearPowers(p[2], q[2], m);
  MpNum t;
  MpPoly a(m + 1), yz(m + 1);
  for (int jk = 0; jk <= m; ++jk)
    for (int k = 0; k <= jk; ++k) {
      const int j = jk - k;
      int top = -1;
      for (auto& c : a) mpfr_set_zero(c.get(), 1);
      for (int i = 0; i + jk <= m; ++i) {
        const double c = f.coeffs()[Polynomial::index(i, j, k)];
        if (c == 0.0) continue;
        top = i;
        for (int r = 0; r <= i; ++r) {
          mpfr_mul_d(t.get(), px[i][r].get(), c, MPFR_RNDN);
          mpfr_add(a[r].get(), a[r].get(), t.get(), MPFR_RNDN);
        }
      }
      if (top < 0) continue;
      for (int r = 0; r <= jk; ++r) mpfr_set_zero(yz[r].get(), 1);
      for (int r = 0; r <= j; ++r)
        for (int w = 0; w <= k; ++w) {
          mpfr_mul(t.get(), py[j][r].get(), pz[k][w].get(), MPFR_RNDN);
          mpfr_add(yz[r + w].get(), yz[r + w].get(), t.get(), MPFR_RNDN);
        }
      for (int r = 0; r <= top; ++r)
        for (int w = 0; w <= jk; ++w) {
          mpfr_mul(t.get(), a[r].get(), yz[w].get(), MPFR_RNDN);
          mpfr_add(h[r + w].get(), h[r + w].get(), t.get(), MPFR_RNDN);
        }
    }
  return h;
}

inline void evalMp(const MpPoly& h, const MpNum& s, MpNum& out) {
  mpfr_set_zero(out.get(), 1);
  for (int i = static_cast<int>(h.size()) - 1; i >= 0; --i) {
    mpfr_mul(out.get(), out.get(), s.get(), MPFR_RNDN);
    mpfr_add(out.get(), out.get(), h[i].get(), MPFR_RNDN);
  }
}

inline MpPoly derivativeMp(const MpPoly& h) {
  MpPoly d(h.size() > 1 ? h.size() - 1 : 1);
  for (size_t i = 1; i < h.size(); ++i) mpfr_mul_ui(d[i - 1].get(), h[i].get(), i, MPFR_RNDN);
  return d;
}

// ---- Isolation ---------------------------------------------------------------------------
struct UnitRoots {
  std::vector<MpNum> roots;     // roots of h in (0, 1), increasing
  std::vector<MpNum> extrema;   // roots of h' in (0, 1), increasing
  std::vector<MpNum> extValue;  // h at each extremum
  bool degenerate = false;      // h identically zero
};

// Root of a monotone h in (a, b) given opposite signs at the ends: bisection to 2^-90.
inline MpNum bisectMp(const MpPoly& h, MpNum a, MpNum b, int signA) {
  MpNum mid, v;
  for (int it = 0; it < 90; ++it) {
    mpfr_add(mid.get(), a.get(), b.get(), MPFR_RNDN);
    mpfr_div_2ui(mid.get(), mid.get(), 1, MPFR_RNDN);
    evalMp(h, mid, v);
    if (v.sign() == 0) return mid;
    if (v.sign() == signA)
      a = mid;
    else
      b = mid;
  }
  mpfr_add(mid.get(), a.get(), b.get(), MPFR_RNDN);
  mpfr_div_2ui(mid.get(), mid.get(), 1, MPFR_RNDN);
  return mid;
}

// Roots of the polynomial in (0, 1), given the sorted roots of its derivative there.
inline std::vector<MpNum> rootsBetween(const MpPoly& h, const std::vector<MpNum>& crit) {
  std::vector<MpNum> pts;
  pts.emplace_back(0.0);
  for (const MpNum& c : crit) pts.push_back(c);
  pts.emplace_back(1.0);
  std::vector<int> sg(pts.size());
  MpNum v;
  for (size_t i = 0; i < pts.size(); ++i) {
    evalMp(h, pts[i], v);
    sg[i] = v.sign();
  }
  std::vector<MpNum> out;
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    if (i > 0 && sg[i] == 0) out.push_back(pts[i]);  // an exact multiple root
    if (sg[i] != 0 && sg[i + 1] != 0 && sg[i] != sg[i + 1])
      out.push_back(bisectMp(h, pts[i], pts[i + 1], sg[i]));
  }
  return out;
}

inline UnitRoots isolateUnit(MpPoly h) {
  UnitRoots r;
  while (h.size() > 1 && h.back().sign() == 0) h.pop_back();
  if (h.size() == 1) {
    r.degenerate = h[0].sign() == 0;
    return r;
  }
  std::vector<MpPoly> der{h};
  while (der.back().size() > 1) der.push_back(derivativeMp(der.back()));
  std::vector<MpNum> crit;  // roots of der[k + 1]
  for (int k = static_cast<int>(der.size()) - 2; k >= 0; --k) {
    std::vector<MpNum> rk = rootsBetween(der[k], crit);
    if (k == 0) {
      r.extrema = crit;
      r.roots = std::move(rk);
    } else {
      crit = std::move(rk);
    }
  }
  MpNum v;
  for (const MpNum& e : r.extrema) {
    evalMp(h, e, v);
    r.extValue.push_back(v);
  }
  return r;
}

// ---- The reference of one ray ----------------------------------------------------------
struct RefOptions {
  double condLimit = 1e-6;       // relative to the clip radius
  double margin = 1e-6;          // no second root this close (clip radii)
  double endMargin = 1e-7;       // no root this close to a span end (clip radii)
  double tangent = 1e-8;         // |h| at an extremum or span end within tangent * S: near-tangent
  double positionNoise = 1e-12;  // relative displacement of points (1e4 u) in that test
};

struct RayRef {
  bool hit = false;
  double t = 0;           // ray parameter of the first root
  glm::dvec3 point{0.0};  // o + t d rounded to double
  bool wellConditioned = false;
  double cond = std::numeric_limits<double>::infinity();  // of the first root
  int roots = 0;                                          // number of roots in the span
  bool spanEmpty = true;
};

// S(x) = sum |c_a x^a|: the scale of the rounding error of evaluating f at x.
inline double absTermSum(const Polynomial& f, const glm::dvec3& x) {
  const int m = f.degree();
  std::vector<double> px(m + 1, 1.0), py(m + 1, 1.0), pz(m + 1, 1.0);
  for (int e = 1; e <= m; ++e) {
    px[e] = px[e - 1] * std::abs(x.x);
    py[e] = py[e - 1] * std::abs(x.y);
    pz[e] = pz[e - 1] * std::abs(x.z);
  }
  double s = 0;
  for (int n = 0; n <= m; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      s += std::abs(f.coeffs()[idx]) * px[i] * py[j] * pz[k];
    });
  return s;
}

// First root of f(o + t d) with tnear < t < tfar inside the clip sphere (centre c,
// radius R), classified as above.
inline RayRef referenceFirstHit(const Polynomial& f, const glm::dvec3& o, const glm::dvec3& d,
                                double tnear, double tfar, const glm::dvec3& c, double R,
                                const RefOptions& opt = {}) {
  RayRef ref;
  // ---- 1. Clip span in MPFR: t = tc -+ sqrt((R^2 - |q|^2) / |d|^2) ---------------------
  MpNum oc[3], dm[3], dd, od, t, tc, h2, lo, hi;
  for (int i = 0; i < 3; ++i) {
    mpfr_set_d(oc[i].get(), o[i], MPFR_RNDN);
    mpfr_sub_d(oc[i].get(), oc[i].get(), c[i], MPFR_RNDN);
    mpfr_set_d(dm[i].get(), d[i], MPFR_RNDN);
    mpfr_mul(t.get(), dm[i].get(), dm[i].get(), MPFR_RNDN);
    mpfr_add(dd.get(), dd.get(), t.get(), MPFR_RNDN);
    mpfr_mul(t.get(), oc[i].get(), dm[i].get(), MPFR_RNDN);
    mpfr_add(od.get(), od.get(), t.get(), MPFR_RNDN);
  }
  if (dd.sign() <= 0) return ref;
  mpfr_div(tc.get(), od.get(), dd.get(), MPFR_RNDN);
  mpfr_neg(tc.get(), tc.get(), MPFR_RNDN);
  mpfr_set_d(h2.get(), R, MPFR_RNDN);
  mpfr_sqr(h2.get(), h2.get(), MPFR_RNDN);
  for (int i = 0; i < 3; ++i) {
    MpNum qi;
    mpfr_mul(qi.get(), tc.get(), dm[i].get(), MPFR_RNDN);
    mpfr_add(qi.get(), qi.get(), oc[i].get(), MPFR_RNDN);
    mpfr_sqr(qi.get(), qi.get(), MPFR_RNDN);
    mpfr_sub(h2.get(), h2.get(), qi.get(), MPFR_RNDN);
  }
  if (h2.sign() <= 0) return ref;
  mpfr_div(h2.get(), h2.get(), dd.get(), MPFR_RNDN);
  mpfr_sqrt(h2.get(), h2.get(), MPFR_RNDN);
  mpfr_sub(lo.get(), tc.get(), h2.get(), MPFR_RNDN);
  mpfr_add(hi.get(), tc.get(), h2.get(), MPFR_RNDN);
  if (mpfr_cmp_d(lo.get(), tnear) < 0) mpfr_set_d(lo.get(), tnear, MPFR_RNDN);
  if (mpfr_cmp_d(hi.get(), tfar) > 0) mpfr_set_d(hi.get(), tfar, MPFR_RNDN);
  if (mpfr_cmp(lo.get(), hi.get()) >= 0) return ref;
  ref.spanEmpty = false;

  // ---- 2. h(s) = f(o + (lo + s L) d) ---------------------------------------------------
  MpNum len, p[3], q[3];
  mpfr_sub(len.get(), hi.get(), lo.get(), MPFR_RNDN);
  for (int i = 0; i < 3; ++i) {
    mpfr_mul(p[i].get(), lo.get(), dm[i].get(), MPFR_RNDN);
    mpfr_add_d(p[i].get(), p[i].get(), o[i], MPFR_RNDN);
    mpfr_mul(q[i].get(), len.get(), dm[i].get(), MPFR_RNDN);
  }
  const MpPoly h = restrictMp(f, p, q);

  // ---- 3. All roots and extrema in (0, 1) ----------------------------------------------
  const UnitRoots u = isolateUnit(h);
  if (u.degenerate) return ref;  // the line lies in the surface: no first point
  ref.roots = static_cast<int>(u.roots.size());
  const double dLen = std::sqrt(dd.toDouble());
  const double lenD = len.toDouble(), loD = lo.toDouble();
  const double toRadii = lenD * dLen / R;  // s units -> clip radii
  auto pointAt = [&](const MpNum& s) {
    glm::dvec3 x;
    MpNum v;
    for (int i = 0; i < 3; ++i) {
      mpfr_mul(v.get(), s.get(), q[i].get(), MPFR_RNDN);
      mpfr_add(v.get(), v.get(), p[i].get(), MPFR_RNDN);
      x[i] = v.toDouble();
    }
    return x;
  };
  // |h| small against what a perturbation can do there: tangent * S(x) for relative
  // perturbations of the coefficients, plus S(|x| + delta) - S(|x|) >= |f(x + e) - f(x)|
  // (|e_i| <= delta) for a displacement of the point by delta = positionNoise (|o| + |t d|),
  // which catches singular curves where every term of f vanishes (the axes of Steiner's
  // Roman surface: S(x) = 0 there, but not S(x + delta)).
  auto nearZero = [&](const MpNum& value, const MpNum& s) {
    const glm::dvec3 x = pointAt(s);
    const double tAt = loD + s.toDouble() * lenD;
    const double delta = opt.positionNoise * (glm::length(o) + std::abs(tAt) * dLen);
    const double sx = absTermSum(f, x);
    const double moved = absTermSum(f, glm::abs(x) + glm::dvec3(delta)) - sx;
    return std::abs(value.toDouble()) <= opt.tangent * sx + moved;
  };

  // ---- 4. Classification -----------------------------------------------------------------
  MpNum v0, v1, zero(0.0), one(1.0);
  evalMp(h, zero, v0);
  evalMp(h, one, v1);
  const bool endsClear = !nearZero(v0, zero) && !nearZero(v1, one);
  if (u.roots.empty()) {
    bool clear = endsClear;
    for (size_t i = 0; i < u.extrema.size(); ++i)
      clear = clear && !nearZero(u.extValue[i], u.extrema[i]);
    ref.wellConditioned = clear;
    return ref;
  }
  const MpNum& s1 = u.roots.front();
  MpNum tm;
  mpfr_mul(tm.get(), s1.get(), len.get(), MPFR_RNDN);
  mpfr_add(tm.get(), tm.get(), lo.get(), MPFR_RNDN);
  ref.hit = true;
  ref.t = tm.toDouble();
  ref.point = pointAt(s1);
  const double s1d = s1.toDouble();
  // Slope dh/ds at the root -> df/dt = h'(s) / L.
  MpNum slope;
  evalMp(derivativeMp(h), s1, slope);
  const double dfdt = std::abs(slope.toDouble()) / lenD;
  ref.cond = dfdt > 0 ? kUnitRoundoff * absTermSum(f, ref.point) / dfdt * dLen / R
                      : std::numeric_limits<double>::infinity();
  bool ok = ref.cond < opt.condLimit;
  ok = ok && s1d * toRadii > opt.endMargin && (1.0 - s1d) * toRadii > opt.endMargin;
  if (u.roots.size() > 1) ok = ok && (u.roots[1].toDouble() - s1d) * toRadii > opt.margin;
  for (size_t i = 0; i < u.extrema.size(); ++i) {
    const double e = u.extrema[i].toDouble();
    if (e > s1d + opt.margin / toRadii) break;
    if (std::abs(e - s1d) * toRadii <= opt.margin || nearZero(u.extValue[i], u.extrema[i]))
      ok = false;
  }
  ref.wellConditioned = ok && !nearZero(v0, zero);
  return ref;
}

// Does the ray from the surface point nearest p (one Newton step from p along grad f, in
// MPFR) meet the surface within a factor 8 of t? The hit point p is only known within its
// rounding bound; a leaving ray at a grazing angle can re-enter a curved surface within
// 1e-6 R (at t ~ 2 angle / curvature), and whether the ray from the rounded p does so
// depends on the side p was rounded to, not on the plugin.
inline bool genuineReentry(const Polynomial& f, const glm::dvec3& p, const glm::dvec3& d,
                           double t) {
  MpNum P[3], axis[3], grad[3], norm2, step, tmp;
  for (int i = 0; i < 3; ++i) mpfr_set_d(P[i].get(), p[i], MPFR_RNDN);
  MpNum value;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) mpfr_set_d(axis[k].get(), i == k ? 1.0 : 0.0, MPFR_RNDN);
    const MpPoly h = restrictMp(f, P, axis);  // f(p + s e_i)
    if (h.size() < 2) return false;
    mpfr_set(value.get(), h[0].get(), MPFR_RNDN);
    mpfr_set(grad[i].get(), h[1].get(), MPFR_RNDN);
    mpfr_sqr(tmp.get(), grad[i].get(), MPFR_RNDN);
    mpfr_add(norm2.get(), norm2.get(), tmp.get(), MPFR_RNDN);
  }
  if (norm2.sign() == 0) return false;
  mpfr_div(step.get(), value.get(), norm2.get(), MPFR_RNDN);
  MpNum start[3], span[3];
  for (int i = 0; i < 3; ++i) {  // p* - (step) grad f, then the piece [t / 8, 8 t] of the ray
    mpfr_mul(tmp.get(), step.get(), grad[i].get(), MPFR_RNDN);
    mpfr_sub(start[i].get(), P[i].get(), tmp.get(), MPFR_RNDN);
    mpfr_set_d(tmp.get(), d[i] * (t / 8), MPFR_RNDN);
    mpfr_add(start[i].get(), start[i].get(), tmp.get(), MPFR_RNDN);
    mpfr_set_d(span[i].get(), d[i] * (8 * t - t / 8), MPFR_RNDN);
  }
  return !isolateUnit(restrictMp(f, start, span)).roots.empty();
}

}  // namespace algray::test
