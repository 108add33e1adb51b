#pragma once
// Range checks shared by the scene loaders (JSON, jsurf), the camera and the scene, so that
// every loader refuses the same values with its own location and the renderer never
// meets them.
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace algray::render {

// Largest magnitude of a position-like value (camera position, light position, lens
// radius, orthographic height, clip region). Embree's rays are float and valid only
// within +-1.8e18 per component (FLT_LARGE; beyond it Embree aborts on an assertion);
// 1e17 leaves a factor 18 for the film and the rays built from these values.
inline constexpr double kMaxCoordinate = 1e17;

// Smallest extent of a triangle mesh in scene space. Embree's float triangle test forms
// products of edge vectors (size s^2 for a mesh of size s): below s ~ 1e-19 they leave
// float's normal range and the mesh covers the wrong pixels (measured: a plane of size
// 1e-19 covered 5.5 % of the image instead of 2.2 %, of 1e-20 none; 1e-18 was still right).
// 1e-15 keeps a margin of 1000.
inline constexpr double kMinMeshExtent = 1e-15;

inline bool withinCoordinateRange(double v) { return std::abs(v) <= kMaxCoordinate; }
inline bool withinCoordinateRange(const glm::dvec3& v) {
  return withinCoordinateRange(v.x) && withinCoordinateRange(v.y) && withinCoordinateRange(v.z);
}

// v / |v|, or nothing when v is zero or not finite. glm::normalize squares the components:
// |v| overflows to inf beyond ~1e154 and underflows to 0 below ~1e-154 (NaN either way),
// so v is scaled by its largest component first.
inline std::optional<glm::dvec3> safeNormalize(const glm::dvec3& v) {
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return std::nullopt;
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0)) return std::nullopt;
  const glm::dvec3 u = v / m;
  return u / glm::length(u);
}

// A colour, radiance or intensity: the image is float, so every component must be finite
// in float (a double beyond 3.4e38 becomes inf there) and not negative.
inline bool isFloatColor(const glm::dvec3& c) {
  constexpr double kMax = std::numeric_limits<float>::max();
  for (int i = 0; i < 3; ++i)
    if (!(c[i] >= 0 && c[i] <= kMax)) return false;
  return true;
}

}  // namespace algray::render
