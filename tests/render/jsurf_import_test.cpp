// SURFER/jsurf import of the shared gallery files.
#include "render.h"
#include "scene.h"
#include "scene_builders.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

namespace algray::render {
namespace {

const std::filesystem::path kJsurfDir =
    std::filesystem::path(ALGRAY_SHARED_DIR) / "gallery" / "jsurf";

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

// A sphere file with `extra` as its last lines (from line 3 on).
std::filesystem::path writeJsurf(const std::string& name, const std::string& extra) {
  std::filesystem::path file = std::filesystem::temp_directory_path() / name;
  std::FILE* f = std::fopen(file.c_str(), "w");
  if (!f) return file;
  std::fputs(("surface_equation=x^2+y^2+z^2-1\nlight_status_0=ON\n" + extra + "\n").c_str(), f);
  std::fclose(f);
  return file;
}

// The error jsurfScene raises for a file, or "".
std::string jsurfError(const std::string& extra) {
  const std::filesystem::path file = writeJsurf("algray_bad_values.jsurf", extra);
  std::string what;
  try {
    jsurfScene(file);
  } catch (const std::exception& e) {
    what = e.what();
  }
  std::filesystem::remove(file);
  return what;
}

// jsurf's own view keys, applied as jsurf's FileFormat.load and RayCreator do: clipping =
// transform_matrix * rotation_matrix * world, surface = surface_transform_matrix * 10^s *
// clipping, and a uniform scale k in camera_transform shrinks the view k times. The unit
// sphere of surface space seen along z in the default orthographic view (half-height 1)
// covers pi a b / 4 of the image, a and b its outline's semi-axes in world units (closed
// form, against the pixels whose first hit is the surface). They were ignored: every case
// rendered as the plain file (pi / 4).
TEST(JsurfImport, JsurfsOwnViewKeysPlaceTheSurface) {
  struct Case {
    std::string keys;
    double a, b;  // semi-axes of the outline in view units (view half-height 1)
  };
  const Case cases[] = {
      // surface = 3 * 0.5 world: radius 1 / 1.5; the clip ball has radius 2.
      {"transform_matrix=0.5 0 0 0 0 0.5 0 0 0 0 0.5 0 0 0 0 1\n"
       "surface_transform_matrix=3 0 0 0 0 3 0 0 0 0 3 0 0 0 0 1",
       1 / 1.5, 1 / 1.5},
      // A non-uniform surface transform (an ellipsoid clip in surface space): the surface
      // (2x)^2 + (1.25y)^2 + (1.25z)^2 = 1 of world space, semi-axes 0.5, 0.8, 0.8.
      {"surface_transform_matrix=2 0 0 0 0 1.25 0 0 0 0 1.25 0 0 0 0 1", 0.5, 0.8},
      // With scale_factor the file is SURFER's, whose loader ignores jsurf's keys: only
      // the zoom log10(2) applies, the unit sphere's outline has radius 1/2.
      {"surface_transform_matrix=1 0 0 0 0 0.625 0 0 0 0 0.625 0 0 0 0 1\n"
       "scale_factor=0.30102999566398120",
       0.5, 0.5},
      // A camera_transform scaled by 0.5: the view is twice as large (half-height 2); the
      // surface transform makes the sphere's radius 0.5: an outline of radius 1/4.
      {"camera_transform=0.5 0 0 0 0 0.5 0 0 0 0 0.5 -0.5 0 0 0 1\n"
       "surface_transform_matrix=2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1",
       0.25, 0.25},
  };
  const int n = 200;
  for (const Case& c : cases) {
    const std::filesystem::path file = writeJsurf("algray_view_keys.jsurf", c.keys);
    const SceneDesc desc = jsurfScene(file);
    std::filesystem::remove(file);
    const Image image = renderSmall(desc, n);
    int covered = 0;
    for (float id : image.id) covered += id > 0;
    EXPECT_NEAR(covered / double(n * n), std::numbers::pi * c.a * c.b / 4, 0.004) << c.keys;
  }
  // Identity values, as jsurf writes them for an unchanged view, change nothing.
  const std::string identity = "1.0 0.0 0.0 0.0 0.0 1.0 0.0 0.0 0.0 0.0 1.0 0.0 0.0 0.0 0.0 1.0";
  const std::filesystem::path plain = writeJsurf("algray_view_plain.jsurf", "scale_factor=0.2");
  const std::filesystem::path keyed =
      writeJsurf("algray_view_identity.jsurf", "scale_factor=0.2\ntransform_matrix=" + identity +
                                                   "\nsurface_transform_matrix=" + identity);
  const Image a = renderSmall(jsurfScene(plain), 64), b = renderSmall(jsurfScene(keyed), 64);
  EXPECT_TRUE(a.color == b.color);
  std::filesystem::remove(plain);
  std::filesystem::remove(keyed);
}

// The pixels of the centre row and of the centre column that show the surface.
std::pair<int, int> centreCrossCoverage(const Image& image) {
  int row = 0, column = 0;
  for (int i = 0; i < image.width; ++i) {
    row += image.id[static_cast<size_t>(image.height / 2) * image.width + i] > 0;
    column += image.id[static_cast<size_t>(i) * image.width + image.width / 2] > 0;
  }
  return {row, column};
}

// A file as SURFER saves it (RenderArea.store: jsurf's FileFormat.save writes
// transform_matrix = R and surface_transform_matrix = 10^s I, then SURFER adds
// rotation_matrix = R and scale_factor = s) shows the view SURFER's load() reads from
// rotation_matrix and scale_factor alone. The ellipsoid 4x^2 + y^2 + z^2 = 1 of surface
// space, surface = 10^s R world with R = (y, -x, z), has world semi-axes 1 / 10^s along x
// and 0.5 / 10^s along y: the centre row of an n-pixel view (half-height 1) covers
// n / 10^s pixels, the centre column n / (2 10^s). Both pairs applied (the fault) made the
// view R R (a half turn: x narrow) zoomed 10^(2s).
TEST(JsurfImport, SurferFilesIgnoreJsurfsCopiesOfTheirView) {
  const double s = 0.1, zoom = std::pow(10.0, s);
  const std::string rotation = "rotation_matrix=0 1 0 0 -1 0 0 0 0 0 1 0 0 0 0 1\nscale_factor=0.1";
  const std::string both = rotation +
                           "\ntransform_matrix=0 1 0 0 -1 0 0 0 0 0 1 0 0 0 0 1\n"
                           "surface_transform_matrix=" +
                           std::to_string(zoom) + " 0 0 0 0 " + std::to_string(zoom) + " 0 0 0 0 " +
                           std::to_string(zoom) + " 0 0 0 0 1";
  const int n = 200;
  for (const std::string& keys : {rotation, both}) {
    SCOPED_TRACE(keys);
    // (A key given twice keeps its last value, as in Java's Properties.)
    const std::filesystem::path file =
        writeJsurf("algray_surfer_view.jsurf", "surface_equation=4*x^2+y^2+z^2-1\n" + keys);
    const SceneDesc desc = jsurfScene(file);
    std::filesystem::remove(file);
    const auto [row, column] = centreCrossCoverage(renderSmall(desc, n));
    EXPECT_NEAR(row, n / zoom, 2.0);
    EXPECT_NEAR(column, n / (2 * zoom), 2.0);
  }
  // SURFER sets its own camera (RenderArea.setOptimalCameraDistance): a camera_transform
  // scaled by 0.5 (a view twice as large for jsurf) leaves the unit sphere's outline at
  // radius 1 of the view (n centre-row pixels), not 1/2.
  const std::filesystem::path file =
      writeJsurf("algray_surfer_camera.jsurf",
                 "scale_factor=0\ncamera_transform=0.5 0 0 0 0 0.5 0 0 0 0 0.5 -0.5 0 0 0 1");
  const SceneDesc desc = jsurfScene(file);
  std::filesystem::remove(file);
  EXPECT_NEAR(centreCrossCoverage(renderSmall(desc, n)).first, n, 2.0);
}

// Values SURFER never writes: each is an error at the line of its key (they aborted in
// Embree, rendered inf/negative pixels with exit code 0, or failed later without a line).
TEST(JsurfImport, BadValuesAreErrorsAtTheirLine) {
  const std::pair<std::string, std::string> cases[] = {
      {"camera_height=1e30", ":3: camera_height"},
      {"camera_height=0", ":3: camera_height"},
      {"camera_height=-2", ":3: camera_height"},
      {"camera_type=PERSPECTIVE_CAMERA\ncamera_fov_y=0", ":4: camera_fov_y"},
      {"camera_type=PERSPECTIVE_CAMERA\ncamera_fov_y=180", ":4: camera_fov_y"},
      {"camera_type=PERSPECTIVE_CAMERA\ncamera_fov_y=-60", ":4: camera_fov_y"},
      {"camera_type=FISHEYE_CAMERA", ":3: camera_type"},
      {"camera_transform=1 0 0 0 0 1 0 0 0 0 0 0 0 0 0 1", ":3: camera_transform"},
      {"camera_transform=1 0 0 0 0 1 0 0 0 0 1 -1 0 0 1 1", ":3: camera_transform"},
      {"camera_transform=1 0 0 0 0 1 0 0 0 0 1 -1e30 0 0 0 1", ":3: camera_transform"},
      {"rotation_matrix=1 0 0 0 0 1 0 0 0 0 0 0 0 0 0 1", ":3: rotation_matrix"},
      // A translation or a projective row was dropped without a word (session 12).
      {"rotation_matrix=1 0 0 5 0 1 0 0 0 0 1 0 0 0 0 1", ":3: rotation_matrix"},
      {"rotation_matrix=1 0 0 0 0 1 0 0 0 0 1 0 0 0 7 1", ":3: rotation_matrix"},
      {"rotation_matrix=1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\nscale_factor=-400", ":4: scale_factor"},
      {"scale_factor=400", ":3: scale_factor"},
      {"scale_factor=-150", ":3: scale_factor"},
      {"front_material_color=-1 -1 -1", ":3: front_material_color"},
      {"back_material_color=1e39 0 0", ":3: back_material_color"},
      {"front_material_diffuse_intensity=-1", ":3: front_material_diffuse_intensity"},
      {"front_material_ambient_intensity=-5", ":3: front_material_ambient_intensity"},
      {"background_color=-1 0 0", ":3: background_color"},
      {"light_position_0=0 0 1\nlight_intensity_0=-100", ":4: light_intensity_0"},
      {"light_position_0=0 0 1\nlight_color_0=1e308 1 1", ":4: light_color_0"},
      {"light_color_0=1e38 1 1\nlight_intensity_0=100", ":4: light_intensity_0"},
      // Anything but ON was OFF (session 51's audit: "MAYBE", "on").
      {"light_status_0=MAYBE", ":3: light_status_0"},
      {"light_status_4=on", ":3: light_status_4"},
      // jsurf's own view keys were ignored; a bad one was too.
      {"transform_matrix=1 0 0 0 0 1 0 0 0 0 0 0 0 0 0 1", ":3: transform_matrix"},
      {"transform_matrix=1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1", ":3: transform_matrix"},
      {"surface_transform_matrix=1 0 0 0 0 0 0 0 0 0 1 0 0 0 0 1", ":3: surface_transform_matrix"},
      {"surface_transform_matrix=1 2", ":3: surface_transform_matrix"},
      // A camera_transform was reduced to its eye and two axes: its scale (the view's
      // size), a shear, a non-uniform scale or a mirror were lost without a word.
      {"camera_transform=1 0.5 0 0 0 1 0 0 0 0 1 -1 0 0 0 1", ":3: camera_transform"},
      {"camera_transform=2 0 0 0 0 1 0 0 0 0 1 -1 0 0 0 1", ":3: camera_transform"},
      {"camera_transform=-1 0 0 0 0 1 0 0 0 0 1 -1 0 0 0 1", ":3: camera_transform"},
  };
  for (const auto& [extra, expected] : cases) {
    const std::string what = jsurfError(extra);
    EXPECT_NE(what.find("algray_bad_values.jsurf" + expected), std::string::npos)
        << extra << ": " << what;
  }
}

// Light positions glm::normalize cannot normalise (NaN rays aborted Embree) and the ends
// of the scale_factor range load and render.
TEST(JsurfImport, ExtremeButValidValuesRender) {
  for (const char* extra :
       {"light_position_0=1e-200 0 1e-200", "light_position_0=1e308 1e308 1e308",
        "scale_factor=100", "scale_factor=-100",
        // A camera 1e16 away (eye + forward rounded to eye from 2^53 on: "look_at must differ").
        "camera_transform=1 0 0 0 0 1 0 0 0 0 1 1e16 0 0 0 1"}) {
    SCOPED_TRACE(extra);
    const std::filesystem::path file = writeJsurf("algray_extreme_values.jsurf", extra);
    SceneDesc desc = jsurfScene(file);
    std::filesystem::remove(file);
    for (const DirectionalLight& l : desc.directionalLights)
      EXPECT_NEAR(glm::length(l.direction), 1.0, 1e-12);
    Image image = renderSmall(desc, 8);
    for (const glm::vec3& c : image.color)
      EXPECT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b));
  }
}

// The program: exit code 2 and file:line (camera errors exited with 1 and no line, the
// light positions with 134), an upper-case .JSURF is a jsurf file, a directory says so.
TEST(JsurfImport, ProgramExitsWithCode2AndLine) {
  auto run = [](const std::string& args) {
    const std::string cmd =
        std::string(ALGRAY_RENDER_EXE) + " " + args + " --width 8 --height 8 -q 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    std::string out;
    if (!pipe) return std::pair{-2, out};
    char buf[512];
    while (fgets(buf, sizeof buf, pipe)) out += buf;
    const int status = pclose(pipe);
    return std::pair{WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
  };
  const std::filesystem::path image =
      std::filesystem::temp_directory_path() / "algray_jsurf_program.png";
  for (const char* extra : {"camera_height=0", "camera_type=PERSPECTIVE_CAMERA\ncamera_fov_y=180",
                            "camera_height=1e30"}) {
    const std::filesystem::path file = writeJsurf("algray_program.jsurf", extra);
    auto [code, out] = run(file.string() + " -o " + image.string());
    EXPECT_EQ(code, 2) << extra << ": " << out;
    EXPECT_NE(out.find(file.string() + ":"), std::string::npos) << extra << ": " << out;
    std::filesystem::remove(file);
  }
  {
    const std::filesystem::path file =
        writeJsurf("algray_program.jsurf", "light_position_0=1e-200 0 1e-200");
    auto [code, out] = run(file.string() + " -o " + image.string());
    EXPECT_EQ(code, 0) << out;
    std::filesystem::remove(file);
  }
  {
    // Upper case: read as jsurf (as JSON it was a syntax error at 1:1).
    const std::filesystem::path file = writeJsurf("ALGRAY_PROGRAM.JSURF", "camera_height=0");
    auto [code, out] = run(file.string() + " -o " + image.string());
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find("ALGRAY_PROGRAM.JSURF:3: camera_height"), std::string::npos) << out;
    std::filesystem::remove(file);
  }
  {
    // The surface's own errors (raised when Scene builds it) name the equation's line.
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / "algray_constant.jsurf";
    std::FILE* f = std::fopen(file.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs("# constant\nsurface_equation=1\n", f);
    std::fclose(f);
    auto [code, out] = run(file.string() + " -o " + image.string());
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find("algray_constant.jsurf:2:"), std::string::npos) << out;
    std::filesystem::remove(file);
  }
  {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "algray_dir.jsurf";
    std::filesystem::create_directories(dir);
    auto [code, out] = run(dir.string() + " -o " + image.string());
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find("is a directory"), std::string::npos) << out;
    std::filesystem::remove(dir);
  }
  std::filesystem::remove(image);
}

}  // namespace
}  // namespace algray::render
