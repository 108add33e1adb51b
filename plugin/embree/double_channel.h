#pragma once
// What the bridge (embree_bridge.cpp: the callbacks) and the double channel's host side
// (double_channel.cpp: the context and its float proxy ray) share: the marker that makes a
// context algray's, and the error-free steps along a line with which both move far origins
// (the bridge's rebaseFarOrigin, the proxy's floatMap).
#include "algray/embree.h"

#include <glm/vec3.hpp>

#include <cmath>
#include <limits>

namespace algray {

// The context filter that marks an IntersectContext (defined in the bridge, which compares
// contexts against it on every call).
void markerFilter(const RTCFilterFunctionNArguments* args);

// Each move gains ~16 digits (u): 20 bring any finite origin from 1e308 to the surface.
inline constexpr int kMaxMoves = 24;

// o + t d with error-free transformations (the product's error by FMA, the sum's by Knuth's
// TwoSum; Ogita, Rump and Oishi, "Accurate sum and dot product", SIAM J. Sci. Comput. 26,
// 2005): the point stays on the line to u |p| + u^2 |t d|.
inline glm::dvec3 pointOnLine(const glm::dvec3& o, const glm::dvec3& d, double t) {
  glm::dvec3 p;
  for (int i = 0; i < 3; ++i) {
    const double prod = t * d[i], prodErr = std::fma(t, d[i], -prod);
    const double sum = o[i] + prod, bv = sum - o[i], sumErr = (o[i] - (sum - bv)) + (prod - bv);
    p[i] = sum + (prodErr + sumErr);
  }
  return p;
}

// hi + low += t, exactly (Knuth's TwoSum; the low parts rounded once more).
inline void addExact(double& hi, double& low, double t) {
  const double sum = hi + t, bv = sum - hi;
  low += (hi - (sum - bv)) + (t - bv);
  hi = sum;
}

// The float tfar Embree keeps must not be below the double hit (it culls the traversal of
// farther boxes); round up.
inline float roundUp(double t) {
  const float f = static_cast<float>(t);
  return static_cast<double>(f) < t ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

}  // namespace algray
