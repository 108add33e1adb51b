#pragma once
// Whether an equation's surface is lost in rounding in its clip region. The parser expands
// an equation exactly as double allows, and one written about a point far from the origin
// cancels there: the torus ((x-1e4)^2+y^2+z^2+0.84)^2 = 4((x-1e4)^2+y^2) has terms near 1e17
// around x = 1e4 whose sum is the torus's values, of size 1, and its expanded coefficients
// hold no torus at all (session 54's audit: a disc the size of its clip sphere at 1e4, a
// blob at 3e3, nothing from 1e5 on, without a word). f is then within its own evaluation
// bound through much of the region, where a real surface is so only in a thin band around
// itself, which a lattice of points tells.
#include <algray/cells.h>
#include <algray/embree.h>
#include <algray/polynomial.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <variant>

namespace algray::cli {

// The fraction of the points of a 9 x 9 x 9 lattice over the box [lo, hi] (the points in the
// sphere, if given, as buildCells takes one) at which |f| is within its evaluation bound; 0
// where no point is inside. f is first scaled by a power of two (exactly) to a largest
// coefficient in [1, 2), as SurfaceGeometry scales what it traces: written as
// 1e300 * (x^2+y^2+z^2-1) in a clip sphere of 1e10, the unscaled f's values and bounds
// overflowed, it was "within its rounding error" at every point, and the tools warned of a
// surface they trace exactly. Not where a coefficient is subnormal: its digits were lost
// when it was rounded (1e-320 * (x^2+y^2+z^2-0.7) is a sphere 6e-5 too small), which the
// scaled f would hide and the unscaled f's underflow floors show.
inline double noiseFraction(Polynomial f, const glm::dvec3& lo, const glm::dvec3& hi,
                            const std::optional<CellSphere>& sphere = std::nullopt) {
  const auto c = f.coeffs();
  const bool subnormal =
      std::any_of(c.begin(), c.end(), [](double v) { return std::fpclassify(v) == FP_SUBNORMAL; });
  if (!subnormal && !f.isZero()) {
    const int e = std::ilogb(f.maxAbsCoeff());
    f *= std::ldexp(1.0, -e / 2);  // two halves: 2^-e alone may leave double's range
    f *= std::ldexp(1.0, -(e - e / 2));
  }
  constexpr int kSteps = 9;
  int inside = 0, noise = 0;
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j)
      for (int k = 0; k < kSteps; ++k) {
        // (Offsets that put no point on a plane of symmetry, where surfaces such as x y z
        // vanish exactly.)
        const glm::dvec3 u = (glm::dvec3(i, j, k) + glm::dvec3(0.37, 0.43, 0.29)) / double(kSteps);
        const glm::dvec3 p = lo + u * (hi - lo);
        if (sphere && glm::distance(p, sphere->center) > sphere->radius) continue;
        ++inside;
        const Polynomial::Evaluation e = f.evaluateWithBound(p);
        noise += std::abs(e.value) <= e.valueError;
      }
  return inside == 0 ? 0.0 : double(noise) / inside;
}

// The same over a surface's clip region (object space).
inline double noiseFraction(const Polynomial& f, const ClipRegion& clip) {
  if (const auto* s = std::get_if<ClipSphere>(&clip))
    return noiseFraction(f, s->center - s->radius, s->center + s->radius,
                         CellSphere{s->center, s->radius});
  const auto& b = std::get<ClipBox>(clip);
  return noiseFraction(f, b.lo, b.hi);
}

// Above this fraction the tools warn: a real surface's noise band holds a few per cent of a
// lattice at most (none of the gallery's 17 surfaces has a point in it; 1.3 % for the
// 7-fold sphere (x^2+y^2+z^2-1)^7); the torus above is at 0.3 % about x = 1e3, 11 % about
// 2e3, 41 % about 3e3 and 100 % from 1e4 on, the 20-fold sphere at 15 % (drawn 0.16 too
// large: its noise band is that wide).
inline constexpr double kNoiseWarning = 0.1;

// The warning's text after "LABEL: ", or empty below kNoiseWarning.
inline std::string noiseWarning(const Polynomial& f, const ClipRegion& clip) {
  const double fraction = noiseFraction(f, clip);
  if (!(fraction > kNoiseWarning)) return {};
  char percent[16];
  std::snprintf(percent, sizeof percent, "%.0f %%", 100.0 * fraction);
  return std::string("f is within its own rounding error at ") + percent +
         " of the points of its clip region, so hits there come from rounding noise, not "
         "from the surface (an equation written about a far point, such as (x-1e4)^2, loses its "
         "digits when expanded: write it about a point near the origin; a high power h^k of a "
         "factor is as noisy around h = 0)";
}

}  // namespace algray::cli
