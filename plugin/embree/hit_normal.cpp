// The normal at a closest hit where grad f at the hit does not give it.
//
// grad f at a root of f is the surface normal, and the walk reports it as computed at the
// hit, except where the ray's slope there, grad f . d, is within 2^10 times the bound of
// its rounding noise over the clip ball (hitGradient, surface_data.h). That happens
//  * on a multiple surface, f = h^k q with k >= 2: grad f = k h^(k-1) q grad h vanishes on
//    h = 0, and the computed hit lies within ~u^(1/k) of the surface on either side. For
//    even k, f >= 0 on both sides of it and grad f points to whichever side rounding put
//    the hit: before this file (x^2 + y^2 + z^2 - 1)^2 = 0 rendered as a speckle of front
//    and back materials, and rays from outside got inward normals on a third of its hits,
//    noise directions on others ((0, -1, 0) for a hit at (0.58, -0.23, 0.79));
//  * at a singular point of a simple surface (a cone's apex, Sarti's nodes), grad f = 0;
//  * on a ray grazing a simple surface (its gradient clear, its slope not).
// Then (gradientBesideNoise): grad f at the hit is kept where it clears its own noise bound
// at the hit (gradientNoise) 2^10-fold, so that rounding turns it by at most ~2^-10
// radians, and either faces the ray (grad f . d < 0 clearly: right for an even root, where
// f = h^2 q rises on both sides and the normal faces the side the ray comes from as a
// simple surface's does where the ray enters it, and for an odd one crossing downwards),
// or lies across the ray (a ray touching a simple surface), or f is clearly negative just
// before the hit and positive after it (an odd root crossing upwards). Otherwise the
// normal is searched for before the hit, at p - delta d/|d| for delta from 2^-32 to 2^-6
// clip radii by factors of 4, on to 2^-2 by factors of 2 (searchBefore): the first gradient
// there that is clear and faces the ray, or, once f is found to have opposite signs at p -+
// delta d/|d| (an odd root: h^3 keeps its gradient's orientation across the surface), the
// first clear one, or, where f is negative on both sides and the gradients there opposite
// at some rung, or across the surface along grad f (evenAcross: a ray grazing it), an even
// root of f <= 0, grad(-f) at the first clear one; each combined with its mirror point
// after the hit (symmetric), unless it lies
// outside the cone of directions the hit's own gradient and its noise bound allow. (A ray
// touching a cone's apex from inside is such an even root along the ray: grad(-f) just
// before the apex, facing the ray.) Where nothing is found and the gradient at the hit is
// zero, the bridge reports the reversed ray direction.
// The gradient's noise at the hit includes what the hit point's own rounding moves it by
// (hitPointError, surface_data.h): from 1e6 radii a double surface's hit lands 2e-10 radii
// to either side of it, where its gradient is clear of the evaluation's noise.
// Cost: up to 18 rungs of a few evaluations of f each along the ray and 18 across it (14
// along it until session 43), only on these hits, and mostly two evaluations (rendering
// (x^2 + y^2 + z^2 - 1)^2 took 1.07-1.08 s instead of 1.05-1.07); every other hit pays the
// slope test (docs/speed-details.md, session 35). Accuracy against grad h in long double
// at the hit: about the distance delta at which grad f is taken times the normal's turning
// rate |hess h| / |grad h| (session 39, 80 seeds of StressRandom.MultipleSurfacesGetTheir-
// OwnNormal, 487538 hits with |grad h| > 1e-3): angle |grad h| / |hess h| at most 1.6e-5
// clip radii on random double surfaces and 8.8e-3 on triple ones, whose gradient clears its
// noise only that far away; angles at most 1.0e-5 and 1.2e-2 radians where the rate is
// below 10 per clip radius, and anything towards h's singular curve, where the rate grows
// without bound (triple: up to 1.5 radians, 23 of 244215 hits wrongly oriented, all with
// |grad h| < 0.03); double surfaces always face the ray (tests/stress_random_test.cpp;
// tests/embree_normals_test.cpp, EmbreeNormals.MultipleSurfacesGetTheirOwnNormal).
// Measured and not kept (session 39): grad f and its bound by a compensated scheme, so
// that it clears at the hit itself: normals up to 90 degrees off (1.49 radians at the 99th
// percentile of 36798 double-surface hits of 12 seeds). The stored coefficients of h^k q
// are rounded (here its expansion's products): f is h^k q plus a perturbation of ~u E, so
// at the hit, the bottom of a valley of depth ~u E, the exact grad f of the stored f is
// that perturbation's, along the valley. What hides the normal is the coefficients' own
// error, which evaluate()'s bound has the size of, not the evaluation's.
// Where those triple-surface figures come from (session 37, that test's worst 25 hits): not
// the hit's offset from the surface (h there is 1e-14..1e-5), but the distance at which
// grad f, which vanishes like h^2, first clears 2^10 times its noise bound: 2^-12..2^-8 clip
// radii, where near h's singular curve (h = P Q, |grad h| < 0.05) the mirror point's gradient
// already points the other way (by the look of it, the other sheet of h = P Q), so the
// one-sided gradient stays, off by that distance times the normal's turning rate.
// Measured and not kept: each side divided by its slope along the ray (g+- / |g+- . u|,
// which removes the weights h^(k-1) of the two sides): the worst angles the same to three
// digits (1927 of the 3685 mirrored pairs moved).
#include "surface_data.h"

#include <cmath>

namespace algray {

namespace {

// A gradient is clear where it exceeds 2^10 times its noise (its direction then moved by
// rounding by at most ~2^-10 radians), and faces the ray where grad f . u < 0 by as much.
constexpr double kClear = 0x1p10;
bool clearOf(const glm::dvec3& g, const glm::dvec3& noise) {
  const glm::dvec3 a = absv(g);
  return std::max({a.x, a.y, a.z}) > kClear * std::max({noise.x, noise.y, noise.z});
}
bool facingOf(const glm::dvec3& g, const glm::dvec3& noise, const glm::dvec3& u) {
  return glm::dot(g, u) < -kClear * glm::dot(noise, absv(u));
}
// The distances looked at before (and after) the hit: 2^-32 to 2^-6 scene radii by factors
// of 4 (kRungs), then on to 2^-2 by factors of 2 for the search alone (kSearchRungs). (The
// scene radius, SurfaceData::sceneRadius, is the clip radius up to 2^13 object radii: in
// clip radii a unit sphere clipped to a ball of radius 1e14 looked 2.3e4 away from its hits
// and turned a normal inside out, the audit of session 51.) f =
// h^m q is within its noise for |h| up to ~(u E)^(1/m), and its gradient, m h^(m-1) q grad
// h, clears its own noise 2^10-fold only farther out: on (x^2 + y^2 + z^2 - 1)^m in a ball
// of radius 1.5, ~2^-6 radii for m = 6, 2^-5 for m = 7, 2^-4 for m = 8 (session 43).
constexpr int kRungs = 14, kSearchRungs = kRungs + 4;
double rung(const SurfaceData& data, int k) {
  return std::ldexp(data.sceneRadius, k < kRungs ? -32 + 2 * k : -6 + (k - kRungs + 1));
}

// grad f at p - delta u, combined with grad f at p + delta u where that is clear and
// oriented as an even root (facing away: g- - g+, or g- + g+ on a grazed simple surface)
// or an odd one (along g-: g- + g+) has it: the difference of the two points' offsets
// cancels to first order, so the result is grad f's direction at the hit to O(delta^2) (on
// the double surfaces of StressRandom.MultipleSurfacesGetTheirOwnNormal with |grad h| >
// 1e-3, its own seed: worst 6.3e-6 radians instead of 1.3e-4; no change on the triple ones).
// `sign` -1 takes grad(-f) after the hit (gMinus is then -grad f before it): an even root
// of f <= 0, such as -h^2, is one of -f >= 0.
glm::dvec3 symmetric(const SurfaceData& data, const glm::dvec3& u, const glm::dvec3& point,
                     double delta, const glm::dvec3& gMinus, bool even, double sign = 1) {
  const glm::dvec3 q = point + delta * u;
  const glm::dvec3 gPlus = sign * data.horner.evaluate(q).gradient, noise = gradientNoise(data, q);
  if (!clearOf(gPlus, noise)) return gMinus;
  // Even: g+ faces away. Pointing against g- (h changes sign across the hit, grad f with
  // it) the two are a multiple surface's sides; along it, a ray grazing a simple surface
  // past the point where it touches, whose normal is their mean (their difference is along
  // the ray: a sphere's normal was the ray's direction).
  if (even) {
    if (!facingOf(-gPlus, noise, u)) return gMinus;
    return glm::dot(gMinus, gPlus) < 0 ? gMinus - gPlus : gMinus + gPlus;
  }
  return glm::dot(gMinus, gPlus) > 0 ? gMinus + gPlus : gMinus;
}

// Whether q lies in the ball holding the clip region: the rungs past 2^-6 radii stop at its
// boundary, beyond which other sheets of f that the surface does not have may lie (a
// review of session 43: (x^2+y^2+z^2-1)^6 (1.05-x^2-y^2-z^2) clipped at 1.02 had all its
// normals reversed by the sheet at 1.025).
bool inClipBall(const SurfaceData& data, const glm::dvec3& q) {
  const glm::dvec3 c = q - data.centre;
  return glm::dot(c, c) <= data.radius * data.radius;
}

// Whether f, negative near the hit, is an even root of f <= 0 there: from the hit along
// g = grad f (towards the surface, where f rises), the first rung with f clear is past the
// surface with f negative and grad f turned against g (h^m q with m even, f <= 0 on both
// sides), not positive (m odd). Only for rays that touch or graze the surface, whose two
// sides along the ray need not straddle it (session 43: 16 of 638 hits of -(x^2 + y^2 +
// z^2 - 1)^8 faced away).
bool evenAcross(const SurfaceData& data, const glm::dvec3& point, const glm::dvec3& g) {
  const glm::dvec3 n = glm::normalize(g);
  for (int k = 0; k < kSearchRungs; ++k) {
    const glm::dvec3 q = point + rung(data, k) * n;
    if (k >= kRungs && !inClipBall(data, q)) break;
    const Polynomial::Evaluation e = data.horner.evaluate(q);
    if (!(std::abs(e.value) > e.valueError)) continue;
    if (e.value > 0) return false;
    if (glm::dot(e.gradient, n) < 0 && clearOf(e.gradient, gradientNoise(data, q))) return true;
  }
  return false;
}

// Back from the hit along the ray: grad f at the first point where it is clear and faces
// the ray (an even root, or an odd one crossing downwards), or, once f is found to change
// sign across the hit (an odd root, whose gradient keeps its orientation across the
// surface), at the first point where it is clear; once f is found negative on both sides
// (an even root of f <= 0: -h^2, h^2 q with q < 0, whose gradient before the hit faces
// away), grad(-f) at the first clear one, facing the ray as every even root's; else
// `fallback`. Each with its mirror point after the hit (symmetric). (Before the last rule
// such roots kept a noise-oriented gradient: half of the hits on 0 = (x^2 + y^2 + z^2 -
// 1)^2 faced away, some 70 degrees off.)
glm::dvec3 searchBefore(const SurfaceData& data, const glm::dvec3& u, const glm::dvec3& point,
                        const glm::dvec3& fallback) {
  int clearRung = -1;
  glm::dvec3 firstClear{0.0};
  bool negativeBefore = false, negativeBoth = false, opposite = false, sameSign = false;
  for (int k = 0; k < kSearchRungs; ++k) {
    const double delta = rung(data, k);
    const glm::dvec3 before = point - delta * u;
    // Past 2^-6 radii (far): inside the clip ball only, and a sign change across the hit
    // after f had one sign on both sides at a nearer rung (sameSign) ends the search
    // instead of deciding it: that is another sheet of f crossed, not this one (348 of 400
    // normals of h^6 (0.95 - x^2 - y^2 - z^2) reversed so); an odd h^7, within its noise
    // out to the far rungs, still changes sign there first.
    const bool far = k >= kRungs;
    if (far && !inClipBall(data, before)) break;
    const Polynomial::Evaluation e = data.horner.evaluate(before);
    const glm::dvec3 noise = gradientNoise(data, before);
    if (clearOf(e.gradient, noise)) {
      if (facingOf(e.gradient, noise, u)) return symmetric(data, u, point, delta, e.gradient, true);
      if (clearRung < 0) {
        firstClear = e.gradient;
        clearRung = k;
      }
    }
    if (!(std::abs(e.value) > e.valueError)) continue;
    if (clearRung < 0) {
      // No clear gradient yet, but f clear: one sign on both sides here makes a farther
      // sign change another sheet's (sameSign).
      if (!far) {
        const Polynomial::Evaluation after = data.horner.evaluate(point + delta * u);
        sameSign |= std::abs(after.value) > after.valueError && (e.value < 0) == (after.value < 0);
      }
      continue;
    }
    negativeBefore |= e.value < 0;
    const glm::dvec3 q = point + delta * u;
    if (far && !inClipBall(data, q)) break;
    const Polynomial::Evaluation after = data.horner.evaluate(q);
    if (!(std::abs(after.value) > after.valueError)) continue;
    if ((e.value < 0) != (after.value < 0)) {
      // After f was negative on both sides with opposite gradients at a nearer rung (an even
      // root of f <= 0), a sign change is another sheet of f crossed, at any rung: on
      // (x^2+y^2+z^2-1)^2 (x - 1.02) seen from inside in a clip sphere of radius 2, the plane
      // 0.012 radii past the +x cap turned 1000 of 1000 normals there away from the ray.
      if ((far && sameSign) || (negativeBoth && opposite)) break;
      return symmetric(data, u, point, rung(data, clearRung), firstClear, false);
    }
    sameSign = true;
    negativeBoth |= e.value < 0;
    // The gradients on the two sides opposite, as where h changes sign across an even
    // surface, at any rung: the hit of h^m, m >= 4, lies up to ~u^(1/m) before the surface
    // (6e-4 radii on -(x^2 + y^2 + z^2 - 1)^4), so at the first clear rung both points may
    // still lie before it, their gradients alike (session 43: that rung alone reversed 63
    // of 1600 normals of -h^6 and 1285 of -h^8).
    opposite |= glm::dot(e.gradient, after.gradient) < 0 && clearOf(e.gradient, noise) &&
                clearOf(after.gradient, gradientNoise(data, q));
    // Decided (below) once the first 2^-6 radii are seen, before the farther rungs, where
    // other parts of the surface come into view (a torus's far side of its tube faced the
    // ray 0.4 radii back, and was taken for the normal of a grazed -T^2).
    if (k >= kRungs - 1 && negativeBoth && opposite) break;
  }
  // Negative on both sides and no sign change out to the last rung (not decided at the
  // first rung with both clear: an odd root's hit lies anywhere in its noise region, up to
  // ~1e-4 radii before the crossing, and f can be clearly negative between the two), and
  // the gradients on the two sides opposite at some rung: an even root of f <= 0. With
  // them alike, or f negative before the hit and within its noise after it at every rung,
  // the ray touches or grazes the surface from one side (the crossing, if any, beyond the
  // rungs or the noise: the audit's ray (0.99, 0, -3) + t (0, 0, 1) on -(x^2 + y^2 + z^2 -
  // 1)^8, whose whole chord inside the sphere lies within f's noise): f = h^3 q touched
  // from h <= 0 keeps the surface's own orientation, the fallback (StressRandom.Multiple-
  // SurfacesGetTheirOwnNormal with other seeds), -h^4 touched from h >= 0 is an even root
  // and takes grad(-f), facing the ray's side; evenAcross tells them apart across the
  // surface.
  if ((negativeBoth && opposite) || (negativeBefore && evenAcross(data, point, firstClear)))
    return symmetric(data, u, point, rung(data, clearRung), -firstClear, true, -1);
  return fallback;
}

// The sign of the first value of f clear of its noise at p - delta u over the rungs: -1,
// 1, or 0 where none is.
int signBefore(const SurfaceData& data, const glm::dvec3& u, const glm::dvec3& point) {
  for (int k = 0; k < kRungs; ++k) {
    const Polynomial::Evaluation e = data.horner.evaluate(point - rung(data, k) * u);
    if (std::abs(e.value) > e.valueError) return e.value < 0 ? -1 : 1;
  }
  return 0;
}

// Whether f is clearly positive at some p + delta u of the rungs after the hit.
bool positiveAfter(const SurfaceData& data, const glm::dvec3& u, const glm::dvec3& point) {
  for (int k = 0; k < kRungs; ++k) {
    const Polynomial::Evaluation e = data.horner.evaluate(point + rung(data, k) * u);
    if (e.value > e.valueError) return true;
  }
  return false;
}

}  // namespace

glm::dvec3 gradientBesideNoise(const SurfaceData& data, const glm::dvec3& dir,
                               const glm::dvec3& point, const glm::dvec3& gradient,
                               double pointError) {
  const double length = glm::length(dir);
  if (!(length > 0.0) || !std::isfinite(length)) return gradient;
  const glm::dvec3 u = dir / length;
  // ---- The gradient at the hit, where it is clear ----------------------------------------
  // Its noise: the evaluation's, and how far the point's own rounding can move it (a hit
  // from far away, hitPointError).
  // Facing the ray it is right for either parity. Across the ray (to 2^-20 radians) it is a
  // ray touching a simple surface, whose normal it is (before, the search below took the
  // gradients before and after such a hit, on the same side of the surface, for an even
  // root's and returned their difference, along the ray: a sphere touched by a ray got the
  // ray's direction as its normal, a torus's top 63 degrees off; a touching hit farther
  // from the point it touches goes to the search, whose mirrored pair then averages). Not
  // every gradient within noise of across the ray: a double surface's, just clear at a hit
  // past it, can be that at a shallow angle, and must be turned to face the ray.
  // Facing away, it is an odd root's crossing upwards (f < 0 before the hit, > 0 after it)
  // or an even root's far side (f > 0 on both sides, the hit past the surface; or f < 0 on
  // both, the near side of an even root of f <= 0): the first clear value of f before the
  // hit, and whether f is clearly positive anywhere after it out to 2^-6 clip radii, tell.
  // (The hit of a multiple root lies anywhere in its noise region: a triple root's up to
  // 1e-4 before the crossing, where its gradient is clear and right, and f can be clearly
  // negative between the hit and the crossing.)
  const glm::dvec3 noise =
      gradientNoise(data, point) + glm::dvec3(data.hitPointNoise * 0x1p-10 * pointError);
  if (clearOf(gradient, noise)) {
    if (facingOf(gradient, noise, u)) return gradient;
    if (std::abs(glm::dot(gradient, u)) <= 0x1p-20 * glm::length(gradient)) return gradient;
    const int before = signBefore(data, u, point);
    if (before > 0 || (before < 0 && !positiveAfter(data, u, point)))
      return searchBefore(data, u, point, gradient);
    return gradient;
  }
  const glm::dvec3 found = searchBefore(data, u, point, gradient);
  // ---- The hit's own gradient bounds the answer ------------------------------------------
  // The exact grad f at the hit lies within `noise` of the computed one: where that cone is
  // narrower than a right angle and the gradient found beside the hit lies outside it, the
  // search went too far for the normal there (near a singular curve of h, where the normal
  // turns within the search's distance): the hit's own gradient, oriented as the one found.
  const double cone = glm::length(noise) / glm::length(gradient);
  if (!(cone < 0.5)) return found;
  const double cosine = glm::dot(found, gradient) / (glm::length(found) * glm::length(gradient));
  if (std::abs(cosine) >= std::sqrt(1.0 - cone * cone)) return found;
  return cosine < 0 ? -gradient : gradient;
}

}  // namespace algray
