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

// a b - fl(a b) exactly (Dekker's TwoProduct). std::fma is one instruction where the
// build targets FMA and a library call otherwise, which glibc serves in software on CPUs
// without FMA (195 ns a call measured against 11.6 with it: rays re-centred about a point
// that cancels took 2.3-2.7x as long, restrictAbout). So without __FMA__, Veltkamp's
// splitting (no contraction: -ffp-contract=off), exact while no step overflows or
// underflows (operands below 2^995, the product between 2^-900 and 2^1023); std::fma
// outside that range.
inline double productError(double a, double b, double prod) {
#if defined(__FMA__)
  return std::fma(a, b, -prod);
#else
  if (a == 0.0 || b == 0.0) return 0.0;  // as fma's (+-0) - (+-0) (axis-aligned directions)
  if (!(std::abs(a) < 0x1p995 && std::abs(b) < 0x1p995 && std::abs(prod) < 0x1p1023 &&
        std::abs(prod) >= 0x1p-900)) [[unlikely]]
    return std::fma(a, b, -prod);
  constexpr double kSplit = 0x1p27 + 1.0;
  const double ca = kSplit * a, aHi = ca - (ca - a), aLo = a - aHi;
  const double cb = kSplit * b, bHi = cb - (cb - b), bLo = b - bHi;
  return ((aHi * bHi - prod) + aHi * bLo + aLo * bHi) + aLo * bLo;
#endif
}

// o + t d with error-free transformations (the product's error by TwoProduct, the sum's by
// Knuth's TwoSum; Ogita, Rump and Oishi, "Accurate sum and dot product", SIAM J. Sci.
// Comput. 26, 2005): the point stays on the line to u |p| + u^2 |t d|.
inline glm::dvec3 pointOnLine(const glm::dvec3& o, const glm::dvec3& d, double t) {
  glm::dvec3 p;
  for (int i = 0; i < 3; ++i) {
    const double prod = t * d[i], prodErr = productError(t, d[i], prod);
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
