#pragma once
// Values rounded to float, as doubles: the numbers float data or a float ray hold, for
// tests and benchmarks that give the double and float channels the same input.
//
// Through volatile floats. GCC 12.2 (Debian bookworm's) at -O2 and above miscompiles the
// plain round trip where its SLP vectoriser pairs two of them, as in
// glm::dvec3(glm::vec3(v)) or the two ends of an interval: its FRE pass then folds the
// vector (double)(float) conversion pair into the identity, and the "float" values keep
// all 53 bits (session 27, reduced from roots_report, whose float rows were solved on
// float(hi) but scored on the double hi; FloatValues.BenchIntervalEndsAreFloats and
// FloatValues.VectorComponentsAreFloats fail with the plain casts).
#include <glm/vec3.hpp>

namespace algray::test {

inline double floatValue(double x) {
  volatile float f = static_cast<float>(x);
  return f;
}

inline glm::dvec3 floatValues(const glm::dvec3& v) {
  return {floatValue(v.x), floatValue(v.y), floatValue(v.z)};
}

}  // namespace algray::test
