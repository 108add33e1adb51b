// The quadric path: a degree-2 surface with one cell takes its own Embree callbacks
// (embree_bridge.cpp registers them when usesQuadricPath), which skip what the generic
// walk of surface_intersect.cpp needs only for many cells or higher degrees: the
// per-thread ray record and its ownership rules, the cell clip, the 41-coefficient
// RayPolynomial and LocalPoly frames (their zeroing alone cost more than the quadratic
// formula; perf on speed_report's sphere). The answers are the same: the restriction is
// the closed form below (also used by the generic walk for quadrics), and quadricRoot
// applies firstRoot's rules (roots_scan.h) to it in the caller's frame.
#include "quadric_path.h"

#include "algray/roots.h"
#include "algray/taylor.h"

#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <variant>

namespace algray {

namespace {

// ---- Roots by firstRoot's rules, in the caller's frame --------------------------------
// firstRoot maps g to a local frame by powers of two (exact), so every comparison of its
// sweep (roots_scan.h: |g| against the noise bound, signs, the closed-form root inside
// its piece) has the same outcome here as long as nothing leaves the range checked
// below (the checks of firstRootQuadratic, roots_quadratic.cpp). Anything else, and
// the rare piece whose closed-form root rounds outside it (bracketed Newton there), is
// answered by the library itself: -1 means "ask firstRoot".
bool inRange(double x) { return x == 0.0 || (std::abs(x) >= 1e-100 && std::abs(x) <= 1e100); }
// inRange of each of c[0..n) and err[0..n), and err finite. Most rays pass by their sum and
// minimum: a rounded sum of non-negative terms is at least each term (rounding is monotone),
// so a sum <= 1e100 bounds every |x| (and is NaN or inf, failing, if any is), and a
// minimum >= 1e-100 the smaller ones. Only a zero value takes the test per value. (Per
// value, short-circuit or with & and |, the checks were 50-90 of a primary hit's ~760
// callback instructions: callgrind, AMD Zen 3.)
template <int n>
bool coefficientsInRange(const QuadricRay& g) {
  double sum = 0.0, least = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const double a = std::abs(g.c[i]), e = std::abs(g.err[i]);
    sum += a + e;
    least = std::min({least, a, e});
  }
  if (sum <= 1e100 && least >= 1e-100) [[likely]]
    return true;
  bool safe = true;
  for (int i = 0; i < n && safe; ++i)
    safe = inRange(g.c[i]) && inRange(g.err[i]) && std::isfinite(g.err[i]);
  return safe;
}

// The caller-frame result of a local root v (toCaller in roots.cpp, firstRootQuadratic):
// a root within noise of hi is hi; one rounded onto lo moves just inside.
double toSpan(double v, double lo, double hi) {
  if (v >= hi) return hi;
  return v > lo ? v : std::nextafter(lo, hi);
}

// Degree 2 (c2 != 0): firstRootQuadratic, i.e. solveClosedForm's degree-2 sweep with
// the vertex as the only critical point (roots_closed_form.cpp, roots_scan.h).
int quadraticFirst(const QuadricRay& g, double lo, double hi, double& s) {
  const double c0 = g.c[0], c1 = g.c[1], c2 = g.c[2];
  const double scale = std::max(std::abs(lo), std::abs(hi));
  // (c0 = 0 with no error is an exact root at 0, which firstRoot factors out: roots.cpp.)
  bool safe = std::isfinite(lo) && std::isfinite(hi) && lo < hi && scale <= 1e30 && c2 != 0.0 &&
              (c0 != 0.0 || g.err[0] != 0.0) && coefficientsInRange<3>(g);
  if (safe) {
    const double lead = std::abs(c2) * scale * scale;
    const double lower = std::max(std::abs(c0), std::abs(c1) * scale);
    safe = lead > 4.0 * kUnitRoundoff * lower && std::abs(c2) > 2.0 * g.err[2];
  }
  if (!safe) return -1;
  // Noise of one Horner evaluation: the caller's bound plus gamma(2n+1) |c_j|.
  const double n0 = g.err[0] + gamma(5) * std::abs(c0), n1 = g.err[1] + gamma(5) * std::abs(c1),
               n2 = g.err[2] + gamma(5) * std::abs(c2);
  auto value = [&](double x) { return (c2 * x + c1) * x + c0; };
  auto noise = [&](double x) {
    const double ax = std::abs(x);
    return (n2 * ax + n1) * ax + n0;
  };
  // Both roots by citardauq (quadraticRoots in roots_detail.h, with Kahan's
  // discriminant), before the sweep asks for one: they depend on c only, so their root
  // and divisions overlap the vertex's division instead of waiting for the sweep.
  // (Kahan's correction only where p - q4 cancels, as discriminant() in roots_detail.h.)
  const double p = c1 * c1, q4 = 4 * c2 * c0, d0 = p - q4;
  double disc = d0;
  if (!(std::abs(d0) > 0.5 * (p + std::abs(q4)))) [[unlikely]]
    disc = d0 + (std::fma(c1, c1, -p) - std::fma(4 * c2, c0, -q4));
  // (The root of max(disc, 0): a negative disc has no root to use, and its NaN would
  // take libm's errno path.)
  const double q = -(c1 + std::copysign(std::sqrt(std::max(disc, 0.0)), c1)) / 2;
  double root0 = q / c2, root1 = c0 / q;
  if (root1 < root0) std::swap(root0, root1);
  const bool real = disc > 0 && q != 0;
  const double vertex = -c1 / (2 * c2);
  const int nCrit = vertex > lo && vertex < hi ? 1 : 0;

  double xPrev = lo, fPrev = value(lo);
  bool zPrev = std::abs(fPrev) <= noise(lo);
  bool inCluster = zPrev, clusterAtLo = zPrev, clusterHasInterior = false;
  double best = lo, bestAbs = std::abs(fPrev);
  for (int i = 0; i <= nCrit; ++i) {
    const bool interior = i < nCrit;
    const double x = interior ? vertex : hi;
    const double f = value(x);
    const bool z = std::abs(f) <= noise(x);
    if (z) {
      if (!inCluster) {
        inCluster = true;
        clusterAtLo = false;
        clusterHasInterior = false;
        bestAbs = std::numeric_limits<double>::infinity();
      }
      if (interior && (!clusterHasInterior || std::abs(f) < bestAbs)) {
        best = x;
        bestAbs = std::abs(f);
        clusterHasInterior = true;
      } else if (!interior && !clusterHasInterior) {
        best = x;
      }
    } else if (inCluster) {
      inCluster = false;
      if (!clusterAtLo) {
        s = toSpan(best, lo, hi);
        return 1;
      }
    } else if (!zPrev && std::signbit(f) != std::signbit(fPrev)) {
      // A simple root in (xPrev, x): the citardauq root inside the piece.
      if (real)
        for (const double r : {root0, root1})
          if (r > xPrev && r < x) {
            s = toSpan(r, lo, hi);
            return 1;
          }
      return -1;
    }
    xPrev = x;
    fPrev = f;
    zPrev = z;
  }
  if (inCluster && !clusterAtLo) {
    s = toSpan(best, lo, hi);
    return 1;
  }
  return 0;
}

// Degree 1 (a ray leaving the surface, after the self-root division): firstRoot's frame
// drops c1 when |c1| 2^e <= u |c0| (2^e in (S, 2S], S = max(|lo|, |hi|)) or |c1| <=
// err1; the checks below keep clear of both. Then the sweep has no critical point: a
// root within noise of lo is none, one within noise of hi is hi, else -c0 / c1.
int linearFirst(const QuadricRay& g, double lo, double hi, double& s) {
  const double c0 = g.c[0], c1 = g.c[1];
  const double scale = std::max(std::abs(lo), std::abs(hi));
  const bool safe = std::isfinite(lo) && std::isfinite(hi) && lo < hi && scale <= 1e30 &&
                    c1 != 0.0 && coefficientsInRange<2>(g);
  if (!safe || !(std::abs(c1) > g.err[1]) ||
      !(std::abs(c1) * scale > 2.0 * kUnitRoundoff * std::abs(c0)))
    return -1;
  const double n0 = g.err[0] + gamma(3) * std::abs(c0), n1 = g.err[1] + gamma(3) * std::abs(c1);
  const double fLo = c1 * lo + c0;
  if (std::abs(fLo) <= n1 * std::abs(lo) + n0) return 0;
  // g moving away from zero beyond lo has no sign change up to hi; a root within noise
  // of hi would be hi itself, which the callers do not report. So none, without hi (a
  // ray leaving a lit surface need not wait for the clip chord's root; measured).
  if (std::signbit(fLo) == std::signbit(c1)) return 0;
  const double fHi = c1 * hi + c0;
  if (std::abs(fHi) <= n1 * std::abs(hi) + n0) {
    s = hi;
    return 1;
  }
  if (std::signbit(fLo) == std::signbit(fHi)) return 0;
  const double r = -c0 / c1;
  if (!(r > lo && r < hi)) return -1;
  s = toSpan(r, lo, hi);
  return 1;
}

}  // namespace

// ---- Restriction -------------------------------------------------------------------------
// About p = o + tShift d,
//   g(s) = f(p) + (grad f(p) . d) s + (d^T A d) s^2,   grad f(p) = 2 A p + b,
// with error bounds by the running sums of Higham, Sec. 3.1: f(p) is at most 8 roundings
// deep per term (evalQuadric), the slope 7, d^T A d 5.
// (A per-thread cache of the origin's terms for rays sharing it was measured: +1-2 % on
// a camera's primary rays, -3-4 % on shadow rays, which never share an origin; not kept.)
namespace {
// Whether the root of the linear rest c0 + c1 s after the self-root rule's division, c0 =
// grad f(o) . d, lies in the origin's cluster: c0 zero within what the origin's uncertainty
// moves it by (its gradient is 2 A d; restrictQuadricRayOf).
[[gnu::noinline]] bool linearRootAtOrigin(const SurfaceData& data, const KernelRay& ray, double c0,
                                          double e0, double orgError) {
  const glm::dvec3 ad = 2.0 * (data.quadric->a * ray.dir);
  // 4 = 2 (k + 1) for k = 1, as multipleRootWindow (ray_roots.cpp) says why.
  return std::abs(c0) <= 4.0 * e0 + 4.0 * originUncertaintyMove(data, ray, ad, orgError);
}

// The self-root rule divides g by its root near the origin, r, not by s, where g(0) = v is
// clear of its rounding (the origin off the surface within its uncertainty: r != 0; g / s
// moved the far root by r, ray_roots.cpp, divideByOriginRoot, says why). With g = c2 (s -
// r)(s - R), the quotient is c2 s - c2 R, and -c2 R = -q for the stable formula's q = -(c1
// + sign(c1) sqrt(c1^2 - 4 c2 v)) / 2 (R = q / c2): (c1 + sign(c1) root) / 2, one square
// root and no division; the root divided out, v / q, is the nearer. Where the roots are well
// apart, 8 |c2 v| <= c1^2 (root >= |c1| / sqrt 2: no cancellation), and, for a ray leaving
// nearly tangentially (session 47: g / s moved a sphere's far side by the origin's root,
// ~ sqrt(delta) from delta off), where the discriminant is clear of its rounding and of
// what the coefficients' bounds move it by (two real roots; a ray passing its origin's
// sheet by keeps g / s, whose roots are those of f = f(o), and the cluster rules).
// k0 = c1, k1 = c2 (the s-deflated coefficients), ke0, ke1 their bounds.
inline bool nearTangentRootsApart(double v, double ve, double k0, double ke0, double k1,
                                  double ke1) {
  const double disc = k0 * k0 - 4.0 * (k1 * v);
  return disc > 4.0 * (gamma(3) * (k0 * k0 + 4.0 * std::abs(k1 * v)) + 2.0 * std::abs(k0) * ke0 +
                       4.0 * (std::abs(k1) * ve + std::abs(v) * ke1));
}
inline bool originRootApart(double v, double ve, double k0, double ke0, double k1, double ke1) {
  return std::abs(v) > 4.0 * ve && k0 != 0.0 &&
         (8.0 * std::abs(k1 * v) <= k0 * k0 || nearTangentRootsApart(v, ve, k0, ke0, k1, ke1));
}
// The quotient's constant term's bound: d/dc1 = (1 + |c1| / root) / 2 (<= 1.21 where the
// roots are well apart), d/dv = |c2| / root, d/dc2 = |v| / root, and the rounding of the
// square root's argument (relative <= 4.5 u with root^2 >= c1^2 / 2; gamma(2) (c1^2 + 4
// |c2 v|) absolute, over 2 root, nearly tangent), the root and the sum, gamma(8) (|c1| +
// root).
inline double originQuotientError(double v, double ve, double k0, double ke0, double k1, double ke1,
                                  double root) {
  if (8.0 * std::abs(k1 * v) <= k0 * k0)
    return 1.25 * ke0 + (std::abs(k1) * ve + std::abs(v) * ke1) / root +
           gamma(8) * (std::abs(k0) + root);
  return 0.5 * (1.0 + std::abs(k0) / root) * ke0 + (std::abs(k1) * ve + std::abs(v) * ke1) / root +
         gamma(8) * (std::abs(k0) + root) +
         gamma(2) * (k0 * k0 + 4.0 * std::abs(k1 * v)) / (2.0 * root);
}

template <bool kDiagonal, bool kNonNegDiagonal, bool kNonNegCentred, bool kUnitA>
void restrictQuadricRayOf(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                          QuadricRay& g, double closest, double oc2) {
  const QuadricForm& q = *data.quadric;
  // A v and |A| v (v, |v| when A = I and v >= 0: the same values).
  auto mulA = [&](const glm::dvec3& v) { return kUnitA ? v : q.mulA<kDiagonal>(v); };
  auto mulAbsA = [&](const glm::dvec3& v) { return kUnitA ? v : q.mulAbsA<kDiagonal>(v); };
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  const glm::dvec3 absD = absv(d);
  // An origin outside the clip ball by 2^-9 of its radius, with an uncertainty below
  // 2^-11 of it (a camera's), cannot put a root at the origin into the ray's span (which
  // starts 2^-9 R / |d| from it): the self-root rule has nothing to remove, and with
  // re-centring f(o) is not needed at all (a fifth of a camera ray's work, measured).
  // (A deferred orgError, KernelRay::orgErrorDeferred, is made whole only when the test
  // needs it: surelyOutsideClipBall.)
  double orgError = ray.orgError;
  bool farOrigin = false;
  if (data.desc.options.recentre) {
    double ocSq = oc2;
    if (std::isnan(ocSq)) {
      const glm::dvec3 oc = o - data.centre;
      ocSq = glm::dot(oc, oc);
    }
    farOrigin = ray.orgErrorDeferred && surelyOutsideClipBall(data, ocSq, ray);
    if (!farOrigin) {
      orgError = wholeOrgError(data, ray);
      farOrigin = originOutsideClipBall(data, ocSq, orgError);
    }
  } else {
    orgError = wholeOrgError(data, ray);
  }
  QuadricValue at{};
  bool onSurface = false;
  if (!farOrigin) {
    at = evalQuadric<kDiagonal, kNonNegDiagonal, kNonNegCentred, kUnitA>(q, o);
    // The self-root rule of originOnSurface (ray_roots.cpp), on the closed-form
    // value. Most origins are far off the surface: the 1-norm of the gradient (>= its
    // length; widened by 2^-20 for the rounding of both) decides them without
    // safeLength. (Rounding is monotone, so the bound with the larger move decides
    // exactly as the length would.)
    const glm::dvec3 absG = absv(at.gradient);
    const double moveRound = ray.orgRoundoff * glm::dot(absG, absv(o));
    const double moveUpper = moveRound + (1.0 + 0x1p-20) * (absG.x + absG.y + absG.z) * orgError;
    // Within that bound, the exact rule takes |grad f| (safeLength: three divisions and
    // a root, most of a shadow ray's restriction). Its largest component m is no larger
    // (safeLength = m |g / m| with a component of g / m exactly 1), so |f| within the
    // bound with m is within it with |grad f|, by the same monotonicity; only the
    // origins in between pay for the length.
    const double absValue = std::abs(at.value);
    if (!(absValue > 4.0 * at.error + 2.0 * moveUpper)) {
      const double m = std::max({absG.x, absG.y, absG.z});
      onSurface = absValue <= 4.0 * at.error + 2.0 * (moveRound + m * orgError);
      if (!onSurface) {
        const double move = orgError != 0.0 ? safeLength(at.gradient) * orgError : 0.0;
        onSurface = absValue <= 4.0 * at.error + 2.0 * (moveRound + move);
      }
      // A transformed surface's world-space part of the bound, along the gradient
      // (originMove; the packet lanes leave such origins to this path).
      if (onSurface && ray.orgErrorWorld > 0.0) [[unlikely]] {
        const double move = originMove(data, ray, at.gradient, safeLength(at.gradient), orgError);
        onSurface = absValue <= 4.0 * at.error + 2.0 * (moveRound + move);
      }
    }
  }
  double tShift = 0.0;
  glm::dvec3 p = o;
  double shiftError0 = 0.0, shiftError1 = 0.0;
  if (!onSurface && data.desc.options.recentre) {
    // A given closest is the clip chord's midpoint, inside [r0, r1] by construction: not
    // clamped, so that p does not wait for the chord's division and root (measured).
    tShift =
        std::isnan(closest) ? std::clamp(closestParameter(o, d, data.centre), r0, r1) : closest;
    p = o + tShift * d;
    at = evalQuadric<kDiagonal, kNonNegDiagonal, kNonNegCentred, kUnitA>(q, p);
    // p is rounded, off the line by up to gamma(2) (|p| + |tShift d|) per coordinate:
    // its effect on f(p) and on the slope (first order; the second is below u^2).
    const glm::dvec3 off = gamma(2) * (absv(p) + std::abs(tShift) * absD);
    shiftError0 = glm::dot(absv(at.gradient), off);
    shiftError1 = 2.0 * glm::dot(mulAbsA(off), absD);
  }
  const glm::dvec3 absP = absv(p);
  double c0 = at.value, c1 = glm::dot(at.gradient, d), c2 = glm::dot(d, mulA(d));
  double e0 = at.error + shiftError0;
  // 2 |A| |p|: for a diagonal A >= +0 and b = 0, |grad f(p)| = |2 A p + b| (each 2 a_i p_i
  // is 2 |a_i| |p_i| up to its sign, and adding b_i = +-0 keeps its magnitude). at is f at p
  // on every path here (re-centred, or p = o).
  const glm::dvec3 absAP2 = kNonNegCentred ? absv(at.gradient) : 2.0 * q.mulAbsA<kDiagonal>(absP);
  double e1 = gamma(7) * glm::dot(kNonNegCentred ? absAP2 : absAP2 + q.absB, absD) + shiftError1;
  double e2 = gamma(5) * (kNonNegDiagonal ? c2 : glm::dot(absD, q.mulAbsA<kDiagonal>(absD)));
  int degree = 2;
  // The self-root rule's division by s (deflateAtZero), on values still in registers:
  // written to g first and read back, a shadow ray waited on its own stores (perf: a tenth
  // of its restriction; shadow rays 2 % faster, measured). Then the linear rest's one root
  // is dropped too (degree 0) where its constant term, grad f(o) . d, is zero within its
  // rounding bound or within what the origin's uncertainty moves it by (its gradient is
  // 2 A d, whose 1-norm bounds the length first): that root lies in the origin's cluster,
  // which the generic walk's window covers (multipleRootWindow, ray_roots.cpp: a double
  // plane's leaving rays hit it at twice the origin's crossing).
  if (onSurface) {
    const double v = c0, ve = e0;
    c0 = c1, c1 = c2, c2 = 0.0;
    e0 = e1, e1 = e2, e2 = 0.0;
    degree = 1;
    bool again = std::abs(c0) <= 4.0 * e0;
    // First with |2 A d|_1 <= 2 max_j sum_i |A_ij| |d|_1 (and |o|_inf <= |o|_1), which
    // keeps the common shadow ray's cost to a few products (the exact test inline cost the
    // sphere's shadow rays 3-4 %, measured).
    const double dSum = absD.x + absD.y + absD.z, pSum = absP.x + absP.y + absP.z;
    if (!again && std::abs(c0) <= 4.0 * e0 + 2.0 * data.quadricMoveBound * dSum *
                                                 (ray.orgRoundoff * pSum + orgError)) [[unlikely]]
      again = linearRootAtOrigin(data, ray, c0, e0, orgError);
    if (again) {
      c0 = c1, c1 = 0.0;
      e0 = e1, e1 = 0.0;
      degree = 0;
    } else if (originRootMatters(data, ray, v, c0, pSum, dSum) &&
               originRootApart(v, ve, c0, e0, c1, e1)) [[unlikely]] {
      // (In this order, as the packet kernel computes it: bit for bit the same.)
      const double root = std::sqrt(c0 * c0 - 4.0 * (c1 * v));
      e0 = originQuotientError(v, ve, c0, e0, c1, e1, root);
      c0 = 0.5 * (c0 + std::copysign(root, c0));
    }
  }
  g.degree = degree;
  g.tShift = tShift;
  g.c[0] = c0;
  g.c[1] = c1;
  g.c[2] = c2;
  g.err[0] = e0;
  g.err[1] = e1;
  g.err[2] = e2;
  g.selfRoot = onSurface;
}
}  // namespace

void restrictQuadricRay(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                        QuadricRay& g, double closest, double oc2) {
  const QuadricForm& q = *data.quadric;
  if (q.nonNegCentred && q.unitA)
    restrictQuadricRayOf<true, true, true, true>(data, ray, r0, r1, g, closest, oc2);
  else if (q.nonNegCentred)
    restrictQuadricRayOf<true, true, true, false>(data, ray, r0, r1, g, closest, oc2);
  else if (q.nonNegDiagonal)
    restrictQuadricRayOf<true, true, false, false>(data, ray, r0, r1, g, closest, oc2);
  else if (q.diagonal)
    restrictQuadricRayOf<true, false, false, false>(data, ray, r0, r1, g, closest, oc2);
  else
    restrictQuadricRayOf<false, false, false, false>(data, ray, r0, r1, g, closest, oc2);
}

// ---- The box of a bounded quadric ----------------------------------------------------------
// Embree calls the callbacks for every ray that meets the cell's bounds. For an ellipsoid
// the clip region's box is loose (the gallery sphere: clip radius 1.2 around the unit
// sphere, ~1.44 times the rays a native sphere gets), so the one cell becomes the
// ellipsoid's own box, padded to hold every point the intersector can report, and
// intersected with the clip region's box. The kernels clip rays to that cell (quadricSpan
// below, walkRoots' cell clip), so Embree's culling never decides a hit: a ray that meets
// the cell is traced, and the padding only makes sure no reportable root lies outside.
//
// Derivation. Take A positive definite (for A negative definite use -f: the same zero set,
// and every rule of the intersector is in |f|). For any point x0 and y = x - x0,
//   f(x) = y^T A y + r^T y + f(x0),   r = 2 A x0 + b          (exact; r = 0 at the centre).
// Completing the square, y = z - A^-1 r / 2:  f(x) = z^T A z + f(x0) - r^T A^-1 r / 4, so
// the sublevel set {f <= delta} is the ellipsoid z^T A z <= K', K' = delta - f(x0) +
// r^T A^-1 r / 4, and by Cauchy-Schwarz in the A inner product (e_i^T z = (A^-1 e_i)^T A z)
//   |y_i| <= |A^-1 r|_i / 2 + sqrt(K' (A^-1)_ii).
// With x0 = -A^-1 b / 2 as computed, r is rounding-sized; the computed f(x0) is bounded
// by its own rounding (evalQuadric), r by gamma(4) (2|A||x0| + |b|), the other terms by
// the absolute values, and what is left (the computed A^-1, off by O(kappa u) relative,
// kappa <= 2^12 below, and the rounding of the final sums) is far below the relative 2^-20
// added to every half-extent and to |x0|.
//
// What the intersector can report lies in {f <= delta} (object space):
//  * a root of the restriction by firstRoot's rules: |f| within the restriction's noise,
//    a few gamma(8) of S = m^T |A| m + |b|^T m + |c| (m bounds |x| componentwise over the
//    clip region and the ellipsoid; the re-centring point and the hit both lie there;
//    a far origin adds its shift error, gamma(2) |tShift d| |grad f|, which stays below
//    delta for origins up to ~1e9 radii away);
//  * the root left by the self-root rule (a ray leaving the surface): g(s) = c0 + s (c1 +
//    c2 s) with the root of the bracket kept, where f = c0 = f(o), and the rule admits
//    |f(o)| <= 4 err + 2 (u_o |grad f| |o| + |grad f| orgError). For float rays the bridge
//    sets orgError <= |T^-1|_F 4 u_f (|o_world| + |t_T|) + 16 u_f (|o - centre| + R).
// So delta = 2^-30 S + 4 G (orgError_max + u_f |m|), G = |2 |A| m + |b|| >= |grad f|, with
// m taken from the ellipsoid of delta = 0 (origins on the surface lie near it). A double
// ray whose host declares a larger origin error (RayD::orgError), or an origin so far
// away that its shift error passes 2^-31 S, may leave a root beyond delta: such rays are
// clipped to the cell (quadricSpan; walkRoots clips every ray), so Embree's culling and
// the kernels agree on them too.
// The float world bounds (worldBounds in surface_geometry.cpp: the transformed corners,
// padded by 2^-16 of their magnitude and rounded outward) then hold the cell and the
// widened slab test's rounding, as for every cell.
bool boundedQuadricBox(const SurfaceData& data, QuadricBox& box) {
  const Polynomial& f = data.desc.polynomial;
  if (f.degree() != 2) return false;
  QuadricForm q = data.quadric ? *data.quadric : QuadricForm::fromPolynomial(f);
  if (q.a[0][0] < 0.0) {
    q.a = -q.a;
    q.b = -q.b;
    q.c = -q.c;
  }
  const glm::dmat3& a = q.a;
  // Definite: Sylvester's leading minors, trusted because kappa_inf(A) <= 2^12 keeps every
  // eigenvalue above |A|_2 / (3 2^12), so the minors (>= lambda_min^k) exceed their
  // rounding (~6 u |A|^k) by far and no sign is decided by rounding.
  const double m1 = a[0][0], m2 = a[0][0] * a[1][1] - a[0][1] * a[1][0], m3 = glm::determinant(a);
  if (!(m1 > 0.0 && m2 > 0.0 && m3 > 0.0)) return false;
  const glm::dmat3 ai = glm::inverse(a);
  auto normInf = [](const glm::dmat3& m) {
    double n = 0.0;
    for (int r = 0; r < 3; ++r)
      n = std::max(n, std::abs(m[0][r]) + std::abs(m[1][r]) + std::abs(m[2][r]));
    return n;
  };
  const double kappa = normInf(a) * normInf(ai);
  if (!(kappa <= 0x1p12) || !(ai[0][0] > 0.0 && ai[1][1] > 0.0 && ai[2][2] > 0.0)) return false;
  glm::dmat3 absAi;
  for (int c = 0; c < 3; ++c) absAi[c] = glm::abs(ai[c]);

  const glm::dvec3 x0 = -0.5 * (ai * q.b);
  const QuadricValue at = evalQuadric(q, x0);
  const glm::dvec3 r = glm::abs(at.gradient) + gamma(4) * (2.0 * (q.absA * glm::abs(x0)) + q.absB);
  const glm::dvec3 shift = 0.5 * (absAi * r);
  const double rAr = 0.25 * glm::dot(r, absAi * r);
  auto halfExtent = [&](double delta) {
    const double k = std::max(0.0, delta - at.value + at.error + rAr);
    const glm::dvec3 e = shift + glm::sqrt(k * glm::dvec3(ai[0][0], ai[1][1], ai[2][2]));
    return e * (1.0 + 0x1p-20) + 0x1p-20 * glm::abs(x0);
  };

  // The clip region's box.
  glm::dvec3 clipLo, clipHi;
  clipRegionBox(data.desc.clip, clipLo, clipHi);
  // delta, from the bounds m of the ellipsoid of delta = 0 and the clip box (see above).
  const glm::dvec3 m =
      glm::max(glm::max(glm::abs(clipLo), glm::abs(clipHi)), glm::abs(x0) + halfExtent(0.0));
  const double lenM = glm::length(m);
  const double scale = glm::dot(m, q.absA * m) + glm::dot(q.absB, m) + std::abs(q.c);
  const double grad = glm::length(2.0 * (q.absA * m) + q.absB);
  constexpr double uFloat = 0x1p-24;
  auto frobenius = [](const glm::dmat3& t) {
    return std::sqrt(glm::dot(t[0], t[0]) + glm::dot(t[1], t[1]) + glm::dot(t[2], t[2]));
  };
  const double orgError =
      frobenius(data.aInv) * 4.0 * uFloat * (frobenius(data.a) * lenM + 2.0 * glm::length(data.b)) +
      16.0 * uFloat * (lenM + glm::length(data.centre) + data.radius);
  const double delta = 0x1p-30 * scale + 4.0 * grad * (orgError + uFloat * lenM);
  const glm::dvec3 e = halfExtent(delta);

  box.lo = glm::max(x0 - e, clipLo);
  box.hi = glm::min(x0 + e, clipHi);
  const glm::dvec3 e0 = halfExtent(0.0);
  box.surfaceLo = x0 - e0;
  box.surfaceHi = x0 + e0;
  // The ball about x0: |z|^2 <= K' lambda_max(A^-1) <= K' |A^-1|_inf (an induced norm
  // bounds the spectral radius; equal for a diagonal A) and |y| <= |shift| + |z|, padded
  // as the half-extents, and once more by 2^-20 for the rounding of a ray's squared
  // distance to x0 (meetsQuadricBall tests lines from origins within 2^16 radii only:
  // about 7 u 2^16 < 2^-33 of the squared radius, and 1 / |d|^2's 2^-40 adds 2^-48).
  const double k = std::max(0.0, delta - at.value + at.error + rAr);
  const double radius = ((glm::length(shift) + std::sqrt(k * normInf(ai))) * (1.0 + 0x1p-20) +
                         0x1p-20 * glm::length(x0)) *
                        (1.0 + 0x1p-20);
  box.ballCentre = x0;
  box.ballRadius2 =
      std::isfinite(radius) ? radius * radius : std::numeric_limits<double>::infinity();
  // The rays the derivation covers (see QuadricBox): origin error up to orgError_max, and
  // a shift error gamma(2) |tShift d| G below 2^-31 S, i.e. |o - centre| + R below
  // 2^20 S / G (gamma(2) < 2^-51).
  box.orgError = orgError;
  box.distance = 0x1p20 * scale / grad - data.radius;
  // coveredNear2 (see QuadricBox): a deferred float term 2^-20 fl(fl(sqrt(oc2)) + R) is
  // within orgError = 2^-20 K when sqrt(oc2) + R <= K (1 - 2^-40) - 5 u K or so; the
  // margins of 2^-40 on K, on its difference with R and on the square stand for every
  // rounding here and there (a few u).
  const double kMax = box.orgError * 0x1p20;
  const double sMax = (kMax * (1.0 - 0x1p-40) - data.radius) * (1.0 - 0x1p-40);
  box.coveredNear2 =
      box.orgError >= 0x1p-900 && std::isfinite(kMax) && sMax > 0.0 && std::isfinite(sMax * sMax)
          ? sMax * sMax * (1.0 - 0x1p-40)
          : 0.0;
  return finite(box.lo) && finite(box.hi) && glm::all(glm::lessThan(box.lo, box.hi)) && grad > 0.0;
}

// ---- The dedicated path ---------------------------------------------------------------------
bool usesQuadricPath(const SurfaceData& data) {
  const SurfaceOptions& opt = data.desc.options;
  // The generic walk's quadric branch (solveFirst) with one cell and the default solver:
  // other root options are measurement switches and keep the generic path.
  return data.quadric && opt.quadricCallbacks && data.cells.size() == 1 && !opt.singlePrecision &&
         opt.roots.method == RootMethod::Auto && opt.roots.relTolerance == 0.0;
}

bool cellHoldsClipRegion(const SurfaceData& data) {
  glm::dvec3 lo, hi;
  clipRegionBox(data.desc.clip, lo, hi);
  const SurfaceCell& cell = data.cells.front();
  return glm::all(glm::lessThanEqual(cell.lo, lo)) && glm::all(glm::greaterThanEqual(cell.hi, hi));
}

namespace {
// Whether the line o + t d passes within the tight box's ball (or too far off to tell):
// its closest point by the chord's arithmetic (clipToSphere). quadricGroup
// (quadric_packet_group.inc) repeats it.
// chord: |o - c|^2 and |q|^2 of the clip sphere's chord (clipToSphere) when the sphere has
// the ball's centre c (else NaN): the same operations as below, so the same values. (==
// takes -0 for 0, and o - c differs then only in the sign of a zero, which no square sees.)
bool meetsQuadricBall(const QuadricBox& box, const glm::dvec3& o, const glm::dvec3& d,
                      const ChordTerms& chord) {
  double ob2 = chord.oc2;
  if (std::isnan(ob2)) {
    const glm::dvec3 ob = o - box.ballCentre;
    ob2 = glm::dot(ob, ob);
  }
  if (ob2 <= box.ballRadius2 || !(ob2 <= 0x1p32 * box.ballRadius2))
    return true;  // inside, or too far
  if (!std::isnan(chord.q2)) return chord.q2 <= box.ballRadius2;
  const glm::dvec3 ob = o - box.ballCentre;
  const double tb = -glm::dot(ob, d) * inverseSquaredLength(glm::dot(d, d));
  const glm::dvec3 qb = ob + tb * d;
  return glm::dot(qb, qb) <= box.ballRadius2;
}
}  // namespace

bool quadricSpan(const SurfaceData& data, const KernelRay& ray, QuadricSpan& q) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  // Non-finite or degenerate rays have no hit (as in walkRoots; written out in both: a
  // shared inline helper measured 3-5 % slower on the sphere's shadow rays). o and d
  // finite at once: x - x is 0 for a finite x and NaN for inf or NaN, so the sum is 0 just
  // when all six are finite (GCC keeps x - x without -ffinite-math-only); a NaN tnear or
  // tfar fails tnear < tfar. (Per value, the tests were ~30 instructions of every ray;
  // callgrind, AMD Zen 3.)
  const glm::dvec3 zo = o - o, zd = d - d;
  if (!((zo.x + zo.y + zo.z) + (zd.x + zd.y + zd.z) == 0.0) || !(ray.orgError >= 0.0)) return false;
  if (!(glm::dot(d, d) > 0.0) || !(ray.tnear < ray.tfar)) return false;
  // The clip region's span; the restriction keeps its frame (its re-centring point), as
  // the generic walk does, so both give the same coefficients. The clip sphere's chord
  // yields the re-centring parameter on the way, which saves the restriction a division
  // on its critical path.
  // (clipToSphere inline here: the call across files to clipRegionSpan cost the sphere
  // 6-7 % of its primary and shadow rays, measured.)
  double r0 = -std::numeric_limits<double>::infinity(),
         r1 = std::numeric_limits<double>::infinity();
  // With it, the chord's |o - c|^2 and |q|^2 for the tests below that repeat them about the
  // same centre (data.centre, the ball's; the gallery's clip spheres share both): |o - c|^2
  // was computed five times per ray, |q|^2 twice for a camera's ray (measured: the sphere's
  // primary rays 1-2 % faster).
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double closest = kNaN, centreOc2 = kNaN;
  ChordTerms ball{kNaN, kNaN};
  if (const auto* sphere = std::get_if<ClipSphere>(&data.desc.clip)) {
    double tc;
    ChordTerms chord{kNaN, kNaN};
    if (!clipToSphere(*sphere, o, d, r0, r1, tc, &chord)) return false;
    if (sphere->center == data.centre) {
      closest = tc;
      centreOc2 = chord.oc2;
    }
    if (sphere->center == data.quadricBox.ballCentre) ball = chord;
  } else if (!clipRegionSpan(data, o, d, r0, r1)) {
    return false;
  }
  // The cell's span, when the cell is smaller than the clip region (an ellipsoid's own
  // box, boundedQuadricBox; or a cell the build shrank): walkRoots' cell clip. A cell
  // holding the clip region needs none (its widened slab holds the region's span).
  // A ray the tight box's derivation covers cannot report a root outside it (nor, then,
  // outside the cell, which is that box within the clip region): it skips the clip, whose
  // three divisions cost shadow rays ~8 % (measured); the others are clipped.
  double c0 = r0, c1 = r1;
  if (data.quadricCellClip) {
    const QuadricBox& box = data.quadricBox;
    double oc2 = centreOc2;
    if (std::isnan(oc2)) {
      const glm::dvec3 oc = o - data.centre;
      oc2 = glm::dot(oc, oc);
    }
    // (A deferred float origin error, the bridge's, is known to be within box.orgError
    // without its square root when the origin is within coveredNear2. Measured, with
    // restrictQuadricRay's farOrigin alike: the sphere's single primary rays 12.1 -> 12.5
    // Mrays/s, 0.945x -> 0.977x of Embree's sphere; speed_report, 5 interleaved runs.)
    const bool covered = oc2 <= box.distance * box.distance &&
                         ((ray.orgErrorDeferred && ray.orgError == 0.0 &&
                           ray.orgRoundoff <= 0x1p-24 && oc2 <= box.coveredNear2) ||
                          wholeOrgError(data, ray) <= box.orgError);
    if (!covered && !clipToBox(data.cells.front().lo, data.cells.front().hi, o, d, c0, c1, true))
      return false;
    // A covered ray that passes outside the ellipsoid's ball has no root to report: no
    // restriction or solve (a quarter of a camera's rays at the gallery sphere, measured).
    if (covered && !meetsQuadricBall(box, o, d, ball)) return false;
  }
  // The solve's span ends where the region (or the cell) does, not at tfar, which
  // offerQuadricRoots compares the roots with (embree_bridge.cpp): the solver reports a
  // root within noise of its span's end at that end, which is no hit (the span is open
  // there), so a span ending at tfar dropped a root just before it. A double ray's closest
  // hit with tfar = nextafter(t) past its own hit t missed the sphere on every ray, and
  // with t (1 + 2e-15) on a third of them (session 48; the generic walk solves over the
  // region). (The packet kernel alike, quadric_packet_group.inc.)
  const double lo = std::max(c0, ray.tnear), hi = c1;
  if (!(lo < hi) || !(lo < ray.tfar)) return false;
  restrictQuadricRay(data, ray, r0, r1, q.g, closest, centreOc2);
  // A constant g has no isolated root (no intersection, or a ruling of the surface), and
  // neither has a g whose coefficients are all exactly 0, whatever their rounding bounds: the
  // line lies in the surface as computed (a ruling through the expansion point), and the
  // solver reported a noise root at the span's middle (the apex, t = 10, of x^2+y^2-z^2 along
  // (-7.5, -10, -12.5) + t (0.75, 1, 1.25); the generic path and docs/accuracy.md: no hit).
  if (q.g.degree < 1 || (q.g.c[0] == 0.0 && q.g.c[1] == 0.0 && q.g.c[2] == 0.0)) return false;
  q.slo = lo - q.g.tShift;
  q.shi = hi - q.g.tShift;
  return q.slo < q.shi;
}

bool quadricRoot(const QuadricSpan& q, double slo, double& s) {
  const QuadricRay& g = q.g;
  if (!(slo < q.shi)) return false;
  const int found = g.degree == 2 && g.c[2] != 0.0 ? quadraticFirst(g, slo, q.shi, s)
                    : g.degree == 1                ? linearFirst(g, slo, q.shi, s)
                                                   : -1;
  if (found >= 0) return found == 1;
  return g.degree == 2 && g.c[2] != 0.0
             ? solveFirstRootQuadratic(std::span<const double, 3>(g.c, 3),
                                       std::span<const double, 3>(g.err, 3), slo, q.shi, s)
             : solveFirstRoot(std::span<const double>(g.c, g.degree + 1),
                              std::span<const double>(g.err, g.degree + 1), slo, q.shi, s);
}

}  // namespace algray
