#pragma once
// Cells: axis-aligned boxes covering the part of a surface f = 0 inside its clip region.
//
// The clip box is split recursively (kd-style: always the longest edge, so elongated
// boxes become cubes first); a box is kept only if the range enclosure of f over it
// (range_bound.h, centred form in interval arithmetic) contains 0. Each kept box becomes
// one Embree user primitive: the BVH then skips empty space, and a ray that meets no
// cell never reaches the root solver (DESIGN.md, "the way of one ray", steps 1-2).
//
// Conservative: every point of {f = 0} inside the clip region lies in some returned cell
// (cells are closed boxes, rounded outward), whatever the rounding of the construction.
#include "algray/polynomial.h"
#include "algray/range_bound.h"

#include <glm/vec3.hpp>

#include <optional>
#include <vector>

namespace algray {

// The cells of one call are one level of a regular subdivision of the clip box: cell
// `index` of a grid of CellStats::grid cells per axis (nominal box lo + (hi - lo) *
// index / grid ... (index + 1) / grid), rounded outward and clipped to the clip box.
struct Cell {
  glm::dvec3 lo{0.0};
  glm::dvec3 hi{0.0};
  glm::ivec3 index{0};
};

// A clip sphere in the cells' terms (the core cannot see embree.h's ClipSphere).
struct CellSphere {
  glm::dvec3 center{0.0};
  double radius = 1.0;
};

// The finest explicit depth (cells 2^-30 of the clip box: far below any use); deeper
// requests are capped by buildCells and refused by SurfaceGeometry.
inline constexpr int kMaxCellDepth = 30;

struct CellOptions {
  // Resolution level: every edge of a cell is <= (longest clip-box edge) / 2^depth,
  // so depth d on a cube is an octree of depth d. -1: chosen automatically (cells.cpp,
  // "Automatic depth"; docs/cells-summary.md has the measurements behind the rule): the
  // finest level a build-time budget allows, or a single cell for the whole region when
  // even that level's cells would meet most rays (CellStats::rayCoverage > 0.3).
  int depth = -1;
  // Hard cap: if a level would keep more cells, the coarser level is returned.
  int maxCells = 1 << 16;
  // The emptiness test of a box (range_bound.h): the centred form alone, or the centred
  // form and, for the boxes it keeps, the Bernstein enclosure (tighter on large boxes and
  // high degrees, much costlier; docs/cells-summary.md compares them).
  RangeBound bound = RangeBound::Centred;
};

struct CellStats {
  int depth = 0;         // level of the returned cells
  glm::ivec3 grid{1};    // cells per axis of that level's grid (powers of two)
  long boxesTested = 0;  // range enclosures evaluated
  // Per level 0..deepest level explored (which may be one level finer than depth when the
  // automatic rule declined it): cells kept and their volume / clip-box volume.
  std::vector<long> keptPerLevel;
  std::vector<double> keptVolumeFraction;
  // Of the axis-parallel rays through the clip region, the fraction that meets a cell
  // (averaged over the axes; -1 if the grid is too fine to count): what the cells cannot
  // cull. Near 1 when the surface fills its clip region. When the automatic choice
  // skipped the build (the surface itself crosses more than 0.2 of the axis-parallel
  // lines through the region: cells could not cull, see cells.cpp), the fraction of
  // probe lines crossing f = 0 instead, and boxesTested is 0.
  double rayCoverage = -1;
};

// Cells (in the polynomial's own coordinates) covering every point of {f = 0} inside the
// clip box [lo, hi] and, if given, inside the sphere as well (cells wholly outside it are
// dropped). An empty box (lo > hi on some axis) or a negative radius gives no cells.
// Throws Error for non-finite coefficients, bounds or radius, maxCells < 1 or depth < -1.
std::vector<Cell> buildCells(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
                             const std::optional<CellSphere>& sphere = std::nullopt,
                             const CellOptions& options = {}, CellStats* stats = nullptr);

// An upper bound of the distance from `from` to every point of {f = 0} inside the clip box
// [lo, hi] (and the sphere, if given): the object's reach, where the clip region may be far
// larger than the object (a unit sphere clipped to a ball of radius 1e14, whose cells,
// capped in number, reach ~1e-3 of it). Best-first subdivision, farthest box first, with
// buildCells' emptiness tests (RangeBound::Bernstein), until the farthest box left is
// within 2^-3 of its distance (the bound then at most 1.28 times the farthest point's,
// where that box holds one) or `work` interval multiply-adds are spent (the bound is then
// the farthest box left's: at worst the region's farthest corner). 0 when the surface
// provably misses the region. With `enough` > 0 a caller that only needs to know whether the
// reach is below it is answered first by a 9 x 9 x 9 lattice over the box: a sign change
// of f (both ends clear of f's rounding bound, both in the region) along an edge that keeps
// at least `enough` from `from` proves a surface point that far, and the region's farthest
// corner is returned without the search (a surface that fills its region does so at once).
// Throws Error as buildCells does, and for negative work or a non-finite `from`.
double surfaceReach(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
                    const std::optional<CellSphere>& sphere, const glm::dvec3& from,
                    double work = 4e6, double enough = 0.0);

// The ray's parameter span inside a closed box: [t0, t1] within [tMin, tMax], or nothing.
// Slab test as pbrt-v4's Bounds3::IntersectP: each slab's far parameter is enlarged by
// a factor 1 + 2 gamma(3) so that the rounding of (bound - o) / d never loses a grazing
// hit (Pharr, Jakob & Humphreys, "Physically Based Rendering", 4th ed., Sec. 6.8.7); the
// near parameter is moved down likewise, so a root on the entry face stays inside.
// Zero direction components are handled (the slab is all or nothing), subnormal ones are
// not zero (the quotients are finite); NaN gives nothing.
struct RaySpan {
  double t0 = 0;
  double t1 = 0;
};
std::optional<RaySpan> clipRayToBox(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo,
                                    const glm::dvec3& hi, double tMin, double tMax);

}  // namespace algray
