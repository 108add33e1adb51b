// SURFER/jsurf import of the shared gallery files.
#include "render.h"
#include "scene.h"
#include "scene_builders.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

namespace algray::render {
namespace {

const std::filesystem::path kJsurfDir = std::filesystem::path(ALGRAY_SHARED_DIR) / "gallery" / "jsurf";

Image renderSmall(SceneDesc desc, int size, int spp = 1) {
  desc.settings.width = size;
  desc.settings.height = size;
  desc.settings.spp = spp;
  Scene scene(desc);
  Image image;
  render(scene, image);
  return image;
}

TEST(JsurfImport, EverySharedFileImportsAndShowsItsSurface) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kJsurfDir)) {
    if (entry.path().extension() != ".jsurf") continue;
    SCOPED_TRACE(entry.path().filename().string());
    ++files;
    SceneDesc desc = jsurfScene(entry.path());
    ASSERT_EQ(desc.surfaces.size(), 1u);
    EXPECT_EQ(desc.camera.type, CameraDesc::Type::Orthographic);
    EXPECT_GE(desc.directionalLights.size(), 1u);
    Image image = renderSmall(desc, 32);
    int covered = 0;
    for (float id : image.id) covered += id > 0;
    // The surface is visible, and SURFER's clip sphere leaves the corners to the
    // background (the unit circle covers pi/4 of the square view).
    EXPECT_GT(covered, 0);
    EXPECT_LT(covered, static_cast<int>(std::numbers::pi / 4 * 32 * 32) + 32);
    EXPECT_EQ(image.id[0], 0.0f);
    EXPECT_EQ(glm::dvec3(image.color[0]), desc.background);
  }
  EXPECT_GE(files, 20);
}

TEST(JsurfImport, SphereHasTheSizeScaleFactorGives) {
  // tutorial_kugel: x^2+y^2+z^2 = a^2 with a = 1, scale_factor s: surface coordinates are
  // 10^s times view coordinates, so the sphere's outline is a circle of radius 10^-s in a
  // view of height 2: it covers pi 10^(-2s) / 4 of the square image.
  std::filesystem::path file = kJsurfDir / "tutorial_kugel.jsurf";
  SceneDesc desc = jsurfScene(file);
  const int n = 200;
  Image image = renderSmall(desc, n);
  int covered = 0;
  for (float id : image.id) covered += id > 0;
  double expected = std::numbers::pi * std::pow(10.0, -2 * 0.15144944) / 4.0;
  EXPECT_NEAR(covered / double(n * n), expected, 0.01);
  // Front material (the outside, gradient towards the viewer) faces the camera.
  const Material& front = desc.materials[desc.surfaces[0].material];
  glm::dvec3 center(image.albedo[n / 2 * n + n / 2]);
  EXPECT_NEAR(center.r, front.color.r, 1e-6);
  EXPECT_NEAR(center.g, front.color.g, 1e-6);
}

TEST(JsurfImport, BrokenFileNamesFileAndLine) {
  std::filesystem::path file = std::filesystem::temp_directory_path() / "algray_broken.jsurf";
  {
    std::FILE* f = std::fopen(file.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("# test\nscale_factor=0.1\nsurface_equation=x^2+(y\n", f);
    std::fclose(f);
  }
  try {
    jsurfScene(file);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    std::string what = e.what();
    EXPECT_NE(what.find("algray_broken.jsurf:3"), std::string::npos) << what;
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace algray::render
