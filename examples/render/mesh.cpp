#include "mesh.h"

#include "sampling.h"
#include "text_lines.h"

#include <tiny_obj_loader.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <istream>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace algray::render {

void MeshData::validate(const std::string& what) const {
  auto finite = [](const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  for (const glm::dvec3& p : positions)
    if (!finite(p)) throw std::runtime_error(what + ": non-finite vertex position");
  if (!normals.empty() && normals.size() != positions.size())
    throw std::runtime_error(what + ": normal count differs from vertex count");
  if (!uvs.empty() && uvs.size() != positions.size())
    throw std::runtime_error(what + ": uv count differs from vertex count");
  for (const auto& t : triangles)
    for (unsigned i : t)
      if (i >= positions.size()) throw std::runtime_error(what + ": vertex index out of range");
  if (triangles.empty()) throw std::runtime_error(what + ": no triangles");
}

void MeshData::transform(const glm::dmat4& m) {
  glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
  for (glm::dvec3& p : positions) p = glm::dvec3(m * glm::dvec4(p, 1.0));
  for (glm::dvec3& n : normals) {
    glm::dvec3 t = normalMatrix * n;
    double len = glm::length(t);
    n = len > 0 ? t / len : t;
  }
  if (glm::determinant(glm::dmat3(m)) < 0)  // keep the winding consistent with normals
    for (auto& t : triangles) std::swap(t[1], t[2]);
}

MeshData makePlane(double half, double uvScale) {
  MeshData m;
  m.positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
  m.normals.assign(4, {0, 0, 1});
  for (const glm::dvec3& p : m.positions) m.uvs.push_back(glm::dvec2(p) / uvScale);
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

MeshData makeQuad(glm::dvec3 corner, glm::dvec3 edge1, glm::dvec3 edge2) {
  MeshData m;
  m.positions = {corner, corner + edge1, corner + edge1 + edge2, corner + edge2};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

MeshData makeBox(glm::dvec3 half) {
  MeshData m;
  // Six faces, four vertices each so that normals stay flat.
  for (int axis = 0; axis < 3; ++axis)
    for (int sign = -1; sign <= 1; sign += 2) {
      glm::dvec3 n(0.0);
      n[axis] = sign;
      int a = (axis + 1) % 3, b = (axis + 2) % 3;
      auto base = static_cast<unsigned>(m.positions.size());
      const double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (const auto& c : corners) {
        glm::dvec3 p(0.0);
        p[axis] = sign * half[axis];
        p[a] = c[0] * half[a];
        p[b] = c[1] * half[b];
        m.positions.push_back(p);
        m.normals.push_back(n);
        m.uvs.push_back({0.5 * (c[0] + 1), 0.5 * (c[1] + 1)});
      }
      if (sign > 0)
        m.triangles.push_back({base, base + 1, base + 2}),
            m.triangles.push_back({base, base + 2, base + 3});
      else
        m.triangles.push_back({base, base + 2, base + 1}),
            m.triangles.push_back({base, base + 3, base + 2});
    }
  m.convexClosed = true;
  return m;
}

MeshData makeIcosphere(int subdivisions) {
  // Icosahedron from the three orthogonal golden rectangles.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (glm::dvec3& p : v) p = glm::normalize(p);
  std::vector<std::array<unsigned, 3>> f = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<unsigned, unsigned>, unsigned> mid;
    auto midpoint = [&](unsigned a, unsigned b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      auto idx = static_cast<unsigned>(v.size() - 1);
      mid.emplace(key, idx);
      return idx;
    };
    std::vector<std::array<unsigned, 3>> next;
    for (const auto& tri : f) {
      unsigned a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]),
               c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    f = std::move(next);
  }
  // Texture coordinates as the environment reads a lat-long image, and as the renderer
  // reads an algebraic surface's: u = 1/2 + azimuth / 2pi, v = 1 - polar angle / pi (the
  // image's top row at +z). Shared vertices cannot hold them everywhere: a triangle across
  // the seam (azimuth +-pi, where u jumps from 1 to 0) gets copies of its corners on the
  // u < 1/2 side with u + 1, and a triangle at a pole (no azimuth) a copy of the pole with
  // its other corners' mean u. Until session 52 the seam's triangles interpolated u across
  // the whole image (a streak along -x).
  MeshData m;
  m.positions = v;
  for (const glm::dvec3& p : v)
    m.uvs.push_back({0.5 + std::atan2(p.y, p.x) / (2 * kPi),
                     1.0 - std::acos(std::clamp(p.z, -1.0, 1.0)) / kPi});
  std::map<std::pair<unsigned, double>, unsigned> copies;
  auto withU = [&](unsigned i, double u) {
    auto [it, added] = copies.try_emplace({i, u}, static_cast<unsigned>(m.positions.size()));
    if (added) {
      const glm::dvec3 position = m.positions[i];
      const double texV = m.uvs[i].y;
      m.positions.push_back(position);
      m.uvs.push_back({u, texV});
    }
    return it->second;
  };
  for (auto& tri : f) {
    bool pole[3];
    double u[3], lo = 1, hi = 0, sum = 0;
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3& p = v[tri[k]];
      pole[k] = p.x == 0 && p.y == 0;
      u[k] = m.uvs[tri[k]].x;
      if (!pole[k]) lo = std::min(lo, u[k]), hi = std::max(hi, u[k]);
    }
    for (int k = 0; k < 3; ++k) {
      if (pole[k]) continue;
      if (hi - lo > 0.5 && u[k] < 0.5) tri[k] = withU(tri[k], u[k] += 1);
      sum += u[k], ++n;
    }
    for (int k = 0; k < 3; ++k)
      if (pole[k] && n > 0) tri[k] = withU(tri[k], sum / n);
  }
  m.normals = m.positions;
  m.triangles = std::move(f);
  m.convexClosed = true;
  m.latLongUv = true;
  return m;
}

namespace {

// tinyobjloader reads what it can: "v inf 1 0", "v abc 1 0", "v 0x1p3 0 0", "v 0 1" (no
// z) and a face index beyond int all became 0 or some other vertex without a warning, and
// the mesh rendered as if the file were right. The lines it turns into geometry are
// checked here first, with their line numbers: every number of v, vn, vt must be a
// decimal literal ([+-]digits[.digits][e[+-]digits], what tinyobjloader parses) within
// float's range (what it stores); every face corner must be i, i/j, i//k or i/j/k with
// non-zero integers in int's range, each naming a v, vt or vn line above the face. The
// reading stays tinyobjloader's.
bool isDecimalLiteral(std::string_view t) {
  size_t i = 0;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  size_t digits = 0;
  while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i, ++digits;
  if (i < t.size() && t[i] == '.')
    for (++i; i < t.size() && std::isdigit(static_cast<unsigned char>(t[i])); ++i) ++digits;
  if (digits == 0) return false;
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    if (++i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    const size_t start = i;
    while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i;
    if (i == start) return false;
  }
  return i == t.size();
}

// tinyobjloader's blanks between a line's words: a line "vn\v0 0 1" or "\fv 1 0 0" is no
// vn or v line to it, so it must be none to the counts of v, vt and vn lines here that
// relative indices are checked against. (Not std::isspace: a library call per character,
// 5 % of loading a 74 MB OBJ.)
bool isBlank(char c) { return c == ' ' || c == '\t'; }

// The value of a face index: a non-zero integer in int's range (tinyobjloader reads it
// with atoi), or 0 when t is none. t comes from a word split at blanks, so strtoll's
// skipping of leading blanks never applies.
long long faceIndex(std::string_view t) {
  const std::string text(t);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  return !text.empty() && *end == '\0' && errno != ERANGE && v >= INT_MIN && v <= INT_MAX ? v : 0;
}

void checkObjText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return;  // tinyobjloader reports it
  // Split as tinyobjloader's safeGetline splits them (at "\n", "\r\n" and a lone "\r").
  algray::text::LineReader lines(in);
  std::string_view text;
  std::vector<std::string_view> items;
  // The v, vt and vn lines so far: an index names one of them, from the first (1) or back
  // from the last (-1). tinyobjloader resolves a negative index against these counts too;
  // one reaching before the first became an index below 0 that loadObj took for "no
  // normal" ("f 1//-9 2//-9 3//-9" with one vn dropped every normal of the mesh). A
  // polygon of 4 or more corners with an index beyond the list ("f 1 2 3 9" or "f 1 2 3
  // -9" with 3 vertices) was dropped by tinyobjloader's triangulation with a warning, and
  // it triangulates a polygon at the next g, o or usemtl line, with the vertices read by
  // then: a vertex defined below its face is refused for every face as well.
  long long counts[3] = {0, 0, 0};  // v, vt, vn
  const char* const names[3] = {"vertex", "uv", "normal"};
  const char* const kinds[3] = {"'v'", "'vt'", "'vn'"};
  while (lines.next(text)) {
    const long long lineNo = lines.number();
    items.clear();
    for (size_t i = 0; i < text.size();) {  // words separated by blanks
      while (i < text.size() && isBlank(text[i])) ++i;
      const size_t start = i;
      while (i < text.size() && !isBlank(text[i])) ++i;
      if (i == start || text[start] == '#') break;  // the rest is a comment
      items.push_back(text.substr(start, i - start));
    }
    if (items.empty()) continue;
    const std::string_view kind = items.front();
    auto fail = [&](const std::string& what) {
      throw std::runtime_error(path + ":" + std::to_string(lineNo) + ": " + what);
    };
    // tinyobjloader keeps every tag line with up to 8192 ints, floats and strings each,
    // whatever the line gives: 2000 lines "t a 8192/8192/8192" (38 KB) took 1.9 GB.
    if (kind == "t")
      fail("'t' (tag) lines are not supported (the renderer does not use them; remove them)");
    if (kind != "v" && kind != "vn" && kind != "vt" && kind != "f") continue;
    const size_t n = items.size() - 1;
    if (kind == "f") {
      if (n < 3) fail("a face needs at least 3 vertices");
      for (size_t k = 1; k <= n; ++k) {
        const std::string_view corner = items[k];
        const size_t a = corner.find('/'),
                     b = a == std::string_view::npos ? a : corner.find('/', a + 1);
        // The corner's v, vt and vn words (vt and vn may be absent).
        std::string_view parts[3];
        bool present[3] = {true, false, false};
        parts[0] = corner.substr(0, a);
        if (a != std::string_view::npos) {
          if (b == std::string_view::npos) {
            parts[1] = corner.substr(a + 1), present[1] = true;
          } else {
            if (b != a + 1) parts[1] = corner.substr(a + 1, b - a - 1), present[1] = true;
            parts[2] = corner.substr(b + 1), present[2] = true;
          }
        }
        long long index[3] = {0, 0, 0};
        for (int p = 0; p < 3; ++p)
          if (present[p] && (index[p] = faceIndex(parts[p])) == 0)
            fail("bad face index '" + std::string(corner) + "'");
        for (int p = 0; p < 3; ++p)
          if (present[p] && std::llabs(index[p]) > counts[p])
            fail(std::string(names[p]) + " index out of range in '" + std::string(corner) + "' (" +
                 std::to_string(counts[p]) + " " + kinds[p] +
                 (counts[p] == 1 ? " line" : " lines") + " above it)");
      }
      continue;
    }
    const bool countOk = kind == "v"    ? (n == 3 || n == 4 || n == 6 || n == 7)
                         : kind == "vn" ? n == 3
                                        : (n >= 1 && n <= 3);
    if (!countOk) fail("'" + std::string(kind) + "' with " + std::to_string(n) + " numbers");
    for (size_t k = 1; k <= n; ++k) {
      const std::string number(items[k]);
      if (!isDecimalLiteral(number) ||
          !(std::abs(std::strtod(number.c_str(), nullptr)) <= std::numeric_limits<float>::max()))
        fail("'" + number + "' is not a finite decimal number (in float's range)");
    }
    ++counts[kind == "v" ? 0 : kind == "vt" ? 1 : 2];
  }
}

}  // namespace

MeshData loadObj(const std::string& path) {
  // An ifstream opens a directory and reads nothing: it was ".: no triangles".
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw std::runtime_error(path + ": is a directory, not an OBJ file");
  checkObjText(path);
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    std::string err = reader.Error();
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    throw std::runtime_error(path + ": cannot read OBJ" + (err.empty() ? "" : ": " + err));
  }
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  MeshData m;
  // OBJ indexes positions, normals and uvs separately; make one vertex per distinct
  // (position, normal, uv) triple.
  std::map<std::array<int, 3>, unsigned> remap;
  // An index below 0 is an absent normal or uv: checkObjText refused the negative ones
  // reaching before their list, which tinyobjloader turned into indices below 0 as well.
  bool allNormals = true, allUvs = true;
  for (const tinyobj::shape_t& shape : reader.GetShapes())
    for (const tinyobj::index_t& idx : shape.mesh.indices) {
      allNormals = allNormals && idx.normal_index >= 0;
      allUvs = allUvs && idx.texcoord_index >= 0;
    }
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& indices = shape.mesh.indices;
    for (size_t i = 0; i + 2 < indices.size(); i += 3) {
      std::array<unsigned, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const tinyobj::index_t& idx = indices[i + k];
        std::array<int, 3> key{idx.vertex_index, allNormals ? idx.normal_index : -1,
                               allUvs ? idx.texcoord_index : -1};
        auto it = remap.find(key);
        if (it == remap.end()) {
          // tinyobjloader only warns about an index beyond its list: every index is checked
          // before it is read (a normal or uv index was not: "f 1//900" read past the heap).
          // checkObjText refuses such an index first, with its line; this guards the reads.
          if (idx.vertex_index < 0 ||
              3 * static_cast<size_t>(idx.vertex_index) + 2 >= attrib.vertices.size())
            throw std::runtime_error(path + ": vertex index out of range");
          if (allNormals && 3 * static_cast<size_t>(idx.normal_index) + 2 >= attrib.normals.size())
            throw std::runtime_error(path + ": normal index out of range");
          if (allUvs && 2 * static_cast<size_t>(idx.texcoord_index) + 1 >= attrib.texcoords.size())
            throw std::runtime_error(path + ": uv index out of range");
          const float* p = &attrib.vertices[3 * static_cast<size_t>(idx.vertex_index)];
          m.positions.push_back({p[0], p[1], p[2]});
          if (allNormals) {
            const float* n = &attrib.normals[3 * static_cast<size_t>(idx.normal_index)];
            glm::dvec3 nn(n[0], n[1], n[2]);
            double len = glm::length(nn);
            m.normals.push_back(len > 0 ? nn / len : nn);
          }
          if (allUvs) {
            const float* t = &attrib.texcoords[2 * static_cast<size_t>(idx.texcoord_index)];
            m.uvs.push_back({t[0], t[1]});
          }
          it = remap.emplace(key, static_cast<unsigned>(m.positions.size() - 1)).first;
        }
        tri[k] = it->second;
      }
      m.triangles.push_back(tri);
    }
  }
  m.validate(path);
  return m;
}

}  // namespace algray::render
