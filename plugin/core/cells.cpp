// Cells: recursive subdivision of the clip region, keeping the boxes where f may vanish.
// See cells.h for the contract and range_bound.h for the emptiness test.
#include "algray/cells.h"

#include "algray/interval.h"
#include "algray/range_bound.h"
#include "algray/roots.h"
#include "algray/taylor.h"
#include "gradual_underflow.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace algray {

namespace {

constexpr int kMaxAutoDepth = 12;

// ---- Automatic depth -------------------------------------------------------------------
// The finest level whose cell count fits a budget set by build work (measured in
// tests/bench/cells_bench.cpp, docs/cells-summary.md):
//  * One halving costs MonomialTables::splitCost() interval multiply-adds (~m^4/24 for
//    degree m; 10-40 ns each measured), and a kept cell costs about kTestsPerCell
//    halvings (its own test plus its share of the rejected siblings and coarser levels:
//    3.5-4.5 measured on the gallery). The build may spend kBuildWork multiply-adds
//    (0.03-0.35 s measured), so quadrics and quartics get maxCells, a sextic ~24k cells, a
//    degree-16 surface ~1000 and degree 40 the minimum of 64.
//  * Diminishing returns: once refinement has become effective (a level kept <=
//    kEffectiveRatio of the previous level's volume, the regime of a surface, where the
//    ratio tends to 1/2), a refinement that keeps more than kVolumeRatio of the volume
//    is not taken: the surface fills its cells at this scale (or the enclosure is too
//    loose to separate it), and 4x the cells would cull little more.
//    (At coarse levels the ratio is ~1 because the clip ball and a loose enclosure keep
//    every box; the rule must not stop there.)
//  * A level whose predicted count (growth of the last level) exceeds the budget is
//    not attempted; an attempted level that exceeds the budget is abandoned.
//  * Cells must cull to pay: with the adapter's kernel (one root solve per ray over the
//    whole clip span, cells only decide which rays solve at all), a ray that meets a
//    cell pays ~0.1 us of Embree callback per cell on top of the solve. Measured on the
//    gallery (cells_bench BM_TraceCells): where the cells meet most rays (coverage
//    0.45-1.0: surfaces that fill their clip ball) the automatic level without this rule
//    was 1.1-1.9x slower than one primitive; where they meet few (coverage 0.09-0.22: the same
//    surfaces in a ball of 3x the radius) 3.5-6x faster. So when the finest affordable level still
//    meets more than kMaxCoverage of the rays (CellStats::rayCoverage), the automatic choice is one
//    cell for the whole region.
//    Measured and not kept (session 3): stopping the build early when a level's coverage, halved
//    per remaining level, stays above kMaxCoverage. Coarse levels cannot tell the cases apart:
//    Chmutov-12 in its clip ball (coverage 1.0 at depths 1-4, 0.57 at 5: falls back) and Chmutov-8
//    in a ball of 3x the radius (1.0 at depths 1-3, then 0.45, 0.14, 0.08: its cells pay) look the
//    same at depth 3, and the rule dropped the latter's cells.
constexpr double kBuildWork = 2e7;
constexpr double kMaxCoverage = 0.3;
constexpr double kTestsPerCell = 4.0;
constexpr double kVolumeRatio = 0.75;
constexpr double kEffectiveRatio = 0.6;
constexpr long kMinAutoCells = 64;
// A level is refined in this many chunks of consecutive cells at most (Builder::refine):
// enough to balance a few dozen threads, few enough that a chunk's start-up is nothing.
constexpr std::size_t kRefineChunks = 64;

long autoBudget(const MonomialTables& t, int maxCells, RangeBound bound) {
  const long perTest = t.splitCost() + (bound == RangeBound::Bernstein ? t.bernsteinCost() : 0);
  const double cells = kBuildWork / (kTestsPerCell * static_cast<double>(perTest));
  return std::clamp(static_cast<long>(cells), std::min(kMinAutoCells, static_cast<long>(maxCells)),
                    static_cast<long>(maxCells));
}

// ---- The subdivision -----------------------------------------------------------------
// A box of the recursion, in the normalised coordinates w in [-1, 1]^3 of the root box
// (world point = c + h*w). Corners are dyadic rationals, hence exact.
struct Node {
  glm::dvec3 wlo{-1.0}, whi{1.0};
  int splits[3] = {0, 0, 0};  // halvings per axis
};

// Level by level: the cells of level L+1 are found by a depth-first split of each cell of
// level L (three halvings for a cube), whose polynomial is re-derived from the root's by
// one Taylor shift per axis (BoxPolynomial::subBox). Memory is the cells, not their
// polynomials, and the automatic rule can stop after any level without wasted work.
class Builder {
 public:
  Builder(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
          const std::optional<CellSphere>& sphere, RangeBound bound)
      : lo_(lo), hi_(hi), sphere_(sphere), bound_(bound), tables_(std::max(f.degree(), 0)) {
    // Root box: centre c and half-widths h rounded up, so [c - h, c + h] contains [lo, hi].
    for (int a = 0; a < 3; ++a) {
      c_[a] = 0.5 * lo[a] + 0.5 * hi[a];
      h_[a] = halfWidth(lo[a], c_[a], hi[a]);
    }
    hMax_ = std::max({h_.x, h_.y, h_.z});
    rootPoly_ = BoxPolynomial(f, c_, h_, tables_);
  }

  const MonomialTables& tables() const { return tables_; }
  bool flat() const { return hMax_ == 0; }

  // The kept root (level 0), or nothing.
  std::vector<Node> rootLevel() {
    Node root;
    ++tested_;
    if (!keep(root, rootPoly_)) return {};
    return {root};
  }

  // The kept boxes of the next level, or nullopt once more than budget are kept. The
  // level's cells are split in parallel (TBB) in fixed chunks of consecutive cells, each
  // depth-first as one thread would, and the chunks' boxes are concatenated in order: the
  // same cells in the same order on any number of threads. "Over budget" is decided on
  // the exact total (one shared count), so it is the same too; only the test count of an
  // abandoned level depends on how far the other chunks got.
  std::optional<std::vector<Node>> refine(const std::vector<Node>& level, int nextLevel,
                                          long budget) {
    const std::size_t chunks = std::min<std::size_t>(level.size(), kRefineChunks);
    std::vector<std::vector<Node>> parts(chunks);
    std::vector<long> tests(chunks, 0);
    std::atomic<long> kept{0};
    std::atomic<bool> over{false};
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t i) {
      // Each worker's own floating-point mode: TBB's and Embree's workers may flush
      // subnormals to zero (gradual_underflow.h).
      const GradualUnderflow gradual;
      const std::size_t from = level.size() * i / chunks, to = level.size() * (i + 1) / chunks;
      tests[i] = refineCells(std::span(level).subspan(from, to - from), nextLevel, budget, kept,
                             over, parts[i]);
    });
    for (long t : tests) tested_ += t;
    if (over.load()) return std::nullopt;
    std::vector<Node> out;
    out.reserve(static_cast<std::size_t>(kept.load()));
    for (const std::vector<Node>& part : parts) out.insert(out.end(), part.begin(), part.end());
    return out;
  }

  long tested() const { return tested_; }

  // surfaceReach (cells.h): best-first on the kept boxes, farthest corner first; a box's
  // polynomial is re-derived from the root's when it is popped (subBox), so memory is the
  // boxes alone. Every box taken off for good was proved empty (keep), so the largest key
  // left bounds the distance of every point of the surface: returned once the box holding
  // it is within 2^-3 of its key (its points within sqrt(3) / 8 of it: the bound at most
  // 1.28 times the farthest point's distance where that box holds a point of the surface)
  // or the tests run out. The emptiness test is the Bernstein one (keep, bound_): with the
  // centred form alone a torus in a ball of 1e7 times its size stopped at ~1e-5 of it, the
  // quartic x^4 + y^4 + z^4 = 1 at 1e14 (boxes beside the axes far from the surface, where
  // the centred form's cross terms reach below 0); with it both reach 1.2 their size up to
  // 1e14 in 3-18 ms.
  double reach(const glm::dvec3& from, long maxTests) {
    struct Item {
      double key;
      Node node;
      bool operator<(const Item& o) const { return key < o.key; }
    };
    const auto farCorner = [&](const Node& node) {
      const Cell box = worldBox(node);
      double d2 = 0;
      for (int a = 0; a < 3; ++a) {
        const double d = std::max(nextUp(from[a] - box.lo[a]), nextUp(box.hi[a] - from[a]));
        d2 = nextUp(d2 + nextUp(d * d));
      }
      return nextUp(std::sqrt(d2) * (1.0 + 0x1p-50));
    };
    const Node root;
    // (A budget below one split buys nothing: the root's corner without its test, which
    // alone costs up to 4e6 multiply-adds at degree 40.)
    if (maxTests < 3) return farCorner(root);
    if (!keep(root, rootPoly_)) return 0.0;
    std::vector<Item> heap = {{farCorner(root), root}};
    BoxPolynomial parent, child;
    long tests = 1;
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end());
      const Item top = heap.back();
      heap.pop_back();
      const int axis = splitAxis(top.node);
      const double edge = 2.0 * std::ldexp(h_[axis], -top.node.splits[axis]);
      if (edge <= 0x1p-3 * top.key || tests + 2 > maxTests) return top.key;
      const glm::dvec3 centre = 0.5 * (top.node.wlo + top.node.whi);  // exact (dyadic)
      rootPoly_.subBox(centre, top.node.splits, parent);
      const double mid = 0.5 * (top.node.wlo[axis] + top.node.whi[axis]);
      for (int side : {-1, +1}) {
        Node node = top.node;
        (side < 0 ? node.whi : node.wlo)[axis] = mid;
        ++node.splits[axis];
        parent.half(axis, side, child);
        ++tests;
        if (!keep(node, child)) continue;
        heap.push_back({farCorner(node), node});
        std::push_heap(heap.begin(), heap.end());
      }
    }
    return 0.0;  // every box proved empty
  }

  // World box of a node, rounded outward, then intersected with the clip box (points of
  // interest lie in both).
  Cell worldBox(const Node& node) const {
    Cell cell;
    for (int a = 0; a < 3; ++a) {
      cell.lo[a] = std::max(lo_[a], (Interval(h_[a]) * node.wlo[a] + c_[a]).lower());
      cell.hi[a] = std::min(hi_[a], (Interval(h_[a]) * node.whi[a] + c_[a]).upper());
      // w = -1 + 2 (index / 2^splits): exact in dyadics. Cells stop at level 30; only
      // surfaceReach's boxes split further (to an edge of 2^-3 of their distance), where the
      // index is not read and from 32 splits on would overflow int (the conversion is
      // undefined: CellsTest.SurfaceReachBoundsEverySurfacePoint under float-cast-overflow).
      cell.index[a] = node.splits[a] < 32
                          ? static_cast<int>(std::ldexp(node.wlo[a] + 1.0, node.splits[a] - 1))
                          : 0;
    }
    return cell;
  }

  // Volume of a box at this split count over the root volume (flat axes ignored).
  double volumeFraction(const Node& n) const {
    int k = 0;
    for (int a = 0; a < 3; ++a) k += h_[a] > 0 ? n.splits[a] : 0;
    return std::ldexp(1.0, -k);
  }

 private:
  // The boxes of the next level inside cells, depth-first, appended to out; returns the
  // number of boxes tested. Stops once the shared count passes budget (over).
  long refineCells(std::span<const Node> cells, int nextLevel, long budget, std::atomic<long>& kept,
                   std::atomic<bool>& over, std::vector<Node>& out) const {
    long tests = 0;
    // Depth-first stack whose slots (and their coefficient storage) are reused: no
    // allocation per box after the first few.
    struct Entry {
      Node node;
      BoxPolynomial poly;
    };
    std::vector<Entry> stack;
    std::size_t top = 0;
    auto push = [&]() -> Entry& {
      if (top == stack.size()) stack.emplace_back();
      return stack[top++];
    };
    BoxPolynomial parent;
    for (const Node& cell : cells) {
      if (over.load(std::memory_order_relaxed)) return tests;
      const glm::dvec3 centre = 0.5 * (cell.wlo + cell.whi);  // exact (dyadic)
      Entry& first = push();
      first.node = cell;
      rootPoly_.subBox(centre, cell.splits, first.poly);
      while (top > 0) {
        --top;
        const Node node = stack[top].node;
        std::swap(parent, stack[top].poly);  // the slot is reused by the children
        const int axis = splitAxis(node);
        const double mid = 0.5 * (node.wlo[axis] + node.whi[axis]);
        for (int side : {+1, -1}) {  // the -1 half is processed first
          Entry& child = push();
          child.node = node;
          (side < 0 ? child.node.whi : child.node.wlo)[axis] = mid;
          ++child.node.splits[axis];
          parent.half(axis, side, child.poly);
          ++tests;
          if (!keep(child.node, child.poly)) {
            --top;
          } else if (reaches(child.node.splits, nextLevel)) {
            out.push_back(child.node);
            --top;
            if (kept.fetch_add(1, std::memory_order_relaxed) + 1 > budget) {
              over.store(true, std::memory_order_relaxed);
              return tests;
            }
          }
        }
      }
    }
    return tests;
  }

  bool keep(const Node& node, const BoxPolynomial& poly) const {
    if (sphere_ && outsideSphere(worldBox(node))) return false;
    if (poly.provablyNonZero()) return false;
    if (bound_ == RangeBound::Bernstein) {
      const Interval r = poly.rangeBernstein();
      if (r.lower() > 0.0 || r.upper() < 0.0) return false;
    }
    return true;
  }

  // The longest (world) edge.
  int splitAxis(const Node& node) const {
    int axis = 0;
    double longest = -1;
    for (int a = 0; a < 3; ++a) {
      const double edge = std::ldexp(h_[a], -node.splits[a]);
      if (edge > longest) longest = edge, axis = a;
    }
    return axis;
  }

  // Every world edge <= (longest root edge) / 2^level.
  bool reaches(const int* splits, int level) const {
    const double limit = std::ldexp(hMax_, -level);
    for (int a = 0; a < 3; ++a)
      if (std::ldexp(h_[a], -splits[a]) > limit) return false;
    return true;
  }

  // True if the closed box provably misses the closed ball: the squared distance from
  // the centre to the box, rounded down, exceeds r^2 rounded up.
  bool outsideSphere(const Cell& cell) const {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const double s = sphere_->center[a];
      double d = 0;
      if (s < cell.lo[a])
        d = nextDown(cell.lo[a] - s);
      else if (s > cell.hi[a])
        d = nextDown(s - cell.hi[a]);
      d = std::max(d, 0.0);
      d2 = nextDown(d2 + nextDown(d * d));
    }
    const double r = sphere_->radius;
    return d2 > nextUp(r * r);
  }

  glm::dvec3 lo_, hi_, c_{0.0}, h_{0.0};
  double hMax_ = 0;
  std::optional<CellSphere> sphere_;
  RangeBound bound_;
  MonomialTables tables_;
  BoxPolynomial rootPoly_;
  long tested_ = 0;
};

// Fraction of axis-parallel rays through the clip region that meet a cell, averaged over
// the three axes: per axis, the grid columns holding a kept cell over the columns whose
// nominal square meets the clip region's projection (the box, or the sphere's disk).
// An estimate of the rays the cells cannot cull (docs/cells-summary.md).
double rayCoverage(const std::vector<Cell>& cells, const glm::ivec3& grid, const glm::dvec3& lo,
                   const glm::dvec3& hi, const std::optional<CellSphere>& sphere) {
  if (cells.empty()) return 0.0;
  double sum = 0;
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    std::vector<char> hit(static_cast<std::size_t>(grid[u]) * grid[v], 0);
    for (const Cell& c : cells)
      hit[static_cast<std::size_t>(c.index[u]) * grid[v] + c.index[v]] = 1;
    long covered = 0, inside = 0;
    const double du = (hi[u] - lo[u]) / grid[u], dv = (hi[v] - lo[v]) / grid[v];
    for (int i = 0; i < grid[u]; ++i)
      for (int j = 0; j < grid[v]; ++j) {
        bool in = true;
        if (sphere) {  // square [u0, u1] x [v0, v1] against the disk
          const double u0 = lo[u] + i * du, v0 = lo[v] + j * dv;
          const double qu = std::clamp(sphere->center[u], u0, u0 + du) - sphere->center[u];
          const double qv = std::clamp(sphere->center[v], v0, v0 + dv) - sphere->center[v];
          in = qu * qu + qv * qv <= sphere->radius * sphere->radius;
        }
        const bool h = hit[static_cast<std::size_t>(i) * grid[v] + j] != 0;
        inside += in || h;
        covered += h;
      }
    sum += inside > 0 ? static_cast<double>(covered) / static_cast<double>(inside) : 1.0;
  }
  return sum / 3.0;
}

void validate(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
              const std::optional<CellSphere>& sphere, const CellOptions& options) {
  if (!f.isFinite()) throw Error("buildCells: polynomial has non-finite coefficients");
  const char* names = "xyz";
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(lo[a]) || !std::isfinite(hi[a]))
      throw Error(std::string("buildCells: non-finite clip box bound on axis ") + names[a]);
  if (sphere) {
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(sphere->center[a]))
        throw Error(std::string("buildCells: non-finite clip sphere centre on axis ") + names[a]);
    if (!std::isfinite(sphere->radius)) throw Error("buildCells: non-finite clip sphere radius");
  }
  if (options.maxCells < 1)
    throw Error("buildCells: maxCells must be >= 1, got " + std::to_string(options.maxCells));
  // -1 asks for the automatic depth; another negative value is a mistake, not a request
  // for it (SurfaceOptions::cellDepth refuses it too).
  if (options.depth < -1)
    throw Error("buildCells: depth must be -1 (automatic) or >= 0, got " +
                std::to_string(options.depth));
}

// ---- Skipping a build that cannot pay ----------------------------------------------------
// The automatic choice falls back to one cell when the finest affordable level still
// meets more than kMaxCoverage of the axis-parallel rays (see "Automatic depth"), and it
// only learns that after building every level: 4-171 ms on the gallery, all of which
// fell back (profile of algray-render, session 2). Every ray that meets the surface meets
// the cells of any level, so the fraction of axis-parallel lines through the clip region
// that cross f = 0 estimates that coverage from below (up to sampling): kProbeLines^2
// lines per axis through the centres of a grid over the clip box, each a univariate
// root query (restriction + hasRoot, a few us). A surface whose lines already cross it
// more than kSkipCoverage of the time is given its one cell without any build. A
// performance decision only: one cell is always correct.
// The probe bounds the cells' coverage from below, and the cells an affordable level
// keeps are much looser than the surface: measured on the gallery in its clip ball and
// in a ball of 3x the radius (session 5), every surface probed at 0.23 or more fell back
// after its build (Barth sextic 0.23: 8 ms, Chmutov-8/12/16 0.24-0.27: 14-48 ms, Endrass
// octic in the 3x ball 0.27: 21 ms), and every one whose cells paid probed at 0.071 or
// less (sphere, ellipsoid, torus, Roman surface, heart, Chmutov-8 in the 3x ball). Hence
// 0.2, not kMaxCoverage plus sampling error (0.33, before).
constexpr int kProbeLines = 24;
constexpr double kSkipCoverage = 0.2;

double probedCoverage(const Polynomial& poly, const glm::dvec3& lo, const glm::dvec3& hi,
                      const std::optional<CellSphere>& sphere) {
  const HornerForm f(poly);  // the restriction over f's own terms (taylor.h)
  double sum = 0.0;
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    long inside = 0, crossing = 0;
    for (int i = 0; i < kProbeLines; ++i)
      for (int j = 0; j < kProbeLines; ++j) {
        glm::dvec3 o(0.0), d(0.0);
        o[u] = lo[u] + (hi[u] - lo[u]) * (i + 0.5) / kProbeLines;
        o[v] = lo[v] + (hi[v] - lo[v]) * (j + 0.5) / kProbeLines;
        o[a] = lo[a];
        d[a] = 1.0;
        double t0 = 0.0, t1 = hi[a] - lo[a];
        if (sphere) {
          const double du = o[u] - sphere->center[u], dv = o[v] - sphere->center[v];
          const double h2 = sphere->radius * sphere->radius - du * du - dv * dv;
          if (!(h2 > 0.0)) continue;
          const double h = std::sqrt(h2), c = sphere->center[a] - lo[a];
          t0 = std::max(t0, c - h);
          t1 = std::min(t1, c + h);
          if (!(t0 < t1)) continue;
        }
        ++inside;
        const double mid = 0.5 * (t0 + t1);
        const RayPolynomial g = restrictToRay(f, o, d, mid);
        if (g.degree < 1) continue;
        const std::span<const double> c(g.coeff.data(), g.degree + 1),
            e(g.error.data(), g.degree + 1);
        crossing += hasRoot(c, e, t0 - mid, t1 - mid);
      }
    sum += inside > 0 ? static_cast<double>(crossing) / static_cast<double>(inside) : 0.0;
  }
  return sum / 3.0;
}

}  // namespace

namespace {

// surfaceReach's `enough` (cells.h): a sign change of f along a lattice edge at least `dist`
// from `from`, both ends in the region.
bool reachesBeyond(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
                   const std::optional<CellSphere>& sphere, const glm::dvec3& from, double dist) {
  constexpr int n = 9;
  std::vector<double> value(n * n * n);
  std::vector<glm::dvec3> point(n * n * n);
  const auto index = [](int i, int j, int k) { return (i * n + j) * n + k; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const glm::dvec3 w = glm::dvec3(i, j, k) / double(n - 1);
        const glm::dvec3 p = glm::mix(lo, hi, w);
        const Polynomial::Evaluation e = f.evaluateWithBound(p);
        const bool inside = !sphere || glm::length(p - sphere->center) <= sphere->radius;
        // 0: no sign known (outside the region, within f's rounding, or not finite).
        value[index(i, j, k)] = inside && std::abs(e.value) > e.valueError ? e.value : 0.0;
        point[index(i, j, k)] = p;
      }
  // The distance from `from` to the segment [a, b] (a lower bound of its points').
  const auto segmentDistance = [&](const glm::dvec3& a, const glm::dvec3& b) {
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double s = len2 > 0.0 ? std::clamp(glm::dot(from - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(a + s * ab - from) * (1.0 - 0x1p-20);
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const int a = index(i, j, k);
        for (const int b :
             {i + 1 < n ? index(i + 1, j, k) : -1, j + 1 < n ? index(i, j + 1, k) : -1,
              k + 1 < n ? index(i, j, k + 1) : -1})
          if (b >= 0 && value[a] * value[b] < 0.0 && segmentDistance(point[a], point[b]) >= dist)
            return true;
      }
  return false;
}

}  // namespace

double surfaceReach(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
                    const std::optional<CellSphere>& sphere, const glm::dvec3& from, double work,
                    double enough) {
  const GradualUnderflow gradual;  // the range test's interval arithmetic needs it
  validate(f, lo, hi, sphere, CellOptions{});
  if (!(work >= 0.0) || !std::isfinite(from.x) || !std::isfinite(from.y) || !std::isfinite(from.z))
    throw Error("surfaceReach: work must be >= 0 and the point finite");
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return 0.0;
  if (sphere && sphere->radius < 0) return 0.0;
  Builder builder(f, lo, hi, sphere, RangeBound::Bernstein);
  if (enough > 0.0 && reachesBeyond(f, lo, hi, sphere, from, enough))
    return builder.reach(from, 0);  // the root box's farthest corner
  // A popped box costs its sub-box (three halvings) and two halvings and Bernstein
  // enclosures for its halves.
  const double perTest = 2.5 * static_cast<double>(std::max(builder.tables().splitCost(), 1L)) +
                         static_cast<double>(builder.tables().bernsteinCost());
  const long maxTests = static_cast<long>(std::clamp(work / perTest, 1.0, 1e6));
  return builder.reach(from, maxTests);
}

std::vector<Cell> buildCells(const Polynomial& f, const glm::dvec3& lo, const glm::dvec3& hi,
                             const std::optional<CellSphere>& sphere, const CellOptions& options,
                             CellStats* stats) {
  const GradualUnderflow gradual;  // the range test's interval arithmetic needs it
  validate(f, lo, hi, sphere, options);
  if (stats) *stats = CellStats{};
  // Empty regions: no cells (not an error: a clip may legitimately be empty).
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) return {};
  if (sphere && sphere->radius < 0) return {};

  Builder builder(f, lo, hi, sphere, options.bound);
  const bool automatic = options.depth < 0;
  int maxLevel = automatic ? kMaxAutoDepth : std::min(options.depth, kMaxCellDepth);
  if (builder.flat()) maxLevel = 0;  // a point: nothing to split
  const long budget = automatic ? autoBudget(builder.tables(), options.maxCells, options.bound)
                                : static_cast<long>(options.maxCells);
  if (automatic && maxLevel > 0) {
    const double probed = probedCoverage(f, lo, hi, sphere);
    if (probed > kSkipCoverage) {
      const std::vector<Node> root = builder.rootLevel();
      if (!root.empty()) {
        if (stats) stats->rayCoverage = probed;
        return {builder.worldBox(root.front())};
      }
    }
  }

  // ---- Level by level, until the depth, the budget or (automatic) diminishing returns.
  const std::vector<Node> root = builder.rootLevel();
  std::vector<Node> cells = root;
  std::vector<long> counts = {static_cast<long>(cells.size())};
  std::vector<double> volumes = {cells.empty() ? 0.0 : 1.0};
  int level = 0;
  bool effective = false;  // some refinement kept <= kEffectiveRatio of the volume
  while (level < maxLevel && !cells.empty()) {
    if (automatic && level > 0 && counts[level - 1] > 0) {
      const double growth =
          static_cast<double>(counts[level]) / static_cast<double>(counts[level - 1]);
      if (static_cast<double>(counts[level]) * growth > static_cast<double>(budget)) break;
    }
    auto next = builder.refine(cells, level + 1, budget);
    if (!next) break;  // over budget: keep this level
    const double volume =
        next->empty() ? 0.0
                      : static_cast<double>(next->size()) * builder.volumeFraction(next->front());
    counts.push_back(static_cast<long>(next->size()));
    volumes.push_back(volume);
    if (automatic && effective && volume > kVolumeRatio * volumes[level]) break;
    effective = effective || volume <= kEffectiveRatio * volumes[level];
    cells = std::move(*next);
    ++level;
  }
  if (stats) {
    stats->depth = level;
    stats->boxesTested = builder.tested();
    stats->keptPerLevel = counts;
    stats->keptVolumeFraction = volumes;
  }
  std::vector<Cell> out;
  out.reserve(cells.size());
  for (const Node& n : cells) out.push_back(builder.worldBox(n));
  glm::ivec3 grid(1);
  if (!cells.empty())
    for (int a = 0; a < 3; ++a) grid[a] = 1 << cells.front().splits[a];
  const bool small = static_cast<double>(grid.x) * grid.y <= (1 << 20) &&
                     static_cast<double>(grid.y) * grid.z <= (1 << 20) &&
                     static_cast<double>(grid.z) * grid.x <= (1 << 20);
  const double coverage = small ? rayCoverage(out, grid, lo, hi, sphere) : -1.0;
  if (stats) {
    stats->grid = grid;
    stats->rayCoverage = coverage;
  }
  // Cells that cannot cull: one cell for the whole region (see "Automatic depth").
  if (automatic && coverage > kMaxCoverage && !root.empty()) {
    if (stats) {
      stats->depth = 0;
      stats->grid = glm::ivec3(1);
    }
    return {builder.worldBox(root.front())};
  }
  return out;
}

// ---- Ray / box ------------------------------------------------------------------------
std::optional<RaySpan> clipRayToBox(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo,
                                    const glm::dvec3& hi, double tMin, double tMax) {
  if (!(tMin <= tMax)) return std::nullopt;  // also NaN
  double t0 = tMin, t1 = tMax;
  for (int a = 0; a < 3; ++a) {
    if (std::isnan(o[a]) || std::isnan(d[a])) return std::nullopt;
    // A zero component (either sign; under DAZ also a subnormal one, as the adapter's
    // clipToBox reads it): the closed slab is all or nothing. Through 1/d it was not for
    // -0 with the origin on a face: 0 / -0 = NaN and 1 / -0 = -inf left the span empty.
    if (d[a] == 0.0) {
      if (!(lo[a] <= o[a] && o[a] <= hi[a])) return std::nullopt;
      continue;
    }
    // A subnormal d_a below 2^-1024 has an infinite reciprocal but finite quotients (an
    // origin within a few d_a of a face crosses it): those divide (the same two roundings).
    const double inv = 1.0 / d[a];
    double tNear, tFar;
    if (std::isinf(inv)) [[unlikely]] {
      tNear = (lo[a] - o[a]) / d[a];
      tFar = (hi[a] - o[a]) / d[a];
    } else {
      tNear = (lo[a] - o[a]) * inv;
      tFar = (hi[a] - o[a]) * inv;
    }
    if (tNear > tFar) std::swap(tNear, tFar);
    // Both ends widened by 2 gamma(3) of their magnitude: the subtraction and the
    // product each round once (pbrt-v4 widens tFar only; a widened tNear also keeps a
    // root on the entry face inside the span).
    // (A product, not an added term: inf stays inf instead of becoming inf - inf.) And
    // two subnormal units: below 2^-1022 the quotient's rounding is absolute, not relative
    // ((0 - (-3 2^-1074)) / 2 = 1.5 2^-1074 rounds to 2^-1073, which the factor keeps).
    tNear = tNear * (tNear > 0 ? 1 - 2 * gamma(3) : 1 + 2 * gamma(3)) - 0x1p-1073;
    tFar = tFar * (tFar > 0 ? 1 + 2 * gamma(3) : 1 - 2 * gamma(3)) + 0x1p-1073;
    t0 = tNear > t0 ? tNear : t0;
    t1 = tFar < t1 ? tFar : t1;
    if (t0 > t1) return std::nullopt;
  }
  return RaySpan{t0, t1};
}

}  // namespace algray
