// The kernel's per-ray record (ray_roots.h): g, the restriction of f to the ray over the
// whole clip region, and its roots: steps 3 and 4 of the way of one ray in
// ../shared/DESIGN.md (surface_intersect.cpp walks the roots through one cell):
//   - g from the per-thread origin cache, about the origin itself (the self-root rule,
//     self_root.cpp), or about the point of the span closest to the object-space origin
//     (re-centring; the quadric path: its closed form);
//   - its first root in the search span, settled on f where the query needs it
//     (ray_settle.cpp), and all of them only when a cell beyond it or a host filter asks.
#include "ray_roots.h"

#include "double_channel.h"
#include "quadric_path.h"
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
  rr.selfWindow = 0.0;
  rr.zeroedConstant = -1.0;
  if (data.quadric) {
    // (A quadric in cells: the quadric path's functions read the bound from the ray.)
    KernelRay whole = ray;
    whole.orgError = orgError;
    whole.orgErrorObject = objectOrgError(data, ray);
    whole.orgErrorDeferred = false;
    if (restrictQuadric(data, whole, r0, r1, rr.g))
      rr.selfWindow = selfRootWindow(data, whole, orgError);
    return nullptr;
  }
  // Outside the clip ball (originOutsideClipBall, as the quadric path) the self-root rule
  // has nothing to remove and testing it could only do harm: a far origin of a
  // high-degree f is "on the surface within rounding" whenever f's expansion cancels more
  // digits there than f(o) has (a random degree-16 surface seen from 3.5 radii), and the
  // deflated polynomial, expanded about that far origin, lost the ray's real roots.
  if (!originOutsideClipBall(data, ray.org, orgError) && originOnSurface(data, ray, orgError)) {
    restrictFromSurfaceOrigin(data, ray, orgError, rr);
    return nullptr;
  }
  return restrictOutside(data, ray, r0, r1, closest, rr.g);
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
