// The kernel's per-ray record (ray_roots.h): g, the restriction of f to the ray over the
// whole clip region, and its roots: steps 3 and 4 of the way of one ray in
// ../shared/DESIGN.md (surface_intersect.cpp walks the roots through one cell):
//   - g from the per-thread origin cache, about the origin itself (self-root rule), or
//     about the point of the span closest to the object-space origin (re-centring; the
//     quadric path: its closed form);
//   - its first root in the search span, settled on f where the query needs it
//     (ray_settle.cpp), and all of them only when a cell beyond it or a host filter asks.
#include "ray_roots.h"

#include "double_channel.h"
#include "thread_heap.h"

#include "algray/roots.h"
#include "algray/taylor.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <span>
#include <type_traits>

namespace algray {

// ---- The expansion point ----------------------------------------------------------------------
// restrictToRay's bound holds about the point p~ = fl(o + fl(tShift d)) it forms (taylor.h),
// which lies off the ray's line by up to u (|p~| + |tShift d|) per coordinate. Where |p~| is
// not small that is a relative rounding of the point, of the order of the bound's own
// (the terms' magnitudes at p~ times gamma_(3m+3)); where the line passes near the
// object-space origin (|p~| below an eighth of |tShift d|, the sum cancelled) it is not, and
// where f's terms all vanish there (a singular or tangent point at the origin) g's bound
// shrinks with |p~| while the displacement does not: a ray exactly through the node of
// (x^2+y^2+z^2)^2 - 4 (x^2+y^2) was expanded about a p~ 1e-16 off its line, along which g
// stays below -9.8e-36 with a bound of 1e-47 on its constant term, and missed the node (5-8 %
// of exact rays through the node, the point of x^4+y^4+z^4 or a sphere's tangent point at 0).
// There the point is formed with error-free transformations (pointOnLine: off the line by
// u |p| + u^2 |tShift d|, a relative rounding again) and g expanded about it.
void restrictAbout(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double tShift,
                   RayPolynomial& g) {
  const glm::dvec3 step = tShift * d, p = o + step;
  const double pNorm = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  const double stepNorm = std::max({std::abs(step.x), std::abs(step.y), std::abs(step.z)});
  if (8.0 * pNorm < stepNorm) [[unlikely]] {
    restrictToRay(f, pointOnLine(o, d, tShift), d, 0.0, g);
    g.tShift = tShift;
    return;
  }
  restrictToRay(f, o, d, tShift, g);
}

namespace {

// ---- Per-thread origin cache ---------------------------------------------------------
// Rays sharing an origin (a pinhole camera's primary rays) restrict f from one
// OriginExpansion: one shift per origin, then O(#terms) per ray (taylor.h, path 1).
// An expansion is built the second time an origin is seen in a row, so rays with
// distinct origins (shadow and bounce rays) never pay for a shift they cannot reuse.
// Keyed by the surface id (unique per process, never reused), not the pointer.
//
// From an origin a few clip radii away the expansion about o keeps fewer digits than the
// re-centred one (|o|^m-sized terms cancel near the surface); its error bound says so, so
// misses stay misses, but the tangent rule then reports near misses within that wider
// bound (measured: 24 % of Chmutov-16's pixels from 3 radii). Every root the cache gives
// is therefore confirmed on f itself (rayRoots below) and the ray falls back to the
// re-centred restriction when it is not. An entry whose roots keep failing (more than a
// quarter after 64 rays: the origin is too far for this degree) stops being used.
struct CacheEntry {
  std::uint64_t id = 0;
  glm::dvec3 origin{0.0};
  OriginExpansion expansion;
  std::uint32_t uses = 0, failures = 0;
};
struct OriginCache {
  std::array<CacheEntry, 4> entries;
  unsigned next = 0;
  std::uint64_t pendingId = 0;
  glm::dvec3 pendingOrigin{0.0};
};

// Per thread, on the heap (thread_heap.h: no destructor registered on a thread's first ray).
OriginCache& threadOriginCache() { return ThreadHeap<OriginCache>::get(); }

CacheEntry* cachedExpansion(const SurfaceData& data, const glm::dvec3& o) {
  OriginCache& cache = threadOriginCache();
  for (CacheEntry& e : cache.entries)
    if (e.id == data.id && e.origin == o)
      return (e.uses < 64 || 4 * e.failures <= e.uses) ? &e : nullptr;
  if (cache.pendingId != data.id || cache.pendingOrigin != o) {
    cache.pendingId = data.id;
    cache.pendingOrigin = o;
    return nullptr;
  }
  CacheEntry& e = cache.entries[cache.next++ % cache.entries.size()];
  e.id = 0;  // invalid until the expansion is complete (it may throw bad_alloc)
  e.expansion = OriginExpansion(data.desc.polynomial, o);
  e.origin = o;
  e.uses = e.failures = 0;
  e.id = data.id;
  return &e;
}

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

// ---- Quadrics --------------------------------------------------------------------------
// Degree 2 in closed form (SurfaceData::quadric; restrictQuadricRay in quadric_path.cpp):
// no expansion, no cache and no polish (the stable quadratic formula is accurate to the
// conditioning of g, and the normal is 2 A x + b at the hit).
bool restrictQuadric(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                     RayPolynomial& g) {
  QuadricRay q;
  restrictQuadricRay(data, ray, r0, r1, q);
  g.degree = q.degree;
  g.tShift = q.tShift;
  for (int i = 0; i < 3; ++i) {
    g.coeff[i] = q.c[i];
    g.error[i] = q.err[i];
  }
  return q.selfRoot;
}

// ---- Restriction, once per ray --------------------------------------------------------------
// (The record it fills, RayRoots, is described in ray_roots.h.)
// About the point of the span closest to the object-space origin, not to the clip centre:
// f's coefficients are given about the origin, so the expansion's rounding grows with the
// expansion point's distance from it; about an off-centre box's centre (-2.05, 0.24, -0.41)
// Chmutov-16's hits were 2e-3 box radii off. For a clip region centred on the origin (the
// gallery, every --clip-sphere) the two points are the same.
// closest: that parameter, closestParameter(o, d, 0), when the walk has it from its clip
// sphere (regionSpan), which holds it in [r0, r1] already (NaN: not). Taken from there,
// the restriction no longer waits for the chord's square root, on which r0 and r1 and so
// the clamp depend (measured at walkRootsOf, surface_intersect.cpp).
void restrictRecentred(const SurfaceData& data, const glm::dvec3& o, const glm::dvec3& d, double r0,
                       double r1, RayPolynomial& g,
                       double closest = std::numeric_limits<double>::quiet_NaN()) {
  double tShift = 0.0;
  if (data.desc.options.recentre)
    tShift =
        closest == closest ? closest : std::clamp(closestParameter(o, d, glm::dvec3(0.0)), r0, r1);
  restrictAbout(data.horner, o, d, tShift, g);
}

// From an origin outside the clip ball (no self-root rule): from the origin cache or
// re-centred.
CacheEntry* restrictOutside(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                            double closest, RayPolynomial& g) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  if (CacheEntry* entry = data.desc.options.originCache ? cachedExpansion(data, o) : nullptr) {
    entry->expansion.restrict(d, g);
    return entry;
  }
  restrictRecentred(data, o, d, r0, r1, g, closest);
  return nullptr;
}

// Sets rr.g, rr.selfWindow, rr.zeroedConstant and the division's terms; returns the cache
// entry when g came from it. selfWindow > 0 when the self-root rule divided out the
// origin's root (selfRootWindow), else 0. orgError: the ray's whole bound (ray.orgError,
// with a deferred float term added).
CacheEntry* restrictWhole(const SurfaceData& data, const KernelRay& ray, double orgError, double r0,
                          double r1, double closest, RayRoots& rr) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  RayPolynomial& g = rr.g;
  double& selfWindow = rr.selfWindow;
  double& zeroedConstant = rr.zeroedConstant;
  selfWindow = 0.0;
  zeroedConstant = -1.0;
  if (data.quadric) {
    // (A quadric in cells: the quadric path's functions read the bound from the ray.)
    KernelRay whole = ray;
    whole.orgError = orgError;
    whole.orgErrorObject = objectOrgError(data, ray);
    whole.orgErrorDeferred = false;
    if (restrictQuadric(data, whole, r0, r1, g)) selfWindow = selfRootWindow(data, whole, orgError);
    return nullptr;
  }
  // Outside the clip ball (originOutsideClipBall, as the quadric path) the self-root rule
  // has nothing to remove and testing it could only do harm: a far origin of a
  // high-degree f is "on the surface within rounding" whenever f's expansion cancels more
  // digits there than f(o) has (a random degree-16 surface seen from 3.5 radii), and the
  // deflated polynomial, expanded about that far origin, lost the ray's real roots.
  if (!originOutsideClipBall(data, o, orgError) && originOnSurface(data, ray, orgError)) {
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
            (!split.apart &&
             divideNearTangentRoot(data, ray, tlsOriginValue, orgError, c0, e0, rr)))
          zeroedConstant = -1.0;
      }
      selfWindow = std::max(selfWindow, cluster);
    }
    return nullptr;
  }
  return restrictOutside(data, ray, r0, r1, closest, g);
}

// Whether originOutsideClipBall holds without the deferred term (surelyOutsideClipBall).
bool surelyOutsideClipBall(const SurfaceData& data, const KernelRay& ray) {
  const glm::dvec3 oc = ray.org - data.centre;
  return surelyOutsideClipBall(data, glm::dot(oc, oc), ray);
}

// restrictWhole, for a ray with a deferred orgError too: a camera's primary rays (origin
// outside the clip ball) never need the term, other rays get it here (bit for bit the
// bridge's, floatOriginError). Measured (speed_report, one thread, interleaved): computed
// for every float ray in the bridge, its square root cost the Barth sextic's primary rays
// 2-3 % (2.85 -> 2.92-2.94 Mrays/s deferred).
CacheEntry* restrict(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                     double closest, RayRoots& rr) {
  if (!ray.orgErrorDeferred) return restrictWhole(data, ray, ray.orgError, r0, r1, closest, rr);
  if (!data.quadric && surelyOutsideClipBall(data, ray)) {
    rr.selfWindow = 0.0;
    rr.zeroedConstant = -1.0;
    return restrictOutside(data, ray, r0, r1, closest, rr.g);
  }
  const double orgError = wholeOrgError(data, ray);
  return restrictWhole(data, ray, orgError, r0, r1, closest, rr);
}

// The solver's options for a clip-region span: its start is the region's boundary, not a
// root the walk already has (the walk keeps its own list), so a root within noise of it
// counts (RootOptions::closedLo; a multiple root's noise region there is u^(1/m) wide:
// rays entering the clip ball 1e-4 to 1e-3 before the plane x^m = 0 missed it, 12 % at
// m = 4 and all of them for m = 6 to 10). Degree 2 (the
// quadratic fast path) stays open: a double root's noise region is far inside the 2^-20
// by which the region is widened. After the self-root rule the span starts at the
// self-root window instead (closedLo false: a root within noise of it is the origin's).
RootOptions regionRoots(RootOptions options, bool closedLo) {
  options.closedLo = closedLo;
  return options;
}
// The same for the first root, which also asks whether g is within its noise before it
// (RootOptions::noiseBefore) where such a root will be looked behind (exactRoots).
RootOptions regionRoots(const SurfaceOptions& opt, const RayRoots& rr) {
  RootOptions roots = regionRoots(opt.roots, rr.closedLo);
  roots.noiseBefore = exactRoots(opt, rr);
  return roots;
}

// (The flag-and-out-parameter form of roots.h: an optional returned through this
// function cost every ray a store-forwarding stall.)
bool firstRootOf(const RayPolynomial& g, double lo, double hi, const RootOptions& options,
                 bool singlePrecision, double& root, bool& atNoise) {
  const std::span<const double> c(g.coeff.data(), g.degree + 1), err(g.error.data(), g.degree + 1);
  if (!singlePrecision) return solveFirstRoot(c, err, lo, hi, root, atNoise, options);
  // The float solver, kept for comparison (SurfaceOptions::singlePrecision).
  std::array<float, kMaxDegree + 1> cf{}, ef{};
  for (int i = 0; i <= g.degree; ++i) {
    cf[i] = static_cast<float>(g.coeff[i]);
    ef[i] = static_cast<float>(g.error[i]);
  }
  float r;
  if (!solveFirstRoot(std::span<const float>(cf.data(), g.degree + 1),
                      std::span<const float>(ef.data(), g.degree + 1), static_cast<float>(lo),
                      static_cast<float>(hi), r, atNoise, options))
    return false;
  root = r;
  return true;
}

// Whether a cached expansion (tShift = 0) keeps at least 6 digits over the span: its
// noise (coefficient error bound plus the rounding of evaluating it) at the span's ends
// is below 1e-6 of the larger |g| there (measured from 3.2 radii, noise / |g|: Barth
// sextic and Chmutov-8 1e-9 to 1e-6, Chmutov-16 1e-3 to 1). An expansion about a far eye cancels
// terms of size sum|c_i| |t|^i down to f's values near the surface, and loses that many digits.
// Confirming roots on f catches a spurious root but not a real one the expansion lost, and with few
// digits left it can lose one: measured, 2 of 576 primary rays on Chmutov-16 from 3.2 radii (~m
// log10 4 = 10 digits lost) hit a later root than the first. Those rays take the re-centred
// restriction instead (and the entry counts them as failures, so a camera too far for this degree
// stops using the cache).
//
// A local rule was measured against it (session 3): accept a cached root when its noise
// region, 4 noise(s) / |g'(s)|, is below 1e-7 of the span. With the rigorous bound that
// region is 1e-8 to 1e-5 of the span for the Barth sextic (20 % of its roots fell back,
// 0.92x) and wider than 1e-4 for every root of Sarti's dodecic, Chmutov-12 and the Barth
// decic from 3 radii: those degrees lose too many digits about a far eye for any rule to
// keep the cache; what would is the expansion in higher precision.
bool keepsDigits(const RayPolynomial& g, double r0, double r1) {
  double noise = 0.0, value = 0.0;
  for (const double t : {r0, r1}) {
    double bound = 0.0;
    const double v = g.evaluateWithBound(t, bound);
    noise = std::max(noise, bound);
    value = std::max(value, std::abs(v));
  }
  return noise <= 1e-6 * value;
}

// The span in s the roots are searched in: the region's span, and from an origin on the
// surface only from tnear and past the self-root window (no work on the roots behind it:
// such a ray, every shadow or bounce ray leaving a surface, found those first and then
// had to find them all; measured, shadow rays on the gallery surfaces took twice as
// long). Its start is closed (regionRoots) except at the window, where a root within
// noise is the origin's. Other rays search from the last point before tnear where g is
// clear of its noise (or the region's start): not from tnear itself, since an m-fold
// root's noise region, u^(1/m) of the scale wide, may straddle tnear, and a span starting
// there reported the root at tnear itself, which the ray excludes ((0.6 x + 0.8 y - 0.1)^6
// = 0 1e-3 beyond tnear was lost on 183 of 200 rays, session 5, before closedLo); the walk
// skips roots outside (tnear, tfar). A root whose noise band holds tnear may still be
// placed at or before tnear and is then not reported (by design, README). Session 34
// measured a start at tnear itself (with closedLo) against this one, tnear 1-16 u^(1/m)
// before the plane above: lost 0 against 4-51 of ~520 rays for m = 4-10, 83 against 20
// for m = 3, the same 285 for m = 2, none by either at 16 u^(1/m). Also tried then: a
// second search from tnear itself after searchFromTnear where the root still lay behind
// it (4-51 -> 0-15 lost for m = 4-10), not kept: on random extreme surfaces it reported
// roots past a sign change of f inside g's noise (3 campaign tests failed), since a span
// starting within g's noise loses what the settling relies on, a clear start.
// Not from the region's start either (until session 31): the first root was then
// often one behind an origin inside the region, and the ray's hit a later one of the
// complete list, without the checks on f that the first root gets (settleFirstRoot): in a
// campaign of random extreme surfaces seen from inside the clip sphere, 33 of 13040 hits
// skipped an earlier root of f (now none); and such rays took 1.5-5.5x as long on the
// gallery's surfaces of degree 3-16 (docs/speed-details.md, session 31).
void searchSpan(RayRoots& rr) {
  rr.slo = rr.r0 - rr.g.tShift;
  rr.shi = rr.r1 - rr.g.tShift;
  rr.closedLo = true;
  if (!(rr.selfWindow > 0.0)) {
    const double near = rr.tnear - rr.g.tShift;
    if (near > rr.slo && near < rr.shi) rr.slo = clearBefore(rr.g, near, rr.slo, false);
    return;
  }
  // From an origin on the surface (tShift = 0): from tnear on, past the window if the
  // span starts inside it; a span starting before it (tnear < 0) keeps the roots behind
  // the origin, and the walk skips those within the window.
  rr.slo = std::max(rr.slo, rr.tnear);
  if (rr.slo < rr.selfWindow && rr.slo > -rr.selfWindow) {
    rr.slo = rr.selfWindow;
    rr.closedLo = false;
  }
}

}  // namespace

void restrictWithoutCache(const SurfaceData& data, const KernelRay& ray, RayRoots& rr) {
  restrictRecentred(data, ray.org, ray.dir, rr.r0, rr.r1, rr.g);
  rr.fromCache = false;
}

// ---- Polish ----------------------------------------------------------------------------
// Newton steps on f(o + t d) evaluated directly, until |f| is within its evaluation bound
// (at most 8; quadratic convergence needs 2-4): repairs digits a cached or far-centred
// expansion lost. A step is kept only if the iterate stays inside the span, within 1e-4 of
// the region's span (maxMove) of where it started, and lowers |f| (so an ill-conditioned
// root never jumps to a neighbour); then last steps on f's compensated value (below).
// Returns whether |f| ended within its bound (evaluate()'s, at the last double step): the
// root is confirmed on f. `last`, if given, receives f at that step (settleFirstRoot).
bool polish(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double lo, double hi,
            double regionSpan, KernelHit& hit, Polynomial::Evaluation* last) {
  const double maxMove = 1e-4 * regionSpan;
  double t = hit.t;
  Polynomial::Evaluation e = f.evaluate(o + t * d);
  for (int it = 0; it < 8 && std::abs(e.value) > e.valueError; ++it) {
    const double slope = glm::dot(e.gradient, d);
    if (!(std::abs(slope) > 0.0)) break;
    const double tn = t - e.value / slope;
    if (!(tn > lo && tn < hi && std::abs(tn - hit.t) <= maxMove)) break;
    const Polynomial::Evaluation en = f.evaluate(o + tn * d);
    if (!(std::abs(en.value) < std::abs(e.value))) break;
    t = tn;
    e = en;
  }
  // ---- Last steps on the compensated value, where f's rounding limits the root ---------
  // The loop stops where |f| is within evaluate()'s bound, which places t only within
  // valueError / |slope| of the root: up to ~2m times the root's conditioning u E / |slope|
  // (Chmutov-20 from 1.5 clip radii: 9.6e-10 radii where the conditioning allowed 5.6e-11;
  // accuracy_report, session 38). Where that window is wider than 2^-35 of the region's span
  // (5.8e-11 clip radii on a chord through the centre, a sixteenth of the accuracy target)
  // and below 2^-10 of it, Newton steps on f's compensated value (exact to the square of
  // evaluate()'s relative bound; the slope's own rounding only scales steps of the window's
  // size) put t within the root's conditioning, each kept only if it stays within twice the
  // window. In a narrow window (below 2^-20 of the span) one step is all: it leaves the
  // curvature's share of the window's square. In a wider one (a product of 20 spheres,
  // degree 40: ~8e4 times the conditioning, 1.4e-5 clip radii, where one step leaves ~1e-7)
  // they go on while each cuts |f| sixteenfold, as Newton does near a simple root and not
  // near a multiple one (a double root's f falls fourfold a step), down to 2^-20 of the
  // window. (Below 2^-35 too, every Chmutov-16 hit took a step: 15 % of its primary rays'
  // time for errors already 15 times below the target; verifying each step there cost 5 %.)
  const double slope = glm::dot(e.gradient, d);
  const double window = e.valueError / std::abs(slope);
  hit.gradient = e.gradient;
  if (window > 0x1p-35 * regionSpan && window <= 0x1p-10 * regionSpan) [[unlikely]] {
    const double before = t;
    const bool narrow = window <= 0x1p-20 * regionSpan;
    double fc = f.valueCompensated(o + t * d);
    for (int it = 0; it < 4; ++it) {
      const double step = fc / slope;
      const double tn = t - step;
      if (!(std::abs(step) > 0x1p-20 * window && std::abs(step) <= 2.0 * window && tn > lo &&
            tn < hi && std::abs(tn - hit.t) <= maxMove))
        break;
      if (narrow) {
        t = tn;
        break;
      }
      const double fn = f.valueCompensated(o + tn * d);
      if (!(16.0 * std::abs(fn) <= std::abs(fc))) break;
      t = tn;
      fc = fn;
    }
    // The normal where the hit is: these steps move t by up to twice the window, over which
    // grad f can turn far more than its rounding does where |grad f| is small beside another
    // sheet of f (a sphere's hit 1.4e-6 from the plane of (x^2+y^2+z^2-1)(x+y-0.5): its
    // normal came from the point 4e-10 back, 4.5e-5 rad off; the audit of session 51).
    if (t != before) hit.gradient = f.evaluate(o + t * d).gradient;
  }
  hit.t = t;
  hit.point = o + t * d;
  if (last) *last = e;
  return std::abs(e.value) <= e.valueError;
}

// ---- The first root, and all of them -------------------------------------------------------
// The first root of rr.g in [rr.slo, rr.shi] (rr.count = 0 or 1).
void solveFirstInSpan(const SurfaceData& data, RayRoots& rr) {
  rr.count = 0;
  rr.complete = true;
  rr.firstPolished = false;
  // A constant g has no isolated root: either no intersection or the whole line lies in
  // the surface (a ruling), which has no first point to report.
  if (rr.g.degree < 1) return;
  const SurfaceOptions& opt = data.desc.options;
  const bool quadratic = data.quadric && rr.g.degree == 2 && rr.g.coeff[2] != 0.0 &&
                         !opt.singlePrecision && opt.roots.method == RootMethod::Auto &&
                         opt.roots.relTolerance == 0.0;
  double s;
  rr.firstAtNoise = false;
  const bool found = quadratic
                         ? solveFirstRootQuadratic(std::span<const double, 3>(rr.g.coeff.data(), 3),
                                                   std::span<const double, 3>(rr.g.error.data(), 3),
                                                   rr.slo, rr.shi, s)
                         : firstRootOf(rr.g, rr.slo, rr.shi, regionRoots(opt, rr),
                                       opt.singlePrecision, s, rr.firstAtNoise);
  if (found) {
    rr.roots[0] = s;
    rr.count = 1;
    rr.complete = false;
  }
}

// Whether the root s of q = g / s (the self-root rule set g(0) = c_0 to 0, c_0 within its
// rounding) exists only because c_0 was set to 0: where |s' q(s')| <= |c_0| on all of [0, s]
// (|s| sum |q_k| |s|^k, q's terms growing with |s'|), g as computed, c_0 + s' q(s'), keeps
// c_0's sign there and has no root of its own before s; q's root is then a point of the
// origin's cluster that the zeroed constant turned real. Needed where f's gradient vanishes
// along a curve of its surface, which is smooth there: Taubin's heart (x^2 + 9/4 y^2 + z^2 -
// 1)^3 = x^2 z^3 + 9/80 y^2 z^3 along its equator ellipse (z = 0), where f ~ dist^3 and hits
// are ill-conditioned: g of a ray leaving such a hit has a near-triple cluster of roots ~1e-6
// wide beyond the window of the origin's stated uncertainty, a complex pair of which q had
// as real roots 1e-8..3e-6 radii from the origin (98 of 2400 leaving rays near the equator;
// session 46's audit, against the exact restriction: no real root there). Not g's rounding
// bound for the test (session 46's first version): c_0's bound (f's rounding at o) can
// exceed g's values over a thin shell's gap, and q's root there, which g as computed has
// too, is a surface (shells 3e-8 to 1e-3 wide, grazing re-entries: the review's cases).
// Where c_0 is 0, no root of q is skipped.
bool inOriginNoise(const RayRoots& rr, double s) {
  const double c0 = rr.zeroedConstant, a = std::abs(s);
  const RayPolynomial& g = rr.g;
  if (!(a * std::abs(g.coeff[0]) <= c0)) return false;  // the common case: one product
  double sum = 0.0;
  for (int k = g.degree; k >= 0; --k) sum = sum * a + std::abs(g.coeff[k]);
  return a * sum <= c0;
}

// The first root of rr.g in the search span (rr.count = 0 or 1), past the origin's noise
// region on a ray leaving the surface (inOriginNoise; at most 8 roots skipped, as a cap).
void solveFirst(const SurfaceData& data, RayRoots& rr) {
  searchSpan(rr);
  solveFirstInSpan(data, rr);
  if (!(rr.zeroedConstant > 0.0)) return;
  for (int i = 0; i < 8 && rr.count == 1 && inOriginNoise(rr, rr.roots[0]); ++i) {
    rr.slo = rr.roots[0];
    rr.closedLo = false;
    solveFirstInSpan(data, rr);
  }
}

constinit thread_local RayRoots tlsRayRoots;

RayRoots& deriveRayRoots(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                         double closest, bool occlusion) {
  RayRoots& rr = tlsRayRoots;
  rr.id = 0;  // invalid until complete (restriction may throw)
  rr.firstRebased = false;
  rr.divisionRemainder = -1.0;
  rr.r0 = r0;
  rr.r1 = r1;
  rr.tnear = ray.tnear;
  CacheEntry* entry = restrict(data, ray, r0, r1, closest, rr);
  // A double ray whose host states an uncertainty of its origin (orgError > 0, pbrt-v4's
  // pError, by which pbrt offsets its spawned rays) but whose origin the rule took for a
  // point off the surface: a root within twice that of the origin is the origin's too, as
  // it is for an origin on the surface (the walk skips it). The rule's test of f(o) is
  // first order, and next to pinch points and double curves f is quadratic or cubic in the
  // offset: leaving rays from the library's own hits 1e-12..1e-8 radii from the pinch points
  // of Steiner's Roman surface, Pluecker's conoid, Whitney's umbrella and the cross-cap hit
  // again 1e-19..3.5e-15 away (session 47's audit: 37-86 of 330-1280 such rays; 179 of
  // 4240 in EmbreeShadowSingular), where the origin lies between two sheets closer than its
  // bound, or off the surface by more than it (a hit from a noise region, 5e-10 off beside
  // pbrt's 3e-15) with a tangent-rule root 5e-16 away that f confirmed within 2^10 times
  // what the bound moves it by (clearlyOffSurface).
  rr.originWindow =
      rr.selfWindow == 0.0 && ray.hostBound ? selfRootWindow(data, ray, ray.orgError) : 0.0;
  if (entry && !keepsDigits(rr.g, r0, r1)) {
    ++entry->uses;
    ++entry->failures;
    restrictRecentred(data, ray.org, ray.dir, r0, r1, rr.g);
    entry = nullptr;
  }
  rr.fromCache = entry != nullptr;
  solveFirst(data, rr);
  if (entry) {
    // Confirm the cache's first root on f (see the origin cache); a miss needs no check:
    // the expansion's error bound is wider, so it misses only where the re-centred
    // restriction misses too.
    ++entry->uses;
    if (rr.count == 1) {
      KernelHit hit;
      hit.t = rr.g.tShift + rr.roots[0];
      if (polish(data.horner, ray.org, ray.dir, r0, r1, r1 - r0, hit)) {
        rr.roots[0] = hit.t - rr.g.tShift;
        rr.firstPolished = true;
        rr.firstGradient = hit.gradient;
      } else {
        ++entry->failures;
        restrictRecentred(data, ray.org, ray.dir, r0, r1, rr.g);
        rr.fromCache = false;
        solveFirst(data, rr);
      }
    }
  }
  // A closest hit needs its first root on f anyway (the hit's polish): done here, where a
  // root g placed wrongly can still be searched for again; an occlusion query only where
  // the noise rules reported the root (a sign change of g proves one), where it lies behind
  // tnear (searchFromTnear), or where g cannot tell on which side of tnear or tfar it lies
  // (walkRootsOf, occlusionRootCertain). A cached root was confirmed above; a quadric's
  // closed form is accurate to its conditioning. A root settled behind tnear is searched
  // for again from tnear, and past one the walk would skip (settleBesideTnear), a cached
  // one too: its polish, over the whole span, may take a root g placed past tnear back to
  // it or before it, and the walk then took the cache's next root unchecked (a stepping
  // host met a point on no surface near a double line of the Roman surface, 2.6e-7 from f's
  // roots; the review of session 49).
  const bool settle =
      firstUnsettled(data, rr) && (!occlusion || rr.firstAtNoise || firstBehindTnear(rr));
  if (settle)
    settleAfterTnear(data, ray, rr);
  else if (rr.fromCache)
    settleBesideTnear(data, ray, rr);
  rr.org = ray.org;
  rr.dir = ray.dir;
  rr.orgRoundoff = ray.orgRoundoff;
  rr.orgError = ray.orgError;
  rr.orgErrorWorld = ray.orgErrorWorld;
  rr.orgErrorObject = ray.orgErrorObject;
  rr.orgErrorDeferred = ray.orgErrorDeferred;
  rr.id = data.id;
  return rr;
}

// All roots, keeping the first one's value (cells may already have judged it).
void completeRoots(const SurfaceData& data, RayRoots& rr) {
  if (rr.fromCache) {
    // The later roots come from the re-centred restriction: the cache confirmed only the
    // first one (a host filter would otherwise be offered unconfirmed roots).
    // The first root keeps its t (firstT): re-based, tShift + roots[0] can lie ulps from it,
    // and a query of the same ray after the first (which found the whole list from a camera
    // inside the clip region) reported, or occluded with, that other value (the second
    // review of session 49: 3,344 warm occlusion checks on the gallery disagreed with the
    // closest hit; StressShadow.CachedCameraRaysFromInsideTheClipRegion).
    const double tFirst = rr.g.tShift + rr.roots[0];
    restrictRecentred(data, rr.org, rr.dir, rr.r0, rr.r1, rr.g);
    rr.fromCache = false;
    searchSpan(rr);
    rr.roots[0] = tFirst - rr.g.tShift;
    rr.firstRebased = true;
    rr.firstT = tFirst;
  }
  const RayPolynomial& g = rr.g;
  const std::span<const double> c(g.coeff.data(), g.degree + 1), err(g.error.data(), g.degree + 1);
  std::array<double, kMaxDegree> all{};
  const int n =
      allRoots(c, err, rr.slo, rr.shi, all, regionRoots(data.desc.options.roots, rr.closedLo));
  const double first = rr.roots[0];
  int closest = -1;
  for (int i = 0; i < n; ++i)
    if (closest < 0 || std::abs(all[i] - first) < std::abs(all[closest] - first)) closest = i;
  rr.count = 0;
  rr.roots[rr.count++] = first;
  for (int i = closest + 1; i < n; ++i)
    if (all[i] > first) rr.roots[rr.count++] = all[i];
  rr.complete = true;
}

}  // namespace algray
