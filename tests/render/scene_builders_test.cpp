// Scenes built without a file: quick mode framing and the POV-Ray export used by
// tests/bench/povray_compare.py.
#include "camera.h"
#include "pov_export.h"
#include "scene_builders.h"

#include <algray/gallery.h>
#include <algray/parser.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <regex>
#include <string>

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

TEST(QuickScene, BadEquationThrowsParseError) {
  QuickOptions q;
  q.surface = "x^2 + * 3";
  EXPECT_THROW(quickScene(q), ParseError);
}

// --param values the surface never reads are refused by name: a parameter the equation
// does not use, any parameter of a gallery surface (whose parameters are built in).
TEST(QuickScene, RefusesParametersTheSurfaceDoesNotUse) {
  auto expectRefused = [](const QuickOptions& q, const std::string& name, const std::string& message) {
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
  for (auto it = std::sregex_iterator(pov.begin(), pov.end(), term); it != std::sregex_iterator(); ++it, ++terms) {
    int i = std::stoi((*it)[1]), j = std::stoi((*it)[2]), k = std::stoi((*it)[3]);
    EXPECT_EQ(std::stod((*it)[4]), p.coeff(i, j, k)) << i << " " << j << " " << k;
  }
  EXPECT_EQ(terms, p.nonZeroCount());
}

TEST(DefaultScene, SurfacesOfDifferentDegreesBesideMeshes) {
  SceneDesc s = defaultScene();
  ASSERT_GE(s.surfaces.size(), 3u);
  for (size_t i = 1; i < s.surfaces.size(); ++i)
    EXPECT_NE(s.surfaces[i].polynomial.degree(), s.surfaces[i - 1].polynomial.degree());
  int emissive = 0;
  for (const MeshItem& m : s.meshes) emissive += s.materials[m.material].type == MaterialType::Emissive;
  EXPECT_EQ(emissive, 1);                  // the area light
  EXPECT_GE(s.meshes.size() - emissive, 2u);  // floor and icosphere
}

}  // namespace
}  // namespace algray::render
