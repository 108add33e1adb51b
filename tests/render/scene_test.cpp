// Scene's guards for values that reach it without a loader's checks (SceneDesc built in
// code): rays Embree would reject and directions glm::normalize cannot normalise.
#include "scene.h"
#include "mesh.h"
#include "render.h"
#include "value_checks.h"

#include <gtest/gtest.h>

#include <algray/parser.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

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

}  // namespace
}  // namespace algray::render
