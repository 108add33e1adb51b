// Scene's guards for values that reach it without a loader's checks (SceneDesc built in
// code): rays Embree would reject and directions glm::normalize cannot normalise.
#include "scene.h"
#include "mesh.h"
#include "render.h"
#include "value_checks.h"

#include <gtest/gtest.h>

#include <algray/parser.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace algray::render {
namespace {

SceneDesc unitSphere() {
  SceneDesc s;
  s.settings.width = 8;
  s.settings.height = 8;
  s.settings.spp = 1;
  SurfaceItem item;
  item.label = "sphere";
  item.polynomial = parsePolynomial("x^2 + y^2 + z^2 - 1");
  item.clip = ClipSphere{glm::dvec3(0.0), 2.0};
  s.surfaces.push_back(item);
  return s;
}

// Embree asserts ray.valid() (|org|, |dir| <= 1.8e18 per component, no NaN) and aborted
// the process; such rays now see nothing.
TEST(Scene, RaysEmbreeWouldRejectMiss) {
  Scene scene(unitSphere());
  RayCounter counter;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // A sane ray hits, so the misses below are the guard's.
  EXPECT_TRUE(scene.intersect({0, -5, 0}, {0, 1, 0}, 0.0, counter).has_value());
  EXPECT_FALSE(scene.intersect({0, -1e19, 0}, {0, 1, 0}, 0.0, counter).has_value());
  EXPECT_FALSE(scene.intersect({0, -5, 0}, {0, 1e30, 0}, 0.0, counter).has_value());
  EXPECT_FALSE(scene.intersect({0, -5, 0}, {nan, 1, 0}, 0.0, counter).has_value());
  EXPECT_FALSE(scene.intersect({0, -5, 0}, {0, 1, 0}, nan, counter).has_value());
  EXPECT_TRUE(scene.occluded({0, -5, 0}, {0, 1, 0}, 0.0, 10.0, counter));
  EXPECT_FALSE(scene.occluded({0, -1e19, 0}, {0, 1, 0}, 0.0, 1e20, counter));
  EXPECT_FALSE(scene.occluded({nan, -5, 0}, {0, 1, 0}, 0.0, 10.0, counter));
}

// A camera far beyond Embree's range (the loaders refuse it; built here directly) renders
// the background instead of aborting.
TEST(Scene, FarCameraRendersWithoutAbort) {
  SceneDesc desc = unitSphere();
  desc.camera.position = {0, -1e19, 0};
  desc.hasBackground = true;
  desc.background = glm::dvec3(0.25);
  Scene scene(desc);
  Image image;
  render(scene, image);
  for (const glm::vec3& c : image.color) EXPECT_EQ(c, glm::vec3(0.25f));
}

// glm::normalize of a direction with components of 1e-160 (or 1e200) gives NaN: the
// light's direction must still be a unit vector.
TEST(Scene, DirectionalLightWithTinyOrHugeDirection) {
  for (double m : {1e-160, 1e-300, 1e200}) {
    SceneDesc desc = unitSphere();
    desc.directionalLights.push_back({glm::dvec3(m, -m, m), glm::dvec3(1.0)});
    Scene scene(desc);
    auto s = scene.sampleLight(0, {0, 0, 0}, {0.5, 0.5});
    ASSERT_TRUE(s.has_value()) << m;
    EXPECT_NEAR(glm::length(s->wi), 1.0, 1e-15) << m;
    EXPECT_NEAR(s->wi.x, 1 / std::sqrt(3.0), 1e-15) << m;
  }
}

// A scene of one triangle mesh (material 0, added here) and nothing else.
SceneDesc meshScene(const MeshData& mesh, const Material& material) {
  SceneDesc s;
  s.addMaterial(material);
  s.meshes.push_back({"mesh", mesh, glm::dmat4(1.0), 0, -1});
  return s;
}

// An emissive mesh is sampled uniformly by area (pbrt-v4 Sec. 4.4.2, 6.2): a triangle in
// proportion to its area, then a uniform point on it, with the solid-angle density d^2 /
// (cos * A) of the mesh's whole area A. Two triangles in z = 0 of areas 1/2 and 3/2 (A = 2):
// a quarter of the samples fall in the first, and their mean is the area-weighted centroid,
// (1/4) (1/3, 1/3, 0) + (3/4) (3, 1/3, 0) = (7/3, 1/3, 0). A stratified grid of u stands for
// uniform random numbers. Every triangle was sampled along one line (its CDF segment read
// as empty) and the mean missed the centroid by 0.1.
TEST(Scene, MeshLightsAreSampledUniformlyByArea) {
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {5, 0, 0}, {2, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  Material light;
  light.type = MaterialType::Emissive;
  light.emission = glm::dvec3(2.0, 1.0, 0.5);
  const Scene scene(meshScene(mesh, light));
  ASSERT_EQ(scene.lightCount(), 1);
  const glm::dvec3 p(1, 0.5, 2);
  const int n = 64;
  glm::dvec3 sum(0.0);
  int first = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const auto s = scene.sampleLight(0, p, {(i + 0.5) / n, (j + 0.5) / n});
      ASSERT_TRUE(s.has_value());
      const glm::dvec3 q = p + s->distance * s->wi;
      EXPECT_NEAR(q.z, 0.0, 1e-12);
      sum += q;
      first += q.x < 1.5;
      EXPECT_EQ(s->radiance, light.emission);
      EXPECT_FALSE(s->delta);
      // The normal is +-z: cos = |wi.z|.
      const double d2 = s->distance * s->distance;
      EXPECT_NEAR(s->pdf, d2 / (std::abs(s->wi.z) * 2.0), 1e-12 * s->pdf);
    }
  const glm::dvec3 mean = sum / double(n * n);
  EXPECT_EQ(first, n * n / 4);
  EXPECT_NEAR(mean.x, 7.0 / 3.0, 2e-3);
  EXPECT_NEAR(mean.y, 1.0 / 3.0, 2e-3);
}

// A triangle's hit interpolates its vertices' normals and uvs with the hit's barycentric
// coordinates: on (0,0,0), (1,0,0), (0,1,0) the point (x, y, 0) has weights 1 - x - y, x, y
// (the vertices' uvs are their x, y, so its uv is (x, y)). The shading normal is the
// normalised interpolation, turned into the geometric normal's hemisphere (Hit::ns): normals
// given against the winding are flipped, not used as they are.
TEST(Scene, TriangleHitsInterpolateNormalsAndUvsByPosition) {
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.normals = {{0, 0, 1}, {0.6, 0, 0.8}, {0, 0.6, 0.8}};
  mesh.triangles = {{0, 1, 2}};
  const double x = 0.2, y = 0.5;
  const glm::dvec3 interpolated = (1 - x - y) * mesh.normals[0] + x * mesh.normals[1] +
                                  y * mesh.normals[2];  // (0.12, 0.3, 0.86)
  RayCounter counter;
  {
    const Scene scene(meshScene(mesh, Material{}));
    const auto hit = scene.intersect({x, y, 1}, {0, 0, -1}, 0.0, counter);
    ASSERT_TRUE(hit.has_value());
    EXPECT_NEAR(hit->uv.x, x, 1e-6);
    EXPECT_NEAR(hit->uv.y, y, 1e-6);
    EXPECT_EQ(hit->ng, glm::dvec3(0, 0, 1));  // cross(p1 - p0, p2 - p0)
    const glm::dvec3 expected = glm::normalize(interpolated);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(hit->ns[k], expected[k], 1e-6) << k;
  }
  for (glm::dvec3& n : mesh.normals) n = -n;  // against the winding
  const Scene scene(meshScene(mesh, Material{}));
  const auto hit = scene.intersect({x, y, 1}, {0, 0, -1}, 0.0, counter);
  ASSERT_TRUE(hit.has_value());
  const glm::dvec3 expected = glm::normalize(interpolated);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(hit->ns[k], expected[k], 1e-6) << k;
}

// A material index must name one of the scene's materials: the count itself is one past
// the last (SceneDesc built in code; the loaders assign indices themselves).
TEST(Scene, MaterialIndexEqualToTheCountIsRefused) {
  MeshData mesh = makePlane(1.0);
  SceneDesc s = meshScene(mesh, Material{});
  s.meshes.front().material = 1;
  try {
    const Scene scene(s);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "mesh: material index out of range");
  }
  s.meshes.front().material = 0;
  s.meshes.front().backMaterial = 1;
  EXPECT_THROW(Scene{s}, std::runtime_error);
  s.meshes.front().backMaterial = 0;
  EXPECT_NO_THROW(Scene{s});
}

TEST(ValueChecks, SafeNormalize) {
  EXPECT_FALSE(safeNormalize(glm::dvec3(0.0)).has_value());
  EXPECT_FALSE(safeNormalize({std::numeric_limits<double>::infinity(), 0, 0}).has_value());
  EXPECT_FALSE(safeNormalize({std::numeric_limits<double>::quiet_NaN(), 1, 0}).has_value());
  auto v = safeNormalize({1e308, 1e308, 0});
  ASSERT_TRUE(v.has_value());
  EXPECT_NEAR(v->x, std::sqrt(0.5), 1e-15);
  EXPECT_TRUE(isFloatColor(glm::dvec3(3e38)));
  EXPECT_FALSE(isFloatColor(glm::dvec3(1e39)));
  EXPECT_FALSE(isFloatColor({1, -1e-300, 1}));
}

// tinyobjloader only warns about a face index beyond its list: a normal or uv index
// beyond the file's vn or vt lines was read past the end of the heap array (ASan).
TEST(ObjFile, IndicesBeyondTheListsAreErrors) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "algray_bad_index.obj";
  const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n";
  const std::pair<const char*, const char*> cases[] = {
      {"f 1//1 2//1 3//900\n", "normal index out of range"},
      {"f 1/1 2/1 3/7\n", "uv index out of range"},
      {"f 1/1/1 2/1/1 3/2/1\n", "uv index out of range"},
      {"f 1 2 9\n", "vertex index out of range"},
  };
  for (const auto& [face, expected] : cases) {
    std::ofstream(file) << vertices << face;
    try {
      loadObj(file.string());
      ADD_FAILURE() << face << ": no error";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
          << face << ": " << e.what();
    }
  }
  std::ofstream(file) << vertices << "f 1/1/1 2/1/1 3/1/1\n";
  EXPECT_EQ(loadObj(file.string()).triangles.size(), 1u);
  std::filesystem::remove(file);
}

// The message of loadObj on the OBJ text obj, its file's path shown as "case.obj", or ""
// when it loads. (A file per test: ctest runs them in parallel.)
std::string objError(const std::string& obj) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      (std::string("algray_") + ::testing::UnitTest::GetInstance()->current_test_info()->name() +
       ".obj");
  std::ofstream(file, std::ios::binary) << obj;
  std::string message;
  try {
    loadObj(file.string());
  } catch (const std::runtime_error& e) {
    message = e.what();
    if (message.rfind(file.string(), 0) == 0)
      message = "case.obj" + message.substr(file.string().size());
  }
  std::filesystem::remove(file);
  return message;
}

// A quad with a vertex index beyond the vertex list ("f 1 2 3 9", "f 1 2 3 -9" with 5
// vertices) was dropped by tinyobjloader's triangulation with a warning and rendered
// without it, exit code 0; the same index in a triangle was refused. Every polygon size,
// and an index to a vertex defined only below the face (tinyobjloader resolves a polygon
// at the next g, o or usemtl line, dropping it if the vertex has not come yet), is
// refused with its line.
TEST(ObjFile, VertexIndicesOutOfRangeAreErrorsInEveryPolygon) {
  const std::string vertices = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n";
  for (const char* face : {"f 1 2 9\n", "f 1 2 3 9\n", "f 1 2 3 -9\n", "f 1 2 3 4 9\n",
                           "f 1 2 3 4 -6\n", "f 9 1 2 3\n", "f 1 2 0x3 4\n"}) {
    const std::string message = objError(vertices + face);
    const bool bad = std::string(face).find('x') != std::string::npos;
    EXPECT_NE(message.find("case.obj:7: " +
                           std::string(bad ? "bad face index" : "vertex index out of range")),
              std::string::npos)
        << face << ": " << message;
  }
  EXPECT_NE(objError("f 1 2 3 4\ng later\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n")
                .find("case.obj:1: vertex index out of range"),
            std::string::npos);
  // The last vertex is -1, the first -5.
  EXPECT_EQ(objError(vertices + "f 1 2 3 -1\nf -5 -4 -3\n"), "");
}

// A negative normal or uv index reaching before the start of its list ("f 1//-9 2//-9
// 3//-9" with one vn) became an index below 0, which loadObj took for "no normal": every
// normal of the mesh was dropped, exit code 0 (a positive index beyond the list was
// refused).
TEST(ObjFile, NegativeNormalAndUvIndicesBeforeTheListAreErrors) {
  const std::string head = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n";
  const std::pair<const char*, const char*> cases[] = {
      {"f 1//-9 2//-9 3//-9\n", "7: normal index out of range"},
      {"f 1//-2 2//-2 3//-2\n", "7: normal index out of range"},  // n + idx = -1: "none"
      {"f 1/-7 3/-7 4/-7\n", "7: uv index out of range"},
      {"f 1/-1/-2 3/-1/-1 4/-1/-1\n", "7: normal index out of range"},
      {"f 1//2 2//1 3//1\n", "7: normal index out of range"},
  };
  for (const auto& [face, expected] : cases) {
    const std::string message = objError(head + face);
    EXPECT_NE(message.find(std::string("case.obj:") + expected), std::string::npos)
        << face << ": " << message;
  }
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "algray_neg.obj";
  std::ofstream(file) << head << "f 1/-1/-1 2/-1/-1 3/-1/-1\n";
  const MeshData m = loadObj(file.string());
  EXPECT_EQ(m.normals.size(), 3u);
  EXPECT_EQ(m.uvs.size(), 3u);
  std::filesystem::remove(file);
}

// OBJ lines end in "\n", "\r\n" or a lone "\r" (classic Mac) for tinyobjloader; the checks
// split at "\n" only. A CR-only file with a comment line first was one comment to them:
// "v abc 1 0", "v 0x1p3 1 0", "v 1 2" rendered (tinyobjloader read 0s) and "f 1 2
// 4294967299" rendered as "f 1 2 3", exit code 0; without the comment a valid CR-only
// file was refused as "'v' with 15 numbers". Every ending gives the same checks and lines.
TEST(ObjFile, EveryLineEndingIsCheckedAlike) {
  const std::pair<const char*, const char*> cases[] = {
      {"# exported\nv abc 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "2: 'abc'"},
      {"# exported\nv 0 0 0\nv 1 0 0\nv 0x1p3 1 0\nf 1 2 3\n", "4: '0x1p3'"},
      {"# exported\nv 0 0 0\nv 1 0 0\nv 1 2\nf 1 2 3\n", "4: 'v' with 2 numbers"},
      {"# exported\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4294967299\n", "6: bad face index"},
      {"# exported\n\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "6: vertex index out of range"},
  };
  for (const auto& [lf, expected] : cases) {
    for (const char* ending : {"\n", "\r\n", "\r"}) {
      std::string obj;
      for (const char c : std::string(lf))
        obj += c == '\n' ? std::string(ending) : std::string(1, c);
      const std::string message = objError(obj);
      EXPECT_NE(message.find(std::string("case.obj:") + expected), std::string::npos)
          << ::testing::PrintToString(obj) << ": " << message;
    }
  }
  for (const char* obj :
       {"v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3",
        "v 0 0 0\r\nv 1 0 0\rv 0 1 0\nf 1 2 3\r\n\r\n",
        "\n\r\r\nv 0 0 0\rv 1 0 0\rv 0 1 0\rf -3 -2 -1"})
    EXPECT_EQ(objError(obj), "") << ::testing::PrintToString(obj);
  // Lines and "\r\n" across the checker's 64 KiB blocks.
  for (const char* ending : {"\r\n", "\r"})
    for (size_t pad = 65520; pad < 65540; ++pad) {
      const std::string e = ending;
      const std::string obj = "#" + std::string(pad, 'x') + e + "v 0 0 0" + e + "v 1 0 0" + e +
                              "v abc 1 0" + e + "f 1 2 3" + e;
      const std::string message = objError(obj);
      EXPECT_NE(message.find("case.obj:4: 'abc'"), std::string::npos) << pad << ": " << message;
    }
}

// tinyobjloader keeps every "t" (tag) line with up to 8192 ints, floats and strings each,
// whatever the line gives: 2000 lines "t a 8192/8192/8192" (38 KB) took 1.9 GB. The
// renderer does not use tags; the lines are refused with their line number.
TEST(ObjFile, TagLinesAreRefused) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  for (const char* tag : {"t a 8192/8192/8192\n", "\tt crease 2/1/0 1 2 1.0\n"}) {
    const std::string message = objError(tri + tag);
    EXPECT_NE(message.find("case.obj:5: 't' (tag) lines are not supported"), std::string::npos)
        << tag << ": " << message;
  }
}

// A directory read as an empty file: ".: no triangles".
TEST(ObjFile, ADirectoryIsNamedAsSuch) {
  const std::string dir = std::filesystem::temp_directory_path().string();
  try {
    loadObj(dir);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": is a directory, not an OBJ file");
  }
}

// loadObj on the OBJ text obj (its own file per test, as objError's).
MeshData objMesh(const std::string& obj) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      (std::string("algray_") + ::testing::UnitTest::GetInstance()->current_test_info()->name() +
       ".obj");
  std::ofstream(file, std::ios::binary) << obj;
  MeshData m;
  try {
    m = loadObj(file.string());
  } catch (const std::runtime_error& e) {
    ADD_FAILURE() << e.what();
  }
  std::filesystem::remove(file);
  return m;
}

// The numbers loadObj returns are the file's (Wavefront OBJ: "v x y z", "vt u v", "vn i j
// k", a face of any number of corners "v/vt/vn", indices from 1 or, negative, back from the
// latest line): a 2 x 3 rectangle as one quad, vt k = (x / 2, y / 3) of v k, one normal of
// length 2 along +z. By hand: two triangles (the quad cut along a diagonal) of total area
// 6, counter-clockwise seen from +z as the face lists its corners, each corner at a written
// position with its own vt, every normal (0, 0, 1) (unit: the renderer interpolates and
// shades with them). 4 vt and 1 vn lines: the uv and normal counts differ.
TEST(ObjFile, ValuesAreReadAsWritten) {
  const std::string head =
      "v 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 2\n";
  for (const char* face :
       {"f 1/1/1 2/2/1 3/3/1 4/4/1\n", "f -4/-4/-1 -3/-3/-1 -2/-2/-1 -1/-1/-1\n"}) {
    const MeshData m = objMesh(head + face);
    ASSERT_EQ(m.triangles.size(), 2u) << face;
    ASSERT_EQ(m.normals.size(), m.positions.size()) << face;
    ASSERT_EQ(m.uvs.size(), m.positions.size()) << face;
    double area = 0;
    for (const auto& t : m.triangles) {
      const glm::dvec3 c =
          glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
      area += 0.5 * c.z;
      for (const unsigned i : t) {
        const glm::dvec3 p = m.positions[i];
        EXPECT_TRUE((p.x == 0 || p.x == 2) && (p.y == 0 || p.y == 3) && p.z == 0) << face;
        EXPECT_EQ(m.uvs[i], glm::dvec2(p.x / 2, p.y / 3)) << face;
        EXPECT_EQ(m.normals[i], glm::dvec3(0, 0, 1)) << face;
      }
    }
    EXPECT_EQ(area, 6.0) << face;
  }
}

// OBJ indexes positions, uvs and normals separately: one position with two vt in two
// faces is two vertices of the mesh, each with its own uv (a texture seam). The second
// face's corners all have vt 4 = (0.5, 0.5), the first's vt k = (x, y) of v k.
TEST(ObjFile, CornersWithOtherUvsStayApart) {
  const MeshData m = objMesh(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
      "f 1/1 2/2 3/3\nf 1/4 2/4 3/4\n");
  ASSERT_EQ(m.triangles.size(), 2u);
  ASSERT_EQ(m.uvs.size(), m.positions.size());
  for (const unsigned i : m.triangles[0])
    EXPECT_EQ(m.uvs[i], glm::dvec2(m.positions[i].x, m.positions[i].y));
  for (const unsigned i : m.triangles[1]) EXPECT_EQ(m.uvs[i], glm::dvec2(0.5, 0.5));
}

// Normals are per vertex for the whole mesh or not at all (mesh.h: empty = flat shading):
// a face whose first corners name no normal makes the mesh flat, whichever corner does.
TEST(ObjFile, CornersWithoutNormalsMakeTheMeshFlat) {
  for (const char* face : {"f 1 2 3//1\n", "f 1//1 2 3\n"}) {
    const MeshData m = objMesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\n" + std::string(face));
    EXPECT_EQ(m.triangles.size(), 1u) << face;
    EXPECT_TRUE(m.normals.empty()) << face;
  }
}

// An index beyond its list names the corner and how many lines of that kind the file has
// above the face (counted here by hand), so that the line to fix is clear.
TEST(ObjFile, OutOfRangeMessagesCountTheLinesAbove) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvn 0 0 1\n";
  const std::pair<std::string, std::string> cases[] = {
      {"f 1 2 3 4\ng later\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n",
       "case.obj:1: vertex index out of range in '1' (0 'v' lines above it)"},
      {"v 0 0 0\nf 1 2 3\n", "case.obj:2: vertex index out of range in '2' (1 'v' line above it)"},
      {tri + "f 1/3 2/1 3/1\n",
       "case.obj:7: uv index out of range in '1/3' (2 'vt' lines above it)"},
      {tri + "f 1//1 2//-2 3//1\n",
       "case.obj:7: normal index out of range in '2//-2' (1 'vn' line above it)"},
  };
  for (const auto& [obj, expected] : cases) EXPECT_EQ(objError(obj), expected) << obj;
}

// tinyobjloader splits a line's words at spaces and tabs only: "vn\v0 0 1" is no vn line to
// it, so a face naming that normal is refused with its line (it was the guard's error, no
// line), not counted against a normal it does not have.
TEST(ObjFile, OnlySpacesAndTabsSeparateWords) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (const char* line : {"vn\v0 0 1\n", "vn\f0 0 1\n"}) {
    const std::string message = objError(tri + line + "f 1//1 2//1 3//1\n");
    EXPECT_NE(message.find("case.obj:5: normal index out of range"), std::string::npos)
        << ::testing::PrintToString(line) << ": " << message;
  }
  // Within a line, "0\v0" is one word: two numbers, not three.
  EXPECT_EQ(objError(tri + "vn 0\v0 1\nf 1 2 3\n"), "case.obj:4: 'vn' with 2 numbers");
}

// A face's vertex indices are 0-based into positions: 3 is beyond 3 positions.
TEST(MeshData, ValidateRefusesIndexEqualToTheCount) {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 3}};
  EXPECT_THROW(m.validate("m"), std::runtime_error);
  m.triangles = {{0, 1, 2}};
  EXPECT_NO_THROW(m.validate("m"));
}

// After any invertible affine map a flat triangle's vertex normals must still be unit,
// perpendicular to the moved triangle and on the side its winding gives (cross(p1 - p0,
// p2 - p0)): the geometric facts a shading normal must keep. A shear (not symmetric, so
// the inverse and the inverse transpose differ), it with a mirror (determinant < 0), and
// non-uniform scales that change a normal's length.
TEST(MeshData, TransformKeepsNormalsPerpendicularAndWindingConsistent) {
  glm::dmat4 shear(1.0);
  shear[1][0] = 1.0;   // x += y
  shear[2][1] = -2.0;  // y -= 2 z
  shear[0][2] = 0.25;  // z += x / 4 (determinant 1 - 2 / 4 > 0)
  shear[3] = glm::dvec4(1, 2, 3, 1);
  glm::dmat4 mirror(1.0);
  mirror[0][0] = -3.0;
  glm::dmat4 scale(1.0);
  scale[0][0] = 2.0, scale[1][1] = 0.5;
  for (const glm::dmat4& map : {shear, shear * mirror, scale, mirror, mirror * scale}) {
    for (MeshData m : {makePlane(1.0), makeBox({1, 2, 3})}) {
      m.transform(map);
      for (const auto& t : m.triangles) {
        const glm::dvec3 c = glm::cross(m.positions[t[1]] - m.positions[t[0]],
                                        m.positions[t[2]] - m.positions[t[0]]);
        const glm::dvec3 g = c / glm::length(c);
        for (const unsigned i : t) {
          EXPECT_NEAR(glm::length(m.normals[i]), 1.0, 1e-12);
          EXPECT_NEAR(glm::dot(m.normals[i], g), 1.0, 1e-12);
        }
      }
    }
  }
}

// The box's faces and the icosphere's triangles wind counter-clockwise seen from outside
// (cross(p1 - p0, p2 - p0) along the outward direction of a convex solid about the
// origin), as their normals point; the box's normal is its face's.
TEST(MeshData, ShapesWindOutward) {
  const MeshData box = makeBox({1, 2, 3});
  for (const auto& t : box.triangles) {
    const glm::dvec3 c = glm::cross(box.positions[t[1]] - box.positions[t[0]],
                                    box.positions[t[2]] - box.positions[t[0]]);
    EXPECT_GT(glm::dot(c, box.positions[t[0]]), 0.0);
    for (const unsigned i : t)
      EXPECT_NEAR(glm::dot(box.normals[i], c / glm::length(c)), 1.0, 1e-15);
  }
  const MeshData sphere = makeIcosphere(2);
  for (const auto& t : sphere.triangles) {
    const glm::dvec3 c = glm::cross(sphere.positions[t[1]] - sphere.positions[t[0]],
                                    sphere.positions[t[2]] - sphere.positions[t[0]]);
    EXPECT_GT(glm::dot(c, sphere.positions[t[0]]), 0.0);
  }
}

// Twice a triangle list's area: the sum of |cross(p1 - p0, p2 - p0)|.
double twiceArea(const MeshData& m) {
  double sum = 0;
  for (const auto& t : m.triangles)
    sum += glm::length(
        glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
  return sum;
}

// mesh.h: the plane is the square [-half, half]^2 (area (2 half)^2) wound to face +z; the
// quad is the parallelogram corner + s edge1 + t edge2 (area |edge1 x edge2|), each of its
// triangles wound to face along cross(edge1, edge2) as its normal is said to.
TEST(MeshData, PlaneAndQuadCoverTheirAreaFacingTheirNormal) {
  const MeshData plane = makePlane(1.5);
  EXPECT_NEAR(twiceArea(plane), 2 * 3.0 * 3.0, 1e-12);
  for (const glm::dvec3& p : plane.positions) {
    EXPECT_EQ(std::abs(p.x), 1.5);
    EXPECT_EQ(std::abs(p.y), 1.5);
    EXPECT_EQ(p.z, 0.0);
  }
  const glm::dvec3 e1(2, 0, 1), e2(0, 3, 0);  // cross = (-3, 0, 6), length sqrt(45)
  const MeshData quad = makeQuad({1, -1, 2}, e1, e2);
  ASSERT_EQ(quad.triangles.size(), 2u);
  EXPECT_NEAR(twiceArea(quad), 2 * std::sqrt(45.0), 1e-12);
  for (const auto& t : quad.triangles) {
    const glm::dvec3 c = glm::cross(quad.positions[t[1]] - quad.positions[t[0]],
                                    quad.positions[t[2]] - quad.positions[t[0]]);
    EXPECT_GT(glm::dot(c, glm::cross(e1, e2)), 0.0);
  }
}

// mesh.h: the box [-half, half]^3 has six faces of two triangles; each corner has
// |coordinate i| = half[i], and the faces cover 2 (ab + bc + ca) for the full extents
// a, b, c = 2, 4, 6: 88.
TEST(MeshData, BoxHasSixFacesOnItsCorners) {
  const MeshData box = makeBox({1, 2, 3});
  EXPECT_EQ(box.triangles.size(), 12u);
  for (const glm::dvec3& p : box.positions)
    for (int i = 0; i < 3; ++i) EXPECT_EQ(std::abs(p[i]), i + 1.0) << i;
  EXPECT_NEAR(twiceArea(box), 2 * 88.0, 1e-12);
}

// Each subdivision splits every triangle in four, from the icosahedron's 20: 20 * 4^n
// triangles, every vertex on the unit sphere (its normal the position), and together
// they close around the centre: the solid angles of the triangles seen from the
// origin (Van Oosterom-Strackee) add up to the whole sphere, 4 pi.
TEST(MeshData, IcosphereIsAClosedUnitSphereOfTwentyTimesFourToTheN) {
  for (int sub : {0, 1, 2, 3}) {
    const MeshData m = makeIcosphere(sub);
    EXPECT_EQ(m.triangles.size(), 20u << (2 * sub)) << sub;
    for (size_t i = 0; i < m.positions.size(); ++i) {
      EXPECT_NEAR(glm::length(m.positions[i]), 1.0, 1e-15) << sub;
      EXPECT_NEAR(glm::length(m.normals[i] - m.positions[i]), 0.0, 1e-15) << sub;
    }
    double solidAngle = 0;
    for (const auto& t : m.triangles) {
      const glm::dvec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
      solidAngle += 2 * std::atan2(glm::dot(a, glm::cross(b, c)),
                                   1 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a));
    }
    EXPECT_NEAR(solidAngle, 4 * std::numbers::pi, 1e-12) << sub;
  }
}

// mesh.h: the plane's uv is position / uvScale.
TEST(MeshData, PlaneUvIsPositionOverScale) {
  const MeshData m = makePlane(2.0, 4.0);
  ASSERT_EQ(m.uvs.size(), m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i)
    EXPECT_EQ(m.uvs[i], glm::dvec2(m.positions[i].x / 4, m.positions[i].y / 4));
}

// The icosphere's uv is the lat-long map (u = 1/2 + azimuth / 2 pi, v = 1 - polar angle /
// pi) on each triangle: across the azimuth seam a triangle's u runs the short way round
// (its span is the shortest arc of its corners' azimuths over 2 pi, never most of the
// image), and a pole corner, which has no azimuth, takes a u within its triangle's span.
// The reference arc is computed here from the positions alone.
TEST(MeshData, IcosphereUvFollowsEachTriangle) {
  for (int sub : {0, 1, 2, 3}) {
    const MeshData m = makeIcosphere(sub);
    for (const auto& t : m.triangles) {
      std::vector<double> az;
      double lo = 2, hi = -1;
      for (const unsigned i : t) {
        const glm::dvec3 p = m.positions[i];
        EXPECT_NEAR(m.uvs[i].y, 1.0 - std::acos(std::clamp(p.z, -1.0, 1.0)) / std::numbers::pi,
                    1e-12);
        lo = std::min(lo, m.uvs[i].x), hi = std::max(hi, m.uvs[i].x);
        if (p.x != 0 || p.y != 0) az.push_back(std::atan2(p.y, p.x));
      }
      // The shortest arc holding the azimuths: 2 pi less the largest gap between them.
      std::sort(az.begin(), az.end());
      double gap = az.front() + 2 * std::numbers::pi - az.back();
      for (size_t k = 1; k < az.size(); ++k) gap = std::max(gap, az[k] - az[k - 1]);
      EXPECT_NEAR(hi - lo, (2 * std::numbers::pi - gap) / (2 * std::numbers::pi), 1e-12) << sub;
    }
  }
}

// A v, vt, vn or f line with no numbers is malformed (OBJ: "v x y z", a face of 3 or more
// corners), even with a blank after its keyword: tinyobjloader read "v " as a vertex at
// the origin, which shifted every index after it.
TEST(ObjFile, KeywordsWithoutNumbersAreErrors) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::pair<const char*, const char*> cases[] = {
      {"v \n", "case.obj:4: 'v' with 0 numbers"},
      {"vn\t\n", "case.obj:4: 'vn' with 0 numbers"},
      {"vt \n", "case.obj:4: 'vt' with 0 numbers"},
      {"f \n", "case.obj:4: a face needs at least 3 vertices"},
  };
  for (const auto& [line, expected] : cases)
    EXPECT_EQ(objError(tri + line + "f 1 2 3\n"), expected) << ::testing::PrintToString(line);
}

// A file that cannot be opened is named with the reason on one line (tinyobjloader ends
// its message with a line break; the program prints the message with its own).
TEST(ObjFile, UnreadableFileIsOneLine) {
  const std::string path = "/nonexistent-dir/m.obj";
  try {
    loadObj(path);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": cannot read OBJ", 0), 0u) << message;
    EXPECT_EQ(message.find_first_of("\r\n"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace algray::render
