// The kernel of the adapter: one ray, one cell, the roots of f along the ray in order.
// No Embree types here (the bridge converts), so an Embree 4 port reuses it unchanged.
//
// The way of one ray (see ../shared/DESIGN.md):
//   1. clip the ray to the clip region and the cell: span (lo, hi);
//   2. restrict f to the ray, g(s) = f(o + (tShift + s) d) with a rounding bound, from
//      the per-thread origin cache, about the origin itself (self-root rule), or about
//      the point of the span closest to the object-space origin (re-centring; the quadric
//      path: the clip centre); once per ray for the whole clip region, shared by the
//      cells the ray visits, with its roots: the
//      first one, all of them only when a cell beyond it or a host filter needs them;
//   3. the roots in the cell's span that the cell owns, in order, offered to the host
//      filter until one is accepted;
//   4. Newton polish on f itself and the gradient at the hit point.
#include "surface_data.h"

#include "algray/roots.h"
#include "algray/taylor.h"

#include <pthread.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>

namespace algray {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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
// is therefore confirmed on f itself (confirmRoot below) and the ray falls back to the
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

// The cache holds vectors, so a `thread_local OriginCache` would have a destructor, and
// C++ registers such a destructor on a thread's first use through __cxa_thread_atexit,
// which takes the dynamic loader's lock: the first ray of every thread then waited for
// any dlopen running in the host at that moment (measured: algray-render's render thread
// stood still for the whole 0.17 s load of OpenImageIO on its second thread, so the
// render loop of a torus took 0.29 s instead of 0.11 s). A POSIX thread key frees the
// cache at thread exit instead, without that lock; the thread_local is only a pointer
// (trivially destructible: nothing registered).
void freeOriginCache(void* p) { delete static_cast<OriginCache*>(p); }

OriginCache& threadOriginCache() {
  thread_local OriginCache* cache = nullptr;
  if (cache) return *cache;
  static const pthread_key_t key = [] {
    pthread_key_t k{};
    if (pthread_key_create(&k, &freeOriginCache) != 0) throw std::bad_alloc();
    return k;
  }();
  auto owned = std::make_unique<OriginCache>();
  if (pthread_setspecific(key, owned.get()) != 0) throw std::bad_alloc();
  cache = owned.release();
  return *cache;
}

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
    move += v.gradLength * orgError;
  }
  return std::abs(v.value) <= 4.0 * v.valueError + 2.0 * move;
}

// ---- Polish --------------------------------------------------------------------------
// Newton steps on f(o + t d) evaluated directly, until |f| is within its evaluation bound
// (at most 8; quadratic convergence needs 2-4): repairs digits a cached or far-centred
// expansion lost. A step is kept only if the iterate stays inside the span, within
// maxMove of where it started, and lowers |f| (so an ill-conditioned root never jumps to
// a neighbour). Returns whether |f| ended within its bound: the root is confirmed on f.
// `last`, if given, receives f at the final point (settleFirstRoot).
bool polish(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double lo, double hi,
            double maxMove, KernelHit& hit, Polynomial::Evaluation* last = nullptr) {
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
  hit.t = t;
  hit.point = o + t * d;
  hit.gradient = e.gradient;
  if (last) *last = e;
  return std::abs(e.value) <= e.valueError;
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

// ---- Restriction and roots, once per ray -------------------------------------------------
// g(s) = f(o + (tShift + s) d) for the whole clip-region span [r0, r1], and its roots
// there, shared by every cell the ray visits (the per-thread last ray): about the origin
// when it lies on the surface (self-root rule), from a cached origin expansion, or about
// the point of the span closest to the object-space origin. The roots are found lazily: the
// first one (all a closest-hit query without a filter needs), then all of them when a
// cell beyond the first root asks. Every cell sees the same root values, which is what
// makes the ownership rule below exact.
struct RayRoots {
  std::uint64_t id = 0;
  glm::dvec3 org{0.0}, dir{0.0};
  double orgRoundoff = 0, orgError = 0;
  bool orgErrorDeferred = false;
  RayPolynomial g;
  double r0 = 0, r1 = 0;    // the region span in t
  double slo = 0, shi = 0;  // the same in s
  double tnear = 0;         // the ray's (searchSpan, with selfWindow)
  double selfWindow = 0;    // > 0: the self-root rule applied (selfRootWindow)
  bool closedLo = true;     // slo is the region's start (regionRoots), not the window
  std::array<double, kMaxDegree> roots{};  // in s, increasing
  int count = 0;
  bool complete = false;
  bool fromCache = false;  // g came from the origin cache (fewer digits, see above)
  // The first root was confirmed (polished) on f when g came from the cache: its
  // gradient, so that the hit does not evaluate f again.
  bool firstPolished = false;
  glm::dvec3 firstGradient{0.0};
  bool firstAtNoise = false;  // the first root came from the solver's noise rules (roots.h)
};
static_assert(std::is_trivially_destructible_v<RayRoots>);  // see threadOriginCache
thread_local RayRoots tlsRayRoots;

// About the point of the span closest to the object-space origin, not to the clip centre:
// f's coefficients are given about the origin, so the expansion's rounding grows with the
// expansion point's distance from it; about an off-centre box's centre (-2.05, 0.24, -0.41)
// Chmutov-16's hits were 2e-3 box radii off. For a clip region centred on the origin (the
// gallery, every --clip-sphere) the two points are the same.
// closest: that parameter, closestParameter(o, d, 0), when the walk has it from its clip
// sphere (regionSpan), which holds it in [r0, r1] already (NaN: not). Taken from there,
// the restriction no longer waits for the chord's square root, on which r0 and r1 and so
// the clamp depend (measured below, at walkRootsOf).
void restrictRecentred(const SurfaceData& data, const glm::dvec3& o, const glm::dvec3& d, double r0,
                       double r1, RayPolynomial& g,
                       double closest = std::numeric_limits<double>::quiet_NaN()) {
  double tShift = 0.0;
  if (data.desc.options.recentre)
    tShift =
        closest == closest ? closest : std::clamp(closestParameter(o, d, glm::dvec3(0.0)), r0, r1);
  restrictToRay(data.horner, o, d, tShift, g);
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

// Returns the cache entry when g came from it; selfWindow > 0 when the self-root rule
// divided out the origin's root (selfRootWindow), else 0. orgError: the ray's whole bound
// (ray.orgError, with a deferred float term added).
CacheEntry* restrictWhole(const SurfaceData& data, const KernelRay& ray, double orgError, double r0,
                          double r1, double closest, RayPolynomial& g, double& selfWindow) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  selfWindow = 0.0;
  if (data.quadric) {
    // (A quadric in cells: the quadric path's functions read the bound from the ray.)
    KernelRay whole = ray;
    whole.orgError = orgError;
    whole.orgErrorDeferred = false;
    if (restrictQuadric(data, whole, r0, r1, g)) selfWindow = selfRootWindow(whole);
    return nullptr;
  }
  // Outside the clip ball (originOutsideClipBall, as the quadric path) the self-root rule
  // has nothing to remove and testing it could only do harm: a far origin of a
  // high-degree f is "on the surface within rounding" whenever f's expansion cancels more
  // digits there than f(o) has (a random degree-16 surface seen from 3.5 radii), and the
  // deflated polynomial, expanded about that far origin, lost the ray's real roots.
  if (!originOutsideClipBall(data, o, orgError) && originOnSurface(data, ray, orgError)) {
    restrictToRay(data.horner, o, d, 0.0, g);
    if (g.degree > 0) deflateAtZero(g.degree, g.coeff, g.error);
    selfWindow = selfRootWindow(ray, orgError);
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
                     double closest, RayPolynomial& g, double& selfWindow) {
  if (!ray.orgErrorDeferred)
    return restrictWhole(data, ray, ray.orgError, r0, r1, closest, g, selfWindow);
  if (!data.quadric && surelyOutsideClipBall(data, ray)) {
    selfWindow = 0.0;
    return restrictOutside(data, ray, r0, r1, closest, g);
  }
  const double orgError = wholeOrgError(data, ray);
  return restrictWhole(data, ray, orgError, r0, r1, closest, g, selfWindow);
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
// Whether rr's roots are the solver's exact ones (no tolerance, not the float solver) on a
// g that a new expansion may replace (not the self-root rule's deflated g): the roots that
// settleFirst searches for again and looks behind.
bool exactRoots(const SurfaceOptions& opt, const RayRoots& rr) {
  return opt.roots.relTolerance == 0.0 && !opt.singlePrecision && !(rr.selfWindow > 0.0);
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
// = 0 1e-3 beyond tnear was lost on 183 of 200 rays); the walk skips roots outside (tnear,
// tfar). Not from the region's start either (until session 31): the first root was then
// often one behind an origin inside the region, and the ray's hit a later one of the
// complete list, without the checks on f that the first root gets (settleFirstRoot): in a
// campaign of random extreme surfaces seen from inside the clip sphere, 33 of 13040 hits
// skipped an earlier root of f (now none); and such rays took 1.5-5.5x as long on the
// gallery's surfaces of degree 3-16 (docs/speed-details.md, session 31).
double clearBefore(const RayPolynomial& g, double s, double slo, bool keepSign = true);
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

// The first root of rr.g in the search span (rr.count = 0 or 1).
void solveFirst(const SurfaceData& data, RayRoots& rr) {
  searchSpan(rr);
  solveFirstInSpan(data, rr);
}

// ---- Roots the expansion cannot place ----------------------------------------------------
// One expansion serves the whole clip region, and its error bound is set by f's terms at
// its centre. Where those terms are far larger than f's terms near the surface elsewhere
// on the ray (a z^7 term of 1e143 beside O(1) ones: session 29's fuzz campaign), g's noise
// bound covers f's values there and g's first root need not be f's: the solver reported a
// point 1.8e-3 before a root whose condition allowed 1e-20, where f was -6e126, the size
// of its largest term (a sign change of g, bracketed beyond its noise, placed by values
// that were noise; on another ray the hit's polish stopped 7.8e-6 short, a Newton step
// across the root raising |f|), and on a disc 4e-13 thick (1e100 z^8 + x^2 + y^2 = 1/4)
// the start of the noise region, by the tangent rule, up to 3.9e-3 radii early. So the
// first root is checked on f itself, which the hit's polish did anyway (settleFirstRoot),
// and where f is clearly non-zero there the ray is restricted again about that point (up
// to kReexpansions times), where the new g holds f's terms there. Occlusion queries,
// which otherwise polish nothing, check roots of the noise rules (roots.h: solveFirstRoot's
// atNoise) and sign changes that g cannot place on one side of tnear and tfar
// (occlusionRootCertain, session 31).
// Measured (session 29, callgrind, 1500 camera rays, the same answers bit for bit): the
// walk's instructions 1.007-1.026x on gallery surfaces; timings docs/speed-details.md.
// Why 8 (4 until session 31): a near miss of even multiplicity (a 6-fold x^6 factor whose
// minimum along the ray stays clear of 0) took 4 expansions, each closer to it, before one
// resolved it and found the next root, a 7-fold z^7 whose g placed it 7.3e-3 late with f
// clearly non-zero there, and with no expansion left that point was the hit (1 of 9252
// campaign hits on random surfaces of degree up to 14 in a clip box; the fifth expansion
// finds the root). Only rays whose root f rejects take them.
constexpr int kReexpansions = 8;

// The last point before s (towards slo) where g is clear of its noise bound, or slo; with
// `keepSign` (searchAgain), clear with the sign g has before its first root s: its sign at
// slo where g is clear there (no root of g in [slo, s) changes it; elsewhere any clear
// point is taken). Why the sign: the solver may place an odd multiple root anywhere in its
// noise region, also at its far edge, where g just before s is clear already but past the
// root (a triple root of f, the ray crossing the plane x = 0 of -1.8e70 x^3 y z (x + 5) +
// O(1e20) terms: the search went on from 1.6e-10 past it and reported the next root, 0.32
// further; session 31).
double clearBefore(const RayPolynomial& g, double s, double slo, bool keepSign) {
  double boundLo = 0.0;
  const double gLo = keepSign ? g.evaluateWithBound(slo, boundLo) : 0.0;
  const bool signKnown = keepSign && std::abs(gLo) > boundLo;
  double step = std::max(0x1p-51 * std::abs(s), std::numeric_limits<double>::min());
  for (int i = 0; i < 2200; ++i, step *= 2.0) {  // (doubling from 2 ulp reaches any span)
    const double y = s - step;
    if (!(y > slo)) break;
    double bound;
    const double v = g.evaluateWithBound(y, bound);
    if (std::abs(v) > bound && (!signKnown || std::signbit(v) == std::signbit(gLo))) return y;
  }
  return slo;
}

// Whether f at the polished point x = o + t d is beyond 2^10 times what its evaluation and
// the point's own rounding allow: x_i errs by up to u (|o_i| + |t d_i|) plus the origin's
// error bound, which moves f by up to |grad f| times as much (from a far origin, 1e5
// radii, that is what keeps f from its bound at every double t: the hits of a torus were
// taken for noise and searched for again).
bool clearlyOffSurface(const KernelRay& ray, const KernelHit& hit,
                       const Polynomial::Evaluation& e) {
  const glm::dvec3 spread = ray.orgRoundoff * (absv(ray.org) + std::abs(hit.t) * absv(ray.dir)) +
                            glm::dvec3(ray.orgError);
  return std::abs(e.value) > 0x1p10 * (e.valueError + glm::dot(absv(e.gradient), spread));
}

// Polishes rr's first root on f; returns whether f is clearly non-zero at the result.
bool polishFirst(const SurfaceData& data, const KernelRay& ray, RayRoots& rr) {
  KernelHit hit;
  hit.t = rr.g.tShift + rr.roots[0];
  Polynomial::Evaluation e;
  const bool onF = polish(data.horner, ray.org, ray.dir, std::max(rr.r0, ray.tnear), rr.r1,
                          1e-4 * (rr.r1 - rr.r0), hit, &e);
  rr.roots[0] = hit.t - rr.g.tShift;
  rr.firstPolished = true;
  rr.firstGradient = hit.gradient;
  return !onF && clearlyOffSurface(ray, hit, e);
}

// rr's first root, polished, is clearly off f: the ray is restricted again about the root
// as g placed it, and the search goes on from the last point before it where the old g
// was clear of its noise, up to kReexpansions times.
[[gnu::noinline, gnu::cold]] void searchAgain(const SurfaceData& data, const KernelRay& ray,
                                              RayRoots& rr, double s) {
  double lastCentre = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < kReexpansions; ++k) {
    // [slo, from] is root-free by the old g's rigorous bounds; a root the new g finds
    // within its noise of `from` is a root there (closedLo: the new g's noise region of a
    // multiple root, u^(1/m) of its scale, may reach back past from).
    const RayRoots before = rr;
    const double from = rr.g.tShift + clearBefore(rr.g, s, rr.slo);
    const double centre = rr.g.tShift + s;
    restrictToRay(data.horner, ray.org, ray.dir, centre, rr.g);
    rr.slo = from - centre;
    rr.shi = rr.r1 - centre;
    rr.closedLo = true;
    solveFirstInSpan(data, rr);
    // No root now: f has none in the span (the old g's bounds exclude [slo, from), the new
    // g's [from, shi]); the hit was g's noise (Chmutov-16 seen from 3 radii: at the clip
    // sphere, where f was 3e5 against an evaluation bound of 1e-7). A root that does not
    // move is the old one.
    if (rr.count == 0) return;
    const double t = rr.g.tShift + rr.roots[0];
    if (std::abs(t - (before.g.tShift + before.roots[0])) <= 0x1p-40 * std::abs(t)) {
      rr = before;
      return;
    }
    s = rr.roots[0];
    if (!polishFirst(data, ray, rr)) return;
    // Two expansions, each within its noise over the stretch between them, can report each
    // other's centre, f clearly non-zero at both: the next one goes halfway between them.
    // Why (session 33): on a degree-39 surface with terms up to 8e126, seen from inside,
    // g about 0.4387 reported 0.4485 and g about 0.4485 reported 0.4387 until the
    // expansions ran out, and the hit was a point off f past f's roots 0.4444 and 0.4497
    // (TwoExpansionsThatReportEachOther; 1 of ~13000 hits of a degree-40 campaign).
    if (std::abs(t - lastCentre) <= 0x1p-40 * std::abs(t)) s = (t + centre) / 2 - rr.g.tShift;
    lastCentre = centre;
  }
}

// A root of the noise rules that the polish confirmed on f (the first polish's, or the
// search again's): g's noise region about it may hold earlier roots of f that g cannot tell
// apart (a cluster within its noise), so the ray is restricted again about the root and
// searched from before the region (searchAgain); a root found there before the confirmed
// one replaces it (and is looked behind in turn if it came from the noise rules too, up to
// kReexpansions times), anything else keeps it (a new expansion never drops a confirmed
// root: on Chmutov-40's ill-conditioned rays it found none). Why (session 31's campaign,
// tests/stress_placement_test.cpp): on -1.8e70 x^3 y z (x + 5) + O(1e20) terms a ray
// crossing y = 0 2.3e-5 before the triple root at x = 0 (passing that close to the z axis)
// had g, expanded 0.2 away (its noise ~1e51 against |f| <= 2e50 between the two,
// estimated), report one noise-level root, the polish took it to x = 0, and y = 0 was
// skipped (1 of 20000 random rays; RootsCloserThanGsNoiseAreSearchedAgain); on -2.5e42 x^8
// y + x^2 + y^2 + z^2 = 29052 (the planes x = +-1.8e-5 where y < 0) the search again about
// a noise-level start 3e-3 before the pair, its g's noise region still covering both, took
// the second, 6.4e-5 late (1 of ~12000 hits; APairWithinGsNoiseFromASearchAgain).
// Measured (speed_report, one thread, alternating with the session's base build, Intel
// host): gallery primary and shadow rays within noise (Barth sextic, 6 runs each: primary
// 5.11-5.52 against 4.94-5.44 Mrays/s, shadow 3.92-4.22 against 3.75-4.18).
//
// The same where g is within its noise bound more than 2^-20 of the search span before a
// sign change (the solver's noise-before query, RootOptions::noiseBefore, which sets
// atNoise then): g's data place an odd number of f's roots within such a region as one sign
// change, anywhere in it, and the polish takes the one it reaches. Why (session 32, the
// campaign at degree up to 40): on a degree-30 surface with terms up to 2e142 three roots of
// f within 1.4e-3 of each other lay in the noise region of a g expanded 7e-3 away, whose
// sign change the polish took to the third; expanded about that root, g holds all three
// apart (AClusterInsideASignChangesNoiseRegion). Session 32 tested g at 2^-20 of the span
// before the root here; session 33 moved the test into the solver, which also proves the
// rest of the root's monotone piece clear and reports a stretch within noise that a clear
// one separates from the root (degree 40, terms of 1e135: g within noise over [0.6908,
// 0.6935], two roots of f there, the sign change at 0.693634; ANoiseShelfBeforeARoot).
// Why 2^-20 (the walk's window): at 2^-30 the roots of Chmutov-16's rays from 3 radii
// often had noise regions that wide, and its primary rays ran at 0.87x the rate
// (speed_report, one thread, 5 alternating runs against session 32's start); at 2^-20
// 0.99x, the other gallery surfaces 0.97-0.99x (then one evaluation of g per hit, since
// session 33 one per solve; docs/speed-details.md).
bool mayHideRoots(const RayRoots& rr) { return rr.count == 1 && rr.firstAtNoise; }
// (Called where mayHideRoots(rr) holds: the first pass does not test it again.)
[[gnu::noinline, gnu::cold]] void searchBefore(const SurfaceData& data, const KernelRay& ray,
                                               RayRoots& rr) {
  int k = 0;
  do {
    const RayRoots confirmed = rr;
    searchAgain(data, ray, rr, rr.roots[0]);
    if (rr.count == 0 || !(rr.g.tShift + rr.roots[0] < confirmed.g.tShift + confirmed.roots[0])) {
      rr = confirmed;
      return;
    }
  } while (++k < kReexpansions && mayHideRoots(rr));
}

// The first root on f (polish): confirmed, or with f not clearly non-zero there (within
// 2^10 times what its evaluation and the point allow: a tangent or grazing point), it
// stands, polished; with f clearly non-zero, and where `reexpand` (not for the self-root
// rule's deflated g, whose root at the origin a new expansion would bring back), the
// search goes on (searchAgain); a root of the noise rules that stands is looked behind
// (searchBefore).
void settleFirstRoot(const SurfaceData& data, const KernelRay& ray, RayRoots& rr, bool reexpand) {
  const double s = rr.roots[0];
  const bool off = polishFirst(data, ray, rr);
  if (!reexpand) return;
  if (off) [[unlikely]]
    searchAgain(data, ray, rr, s);
  if (mayHideRoots(rr)) [[unlikely]]
    searchBefore(data, ray, rr);
}

// settleFirstRoot with the search again where it applies: it needs the solver's exact
// first root (all before it is then clear of g's noise), not one with a tolerance or the
// float solver's, whose roots may lie past f's (with them it took later roots, 0.7-0.96
// radii off, in intersector_report's tol1e-03 and float-solver rows); not a cached
// expansion's, whose root was confirmed on f already; and not the self-root rule's
// deflated g, whose root at the origin a new expansion would bring back.
void settleFirst(const SurfaceData& data, const KernelRay& ray, RayRoots& rr) {
  settleFirstRoot(data, ray, rr, exactRoots(data.desc.options, rr) && !rr.fromCache);
}

// Whether an occlusion query can keep g's first root, a sign change, without placing it on
// f (the closest hit does that anyway, settleFirst): f's root must be on the same side of
// tnear and of tfar as g's. g's rigorous noise bound proves a root of f wherever g clears
// it with opposite signs, so that holds where g does so at two points a < s < b with
// neither tnear nor tfar in [a, b]: trivially when the whole search span lies in (tnear,
// tfar) (the solver's own bracket lies in it), else at s -+ 4 |bound / g'(s)|, the
// first-order reach of the noise bound (the factor covers the curvature and the solver's
// error). Where g cannot show it there (a wide noise region, as where g's terms are far
// larger than f's: the sign change placed anywhere inside it), or tnear or tfar lies in
// [a, b], the root is settled on f as the closest hit's is. Why: on 1e143 z^7 + x^2 + y^2 +
// z^2 = 1 (the plane z = 0 to 1e-20, g's noise region about it 1e-3 wide) rays ending up
// to 1e-4 before the closest hit were occluded, or rays ending just past it not: 43 of
// 117 hits in tests/stress_placement_test.cpp,
// OcclusionAgreesWithTheClosestHitInAWideNoiseRegion (session 31; 9 of them with the
// first-order test of [a, b] alone, no evaluation at a and b).
// Measured (speed_report, shadow 1T, 4 alternating runs against the base build): the
// gallery's shadow rays 0.99-1.02x the time (its light lies outside the clip region).
bool occlusionRootCertain(const RayRoots& rr, const KernelRay& ray) {
  const RayPolynomial& g = rr.g;
  if (g.tShift + rr.slo > ray.tnear && g.tShift + rr.shi < ray.tfar) return true;
  const double s = rr.roots[0];
  double bound;
  g.evaluateWithBound(s, bound);
  double v = g.coeff[g.degree], slope = 0.0;
  for (int i = g.degree - 1; i >= 0; --i) {
    slope = slope * s + v;
    v = v * s + g.coeff[i];
  }
  const double h = std::max(4.0 * bound / std::abs(slope), 0x1p-50 * std::abs(s));
  const double a = s - h, b = s + h;
  const auto outside = [&](double t) { return t < g.tShift + a || t > g.tShift + b; };
  if (!(h < kInf) || !outside(ray.tnear) || !outside(ray.tfar)) return false;
  double boundA, boundB;
  const double ga = g.evaluateWithBound(a, boundA), gb = g.evaluateWithBound(b, boundB);
  return std::abs(ga) > boundA && std::abs(gb) > boundB && std::signbit(ga) != std::signbit(gb);
}

// A first root settled behind tnear (a ray from inside the clip region searches from the
// last point before tnear where g is clear of its noise, searchSpan, so g's noise region
// reached tnear): the walk would take the next roots from the rest of the list, which gets
// no check on f, from a g that may not place them. The ray is restricted again about tnear
// (a point of the region, so the expansion keeps f's digits there), searched from before
// tnear and settled again (settleAfterTnear); occlusion settles a first root behind tnear
// too (rayRoots), so both queries take the same path. Why (session 32): on -1.8e85 x^33 y +
// x^2 + y^2 + z^2 = 1e-18 seen from inside the clip sphere, g about the point nearest the
// origin was within its noise from the region's start to 0.25 past tnear = 0, over f's root
// at 0.0896: the first root settled behind the origin and the ray missed (in a campaign of
// random extreme surfaces of degree up to 40, 31 of 13913 hits from inside skipped an
// earlier root; AWideNoiseRegionAtTheOrigin, ARootThatSettlesBehindTheOrigin). Only after
// the first settling: expanded about tnear at once wherever g is within its noise there, a
// g within its noise from just past tnear reported a point past f's root, and the searches
// again about it and about tnear returned each other's answers (1 of 13048 such hits).
bool firstBehindTnear(const RayRoots& rr) {
  const double near = rr.tnear - rr.g.tShift;
  return rr.count == 1 && rr.roots[0] < near && near < rr.shi && near != 0.0 &&
         !(rr.selfWindow > 0.0);
}
[[gnu::noinline, gnu::cold]] void searchFromTnear(const SurfaceData& data, const KernelRay& ray,
                                                  RayRoots& rr) {
  restrictToRay(data.horner, ray.org, ray.dir, ray.tnear, rr.g);
  rr.fromCache = false;
  rr.firstPolished = false;
  solveFirst(data, rr);
  if (rr.count == 1) settleFirst(data, ray, rr);
}

// settleFirst, and the search from tnear where the root settled behind it: the same path for
// occlusion, wherever it settles the root (rayRoots, walkRootsOf), as for the closest hit.
void settleAfterTnear(const SurfaceData& data, const KernelRay& ray, RayRoots& rr) {
  settleFirst(data, ray, rr);
  if (firstBehindTnear(rr)) [[unlikely]]
    searchFromTnear(data, ray, rr);
}

RayRoots& rayRoots(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                   double closest, bool occlusion) {
  RayRoots& rr = tlsRayRoots;
  if (rr.id == data.id && rr.org == ray.org && rr.dir == ray.dir &&
      rr.orgRoundoff == ray.orgRoundoff && rr.orgError == ray.orgError && rr.tnear == ray.tnear &&
      rr.orgErrorDeferred == ray.orgErrorDeferred)
    return rr;
  rr.id = 0;  // invalid until complete (restriction may throw)
  rr.r0 = r0;
  rr.r1 = r1;
  rr.tnear = ray.tnear;
  CacheEntry* entry = restrict(data, ray, r0, r1, closest, rr.g, rr.selfWindow);
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
      if (polish(data.horner, ray.org, ray.dir, r0, r1, 1e-4 * (r1 - r0), hit)) {
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
  // for again from tnear (settleAfterTnear).
  const bool settle = rr.count == 1 && !rr.firstPolished && !data.quadric &&
                      (!occlusion || rr.firstAtNoise || firstBehindTnear(rr));
  if (settle) settleAfterTnear(data, ray, rr);
  rr.org = ray.org;
  rr.dir = ray.dir;
  rr.orgRoundoff = ray.orgRoundoff;
  rr.orgError = ray.orgError;
  rr.orgErrorDeferred = ray.orgErrorDeferred;
  rr.id = data.id;
  return rr;
}

// ---- Offered roots (double channel) ------------------------------------------------------
// Per surface, ray and trace: the roots (bit i: roots[i] of the ray's record, the same
// list whenever it is rebuilt) offered to the host, and those offered by a shared claim
// (walkRoots). Kept apart from the record, which the cells of other surfaces replace in
// the same trace: masks kept in it were rebuilt empty on each visit back, and a plane's
// orphan root reached an any-hit filter up to 4 times in a scene of three planes. (They
// must never hide another surface's or ray's roots: the key.) An entry evicted early only
// lets a root be offered again, never hides one.
struct OfferedRoots {
  std::uint64_t id = 0, trace = 0;
  glm::dvec3 org{0.0}, dir{0.0};
  double tnear = 0;
  std::uint64_t offered = 0, shared = 0;
};
struct OfferedTable {
  std::array<OfferedRoots, 16> entries{};
  unsigned next = 0;
  unsigned last = 0;  // the entry found last: a ray's roots ask for the same one in a row
};
static_assert(std::is_trivially_destructible_v<OfferedTable>);  // see threadOriginCache
thread_local OfferedTable tlsOffered;

OfferedRoots& offeredRoots(const SurfaceData& data, const KernelRay& ray) {
  OfferedTable& table = tlsOffered;
  auto matches = [&](const OfferedRoots& e) {
    return e.trace == ray.trace && e.id == data.id && e.org == ray.org && e.dir == ray.dir &&
           e.tnear == ray.tnear;
  };
  if (matches(table.entries[table.last])) return table.entries[table.last];
  for (unsigned i = 0; i < table.entries.size(); ++i)
    if (matches(table.entries[i])) {
      table.last = i;
      return table.entries[i];
    }
  table.last = table.next++ % table.entries.size();
  OfferedRoots& e = table.entries[table.last];
  e = OfferedRoots{data.id, ray.trace, ray.org, ray.dir, ray.tnear, 0, 0};
  return e;
}

// All roots, keeping the first one's value (cells may already have judged it).
void completeRoots(const SurfaceData& data, RayRoots& rr) {
  if (rr.fromCache) {
    // The later roots come from the re-centred restriction: the cache confirmed only the
    // first one (a host filter would otherwise be offered unconfirmed roots).
    const double tFirst = rr.g.tShift + rr.roots[0];
    restrictRecentred(data, rr.org, rr.dir, rr.r0, rr.r1, rr.g);
    rr.fromCache = false;
    searchSpan(rr);
    rr.roots[0] = tFirst - rr.g.tShift;
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

// ---- Cell ownership ------------------------------------------------------------------------
// Cells are closed boxes rounded outward, so neighbours overlap and a root near a shared
// face lies in several. The host filter must see each root once (an any-hit filter
// accumulating transparency would count it twice), so exactly one cell owns it: the one
// whose nominal grid box contains the root point (half-open, computed from the same root
// value in every cell). A root whose grid box holds no cell (possible only by rounding
// at a face) is owned by every cell that reaches it: a duplicate rather than a loss.
// With the double channel Embree traverses with the float ray, which for a far origin can
// pass beside the owner cell's (padded) box: the owner then never sees the root. So the
// owner keeps a root only if the float ray surely crosses its padded box (shrunk by the
// rounding of Embree's float slab test); otherwise every cell that reaches the root takes
// it (a duplicate in that rare band rather than a loss).
bool surelyReached(const RTCBounds& b, const glm::dvec3& o, const glm::dvec3& d) {
  const glm::dvec3 lo(b.lower_x, b.lower_y, b.lower_z), hi(b.upper_x, b.upper_y, b.upper_z);
  // Embree's own float slab test is off by about u_float (|o| + |box|): beyond the margin.
  const double slack =
      16.0 * 0x1p-24 * (glm::length(o) + glm::length(glm::max(glm::abs(lo), glm::abs(hi))));
  const glm::dvec3 margin(slack);
  double t0 = 0.0, t1 = kInf;
  return clipToBox(lo + margin, hi - margin, o, d, t0, t1) && t0 < t1;
}

// How a cell takes a root: not at all, as its one owner (Embree visits a primitive once
// per trace), or shared with other cells that may take it in the same trace too.
enum class Claim { kNone, kOwner, kShared };

// Whether `cell` takes the root at p. inSpan: p is in the cell's span of the ray. The
// owner takes it wherever the span ends (walkRoots offers it roots just outside the span,
// which rounding puts there). Another cell takes a root outside its span only in the
// double channel, as an orphan: its owner cell is not surely reached by the float ray
// Embree traverses with (origins ~1e6 clip radii away), so the first cell Embree does
// visit reports it. A root whose grid box holds no cell is shared by the cells whose span
// holds it.
Claim claimsRoot(const SurfaceData& data, unsigned cell, const glm::dvec3& p, const KernelRay& ray,
                 bool inSpan) {
  if (data.cells.size() == 1 || data.cellOfKey.empty())
    return inSpan ? Claim::kOwner : Claim::kNone;
  long k[3];
  for (int a = 0; a < 3; ++a) {
    const double x = (p[a] - data.gridLo[a]) / data.gridSize[a] * data.gridN[a];
    k[a] = std::clamp(static_cast<long>(std::floor(x)), 0L, static_cast<long>(data.gridN[a] - 1));
  }
  auto keyOf = [&] { return (static_cast<std::uint64_t>(k[0]) * 65536u + k[1]) * 65536u + k[2]; };
  auto it = data.cellOfKey.find(keyOf());
  // The key rounds: p - gridLo can carry p across a face (x = -1e-20 beside the face x = 0
  // of the box -2..2 got the key of the cell above it), whose span (its own box) does not
  // hold p: a ray parallel to that face on the other side was claimed by no cell, and one
  // from (-1e-20, -5, 0) along +y missed the unit sphere. The cell's own box decides.
  if (it != data.cellOfKey.end()) {
    const SurfaceCell& c = data.cells[it->second];
    bool moved = false;
    for (int a = 0; a < 3; ++a) {
      if (p[a] < c.lo[a] && k[a] > 0)
        --k[a], moved = true;
      else if (p[a] > c.hi[a] && k[a] + 1 < static_cast<long>(data.gridN[a]))
        ++k[a], moved = true;
    }
    if (moved) it = data.cellOfKey.find(keyOf());
  }
  if (it == data.cellOfKey.end()) return inSpan ? Claim::kShared : Claim::kNone;
  if (it->second == cell) return Claim::kOwner;  // Embree reached the owner: wherever its span ends
  const bool orphan = ray.hasTraversalRay &&
                      !surelyReached(data.cells[it->second].bounds, ray.travOrg, ray.travDir);
  return orphan ? Claim::kShared : Claim::kNone;
}

}  // namespace

void surfaceUV(const SurfaceData& data, const glm::dvec3& point, double& u, double& v) {
  constexpr double kPi = 3.14159265358979323846;
  const glm::dvec3 r = point - data.centre;
  if (!(std::abs(r.x) + std::abs(r.y) + std::abs(r.z) > 0.0)) {  // the centre, or NaN
    u = v = 0.0;
    return;
  }
  double phi = std::atan2(r.y, r.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  u = std::min(phi / (2.0 * kPi), std::nextafter(1.0, 0.0));
  // The polar angle as atan2(rho, z): acos(z / |r|) loses half the digits near the poles
  // (tests: FloatUvAreTheDoubleOnesToAnUlp).
  v = std::atan2(std::hypot(r.x, r.y), r.z) / kPi;
}

namespace {
// atan(t) for t in [0, 1], from t and t^2, for the float u, v: t p(t^2), p of degree 9
// (least squares at 4000 Chebyshev points of atan(t) / t in t^2, fitted for this file;
// measured max error 9.8e-10 rad over 2e7 random atan2 calls, i.e. 1.6e-10 in u, v
// against float's 6e-8 at 1). Estrin's scheme keeps the dependency chain short (glibc's
// atan2 and acos were 11 % of a quadric primary ray; perf, speed_report's sphere).
double atanUnit(double t, double t2) {
  const auto& c = kAtanPoly;
  const double t4 = t2 * t2, t8 = t4 * t4;
  const double p01 = c[0] + c[1] * t2, p23 = c[2] + c[3] * t2, p45 = c[4] + c[5] * t2,
               p67 = c[6] + c[7] * t2, p89 = c[8] + c[9] * t2;
  return ((p01 + p23 * t4) + ((p45 + p67 * t4) + p89 * t8) * t8) * t;
}
}  // namespace

void surfaceUVFloat(const SurfaceData& data, const glm::dvec3& point, float& u, float& v) {
  constexpr double kPi = 3.14159265358979323846;
  const glm::dvec3 r = point - data.centre;
  const double rho2 = r.x * r.x + r.y * r.y, z2 = r.z * r.z;
  if (!(rho2 + z2 > 0.0) || !std::isfinite(rho2 + z2)) {
    double ud, vd;
    surfaceUV(data, point, ud, vd);
    u = floatU(ud);
    v = static_cast<float>(vd);
    return;
  }
  // The azimuth atan2(y, x) from the octant of |x|, |y| (on the z axis, rho = 0, it is
  // atan2(+-0, x) as for surfaceUV).
  double phi;
  if (rho2 > 0.0) {
    const double ax = std::abs(r.x), ay = std::abs(r.y), t = std::min(ax, ay) / std::max(ax, ay);
    phi = atanUnit(t, t * t);
    if (ay > ax) phi = kPi / 2 - phi;
    if (std::signbit(r.x)) phi = kPi - phi;
    phi = std::copysign(phi, r.y);
  } else {
    phi = std::atan2(r.y, r.x);
  }
  if (phi < 0.0) phi += 2.0 * kPi;
  // The polar angle atan2(rho, z) (acos(z / |r|) without its clamp, and as accurate),
  // from the squares: t^2 = min / max of rho^2, z^2 and its root t side by side, so that
  // no root delays the division (a hit's last latency chain; measured).
  const double t2 = std::min(rho2, z2) / std::max(rho2, z2), t = std::sqrt(t2);
  double theta = atanUnit(t, t2);
  if (rho2 > z2) theta = kPi / 2 - theta;
  if (std::signbit(r.z)) theta = kPi - theta;
  // Products with the rounded 1 / (2 pi) and 1 / pi (one more rounding, far below
  // float's; the quotients' latency came last on a hit's critical path, measured).
  u = floatU(std::min(phi * kInvTwoPi, std::nextafter(1.0, 0.0)));
  v = static_cast<float>(std::min(std::max(theta * kInvPi, 0.0), 1.0));
}

namespace {

// ---- Directions far from the clip radius in length -----------------------------------------
// The restriction's coefficient of s^r scales as |d|^r: with |d| = 2^-k R (R the clip
// radius) the top ones of a degree-m f shrink by 2^-km relative to the others and leave
// double's range from k m ~ 1000 (a direction of length 1e-20 on Chmutov-16: 1e-320, a
// flushed or 10-bit subnormal; missed and spurious hits on 8 % of random rays, both
// channels; long directions overflow alike). When k m exceeds 256 the walk takes the ray
// with its direction scaled by a power of two to a largest component in [R, 2R) and t
// inversely, both exact, and reports each root's t scaled back (exact but for underflow
// or overflow of t itself). (The double channel's bridge rescales lengths beyond 2^+-100
// for the clip's dot products; this one is relative to R and to the degree.)
constexpr int kDirectionExponentBudget = 256;

// The e with max|d_i| 2^-e in [R, 2R) when the walk must rescale d, else 0.
int directionRescale(const SurfaceData& data, const glm::dvec3& d) {
  const double md = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
  // The biased exponents, from the bits (no libm call on every ray); md = 0, inf or NaN
  // is walkRoots' own business.
  const auto field = [](double x) {
    return static_cast<int>(std::bit_cast<std::uint64_t>(x) >> 52);
  };
  if (!(md > 0.0) || !std::isfinite(md)) return 0;
  const int k = std::abs(field(md) - field(data.radius));
  if (k * std::max(data.horner.degree(), 1) <= kDirectionExponentBudget) [[likely]]
    return 0;
  return std::ilogb(md) - std::ilogb(data.radius);  // exact for subnormal md too
}

struct RescaledAccept {
  AcceptFn accept;
  void* user;
  int exp;  // host t = 2^exp kernel t
};
bool acceptRescaled(void* user, const KernelHit& hit) {
  const auto& r = *static_cast<const RescaledAccept*>(user);
  KernelHit h = hit;
  h.t = std::ldexp(hit.t, r.exp);
  return r.accept(r.user, h);
}

bool walkRootsOf(const SurfaceData& data, unsigned cell, const KernelRay& ray, bool occlusion,
                 AcceptFn accept, void* user);

}  // namespace

bool walkRoots(const SurfaceData& data, unsigned cell, const KernelRay& ray, bool occlusion,
               AcceptFn accept, void* user) {
  const int e = directionRescale(data, ray.dir);
  if (e == 0) [[likely]]
    return walkRootsOf(data, cell, ray, occlusion, accept, user);
  KernelRay scaled = ray;
  scaled.dir =
      glm::dvec3(std::ldexp(ray.dir.x, -e), std::ldexp(ray.dir.y, -e), std::ldexp(ray.dir.z, -e));
  scaled.tnear = std::ldexp(ray.tnear, e);
  scaled.tfar = std::ldexp(ray.tfar, e);
  RescaledAccept rescaled{accept, user, -e};
  return walkRootsOf(data, cell, scaled, occlusion, &acceptRescaled, &rescaled);
}

namespace {

// clipRegionSpan, and closest: closestParameter(o, d, 0) for restrictRecentred when the
// clip region is a sphere centred on the object-space origin (the gallery's), else NaN.
// clipToSphere's tc is that value bit for bit: with the centre 0, o - 0 = o, and
// dot(0 - o, d) is -dot(o, d) exactly but for the sign of a zero sum (0 - o_i is +0 where
// -o_i is -0), so a zero tc is left to closestParameter. It lies in [t0, t1] =
// [tc - dt, tc + dt] (dt >= 0 or NaN, and t0, t1 start unbounded), where the clamp of
// restrictRecentred keeps it.
inline bool regionSpan(const SurfaceData& data, const glm::dvec3& o, const glm::dvec3& d,
                       double& t0, double& t1, double& closest) {
  closest = std::numeric_limits<double>::quiet_NaN();
  const auto* s = std::get_if<ClipSphere>(&data.desc.clip);
  if (!s) return clipRegionSpan(data, o, d, t0, t1);
  t0 = -kInf;
  t1 = kInf;
  double tc;
  if (!clipToSphere(*s, o, d, t0, t1, tc)) return false;
  if (tc != 0.0 && s->center == glm::dvec3(0.0)) closest = tc;
  return true;
}

bool walkRootsOf(const SurfaceData& data, unsigned cell, const KernelRay& ray, bool occlusion,
                 AcceptFn accept, void* user) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  // ---- Input: non-finite or degenerate rays have no hit (and must not hang) ----------
  // (A deferred orgError, the bridge's, is >= 0 or NaN, and its floatOriginError >= 0
  // for a finite origin: the whole bound passes this test exactly when it does.)
  if (!finite(o) || !finite(d) || std::isnan(ray.tnear) || std::isnan(ray.tfar) ||
      !(ray.orgError >= 0.0))
    return false;
  if (!(glm::dot(d, d) > 0.0) || !(ray.tnear < ray.tfar)) return false;

  // ---- 1. Span: clip region, then the cell (closed, widened for rounding) -------------
  // (closest: the re-centring point from the clip sphere's chord, regionSpan; measured,
  // speed_report one thread, interleaved: Barth sextic primary 2.83 -> 2.85 Mrays/s,
  // Sarti dodecic 0.941 -> 0.952.)
  double r0, r1, closest;
  if (!regionSpan(data, o, d, r0, r1, closest)) return false;
  const SurfaceCell& box = data.cells[cell];
  double c0 = r0, c1 = r1;
  if (!clipToBox(box.lo, box.hi, o, d, c0, c1, true)) return false;
  const double lo = std::max(c0, ray.tnear), hi = std::min(c1, ray.tfar);
  if (!(lo < hi)) return false;

  // ---- 2. Restriction and roots (shared by all cells the ray visits) -------------------
  // The per-thread record, re-derived if the host filter called below traced rays of its
  // own on this thread and so replaced it (the same computation gives the same roots).
  auto current = [&]() -> RayRoots& { return rayRoots(data, ray, r0, r1, closest, occlusion); };

  // ---- 3. The cell's roots in order, offered to the host filter -------------------------
  // A root belongs to the cell whose grid box holds its point (claimsRoot), which the
  // span decides only up to rounding: the span is widened by the rounding of its own slab
  // test, relative to t at the face, while the root carries the rounding of the
  // re-centred restriction, relative to tShift, which can lie far beyond a face near the
  // origin (a ray crossing the plane x = 0 on a cell face was claimed by no cell). So
  // roots within `window` of the span go to claimsRoot as well.
  const HornerForm& f = data.horner;
  for (int i = 0;; ++i) {
    RayRoots& rr = current();
    if (occlusion && i == 0 && rr.count == 1 && !rr.firstPolished && !data.quadric &&
        !occlusionRootCertain(rr, ray)) [[unlikely]]
      settleAfterTnear(data, ray, rr);
    const double window = 0x1p-20 * (std::abs(rr.g.tShift) + std::abs(lo) + std::abs(hi));
    if (i >= rr.count) {
      if (rr.complete || !(rr.roots[rr.count - 1] < hi + window - rr.g.tShift)) break;
      completeRoots(data, rr);  // the next cells of this ray find the full list here
      if (i >= rr.count) break;
    }
    const RayPolynomial& g = rr.g;
    const double slo = lo - g.tShift, shi = hi - g.tShift;
    const double s = rr.roots[i];
    // Behind an origin on the surface (tnear < 0): the search span kept the window, whose
    // roots are the origin's own (searchSpan).
    if (rr.selfWindow > 0.0 && std::abs(s) <= rr.selfWindow) continue;
    // The solver reports a root within noise of an end of the region's span at that end
    // (roots.h; the start is closed, regionRoots): nothing beyond the region could report
    // it, so it counts there, inside (tnear, tfar) (a triple factor seen through a
    // degree-16 product was within noise over the last 1 % of a ray's span: the root came
    // back as r1 and was dropped).
    const bool inSpan = (s > slo || (s == rr.slo && lo == r0 && r0 > ray.tnear)) &&
                        (s < shi || (s == rr.shi && hi == r1 && r1 < ray.tfar));
    if (!inSpan && !ray.hasTraversalRay && !(s > slo - window && s < shi + window)) {
      if (s >= shi) break;
      continue;
    }
    KernelHit hit;
    hit.t = g.tShift + s;
    hit.point = o + hit.t * d;
    const Claim claim = claimsRoot(data, cell, hit.point, ray, inSpan);
    if (claim == Claim::kNone) {
      if (s >= shi && !ray.hasTraversalRay) break;
      continue;
    }
    // In the double channel the orphan rule of claimsRoot may let several cells take a
    // root (its owner not surely reached by the float ray): each is offered once per
    // trace (an any-hit filter saw a root on a grid edge 7 times from 100 box radii).
    // The owner, visited once per trace, defers only to a shared claim of this trace: the
    // trace id is the context's, and a host tracing the same ray again with the same
    // context got the next root each time (the owner skipped the roots offered before).
    const std::uint64_t bit = i < 64 ? std::uint64_t{1} << i : 0;
    if (ray.trace != 0) {
      const OfferedRoots& seen = offeredRoots(data, ray);
      if (((claim == Claim::kOwner ? seen.shared : seen.offered) & bit) != 0) continue;
    }
    // Polish within the whole span (a root near a cell face may move across it; the
    // owner was decided on the unpolished value). A cache root was polished already.
    if (i == 0 && rr.firstPolished)
      hit.gradient = rr.firstGradient;
    else if (data.quadric)
      hit.gradient = occlusion ? glm::dvec3(0.0) : data.quadric->gradient(hit.point);
    else if (!occlusion)
      polish(f, o, d, std::max(r0, ray.tnear), std::min(r1, ray.tfar), 1e-4 * (r1 - r0), hit);
    if (!(hit.t > ray.tnear && hit.t < ray.tfar)) continue;
    if (ray.trace != 0) {
      OfferedRoots& seen = offeredRoots(data, ray);
      seen.offered |= bit;
      if (claim == Claim::kShared) seen.shared |= bit;
    }
    if (accept(user, hit)) return true;
  }
  return false;
}

}  // namespace

}  // namespace algray
