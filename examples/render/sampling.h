#pragma once
// Random numbers and the warps from [0,1)^2 to directions that the integrators use.
// References: pbrt-v4 (Pharr, Jakob, Humphreys), Sec. A.5 (sampling) and B.2 (frames);
// O'Neill, "PCG: A Family of Simple Fast Space-Efficient Statistically Good Algorithms
// for Random Number Generation" (2014) for the generator.
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace algray::render {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kInvPi = std::numbers::inv_pi;

// 64-bit finaliser of MurmurHash3 (Appleby): decorrelates pixel index and seed so that
// neighbouring pixels get unrelated streams.
constexpr std::uint64_t mixBits(std::uint64_t v) {
  v ^= v >> 33;
  v *= 0xff51afd7ed558ccdULL;
  v ^= v >> 33;
  v *= 0xc4ceb9fe1a85ec53ULL;
  v ^= v >> 33;
  return v;
}

// PCG32 (XSH RR variant). One generator per pixel, seeded from (pixel, user seed): the
// image does not depend on which thread renders which tile.
class Rng {
 public:
  Rng(std::uint64_t sequence, std::uint64_t seed) {
    state_ = 0;
    inc_ = (sequence << 1u) | 1u;
    nextU32();
    state_ += mixBits(seed);
    nextU32();
  }
  std::uint32_t nextU32() {
    std::uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
  }
  // Uniform in [0, 1): 53 random bits from two draws, so never exactly 1.
  double uniform() {
    std::uint64_t hi = nextU32() >> 5, lo = nextU32() >> 6;  // 27 + 26 bits
    return static_cast<double>((hi << 26) | lo) * 0x1p-53;
  }
  glm::dvec2 uniform2() {
    double a = uniform();
    return {a, uniform()};
  }

 private:
  std::uint64_t state_;
  std::uint64_t inc_;
};

// Orthonormal basis around a unit normal without branches on the axis: Duff et al.,
// "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017, Listing 3.
struct Frame {
  glm::dvec3 s, t, n;
  explicit Frame(const glm::dvec3& normal) : n(normal) {
    double sign = std::copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double b = n.x * n.y * a;
    s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
  }
  glm::dvec3 toLocal(const glm::dvec3& v) const {
    return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)};
  }
  glm::dvec3 toWorld(const glm::dvec3& v) const { return v.x * s + v.y * t + v.z * n; }
};

// Concentric map of the square to the disk (Shirley and Chiu 1997), pbrt-v4 A.5.1.
inline glm::dvec2 sampleUniformDisk(glm::dvec2 u) {
  glm::dvec2 o = 2.0 * u - 1.0;
  if (o.x == 0 && o.y == 0) return {0, 0};
  double r, theta;
  if (std::abs(o.x) > std::abs(o.y)) {
    r = o.x;
    theta = kPi / 4 * (o.y / o.x);
  } else {
    r = o.y;
    theta = kPi / 2 - kPi / 4 * (o.x / o.y);
  }
  return r * glm::dvec2(std::cos(theta), std::sin(theta));
}

// Malley's method: cosine-weighted hemisphere about +z, pdf = cos(theta)/pi.
inline glm::dvec3 sampleCosineHemisphere(glm::dvec2 u) {
  glm::dvec2 d = sampleUniformDisk(u);
  double z = std::sqrt(std::max(0.0, 1.0 - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}

// Uniform direction on the sphere, pdf = 1/(4 pi).
inline glm::dvec3 sampleUniformSphere(glm::dvec2 u) {
  double z = 1.0 - 2.0 * u.x;
  double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  double phi = 2.0 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr double kUniformSpherePdf = 1.0 / (4.0 * std::numbers::pi);

// Uniform point on a triangle as barycentrics (b1, b2): pbrt-v4 Sec. 6.5.4.
inline glm::dvec2 sampleUniformTriangle(glm::dvec2 u) {
  double su = std::sqrt(u.x);
  return {1.0 - su, u.y * su};
}

// Veach's power heuristic with beta = 2 (thesis, Sec. 9.2.4).
inline double powerHeuristic(double pdfA, double pdfB) {
  double a = pdfA * pdfA, b = pdfB * pdfB;
  if (std::isinf(a)) return 1.0;
  return a + b > 0 ? a / (a + b) : 0.0;
}

inline double luminance(const glm::dvec3& c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;  // Rec. 709 weights
}

}  // namespace algray::render
