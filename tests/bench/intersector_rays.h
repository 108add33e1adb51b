#pragma once
// Fixed ray sets for tests/bench/intersector_report.cpp, built without the library's
// intersector: a camera's primary rays, shadow rays from their *reference* hits, grazing
// rays along tangent planes at reference hits, rays aimed at singular points that are
// verified from the polynomial itself, and rays from 10^3 and 10^6 clip radii away.
#include "algray/embree.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "../support/reference.h"

namespace algray::bench {

enum class RayClass { Primary, Shadow, Grazing, Singular, Far1e3, Far1e6 };
inline constexpr RayClass kRayClasses[] = {RayClass::Primary,  RayClass::Shadow, RayClass::Grazing,
                                           RayClass::Singular, RayClass::Far1e3, RayClass::Far1e6};
inline const char* className(RayClass c) {
  switch (c) {
    case RayClass::Primary:
      return "primary";
    case RayClass::Shadow:
      return "shadow";
    case RayClass::Grazing:
      return "grazing";
    case RayClass::Singular:
      return "singular";
    case RayClass::Far1e3:
      return "far1e3";
    case RayClass::Far1e6:
      return "far1e6";
  }
  return "?";
}

// A ray with its reference answer. refTnear is the start of the reference search: the
// ray's tnear, or for a shadow ray 1e-6 clip radii past its origin (the root at the
// origin itself is the self-intersection the library must skip).
// selfClean: for a shadow ray, the reference over (-1e-6, 1e-6) radii about the origin
// finds exactly one simple, well-separated root (the origin's own); otherwise the origin
// sits where two sheets cross (a double line, a node) and a hit right at the origin is a
// true intersection, not a speckle, so the ray is neither scored nor counted as a speckle.
struct BenchRay {
  RayD ray;
  double refTnear = 0;
  test::RayRef ref;
  bool selfClean = true;
  // Singular rays whose node (at t = 1) is the first intersection, by the reference (no
  // root and no near-tangency in (0, 1 - 1e-4)): the node is the expected hit.
  bool nodeFirst = false;
};

struct RaySets {
  std::vector<BenchRay> sets[6];
  std::vector<BenchRay>& operator[](RayClass c) { return sets[static_cast<int>(c)]; }
  const std::vector<BenchRay>& operator[](RayClass c) const { return sets[static_cast<int>(c)]; }
};

// ---- Singular points ----------------------------------------------------------------
// Candidates from the classic constructions, kept only where f and grad f vanish to
// rounding (checked on the polynomial, so a candidate that is not a node of this surface
// is dropped whatever its name):
//  * the origin, points on the coordinate axes (double lines of Steiner's Roman surface),
//    (0, 0, +-1) (Taubin's heart);
//  * (+-1, +-1, +-1) (Cayley's cubic in the SURFER form);
//  * Barth's sextic: the 6 axis points (+-1, 0, 0)... and the 24 points of the unit sphere
//    where two of the factors phi^2 x^2 - y^2, ... vanish (there the product and its
//    gradient vanish, and so does (r^2 - 1)^2 with its gradient);
//  * Kummer's quartic: the 12 nodes on the edges of the tetrahedron p q r s = 0 where the
//    edge meets the sphere r^2 = mu^2 (p q r s vanishes to second order along an edge);
//  * Chmutov's T_n(x) + T_n(y) + T_n(z) + 1: x, y, z at extrema cos(k pi / n) of T_n with
//    values (-1, -1, +1) in some order.
inline bool isSingular(const Polynomial& f, const glm::dvec3& x, double radius) {
  // The scale: |terms| at a point a little farther out than x in every coordinate (at x
  // itself every term may vanish, as on the axes of the Roman surface).
  const double s = test::absTermSum(f, glm::abs(x) + glm::dvec3(0.1 * radius));
  if (!(s > 0)) return false;
  return std::abs(f.evaluate(x)) <= 1e-12 * s && glm::length(f.gradient(x)) * radius <= 1e-7 * s;
}

inline std::vector<glm::dvec3> singularPoints(const Polynomial& f, double radius) {
  std::vector<glm::dvec3> cand = {glm::dvec3(0.0), {0, 0, 1}, {0, 0, -1}};
  for (double a : {0.1, -0.25, 0.4})
    for (int ax = 0; ax < 3; ++ax) {
      glm::dvec3 p(0.0);
      p[ax] = a;
      cand.push_back(p);
    }
  for (int s = 0; s < 8; ++s)
    cand.push_back({s & 1 ? -1.0 : 1.0, s & 2 ? -1.0 : 1.0, s & 4 ? -1.0 : 1.0});
  // Barth's sextic.
  const double phi = std::numbers::phi, p2 = phi * phi;
  for (int ax = 0; ax < 3; ++ax)
    for (double sg : {1.0, -1.0}) {
      glm::dvec3 p(0.0);
      p[ax] = sg;
      cand.push_back(p);
    }
  const glm::dvec3 base[3] = {{1.0, phi, p2}, {p2, 1.0, phi}, {1.0, phi, 1.0 / phi}};
  for (glm::dvec3 b : base) {
    b /= glm::length(b);
    for (int s = 0; s < 8; ++s)
      cand.push_back({s & 1 ? -b.x : b.x, s & 2 ? -b.y : b.y, s & 4 ? -b.z : b.z});
  }
  // Kummer's quartic (SURFER's mu^2 = 1.69).
  if (f.degree() == 4) {
    const double sq2 = std::numbers::sqrt2;
    const glm::dvec3 n[4] = {{sq2, 0, 1}, {-sq2, 0, 1}, {0, sq2, 1}, {0, -sq2, 1}};
    const double c[4] = {1, 1, -1, -1};  // planes n . x = c
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const glm::dvec3 e = glm::normalize(glm::cross(n[i], n[j]));
        // A point of the line: least-norm solution of the two plane equations.
        const double g11 = glm::dot(n[i], n[i]), g12 = glm::dot(n[i], n[j]),
                     g22 = glm::dot(n[j], n[j]);
        const double det = g11 * g22 - g12 * g12;
        const double a = (c[i] * g22 - c[j] * g12) / det, b = (c[j] * g11 - c[i] * g12) / det;
        const glm::dvec3 x0 = a * n[i] + b * n[j];
        // Nodes at |x0 + t e|^2 = mu^2 (a quartic of another form fails the check below).
        const double mu2 = 1.69, h = mu2 - glm::dot(x0, x0);
        if (h < 0) continue;
        for (double sg : {1.0, -1.0}) cand.push_back(x0 + sg * std::sqrt(h) * e);
      }
  }
  // Chmutov.
  const int m = f.degree();
  if (m >= 2) {
    std::vector<double> minus, plus;
    for (int k = 1; k < m; ++k)
      (k % 2 ? minus : plus).push_back(std::cos(k * std::numbers::pi / m));
    for (size_t i = 0; i < std::min<size_t>(minus.size(), 3); ++i)
      for (size_t j = 0; j < std::min<size_t>(plus.size(), 3); ++j) {
        cand.push_back({minus[i], minus[minus.size() - 1 - i], plus[j]});
        cand.push_back({plus[j], minus[i], minus[(i + 1) % minus.size()]});
      }
  }
  std::vector<glm::dvec3> out;
  for (const glm::dvec3& p : cand)
    if (glm::length(p) < 0.9 * radius && isSingular(f, p, radius)) out.push_back(p);
  return out;
}

// ---- Ray sets -------------------------------------------------------------------------
struct RaySetSizes {
  int camera = 24;     // camera x camera primary rays
  int grazing = 160;   // at most this many grazing rays
  int singular = 120;  // rays aimed at singular points (spread over the points found)
  int far = 160;       // per distance
};

// Direction of a primary ray: a pinhole camera 3.2 radii away looking at the centre,
// framing the clip sphere.
inline glm::dvec3 cameraEye(double radius) {
  return 3.2 * radius * glm::normalize(glm::dvec3(1.0, 0.75, 0.55));
}
inline glm::dvec3 lightPosition(double radius) {
  return 4.0 * radius * glm::normalize(glm::dvec3(-0.5, 0.9, 1.0));
}

template <class Rng>
glm::dvec3 randomUnit(Rng& rng) {
  std::normal_distribution<double> normal;
  for (;;) {
    const glm::dvec3 v{normal(rng), normal(rng), normal(rng)};
    const double l = glm::length(v);
    if (l > 1e-3) return v / l;
  }
}

inline RayD makeRay(const glm::dvec3& o, const glm::dvec3& d, double tnear = 0.0,
                    double tfar = std::numeric_limits<double>::infinity()) {
  return RayD{o, d, tnear, tfar};
}

// Computes the primary rays' references first (shadow and grazing rays start from their
// hits), then every other reference; `parallel` runs a loop body over an index range.
template <class Parallel>
RaySets buildRaySets(const Polynomial& f, double radius, const RaySetSizes& n, unsigned seed,
                     Parallel parallel) {
  RaySets sets;
  const glm::dvec3 centre(0.0);
  auto solve = [&](std::vector<BenchRay>& rays) {
    parallel(rays.size(), [&](size_t i) {
      BenchRay& b = rays[i];
      b.ref =
          test::referenceFirstHit(f, b.ray.org, b.ray.dir, b.refTnear, b.ray.tfar, centre, radius);
      if (b.refTnear > b.ray.tnear) {
        const test::RayRef self = test::referenceFirstHit(f, b.ray.org, b.ray.dir, -b.refTnear,
                                                          b.refTnear, centre, radius);
        b.selfClean = self.hit && self.roots == 1 && self.wellConditioned;
        if (!b.selfClean) b.ref.wellConditioned = false;
      }
    });
  };
  // ---- Primary ----------------------------------------------------------------------
  const glm::dvec3 eye = cameraEye(radius);
  const glm::dvec3 fwd = glm::normalize(centre - eye);
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(0, 0, 1)));
  const glm::dvec3 up = glm::cross(right, fwd);
  for (int j = 0; j < n.camera; ++j)
    for (int i = 0; i < n.camera; ++i) {
      const double u = (2.0 * (i + 0.5) / n.camera - 1.0) * 1.05 * radius;
      const double v = (2.0 * (j + 0.5) / n.camera - 1.0) * 1.05 * radius;
      const glm::dvec3 target = centre + u * right + v * up;
      BenchRay b;
      b.ray = makeRay(eye, glm::normalize(target - eye));
      sets[RayClass::Primary].push_back(b);
    }
  solve(sets[RayClass::Primary]);

  // ---- Shadow: from the reference hit (rounded to double) to the light ---------------
  std::mt19937_64 rng(seed);
  const glm::dvec3 light = lightPosition(radius);
  std::vector<glm::dvec3> hits;
  for (const BenchRay& p : sets[RayClass::Primary])
    if (p.ref.hit) hits.push_back(p.ref.point);
  for (const glm::dvec3& p : hits) {
    BenchRay b;
    b.ray = makeRay(p, light - p, 0.0, 1.0);
    b.refTnear = 1e-6 * radius / glm::length(light - p);
    sets[RayClass::Shadow].push_back(b);
  }
  // ---- Grazing: along a tangent plane at a reference hit, offset along the normal by
  // 0 or +-1e-12 ... +-1e-3 radii (a touching ray, a near miss, a close root pair) --------
  const double offsets[] = {0.0, 1e-12, -1e-12, 1e-9, -1e-9, 1e-6, -1e-6, 1e-3, -1e-3};
  for (size_t k = 0;
       k < hits.size() && static_cast<int>(sets[RayClass::Grazing].size()) < n.grazing; ++k) {
    const glm::dvec3 p = hits[(k * 7919) % hits.size()];
    const glm::dvec3 g = f.gradient(p);
    if (!(glm::length(g) > 0.0)) continue;
    const glm::dvec3 nrm = glm::normalize(g);
    const glm::dvec3 w = randomUnit(rng);
    const glm::dvec3 tan = w - glm::dot(w, nrm) * nrm;
    if (!(glm::length(tan) > 1e-3)) continue;
    const glm::dvec3 dir = glm::normalize(tan);
    const double off = offsets[k % std::size(offsets)] * radius;
    BenchRay b;
    b.ray = makeRay(p + off * nrm - 1.5 * radius * dir, dir);
    sets[RayClass::Grazing].push_back(b);
  }
  // ---- Singular: aimed exactly at a verified singular point (at t = 1) ----------------
  const std::vector<glm::dvec3> nodes = singularPoints(f, radius);
  for (int k = 0; !nodes.empty() && k < n.singular; ++k) {
    const glm::dvec3 node = nodes[k % nodes.size()];
    const glm::dvec3 o = node + 2.0 * radius * randomUnit(rng);
    BenchRay b;
    b.ray = makeRay(o, node - o);
    sets[RayClass::Singular].push_back(b);
  }
  // ---- Far: origins 1e3 and 1e6 radii away, aimed into the clip ball ----------------------
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (RayClass c : {RayClass::Far1e3, RayClass::Far1e6}) {
    const double dist = (c == RayClass::Far1e3 ? 1e3 : 1e6) * radius;
    for (int k = 0; k < n.far; ++k) {
      const glm::dvec3 o = centre + dist * randomUnit(rng);
      const glm::dvec3 target = centre + 0.7 * radius * std::cbrt(unit(rng)) * randomUnit(rng);
      BenchRay b;
      b.ray = makeRay(o, glm::normalize(target - o));
      sets[c].push_back(b);
    }
  }
  for (RayClass c : {RayClass::Shadow, RayClass::Grazing, RayClass::Singular, RayClass::Far1e3,
                     RayClass::Far1e6})
    solve(sets[c]);
  auto& singular = sets[RayClass::Singular];
  parallel(singular.size(), [&](size_t i) {
    BenchRay& b = singular[i];
    const test::RayRef before =
        test::referenceFirstHit(f, b.ray.org, b.ray.dir, 0.0, 1.0 - 1e-4, centre, radius);
    b.nodeFirst = !before.hit && before.wellConditioned;
  });
  return sets;
}

}  // namespace algray::bench
