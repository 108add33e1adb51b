#pragma once
// Marching cubes (Lorensen & Cline, "Marching cubes: a high resolution 3D surface
// construction algorithm", SIGGRAPH 1987) of an algebraic surface f = 0 inside a clip
// sphere: the triangle tessellation that tests/bench/speed_report.cpp traces beside the
// exact surface. Header-only (the bench CMake builds one executable per *_report.cpp).
//
// The case table is not copied: it is derived at start-up from the algorithm itself
// (marchingCubesTable below). For each of the 256 sign patterns of a cube's corners:
//   1. on every face, the edges where the sign changes are joined pairwise by segments
//      that cut off each run of inside corners (f < 0). A face with 4 crossings (the
//      ambiguous face of Duerst, "Letters: additional reference to marching cubes",
//      Computer Graphics 22(2), 1988) thus separates its two inside corners. The rule
//      depends only on the face's own four signs, so the two cubes sharing a face cut it
//      the same way and the mesh has no cracks;
//   2. segments are directed by walking each face counter-clockwise seen from outside
//      the cube (exit edge of an inside run -> entry edge of the same run). A shared cube
//      edge is walked in opposite directions by its two faces, so every crossing edge
//      starts exactly one segment and ends exactly one: the segments chain into loops;
//   3. each loop (3 to 7 crossings, as in the classic 15 cases) becomes a triangle fan.
// Vertices lie on grid edges by linear interpolation of f and are shared between the
// cubes of an edge, so the mesh is indexed (about half as many vertices as triangles).
//
// Evaluating f at the grid points is the cost of a fine grid (10^8 points for 1M
// triangles), so f is never evaluated point by point: per z slice it is restricted to a
// bivariate polynomial in (x, y), per grid row to a univariate one in x, and that is
// evaluated by Horner at the row's points (cost per point: degree multiply-adds).
#include "algray/polynomial.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace algray::bench {

// ---- Case table ------------------------------------------------------------------------
// Corner c of the unit cube has coordinates (c & 1, c >> 1 & 1, c >> 2 & 1). Edge e joins
// corners kEdgeCorner[e][0] < kEdgeCorner[e][1]; they differ in bit kEdgeAxis[e].
struct McTable {
  std::array<std::array<int, 2>, 12> edgeCorner{};
  std::array<int, 12> edgeAxis{};
  // Per case: triangles as triples of edge indices, terminated by -1 (at most 5 triangles).
  std::array<std::array<std::int8_t, 16>, 256> triangles{};
};

inline McTable marchingCubesTable() {
  McTable t;
  int edgeOf[8][8];
  for (auto& row : edgeOf)
    for (int& e : row) e = -1;
  int e = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int c = 0; c < 8; ++c)
      if (!(c >> axis & 1)) {
        const int c1 = c | 1 << axis;
        t.edgeCorner[e] = {c, c1};
        t.edgeAxis[e] = axis;
        edgeOf[c][c1] = edgeOf[c1][c] = e;
        ++e;
      }
  // Faces: axis a, side s; corners counter-clockwise seen from outside. With (b, c) the
  // next two axes cyclically (e_b x e_c = e_a), the order (0,0) (1,0) (1,1) (0,1) in (b, c)
  // is counter-clockwise about +e_a; the face at s = 0 has outward normal -e_a: reversed.
  std::array<std::array<int, 4>, 6> faces{};
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      auto corner = [&](int ub, int uc) { return s << a | ub << b | uc << c; };
      faces[2 * a + s] =
          s ? std::array<int, 4>{corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)}
            : std::array<int, 4>{corner(0, 0), corner(0, 1), corner(1, 1), corner(1, 0)};
    }
  for (int mask = 0; mask < 256; ++mask) {
    auto inside = [&](int corner) { return (mask >> corner & 1) != 0; };
    // ---- 1-2. Directed segments: next[exit edge] = entry edge of the same inside run --
    std::array<int, 12> next;
    next.fill(-1);
    for (const auto& q : faces)
      for (int m = 0; m < 4; ++m) {
        if (!inside(q[m]) || inside(q[(m + 1) % 4])) continue;  // not an exit edge
        int r = m;  // walk back to the first corner of this inside run
        while (inside(q[(r + 3) % 4])) r = (r + 3) % 4;
        next[edgeOf[q[m]][q[(m + 1) % 4]]] = edgeOf[q[(r + 3) % 4]][q[r]];
      }
    // ---- 3. Loops, each as a triangle fan ------------------------------------------------
    std::array<bool, 12> used{};
    int n = 0;
    for (int start = 0; start < 12; ++start) {
      if (next[start] < 0 || used[start]) continue;
      std::array<int, 12> loop{};
      int len = 0;
      for (int edge = start; !used[edge]; edge = next[edge]) {
        used[edge] = true;
        loop[len++] = edge;
      }
      for (int i = 1; i + 1 < len; ++i) {
        t.triangles[mask][n++] = static_cast<std::int8_t>(loop[0]);
        t.triangles[mask][n++] = static_cast<std::int8_t>(loop[i]);
        t.triangles[mask][n++] = static_cast<std::int8_t>(loop[i + 1]);
      }
    }
    for (int i = n; i < 16; ++i) t.triangles[mask][i] = -1;
  }
  return t;
}

// ---- Grid evaluation -------------------------------------------------------------------
// f restricted to z = const: b[i][j] coefficients of x^i y^j (dense, (n+1)^2).
inline std::vector<double> restrictToZ(const Polynomial& f, double z) {
  const int n = std::max(f.degree(), 0);
  std::vector<double> zp(n + 1, 1.0), b((n + 1) * (n + 1), 0.0);
  for (int k = 1; k <= n; ++k) zp[k] = zp[k - 1] * z;
  for (int m = 0; m <= f.degree(); ++m)
    forEachMonomialOfDegree(
        m, [&](int i, int j, int k, int idx) { b[i * (n + 1) + j] += f.coeffs()[idx] * zp[k]; });
  return b;
}

// ---- The mesh --------------------------------------------------------------------------
struct TriangleMesh {
  std::vector<glm::vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// Marching cubes of f over the box [c - r, c + r]^3 with `cells` cubes per axis, keeping
// the cubes whose centre lies inside the clip sphere (c, r). Processes one slab of cubes
// at a time (two slices of values), so memory is O(cells^2) besides the mesh.
inline TriangleMesh marchingCubes(const Polynomial& f, const glm::dvec3& c, double r, int cells) {
  static const McTable table = marchingCubesTable();
  const int n = cells, np = n + 1, deg = std::max(f.degree(), 0);
  const double h = 2.0 * r / n;
  auto coord = [&](int axis, int i) { return c[axis] - r + h * i; };
  // Grid points needed: corners of cubes whose centre is inside, i.e. within r + sqrt(3)/2 h.
  const double reach = r + 0.87 * h;
  TriangleMesh mesh;
  std::vector<double> slice[2] = {std::vector<double>(np * np), std::vector<double>(np * np)};
  std::vector<double> row(deg + 1);
  auto evaluateSlice = [&](int k, std::vector<double>& out) {
    const double z = coord(2, k), dz = z - c.z;
    const std::vector<double> b = restrictToZ(f, z);
    for (int j = 0; j < np; ++j) {
      const double y = coord(1, j), dy = y - c.y;
      const double rest = reach * reach - dy * dy - dz * dz;
      double* v = &out[j * np];
      if (rest < 0.0) {
        for (int i = 0; i < np; ++i) v[i] = NAN;
        continue;
      }
      // Row polynomial a_i = sum_j b[i][j] y^j (Horner in y), then Horner in x.
      for (int i = 0; i <= deg; ++i) {
        double s = 0.0;
        for (int jj = deg - i; jj >= 0; --jj) s = s * y + b[i * (deg + 1) + jj];
        row[i] = s;
      }
      const double half = std::sqrt(rest);
      for (int i = 0; i < np; ++i) {
        const double x = coord(0, i);
        if (std::abs(x - c.x) > half) {
          v[i] = NAN;
          continue;
        }
        double s = 0.0;
        for (int m = deg; m >= 0; --m) s = s * x + row[m];
        v[i] = s;
      }
    }
  };
  // Vertex ids of grid edges: x and y edges on the two slices, z edges of the slab.
  std::vector<std::int32_t> xEdge[2] = {std::vector<std::int32_t>(np * np, -1),
                                        std::vector<std::int32_t>(np * np, -1)};
  std::vector<std::int32_t> yEdge[2] = {std::vector<std::int32_t>(np * np, -1),
                                        std::vector<std::int32_t>(np * np, -1)};
  std::vector<std::int32_t> zEdge(np * np, -1);
  evaluateSlice(0, slice[0]);
  for (int k = 0; k < n; ++k) {
    evaluateSlice(k + 1, slice[1]);
    std::fill(zEdge.begin(), zEdge.end(), -1);
    std::fill(xEdge[1].begin(), xEdge[1].end(), -1);
    std::fill(yEdge[1].begin(), yEdge[1].end(), -1);
    const double zc = coord(2, k) + 0.5 * h - c.z;
    for (int j = 0; j < n; ++j) {
      const double yc = coord(1, j) + 0.5 * h - c.y;
      for (int i = 0; i < n; ++i) {
        const double xc = coord(0, i) + 0.5 * h - c.x;
        if (xc * xc + yc * yc + zc * zc > r * r) continue;
        // ---- Corner values and case ------------------------------------------------
        double v[8];
        int mask = 0;
        for (int q = 0; q < 8; ++q) {
          v[q] = slice[q >> 2 & 1][(j + (q >> 1 & 1)) * np + i + (q & 1)];
          if (v[q] < 0.0) mask |= 1 << q;
        }
        if (mask == 0 || mask == 255) continue;
        // ---- Edge vertices (shared with the neighbouring cubes) ---------------------
        auto vertex = [&](int e) -> std::uint32_t {
          const int q0 = table.edgeCorner[e][0], q1 = table.edgeCorner[e][1];
          const int ii = i + (q0 & 1), jj = j + (q0 >> 1 & 1), kk = q0 >> 2 & 1;
          std::int32_t* id = nullptr;
          switch (table.edgeAxis[e]) {
            case 0:
              id = &xEdge[kk][jj * np + ii];
              break;
            case 1:
              id = &yEdge[kk][jj * np + ii];
              break;
            default:
              id = &zEdge[jj * np + ii];
              break;
          }
          if (*id < 0) {
            const double s = v[q0] / (v[q0] - v[q1]);
            glm::dvec3 p{coord(0, ii), coord(1, jj), coord(2, k + kk)};
            p[table.edgeAxis[e]] += s * h;
            *id = static_cast<std::int32_t>(mesh.vertices.size());
            mesh.vertices.push_back(glm::vec3(p));
          }
          return static_cast<std::uint32_t>(*id);
        };
        const auto& tri = table.triangles[mask];
        for (int t = 0; t < 16 && tri[t] >= 0; t += 3)
          mesh.triangles.push_back({vertex(tri[t]), vertex(tri[t + 1]), vertex(tri[t + 2])});
      }
    }
    std::swap(slice[0], slice[1]);
    std::swap(xEdge[0], xEdge[1]);
    std::swap(yEdge[0], yEdge[1]);
  }
  return mesh;
}

// Cubes per axis for about `target` triangles: the count grows like the surface area in
// cube faces, cells^2, so one coarse run fixes the constant.
inline int marchingCubesResolution(const Polynomial& f, const glm::dvec3& c, double r,
                                   double target) {
  const int coarse = 40;
  const double count = static_cast<double>(marchingCubes(f, c, r, coarse).triangles.size());
  if (!(count > 0.0)) return coarse;
  return std::max(4, static_cast<int>(std::lround(coarse * std::sqrt(target / count))));
}

}  // namespace algray::bench
