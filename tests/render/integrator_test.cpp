// Light transport checks against closed forms:
//  * white furnace: a surface of albedo 1 inside a uniform environment of radiance Le
//    reflects exactly Le, whatever its shape (all light is eventually reflected out);
//    with albedo a < 1 a convex surface reflects a * Le (one bounce, nothing else seen);
//  * the same image for 1 and 2 threads (per-pixel random streams).
#include "camera.h"
#include "render.h"
#include "sampling.h"
#include "scene.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algray/gallery.h>

#include "mesh.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <thread>
#include <vector>

namespace algray::render {
namespace {

SceneDesc furnace(double albedo) {
  SceneDesc s;
  s.settings.width = 24;
  s.settings.height = 24;
  s.settings.spp = 48;
  s.settings.maxDepth = 200;
  s.camera.position = {0, -5, 0.5};
  s.camera.lookAt = {0, 0, 0};
  s.camera.fovY = 30;
  s.environment.color = glm::dvec3(0.7);
  Material m;
  m.color = glm::dvec3(albedo);
  s.addMaterial(m);
  return s;
}

// Mean radiance over the pixels whose camera rays hit something, and how many. Pixels
// next to the outline are left out: some of their samples see the background.
std::pair<glm::dvec3, int> meanOverHits(const SceneDesc& desc) {
  Scene scene(desc);
  Image image;
  render(scene, image);
  glm::dvec3 sum(0.0);
  int n = 0;
  const int w = image.width, h = image.height;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      auto at = [&](int dx, int dy) { return image.id[(y + dy) * w + x + dx] > 0; };
      if (at(0, 0) && at(1, 0) && at(-1, 0) && at(0, 1) && at(0, -1))
        sum += glm::dvec3(image.color[y * w + x]), ++n;
    }
  return {n ? sum / static_cast<double>(n) : sum, n};
}

// The gallery's unit sphere in a clip ball of radius 1.5, moved to `at`.
void addUnitSphere(SceneDesc& s, glm::dvec3 at = glm::dvec3(0.0)) {
  SurfaceItem item;
  item.label = "sphere";
  item.polynomial = findGallerySurface("sphere")->build();
  item.clip = ClipSphere{glm::dvec3(0.0), 1.5};
  item.transform = glm::translate(glm::dmat4(1.0), at);
  s.surfaces.push_back(item);
}

void addSurface(SceneDesc& s, const char* name) {
  const GallerySurface* g = findGallerySurface(name);
  ASSERT_NE(g, nullptr) << name;
  SurfaceItem item;
  item.label = name;
  item.polynomial = g->build();
  item.clip = ClipSphere{glm::dvec3(0.0), g->clipRadius};
  item.transform = glm::scale(glm::rotate(glm::dmat4(1.0), 0.6, glm::dvec3(1, 0, 0)),
                              glm::dvec3(1.0 / g->clipRadius));
  s.surfaces.push_back(item);
}

TEST(WhiteFurnace, AlgebraicTorusReturnsTheEnvironment) {
  SceneDesc s = furnace(1.0);
  addSurface(s, "torus");  // not convex: inter-reflections must add up to Le
  auto [mean, hits] = meanOverHits(s);
  ASSERT_GT(hits, 50);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean[k], 0.7, 0.7 * 0.02);
}

TEST(WhiteFurnace, AlgebraicSurfaceOfHigherDegree) {
  SceneDesc s = furnace(1.0);
  addSurface(s, "heart");  // degree 6, closed
  s.settings.spp = 24;
  auto [mean, hits] = meanOverHits(s);
  ASSERT_GT(hits, 50);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean[k], 0.7, 0.7 * 0.03);
}

TEST(WhiteFurnace, MeshIcosphereReturnsTheEnvironment) {
  SceneDesc s = furnace(1.0);
  s.meshes.push_back({"icosphere", makeIcosphere(3), glm::dmat4(1.0), 0, -1});
  auto [mean, hits] = meanOverHits(s);
  ASSERT_GT(hits, 50);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean[k], 0.7, 0.7 * 0.02);
}

TEST(WhiteFurnace, GreyConvexSurfaceReflectsAlbedoTimesEnvironment) {
  for (IntegratorType type : {IntegratorType::Path, IntegratorType::Direct}) {
    SceneDesc s = furnace(0.5);
    s.settings.integrator = type;
    addSurface(s, "sphere");
    auto [mean, hits] = meanOverHits(s);
    ASSERT_GT(hits, 50);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean[k], 0.35, 0.35 * 0.02);
  }
}

// A float RGB image of `width` columns whose rows (top to bottom) are each one grey value.
// A float RGB image of grey values, row by row from the top.
void writeGreyImage(const std::string& file, int width, int height,
                    const std::vector<float>& grey) {
  std::vector<float> pixels;
  for (float g : grey)
    for (int c = 0; c < 3; ++c) pixels.push_back(g);
  auto out = OIIO::ImageOutput::create(file);
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(file, OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  ASSERT_TRUE(out->close());
}
void writeRowImage(const std::string& file, int width, const std::vector<float>& rows) {
  std::vector<float> grey;
  for (float r : rows) grey.insert(grey.end(), width, r);
  writeGreyImage(file, width, static_cast<int>(rows.size()), grey);
}

// The direct integrator's ambient light is the environment's mean radiance, colour times
// the image's solid-angle mean: it read the colour alone, so a white sphere under an image
// of constant 0.1 came out 1.0. A convex sphere with no other light reflects albedo x mean
// at every pixel. References in closed form: a constant image c gives c; an image of rows
// a, b, b, a (z up) is, interpolated like lookupLatLong(), a on theta in [0, pi/8] and its
// mirror, b on [3pi/8, 5pi/8], linear between, so its mean int_0^(pi/2) L sin = a + (b - a)
// (4/pi) (sin(3pi/8) - sin(pi/8)) (int (theta - pi/8) sin = sin - (theta - pi/8) cos).
TEST(DirectIntegrator, AmbientLightIsTheImageEnvironmentsMean) {
  const double a = 1.0, b = 0.2;
  const double rowsMean = a + (b - a) * (4 / kPi) * (std::sin(3 * kPi / 8) - std::sin(kPi / 8));
  struct Case {
    std::vector<float> rows;
    double colour, albedo, expected;
  };
  for (const Case& c : {Case{{0.1f, 0.1f}, 1.0, 1.0, 0.1},
                        Case{{1.0f, 0.2f, 0.2f, 1.0f}, 0.5, 0.8, 0.5 * 0.8 * rowsMean}}) {
    // One file per image: OIIO's image cache keeps a file's first size for its name.
    const std::string file = (std::filesystem::temp_directory_path() /
                              ("algray_ambient_env" + std::to_string(c.rows.size()) + ".exr"))
                                 .string();
    writeRowImage(file, 3, c.rows);
    SceneDesc s = furnace(c.albedo);
    s.settings.integrator = IntegratorType::Direct;
    s.settings.spp = 1;
    s.environment.color = glm::dvec3(c.colour);
    s.environment.image = file;
    s.environment.rotation = 37;  // turns the image about z: the mean stays
    addSurface(s, "sphere");
    auto [mean, hits] = meanOverHits(s);
    ASSERT_GT(hits, 50);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean[k], c.expected, 1e-6) << c.rows.size();
    std::filesystem::remove(file);
  }
}

// An environment's rotation turns the image about z by whole turns as by none: rotations
// of 360 k + a degrees look up what a does (bit for bit for an exact multiple; the image's
// columns differ, so a wrong turn shows). 360 * 2^60 times pi / 180 kept none of the
// fraction of a turn and read up to 0.22 off.
TEST(EnvironmentImage, WholeTurnsOfTheRotationChangeNothing) {
  const int width = 16, height = 4;
  std::vector<float> grey;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) grey.push_back(0.1f + 0.05f * x + 0.01f * y);
  const std::string file =
      (std::filesystem::temp_directory_path() / "algray_env_turns.exr").string();
  writeGreyImage(file, width, height, grey);
  const auto sceneTurnedBy = [&](double degrees) {
    SceneDesc s = furnace(0.5);
    s.environment.color = glm::dvec3(1.0);
    s.environment.image = file;
    s.environment.rotation = degrees;
    return std::make_unique<Scene>(s);
  };
  const auto none = sceneTurnedBy(0.0), some = sceneTurnedBy(37.0);
  for (const double turns : {1.0, -3.0, 0x1p40, 0x1p60, 1e15}) {
    const auto whole = sceneTurnedBy(360.0 * turns), more = sceneTurnedBy(360.0 * turns + 37.0);
    for (const glm::dvec3& dir :
         {glm::dvec3(1, 0.3, 0.2), glm::dvec3(-0.4, -1, 0.5), glm::dvec3(0.2, -0.7, -0.6)}) {
      const glm::dvec3 d = glm::normalize(dir);
      EXPECT_EQ(whole->environment(d).x, none->environment(d).x) << turns;
      if (360.0 * turns + 37.0 - 360.0 * turns == 37.0) {  // 37 degrees more, exactly
        EXPECT_NEAR(more->environment(d).x, some->environment(d).x, 1e-9) << turns;
      }
    }
  }
  std::filesystem::remove(file);
}

// An image environment at its poles: straight up the top row, straight down the bottom one,
// and near them only those rows (each row constant here, so the azimuth does not matter).
// The lookup wrapped rows like a surface texture's: v = 1 (the zenith) read the bottom row,
// and within half a texel of the zenith the top row was blended with the bottom one.
TEST(EnvironmentImage, PolesReadOnlyTheirOwnRows) {
  const std::vector<float> rows = {2.0f, 0.5f, 0.25f, 0.125f};  // top to bottom
  const std::string file =
      (std::filesystem::temp_directory_path() / "algray_env_poles.exr").string();
  writeRowImage(file, 8, rows);
  SceneDesc s = furnace(0.5);
  s.environment.color = glm::dvec3(1.0);
  s.environment.image = file;
  const Scene scene(s);
  for (const double tilt : {0.0, 1e-6, 0.05, 0.1}) {  // radians from the pole; a row is pi/4
    const glm::dvec3 up(std::sin(tilt), 0.0, std::cos(tilt)), down(up.x, up.y, -up.z);
    EXPECT_DOUBLE_EQ(scene.environment(up).x, rows.front()) << tilt;
    EXPECT_DOUBLE_EQ(scene.environment(down).x, rows.back()) << tilt;
  }
  std::filesystem::remove(file);
}

// The lat-long image's azimuth: its centre column looks along +x (u = 1/2 + azimuth / 2pi,
// as surfaces read their textures, SurfaceTexture above), and a rotation of a degrees turns
// the image about +z by the right-hand rule, so what lay at azimuth phi lies at phi + a.
// Four columns of 1, 2, 4, 8 (one row): column k's centre is at u = (k + 1/2) / 4, azimuth
// (k - 3/2) pi / 2, where any interpolation reads the column's own value.
TEST(EnvironmentImage, CentreColumnFacesPlusXAndRotationsTurnAnticlockwise) {
  const std::vector<float> columns = {1, 2, 4, 8};
  const std::string file =
      (std::filesystem::temp_directory_path() / "algray_env_columns.exr").string();
  writeGreyImage(file, 4, 1, columns);
  for (const double degrees : {0.0, 90.0, -30.0}) {
    SceneDesc s = furnace(0.5);
    s.environment.color = glm::dvec3(1.0);
    s.environment.image = file;
    s.environment.rotation = degrees;
    const Scene scene(s);
    for (int k = 0; k < 4; ++k) {
      const double phi = (k - 1.5) * kPi / 2 + degrees * kPi / 180;
      const glm::dvec3 dir(std::cos(phi), std::sin(phi), 0.0);
      EXPECT_NEAR(scene.environment(dir).x, columns[k], 1e-6) << degrees << " " << k;
    }
  }
  std::filesystem::remove(file);
}

// A sphere light of radius r and radiance L lights a distant point as a point light of
// intensity pi r^2 L does. Light sampling picks points of its whole (two-sided) surface;
// those on the far side must be blocked by the near side, which shadow rays stopping 1e-4
// of the distance short did not reach once r was below that: a sphere light of radius 1e-4
// at distance 3 shone twice as bright (measured 1.97x).
TEST(LightSampling, SmallSphereLightsMatchAPointLight) {
  auto scene = [](double radius) {
    SceneDesc s;
    s.settings.width = 32;
    s.settings.height = 24;
    s.settings.spp = 16;
    s.settings.integrator = IntegratorType::Direct;
    s.camera.position = {0, -6, 2};
    s.camera.lookAt = {0, 0, 0};
    s.camera.fovY = 20;
    s.environment.color = glm::dvec3(0.0);
    s.addMaterial(Material{});
    addSurface(s, "sphere");
    if (radius > 0) {
      Material light;
      light.type = MaterialType::Emissive;
      light.emission = glm::dvec3(1.0 / (radius * radius));
      MeshItem item;
      item.label = "light";
      item.mesh = makeIcosphere(3);
      item.transform =
          glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(0, 0, 3)), glm::dvec3(radius));
      item.material = s.addMaterial(light);
      s.meshes.push_back(std::move(item));
    } else {
      s.pointLights.push_back(PointLight{{0, 0, 3}, glm::dvec3(M_PI)});
    }
    return s;
  };
  const auto [point, n] = meanOverHits(scene(0.0));
  ASSERT_GT(n, 50);
  ASSERT_GT(point.x, 0.0);
  // Below ~1e-6 (2^-20 of the coordinates, the shadow ray's least gap) the near side no
  // longer blocks the far side's samples: convex emitters return none (radius 3e-7: 1.99x).
  for (const double radius : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 3e-7, 1e-7, 1e-9}) {
    // The icosphere's area is 0.4 % below the sphere's (its power likewise).
    const double ratio = meanOverHits(scene(radius)).first.x / point.x;
    EXPECT_NEAR(ratio, 1.0, 0.08) << "radius " << radius;
  }
}

// A diffuse floor under a quad light: the radiance at the floor point below it is
// albedo * L * F, F the form factor of a differential area to a parallel rectangle (Howell's
// catalogue, C-11, by superposition of rectangles with a corner above the point). Shadow rays
// from a mesh start pushed off the floor by 64 float ulps of its coordinates; aimed along the
// direction sampled from the unpushed point, they ended past the light by that push, and on a
// floor of half-size 100 under a light 2 above every sample was blocked by the light itself.
TEST(LightSampling, AreaLightsLightLargeFloors) {
  const double h = 2, albedo = 0.6, radiance = 2;
  auto corner = [h](double a, double b) {  // rectangle [0, a] x [0, b] at height h
    const double A = a / h, B = b / h, sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
    return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2 * M_PI);
  };
  // The light covers x in [0.5, 1.5], y in [-0.5, 0.5]: twice [0.5, 1.5] x [0, 0.5].
  const double formFactor = 2 * (corner(1.5, 0.5) - corner(0.5, 0.5));
  const double expected = albedo * radiance * formFactor;
  for (const double half : {1.0, 100.0, 1000.0})
    for (const double shift : {0.0, 1000.0}) {
      const glm::dvec3 offset(shift, 0, 0);
      SceneDesc s;
      s.settings.width = 4;
      s.settings.height = 4;
      s.settings.spp = 64;
      s.settings.integrator = IntegratorType::Direct;
      s.camera.type = CameraDesc::Type::Orthographic;
      s.camera.height = 1e-6;  // every pixel sees the floor point below the camera
      s.camera.position = offset + glm::dvec3(0, 0, 1);
      s.camera.lookAt = offset;
      s.camera.up = {0, 1, 0};
      s.environment.color = glm::dvec3(0.0);
      Material floor;
      floor.color = glm::dvec3(albedo);
      Material light;
      light.type = MaterialType::Emissive;
      light.emission = glm::dvec3(radiance);
      MeshItem plane{"floor", makePlane(half), glm::translate(glm::dmat4(1.0), offset),
                     s.addMaterial(floor), -1};
      MeshItem quad{"light", makeQuad(offset + glm::dvec3(0.5, -0.5, h), {1, 0, 0}, {0, 1, 0}),
                    glm::dmat4(1.0), s.addMaterial(light), -1};
      s.meshes.push_back(std::move(plane));
      s.meshes.push_back(std::move(quad));
      Scene scene(s);
      Image image;
      render(scene, image);
      double sum = 0;
      for (const auto& c : image.color) sum += c.x;
      const double mean = sum / static_cast<double>(image.color.size());
      EXPECT_NEAR(mean, expected, 0.03 * expected) << "half-size " << half << ", shift " << shift;
    }
}

// A textured material on an algebraic surface reads the surface's u, v (the plugin's
// spherical parametrisation about the clip centre, u = atan2(y, x) / 2pi, v = acos(z / r) /
// pi) as the environment reads a lat-long image, and so does the icosphere: texture
// coordinates 1/2 + u (mod 1) and 1 - v, the image's top row at +z. An untextured surface
// asks the plugin for none (SurfaceOptions::uv off: 0, 0). Until session 52 both spheres
// read v = 0 at +z, the image's bottom row (upside down), and the icosphere's triangles
// across its seam (azimuth +-pi) interpolated u across the whole image (0.5 where 0.99
// was due).
TEST(SurfaceTexture, SpheresReadALatLongImageAsTheEnvironmentDoes) {
  for (const int kind : {0, 1, 2}) {  // textured surface, untextured surface, icosphere
    SceneDesc s;
    Material m;
    if (kind != 1)
      m.texture = std::make_shared<const Texture>(1, 1, std::vector<glm::vec3>{glm::vec3(0.5f)});
    s.addMaterial(m);
    if (kind == 2) {
      s.meshes.push_back({"icosphere", makeIcosphere(4), glm::dmat4(1.0), 0, -1});
    } else {
      addUnitSphere(s);
    }
    Scene scene(s);
    RayCounter counter;
    // The icosphere's facets (subdivision 4) put its hit points and their interpolated
    // coordinates within ~1e-3 of the sphere's; the poles' own neighbourhood is left out
    // for u, where the azimuth turns fast across a facet.
    const double tolerance = kind == 2 ? 4e-3 : 1e-6;
    int checked = 0;
    for (const double phi :
         {-M_PI, -M_PI + 1e-3, M_PI - 1e-3, M_PI - 0.02, 0.2, 0.5 * M_PI, 1.25 * M_PI, -0.6})
      for (const double theta : {0.03 * M_PI, 0.3 * M_PI, 0.5 * M_PI, 0.8 * M_PI, 0.97 * M_PI}) {
        const glm::dvec3 p(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                           std::cos(theta));
        const auto hit = scene.intersect(3.0 * p, -p, 0.0, counter);
        ASSERT_TRUE(hit);
        EXPECT_NEAR(hit->t, 2.0, kind == 2 ? 3e-3 : 1e-6);
        if (kind == 1) {
          EXPECT_EQ(hit->uv, glm::dvec2(0.0));
          continue;
        }
        EXPECT_NEAR(hit->uv.y, 1 - theta / M_PI, tolerance) << phi << " " << theta;
        if (kind == 2 && (theta < 0.1 * M_PI || theta > 0.9 * M_PI)) continue;
        double du = hit->uv.x - (0.5 + phi / (2 * M_PI));
        du -= std::round(du);  // u repeats
        EXPECT_NEAR(du, 0.0, tolerance) << phi << " " << theta << " u " << hit->uv.x;
        ++checked;
      }
    if (kind != 1) {
      EXPECT_EQ(checked, kind == 2 ? 24 : 40);
    }
  }
}

// At the poles a textured sphere reads the image's edge rows as the environment does
// (rows clamped, Texture::lookupLatLong): a 1x2 image, top row red, bottom row blue, seen
// straight down on +z and straight up at -z, on the algebraic sphere and the icosphere.
// Until session 52 the rows repeated there, and the pole read half of the other edge row.
TEST(SurfaceTexture, PolesReadTheImagesEdgeRowsAsTheEnvironmentDoes) {
  for (const bool icosphere : {false, true})
    for (const double side : {1.0, -1.0}) {
      SceneDesc s;
      s.settings.width = s.settings.height = 9;
      s.settings.spp = 1;
      s.settings.integrator = IntegratorType::Direct;
      s.camera.position = {0, 0, 4 * side};
      s.camera.lookAt = {0, 0, 0};
      s.camera.up = {0, 1, 0};
      s.camera.fovY = 10;
      Material m;
      m.color = glm::dvec3(1.0);
      m.texture = std::make_shared<const Texture>(
          1, 2, std::vector<glm::vec3>{glm::vec3(1, 0, 0), glm::vec3(0, 0, 1)});
      s.addMaterial(m);
      if (icosphere) {
        s.meshes.push_back({"icosphere", makeIcosphere(5), glm::dmat4(1.0), 0, -1});
      } else {
        addUnitSphere(s);
      }
      Scene scene(s);
      Image image;
      render(scene, image);
      const glm::vec3 albedo = image.albedo[4 * 9 + 4];
      const glm::vec3 expected = side > 0 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
      EXPECT_NEAR(glm::length(albedo - expected), 0.0, 1e-6)
          << (icosphere ? "icosphere " : "sphere ") << side << ": " << albedo.x << " " << albedo.y
          << " " << albedo.z;
    }
}

// A unit sphere 6 away and a floor 3 behind its centre, facing the camera and covering the
// lower half of the picture, 16 samples a pixel (the AOV tests' scene).
SceneDesc sphereBeforeAFloor() {
  SceneDesc s;
  s.settings.width = 40;
  s.settings.height = 30;
  s.settings.spp = 16;
  s.settings.maxDepth = 1;
  s.camera.position = {0, -6, 0};
  s.camera.lookAt = {0, 0, 0};
  s.camera.fovY = 30;
  s.addMaterial(Material{});
  addUnitSphere(s);
  s.meshes.push_back(
      {"floor", makePlane(2.0),
       glm::rotate(glm::translate(glm::dmat4(1.0), {0, 3, -2}), 0.5 * M_PI, glm::dvec3(1, 0, 0)), 0,
       -1});
  return s;
}

// The depth and id AOVs of a pixel come from one of its samples, the nearest hit
// (sphereBeforeAFloor). Until session 52 depth was the mean over the samples with a miss
// counted as 0 and id sample 0's: outline pixels read depths in front of everything (0.38
// where the nearest surface is 5), and some had a depth with id 0.
TEST(Aov, DepthAndIdOfOutlinePixelsComeFromOneSurface) {
  const SceneDesc s = sphereBeforeAFloor();
  Scene scene(s);
  Image image;
  render(scene, image);
  int sphereIds = 0, floorIds = 0, misses = 0;
  for (size_t i = 0; i < image.depth.size(); ++i) {
    const double depth = image.depth[i], id = image.id[i];
    if (id == 0) {
      EXPECT_EQ(depth, 0.0) << i;
      ++misses;
      continue;
    }
    // The sphere's points lie 5 to sqrt(35) from the camera (its silhouette), the floor's
    // at least 9 (its plane, y = 3, is 9 away; the sphere hides nothing nearer).
    if (depth < 8) {
      EXPECT_GE(depth, 5.0 * (1 - 1e-6)) << i;
      EXPECT_LE(depth, std::sqrt(35.0) * (1 + 1e-6)) << i;
      ++sphereIds;
    } else {
      EXPECT_GE(depth, 9.0 * (1 - 1e-6)) << i;
      ++floorIds;
    }
  }
  // The three kinds of pixel exist (the test could fail), and the sphere's id is one.
  EXPECT_GT(sphereIds, 50);
  EXPECT_GT(floorIds, 50);
  EXPECT_GT(misses, 50);
}

// The depth and id of a pixel are its nearest sample's (a z-buffer's choice), in
// DepthAndIdOfOutlinePixelsComeFromOneSurface's scene: where the unit sphere covers at least
// half of a pixel and the floor lies behind the rest, the pixel is the sphere's unless all
// of its 16 samples missed it (probability at most 2^-16). The coverage: an 8 x 8 grid of
// camera rays o + t d across the pixel, each meeting the sphere iff o.d < 0 and
// (o.d)^2 - |o|^2 + 1 >= 0 (|o + t d|^2 = 1 has a real root, in front).
TEST(Aov, PixelsMostlyCoveredByTheNearerSurfaceAreIts) {
  const SceneDesc s = sphereBeforeAFloor();
  Scene scene(s);
  Image image;
  render(scene, image);
  const Camera camera(s.camera, s.settings.width, s.settings.height);
  int partial = 0;
  for (int y = 0; y < s.settings.height; ++y)
    for (int x = 0; x < s.settings.width; ++x) {
      int covered = 0;
      for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
          const CameraRay r = camera.generateRay({x + (i + 0.5) / 8, y + (j + 0.5) / 8}, {});
          const double od = glm::dot(r.org, r.dir);
          covered += od < 0 && od * od - glm::dot(r.org, r.org) + 1 >= 0;
        }
      const size_t i = static_cast<size_t>(y) * s.settings.width + x;
      if (covered < 32 || image.id[i] == 0) continue;
      EXPECT_LT(image.depth[i], 8.0f) << x << " " << y << ": " << covered << " of 64";
      partial += covered < 64 && y > s.settings.height / 2;  // floor behind the rest
    }
  EXPECT_GT(partial, 5);  // pixels where a farther sample could win (the test could fail)
}

// A scene far from the world origin renders as at the origin: it is built and rendered
// about its own centre (Scene::frameOrigin), camera and lights moved with it. A unit
// sphere on a floor under a directional and a point light, moved along x with its camera:
// until session 52 mesh hits at 1e5 pushed spawned origins 64 float ulps of 1e5 (0.38) off
// the floor, and 45 pixels of this image differed from the scene at the origin; at 1e12
// most did. A scene only 20 away (less than 16 times its size) keeps the world origin: a
// move would not gain every point precision.
TEST(Frame, ASceneFarFromTheWorldOriginRendersAsAtTheOrigin) {
  const double offsets[] = {0.0, 20.0, 1e5, 1e12};
  Image images[4];
  for (int k = 0; k < 4; ++k) {
    const glm::dvec3 c(offsets[k], 0.0, 0.0);
    SceneDesc s;
    s.settings.width = 64;
    s.settings.height = 48;
    s.settings.spp = 1;
    s.settings.integrator = IntegratorType::Direct;
    s.camera.position = c + glm::dvec3(0, -6, 2);
    s.camera.lookAt = c;
    s.camera.fovY = 35;
    s.addMaterial(Material{});
    addUnitSphere(s, c);
    s.meshes.push_back({"floor", makePlane(4.0),
                        glm::translate(glm::dmat4(1.0), c + glm::dvec3(0, 0, -1)), 0, -1});
    s.directionalLights.push_back({glm::normalize(glm::dvec3(1, -1, 2)), glm::dvec3(2.0)});
    s.pointLights.push_back({c + glm::dvec3(-2, -1, 3), glm::dvec3(3.0)});
    Scene scene(s);
    EXPECT_EQ(scene.frameOrigin(), k < 2 ? glm::dvec3(0.0) : c) << offsets[k];
    render(scene, images[k]);
  }
  for (int k = 1; k < 4; ++k) {
    int differing = 0, lit = 0, dark = 0;
    for (size_t i = 0; i < images[0].color.size(); ++i) {
      const float a = images[0].color[i].x, b = images[k].color[i].x;
      differing += std::abs(a - b) > 0.02f;
      lit += a > 0.3f, dark += a < 0.1f;
    }
    EXPECT_LE(differing, 2) << offsets[k];
    // Lit floor, shadows and sphere are all in the picture (the test could fail).
    EXPECT_GT(lit, 200);
    EXPECT_GT(dark, 50);
  }
}

TEST(Determinism, SameImageForOneAndTwoThreads) {
  SceneDesc s = furnace(0.8);
  addSurface(s, "torus");
  s.meshes.push_back(
      {"floor", makePlane(5.0), glm::translate(glm::dmat4(1.0), {0, 0, -0.6}), 0, -1});
  s.pointLights.push_back({{1, -2, 3}, glm::dvec3(10.0)});
  s.settings.spp = 4;
  s.settings.maxDepth = 5;
  Image images[2];
  for (int t = 0; t < 2; ++t) {
    s.settings.threads = t + 1;
    Scene scene(s);
    render(scene, images[t]);
  }
  ASSERT_EQ(images[0].color.size(), images[1].color.size());
  int differing = 0;
  for (size_t i = 0; i < images[0].color.size(); ++i)
    differing += images[0].color[i] != images[1].color[i];
  EXPECT_EQ(differing, 0);
  // And the picture is not trivially constant (the test could fail).
  EXPECT_NE(images[0].color.front(), images[0].color[images[0].color.size() / 2]);
}

TEST(Cancel, StopsAndReportsInterruption) {
  SceneDesc s = furnace(0.8);
  addSurface(s, "sphere");
  std::atomic<bool> cancel{true};
  Scene scene(s);
  Image image;
  RenderOptions options;
  options.cancel = &cancel;
  RenderStats stats = render(scene, image, options);
  EXPECT_TRUE(stats.interrupted);
  EXPECT_LT(stats.tilesDone, stats.tilesTotal);
}

// ---- Closed forms for the path integrator's estimators --------------------------------

// Planes and quads are two triangles split along a diagonal; moved off the camera ray's
// point so that it meets one triangle, not their shared edge.
const glm::dmat4 kOffCentre = glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, 0.25, 0));

// A scene seen through a pinhole-thin orthographic camera: every pixel's rays meet the
// surface at the one point below `position` along `lookAt - position`, so the pixels are
// independent estimates (per-pixel random streams) of one radiance.
SceneDesc pointCamera(glm::dvec3 position, glm::dvec3 lookAt, glm::dvec3 up, int size, int spp) {
  SceneDesc s;
  s.settings.width = size;
  s.settings.height = size;
  s.settings.spp = spp;
  s.camera.type = CameraDesc::Type::Orthographic;
  s.camera.height = 1e-6;
  s.camera.position = position;
  s.camera.lookAt = lookAt;
  s.camera.up = up;
  s.environment.color = glm::dvec3(0.0);
  return s;
}

// The red channel's mean over the pixels and the standard error of that mean from the
// pixels' own sample variance (the pixels being independent, identically distributed).
struct Estimate {
  double mean = 0, standardError = 0;
};
Estimate estimate(const std::vector<double>& values) {
  const double n = static_cast<double>(values.size());
  double sum = 0, sum2 = 0;
  for (double v : values) sum += v, sum2 += v * v;
  const double mean = sum / n, variance = std::max(0.0, (sum2 / n - mean * mean) * n / (n - 1));
  return {mean, std::sqrt(variance / n)};
}
Estimate renderEstimate(const SceneDesc& desc) {
  Scene scene(desc);
  Image image;
  render(scene, image);
  std::vector<double> values;
  for (const glm::vec3& c : image.color) values.push_back(c.x);
  return estimate(values);
}

// Irradiance from a point light of intensity I at distance r and incidence theta is
// E = I cos(theta) / r^2, and a Lambertian floor of albedo a reflects L = (a / pi) E. With
// maxDepth 1 (one vertex after the camera) that is all the path integrator adds, though
// a white sphere beside the point would reflect more light onto it: the point light is a
// Dirac delta, not weighted against BSDF sampling, and the estimate is exact (no noise).
TEST(PathIntegrator, PointLightOnAFloorIsLambertTimesIrradiance) {
  const double albedo = 0.6, intensity = 3;
  const glm::dvec3 light(1, 0, 2);  // r^2 = 5, cos(theta) = 2 / sqrt(5) at the origin
  const double expected = albedo / kPi * intensity * (2 / std::sqrt(5.0)) / 5;
  for (IntegratorType type : {IntegratorType::Path, IntegratorType::Direct}) {
    SceneDesc s = pointCamera({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 4, 16);
    s.settings.integrator = type;
    s.settings.maxDepth = 1;
    Material floor;
    floor.color = glm::dvec3(albedo);
    Material white;
    white.color = glm::dvec3(1.0);
    s.meshes.push_back({"floor", makePlane(5.0), kOffCentre, s.addMaterial(floor), -1});
    addUnitSphere(s, {-1.6, 0, 1.2});  // clear of the camera ray and the light's
    s.surfaces.back().material = s.addMaterial(white);
    s.pointLights.push_back({light, glm::dvec3(intensity)});
    const Estimate e = renderEstimate(s);
    EXPECT_NEAR(e.mean, expected, 1e-5 * expected) << static_cast<int>(type);
    EXPECT_NEAR(e.standardError, 0.0, 1e-5 * expected) << static_cast<int>(type);
  }
}

// The floor under a quad light (AreaLightsLightLargeFloors' closed form, albedo * L * F)
// with the path integrator, where light samples and BSDF rays that hit the light are
// combined by multiple importance sampling: the weights of a direction sum to one only if
// both use the right densities. The light, 4 x 4 at height 1, subtends so much that both
// strategies carry weight. Tolerance: 6 standard errors of the pixels' mean.
TEST(PathIntegrator, QuadLightOnAFloorMatchesTheFormFactor) {
  const double h = 1, albedo = 0.6, radiance = 2;
  auto corner = [h](double a, double b) {  // Howell C-11, rectangle [0, a] x [0, b]
    const double A = a / h, B = b / h, sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
    return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2 * M_PI);
  };
  // The light covers x in [-1, 3], y in [-2, 2] above the origin: four corner rectangles.
  const double expected = albedo * radiance * 2 * (corner(3, 2) + corner(1, 2));
  SceneDesc s = pointCamera({0, 0, 0.5}, {0, 0, 0}, {0, 1, 0}, 32, 16);
  Material floor;
  floor.color = glm::dvec3(albedo);
  Material light;
  light.type = MaterialType::Emissive;
  light.emission = glm::dvec3(radiance);
  s.meshes.push_back({"floor", makePlane(10.0), kOffCentre, s.addMaterial(floor), -1});
  s.meshes.push_back({"light", makeQuad({-1, -2, h}, {4, 0, 0}, {0, 4, 0}), glm::dmat4(1.0),
                      s.addMaterial(light), -1});
  const Estimate e = renderEstimate(s);
  EXPECT_NEAR(e.mean, expected, 6 * e.standardError) << "expected " << expected;
  EXPECT_GT(e.standardError, 0.0);  // a real estimate, not a degenerate one
}

// The grey-sphere furnace under an image environment, which joins next-event estimation
// (uniform sphere samples, weighted against cosine-weighted BSDF rays): a constant image c
// still gives albedo * c at every point of a convex surface. Tolerance: 6 standard errors
// of the mean over the hit pixels (interior pixels, identically distributed by symmetry).
TEST(PathIntegrator, ImageEnvironmentFurnaceReflectsAlbedoTimesTheImage) {
  const std::string file =
      (std::filesystem::temp_directory_path() / "algray_env_furnace.exr").string();
  writeRowImage(file, 4, {0.6f, 0.6f});
  SceneDesc s = furnace(0.5);
  s.environment.color = glm::dvec3(1.0);
  s.environment.image = file;
  s.settings.spp = 16;
  addSurface(s, "sphere");
  Scene scene(s);
  Image image;
  render(scene, image);
  std::vector<double> values;
  const int w = image.width, h = image.height;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      auto at = [&](int dx, int dy) { return image.id[(y + dy) * w + x + dx] > 0; };
      if (at(0, 0) && at(1, 0) && at(-1, 0) && at(0, 1) && at(0, -1))
        values.push_back(image.color[y * w + x].x);
    }
  ASSERT_GT(values.size(), 50u);
  const Estimate e = estimate(values);
  EXPECT_NEAR(e.mean, 0.5 * 0.6, 6 * e.standardError);
  EXPECT_GT(e.standardError, 0.0);
  std::filesystem::remove(file);
}

// A sheet of glass (n = 1.5) seen at normal incidence reflects F = ((n - 1) / (n + 1))^2 =
// 0.04 and transmits the rest, the radiance from behind scaled by 1 / n^2 (L / n^2 is
// conserved across the interface). Behind it a small emitter of radiance Le: (1 - F) Le / n^2;
// in a constant image environment c (seen both ways): c (F + (1 - F) / n^2). The emitter
// and the environment are reached through a specular bounce, which no light sample could
// have found: their MIS weight is one. Tolerance: 6 standard errors of the pixels' mean.
TEST(PathIntegrator, LightSeenThroughGlassIsScaledByFresnelAndTheIndex) {
  const double n = 1.5, fresnel = std::pow((n - 1) / (n + 1), 2), le = 1.0, c = 0.8;
  const std::string file =
      (std::filesystem::temp_directory_path() / "algray_env_glass.exr").string();
  writeRowImage(file, 4, {static_cast<float>(c), static_cast<float>(c)});
  for (IntegratorType type : {IntegratorType::Path, IntegratorType::Direct})
    for (const bool emitter : {true, false}) {
      SceneDesc s = pointCamera({0, -2, 0}, {0, 0, 0}, {0, 0, 1}, 64, 64);
      s.settings.integrator = type;
      s.settings.maxDepth = 1;  // one bounce (the glass), and what it finds, as pbrt counts
      Material glass;
      glass.type = MaterialType::Dielectric;
      glass.color = glm::dvec3(1.0);
      glass.ior = n;
      // Normal (0, -1, 0), towards the camera: the camera ray enters the glass.
      s.meshes.push_back({"glass", makeQuad({-1, 0, -0.7}, {2, 0, 0}, {0, 0, 2}), glm::dmat4(1.0),
                          s.addMaterial(glass), -1});
      double expected;
      if (emitter) {
        Material light;
        light.type = MaterialType::Emissive;
        light.emission = glm::dvec3(le);
        s.meshes.push_back({"light", makeQuad({-0.2, 1, -0.3}, {0.5, 0, 0}, {0, 0, 0.5}),
                            glm::dmat4(1.0), s.addMaterial(light), -1});
        expected = (1 - fresnel) * le / (n * n);
      } else {
        s.environment.color = glm::dvec3(1.0);
        s.environment.image = file;
        expected = c * (fresnel + (1 - fresnel) / (n * n));
      }
      const Estimate e = renderEstimate(s);
      EXPECT_NEAR(e.mean, expected, 6 * e.standardError)
          << static_cast<int>(type) << " " << emitter << " expected " << expected;
      EXPECT_GT(e.standardError, 0.0);
    }
  std::filesystem::remove(file);
}

// The firefly clamp limits paths with at least one bounce (RenderSettings::clampIndirect):
// an emitter the camera sees directly keeps its radiance above the limit.
TEST(PathIntegrator, FireflyClampSparesEmittersSeenDirectly) {
  SceneDesc s = pointCamera({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 2, 4);
  s.settings.clampIndirect = 1.0;
  Material light;
  light.type = MaterialType::Emissive;
  light.emission = glm::dvec3(5.0);
  s.meshes.push_back({"light", makePlane(1.0), kOffCentre, s.addMaterial(light), -1});
  const Estimate e = renderEstimate(s);
  EXPECT_NEAR(e.mean, 5.0, 1e-6);
}

// The white furnace where paths bounce many times: the gap between two parallel white
// squares (side 2, 0.2 apart) lets the environment in only at the edges, so most paths
// reach Russian roulette (depth 3 on); the radiance is still Le, exactly in expectation,
// only if the survivors are reweighted by 1 / (1 - q). Tolerance: 6 standard errors.
TEST(WhiteFurnace, NarrowGapBetweenWhitePlanesReturnsTheEnvironment) {
  SceneDesc s = pointCamera({0.1, 0.05, 0.1}, {0.1, 0.05, 0}, {0, 1, 0}, 32, 4);
  s.settings.maxDepth = 1000;
  s.environment.color = glm::dvec3(0.7);
  Material white;
  white.color = glm::dvec3(1.0);
  const int m = s.addMaterial(white);
  s.meshes.push_back({"floor", makePlane(1.0), kOffCentre, m, -1});
  s.meshes.push_back(
      {"ceiling", makePlane(1.0), glm::translate(kOffCentre, glm::dvec3(0, 0, 0.2)), m, -1});
  const Estimate e = renderEstimate(s);
  EXPECT_NEAR(e.mean, 0.7, 6 * e.standardError);
  EXPECT_GT(e.standardError, 0.0);
}

// Shading normals do not carry light through a surface: a floor whose interpolated
// normals lean 63 degrees towards +x, above it the camera, below it a point light that
// lies above the tilted shading plane. The light is on the far side of the true surface
// (the geometric normal), so the floor is black.
TEST(PathIntegrator, ShadingNormalsLetNoLightThroughTheSurface) {
  for (IntegratorType type : {IntegratorType::Path, IntegratorType::Direct}) {
    SceneDesc s = pointCamera({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 4, 4);
    s.settings.integrator = type;
    MeshData plane = makePlane(5.0);
    plane.normals.assign(4, glm::normalize(glm::dvec3(1, 0, 0.5)));
    s.meshes.push_back({"floor", plane, kOffCentre, s.addMaterial(Material{}), -1});
    s.pointLights.push_back({{3, 0, -0.5}, glm::dvec3(10.0)});  // (3, 0, -0.5).(1, 0, 0.5) > 0
    const Estimate e = renderEstimate(s);
    EXPECT_EQ(e.mean, 0.0) << static_cast<int>(type);
  }
}

// A background colour replaces the environment for camera rays only: the grey sphere still
// reflects albedo * environment (exactly: every cosine-sampled ray from a convex surface
// escapes, and the diffuse weight is the albedo), while a pixel that misses shows the
// background.
TEST(WhiteFurnace, BackgroundIsSeenOnlyByCameraRays) {
  for (IntegratorType type : {IntegratorType::Path, IntegratorType::Direct}) {
    SceneDesc s = furnace(0.5);
    s.settings.integrator = type;
    s.hasBackground = true;
    s.background = glm::dvec3(0.1, 0.2, 0.3);
    addSurface(s, "sphere");
    Scene scene(s);
    Image image;
    render(scene, image);
    // The central 4 x 4 pixels (all of their samples hit the sphere; outline pixels mix in
    // the background).
    for (int y = 10; y < 14; ++y)
      for (int x = 10; x < 14; ++x) {
        const int i = y * image.width + x;
        ASSERT_GT(image.id[i], 0.0f);
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(image.color[i][k], 0.35, 1e-6) << static_cast<int>(type) << " " << i;
      }
    ASSERT_EQ(image.id[0], 0.0f);  // the corner sees past the sphere
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(image.color[0][k], s.background[k], 1e-6);
  }
}

// ---- The render loop (render.h) ----------------------------------------------------------

// The seed chooses the random numbers (RenderSettings::seed): the same seed gives the
// same image, another seed another one (the noise of a path-traced scene).
TEST(Render, TheSeedChoosesTheRandomStream) {
  SceneDesc s = furnace(0.8);
  addSurface(s, "torus");
  s.meshes.push_back(
      {"floor", makePlane(5.0), glm::translate(glm::dmat4(1.0), {0, 0, -0.6}), 0, -1});
  s.pointLights.push_back({{1, -2, 3}, glm::dvec3(10.0)});
  s.settings.spp = 2;
  s.settings.maxDepth = 5;
  Image images[3];
  for (int k = 0; k < 3; ++k) {
    s.settings.seed = k == 1 ? 1 : 0;
    Scene scene(s);
    render(scene, images[k]);
  }
  int same = 0, other = 0;
  for (size_t i = 0; i < images[0].color.size(); ++i) {
    same += images[0].color[i] != images[2].color[i];
    other += images[0].color[i] != images[1].color[i];
  }
  EXPECT_EQ(same, 0);
  // Most pixels see the noisy torus or floor: far more than a quarter differ.
  EXPECT_GT(other, static_cast<int>(images[0].color.size() / 4));
}

// The normal AOV is a direction: the samples' normals summed and normalised, unit length
// in every pixel where a sample hit (also where others missed, on the outline, or met the
// sphere at other angles) and zero where none did. The albedo AOV is the samples' mean:
// the grey sphere's 0.5 where every sample hit it, 0 where none did.
TEST(Render, NormalAovIsUnitAndAlbedoAovTheMean) {
  SceneDesc s = furnace(0.5);
  s.settings.spp = 8;
  s.settings.maxDepth = 1;
  addUnitSphere(s);
  Scene scene(s);
  Image image;
  render(scene, image);
  const int w = image.width, h = image.height;
  int hits = 0, misses = 0, inside = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      const double length = glm::length(glm::dvec3(image.normal[i]));
      if (image.id[i] == 0) {
        EXPECT_EQ(length, 0.0) << i;
        EXPECT_EQ(image.albedo[i], glm::vec3(0.0f)) << i;
        ++misses;
        continue;
      }
      EXPECT_NEAR(length, 1.0, 1e-6) << i;
      ++hits;
      // A pixel whose eight neighbours all hold a hit lies inside the sphere's (convex)
      // outline: every closed half-plane through a point of it holds one of them.
      if (x == 0 || y == 0 || x + 1 == w || y + 1 == h) continue;
      bool ring = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) ring = ring && image.id[i + dy * w + dx] > 0;
      if (!ring) continue;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(image.albedo[i][k], 0.5, 1e-6) << i;
      ++inside;
    }
  EXPECT_GT(hits, 50);
  EXPECT_GT(misses, 50);
  EXPECT_GT(inside, 20);
}

// A pixel beyond float's range is reported by its column and row (RenderStats::overflowX,
// overflowY, the first in row order) and its value. An orthographic view of the floor 8
// wide and 2 high, 8 x 2 pixels: pixel (x, y) sees the floor point (x - 3.5, 0.5 - y). A
// point light of intensity I = 1e37 at h = 0.01 above the point of pixel (5, 1) gives
// there (0.8 / pi) I / h^2 = 2.5e40, beyond float; one pixel away at most (0.8 / pi) I h /
// (1 + h^2)^(3/2) = 2.5e34, within it.
TEST(Render, PixelsBeyondFloatAreFoundByColumnAndRow) {
  const double intensity = 1e37, h = 0.01;
  SceneDesc s = pointCamera({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 8, 1);
  s.settings.height = 2;
  s.camera.height = 2;
  s.settings.integrator = IntegratorType::Direct;
  s.settings.maxDepth = 1;
  s.meshes.push_back({"floor", makePlane(10.0), kOffCentre, s.addMaterial(Material{}), -1});
  s.pointLights.push_back({{1.5, -0.5, h}, glm::dvec3(intensity)});
  Scene scene(s);
  Image image;
  const RenderStats stats = render(scene, image);
  EXPECT_EQ(stats.overflowPixels, 1u);
  EXPECT_EQ(stats.overflowX, 5);
  EXPECT_EQ(stats.overflowY, 1);
  const double expected = 0.8 / kPi * intensity / (h * h);
  EXPECT_NEAR(stats.overflowValue, expected, 1e-4 * expected);
  // The value is the pixel's mean over its samples: at 4 samples a pixel, every sample of
  // the 2 x 2 pinhole-thin view sees the point below the light, each the same 2.5e40.
  SceneDesc thin = pointCamera({1.5, -0.5, 1}, {1.5, -0.5, 0}, {0, 1, 0}, 2, 4);
  thin.settings.integrator = IntegratorType::Direct;
  thin.settings.maxDepth = 1;
  thin.meshes = s.meshes;
  thin.materials = s.materials;
  thin.pointLights = s.pointLights;
  Scene thinScene(thin);
  const RenderStats four = render(thinScene, image);
  EXPECT_EQ(four.overflowPixels, 4u);
  EXPECT_NEAR(four.overflowValue, expected, 1e-4 * expected);
}

// The ray count adds up every thread's: a scene whose camera rays all miss (the sphere is
// behind the camera) traces exactly one ray a sample, width x height x spp, on two threads.
TEST(Render, RayCountIsEveryThreadsSum) {
  SceneDesc s = furnace(0.5);
  s.settings.width = s.settings.height = 64;  // 16 tiles to share
  s.settings.spp = 128;                       // enough work for the second thread to join in
  s.settings.threads = 2;
  addUnitSphere(s, {0, -10, 0});
  Scene scene(s);
  Image image;
  const RenderStats stats = render(scene, image);
  ASSERT_EQ(*std::max_element(image.id.begin(), image.id.end()), 0.0f);  // nothing hit
  EXPECT_EQ(stats.rays, 64u * 64u * 128u);
}

// Cancellation is checked before every pixel, not only between tiles: one 16 x 16 tile at
// 32768 samples a pixel (seconds of work) is cancelled 50 ms in and stops there, the tile
// unfinished (a 16x16 image at --spp 1048576 ran on for 10 minutes after Ctrl-C).
TEST(Cancel, StopsWithinATile) {
  SceneDesc s = furnace(0.8);
  s.settings.width = s.settings.height = 16;
  s.settings.spp = 32768;
  addSurface(s, "sphere");
  Scene scene(s);
  Image image;
  std::atomic<bool> cancel{false};
  RenderOptions options;
  options.cancel = &cancel;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    cancel = true;
  });
  const RenderStats stats = render(scene, image, options);
  stopper.join();
  EXPECT_TRUE(stats.interrupted);
  EXPECT_EQ(stats.tilesDone, 0);
  EXPECT_EQ(stats.tilesTotal, 1);
}

}  // namespace
}  // namespace algray::render
