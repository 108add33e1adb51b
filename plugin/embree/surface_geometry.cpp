// SurfaceGeometry: validates a SurfaceDesc, lays out the cells (Embree primitives) and
// their padded bounds, and creates the Embree user geometry (embree_bridge.cpp).
#include "quadric_path.h"

#include "algray/cells.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vector_relational.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

namespace algray {

// Defined in embree_bridge.cpp: the only place that knows the callback ABI.
RTCGeometry createUserGeometry(RTCDevice device, SurfaceData* data);

namespace {

std::string str(const glm::dvec3& v) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

std::string str(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

constexpr const char* kPrefix = "algray::SurfaceGeometry: ";

[[noreturn]] void fail(const std::string& what) { throw Error(kPrefix + what); }

// A measure of the description for a message: one beyond double's range has no value to
// print ("inf" or "-nan" said nothing: a clip box spanning more than 1.8e308, the
// condition number of a scale of 1e-300 against 1, whose inverse overflows).
void putMeasure(std::ostream& os, double v) {
  if (std::isfinite(v))
    os << v;
  else
    os << "beyond double's range";
}

// f and 2^k f have the same surface, and every computation of the kernels (restriction
// and its noise bounds, roots, self-root test, cell enclosures) is scaled exactly by a
// power of two as long as it stays in double's normal range. A polynomial whose largest
// coefficient lies far from 1 is therefore scaled to [1, 2) first: written as
// 1e-300 * (...), a torus's products with small powers of the ray fell below the normal
// range and 4 of 2000 hits moved by 1e-9 of the radius (their noise bounds no longer held),
// and 1e300 * (...) or 1e-200 * (...) traced 4x slower than the same torus unscaled.
// Within 2^-64 .. 2^64 nothing is scaled, so Ng stays grad f there (embree.h).
void normaliseScale(Polynomial& f) {
  const double largest = f.maxAbsCoeff();
  const int e = std::ilogb(largest);
  if (e >= -64 && e <= 64) return;
  f *= std::ldexp(1.0, -e / 2);  // two halves: 2^-e alone may leave double's range
  f *= std::ldexp(1.0, -(e - e / 2));
}

}  // namespace

ScaleError::ScaleError(const std::string& problem, const std::string& remedy)
    : Error(kPrefix + problem + ": " + remedy), problem_(problem) {}

namespace {

// ---- Validation ------------------------------------------------------------------------
void validate(const SurfaceDesc& desc) {
  const Polynomial& f = desc.polynomial;
  if (f.isZero()) fail("the polynomial is zero (every point would be on the surface)");
  if (!f.isFinite()) fail("the polynomial has a non-finite coefficient");
  if (f.degree() < 1) fail("the polynomial is a non-zero constant (the surface is empty)");
  // -1 is the automatic choice; other negative depths were taken for it and depths beyond
  // kMaxCellDepth silently capped: a caller's typo then builds something else than asked.
  if (desc.options.cellDepth < -1 || desc.options.cellDepth > kMaxCellDepth)
    fail("options.cellDepth must be -1 (automatic) or 0.." + std::to_string(kMaxCellDepth) +
         ", got " + std::to_string(desc.options.cellDepth));
  // The solver's options as firstRoot checks them (roots.h), here with the field's name
  // (in a callback the solver's Error would only count as a miss).
  if (const RootOptions& r = desc.options.roots; !validRootMethod(r.method))
    fail("options.roots.method " + std::to_string(static_cast<int>(r.method)) +
         " is not a RootMethod");
  else if (!validRelTolerance(r.relTolerance)) {
    std::ostringstream os;
    os << "options.roots.relTolerance must be in [0, 1], got " << r.relTolerance;
    fail(os.str());
  }
  double size = 0.0;  // of the clip region in object space
  if (const auto* s = std::get_if<ClipSphere>(&desc.clip)) {
    if (!finite(s->center)) fail("clip sphere centre is not finite: " + str(s->center));
    if (!(std::isfinite(s->radius) && s->radius > 0.0))
      fail("clip sphere radius must be finite and > 0, got " + std::to_string(s->radius));
    size = s->radius;
  } else {
    const auto& b = std::get<ClipBox>(desc.clip);
    if (!finite(b.lo) || !finite(b.hi))
      fail("clip box is not finite: " + str(b.lo) + " " + str(b.hi));
    if (!(b.lo.x < b.hi.x && b.lo.y < b.hi.y && b.lo.z < b.hi.z))
      fail("clip box is empty (need lo < hi on every axis): " + str(b.lo) + " " + str(b.hi));
    size = std::max({b.hi.x - b.lo.x, b.hi.y - b.lo.y, b.hi.z - b.lo.z});
  }
  // Object space far from unit size, reachable only through a transform that undoes it
  // (the world is held to Embree's range below): the kernels' products of coefficients,
  // directions and error bounds leave double's range from ~1e+-104 on (a unit sphere
  // drawn as x^2+y^2+z^2-1e-220 under a scale of 1e110 was missed by every ray).
  // Measured working to 1e+-100 (a sphere's clip radius of 1.5e+-100); refused beyond,
  // with the remedy.
  if (!(size >= 1e-100 && size <= 1e100)) {
    std::ostringstream os;
    os << "the clip region's size in object space is ";
    putMeasure(os, size);
    os << ", outside 1e-100 .. 1e100";
    throw ScaleError(os.str(),
                     "scale the polynomial's variables instead of undoing it by the transform");
  }
  // A polynomial of degree m over a region of size R spreads its coefficients over about R^m
  // (x^20 + y^20 + z^20 - R^20), and once scaled (normaliseScale) the small ones, times the
  // ray's powers, reach double's underflow floor, whose bound then swallows them: from R^m
  // ~ 1e+-290 on rays missed or hit inside the surface (degree 20 at R = 6e14, 40 at 2e7 and
  // 3e-8, 30 at 1e10; right at 4e14, 1.5e7 and 5e-8). Refused from 1e+-250 on, with the
  // remedy that works at any scale.
  if (const double exponent = f.degree() * std::log10(size); std::abs(exponent) > 250.0) {
    std::ostringstream os;
    os << "the clip region's size in object space (" << size << ") to the polynomial's degree ("
       << f.degree() << ") is about 1e" << std::lround(exponent)
       << ", outside 1e-250 .. 1e250, where its coefficients leave double's range";
    throw ScaleError(os.str(),
                     "write the polynomial in units of about the surface's size and put the "
                     "scale in the transform");
  }
  const glm::dmat4& m = desc.transform;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) fail("the transform has a non-finite entry");
  if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
    fail("the transform is not affine (last row must be 0 0 0 1)");
  // Singular relative to its own scale: |det A| against the product of the column
  // lengths (Hadamard's bound), so that a uniformly tiny but well-shaped transform passes.
  // Each column is first scaled by a power of two to a largest entry in [1, 2): the ratio
  // does not change, and neither product over- or underflows (a scale of 1e200 or 1e-110
  // was called singular).
  glm::dmat3 a(m);
  for (int c = 0; c < 3; ++c) {
    const double mc = std::max({std::abs(a[c].x), std::abs(a[c].y), std::abs(a[c].z)});
    if (!(mc > 0.0)) fail("the transform is singular (column " + std::to_string(c) + " is zero)");
    const int e = std::ilogb(mc);
    a[c] = glm::dvec3(std::ldexp(a[c].x, -e), std::ldexp(a[c].y, -e), std::ldexp(a[c].z, -e));
  }
  const double hadamard = glm::length(a[0]) * glm::length(a[1]) * glm::length(a[2]);
  if (!(std::abs(glm::determinant(a)) > 64.0 * kUnitRoundoff * hadamard))
    fail("the transform is singular");
  // Numerically singular in the whole: a scale that squashes one axis against the others
  // (scale [1, 1, 1e-20] of a torus) passes the test above, column by column, but a world
  // point is known to u |p|, which along the thin axis is u cond(A) of the surface's own
  // size there: beyond 2^40 (under 1e-4 of it for a view from its own distance) the hits
  // and normals are noise (measured on that torus: from a view 5 sizes away the normal was
  // off by 0.4 % at cond 1e13, 7 % at 1e14, lost at 1e15 and the surface missed at 1e16,
  // exit code 0). Frobenius norms (cond_F >= cond_2), of A scaled by a power of two.
  glm::dmat3 w(m);
  double largest = 0;
  for (int c = 0; c < 3; ++c)
    largest = std::max({largest, std::abs(w[c].x), std::abs(w[c].y), std::abs(w[c].z)});
  const int e = std::ilogb(largest);
  for (int c = 0; c < 3; ++c)
    w[c] = glm::dvec3(std::ldexp(w[c].x, -e), std::ldexp(w[c].y, -e), std::ldexp(w[c].z, -e));
  auto frobenius = [](const glm::dmat3& x) {
    return std::sqrt(glm::dot(x[0], x[0]) + glm::dot(x[1], x[1]) + glm::dot(x[2], x[2]));
  };
  const double cond = frobenius(w) * frobenius(glm::inverse(w));
  if (!(cond <= 0x1p40)) {
    std::ostringstream os;
    os << "the transform's condition number is ";
    putMeasure(os, cond);
    os << " (beyond 2^40 = 1.1e12): it squashes one direction against the others by more than "
          "double "
          "precision resolves in world space; scale the equation's variables instead";
    fail(os.str());
  }
}

// ---- The working clip region ----------------------------------------------------------
// The clip region is closed, but the solver's interval is open at its near end (a root
// within noise of lo is the one a caller already has, roots.h) and a cell's span at both:
// a surface lying on the clip boundary (x^2+y^2+z^2-1 in the clip sphere of radius 1, a
// plane on a face of the clip box) had every root at an end of the span and was never
// hit. So the region the kernels clip to is the user's, widened by 2^-20 of its size
// (plus 2^-40 of its distance from the origin, beyond the rounding of far boundaries):
// roots on the boundary are inside, and nothing farther than a millionth of the region
// beyond it shows.
ClipRegion widenedClip(const ClipRegion& clip) {
  constexpr double kRelative = 0x1p-20, kFar = 0x1p-40;
  if (const auto* s = std::get_if<ClipSphere>(&clip)) {
    const double far =
        std::max({std::abs(s->center.x), std::abs(s->center.y), std::abs(s->center.z)});
    return ClipSphere{s->center, s->radius * (1.0 + kRelative) + kFar * far};
  }
  const auto& b = std::get<ClipBox>(clip);
  const glm::dvec3 pad =
      kRelative * (b.hi - b.lo) + kFar * glm::max(glm::abs(b.lo), glm::abs(b.hi));
  return ClipBox{b.lo - pad, b.hi + pad};
}

// ---- Embree's coordinate range --------------------------------------------------------
// Embree builds its BVH only from primitives whose float bounds lie within +-FLT_LARGE
// (1.844e18; larger boxes are dropped without a message), the double channel's far rays
// enter at 1.5e18 (kEmbreeReach), and with flush-to-zero a box whose coordinates are
// subnormal floats collapses. Either way rays would silently miss the surface, so such a
// surface is refused with the scale it has.
// A box without extent on an axis is one whose world size and padding underflowed to
// nothing (worldBounds pads by a relative 2^-16 and rounds outward, so any box of non-zero
// size stays one): it needs coordinates as small as 0, below the range like a subnormal one
// (a surface scaled by 1e-162 had an all-zero box, skipped as zeros, and was accepted).
void checkEmbreeRange(const SurfaceData& data) {
  double largest = 0.0, smallestNonZero = std::numeric_limits<double>::infinity();
  for (const SurfaceCell& c : data.cells) {
    const RTCBounds& b = c.bounds;
    for (const float v : {b.lower_x, b.lower_y, b.lower_z, b.upper_x, b.upper_y, b.upper_z}) {
      largest = std::max(largest, static_cast<double>(std::abs(v)));
      if (v != 0.0f) smallestNonZero = std::min(smallestNonZero, static_cast<double>(std::abs(v)));
    }
    if (b.lower_x == b.upper_x || b.lower_y == b.upper_y || b.lower_z == b.upper_z)
      smallestNonZero = 0.0;
  }
  if (!(largest <= kEmbreeReach))
    fail("the surface's bounds reach " + str(largest) +
         ", beyond 1e18, the range of Embree's float boxes and rays (it drops boxes beyond "
         "1.8e18): scale the "
         "scene down");
  if (smallestNonZero < std::numeric_limits<float>::min())
    fail("the surface's bounds need coordinates as small as " + str(smallestNonZero) +
         ", below float's normal range (1.2e-38) that Embree's BVH resolves: scale the scene up");
}

// ---- Bounds ----------------------------------------------------------------------------
// World-space box of an object-space box (its 8 corners through the affine map), tightened
// by the exact box of the transformed clip sphere (an ellipsoid: half-extent along world
// axis i is R |row_i(A)|), then padded by a relative 2^-16 of its magnitude and rounded
// outward to float. Embree's non-robust float traversal and the conversion to float
// must never cull a ray that the double kernel would hit (and the cell ownership rule
// counts on a ray inside a face reaching the cells on both sides).
RTCBounds worldBounds(const SurfaceData& data, const glm::dvec3& lo, const glm::dvec3& hi) {
  glm::dvec3 wlo(std::numeric_limits<double>::infinity()),
      whi(-std::numeric_limits<double>::infinity());
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p{corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y,
                       corner & 4 ? hi.z : lo.z};
    const glm::dvec3 w = data.a * p + data.b;
    wlo = glm::min(wlo, w);
    whi = glm::max(whi, w);
  }
  if (const auto* s = std::get_if<ClipSphere>(&data.desc.clip)) {
    const glm::dvec3 c = data.a * s->center + data.b;
    const glm::dmat3 at = glm::transpose(data.a);
    for (int i = 0; i < 3; ++i) {
      // safeLength: glm::length squares the entries, and a column of 1e-162 gave 0 (an
      // all-zero box, accepted as if it were in range).
      const double e = s->radius * safeLength(at[i]);
      wlo[i] = std::max(wlo[i], c[i] - e);
      whi[i] = std::min(whi[i], c[i] + e);
    }
  }
  const double scale = std::max(safeLength(wlo), safeLength(whi));
  const double pad = 0x1p-16 * scale;
  RTCBounds b{};
  auto down = [](double v) {
    float f = static_cast<float>(v);
    return static_cast<double>(f) > v ? std::nextafter(f, -INFINITY) : f;
  };
  auto up = [](double v) {
    float f = static_cast<float>(v);
    return static_cast<double>(f) < v ? std::nextafter(f, INFINITY) : f;
  };
  b.lower_x = down(wlo.x - pad);
  b.lower_y = down(wlo.y - pad);
  b.lower_z = down(wlo.z - pad);
  b.upper_x = up(whi.x + pad);
  b.upper_y = up(whi.y + pad);
  b.upper_z = up(whi.z + pad);
  return b;
}

// The cells are one level of a regular subdivision of [boxLo, boxHi] (rounded outward by
// a few ulps): recover each cell's integer grid position, so that the kernel can give
// every root exactly one owning cell (surface_intersect.cpp, "Cell ownership"). If the
// cells do not form a regular grid, the map stays empty (a root near a face may then be
// offered once per cell that holds it).
void indexGrid(SurfaceData& data, const glm::dvec3& boxLo, const glm::dvec3& boxHi) {
  data.cellOfKey.clear();
  if (data.cells.size() < 2) return;
  data.gridLo = boxLo;
  data.gridSize = boxHi - boxLo;
  const SurfaceCell& first = data.cells.front();
  for (int a = 0; a < 3; ++a)
    data.gridN[a] = std::round(data.gridSize[a] / (first.hi[a] - first.lo[a]));
  for (int a = 0; a < 3; ++a)
    if (!(data.gridN[a] >= 1 && data.gridN[a] <= 65535)) return;
  for (unsigned i = 0; i < data.cells.size(); ++i) {
    const SurfaceCell& c = data.cells[i];
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const double size = (c.hi[a] - c.lo[a]) * data.gridN[a] / data.gridSize[a];
      const double pos =
          (0.5 * (c.lo[a] + c.hi[a]) - data.gridLo[a]) * data.gridN[a] / data.gridSize[a] - 0.5;
      const double k = std::round(pos);
      if (std::abs(size - 1.0) > 1e-6 || std::abs(pos - k) > 1e-6 || k < 0 || k >= data.gridN[a]) {
        data.cellOfKey.clear();
        return;
      }
      key = key * 65536u + static_cast<std::uint64_t>(k);
    }
    if (!data.cellOfKey.emplace(key, i).second) {
      data.cellOfKey.clear();
      return;
    }
  }
}

std::atomic<std::uint64_t> nextSurfaceId{1};
constexpr int kMaxAutoCells = 4096;
// SurfaceData::sceneRadius: the clip radius, at most this many object radii. A float host's
// hit points are taken to come from rays that started within ~8 scene radii, and its
// origins are uncertain by 16 u_float of it: up to 2^13 object radii that is at most ~1 %
// of the object's radius (8e-3), beyond which the self-root rule's window would swallow
// the object's own features (a unit sphere in a clip ball of radius 1e7: a camera 5 away
// saw nothing). So cameras up to ~8e4 object radii send leaving rays that do not meet their
// origin; farther, a float host's hit points err by more than 1 % of the object (at 1e6
// object radii, 6 %), and such leaving rays can (the second review of session 51: with
// the clip radius, inward rays there lost the far side instead). At 2^10 (the first
// review) cameras 4e4-1e5 object radii away in a clip ball of 1e4 already met their origin.
constexpr double kSceneObjects = 0x1p13;
// surfaceReach's budget here (interval multiply-adds, ~60 ms at most): enough for quadrics
// and quartics in regions up to 1e14 times their size.
constexpr double kReachWork = 1.6e7;

// The Hessian's size as sampled: 4 times the largest change of grad f over a step of 2^-8
// of the clip box along an axis, divided by the step, at the 9^3 grid points of the box (for
// multipleRootWindow's first gate: a measure, not a bound; hitPointNoise's bound is far
// looser where f's coefficients cancel, which opened the gate for every shadow ray of a
// Chmutov or Sarti surface); inf where none is measured.
double sampledHessian(const HornerForm& f, const ClipRegion& clip) {
  glm::dvec3 lo, hi;
  clipRegionBox(clip, lo, hi);
  const glm::dvec3 size = hi - lo;
  const double step = 0x1p-8 * std::max({size.x, size.y, size.z});
  double largest = 0.0;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 8; ++k) {
        const glm::dvec3 p = lo + size * glm::dvec3(i, j, k) / 8.0;
        const glm::dvec3 g = f.evaluate(p).gradient;
        for (int a = 0; a < 3; ++a) {
          glm::dvec3 q = p;
          q[a] += step;
          largest = std::max(largest, safeLength(f.evaluate(q).gradient - g) / step);
        }
      }
  return std::isfinite(largest) && largest > 0.0 ? 4.0 * largest
                                                 : std::numeric_limits<double>::infinity();
}

// SurfaceData::objectRadius: the farthest corner of any cell from the clip centre (of an
// ellipsoid's own box where its one cell is the ellipsoid's padded box, whose padding for
// float origins anywhere in the clip region grows with that region: +-4.6e11 about a unit
// sphere in a clip box 2e14 long), at most the clip radius (the clip radius with no cells:
// no ray reaches the kernels then); and where the cells lie well inside the region or the
// degree is at most 4, unless the surface surely reaches out to 1 / kSceneObjects of the
// clip radius (surfaceReach's `enough`: then sceneRadius is the clip radius anyway),
// surfaceReach's bound (cells.h): the cells, capped in number, reach ~1e-3 of a
// large region's radius (a unit sphere in a clip ball of radius 1e7: 8458), the search
// about 1.2-1.4 object radii for quadrics and quartics in regions up to 1e14 times their
// size (degree 6-8 surfaces there stop on its work: Taubin's heart ~50, Chmutov-8 ~6000
// times their size from 1e6 on). Each corner's distance as |c - lo| or |hi - c| per axis,
// the larger one: a safeLength of differences within the clip box, so no overflow where
// the radius itself is in range. (A surface's construction pays the search, 1-60 ms, only
// in such regions.)
double objectRadiusOf(const SurfaceData& data, const QuadricBox* ellipsoid, const glm::dvec3& boxLo,
                      const glm::dvec3& boxHi, const std::optional<CellSphere>& sphere) {
  const auto farCorner = [&](const glm::dvec3& lo, const glm::dvec3& hi) {
    const glm::dvec3 corner = glm::max(data.centre - lo, hi - data.centre);
    return safeLength(glm::max(corner, glm::dvec3(0.0)));
  };
  double farthest = 0.0;
  for (const SurfaceCell& c : data.cells) farthest = std::max(farthest, farCorner(c.lo, c.hi));
  if (ellipsoid)
    farthest = std::min(farthest, farCorner(ellipsoid->surfaceLo, ellipsoid->surfaceHi));
  // Where the cells lie well inside the clip region, or for degrees up to 4 (whose search
  // converges) unless the lattice shows the surface reaching out: not for every surface, as
  // Chmutov-12 in its own clip ball (no sign change on the lattice, a search that runs out
  // of work) took 57 ms to build instead of 1.
  const int degree = data.desc.polynomial.degree();
  if (farthest > 0.0 && kSceneObjects * farthest > data.radius &&
      (farthest < data.radius / 16.0 || degree <= 4)) {
    const double reach = surfaceReach(data.desc.polynomial, boxLo, boxHi, sphere, data.centre,
                                      kReachWork, data.radius / kSceneObjects);
    if (reach > 0.0) farthest = std::min(farthest, reach);
  }
  return farthest > 0.0 && farthest < data.radius ? farthest : data.radius;
}

}  // namespace

QuadricForm QuadricForm::fromPolynomial(const Polynomial& f) {
  QuadricForm q;
  auto e = [](int axis) { return glm::ivec3(axis == 0, axis == 1, axis == 2); };
  for (int r = 0; r < 3; ++r) {
    for (int s = 0; s < 3; ++s) {
      const glm::ivec3 m = e(r) + e(s);
      // x_r x_s appears once in f for r != s and is split over A_rs and A_sr (exact halving).
      q.a[s][r] = f.coeff(m.x, m.y, m.z) * (r == s ? 1.0 : 0.5);
    }
    q.b[r] = f.coeff(e(r).x, e(r).y, e(r).z);
  }
  q.c = f.coeff(0, 0, 0);
  for (int r = 0; r < 3; ++r) q.absA[r] = glm::abs(q.a[r]);
  q.absB = glm::abs(q.b);
  q.diagonal = q.a[0][1] == 0.0 && q.a[0][2] == 0.0 && q.a[1][2] == 0.0;
  q.diagA = {q.a[0][0], q.a[1][1], q.a[2][2]};
  q.absDiagA = glm::abs(q.diagA);
  q.nonNegDiagonal = q.diagonal;
  for (int i = 0; i < 3; ++i)
    q.nonNegDiagonal = q.nonNegDiagonal && q.diagA[i] >= 0.0 && !std::signbit(q.diagA[i]);
  q.nonNegCentred = q.nonNegDiagonal && q.b == glm::dvec3(0.0);
  q.unitA = q.diagonal && q.diagA == glm::dvec3(1.0);
  return q;
}

SurfaceGeometry::SurfaceGeometry(RTCDevice device, SurfaceDesc desc) {
  if (!device) fail("the RTCDevice is null");
  validate(desc);
  auto data = std::make_unique<SurfaceData>();
  data->given = desc;
  data->desc = std::move(desc);
  data->desc.clip = widenedClip(data->desc.clip);
  normaliseScale(data->desc.polynomial);
  data->id = nextSurfaceId.fetch_add(1);
  data->horner = HornerForm(data->desc.polynomial);
  // Degree 1 too (a plane: A = 0, never an ellipsoid): the general path's restriction,
  // solver frame and settling took a plane 1.6x the instructions (session 54's audit).
  if (data->desc.polynomial.degree() <= 2 && data->desc.options.quadricPath) {
    data->quadric = QuadricForm::fromPolynomial(data->desc.polynomial);
    // 4 (1 + 2^-20) max_j sum_i |A_ij|: restrictQuadricRay's first test of its second
    // division.
    const glm::dmat3& absA = data->quadric->absA;
    double column = 0.0;
    for (int j = 0; j < 3; ++j) column = std::max(column, absA[j][0] + absA[j][1] + absA[j][2]);
    data->quadricMoveBound = 4.0 * (1.0 + 0x1p-20) * column;
  }

  // ---- Transform ----------------------------------------------------------------------
  const glm::dmat4& m = data->desc.transform;
  data->a = glm::dmat3(m);
  data->b = glm::dvec3(m[3]);
  data->aInv = glm::inverse(data->a);
  data->aInvT = glm::transpose(data->aInv);
  data->identity = m == glm::dmat4(1.0);

  // ---- Clip ball and cells ------------------------------------------------------------
  // One Embree primitive per cell the surface may cross (cells.h), so that the BVH skips
  // empty space and the solver searches short spans; or one for the whole clip region.
  glm::dvec3 boxLo, boxHi;
  std::optional<CellSphere> sphere;
  if (const auto* s = std::get_if<ClipSphere>(&data->desc.clip)) {
    data->centre = s->center;
    data->radius = s->radius;
    boxLo = s->center - glm::dvec3(s->radius);
    boxHi = s->center + glm::dvec3(s->radius);
    sphere = CellSphere{s->center, s->radius};
  } else {
    const auto& b = std::get<ClipBox>(data->desc.clip);
    data->centre = 0.5 * (b.lo + b.hi);
    data->radius = 0.5 * glm::length(b.hi - b.lo);
    boxLo = b.lo;
    boxHi = b.hi;
  }
  data->selfRootRadius2 = (data->radius * (1.0 + 0x1p-9)) * (data->radius * (1.0 + 0x1p-9));
  // ---- The gradient's noise (hit_normal.cpp) -----------------------------------------
  // gradientNoise's |f| and factor; the hits' slope test, 2^10 times gradientNoise bounded
  // over the clip ball: each |p_i| <= R = max |c_i| + r (2^-20 over it for rounding), so
  // sum |c| e_i |p|^(e - e_i) <= sum_d d A_d R^(d - 1), A_d the sum of |c| of degree d. Where
  // that overflows (degree 40 with a clip radius of 1e10) the test is off: every slope
  // counts as clear.
  const Polynomial& poly = data->desc.polynomial;
  const int degree = std::max(poly.degree(), 0);
  Polynomial absPoly;
  std::vector<double> weights;         // d A_d, d = 1..degree
  std::vector<double> hessianWeights;  // d (d - 1) A_d, d = 2..degree
  for (int d = 0; d <= degree; ++d) {
    double sum = 0;
    for (int i = d; i >= 0; --i)
      for (int j = d - i; j >= 0; --j) {
        const double c = std::abs(poly.coeff(i, j, d - i - j));
        if (c != 0) absPoly.setCoeff(i, j, d - i - j, c);
        sum += c;
      }
    if (d > 0) weights.push_back(d * sum);
    if (d > 1) hessianWeights.push_back(d * (d - 1.0) * sum);
  }
  data->absHorner = HornerForm(absPoly);
  data->gradientGamma = gamma(4 * degree + 8);
  // The bound of |p_i| over the ball of radius `ball` about the centre: max |c_i| + ball.
  const auto coordinateBound = [&](double ball) {
    const glm::dvec3 corner = absv(data->centre) + glm::dvec3(ball);
    return std::max({corner.x, corner.y, corner.z});
  };
  const auto slopeNoiseWithin = [&](double ball) {
    const double r = coordinateBound(ball);
    double bound = 0;
    for (size_t i = weights.size(); i-- > 0;) bound = bound * r + weights[i];
    const double slopeNoise = 0x1p10 * data->gradientGamma * bound;
    return std::isfinite(slopeNoise) ? slopeNoise : 0.0;
  };
  data->hitSlopeNoise = slopeNoiseWithin(data->radius * (1.0 + 0x1p-20));
  const double r = coordinateBound(data->radius * (1.0 + 0x1p-20));
  // How far grad f moves when the point moves: sum_j |d_i d_j f| <= sum_d d (d - 1) A_d
  // R^(d - 2) over the clip ball (each monomial's second derivatives summed over j are at
  // most e_i (|e| - 1) of it over R^2), times 2^10 as the slope's own noise (hitPointNoise).
  double hessian = 0;
  for (size_t i = hessianWeights.size(); i-- > 0;) hessian = hessian * r + hessianWeights[i];
  const double pointNoise = 0x1p10 * (1.0 + 0x1p-20) * hessian;
  data->hitPointNoise = std::isfinite(pointNoise) ? pointNoise : 0.0;
  // The self-root rule's bounds for multiple roots at an origin (multipleRootWindow), used by
  // the generic walk only: a quadric takes its own rule (quadric_path.cpp), so they are not
  // computed for one (the sampling alone is 4 9^3 evaluations of f).
  if (!data->quadric) {
    data->sampledHessian = sampledHessian(data->horner, data->desc.clip);
    // How far c_k = D^k f(x) [d^k] / k! moves with x (the self-root rule's test for a root of
    // multiplicity above 1 at the origin, multipleRootWindow): d/dv c_k is the coefficient of
    // s^k t in f(x + s d + t v), and for a monomial of degree j with |x_i| <= R that is at
    // most the one of (R + s |d|_inf + t |v|_inf)^j, j! / (k! (j - k - 1)!) R^(j - k - 1)
    // |d|_inf^k |v|_inf. R as above with 2^-7 R more: origins up to 2^-9 R outside the clip
    // ball take the rule. (k = 1 is the Hessian's bound of hitPointNoise.)
    const double rMove = r + 0x1p-7 * data->radius;
    for (int k = 0; k < degree; ++k) {
      double sum = 0;
      for (int j = degree; j > k; --j) {
        // A_j j! / (k! (j - k - 1)!) = A_j C(j, k) (j - k).
        double binomial = 1;
        for (int i = 1; i <= k; ++i) binomial = binomial * (j - k + i) / i;
        sum = sum * rMove + weights[j - 1] / j * binomial * (j - k);
      }
      data->coefficientMove[k] = std::isfinite(sum) ? sum : std::numeric_limits<double>::infinity();
    }
  }
  // (256 R)^2, exact scalings of R^2 (rounded once) within this range of R; else 0: the
  // walk's shortcut for deferred float origin errors is off (surelyOutsideClipBall).
  const bool normalRange = data->radius >= 0x1p-400 && data->radius <= 0x1p400;
  data->floatOriginNear2 = normalRange ? 65536.0 * (data->radius * data->radius) : 0.0;
  // The Frobenius norm bounds A's spectral norm; 2^-20 covers the rounding of both.
  data->worldCentre = data->a * data->centre + data->b;
  const double normA =
      std::sqrt(glm::dot(data->a[0], data->a[0]) + glm::dot(data->a[1], data->a[1]) +
                glm::dot(data->a[2], data->a[2]));
  data->worldRadius = normA * data->radius * (1.0 + 0x1p-20);
  const SurfaceOptions& opt = data->desc.options;
  if (opt.useCells) {
    CellOptions cellOptions;
    cellOptions.depth = opt.cellDepth;
    // The adapter caps the automatic choice: beyond a few thousand cells a ray visits
    // many primitives (one solve each) for little extra culling, and the build time of
    // tens of thousands of cells (seconds) is paid per surface.
    if (opt.cellDepth < 0) cellOptions.maxCells = kMaxAutoCells;
    for (const Cell& c : buildCells(data->desc.polynomial, boxLo, boxHi, sphere, cellOptions))
      data->cells.push_back(SurfaceCell{c.lo, c.hi, worldBounds(*data, c.lo, c.hi)});
  } else {
    data->cells.push_back(SurfaceCell{boxLo, boxHi, worldBounds(*data, boxLo, boxHi)});
  }
  // An ellipsoid's one cell shrinks to the ellipsoid's own padded box (quadric_path.cpp,
  // boundedQuadricBox): Embree then sends the callbacks only the rays near it, as for a
  // native sphere. A grid of cells keeps its boxes (the ownership rule needs the grid).
  std::optional<QuadricBox> ellipsoid;
  if (data->cells.size() == 1 && opt.quadricBounds) {
    SurfaceCell& cell = data->cells.front();
    QuadricBox box;
    if (boundedQuadricBox(*data, box)) {
      ellipsoid = box;
      const glm::dvec3 lo = glm::max(box.lo, cell.lo), hi = glm::min(box.hi, cell.hi);
      if (glm::all(glm::lessThan(lo, hi))) {
        cell = SurfaceCell{lo, hi, worldBounds(*data, lo, hi)};
        // Rays the box's derivation covers skip the quadric path's cell clip only when
        // the cell is that box (not one the cell build shrank further).
        if (lo == box.lo && hi == box.hi) data->quadricBox = box;
      }
    }
  }
  data->quadricCellClip = data->cells.size() == 1 && !cellHoldsClipRegion(*data);
  data->objectRadius =
      objectRadiusOf(*data, ellipsoid ? &*ellipsoid : nullptr, boxLo, boxHi, sphere);
  data->sceneRadius = std::min(data->radius, kSceneObjects * data->objectRadius);
  // Hits lie on the surface: where it lies well inside the clip ball, the slope test is
  // bounded over the object's ball instead (2^-10 over it for the hits a cell's span and
  // the walk's window let past its faces). Over the clip ball a unit sphere clipped to a
  // ball of radius 1e14 had no hit with a clear slope (all went to gradientBesideNoise).
  if (data->objectRadius < data->radius)
    data->hitSlopeNoise = slopeNoiseWithin(data->objectRadius * (1.0 + 0x1p-10));
  indexGrid(*data, boxLo, boxHi);
  checkEmbreeRange(*data);

  data->geometry = createUserGeometry(device, data.get());
  data_ = std::move(data);
}

SurfaceGeometry::~SurfaceGeometry() {
  if (data_ && data_->geometry) rtcReleaseGeometry(data_->geometry);
}
SurfaceGeometry::SurfaceGeometry(RTCDevice device, std::string_view equation, ClipRegion clip,
                                 const ParseOptions& parse, const glm::dmat4& transform,
                                 const SurfaceOptions& options)
    : SurfaceGeometry(device,
                      SurfaceDesc{parsePolynomial(equation, parse), clip, transform, options}) {}

SurfaceGeometry::SurfaceGeometry(SurfaceGeometry&&) noexcept = default;
SurfaceGeometry& SurfaceGeometry::operator=(SurfaceGeometry&& other) noexcept {
  if (this != &other) {
    if (data_ && data_->geometry) rtcReleaseGeometry(data_->geometry);
    data_ = std::move(other.data_);
  }
  return *this;
}

RTCGeometry SurfaceGeometry::geometry() const { return data_ ? data_->geometry : nullptr; }
unsigned SurfaceGeometry::primitiveCount() const {
  return data_ ? static_cast<unsigned>(data_->cells.size()) : 0u;
}
const SurfaceDesc& SurfaceGeometry::desc() const {
  // A moved-from geometry has no data: an empty description, as geometry() is null.
  static const SurfaceDesc kEmpty;
  return data_ ? data_->given : kEmpty;
}
unsigned long long SurfaceGeometry::callbackErrors() const {
  return data_ ? data_->errors.load() : 0ull;
}

}  // namespace algray
