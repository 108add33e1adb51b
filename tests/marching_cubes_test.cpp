// Tests of tests/bench/marching_cubes.h, the tessellation the speed report compares
// against: the derived case table against the definition of a marching-cubes case
// (computed again here from corner signs), and meshes of closed surfaces against their
// topology (watertight, consistently oriented, Euler characteristic) and closed-form
// geometry (distance to the sphere, its area 4 pi).
#include "bench/marching_cubes.h"

#include "algray/gallery.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <utility>

namespace algray::bench {
namespace {

// ---- Case table ---------------------------------------------------------------------------
TEST(MarchingCubesTable, UsesExactlyTheEdgesWhereTheSignChanges) {
  const McTable t = marchingCubesTable();
  for (int mask = 0; mask < 256; ++mask) {
    std::set<int> expected, used;
    for (int e = 0; e < 12; ++e) {
      const int a = t.edgeCorner[e][0], b = t.edgeCorner[e][1];
      ASSERT_EQ(__builtin_popcount(a ^ b), 1) << "edge " << e;
      if ((mask >> a & 1) != (mask >> b & 1)) expected.insert(e);
    }
    int n = 0;
    for (; n < 16 && t.triangles[mask][n] >= 0; ++n) used.insert(t.triangles[mask][n]);
    EXPECT_EQ(n % 3, 0) << "case " << mask;
    EXPECT_LE(n / 3, 5) << "case " << mask;  // the classic bound of the 15 cases
    EXPECT_EQ(used, expected) << "case " << mask;
  }
}

// Every side of a case's triangles is either shared by two of its triangles (a fan
// diagonal) or a boundary segment, and a boundary segment must join two cube edges of one
// face (it lies in that face), each crossing edge ending exactly two boundary segments.
TEST(MarchingCubesTable, PolygonBoundariesRunAlongCubeFaces) {
  const McTable t = marchingCubesTable();
  auto corners = [&](int e) { return std::set<int>{t.edgeCorner[e][0], t.edgeCorner[e][1]}; };
  auto shareFace = [&](int e0, int e1) {
    // Two edges lie in one face iff their four corners agree in some coordinate bit.
    std::set<int> all = corners(e0);
    for (int c : corners(e1)) all.insert(c);
    for (int bit = 0; bit < 3; ++bit) {
      int ones = 0;
      for (int c : all) ones += c >> bit & 1;
      if (ones == 0 || ones == static_cast<int>(all.size())) return true;
    }
    return false;
  };
  for (int mask = 1; mask < 255; ++mask) {
    std::map<std::pair<int, int>, int> sides;
    for (int n = 0; n < 16 && t.triangles[mask][n] >= 0; n += 3)
      for (int k = 0; k < 3; ++k) {
        const int a = t.triangles[mask][n + k], b = t.triangles[mask][n + (k + 1) % 3];
        ++sides[{std::min(a, b), std::max(a, b)}];
      }
    std::map<int, int> boundaryDegree;
    for (const auto& [side, count] : sides) {
      ASSERT_LE(count, 2) << "case " << mask;
      if (count == 2) continue;
      EXPECT_TRUE(shareFace(side.first, side.second))
          << "case " << mask << " edges " << side.first << " " << side.second;
      ++boundaryDegree[side.first];
      ++boundaryDegree[side.second];
    }
    for (const auto& [edge, degree] : boundaryDegree)
      EXPECT_EQ(degree, 2) << "case " << mask << " edge " << edge;
  }
}

// ---- Meshes ---------------------------------------------------------------------------------
struct Topology {
  bool closedOriented = true;  // every directed edge once, its reverse once
  long euler = 0;              // V - E + F
};

Topology topology(const TriangleMesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  Topology out;
  for (const auto& [e, count] : directed) {
    const auto reverse = directed.find({e.second, e.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) out.closedOriented = false;
  }
  out.euler = static_cast<long>(m.vertices.size()) - static_cast<long>(directed.size() / 2) +
              static_cast<long>(m.triangles.size());
  return out;
}

TEST(MarchingCubes, SphereIsAClosedSphereCloseToTheTrueOne) {
  const Polynomial f = findGallerySurface("sphere")->build();  // x^2 + y^2 + z^2 - 1
  const double r = 1.2;
  const int cells = 40;
  const double h = 2 * r / cells;
  const TriangleMesh m = marchingCubes(f, glm::dvec3(0.0), r, cells);
  ASSERT_GT(m.triangles.size(), 1000u);
  const Topology top = topology(m);
  EXPECT_TRUE(top.closedOriented);
  EXPECT_EQ(top.euler, 2);
  // Linear interpolation of |p|^2 - 1 along an edge misses the sphere by O(h^2).
  double area = 0.0;
  for (const auto& v : m.vertices) EXPECT_NEAR(glm::length(glm::dvec3(v)), 1.0, h * h);
  for (const auto& t : m.triangles) {
    const glm::dvec3 a(m.vertices[t[0]]), b(m.vertices[t[1]]), c(m.vertices[t[2]]);
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  EXPECT_NEAR(area, 4 * std::numbers::pi, 0.01 * 4 * std::numbers::pi);
}

TEST(MarchingCubes, TorusHasEulerCharacteristicZero) {
  const TriangleMesh m =
      marchingCubes(findGallerySurface("torus")->build(), glm::dvec3(0.0), 1.6, 48);
  const Topology top = topology(m);
  EXPECT_TRUE(top.closedOriented);
  EXPECT_EQ(top.euler, 0);
}

// The Chmutov octic lies inside [-1, 1]^3 (|T8| <= 1 there and T8 > 1 outside, so the sum
// + 1 cannot vanish beyond), well inside its clip sphere: a closed surface with many
// saddles, i.e. many ambiguous faces.
TEST(MarchingCubes, ChmutovOcticIsClosed) {
  const TriangleMesh m =
      marchingCubes(findGallerySurface("chmutov-8")->build(), glm::dvec3(0.0), 1.75, 60);
  ASSERT_GT(m.triangles.size(), 1000u);
  EXPECT_TRUE(topology(m).closedOriented);
}

TEST(MarchingCubes, ResolutionGivesAboutTheRequestedCount) {
  const Polynomial f = findGallerySurface("barth-sextic")->build();
  const int cells = marchingCubesResolution(f, glm::dvec3(0.0), 2.0, 50000);
  const double count =
      static_cast<double>(marchingCubes(f, glm::dvec3(0.0), 2.0, cells).triangles.size());
  EXPECT_GT(count, 0.7 * 50000);
  EXPECT_LT(count, 1.3 * 50000);
}

}  // namespace
}  // namespace algray::bench
