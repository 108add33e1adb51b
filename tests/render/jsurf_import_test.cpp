// SURFER/jsurf import of the shared gallery files.
#include "camera.h"
#include "render.h"
#include "scene.h"
#include "scene_builders.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <sys/wait.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

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

// ---- SURFER's look: jsurf's shading (rendering/cpu/Shader.java, RenderingTask.shade) ----
// The sphere of radius r about the origin of a SURFER file (scale_factor 0, SURFER's
// orthographic camera: the eye at the origin of camera space, the sphere's centre at (0, 0,
// -1), view half-height 1) is hit through the centre of pixel (i, j) of an n x n image at
// camera-space point (X, Y, Z - 1), X = 2 (i + 1/2) / n - 1, Y = 1 - 2 (j + 1/2) / n, Z =
// sqrt(r^2 - X^2 - Y^2), with the outward normal (X, Y, Z) / r and the view vector (0, 0,
// 1). (r < 1: the unit sphere's pole is the eye itself, where a light at the eye lights
// nothing.) jsurf's colour there:
// ambient + sum over the lights that are ON with L = normalize(position - hit), n.L > 0, of
// n.L colour kd light I + max(0, n.h)^shininess ks light I, h = normalize(L + view), each
// channel clamped to 1.
struct JsurfSide {
  glm::dvec3 color;
  double kd, ks, shininess;
};
struct JsurfLight {
  glm::dvec3 position, color;
  double intensity;
};
glm::dvec3 jsurfSpherePixel(int n, double r, int i, int j, const glm::dvec3& ambient,
                            const JsurfSide& m, const std::vector<JsurfLight>& lights) {
  const double x = 2 * (i + 0.5) / n - 1, y = 1 - 2 * (j + 0.5) / n;
  const glm::dvec3 onSphere(x, y, std::sqrt(r * r - x * x - y * y));
  const glm::dvec3 normal = onSphere / r;
  const glm::dvec3 hit = onSphere - glm::dvec3(0, 0, 1), view(0, 0, 1);
  glm::dvec3 c = ambient;
  for (const JsurfLight& l : lights) {
    const glm::dvec3 dir = glm::normalize(l.position - hit);
    const double lambert = glm::dot(normal, dir);
    if (lambert <= 0) continue;
    c += lambert * m.color * l.color * (m.kd * l.intensity);
    const double nh = std::max(0.0, glm::dot(normal, glm::normalize(dir + view)));
    c += std::pow(nh, m.shininess) * l.color * (m.ks * l.intensity);
  }
  return glm::min(c, glm::dvec3(1.0));
}

glm::dvec3 pixel(const Image& image, int i, int j) {
  return glm::dvec3(image.color[static_cast<size_t>(j) * image.width + i]);
}

// A light at 0 0 0 is at the eye (it was dropped); no shadow rays; the back side's ambient
// colour takes the front ambient intensity; a highlight; jsurf's defaults for keys not
// given, and the misspelt specular_iIntensity of 23 gallery files ignored as jsurf does.
TEST(JsurfImport, SurferLookIsJsurfsShading) {
  const std::string lights =
      "light_status_0=ON\nlight_position_0=-100 100 100\nlight_color_0=1 0.9 0.8\n"
      "light_intensity_0=0.7\nlight_status_1=ON\nlight_position_1=0 0 0\n"
      "light_intensity_1=0.4\nbackground_color=0.25 0.5 0.75\nscale_factor=0\n";
  const std::string front =
      "front_material_color=0.9 0.5 0.2\nfront_material_ambient_intensity=0.3\n"
      "front_material_diffuse_intensity=0.6\nfront_material_specular_intensity=0.5\n"
      "front_material_shininess=20\n";
  const std::string back =
      "back_material_color=0.1 0.4 0.8\nback_material_ambient_intensity=0.05\n"
      "back_material_diffuse_intensity=0.7\nback_material_specular_intensity=0.2\n"
      "back_material_shininess=5\n";
  const std::vector<JsurfLight> on = {{{-100, 100, 100}, {1, 0.9, 0.8}, 0.7},
                                      {{0, 0, 0}, {1, 1, 1}, 0.4}};
  const JsurfSide frontSide{{0.9, 0.5, 0.2}, 0.6, 0.5, 20}, backSide{{0.1, 0.4, 0.8}, 0.7, 0.2, 5};
  const glm::dvec3 frontAmbient = 0.3 * frontSide.color;
  struct Case {
    std::string name, keys;
    glm::dvec3 ambient;
    JsurfSide side;
    std::vector<JsurfLight> lights;
  };
  const std::vector<Case> cases = {
      {"front", lights + front + back, frontAmbient, frontSide, on},
      {"lights off: ambient only",
       front + "background_color=0.25 0.5 0.75\nscale_factor=0\nlight_status_0=OFF",
       frontAmbient,
       frontSide,
       {}},
      {"kd 0: ambient and highlights",
       lights + front + "front_material_diffuse_intensity=0",
       frontAmbient,
       {frontSide.color, 0.0, 0.5, 20},
       on},
      // Inside out: the gradient points inwards, the viewer sees the back side.
      {"back", lights + front + back + "surface_equation=0.25-x^2-y^2-z^2", 0.3 * backSide.color,
       backSide, on},
      {"defaults",
       lights + "front_material_specular_iIntensity=0.1",
       0.1 * glm::dvec3(0.5),
       {glm::dvec3(0.5), 0.23232, 0.9, 1.0},
       on},
  };
  const int n = 40;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::filesystem::path file =
        writeJsurf("algray_surfer_look.jsurf", "surface_equation=x^2+y^2+z^2-0.25\n" + c.keys);
    const SceneDesc desc = jsurfScene(file);
    std::filesystem::remove(file);
    const Image image = renderSmall(desc, n);
    EXPECT_EQ(pixel(image, 0, 0), glm::dvec3(0.25, 0.5, 0.75));  // the background as given
    // The centre (the light at the eye's highlight), 45 degrees up-left, near the rim, off
    // the axes: the sphere of radius 0.5 covers pixels within 10 of the centre.
    for (const auto& [i, j] : {std::pair{n / 2, n / 2}, {15, 15}, {n / 2, 11}, {27, 17}}) {
      const glm::dvec3 expected = jsurfSpherePixel(n, 0.5, i, j, c.ambient, c.side, c.lights);
      const glm::dvec3 got = pixel(image, i, j);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(got[k], expected[k], 2e-4) << "pixel " << i << " " << j << " channel " << k;
      }
    }
  }
}

// No shadow rays, as in jsurf: two spheres of radius 0.3 at x = -0.4 and 0.4 and a light far
// along +x of camera space; the point of the left sphere at X = -0.2, Y = 0 faces the light
// (normal (0.2, 0, sqrt(0.05)) / 0.3) though the right sphere lies between them. Lit, as jsurf
// shows it: ambient + diffuse + highlight (a shadow ray left the ambient term alone).
TEST(JsurfImport, SurferLookCastsNoShadows) {
  const std::filesystem::path file = writeJsurf(
      "algray_surfer_shadow.jsurf",
      "surface_equation=((x+0.4)^2+y^2+z^2-0.09)*((x-0.4)^2+y^2+z^2-0.09)\nscale_factor=0\n"
      "light_position_0=1000000 0 -1\nfront_material_color=1 1 1\n"
      "front_material_ambient_intensity=0.1\nfront_material_diffuse_intensity=0.5\n"
      "front_material_specular_intensity=0\n");
  const SceneDesc desc = jsurfScene(file);
  std::filesystem::remove(file);
  const int n = 40;  // pixel (16, 19) has its centre at X = -0.175, Y = 0.025
  const Image image = renderSmall(desc, n);
  const double x = -0.175 + 0.4, y = 0.025, z = std::sqrt(0.09 - x * x - y * y);
  const double lambert = x / 0.3;  // the light's direction is +x to 1e-6
  EXPECT_NEAR(pixel(image, 16, 19).r, 0.1 + 0.5 * lambert, 1e-4) << z;
}

// The pixels of a PNG are jsurf's: round(255 * clamp(v)), no sRGB curve (a background of
// 0.5 was 188, not 128).
TEST(JsurfImport, SurferPngHoldsJsurfsBytes) {
  const std::filesystem::path file =
      writeJsurf("algray_surfer_png.jsurf", "background_color=0.5 0.25 0.1\nscale_factor=0");
  const std::filesystem::path png =
      std::filesystem::temp_directory_path() / "algray_surfer_png.png";
  auto corner = [&](const std::string& options) {
    const std::string cmd = std::string(ALGRAY_RENDER_EXE) + " " + file.string() + " -o " +
                            png.string() + " --width 8 --height 8 -q" + options;
    EXPECT_EQ(std::system(cmd.c_str()), 0) << options;
    std::vector<unsigned char> bytes(8 * 8 * 3);
    auto in = OIIO::ImageInput::open(png.string());
    if (!in) return bytes;
    EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, bytes.data()));
    in->close();
    return bytes;
  };
  std::vector<unsigned char> bytes = corner("");
  EXPECT_EQ(bytes[0], 128);  // 127.5 rounds up, as (int) (255 v + 0.5) does
  EXPECT_EQ(bytes[1], 64);   // 63.75
  EXPECT_EQ(bytes[2], 26);   // 25.5
  // Path and direct compute radiance: their PNG goes through the sRGB curve again,
  // 255 * (1.055 v^(1 / 2.4) - 0.055) rounded.
  for (const char* integrator : {" --integrator direct", " --integrator path"}) {
    bytes = corner(integrator);
    for (int k = 0; k < 3; ++k) {
      const double v = std::array{0.5, 0.25, 0.1}[static_cast<size_t>(k)];
      EXPECT_EQ(bytes[static_cast<size_t>(k)],
                std::lround(255 * (1.055 * std::pow(v, 1 / 2.4) - 0.055)))
          << integrator << " " << k;
    }
  }
  std::filesystem::remove(file);
  std::filesystem::remove(png);
}

// SURFER's perspective camera stands at 1 / sin(fov / 2) on +z (RenderArea), where the
// unit clip sphere just fills the view's height: a sphere of half the clip radius
// (scale_factor log10 2) then spans tan(asin(sin(fov / 2) / 2)) / tan(fov / 2) of the centre
// row and column, with camera_fov_y given and with jsurf's default of 60 degrees (a
// mutation round of session 56 put the eye at 1 / tan(fov / 2), and the default at 45
// degrees, without a test failing).
TEST(JsurfImport, PerspectiveEyeStandsWhereSurferPutsIt) {
  const int n = 400;
  for (const std::string fov : {"", "40"}) {
    const double f = (fov.empty() ? 60.0 : std::stod(fov)) * std::numbers::pi / 180;
    const std::filesystem::path file =
        writeJsurf("algray_perspective.jsurf",
                   "camera_type=PERSPECTIVE_CAMERA\nscale_factor=0.30102999566398120" +
                       (fov.empty() ? std::string() : "\ncamera_fov_y=" + fov));
    const Image image = renderSmall(jsurfScene(file), n);
    std::filesystem::remove(file);
    const auto [row, column] = centreCrossCoverage(image);
    const double expected = n * std::tan(std::asin(std::sin(f / 2) / 2)) / std::tan(f / 2);
    EXPECT_NEAR(row, expected, 2.0) << "fov " << fov;
    EXPECT_NEAR(column, expected, 2.0) << "fov " << fov;
  }
}

// With the direct integrator (--integrator direct) the import's lights and environment give
// jsurf's ambient and diffuse terms: a light of intensity I and colour L at the eye becomes
// a directional light of irradiance pi I L, which a Lambertian albedo kd c turns into
// kd c I L, and the ambient term ka c an environment of radiance ka / kd, which that albedo
// reflects as ka c. So the sphere's point facing the camera shows c (kd I L + ka), and a
// pixel beside it jsurf's default white background (the same mutation round dropped the
// pi, the division by kd and the white without a test failing).
TEST(JsurfImport, DirectIntegratorGivesJsurfsAmbientAndDiffuse) {
  const std::filesystem::path file = writeJsurf(
      "algray_direct_terms.jsurf",
      "scale_factor=0.30102999566398120\nlight_intensity_0=0.7\nlight_color_0=1 0.5 0.25\n"
      "front_material_color=0.8 0.6 0.4\nfront_material_ambient_intensity=0.3\n"
      "front_material_diffuse_intensity=0.6");
  SceneDesc desc = jsurfScene(file);
  std::filesystem::remove(file);
  desc.settings.integrator = IntegratorType::Direct;
  const int n = 9;
  const Image image = renderSmall(desc, n);
  const glm::dvec3 c(0.8, 0.6, 0.4), light(1, 0.5, 0.25);
  const glm::dvec3 expected = c * (0.6 * 0.7 * light + 0.3);
  const glm::vec3 centre = image.color[static_cast<size_t>(n / 2) * n + n / 2];
  const glm::vec3 corner = image.color[0];
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(centre[k], expected[k], 1e-5 * expected[k]) << k;
    EXPECT_EQ(corner[k], 1.0f) << k;
  }
}

// SURFER's view is square: a portrait image sees the width a square one does (its
// camera_height spanned the height, and the clip sphere was cut off at both sides), a
// landscape one the height; for both camera kinds.
TEST(JsurfImport, PortraitImagesSeeTheWholeWidth) {
  for (const char* camera : {"", "camera_type=PERSPECTIVE_CAMERA\ncamera_fov_y=60\n"}) {
    const std::filesystem::path file =
        writeJsurf("algray_portrait.jsurf", std::string(camera) + "scale_factor=0");
    const SceneDesc desc = jsurfScene(file);
    std::filesystem::remove(file);
    // The ray through the middle of the left edge: its origin (orthographic) or direction
    // (perspective) in camera space.
    auto leftEdge = [&](int w, int h) {
      const CameraRay r = Camera(desc.camera, w, h).generateRay({0.0, h / 2.0}, {0.5, 0.5});
      return r.org + r.dir;
    };
    auto topEdge = [&](int w, int h) {
      const CameraRay r = Camera(desc.camera, w, h).generateRay({w / 2.0, 0.0}, {0.5, 0.5});
      return r.org + r.dir;
    };
    const glm::dvec3 square = leftEdge(64, 64), squareTop = topEdge(64, 64);
    const glm::dvec3 portrait = leftEdge(32, 128), landscape = topEdge(128, 32);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(portrait[k], square[k], 1e-12) << camera << k;
      EXPECT_NEAR(landscape[k], squareTop[k], 1e-12) << camera << k;
    }
  }
}

// Path and direct: a light at 0 0 0 (at the eye) is a light towards the eye; it was dropped.
TEST(JsurfImport, LightAtTheEyeLightsTowardsTheEye) {
  const std::filesystem::path file =
      writeJsurf("algray_eye_light.jsurf", "light_position_0=0 0 0\nscale_factor=0");
  const SceneDesc desc = jsurfScene(file);
  std::filesystem::remove(file);
  ASSERT_EQ(desc.directionalLights.size(), 1u);
  // SURFER's camera looks down -z from +z: towards the eye is +z.
  EXPECT_NEAR(desc.directionalLights[0].direction.z, 1.0, 1e-12);
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
