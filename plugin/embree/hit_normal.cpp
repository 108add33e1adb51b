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
//  * on a ray grazing a simple surface, whose gradient is clear: the one found beside the
//    hit differs from it by about delta times the curvature (or is not found, below).
// There the normal is grad f at the nearest point p - delta d/|d| before the hit, delta
// from 2^-44 to 2^-10 clip radii by factors of 4, where grad f clears its noise 2^10-fold
// (so that rounding moves its direction by at most ~2^-10 radians) and either
//  * faces the ray, grad f . d < 0 clearly: an even root, f = h^2 q rising on both sides of
//    the surface, so grad f points to the side the ray comes from, as a simple surface's
//    normal does where the ray enters it; or
//  * f has clearly opposite signs at p - delta d and p + delta d: an odd root (h^3: grad f
//    keeps its orientation across the surface, and this is it).
// A grazing ray on a simple surface from its negative side meets neither (f < 0 on both
// sides, grad f facing away), and one touching a cone's apex from inside neither: the
// gradient at the hit stays (zero there: the bridge then reports the reversed ray
// direction). The search costs up to 36 evaluations of f, only on these hits (rendering
// (x^2 + y^2 + z^2 - 1)^2 took 0.21 s instead of 0.11; every other surface pays the slope
// test, measured in docs/speed-details.md, session 35). Measured accuracy: within 4e-6
// radians of grad h on double surfaces, 1.5e-3 on the triple sphere, whose gradient clears
// its noise only ~1e-5 from it (tests/embree_hits_test.cpp,
// EmbreeHits.MultipleSurfacesGetTheirOwnNormal).
#include "surface_data.h"

#include <cmath>

namespace algray {

glm::dvec3 gradientBesideNoise(const SurfaceData& data, const glm::dvec3& dir,
                               const glm::dvec3& point, const glm::dvec3& gradient) {
  const double length = glm::length(dir);
  if (!(length > 0.0) || !std::isfinite(length)) return gradient;
  const glm::dvec3 u = dir / length;
  const double l1 = std::abs(u.x) + std::abs(u.y) + std::abs(u.z);
  for (int k = 0; k <= 17; ++k) {
    const double delta = std::ldexp(data.radius, -44 + 2 * k);
    const glm::dvec3 before = point - delta * u;
    const Polynomial::Evaluation e = data.horner.evaluate(before);
    const double noise = gradientNoise(data, before);
    const glm::dvec3 a = absv(e.gradient);
    if (!(std::max({a.x, a.y, a.z}) > 0x1p10 * noise)) continue;
    // ---- An even root: grad f faces the ray ----------------------------------------------
    if (glm::dot(e.gradient, u) < -0x1p10 * noise * l1) return e.gradient;
    // ---- An odd root: f changes sign across the hit --------------------------------------
    if (!(std::abs(e.value) > e.valueError)) continue;
    const Polynomial::Evaluation after = data.horner.evaluate(point + delta * u);
    if (std::abs(after.value) > after.valueError && (e.value < 0) != (after.value < 0))
      return e.gradient;
  }
  return gradient;
}

}  // namespace algray
