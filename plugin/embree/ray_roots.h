#pragma once
// The kernel's per-ray record: g, the restriction of f to one ray over the whole clip
// region, and g's roots there in order, shared by every cell the ray visits
// (ray_roots.cpp: restriction, origin cache, the solver's calls; self_root.cpp: the
// self-root rule), and the checks that place g's first root on f itself (ray_settle.cpp).
// The walk through one cell (surface_intersect.cpp) reads it. No Embree types, as in
// surface_data.h.
#include "surface_data.h"

#include "algray/horner_form.h"
#include "algray/taylor.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace algray {

// g(s) = f(o + (tShift + s) d) for the whole clip-region span [r0, r1], and its roots
// there, shared by every cell the ray visits (the per-thread last ray): about the origin
// when it lies on the surface (self-root rule), from a cached origin expansion, or about
// the point of the span closest to the object-space origin. The roots are found lazily: the
// first one (all a closest-hit query without a filter needs), then all of them when a
// cell beyond the first root asks. Every cell sees the same root values, which is what
// makes the walk's ownership rule exact.
struct RayRoots {
  std::uint64_t id = 0;
  glm::dvec3 org{0.0}, dir{0.0};
  double orgRoundoff = 0, orgError = 0, orgErrorWorld = 0, orgErrorObject = 0;
  bool orgErrorDeferred = false;
  RayPolynomial g;
  double r0 = 0, r1 = 0;    // the region span in t
  double slo = 0, shi = 0;  // the same in s
  double tnear = 0;         // the ray's (searchSpan, with selfWindow)
  double selfWindow = 0;    // > 0: the self-root rule applied (selfRootWindow)
  // > 0: a double ray with the host's orgError whose origin the rule did not take for a
  // surface point; roots with |t| within it are still the origin's (deriveRayRoots).
  double originWindow = 0;
  // With it and g = g0 / s: |g0(0)|, the constant the rule set to 0, which a root of g
  // must outgrow to be a surface's (inOriginNoise, ray_roots.cpp); else -1.
  double zeroedConstant = -1;
  // The rule's division of G, the restriction about the origin, by its root there r (0:
  // by s, G(0) = c_0 set to 0), g = (G - G(r)) / (s - r), and a bound of |G(r)| with G's
  // noise at r (-1: no division; divisionNoise).
  double divisionRoot = 0, divisionRemainder = -1;
  bool closedLo = true;  // slo is the region's start (regionRoots), not the window
  std::array<double, kMaxDegree> roots{};  // in s, increasing
  int count = 0;
  bool complete = false;
  bool fromCache = false;  // g came from the origin cache (fewer digits, ray_roots.cpp)
  // The first root was confirmed (polished) on f: its gradient, so that the hit does not
  // evaluate f again.
  bool firstPolished = false;
  glm::dvec3 firstGradient{0.0};
  bool firstAtNoise = false;  // the first root came from the solver's noise rules (roots.h)
  // completeRoots moved a cached first root onto the re-centred restriction: its t as the
  // cache had it, which the walk reports (tShift + roots[0] can be ulps off it).
  bool firstRebased = false;
  double firstT = 0;
};
// Kept per thread without a registered destructor (see threadOriginCache, ray_roots.cpp).
static_assert(std::is_trivially_destructible_v<RayRoots>);

// Whether rr's first root is g's alone, not yet placed on f (a quadric's closed form
// needs no placing; ray_settle.cpp places it), also where an occlusion query completed
// the list behind it (count == 1 alone let a closest hit after it keep g's placing, 1.8e-12
// early on Chmutov-16, and report a root past its tfar).
inline bool firstUnsettled(const SurfaceData& data, const RayRoots& rr) {
  return rr.count > 0 && !rr.firstPolished && !data.quadric;
}

// ---- ray_roots.cpp -------------------------------------------------------------------------
// The thread's record (constant-initialised: other files read it without a call through
// a thread-local wrapper).
extern constinit thread_local RayRoots tlsRayRoots;
// The record for this ray, surface and clip-region span [r0, r1] (closest: the re-centring
// point when the walk has it, else NaN), restricted and solved for its first root afresh,
// the first root settled on f where the query needs it (a closest hit always, occlusion
// where g alone cannot tell).
RayRoots& deriveRayRoots(const SurfaceData& data, const KernelRay& ray, double r0, double r1,
                         double closest, bool occlusion);
// The thread's record where it holds this ray already (every cell after the first, and the
// walk after a host filter that traced no rays of its own), else deriveRayRoots. A closest
// hit derives again a record that an occlusion query of the same ray left with its first
// root unsettled (afresh rather than settled in place, so that it is the fresh query's
// answer by construction): a closest hit must not depend on what was asked before it. Why
// (session 34): on session 31's random extreme surfaces settling moves the first root on
// 1-2 % of the rays, by up to 1.5e-8 radii, and a closest hit after an occlusion query of
// the same ray kept g's placing (StressPlacement.ClosestHitAfterOcclusionOfTheSameRay).
[[gnu::always_inline]] inline RayRoots& rayRoots(const SurfaceData& data, const KernelRay& ray,
                                                 double r0, double r1, double closest,
                                                 bool occlusion) {
  RayRoots& rr = tlsRayRoots;
  if (rr.id == data.id && rr.org == ray.org && rr.dir == ray.dir &&
      rr.orgRoundoff == ray.orgRoundoff && rr.orgError == ray.orgError && rr.tnear == ray.tnear &&
      rr.orgErrorDeferred == ray.orgErrorDeferred && rr.orgErrorWorld == ray.orgErrorWorld &&
      rr.orgErrorObject == ray.orgErrorObject && (occlusion || !firstUnsettled(data, rr)))
      [[likely]]
    return rr;
  return deriveRayRoots(data, ray, r0, r1, closest, occlusion);
}
// All roots of rr.g in its search span, keeping the first one's value.
void completeRoots(const SurfaceData& data, RayRoots& rr);
// Newton on f itself about hit.t within [lo, hi] and 1e-4 of the clip region's span
// regionSpan (r1 - r0) of the start, then last steps on f's compensated value where f's
// rounding would leave t between 2^-35 and 2^-10 of that span from the root; whether f
// ended within its evaluation bound (confirmed). `last`, if given, receives f at the result.
bool polish(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double lo, double hi,
            double regionSpan, KernelHit& hit, Polynomial::Evaluation* last = nullptr);
// restrictToRay(f, o, d, tShift, g) about a point on the line itself where it matters
// (restrictAbout, ray_roots.cpp): every restriction about a point of the ray other than o.
void restrictAbout(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double tShift,
                   RayPolynomial& g);
// rr.g restricted as for a ray without the origin cache (re-centred; rr.fromCache false).
void restrictWithoutCache(const SurfaceData& data, const KernelRay& ray, RayRoots& rr);
// The first root of rr.g in [rr.slo, rr.shi] (rr.count = 0 or 1); solveFirst sets that
// search span first.
void solveFirstInSpan(const SurfaceData& data, RayRoots& rr);
void solveFirst(const SurfaceData& data, RayRoots& rr);
// Whether rr's roots are the solver's exact ones (no tolerance, not the float solver) on a
// g that a new expansion may replace (not the self-root rule's deflated g): the roots that
// settleFirst searches for again and looks behind (ray_settle.cpp), and for whose first
// one the solver is asked whether g is within its noise before it (RootOptions::noiseBefore).
inline bool exactRoots(const SurfaceOptions& opt, const RayRoots& rr) {
  return opt.roots.relTolerance == 0.0 && !opt.singlePrecision && !(rr.selfWindow > 0.0);
}

// What the self-root rule's division adds to g's noise bound at s, as a bound on f (0
// where it made none). With G(s) = (s - r) g(s) + G(r) and |G(r)| <= K (divisionRoot r,
// divisionRemainder K), f(o + s d) = (s - r) g(s) + G(r) within |s - r| bound(s) (g's
// coefficient bounds carry G's): f's sign at s is that of (s - r) g(s) only where |g(s)|
// clears bound(s) + K / |s - r|, and g's roots lie up to that over |g'| from f's. Not
// small: on a float ray leaving a hit, K = |c_0| + e_0 is the float origin's offset from
// the surface (g / s stays where that moves the roots by a few float roundings,
// originRootMatters), and occlusion, which keeps g's root where g's bound proves it
// (occlusionRootCertain), put f's root on the other side of a tfar one float step from
// the closest hit on 47-88 % of the gallery's float rays leaving a hit (StressShadow.
// ColdQueriesOfALeavingFloatRayAgreeWithTheClosestHit); and where r is a
// nearly tangent origin's root, divideByOriginRoot's constant bound K (not over |s - r|)
// left a root 1.6e-4 from r 2.8e-6 off (Chmutov-16; session 48).
inline double divisionNoise(const RayRoots& rr, double s) {
  return rr.divisionRemainder >= 0.0 ? rr.divisionRemainder / std::abs(s - rr.divisionRoot) : 0.0;
}

// How far g's noise region reaches about its root s, to first order: 4 |bound / g'(s)|
// (the factor covers the curvature and the solver's error), at least 2^-50 of `scale`, the
// size of the parameters it is compared with; bound with the self-root rule's division
// (divisionNoise). Not finite where g' is 0 (NaN where the bound is 0 too): the callers then
// place the root on f. One formula for occlusionRootCertain and the walk's endWithinReach
// (surface_intersect.cpp), so that they agree.
inline double noiseReach(const RayRoots& rr, double s, double scale) {
  double bound, slope;
  rr.g.evaluateWithBound(s, bound, slope);
  return std::max(4.0 * (bound + divisionNoise(rr, s)) / std::abs(slope), 0x1p-50 * scale);
}

// How far from an end at t the root must lie for the end's side to be the root's: a plain
// float ray's host compares t rounded to float with its float tnear and tfar (embree_bridge
// .cpp, candidateTfar), so an end one float step from the root decides by that rounding,
// on which g's root and f's (the closest hit's) can differ. Occlusion then places the root
// on f too (occlusionRootCertain, endWithinReach): with tfar one float step past the
// closest hit, 9 of ~40,000 of the gallery's rays said "not occluded", or occluded with it
// one step before (session 48).
inline double floatEndReach(const KernelRay& ray, double t) {
  return ray.orgRoundoff > kUnitRoundoff ? 0x1p-23 * std::abs(t) : 0.0;
}

// ---- self_root.cpp -------------------------------------------------------------------------
// Whether the ray's origin lies on the surface within its uncertainty: f(o) within its
// evaluation bound plus what the origin's rounding and orgError (the ray's whole bound)
// move it by. f at the origin is kept per thread for the last origin.
bool originOnSurface(const SurfaceData& data, const KernelRay& ray, double orgError);
// The self-root rule for such a ray: rr.g about the origin with the origin's root divided
// out, rr.selfWindow (the origin's roots, a multiple root's cluster included),
// rr.zeroedConstant and the division's terms (divisionRoot, divisionRemainder).
void restrictFromSurfaceOrigin(const SurfaceData& data, const KernelRay& ray, double orgError,
                               RayRoots& rr);

// ---- ray_settle.cpp ------------------------------------------------------------------------
// The last point before s (towards slo) where g is clear of its noise bound, or slo.
double clearBefore(const RayPolynomial& g, double s, double slo, bool keepSign = true);
// Whether occlusion can keep g's first root, a sign change, without placing it on f.
bool occlusionRootCertain(const RayRoots& rr, const KernelRay& ray);
// Whether the first root settled behind tnear, where the walk's later roots get no check.
bool firstBehindTnear(const RayRoots& rr);
// A root within f's rounding noise of tnear counts as at tnear and is not reported (README,
// "by design"; the search starts before tnear, searchSpan), as a host stepping on from a hit
// (tnear = its t) has it: whether the root t, past tnear by at most 2^-30 of their size
// (withinTnearWindow), is tnear's own: within f's noise reach of tnear (or of both ends, f
// within its noise at each), one grazing point with a tnear where f is clear of its noise
// but not clearly off the surface, or placed past it by g (kFallsBack). The walk skips
// either kind; settleBesideTnear searches past both.
enum class AtTnear { kNo, kWithinReach, kFallsBack };
inline bool withinTnearWindow(double tnear, double t) {
  return t - tnear <= 0x1p-30 * (std::abs(tnear) + std::abs(t));
}
AtTnear rootAtTnear(const HornerForm& f, const KernelRay& ray, double t, double r0, double r1);
inline bool tnearsOwnRoot(const HornerForm& f, const KernelRay& ray, double t, double r0,
                          double r1) {
  return withinTnearWindow(ray.tnear, t) && rootAtTnear(f, ray, t, r0, r1) != AtTnear::kNo;
}
// Places rr's first root on f (polish, search again, look behind), then settleBesideTnear.
void settleAfterTnear(const SurfaceData& data, const KernelRay& ray, RayRoots& rr);
// rr's first root on f (settled, or a cached one confirmed on f) searched for again from
// tnear where it lies behind it, and past it wherever the walk would skip it (at or behind
// tnear, or tnear's own: rootAtTnear), so that the next root is settled on f as well.
void settleBesideTnear(const SurfaceData& data, const KernelRay& ray, RayRoots& rr);

}  // namespace algray
