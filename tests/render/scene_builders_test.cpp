// Scenes built without a file: quick mode framing and the POV-Ray export used by
// tests/bench/povray_compare.py.
#include "scene_builders.h"
#include "camera.h"
#include "mesh.h"
#include "pov_export.h"

#include <algray/gallery.h>
#include <algray/parser.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

namespace algray::render {
namespace {

TEST(QuickScene, ClipSphereFillsMostOfTheFrame) {
  QuickOptions q;
  q.surface = "x^2 + y^2 + z^2 - 1";
  q.clipRadius = 1.5;
  SceneDesc s = quickScene(q);
  ASSERT_EQ(s.surfaces.size(), 1u);
  const auto& clip = std::get<ClipSphere>(s.surfaces[0].clip);
  EXPECT_EQ(clip.radius, 1.5);
  // The ray through the top-centre pixel passes outside the clip sphere, the one a
  // tenth of the height lower passes through it: the sphere nearly fills the height.
  Camera cam(s.camera, s.settings.width, s.settings.height);
  auto missDistance = [&](double y) {
    CameraRay r = cam.generateRay({s.settings.width / 2.0, y}, {0.5, 0.5});
    glm::dvec3 toCenter = clip.center - r.org;
    return glm::length(toCenter - glm::dot(toCenter, r.dir) * r.dir);
  };
  EXPECT_GT(missDistance(0.0), clip.radius);
  EXPECT_LT(missDistance(0.1 * s.settings.height), clip.radius);
}

// Quick mode's scene of `surface` for a w x h image.
SceneDesc quickSceneSized(const std::string& surface, int w, int h) {
  QuickOptions q;
  q.surface = surface;
  q.width = w;
  q.height = h;
  return quickScene(q);
}

// A portrait image frames the clip sphere in its width (framed by the height alone, a
// 60 x 240 image cut the sphere off at both sides), and one size given alone keeps quick
// mode's square (--width 200 made 200 x 512).
TEST(QuickScene, ClipSphereFitsTheShorterSide) {
  for (const auto& [w, h] : {std::pair{60, 240}, std::pair{240, 60}, std::pair{300, 300}}) {
    const SceneDesc s = quickSceneSized("x^2 + y^2 + z^2 - 1", w, h);
    ASSERT_EQ(s.settings.width, w);
    ASSERT_EQ(s.settings.height, h);
    const auto& clip = std::get<ClipSphere>(s.surfaces[0].clip);
    const Camera cam(s.camera, w, h);
    auto missDistance = [&](double x, double y) {
      const CameraRay r = cam.generateRay({x, y}, {0.5, 0.5});
      const glm::dvec3 toCenter = clip.center - r.org;
      return glm::length(toCenter - glm::dot(toCenter, r.dir) * r.dir);
    };
    // The rays through the middle of each edge pass outside the sphere; the rays a tenth of
    // the shorter side in from the edges of the shorter side pass through it.
    EXPECT_GT(missDistance(0.0, h / 2.0), clip.radius) << w << "x" << h;
    EXPECT_GT(missDistance(w, h / 2.0), clip.radius) << w << "x" << h;
    EXPECT_GT(missDistance(w / 2.0, 0.0), clip.radius) << w << "x" << h;
    EXPECT_GT(missDistance(w / 2.0, h), clip.radius) << w << "x" << h;
    const double in = 0.1 * std::min(w, h);
    if (w <= h) {
      EXPECT_LT(missDistance(in, h / 2.0), clip.radius) << w << "x" << h;
    } else {
      EXPECT_LT(missDistance(w / 2.0, in), clip.radius) << w << "x" << h;
    }
  }
  for (const bool widthOnly : {true, false}) {
    QuickOptions q;
    q.surface = "x^2 + y^2 + z^2 - 1";
    (widthOnly ? q.width : q.height) = 200;
    const SceneDesc s = quickScene(q);
    EXPECT_EQ(s.settings.width, 200);
    EXPECT_EQ(s.settings.height, 200);
  }
}

// scene_builders.h: the floor is at z = -R; the code's comment and its range checks say
// it is 40 R across. So its corners, placed by the item's transform, are (+-20 R, +-20 R,
// -R), and with kMaxCoordinate = 1e17 (value_checks.h) the largest radius is
// 1e17 / 20 = 5e15 and the smallest 1e-15 / 40 = 2.5e-17 (kMinMeshExtent).
TEST(QuickScene, FloorIsFortyRadiiAcrossOneRadiusBelowTheCentre) {
  QuickOptions q;
  q.surface = "x^2 + y^2 + z^2 - 1";
  q.clipRadius = 1.5;
  const SceneDesc s = quickScene(q);
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_FALSE(s.meshes[0].mesh.positions.empty());
  for (const glm::dvec3& p : s.meshes[0].mesh.positions) {
    const glm::dvec3 w(s.meshes[0].transform * glm::dvec4(p, 1.0));
    EXPECT_EQ(std::abs(w.x), 30.0);
    EXPECT_EQ(std::abs(w.y), 30.0);
    EXPECT_EQ(w.z, -1.5);
  }
  q.clipRadius = 5e15;
  EXPECT_NO_THROW(quickScene(q));
  q.clipRadius = 1e16;
  EXPECT_THROW(quickScene(q), Error);
  q.clipRadius = 3e-17;
  EXPECT_NO_THROW(quickScene(q));
  q.clipRadius = 2e-17;
  EXPECT_THROW(quickScene(q), Error);
}

TEST(QuickScene, BadEquationThrowsParseError) {
  QuickOptions q;
  q.surface = "x^2 + * 3";
  EXPECT_THROW(quickScene(q), ParseError);
}

// A gallery name as people type it renders that surface; one that is neither a gallery
// name nor an equation keeps the parser's column and names the close gallery surfaces.
TEST(QuickScene, GalleryNamesAsTypedAndSuggestions) {
  QuickOptions q;
  q.surface = "Barth_Sextic";
  const SceneDesc s = quickScene(q);
  EXPECT_EQ(s.name, "barth-sextic");
  ASSERT_EQ(s.surfaces.size(), 1u);
  EXPECT_EQ(s.surfaces[0].polynomial.degree(), 6);
  auto message = [](const std::string& text) -> std::pair<int, std::string> {
    QuickOptions bad;
    bad.surface = text;
    try {
      quickScene(bad);
    } catch (const ParseError& e) {
      return {e.column(), e.message()};
    }
    return {0, "accepted"};
  };
  auto [column, text] = message("barth");
  EXPECT_EQ(column, 1);
  EXPECT_NE(text.find("unknown name 'barth'"), std::string::npos) << text;
  EXPECT_NE(text.find("one of the gallery surfaces 'barth-sextic', 'barth-decic'?"),
            std::string::npos)
      << text;
  std::tie(column, text) = message("chmutov8");
  EXPECT_NE(text.find("the gallery surface 'chmutov-8'?"), std::string::npos) << text;
  std::tie(column, text) = message("dodecahedron");
  EXPECT_NE(text.find("nor is it a gallery surface: sphere, "), std::string::npos) << text;
  // An equation's error gets no gallery hint; an unknown name in it, how to give it a value.
  std::tie(column, text) = message("x^2 + * 3");
  EXPECT_EQ(column, 7);
  EXPECT_EQ(text.find("gallery"), std::string::npos) << text;
  std::tie(column, text) = message("x²+y²+z²−a");
  EXPECT_EQ(column, 10);
  EXPECT_EQ(text, "unknown name 'a' (give it a value with --param a=VALUE)");
}

// --param values the surface never reads are refused by name: a parameter the equation
// does not use, any parameter of a gallery surface (whose parameters are built in).
TEST(QuickScene, RefusesParametersTheSurfaceDoesNotUse) {
  auto expectRefused = [](const QuickOptions& q, const std::string& name,
                          const std::string& message) {
    try {
      quickScene(q);
      ADD_FAILURE() << "parameter " << name << " accepted for " << q.surface;
    } catch (const ParameterError& e) {
      EXPECT_EQ(e.name(), name);
      EXPECT_NE(e.message().find(message), std::string::npos) << e.message();
    }
  };
  QuickOptions q;
  q.surface = "x^2 + y^2 + z^2 - r^2";
  q.parameters = {{"r", 1.0}};
  EXPECT_EQ(quickScene(q).surfaces.size(), 1u);
  q.parameters["s"] = 2.0;
  expectRefused(q, "s", "not used");
  q.surface = gallery().front().name;
  q.parameters = {{"r", 1.0}};
  expectRefused(q, "r", "takes no parameters");
}

// Quick mode's warning for a surface outside its clip sphere tells "nowhere" from "farther
// out" where the terms show it: all even powers with the constant's sign have no real zero.
TEST(QuickScene, NoRealPointsWhenTheTermsShowIt) {
  for (const char* none : {"x^2+y^2+z^2+1", "(x^2+y^2+z^2)^2+1", "-x^4-2*y^2*z^2-3", "5"})
    EXPECT_TRUE(evidentlyHasNoRealPoints(parsePolynomial(none))) << none;
  // A real point, or signs that do not tell (x^2 - y^2 + 1 has points; so may others).
  for (const char* some : {"x^2+y^2+z^2-100", "x^2-y^2+1", "x^2+y^2+z^2", "x^3+1", "x^2*y+1",
                           "(x^2+y^2+z^2-1)^2+1", "x^2+y^2+z^2+1-0.5*x*y"})
    EXPECT_FALSE(evidentlyHasNoRealPoints(parsePolynomial(some))) << some;
}

TEST(PovExport, PolynomialTermsMatchTheSurface) {
  QuickOptions q;
  q.surface = "barth-sextic";
  SceneDesc s = quickScene(q);
  std::string pov = povrayScene(s, false);
  const Polynomial& p = s.surfaces[0].polynomial;
  EXPECT_NE(pov.find("polynomial { " + std::to_string(p.degree())), std::string::npos);
  EXPECT_NE(pov.find("clipped_by { sphere"), std::string::npos);
  EXPECT_NE(pov.find("parallel"), std::string::npos);
  // Every xyz(i, j, k): c term reads back to the coefficient; every non-zero one is there.
  std::regex term(R"(xyz\((\d+), (\d+), (\d+)\): ([-+0-9.eE]+))");
  int terms = 0;
  for (auto it = std::sregex_iterator(pov.begin(), pov.end(), term); it != std::sregex_iterator();
       ++it, ++terms) {
    int i = std::stoi((*it)[1]), j = std::stoi((*it)[2]), k = std::stoi((*it)[3]);
    EXPECT_EQ(std::stod((*it)[4]), p.coeff(i, j, k)) << i << " " << j << " " << k;
  }
  EXPECT_EQ(terms, p.nonZeroCount());
}

// POV-Ray's camera angle is the horizontal field of view algray's camera has: the angle
// between the rays through the middle of the left and right edges (a portrait quick scene
// was exported with the vertical angle's rule, 15.26 degrees instead of 30).
TEST(PovExport, CameraAngleIsTheImagesHorizontalView) {
  for (const auto& [w, h] : {std::pair{200, 400}, std::pair{400, 200}, std::pair{300, 300}}) {
    const SceneDesc s = quickSceneSized("sphere", w, h);
    const std::string pov = povrayScene(s, false);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(pov, m, std::regex(R"(angle ([-+0-9.eE]+))"))) << pov;
    const Camera cam(s.camera, w, h);
    const glm::dvec3 left = cam.generateRay({0.0, h / 2.0}, {0.5, 0.5}).dir;
    const glm::dvec3 right = cam.generateRay({double(w), h / 2.0}, {0.5, 0.5}).dir;
    const double across = std::acos(glm::dot(left, right)) * 180.0 / std::acos(-1.0);
    EXPECT_NEAR(std::stod(m[1]), across, 1e-9) << w << "x" << h;
  }
}

// Meshes are exported as the same triangles in scene space (every 2-triangle mesh was an
// infinite plane through its transform's z axis: a vertical wall became a floor), and a
// surface of a degree POV-Ray's polynomial does not take is refused.
TEST(PovExport, MeshesAreTheirTrianglesAndHighDegreesAreRefused) {
  QuickOptions q;
  q.surface = "sphere";
  SceneDesc s = quickScene(q);
  MeshItem wall;
  wall.mesh = makePlane(2.0, 1.0);
  wall.transform =
      glm::dmat4(1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 5, 0, 0, 1);  // x = 5 + x', z = y'
  wall.material = s.meshes.front().material;
  s.meshes = {wall};
  const std::string pov = povrayScene(s, false);
  EXPECT_EQ(pov.find("plane {"), std::string::npos) << pov;
  ASSERT_NE(pov.find("mesh2 {"), std::string::npos) << pov;
  // Every exported vertex is the transformed one: on the wall (y = 0), z in [-2, 2].
  std::regex vertex(R"(<([-+0-9.eE]+), ([-+0-9.eE]+), ([-+0-9.eE]+)>)");
  const size_t from = pov.find("vertex_vectors"), to = pov.find("normal_vectors", from);
  ASSERT_NE(to, std::string::npos) << pov;
  const std::string vertices = pov.substr(from, to - from);
  int count = 0;
  for (auto it = std::sregex_iterator(vertices.begin(), vertices.end(), vertex);
       it != std::sregex_iterator(); ++it) {
    const glm::dvec3 v(std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]));
    const glm::dvec3 expected(wall.transform * glm::dvec4(wall.mesh.positions[count++], 1.0));
    EXPECT_EQ(v, expected);
  }
  EXPECT_EQ(count, static_cast<int>(wall.mesh.positions.size()));
  q.surface = "x^36 + y^36 + z^36 - 1";
  q.clipRadius = 2;
  EXPECT_THROW(
      {
        try {
          povrayScene(quickScene(q), false);
        } catch (const std::runtime_error& e) {
          EXPECT_NE(std::string(e.what()).find("degree <= 35"), std::string::npos) << e.what();
          throw;
        }
      },
      std::runtime_error);
}

// A plane was written as `polynomial { 1, ... }`, which POV-Ray 3.7 refuses ("Order of
// polynom is out of range": its orders are 2..35), with exit code 0; it is order 2 with
// the plane's terms only. POV-Ray itself, when installed, is the reference that parses it.
TEST(PovExport, PlanesAreOrderTwoPolynomialsPovRayParses) {
  QuickOptions q;
  q.surface = "x + y + z - 0.5";
  const SceneDesc s = quickScene(q);
  const std::string pov = povrayScene(s, false);
  EXPECT_NE(pov.find("polynomial { 2,"), std::string::npos) << pov;
  std::regex term(R"(xyz\((\d+), (\d+), (\d+)\): ([-+0-9.eE]+))");
  int terms = 0;
  for (auto it = std::sregex_iterator(pov.begin(), pov.end(), term); it != std::sregex_iterator();
       ++it, ++terms) {
    const int i = std::stoi((*it)[1]), j = std::stoi((*it)[2]), k = std::stoi((*it)[3]);
    EXPECT_LE(i + j + k, 1);
    EXPECT_EQ(std::stod((*it)[4]), i + j + k == 1 ? 1.0 : -0.5) << i << " " << j << " " << k;
  }
  EXPECT_EQ(terms, 4);
  if (std::system("command -v povray > /dev/null 2>&1") != 0) GTEST_SKIP() << "no povray";
  const auto dir = std::filesystem::temp_directory_path();
  const std::string file = (dir / "algray_pov_plane.pov").string();
  const std::string image = (dir / "algray_pov_plane.png").string();
  std::ofstream(file) << pov;
  const std::string command =
      "povray +I" + file + " +O" + image + " +W8 +H8 -D -V > /dev/null 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  std::filesystem::remove(file);
  std::filesystem::remove(image);
}

// An image environment was exported as its colour alone (a white background and ambient
// light for any image), with exit code 0, though coloured environments are refused.
TEST(PovExport, ImageEnvironmentsAreRefused) {
  QuickOptions q;
  q.surface = "sphere";
  SceneDesc s = quickScene(q);
  s.environment.color = glm::dvec3(1.0);
  EXPECT_NO_THROW(povrayScene(s, false));
  s.environment.image = "sky.exr";
  EXPECT_THROW(
      {
        try {
          povrayScene(s, false);
        } catch (const std::runtime_error& e) {
          EXPECT_NE(std::string(e.what()).find("image environments are not exported"),
                    std::string::npos)
              << e.what();
          throw;
        }
      },
      std::runtime_error);
}

TEST(DefaultScene, SurfacesOfDifferentDegreesBesideMeshes) {
  SceneDesc s = defaultScene();
  ASSERT_GE(s.surfaces.size(), 3u);
  for (size_t i = 1; i < s.surfaces.size(); ++i)
    EXPECT_NE(s.surfaces[i].polynomial.degree(), s.surfaces[i - 1].polynomial.degree());
  int emissive = 0;
  for (const MeshItem& m : s.meshes)
    emissive += s.materials[m.material].type == MaterialType::Emissive;
  EXPECT_EQ(emissive, 1);                     // the area light
  EXPECT_GE(s.meshes.size() - emissive, 2u);  // floor and icosphere
}

// The numbers of the exported scene are algray's (a scene built here, not by quick mode:
// a camera off the axes, a coloured directional light, front and back materials, a
// background):
//  * POV-Ray's camera is left-handed; with `right` along -x at the image's aspect (its
//    documentation's recipe for right-handed coordinates) the picture is not mirrored;
//  * positions keep every digit (1/3 reads back as the same double);
//  * a `parallel` light shines from its location towards point_at: the location lies along
//    algray's direction, which points towards the light;
//  * algray's Lambertian floor reflects (albedo / pi) E cos under irradiance E, POV-Ray's
//    `diffuse 1 brilliance 1` pigment * colour * cos: the light's colour is E / pi;
//  * the direct integrator adds albedo times the (grey) environment as ambient light, POV-Ray
//    pigment * ambient * ambient_light (1): `ambient` is the environment's grey;
//  * the background, the clip sphere's radius, the back material's colour as the interior
//    texture, and each triangle's vertices in their order (which side is the front).
TEST(PovExport, CameraLightsAndColoursAreAlgraysNumbers) {
  SceneDesc s;
  s.settings.width = 40;
  s.settings.height = 30;
  s.camera.position = {1.0 / 3.0, -6, 2.0 / 3.0};
  s.camera.lookAt = {0, 0, 0};
  s.environment.color = glm::dvec3(0.25);
  s.hasBackground = true;
  s.background = {0.1, 0.2, 0.3};
  s.directionalLights.push_back({{1, 2, 2}, {3, 1.5, 0.75}});
  Material front, back;
  front.color = {0.5, 0.25, 0.125};
  back.color = {0.2, 0.4, 0.6};
  const int f = s.addMaterial(front), b = s.addMaterial(back);
  SurfaceItem sphere;
  sphere.polynomial = parsePolynomial("x^2 + y^2 + z^2 - 1");
  sphere.clip = ClipSphere{glm::dvec3(0.0), 1.5};
  sphere.material = f;
  sphere.backMaterial = b;
  s.surfaces.push_back(sphere);
  MeshItem floor;
  floor.mesh.positions = {{-2, -2, -1}, {2, -2, -1}, {2, 2, -1}, {-2, 2, -1}};
  floor.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  floor.material = f;
  floor.backMaterial = b;
  s.meshes.push_back(floor);
  const std::string pov = povrayScene(s, false);
  const std::string number = "([-+0-9.eE]+)";
  const std::string triple = "<" + number + ", " + number + ", " + number + ">";
  auto vectorAfter = [&](const std::string& prefix) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(pov, m, std::regex(prefix + triple))) << prefix << "\n" << pov;
    return m.empty() ? glm::dvec3(0.0)
                     : glm::dvec3(std::stod(m[1]), std::stod(m[2]), std::stod(m[3]));
  };
  auto numberAfter = [&](const std::string& prefix) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(pov, m, std::regex(prefix + number))) << prefix << "\n" << pov;
    return m.empty() ? 0.0 : std::stod(m[1]);
  };
  EXPECT_EQ(vectorAfter(R"(right )").x, -40.0 / 30.0);
  EXPECT_EQ(vectorAfter(R"(location )"), s.camera.position);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      pov, m, std::regex(R"(light_source \{ )" + triple + " color rgb " + triple + " parallel")))
      << pov;
  const glm::dvec3 light(std::stod(m[1]), std::stod(m[2]), std::stod(m[3]));
  const glm::dvec3 towards(1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0);  // (1, 2, 2) normalised
  EXPECT_NEAR(glm::dot(glm::normalize(light), towards), 1.0, 1e-12);
  const double pi = std::acos(-1.0);
  EXPECT_NEAR(std::stod(m[4]), 3 / pi, 1e-15);
  EXPECT_NEAR(std::stod(m[5]), 1.5 / pi, 1e-15);
  EXPECT_NEAR(std::stod(m[6]), 0.75 / pi, 1e-15);
  EXPECT_EQ(vectorAfter(R"(background \{ color rgb )"), s.background);
  EXPECT_EQ(numberAfter(R"(clipped_by \{ sphere \{ <0, 0, 0>, )"), 1.5);
  // Every texture's ambient is the environment's grey; the front pigments are the front
  // material's colour, the interior ones the back material's (one each for the surface and
  // the mesh).
  std::regex ambient("ambient " + number);
  int ambients = 0;
  for (auto it = std::sregex_iterator(pov.begin(), pov.end(), ambient);
       it != std::sregex_iterator(); ++it, ++ambients)
    EXPECT_EQ(std::stod((*it)[1]), 0.25);
  EXPECT_EQ(ambients, 4);
  for (const auto& [kind, material] : {std::pair{std::string("  texture"), front},
                                       std::pair{std::string("interior_texture"), back}}) {
    std::regex pigment(kind + R"( \{ pigment \{ color rgb )" + triple);
    int count = 0;
    for (auto it = std::sregex_iterator(pov.begin(), pov.end(), pigment);
         it != std::sregex_iterator(); ++it, ++count)
      EXPECT_EQ(glm::dvec3(std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3])),
                material.color)
          << kind;
    EXPECT_EQ(count, 2) << kind;
  }
  EXPECT_NE(pov.find("face_indices { 2, <0, 1, 2>, <0, 2, 3> }"), std::string::npos) << pov;
}

// A thin-lens camera (aperture > 0) has no POV-Ray counterpart here: refused, as an
// orthographic one is, rather than exported as a pinhole with everything in focus.
TEST(PovExport, ThinLensCamerasAreRefused) {
  QuickOptions q;
  q.surface = "sphere";
  SceneDesc s = quickScene(q);
  EXPECT_NO_THROW(povrayScene(s, false));
  s.camera.aperture = 0.05;
  try {
    povrayScene(s, false);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "POV-Ray export: only pinhole perspective cameras");
  }
}

// POV-Ray takes the picture's height from the length of `up` (look_at turns up and right
// about sky, keeping their lengths): an up of length 3 is exported as the unit vector, and
// one that is no direction is refused.
TEST(PovExport, UpIsWrittenAsAUnitVector) {
  QuickOptions q;
  q.surface = "sphere";
  SceneDesc s = quickScene(q);
  s.camera.up = {0, 0, 3};
  const std::string pov = povrayScene(s, false);
  EXPECT_NE(pov.find(" up <0, 0, 1> "), std::string::npos) << pov;
  EXPECT_NE(pov.find(" sky <0, 0, 1> "), std::string::npos) << pov;
  s.camera.up = {0, 0, 0};
  EXPECT_THROW(povrayScene(s, false), std::runtime_error);
}

// What POV-Ray cannot be given the same way is refused, not exported as something else:
// a coloured environment (the ambient light is one grey), a textured or non-diffuse
// material (a plain pigment), a surface with a transform or a clip box (the polynomial is
// written in scene space, clipped by a sphere), a point light.
TEST(PovExport, WhatPovRayCannotBeGivenIsRefused) {
  QuickOptions q;
  q.surface = "sphere";
  const SceneDesc base = quickScene(q);
  ASSERT_NO_THROW(povrayScene(base, false));
  const auto refused = [&](SceneDesc s, const std::string& message) {
    try {
      povrayScene(s, false);
      ADD_FAILURE() << "no error for " << message;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "POV-Ray export: " + message);
    }
  };
  SceneDesc s = base;
  s.environment.color = {0.5, 0.5, 0.6};
  refused(s, "grey environments only");
  s = base;
  Material textured = s.materials.at(s.surfaces[0].material);
  textured.texture = std::make_shared<const Texture>(1, 1, std::vector<glm::vec3>{glm::vec3(1)});
  s.surfaces[0].material = s.addMaterial(textured);
  refused(s, "untextured diffuse materials only");
  s = base;
  Material metal;
  metal.type = MaterialType::Conductor;
  s.surfaces[0].backMaterial = s.addMaterial(metal);
  refused(s, "untextured diffuse materials only");
  s = base;
  s.surfaces[0].transform[3] = glm::dvec4(0, 0, 1, 1);  // moved up by 1
  refused(s, "surfaces need a clip sphere and no transform");
  s = base;
  s.surfaces[0].clip = ClipBox{glm::dvec3(-1), glm::dvec3(1)};
  refused(s, "surfaces need a clip sphere and no transform");
  s = base;
  s.pointLights.push_back({{0, 0, 3}, glm::dvec3(1.0)});
  refused(s, "point lights are not exported");
}

}  // namespace
}  // namespace algray::render
