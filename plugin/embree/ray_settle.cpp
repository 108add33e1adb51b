// The kernel's checks of a ray's first root on f itself (ray_roots.h): g, one expansion
// for the whole clip region, may place a root where f has none or miss roots of f inside
// its noise, so the first root is polished on f, searched for again about a better point
// where f rejects it, and looked behind where g's noise could hide earlier roots.
#include "ray_roots.h"

#include "algray/taylor.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace algray {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- Roots the expansion cannot place ------------------------------------------------------
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

// How far beyond what its evaluation and its point's rounding allow f may be at a root that
// stands (clearlyOffSurface): a grazing hit of the tangent rule, f's minimum along the ray
// within this factor of its noise, is a hit.
constexpr double kOffSurface = 0x1p10;

}  // namespace

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

namespace {

// Whether f at the polished point x = o + t d is beyond 2^10 times what its evaluation and
// the point's own rounding allow: x_i errs by up to u (|o_i| + |t d_i|) plus the origin's
// error bound, which moves f by up to |grad f| times as much (from a far origin, 1e5
// radii, that is what keeps f from its bound at every double t: the hits of a torus were
// taken for noise and searched for again). Where f is beyond its bound but within 2^10 of
// it, f's compensated value decides with its own bound, 2u|f| + gamma(2m+6)^2 E
// (horner_form.h), in place of evaluate()'s gamma(2m+3) E: at degree 40 that bound is
// 8e4 times a root's conditioning, and on a product of 20 spheres g's noise region
// reported first roots up to 0.005 clip radii before the true one (accuracy_report,
// session 38), where f was 290 times its bound and the polish's steps too long to reach
// it.
bool clearlyOffSurface(const HornerForm& f, const KernelRay& ray, const KernelHit& hit,
                       const Polynomial::Evaluation& e) {
  const glm::dvec3 spread = ray.orgRoundoff * (absv(ray.org) + std::abs(hit.t) * absv(ray.dir)) +
                            glm::dvec3(ray.orgError);
  const double moved = glm::dot(absv(e.gradient), spread);
  if (std::abs(e.value) > kOffSurface * (e.valueError + moved)) return true;
  if (!(std::abs(e.value) > e.valueError)) return false;
  const double fc = f.valueCompensated(hit.point);
  return std::abs(fc) > kOffSurface * (f.compensatedBound(fc, e.magnitude, hit.point) + moved);
}

// Polishes rr's first root on f; returns whether f is clearly non-zero at the result.
bool polishFirst(const SurfaceData& data, const KernelRay& ray, RayRoots& rr) {
  KernelHit hit;
  hit.t = rr.g.tShift + rr.roots[0];
  Polynomial::Evaluation e;
  const bool onF = polish(data.horner, ray.org, ray.dir, std::max(rr.r0, ray.tnear), rr.r1,
                          rr.r1 - rr.r0, hit, &e);
  rr.roots[0] = hit.t - rr.g.tShift;
  rr.firstPolished = true;
  rr.firstGradient = hit.gradient;
  return !onF && clearlyOffSurface(data.horner, ray, hit, e);
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
    restrictAbout(data.horner, ray.org, ray.dir, centre, rr.g);
    rr.divisionRemainder = -1.0;
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

}  // namespace

// Whether an occlusion query can keep g's first root, a sign change, without placing it on
// f (the closest hit does that anyway, settleFirst): f's root must be on the same side of
// tnear and of tfar as g's. g's rigorous noise bound proves a root of f wherever g clears
// it with opposite signs (the bound with the self-root rule's division, divisionNoise, and
// a and b on one side of the root it divided out), so that holds where g does so at two
// points a < s < b with neither tnear nor tfar in [a, b]: trivially when the whole search
// span lies in (tnear, tfar) (the solver's own bracket lies in it), else at s -+ 4 |bound
// / g'(s)|, the first-order reach of the noise bound (the factor covers the curvature and
// the solver's error), and a float step more for a float ray (floatEndReach). Where g
// cannot show it there (a wide noise region, as where g's terms are far larger than f's:
// the sign change placed anywhere inside it), or tnear or tfar lies in
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
  const double h = noiseReach(rr, s, std::abs(s)) + floatEndReach(ray, g.tShift + s);
  const double a = s - h, b = s + h;
  const auto outside = [&](double t) { return t < g.tShift + a || t > g.tShift + b; };
  if (!(h < kInf) || !outside(ray.tnear) || !outside(ray.tfar)) return false;
  if (rr.divisionRemainder >= 0.0 && (a - rr.divisionRoot < 0.0) != (b - rr.divisionRoot < 0.0))
    return false;
  double boundA, boundB;
  const double ga = g.evaluateWithBound(a, boundA), gb = g.evaluateWithBound(b, boundB);
  return std::abs(ga) > boundA + divisionNoise(rr, a) &&
         std::abs(gb) > boundB + divisionNoise(rr, b) && std::signbit(ga) != std::signbit(gb);
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

namespace {

// f's rounding noise at o + t d, e = f.evaluate(o + t d): its evaluation bound plus what the
// rounding of that point moves it by.
double noiseAt(const Polynomial::Evaluation& e, const glm::dvec3& o, const glm::dvec3& d,
               double t) {
  const glm::dvec3 pointError = gamma(2) * (glm::abs(o) + std::abs(t) * glm::abs(d));
  return e.valueError + glm::dot(glm::abs(e.gradient), pointError);
}

// Whether f at o + t d is within its noise there (noiseAt).
bool withinNoiseAt(const HornerForm& f, const glm::dvec3& o, const glm::dvec3& d, double t) {
  const Polynomial::Evaluation e = f.evaluate(o + t * d);
  return std::abs(e.value) <= noiseAt(e, o, d, t);
}

// Whether the root at t, which the restriction placed past f's noise reach of tnear, is
// tnear's own all the same (rootAtTnear): Newton on f from t, free to cross tnear, lands
// within that reach (`limit`) on f's noise, and f at t is clear of its noise and on f's
// tangent line at the landing point within a factor 2, so that f has no other root between
// them (two more would bend f away from the line, one more give t the other sign). Why
// (session 49): near the double lines of Steiner's Roman surface a host stepping along a
// ray (tnear = its last hit) met the root it had just reported again, up to six times: the
// root lay 0.5 ulp before tnear, g placed it 7.7e-16 to 1e-13 after it (its noise reach
// there 2e-13), past f's reach of 2.5e-16 and 4 ulps, and the polish, held to t > tnear,
// could not move it back (181 and 233 of 1000 rays near those lines, plain and
// transformed, had more hits than the degree; the third review of session 48; the same on
// Whitney's umbrella, Pluecker's conoid and the cross-cap). Not g's reach in place of f's
// (session 48, reverted): g expanded far away reaches over real roots past tnear (4e-13 to
// 2e-3 on random extreme surfaces).
// (e: f at o + t d, clear of its noise there.)
[[gnu::noinline, gnu::cold]] bool fallsBackOnTnear(const HornerForm& f, const glm::dvec3& o,
                                                   const glm::dvec3& d, double limit, double t,
                                                   const Polynomial::Evaluation& e, double r0,
                                                   double r1) {
  KernelHit back;
  back.t = t;
  Polynomial::Evaluation atBack;
  polish(f, o, d, r0, r1, r1 - r0, back, &atBack);
  if (!(back.t <= limit && std::abs(atBack.value) <= noiseAt(atBack, o, d, back.t))) return false;
  const double ratio = e.value / (glm::dot(atBack.gradient, d) * (t - back.t));
  return ratio >= 0.5 && ratio <= 2.0;
}

// Whether tnear and t, f clear of its noise at tnear, are one grazing point: f at both, and
// halfway, is not clearly off the surface (the test a settled root passes, so that a graze
// of the tangent rule is a hit) and has tnear's sign, and is clear of its noise at t (t is
// then no root within f's noise, such as a sign change just past the graze). Why (session
// 50): near the double lines of the Roman surface and the cross-cap a ray passes a minimum
// of f 100-2,500 times its noise (within what a transform's rounding of the origin allows),
// a grazing hit; a host stepping on from it met it again 1-3 ulps on, where f's rounding
// moved the polish (AGrazingPointIsMetOnce: five hits for degree 4).
[[gnu::noinline, gnu::cold]] bool oneGrazingPoint(const HornerForm& f, const KernelRay& ray,
                                                  double t, const Polynomial::Evaluation& e) {
  const auto grazing = [&](double x, const Polynomial::Evaluation& at) {
    KernelHit hit;
    hit.t = x;
    hit.point = ray.org + x * ray.dir;
    return std::signbit(at.value) == std::signbit(e.value) && !clearlyOffSurface(f, ray, hit, at);
  };
  if (!grazing(ray.tnear, e)) return false;
  const Polynomial::Evaluation et = f.evaluate(ray.org + t * ray.dir);
  if (!(std::abs(et.value) > noiseAt(et, ray.org, ray.dir, t) && grazing(t, et))) return false;
  const double mid = ray.tnear + 0.5 * (t - ray.tnear);
  return grazing(mid, f.evaluate(ray.org + mid * ray.dir));
}

}  // namespace

// f at o + tnear d is within its noise (noiseAt), and t lies within that noise's reach
// along the ray (its width over f's slope there) and 4 ulps, or f is within its noise at t
// too and the two reaches together span the gap, or f's Newton steps from t fall back
// there (fallsBackOnTnear). A host stepping past a hit with tnear = its t (the
// double nearest the root, which may lie below it) met the same root again one double on
// (1152 of 14313 double-channel rays through a torus with hits). Without the reach, any
// root within 2^-30 of tnear went (a second plane 1e-8 on; the far side of a torus seen
// from 1e9 radii). Where f at tnear is clear of its noise, t is tnear's own only as the same
// grazing point (oneGrazingPoint).
AtTnear rootAtTnear(const HornerForm& f, const KernelRay& ray, double t, double r0, double r1) {
  const glm::dvec3& o = ray.org;
  const glm::dvec3& d = ray.dir;
  const double tnear = ray.tnear;
  const Polynomial::Evaluation e = f.evaluate(o + tnear * d);
  const double noise = noiseAt(e, o, d, tnear);
  if (!(std::abs(e.value) <= noise))
    return oneGrazingPoint(f, ray, t, e) ? AtTnear::kWithinReach : AtTnear::kNo;
  const double a = std::max(std::abs(tnear), std::abs(t));
  const double slope = std::abs(glm::dot(e.gradient, d));
  const double reach = noise / slope;  // inf at a zero slope
  const double width = 4.0 * (std::nextafter(a, kInf) - a) + reach;
  if (t - tnear <= width) return AtTnear::kWithinReach;
  // f within its noise at t too: t may lie at the far edge of the noise region whose near
  // edge tnear is (a hit the walk's polish left where f first came within its bound; the
  // next query placed the root 2.1e-14 on, at the far edge, 191 ulps: a Chmutov-8 ray from a
  // camera inside the clip region, with the origin cache, met its root twice; the second
  // review of session 49), so t's noise counts as well, over the slope of tnear's root, and
  // f must stay within its noise between them (halfway). Not over the slope at t: a ray
  // grazing another sheet just past tnear has none there, and its pair of roots, clear of
  // f's noise from tnear, went (the third review: a plane, then a sphere grazed 4.3e-4 on).
  const Polynomial::Evaluation et = f.evaluate(o + t * d);
  const double noiseT = noiseAt(et, o, d, t);
  if (!(std::abs(et.value) > noiseT)) {
    if (!(t - tnear <= width + noiseT / slope)) return AtTnear::kNo;
    const double mid = tnear + 0.5 * (t - tnear);
    return withinNoiseAt(f, o, d, mid) ? AtTnear::kWithinReach : AtTnear::kNo;
  }
  return fallsBackOnTnear(f, o, d, tnear + width, t, et, r0, r1) ? AtTnear::kFallsBack
                                                                 : AtTnear::kNo;
}

namespace {

// rr's g restricted again about the ray's point at t, a record of none of the first
// expansion's kinds (no division, no cache, nothing polished).
void restrictAgainAbout(const SurfaceData& data, const KernelRay& ray, double t, RayRoots& rr) {
  restrictAbout(data.horner, ray.org, ray.dir, t, rr.g);
  rr.divisionRemainder = -1.0;
  rr.fromCache = false;
  rr.firstPolished = false;
}

[[gnu::noinline, gnu::cold]] void searchFromTnear(const SurfaceData& data, const KernelRay& ray,
                                                  RayRoots& rr) {
  restrictAgainAbout(data, ray, ray.tnear, rr);
  solveFirst(data, rr);
  if (rr.count == 1) settleFirst(data, ray, rr);
}

// Whether f is within its noise at tnear, at t and at 15 points evenly between (halfway, the
// ends, then the rest: the checks that reject a clear stretch soonest), as across the noise
// region of a root of odd multiplicity. Not halfway alone: f between a 7-fold root's noise
// region and a simple root 0.02 past it rises to 28 times its noise, and a host stepping
// from the region's start lost the simple root ((x - 0.3)^7 (x - 0.32); the second review
// of session 50). The cost falls on the rare roots that pass the first checks.
[[gnu::noinline]] bool inTnearsNoiseRegion(const HornerForm& f, const KernelRay& ray, double t) {
  const auto withinNoise = [&](double x) { return withinNoiseAt(f, ray.org, ray.dir, x); };
  const double step = (t - ray.tnear) / 16.0;
  if (!(withinNoise(ray.tnear + 8.0 * step) && withinNoise(ray.tnear) && withinNoise(t)))
    return false;
  for (int j = 1; j < 16; ++j)
    if (j != 8 && !withinNoise(ray.tnear + j * step)) return false;
  return true;
}

// Whether the settled first root is one the walk would skip, at or behind tnear
// (kWithinReach) or tnear's own (rootAtTnear), and take the next root of the list, which
// gets no check on f; or one in the noise region of f that holds tnear, past the window of
// rootAtTnear (an m-fold root whose noise region holds tnear counts as at tnear, README):
// a host stepping through the noise region of a triple cylinder (x^2 + y^2 - 1/4)^3, 6e-6
// wide, met it five times, each step's settled root (searchFromTnear, searchBefore) a point
// further in the region, where the list's next root had lain past it (the review of session
// 50). Only for a tnear inside the clip region, where it can be a root (a camera's rays from
// outside do not pay the evaluation).
AtTnear firstSkippedAtTnear(const SurfaceData& data, const KernelRay& ray, const RayRoots& rr) {
  if (rr.count != 1 || rr.selfWindow > 0.0) return AtTnear::kNo;
  const double t = rr.g.tShift + rr.roots[0];
  if (t <= ray.tnear) return AtTnear::kWithinReach;
  if (withinTnearWindow(ray.tnear, t)) return rootAtTnear(data.horner, ray, t, rr.r0, rr.r1);
  if (!(ray.tnear > rr.r0)) return AtTnear::kNo;
  // g clear of twice its bound halfway: f is clear there too where g keeps f's digits (a
  // gate of one evaluation of g before up to 17 of f; where f's noise exceeds g's bound it
  // errs towards reporting the root).
  double bound;
  const double mid = 0.5 * (ray.tnear + t) - rr.g.tShift;
  if (std::abs(rr.g.evaluateWithBound(mid, bound)) > 2.0 * bound) return AtTnear::kNo;
  return inTnearsNoiseRegion(data.horner, ray, t) ? AtTnear::kWithinReach : AtTnear::kNo;
}

// The first root is one the walk skips: the ray is searched on from it, open (the solver
// leaves a root within noise of an open start, the one the host has), and the root found
// there is settled on f, as for a host stepping on from it (one found in tnear's noise
// region of f is skipped in turn: firstSkippedAtTnear). Not the rest of the list: its roots
// get no check on f (near the double lines of the Roman surface and the cross-cap the list
// held points between two roots 1e-8 apart, or beside a complex pair 4e-9 from the axis;
// PastARootSettledBehindTnearTheNextHitIsFsNextRoot).
// With `reexpand` (a root tnear's own though g placed it past f's reach,
// AtTnear::kFallsBack) g is restricted again about the root: the g that placed it wrongly
// need not place the next one (near a Roman double line, g about the region's middle placed
// tnear's root 1e-13 past it and listed 1.00000026 next, where f has roots at 1.0000000048
// and 1.0000005193; session 49, PastARootPlacedBeyondTnearTheNextHitIsTheNextRoot).
// Otherwise g stays (re-expanding about every root a stepping host had just met took its
// steps 1.4-1.6x the time on the gallery), but for the origin cache's expansion, which
// settling does not search again: the record takes the re-centred restriction a ray gets
// without the cache (about the skipped root instead, a filter's walk on from the next root
// took the later roots from that expansion: points beside a complex pair 5e-8 from the axis
// of the Roman surface; the review of session 50).
[[gnu::noinline, gnu::cold]] void searchPast(const SurfaceData& data, const KernelRay& ray,
                                             RayRoots& rr, bool reexpand) {
  const double t = rr.g.tShift + rr.roots[0];
  if (reexpand) {
    restrictAgainAbout(data, ray, t, rr);
  } else if (rr.fromCache) {
    restrictWithoutCache(data, ray, rr);
    rr.firstPolished = false;
  }
  rr.slo = t - rr.g.tShift;
  rr.shi = rr.r1 - rr.g.tShift;
  rr.closedLo = false;
  solveFirstInSpan(data, rr);
  // A root g places within half a double of t is t itself: the search goes on from t's next
  // double. Without it a search from the root found t again, eight times, and the walk then
  // took the list's next root, a point where f was 1e10 times its noise (a random surface of
  // degree 14 with terms of 1e69, session 50).
  if (rr.count == 1 && rr.g.tShift + rr.roots[0] <= t) {
    rr.slo = std::nextafter(t, kInf) - rr.g.tShift;
    solveFirstInSpan(data, rr);
  }
  if (rr.count == 1) settleFirst(data, ray, rr);
}

}  // namespace

// settleFirst, the search from tnear where the root settled behind it, and past it where
// the walk would skip it: the same path for occlusion, wherever it settles the root (rayRoots,
// walkRootsOf), as for the closest hit.
void settleAfterTnear(const SurfaceData& data, const KernelRay& ray, RayRoots& rr) {
  settleFirst(data, ray, rr);
  settleBesideTnear(data, ray, rr);
}

void settleBesideTnear(const SurfaceData& data, const KernelRay& ray, RayRoots& rr) {
  if (firstBehindTnear(rr)) [[unlikely]]
    searchFromTnear(data, ray, rr);
  for (int k = 0; k < kReexpansions; ++k) {
    const AtTnear skipped = firstSkippedAtTnear(data, ray, rr);
    if (skipped == AtTnear::kNo) break;
    searchPast(data, ray, rr, skipped == AtTnear::kFallsBack);
  }
}

}  // namespace algray
