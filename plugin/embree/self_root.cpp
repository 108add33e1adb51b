// The self-root rule (ray_roots.h): a ray whose origin lies on the surface, where an
// epsilon-free solver would find the origin's own root, gets g about the origin with that
// root divided out, and a window about the origin whose roots are the origin's: simple
// roots (the division), multiple ones (a cluster on a surface of multiplicity m, a singular
// origin), and roots of the quotient that only the zeroed constant made real
// (inOriginNoise, ray_roots.cpp). Step 4 of the way of one ray in ../shared/DESIGN.md:
// "the self-root at a ray's own origin excluded".
#include "ray_roots.h"

#include "double_channel.h"

#include "algray/taylor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <type_traits>

namespace algray {

namespace {

// ---- Self-root rule ------------------------------------------------------------------
// A ray leaving the surface starts at a point p that is on the surface only up to
// rounding: f(p) = O(u). Its polynomial g(s) = f(p + s d) then has a root at |s| tiny,
// which an epsilon-free solver reports as a hit at the origin (shadow acne). When f(p)
// is zero within the bound of its evaluation plus the effect of p's own uncertainty
// (|grad f| times the coordinate rounding or the host's orgError, pbrt-v4 Sec. 6.8.6),
// the origin is on the surface: expand about p itself (tShift = 0), set g(0) = 0 and
// divide by s. The quotient has exactly the other intersections. Repeat while the new
// constant term is zero within its bound: a ray tangent at its origin, or an origin at a
// singular point (cone apex, Sarti's nodes) where the root at 0 is multiple.
//
// What the rule needs of f at the origin does not depend on the direction, so it is kept
// per thread for the last origin: a camera's primary rays evaluate f at the eye once
// instead of once per ray (for a surface the rays mostly miss, that evaluation was the
// only one on their path).
struct OriginValue {
  std::uint64_t id = 0;
  glm::dvec3 org{0.0};
  double value = 0, valueError = 0;
  double gradDotOrg = 0;  // |grad f| . |o|
  glm::dvec3 gradient{0.0};
  double gradLength = -1;  // ||grad f||, computed when a ray has an origin error (-1: not yet)
};
// Trivially destructible, so no destructor is registered (see threadOriginCache).
static_assert(std::is_trivially_destructible_v<OriginValue>);
thread_local OriginValue tlsOriginValue;

}  // namespace

// orgError: the ray's whole bound (with a deferred float term added).
bool originOnSurface(const SurfaceData& data, const KernelRay& ray, double orgError) {
  OriginValue& v = tlsOriginValue;
  if (v.id != data.id || v.org != ray.org) {
    v.id = 0;
    const Polynomial::Evaluation e = data.horner.evaluate(ray.org);
    v.value = e.value;
    v.valueError = e.valueError;
    v.gradDotOrg = glm::dot(absv(e.gradient), absv(ray.org));
    v.gradient = e.gradient;
    v.gradLength = -1;
    v.org = ray.org;
    v.id = data.id;
  }
  // A float ray's origin is exact (orgError = 0): no length, whose square root and
  // divisions were the largest single cost of a shadow ray leaving a quadric.
  double move = ray.orgRoundoff * v.gradDotOrg;
  if (orgError != 0.0) {
    if (v.gradLength < 0) v.gradLength = safeLength(v.gradient);
    move += originMove(data, ray, v.gradient, v.gradLength, orgError);
  }
  return std::abs(v.value) <= 4.0 * v.valueError + 2.0 * move;
}

namespace {

// deflateAtZero undone: g / s (degree n - 1) is G again, its constant c0 (bound e0).
void undeflate(RayPolynomial& g, double c0, double e0) {
  ++g.degree;
  for (int i = g.degree; i > 0; --i) g.coeff[i] = g.coeff[i - 1], g.error[i] = g.error[i - 1];
  g.coeff[0] = c0, g.error[0] = e0;
}

// A sign change of G = f(o + s d) in (lo, hi); lo = hi = 0: none.
struct OwnRootBracket {
  double lo = 0.0, hi = 0.0;
};
// crossingsNearOrigin's and splitCluster's answer: own, the origin's crossing among G's
// sign changes near it (none: the ray does not cross the origin's sheet there), changes and
// unclear, what the look saw; apart (splitCluster), the cluster is sheets apart.
struct ClusterSplit {
  bool apart = false;
  OwnRootBracket own;
  int changes = 0;  // G's sign changes seen
  int unclear = 0;  // points where G was within its noise
  int nearby = 0;   // crossings whose tangent plane lies within reach of the origin
};

// ---- Multiple roots at the origin -----------------------------------------------------------
// On a surface of multiplicity m (f = h^m q: a double plane, a squared sphere) the origin
// lies off h = 0 by up to its uncertainty, so g = f(o + s d) has m roots clustered around
// the origin's own crossing t* (g ~ a^m (s - t*)^m there), and its coefficients c_1 ..
// c_(m-1) are small but not zero. Dividing out the root at 0 leaves the others: for m = 2
// the quotient a (a s - 2 a t*) has its root at 2 t*, beyond the self-root window where the
// ray grazes (a leaving ray found its own surface at 2 t*, 3 t* for m = 3, and an occlusion
// query could disagree with the closest hit of the same ray). Dividing out c_1 .. c_(m-1)
// too would be wrong: setting them to 0 perturbs g by O(c_1 s) far from the origin, which
// splits the far side's double root of h^2 into a complex pair (rays leaving a squared
// sphere inwards missed its far side; so did the repeated division of a constant term that
// was zero within its rounding bound, until session 43). So the window grows instead, over
// the cluster: the rule finds m as the first coefficient clear of its rounding bound and, at
// an origin where f may be singular (multipleRootWindow's gates), of what the origin's
// uncertainty moves it by (as it asks of c_0 = f(o) in originOnSurface: grad c_k =
// grad H_(k+1)(d), H_n the degree-n homogeneous part of f expanded about o, through
// originMove); the cluster's roots lie within Fujiwara's bound of c_1 + ... + c_m s^(m-1),
// 2 max |c_i / c_m|^(1 / (m - i)), and the window is twice that for the higher terms.
glm::dvec3 homogeneousGradient(const Polynomial& shifted, int n, const glm::dvec3& d) {
  glm::dvec3 grad(0.0);
  auto power = [](double x, int e) {
    double p = 1.0;
    for (int i = 0; i < e; ++i) p *= x;
    return p;
  };
  for (int i = n; i >= 0; --i)
    for (int j = n - i; j >= 0; --j) {
      const int k = n - i - j;
      const double c = shifted.coeff(i, j, k);
      if (c == 0.0) continue;
      const double px = power(d.x, i), py = power(d.y, j), pz = power(d.z, k);
      if (i > 0) grad.x += c * i * power(d.x, i - 1) * py * pz;
      if (j > 0) grad.y += c * j * px * power(d.y, j - 1) * pz;
      if (k > 0) grad.z += c * k * px * py * power(d.z, k - 1);
    }
  return grad;
}

// Whether the ray from the origin moved onto the surface (one Newton step along grad f)
// changes sign, clearly, between s / 2 and 2 s: a crossing near s that is not there only
// because the origin lies off the surface.
// origin: f and grad f at the origin (originOnSurface's).
bool crossesFromSurfacePoint(const SurfaceData& data, const KernelRay& ray,
                             const OriginValue& origin, double s) {
  const double gg = glm::dot(origin.gradient, origin.gradient);
  if (!(gg > 0.0) || !std::isfinite(gg)) return false;
  const glm::dvec3 p = ray.org - (origin.value / gg) * origin.gradient;
  const Polynomial::Evaluation a = data.horner.evaluate(p + 0.5 * s * ray.dir),
                               b = data.horner.evaluate(p + 2.0 * s * ray.dir);
  return std::abs(a.value) > a.valueError && std::abs(b.value) > b.valueError &&
         (a.value < 0.0) != (b.value < 0.0);
}

// The crossings of G(s) = f(o + s d) near the origin, where the self-root rule cannot take
// the origin's root from g's coefficients alone: G's clear sign changes on a grid over
// +-window (16 steps) and at the extra points, and among them the origin's own crossing,
// the one whose tangent plane lies nearest the origin, |s| |d . n| (n the unit normal
// there), if within 4 dist (the rule takes origins up to about twice dist off their
// sheet). Along a grazing ray that crossing can lie far from the origin, and a ray leaving
// nearly tangentially may not cross the origin's sheet at all, or cross it twice within a
// step of the grid (the halvings towards the origin below). g is deflated (g.coeff[i] =
// c_(i+1)); c0, e0: G's constant and its rounding bound; dist: the origin's uncertainty
// (originDistance); origin: f and grad f at the origin (originOnSurface's).
ClusterSplit crossingsNearOrigin(const SurfaceData& data, const KernelRay& ray,
                                 const OriginValue& origin, double dist, double c0, double e0,
                                 const RayPolynomial& g, double window,
                                 std::initializer_list<double> extra) {
  constexpr int kSteps = 8, kHalvings = 12;
  std::array<double, 2 * kSteps + 2 * kHalvings + 4> at{};
  int count = 0;
  for (int j = -kSteps; j <= kSteps; ++j) at[count++] = window * j / kSteps;
  // (and at +-window 2^-k, k = 4 .. 15, for the pair a ray nearly tangent to the origin's
  // sheet crosses it in, which can lie within one step)
  for (int k = 4; k < 4 + kHalvings; ++k) {
    const double x = std::ldexp(window, -k);
    at[count++] = -x, at[count++] = x;
  }
  for (const double x : extra)
    if (std::isfinite(x) && count < static_cast<int>(at.size())) at[count++] = x;
  std::sort(at.begin(), at.begin() + count);
  // G at x, and its sign where G is clear of its noise (g's bound at x, the two roundings
  // of c0 + x g(x), c0's own), else 0.
  auto valueAt = [&](double x) { return c0 + x * g.evaluate(x); };
  auto clearSign = [&](double x) {
    double bound;
    const double tail = x * g.evaluateWithBound(x, bound), value = c0 + tail;
    const double noise = e0 + std::abs(x) * bound + gamma(2) * (std::abs(c0) + std::abs(tail));
    return std::abs(value) > 4.0 * noise ? (value > 0.0 ? 1 : -1) : 0;
  };
  ClusterSplit split;
  int lastSign = 0;
  double last = 0.0;
  // The two crossings within reach nearest the origin's tangent planes: bracket, s, distance.
  struct Near {
    OwnRootBracket bracket;
    double s = 0.0, distance = std::numeric_limits<double>::infinity();
  } first, second;
  for (int i = 0; i < count; ++i) {
    const int sign = clearSign(at[i]);
    if (sign == 0) {
      ++split.unclear;
      continue;
    }
    if (lastSign == -sign) {
      ++split.changes;
      // The crossing to a few digits (bisection on G's computed sign), its tangent plane's
      // distance from the origin.
      double lo = last, hi = at[i];
      for (int k = 0; k < 16; ++k) {
        const double mid = 0.5 * (lo + hi);
        ((valueAt(mid) > 0.0) == (lastSign > 0) ? lo : hi) = mid;
      }
      const double s = 0.5 * (lo + hi);
      const glm::dvec3 n = data.horner.evaluate(ray.org + s * ray.dir).gradient;
      const double length = safeLength(n);
      const double distance = length > 0.0 ? std::abs(s * glm::dot(ray.dir, n)) / length
                                           : std::numeric_limits<double>::infinity();
      if (distance <= 4.0 * dist) {
        ++split.nearby;
        const Near here{{last, at[i]}, s, distance};
        if (distance < first.distance)
          second = first, first = here;
        else if (distance < second.distance)
          second = here;
      }
    }
    lastSign = sign, last = at[i];
  }
  // One crossing within reach is the origin's. Of two, the nearer is where the other is a
  // crossing of the ray from the origin moved onto the surface too (one Newton step along
  // grad f; a ray from a point inside a sphere near its surface, nearly tangent: the
  // origin's crossing behind it, the far side ahead); else both are the origin's (the pair
  // a ray nearly tangent at its origin crosses its own sheet in where the origin lies off
  // it, one either side: dividing out one reported the other, 6e-3 ahead on the Cayley
  // cubic where the ray from the surface point meets nothing; the review of session 47).
  if (split.nearby == 1 ||
      (split.nearby == 2 && crossesFromSurfacePoint(data, ray, origin, second.s)))
    split.own = first.bracket;
  return split;
}

// Whether a cluster that the origin's uncertainty made (c_1 .. c_m zero within it) is
// sheets apart instead: on f = h^k q (q != 0 near the origin) G(s) = h(o + s d)^k q(o + s
// d) changes sign at most once through the cluster, wherever the origin lies (never for
// even k), so two clear sign changes of G over its window say it crosses sheets apart. A
// thin shell (x^2+y^2+z^2-1)(x^2+y^2+z^2-1.00008) left from 2.8e-6 off its inner sheet,
// with an orgError twice that, took c_1 for zero (the shell's mid-surface, where grad f
// vanishes, is within 4 times the move) and the window, 4 |c_1 / c_2|, swallowed the outer
// sheet 4.4e-4 along a grazing ray (a miss); with orgError near the shell's width c_2 too.
// For a pair (m = 1) whose quadratic c_0 + c_1 s + c_2 s^2 has real roots G is also looked
// at in their middle and as far again beyond each.
ClusterSplit splitCluster(const SurfaceData& data, const KernelRay& ray, const OriginValue& origin,
                          double dist, double c0, double e0, const RayPolynomial& g, int m,
                          double window) {
  const double c1 = g.coeff[0], c2 = g.coeff[1];
  const double middle = -c1 / (2.0 * c2), half = std::sqrt(c1 * c1 - 4.0 * c0 * c2) / (2.0 * c2);
  const double none = std::numeric_limits<double>::quiet_NaN();
  ClusterSplit split =
      m == 1 ? crossingsNearOrigin(data, ray, origin, dist, c0, e0, g, window,
                                   {middle - 2.0 * half, middle, middle + 2.0 * half})
             : crossingsNearOrigin(data, ray, origin, dist, c0, e0, g, window, {none});
  // Sheets apart where the origin's crossing is told (crossingsNearOrigin), or no crossing
  // is within its reach and G is clear of its noise everywhere looked at with c_0 clear
  // (the ray passes its sheet by). A cluster whose G is within its noise
  // somewhere and with no crossing in reach is the multiple surface the rule is for (a
  // double plane x^2 q with a sphere's crossings in its long window: g / s with window 0
  // reported a point 2.6-3.6 orgError off both surfaces; the review).
  const bool own = split.own.lo < split.own.hi;
  split.apart = split.changes >= 2 &&
                (own || (split.nearby == 0 && split.unclear == 0 && std::abs(c0) > 4.0 * e0));
  if (!split.apart) split.own = {};
  return split;
}

// The window over the origin's cluster of roots, for g after deflateAtZero (so g's c_i is
// the Taylor coefficient c_(i + 1) at o), or 0 when g's constant term is clear. orgError:
// the ray's whole bound; origin: f(o), its error bound and grad f(o) (originOnSurface's);
// c0, e0: g's constant before deflateAtZero and its rounding bound. split: where a
// cluster the uncertainty made is sheets apart (splitCluster; the window is then 0).
double multipleRootWindow(const SurfaceData& data, const KernelRay& ray, double orgError,
                          const OriginValue& origin, double c0, double e0, const RayPolynomial& g,
                          ClusterSplit& split) {
  split = {};
  const double originValue = origin.value, originValueError = origin.valueError;
  const glm::dvec3& gradient = origin.gradient;
  // Coefficients zero within their rounding bound (a ray tangent at its origin, a node)
  // need no expansion.
  int m = 0;
  while (m <= g.degree && std::abs(g.coeff[m]) <= 4.0 * g.error[m]) ++m;
  const int roundingM = m;
  // Beyond those, only where the origin may be a singular point of f (elsewhere its root is
  // simple: a ray grazing a simple surface keeps the rule of before). The expansion below
  // for every leaving ray cost Sarti's shadow rays 7x their time, so two gates first.
  // (1) From the values the rule already has: on f = h^2 q near the origin grad f =
  // 2 h q grad h, c_0 = h^2 q and c_1 = 2 h q (grad h . d), so |hess f d| ~ 2 q |grad h|
  // |grad h . d| = |grad f| |c_1| / (2 |c_0|) (|c_0| with 4 times its error bound: f(o) can
  // round to 0); it must lie within 4 times the smaller of the clip ball's Hessian bound
  // (2^-10 hitPointNoise, row sums: |hess f d|_2 <= sqrt(3) that |d|_inf) and the Hessian
  // as sampled over the clip box (SurfaceData::sampledHessian, 4 times the largest column
  // seen: |hess f d|_2 <= 3 max column |d|_inf; the bound is far looser where f's
  // coefficients cancel, and with it every shadow ray of Barth's decic paid gate (2)), times
  // |d|_inf (grad f's largest component for its length: smaller, so safe). At a simple
  // surface's origin, c_0 ~ |grad f| dist and c_1 ~ |grad f| |d| sin(angle): the quotient is
  // |grad f| sin(angle) / dist, far beyond that bound unless the ray grazes within ~dist.
  // (A cluster radius from c_0..c_2 let a double sphere's grazing rays through: c_2 =
  // (grad h . d)^2 + 2 h a cancels there.) (2) At the origin: |grad f(o)| within 32 times
  // what the origin's uncertainty moves it by along grad f, the change of grad f over a
  // step `step` that way (one evaluation) over the step: on h^2, where the rule admits
  // |h(o)| <= 8 dist, |grad f| = 2 |h| |grad h| <= 8 |hess f grad f / |grad f|| dist; at a
  // simple surface's origin the quotient is the curvature's, |grad f| / (curvature dist).
  // (Bounds from f's |coefficients| - the clip ball's, or grad F(|o| + R / 16) / (R / 16)
  // with F = f's |coefficients| - are too loose where the coefficients cancel: every
  // shadow ray of Chmutov-16 expanded f, 13x their time.) Where grad f is rounding noise,
  // c_1 is within its rounding bound too, which the first loop takes.
  const glm::dvec3& o = ray.org;
  const double dist = originDistance(ray, orgError);
  const double gradMax =
      std::max({std::abs(gradient.x), std::abs(gradient.y), std::abs(gradient.z)});
  const glm::dvec3& d = ray.dir;
  const double dInf = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  const double hessian =
      std::min(data.hitPointNoise > 0.0 ? 0x1p-10 * data.hitPointNoise
                                        : std::numeric_limits<double>::infinity(),
               data.sampledHessian);
  bool singular =
      m <= g.degree && gradMax * std::abs(g.coeff[0]) <=
                           8.0 * (std::abs(originValue) + 4.0 * originValueError) * hessian * dInf;
  if (singular && gradMax > 0.0) {
    const double gradLength = safeLength(gradient);
    const double step = 32.0 * dist + 0x1p-24 * data.radius;
    const glm::dvec3 across =
        data.horner.evaluate(o + (step / gradLength) * gradient).gradient - gradient;
    singular = gradLength <= 32.0 * (safeLength(across) / step) * dist;
  }
  if (singular) {
    Polynomial shifted;
    bool expanded = false;
    for (; m <= g.degree; ++m) {
      const int k = m + 1;
      const double c = std::abs(g.coeff[m]), rounding = 4.0 * g.error[m];
      // Within 2 (k + 1) times the move, not twice as c_0's test: on f = h^m (h with
      // |grad h| = 1 at the origin) the rule takes an origin with |h(o)| up to 2 m dist for
      // a point of the surface, and c_k, C(m, k) h(o)^(m-k) a^k, is within 2 (k + 1) |grad
      // c_k| dist for every such origin and k < m (since m <= (k + 1)(m - k)). With twice,
      // |h(o)| between 4 and 8 dist on a double sphere left c_1 outside the cluster and its
      // root at 2 t* (grazing rays in the sanitizer build's rounding).
      const double factor = 2.0 * (k + 1);
      // Coarse: |grad c_k|_2 <= sqrt(3) B_k |d|_inf^k, so the move below is at most twice
      // this.
      double coarse = k < kMaxDegree ? data.coefficientMove[k] : 0.0;
      for (int i = 0; i < k; ++i) coarse *= dInf;
      if (!(c <= rounding + 2.0 * factor * coarse * dist)) break;
      if (!expanded) {
        shifted = data.desc.polynomial.translate(o);
        expanded = true;
      }
      const glm::dvec3 grad = homogeneousGradient(shifted, k + 1, d);
      if (!(c <= rounding + factor * originUncertaintyMove(data, ray, grad, orgError))) break;
    }
  }
  if (m == 0) return 0.0;
  // Every coefficient zero within the origin's uncertainty: the ray runs along the surface.
  if (m > g.degree) return std::numeric_limits<double>::infinity();
  double bound = 0.0;
  const double top = std::abs(g.coeff[m]);
  for (int i = 0; i < m; ++i)
    bound = std::max(bound, std::pow(std::abs(g.coeff[i]) / top, 1.0 / (m - i)));
  const double window = 4.0 * bound;
  if (roundingM == 0) {
    split = splitCluster(data, ray, origin, dist, c0, e0, g, m, window);
    if (split.apart) return 0.0;
  }
  return window;
}

// ---- The origin's own root, when it is not 0 -------------------------------------------------
// An origin the rule takes for a point of the surface lies off it by up to its uncertainty
// (the host's orgError, up to twice over: originOnSurface). g(0) = c_0 = f(o) is then clear
// of its rounding, and g's root near the origin is r ~ -c_0 / c_1, not 0. deflateAtZero's
// g / s (c_0 set to 0) keeps the sum of the roots (Vieta), so every other root moved by
// about r: the far side of a unit sphere seen from 1e-4 off, with orgError 1e-4, was 1e-4
// off, and where the surface meets the clip region the moved root left it (a miss; a
// clip ball at the sphere's radius lost the far side for offsets from 1e-4 down).
// Where that moves them by more than the ray's resolution (originRootMatters), g is
// divided by (s - r) instead: Newton from r0 = -c_0 / c_1 gives r, and synthetic division
// the quotient q (q_(n-1) = c_n, q_(k-1) = c_k + r q_k), whose roots are g's others. Only
// for a simple root well apart from the rest, rho = sum_(i>=2) |c_i| |r0|^(i-1) / |c_1| <=
// 1/8 (g within 1/8 of its tangent line over [0, 2 r0], so Newton converges there,
// quadratically: the relative error after k steps is at most rho^(2^k), one step where rho
// <= 2^-27); near-tangent origins, whose clusters multipleRootWindow covers, keep g / s.
// Error bounds (Higham, Sec. 3.1, for the recurrence; the remainder g(r), within g's noise,
// is dropped with its size and g's noise at r added to the constant term's bound). Whatever
// r is, g(s) = (s - r) q(s) + g(r), so q's roots are g's others up to the remainder: r's
// own error needs no term (session 46 added dr |q_(k+1)| to every q_k, with dr = g's noise
// at r over |g'(r)|; the review of session 47 found that, at the tiny slopes of a thin
// shell's or a nearly tangent origin's root, it raised q's bound over a shell's gap, and
// the noise rule reported points there, on no surface: 10-22 of 1776 grazing float rays).
// A near-tangent origin (rho above 1/8: a cluster splitCluster told apart, a thin shell's
// sheets, or divideNearTangentRoot's) has a bracket of its root instead, own: Newton
// safeguarded by bisection in it, to a step or bracket within 2^-50 |r|, and g evaluated
// again at r for the bounds. rr.g: after deflateAtZero (coeff[k] = c_(k+1)), divided in
// place, and rr's division terms set (divisionNoise); c0, e0: g's constant term and its
// bound; own: lo = hi = 0 for the simple root's rule.
bool divideByOriginRoot(RayRoots& rr, double c0, double e0, OwnRootBracket own) {
  RayPolynomial& g = rr.g;
  const int n = g.degree + 1;  // g's degree before the division by s
  const double c1 = g.coeff[0];
  if (!(std::abs(c0) > 4.0 * e0) || !(std::abs(c1) > 4.0 * g.error[0])) return false;
  const double noiseFactor = gamma(2 * n + 1);
  double value = 0.0, slope = 0.0, noise = 0.0, rest = 0.0;
  // g(r), g'(r), sum (e_i + gamma(2n + 1) |c_i|) |r|^i and sum_(i>=2) |c_i| |r|^(i-1) in one
  // pass (c_(k+1) = coeff[k]).
  auto horner = [&](double r) {
    const double ar = std::abs(r);
    value = g.coeff[n - 1], slope = 0.0, noise = g.error[n - 1] + noiseFactor * std::abs(value);
    rest = std::abs(value);
    for (int k = n - 2; k >= -1; --k) {
      const double ck = k >= 0 ? g.coeff[k] : c0, ek = k >= 0 ? g.error[k] : e0;
      slope = slope * r + value;
      value = value * r + ck;
      noise = noise * ar + ek + noiseFactor * std::abs(ck);
      if (k >= 1) rest = rest * ar + std::abs(ck);
    }
  };
  double r = -c0 / c1;
  if (!(own.lo < own.hi)) {
    double predicted = 0.0;
    for (int step = 0; step < 6; ++step) {
      horner(r);
      if (step == 0) {
        predicted = rest * std::abs(r) / std::abs(c1);  // rho, r0's relative error at most
        if (!(predicted <= 0.125)) return false;
      }
      r -= value / slope;
      // Newton's relative error e_(k+1) <= rho e_k^2 <= e_k^2 (the review of session 46: a
      // test of rho alone, which does not shrink with the steps, ran all six every time).
      predicted *= predicted;
      if (predicted <= 0x1p-54) break;
    }
  } else {
    horner(own.lo);
    const bool loNegative = value < 0.0;
    double lo = own.lo, hi = own.hi;
    if (!(r > lo && r < hi)) r = 0.5 * (lo + hi);
    bool converged = false;
    for (int step = 0; step < 128 && !converged; ++step) {
      horner(r);
      ((value < 0.0) == loNegative ? lo : hi) = r;
      double next = r - value / slope;
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      converged =
          std::abs(next - r) <= 0x1p-50 * std::abs(next) || hi - lo <= 0x1p-50 * std::abs(next);
      r = next;
    }
    if (!converged) return false;
    horner(r);
  }
  if (!std::isfinite(r) || !(slope != 0.0)) return false;
  const double ar = std::abs(r);
  for (int k = n - 2; k >= 0; --k) {
    const double q = g.coeff[k + 1], term = r * q;
    g.coeff[k] += term;
    g.error[k] += ar * g.error[k + 1] + gamma(2) * (std::abs(g.coeff[k]) + std::abs(term));
  }
  g.error[0] += std::abs(value) + noise;
  rr.divisionRoot = r;
  rr.divisionRemainder = std::abs(value) + noise;
  return true;
}

// A near-tangent origin off its surface (divideByOriginRoot's rho above 1/8, where
// -c_0 / c_1 is no estimate of the root): the origin's crossing among those near it
// (crossingsNearOrigin, over twice the quadratic c_0 + c_1 s + c_2 s^2's nearer root),
// divided out from its bracket; no crossing near enough, or the quadratic's roots complex:
// g / s stays. From an origin 0.06 w off a thin shell's inner sheet (w = 1e-3, orgError
// 7e-5), leaving at 0.012 rad, g / s moved the outer sheet's root by the origin's, 1.2e-3
// of 0.033. (Where the ray passes its sheet by, g = G itself was tried (f58089f) and taken
// out: from a float hit 7.4e-8 inside a torus, 1.4e-4 rad from the tangent plane, the ray
// from the exact hit point re-crosses the sheet 4.4e-4 ahead, which g / s, whose roots are
// f = f(o)'s, finds and G from the rounded origin does not: 426 of 445 differing grazing
// float rays on 14 gallery surfaces lost such a hit, and the look cost grazing rays 17-30
// %; the review of session 47.) Returns whether g is no longer g / s.
bool divideNearTangentRoot(const SurfaceData& data, const KernelRay& ray, const OriginValue& origin,
                           double orgError, double c0, double e0, RayRoots& rr) {
  RayPolynomial& g = rr.g;
  if (!(std::abs(c0) > 4.0 * e0)) return false;
  const double c1 = g.coeff[0], c2 = g.degree >= 1 ? g.coeff[1] : 0.0;
  const double disc = c1 * c1 - 4.0 * c0 * c2;
  if (!(disc >= 0.0)) return false;
  const double nearRoot = c0 / (-0.5 * (c1 + std::copysign(std::sqrt(disc), c1)));
  if (!std::isfinite(nearRoot) || nearRoot == 0.0) return false;
  // The quadratic must model g there (|c_3 r| <= |c_2| / 2) and the crossing found lie on
  // its root's side: on the Clebsch cubic c_3 = 94 against c_2 = -0.63 predicted a root
  // 0.005 ahead where G had none, the crossing found 0.006 behind was divided out, and
  // the sheet's re-crossing ahead that g / s keeps was lost (the third review).
  const double c3 = g.degree >= 2 ? g.coeff[2] : 0.0;
  if (!(std::abs(c3 * nearRoot) <= 0.5 * std::abs(c2))) return false;
  const ClusterSplit near = crossingsNearOrigin(data, ray, origin, originDistance(ray, orgError),
                                                c0, e0, g, 2.0 * std::abs(nearRoot), {nearRoot});
  const bool sameSide = nearRoot > 0.0 ? near.own.lo >= 0.0 : near.own.hi <= 0.0;
  return near.own.lo < near.own.hi && sameSide && divideByOriginRoot(rr, c0, e0, near.own);
}

}  // namespace

// The self-root rule for a ray whose origin lies on the surface (originOnSurface): rr.g
// about the origin with the origin's root divided out, rr.selfWindow, rr.zeroedConstant
// and the division's terms (ray_roots.h). orgError: the ray's whole bound.
void restrictFromSurfaceOrigin(const SurfaceData& data, const KernelRay& ray, double orgError,
                               RayRoots& rr) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  RayPolynomial& g = rr.g;
  double& selfWindow = rr.selfWindow;
  double& zeroedConstant = rr.zeroedConstant;
  restrictToRay(data.horner, o, d, 0.0, g);
  selfWindow = selfRootWindow(data, ray, orgError);
  const double c0 = g.coeff[0], e0 = g.error[0];
  zeroedConstant = std::abs(c0);
  rr.divisionRoot = 0.0;
  rr.divisionRemainder = std::abs(c0) + e0;
  if (g.degree > 0) deflateAtZero(g.degree, g.coeff, g.error);
  if (g.degree > 0) {
    ClusterSplit split;
    const double cluster =
        multipleRootWindow(data, ray, orgError, tlsOriginValue, c0, e0, g, split);
    if (split.apart && !(split.own.lo < split.own.hi)) {
      // Sheets apart, none of them crossed near enough to be the origin's (a ray leaving
      // nearly tangentially past its sheet; G was clear of its noise at every point looked
      // at, splitCluster): g is G again (g / s had the roots of f = f(o), up to 23 % off
      // in t on a thin shell's rays leaving at 0.01 rad).
      undeflate(g, c0, e0);
      zeroedConstant = -1.0;
      rr.divisionRemainder = -1.0;
    } else if (cluster == 0.0 && (split.apart || originRootMatters(data, ray, c0, g.coeff[0]))) {
      // A simple root at the origin (no cluster, or the origin's among sheets apart, a
      // rare path that skips the gate): divided out where it lies, not at 0. (g is then
      // no longer g / s: nothing was zeroed.)
      if (divideByOriginRoot(rr, c0, e0, split.own) ||
          (!split.apart && divideNearTangentRoot(data, ray, tlsOriginValue, orgError, c0, e0, rr)))
        zeroedConstant = -1.0;
    }
    selfWindow = std::max(selfWindow, cluster);
  }
}

}  // namespace algray
