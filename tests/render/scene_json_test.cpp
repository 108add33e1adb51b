// Scene files: what they mean, and errors that point at file:line:column.
#include "scene_json.h"

#include "json_locate.h"

#include "algray/gallery.h"
#include "algray/parser.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <tuple>
#include <vector>

namespace algray::render {
namespace {

// The error a scene text raises, or "" when it loads.
SceneError errorOf(const std::string& text) {
  try {
    loadSceneText(text, "t.json", ".");
  } catch (const SceneError& e) {
    return e;
  }
  return SceneError("", -1, -1, "no error");
}

TEST(JsonLocate, LineAndColumnCountFromOne) {
  std::string text = "{\n  \"a\": [1,\n   2]\n}";
  auto where = locateJsonValues(text);
  // Independent reference: find the characters by hand.
  size_t one = text.find('1'), two = text.find('2');
  EXPECT_EQ(where.at("/a/0"), one);
  EXPECT_EQ(where.at("/a/1"), two);
  TextLocation loc = locateOffset(text, two);
  EXPECT_EQ(loc.line, 3);
  EXPECT_EQ(loc.column, 4);
}

TEST(SceneJson, ReadsEverySection) {
  SceneDesc s = loadSceneText(R"({
    "render": {"width": 32, "height": 16, "spp": 3, "integrator": "direct", "seed": 7, "max_depth": 2},
    "camera": {"position": [0, -4, 1], "look_at": [0, 0, 0], "fov": 50},
    "materials": {"m": {"type": "conductor", "color": [0.9, 0.8, 0.7], "roughness": 0.2}},
    "surfaces": [{"equation": "x^2 + y^2 + z^2 - r^2", "parameters": {"r": 0.5},
                  "clip": {"sphere": {"radius": 1}}, "material": "m",
                  "transform": {"translate": [0, 0, 1]}}],
    "meshes": [{"shape": "plane", "size": 5}],
    "lights": [{"type": "point", "position": [1, 2, 3], "intensity": 5},
               {"type": "quad", "corner": [0, 0, 3], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "radiance": 2}],
    "environment": {"color": 0.25}
  })",
                              "t.json", ".");
  EXPECT_EQ(s.settings.width, 32);
  EXPECT_EQ(s.settings.height, 16);
  EXPECT_EQ(s.settings.spp, 3);
  EXPECT_EQ(s.settings.integrator, IntegratorType::Direct);
  EXPECT_EQ(s.settings.seed, 7u);
  ASSERT_EQ(s.surfaces.size(), 1u);
  // x^2 + y^2 + z^2 - 0.25: the parameter reached the parser.
  EXPECT_DOUBLE_EQ(s.surfaces[0].polynomial.coeff(0, 0, 0), -0.25);
  EXPECT_EQ(s.materials[s.surfaces[0].material].type, MaterialType::Conductor);
  EXPECT_DOUBLE_EQ(s.surfaces[0].transform[3][2], 1.0);
  ASSERT_EQ(s.meshes.size(), 2u);  // the plane and the quad light
  EXPECT_EQ(s.materials[s.meshes[1].material].type, MaterialType::Emissive);
  EXPECT_EQ(s.pointLights.size(), 1u);
  EXPECT_DOUBLE_EQ(s.environment.color.g, 0.25);
}

TEST(SceneJson, SyntaxErrorHasLineAndColumn) {
  SceneError e = errorOf("{\n  \"render\": {\"width\": 10,,}\n}");
  EXPECT_EQ(e.file(), "t.json");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 26);  // the second comma
}

TEST(SceneJson, SemanticErrorsPointAtTheValue) {
  // Unknown material: the string value on line 3.
  SceneError a =
      errorOf("{\n \"surfaces\": [\n  {\"gallery\": \"sphere\", \"material\": \"gold\"}]}");
  EXPECT_EQ(a.line(), 3);
  EXPECT_EQ(a.column(), 37);
  EXPECT_NE(a.message().find("gold"), std::string::npos);
  // Wrong type.
  SceneError b = errorOf("{\"render\": {\"width\": \"wide\"}}");
  EXPECT_EQ(b.line(), 1);
  EXPECT_EQ(b.column(), 22);
  // Unknown key (typo) points at the key's value.
  SceneError c = errorOf("{\"camera\": {\"postion\": [0, 0, 1]}}");
  EXPECT_EQ(c.column(), 24);
  EXPECT_NE(c.message().find("postion"), std::string::npos);
  // An unknown gallery name: its value, the close names, every name.
  SceneError g = errorOf("{\"surfaces\": [{\"gallery\": \"tours\"}]}");
  EXPECT_EQ(g.column(), 27);
  EXPECT_NE(g.message().find("no gallery surface 'tours'; did you mean 'torus'? (known: sphere, "),
            std::string::npos)
      << g.message();
  // No clip region for an equation.
  SceneError d = errorOf("{\"surfaces\": [{\"equation\": \"x^2 + y^2 - 1\"}]}");
  EXPECT_EQ(d.column(), 15);
  EXPECT_NE(d.message().find("clip"), std::string::npos);
  // A camera whose up is the view direction: the up value (the camera found it only when
  // the render started, without a position, exit code 1).
  SceneError u =
      errorOf("{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]}}");
  EXPECT_EQ(u.column(), 64);
  EXPECT_NE(u.message().find("parallel"), std::string::npos);
  // A parameter named after a variable: its value on line 2, not the equation.
  SceneError v = errorOf(
      "{\"surfaces\": [{\"equation\": \"x^2 + y^2 + z^2 - 1\", \"clip\": {\"sphere\": {\"radius\": "
      "2}},\n"
      "  \"parameters\": {\"x\": 1}}]}");
  EXPECT_EQ(v.line(), 2);
  EXPECT_EQ(v.column(), 23);
  // Named as --param names it ("--param: x: clashes ..."): the position alone left the
  // reader to find which key the value belongs to.
  EXPECT_NE(v.message().find("parameter 'x': clashes with the built-in name 'x'"),
            std::string::npos)
      << v.message();
  // A parameter the equation never reads: its value, on line 2.
  SceneError w = errorOf(
      "{\"surfaces\": [{\"equation\": \"x^2 + y^2 + z^2 - r^2\", \"clip\": {\"sphere\": "
      "{\"radius\": 2}},\n"
      "  \"parameters\": {\"r\": 1, \"rr\": 2}}]}");
  EXPECT_EQ(w.line(), 2);
  EXPECT_EQ(w.column(), 32);
  EXPECT_NE(w.message().find("parameter 'rr': is not used"), std::string::npos) << w.message();
  // "description" is free text, but text: a number was accepted.
  SceneError x = errorOf("{\"description\": 5}");
  EXPECT_EQ(x.column(), 17);
}

TEST(SceneJson, EquationErrorPointsIntoTheString) {
  // The '@' is the 7th character of the equation; the string starts at column 28.
  std::string text =
      "{\"surfaces\": [{\"equation\": \"x^2 + @\", \"clip\": {\"sphere\": {\"radius\": 1}}}]}";
  SceneError e = errorOf(text);
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(static_cast<size_t>(e.column()), text.find('@') + 1);
  // Multi-byte characters and escapes before the error (the file's columns count
  // characters): the '@' itself, also behind a name with a multi-byte character earlier on
  // the line; past the equation's end, its closing quote.
  auto characterColumn = [](const std::string& t, size_t byte) {
    return 1 + std::count_if(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(byte),
                             [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; });
  };
  text =
      "{\"surfaces\": [{\"name\": \"é\", \"equation\": \"x² + y\\u00b2 − \\t@\", "
      "\"clip\": {\"sphere\": {\"radius\": 1}}}]}";
  e = errorOf(text);
  EXPECT_EQ(e.column(), characterColumn(text, text.find('@'))) << e.message();
  EXPECT_EQ(e.column(), 59);  // counted by hand
  EXPECT_NE(e.message().find("unexpected character '@'"), std::string::npos) << e.message();
  text =
      "{\"surfaces\": [{\"equation\": \"x² −\", \"clip\": {\"sphere\": {\"radius\": "
      "1}}}]}";
  e = errorOf(text);
  EXPECT_EQ(e.column(), characterColumn(text, text.find("\", \"clip"))) << e.message();
  EXPECT_NE(e.message().find("the equation ends after"), std::string::npos) << e.message();
  // An unknown name: where it is, and how a scene gives it a value.
  text =
      "{\"surfaces\": [{\"equation\": \"x^2 + y^2 - r^2\", \"clip\": {\"sphere\": {\"radius\": "
      "1}}}]}";
  e = errorOf(text);
  EXPECT_EQ(static_cast<size_t>(e.column()), text.find("r^2") + 1);
  EXPECT_NE(e.message().find("unknown name 'r' (give it a value in the surface's \"parameters\", "
                             "e.g. {\"r\": 1})"),
            std::string::npos)
      << e.message();
}

// Every position in an equation's message is the file's: an unclosed '(' is named by the
// prefix alone, and a second place is written as the file's line and column (the message
// said "'(' at column 7" after the prefix "t.json:2:36", the equation's column beside the
// file's).
TEST(SceneJson, EquationMessagesUseTheFilesColumns) {
  SceneError e = errorOf(
      "{\n  \"surfaces\": [{\"equation\": \"x^2 + (y^2 + z^2 - 1\", \"clip\": {\"sphere\": "
      "{\"radius\": 2}}}]\n}");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 36);
  EXPECT_EQ(e.message(), "unbalanced parenthesis: '(' is never closed");
  e = errorOf(
      "{\n  \"surfaces\": [{\"equation\": \"x^2 + (y^2 = 1)\", \"clip\": {\"sphere\": "
      "{\"radius\": 2}}}]\n}");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 41);
  EXPECT_EQ(e.message(), "expected ')' to close '(' at line 2, column 36 but found '='");
}

TEST(SceneJson, MissingFileNamesTheFile) {
  try {
    loadSceneFile("/nonexistent/scene.json");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json"), std::string::npos);
  }
}

TEST(SceneJson, ExampleScenesLoad) {
  std::filesystem::path dir = std::filesystem::path(ALGRAY_SOURCE_DIR) / "examples" / "scenes";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(loadSceneFile(entry.path()));
    ++count;
  }
  EXPECT_GE(count, 3);
}

// examples/scenes/gallery-grid.json (the README's picture of the gallery) holds every
// gallery surface once, in the order of algray::gallery(): a surface added to the gallery
// must be added to the picture too.
TEST(SceneJson, GalleryGridHoldsEveryGallerySurface) {
  const SceneDesc scene = loadSceneFile(std::filesystem::path(ALGRAY_SOURCE_DIR) / "examples" /
                                        "scenes" / "gallery-grid.json");
  const auto all = gallery();
  ASSERT_EQ(scene.surfaces.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::string& label = scene.surfaces[i].label;
    EXPECT_NE(label.find("gallery surface '" + std::string(all[i].name) + "'"), std::string::npos)
        << label;
  }
}

// Where `needle` starts in `text`, as the 1-based column of a one-line scene.
int columnOf(const std::string& text, const std::string& needle) {
  return static_cast<int>(text.find(needle)) + 1;
}

// Values Embree cannot trace (it aborted the process on an assertion) and directions
// that do not normalise: errors at the offending value.
TEST(SceneJson, OutOfRangeCameraAndLightValuesAreErrors) {
  const std::pair<std::string, std::string> cases[] = {
      {R"({"camera": {"position": [0, -1e19, 0]}})", "-1e19"},
      {R"({"camera": {"position": [0, -1e30, 0]}})", "-1e30"},
      {R"({"camera": {"look_at": [1e18, 0, 0]}})", "1e18"},
      {R"({"camera": {"aperture": 1e19}})", "1e19"},
      {R"({"camera": {"focus_distance": 1e19}})", "1e19"},
      {R"({"camera": {"type": "orthographic", "height": 1e19}})", "1e19"},
      {R"({"lights": [{"type": "point", "position": [0, 0, 1e20]}]})", "1e20"},
      {R"({"lights": [{"type": "directional", "direction": [0, 0, 0]}]})", "[0, 0, 0]"},
      {R"({"camera": {"up": [0, 0, 0]}})", "[0, 0, 0]"},
      // A quad light of no area emitted nothing, accepted without a word.
      {R"({"lights": [{"type": "quad", "corner": [0, 0, 2], "edge1": [1, 0, 0], "edge2": [-3, 0, 0], "radiance": 1}]})",
       "[-3, 0, 0]"},
  };
  for (const auto& [text, value] : cases) {
    SceneError e = errorOf(text);
    EXPECT_EQ(e.line(), 1) << text << ": " << e.what();
    EXPECT_EQ(e.column(), columnOf(text, value)) << text << ": " << e.what();
  }
  EXPECT_NE(errorOf(R"({"camera": {"position": [0, -1e19, 0]}})").message().find("1e17"),
            std::string::npos);
  // Tiny and huge directions are fine: normalised without underflow or overflow.
  SceneDesc d =
      loadSceneText(R"({"lights": [{"type": "directional", "direction": [1e-160, -1e-160, 1e-160]},
                                             {"type": "directional", "direction": [1e300, 0, 0]}]})",
                    "t.json", ".");
  ASSERT_EQ(d.directionalLights.size(), 2u);
  EXPECT_NEAR(d.directionalLights[0].direction.x, 1 / std::sqrt(3.0), 1e-15);
  EXPECT_EQ(d.directionalLights[1].direction, glm::dvec3(1, 0, 0));
  // Position and look_at 1e-200 apart: their difference normalises (was NaN, reported as
  // "up must not be parallel").
  EXPECT_NO_THROW(loadSceneText(
      R"({"camera": {"position": [0, -1e-200, 0], "look_at": [0, 0, 0]}})", "t.json", "."));
}

// A mesh beyond Embree's float range in scene space was dropped by Embree without a word
// (a floor of size 1e19 vanished from the image, exit code 0): an error at the mesh.
TEST(SceneJson, MeshesBeyondTheCoordinateRangeAreErrors) {
  const std::string cases[] = {
      R"({"meshes": [{"shape": "plane", "size": 1e19}]})",
      R"({"meshes": [{"shape": "box", "size": 1e300}]})",
      R"({"meshes": [{"shape": "plane", "transform": {"scale": 1e19}}]})",
      R"({"meshes": [{"shape": "icosphere", "transform": {"translate": [0, 0, 2e17]}}]})",
  };
  for (const std::string& text : cases) {
    SceneError e = errorOf(text);
    EXPECT_EQ(e.column(), columnOf(text, "{\"shape\"")) << text << ": " << e.what();
    EXPECT_NE(e.message().find("1e17"), std::string::npos) << text << ": " << e.what();
  }
  EXPECT_NO_THROW(
      loadSceneText(R"({"meshes": [{"shape": "plane", "size": 1e17}]})", "t.json", "."));
  // And below Embree's float triangle test (a plane of size 1e-20 covered no pixel, one of
  // 1e-19 the wrong ones, exit code 0); a flat mesh is fine, its extent is its largest side.
  for (const std::string& text :
       {std::string(R"({"meshes": [{"shape": "plane", "size": 1e-20}]})"),
        std::string(R"({"meshes": [{"shape": "box", "transform": {"scale": 1e-16}}]})")}) {
    SceneError e = errorOf(text);
    EXPECT_EQ(e.column(), columnOf(text, "{\"shape\"")) << text << ": " << e.what();
    EXPECT_NE(e.message().find("below 1e-15"), std::string::npos) << text << ": " << e.what();
  }
  EXPECT_NO_THROW(
      loadSceneText(R"({"meshes": [{"shape": "plane", "size": 1e-15}]})", "t.json", "."));
}

// nlohmann's number overflow ("number overflow parsing '1e400'") had no position.
TEST(SceneJson, NumberOverflowHasLineAndColumn) {
  SceneError e = errorOf("{\n  \"camera\": {\"fov\": 1e400}\n}");
  EXPECT_EQ(e.file(), "t.json");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 21);
  EXPECT_NE(e.message().find("1e400"), std::string::npos) << e.what();
  // The same digits inside a string do not mislead the search.
  SceneError f = errorOf("{\"description\": \"1e400\",\n \"camera\": {\"fov\": -1e400}}");
  EXPECT_EQ(f.line(), 2);
  EXPECT_EQ(f.column(), 20);
}

// Keys with '/', '~' or \u escapes: the loader's pointers and the scanner's agree.
TEST(SceneJson, KeysWithSlashTildeOrEscapesHaveLocations) {
  const std::string a = R"({"materials": {"a/b": {"type": "bogus"}}})";
  EXPECT_EQ(errorOf(a).column(), columnOf(a, "\"bogus\"")) << errorOf(a).what();
  const std::string b = R"({"materials": {"a~1\u0041\n\/": {"type": "bogus"}}})";
  EXPECT_EQ(errorOf(b).column(), columnOf(b, "\"bogus\"")) << errorOf(b).what();
  const std::string c =
      R"({"surfaces": [{"equation": "x^2 + y^2 + z^2 - r", "parameters": {"r/\u00e9": "one"}}]})";
  EXPECT_EQ(errorOf(c).column(), columnOf(c, "\"one\"")) << errorOf(c).what();
  const std::string d = R"({"camera": {"fo\u0076": 30, "bad~key": 1}})";
  EXPECT_EQ(errorOf(d).column(), columnOf(d, "1}")) << errorOf(d).what();
}

// Colours become float pixels: beyond 3.4e38 they were inf, with exit code 0.
TEST(SceneJson, ColoursBeyondFloatAreErrors) {
  const std::pair<std::string, std::string> cases[] = {
      {R"({"environment": {"color": 1e308}})", "1e308"},
      {R"({"background": [0, 1e39, 0]})", "1e39"},
      {R"({"lights": [{"type": "point", "position": [0, 0, 3], "intensity": 1e308}]})", "1e308"},
      {R"({"materials": {"m": {"type": "emissive", "emission": 1e308}}})", "1e308"},
      {R"({"lights": [{"type": "directional", "direction": [0, 0, 1], "irradiance": [1, 1, 1e300]}]})",
       "1e300"},
      {R"({"environment": {"color": -1}})", "-1"},
  };
  for (const auto& [text, value] : cases) {
    SceneError e = errorOf(text);
    EXPECT_EQ(e.line(), 1) << text << ": " << e.what();
    // A one-number colour points at the number, an array at its component or the array.
    EXPECT_GE(e.column(), columnOf(text, value) - (value == "1e39"    ? 4
                                                   : value == "1e300" ? 7
                                                                      : 0))
        << text;
    EXPECT_LE(e.column(), columnOf(text, value)) << text;
    EXPECT_NE(e.message().find("colour"), std::string::npos) << e.what();
  }
}

TEST(SceneJson, ClipWithBothSphereAndBoxIsAnError) {
  const std::string text =
      R"({"surfaces": [{"equation": "x", "clip": {"sphere": {"radius": 2}, "box": {"min": [0, 0, 0], "max": [1, 1, 1]}}}]})";
  SceneError e = errorOf(text);
  EXPECT_EQ(e.column(), columnOf(text, "{\"min\"")) << e.what();
  EXPECT_NE(e.message().find("exactly one of sphere, box"), std::string::npos) << e.what();
}

// Keys a kind of object does not read were ignored (session 12's sweep): refused at the key.
TEST(SceneJson, KeysThatDoNotApplyAreErrors) {
  const std::pair<std::string, std::string> cases[] = {
      {R"({"meshes": [{"obj": "m.obj", "size": 2}]})", "size"},
      {R"({"meshes": [{"shape": "box", "uv_scale": 2}]})", "uv_scale"},
      {R"({"meshes": [{"shape": "plane", "subdivisions": 2}]})", "subdivisions"},
      {R"({"materials": {"m": {"type": "diffuse", "roughness": 0.5}}})", "roughness"},
      {R"({"materials": {"m": {"type": "conductor", "ior": 1.5}}})", "ior"},
      {R"({"materials": {"m": {"type": "emissive", "emission": 1, "color": 1}}})", "color"},
      {R"({"materials": {"m": {"emission": 2}}})", "emission"},
      {R"({"camera": {"type": "orthographic", "fov": 30}})", "fov"},
      {R"({"camera": {"height": 3}})", "height"},
  };
  for (const auto& [text, key] : cases) {
    SceneError e = errorOf(text);
    EXPECT_EQ(e.column(), columnOf(text, "\"" + key + "\"") + static_cast<int>(key.size()) + 4)
        << text << ": " << e.what();
    EXPECT_NE(e.message().find("'" + key + "' does not apply to"), std::string::npos)
        << text << ": " << e.what();
  }
  // Where they apply they are read.
  EXPECT_NO_THROW(loadSceneText(
      R"({"meshes": [{"shape": "icosphere", "subdivisions": 2}], "camera": {"fov": 30}})", "t.json",
      "."));
}

// nlohmann stops at a NUL byte as at the end of the text, and rounds a literal below
// double's range to 0: both were accepted without a word.
TEST(SceneJson, NulBytesAndUnderflowingNumbersAreErrors) {
  const std::string nul = std::string("{\"camera\": {\"fov\": 30}}\n") + '\0' + "garbage {{{";
  SceneError e = errorOf(nul);
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 1);
  EXPECT_NE(e.message().find("NUL byte"), std::string::npos) << e.what();
  // The same escaped in a string: file names ended at it (a.obj\u0000junk loaded a.obj), and
  // so did names in messages (session 51's audit).
  const std::pair<std::string, std::string> escaped[] = {
      {R"({"meshes": [{"obj": "a.obj\u0000junk"}]})", "\"a.obj"},
      {R"({"surfaces": [{"gallery": "torus\u0000x"}]})", "\"torus"}};
  for (const auto& [text, value] : escaped) {
    SceneError g = errorOf(text);
    EXPECT_EQ(g.column(), columnOf(text, value)) << g.what();
    EXPECT_NE(g.message().find("NUL character"), std::string::npos) << g.what();
  }
  const std::string under =
      R"({"surfaces": [{"equation": "x^2+y^2+z^2-a", "parameters": {"a": 1e-400}, "clip": {"sphere": {"radius": 2}}}]})";
  SceneError f = errorOf(under);
  EXPECT_EQ(f.column(), columnOf(under, "1e-400")) << f.what();
  EXPECT_NE(f.message().find("'1e-400' underflows to 0"), std::string::npos) << f.what();
  // An exact zero and a subnormal are values.
  EXPECT_NO_THROW(loadSceneText(
      R"({"camera": {"aperture": 0.0e5}, "environment": {"color": 1e-310}})", "t.json", "."));
}

// OBJ lines tinyobjloader read as 0 or as another vertex, with exit code 0: refused with
// the OBJ's line number, under the scene's position of "obj".
TEST(SceneJson, MalformedObjNumbersAreErrors) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::pair<std::string, std::string> cases[] = {
      {tri + "v inf 1 0\nf 1 2 3\n", "4: 'inf'"},
      {tri + "v abc 1 0\nf 1 2 3\n", "4: 'abc'"},
      {"v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n", "3: 'v' with 2 numbers"},
      {tri + "vn 0 0 nan\nf 1 2 3\n", "4: 'nan'"},
      {tri + "v 1e39 0 0\nf 1 2 3\n", "4: '1e39'"},
      {tri + "v 0x1p3 0 0\nf 1 2 3\n", "4: '0x1p3'"},  // strtod's hex: tinyobjloader read 0
      {tri + "vt 0.5 .\nf 1 2 3\n", "4: '.'"},
      {tri + "f 1/2/ 2 3\n", "4: bad face index '1/2/'"},
      {tri + "f 1 2 99999999999999999999\n", "4: bad face index"},
      {tri + "f 1 2 3x\n", "4: bad face index"},
      {tri + "f 1/1/1/1 2 3\n", "4: bad face index"},
      {tri + "f 1 2\n", "4: a face needs at least 3"},
  };
  for (const auto& [obj, expected] : cases) {
    const std::filesystem::path file = dir / "algray_bad_numbers.obj";
    std::ofstream(file) << obj;
    const std::string text = R"({"meshes": [{"obj": ")" + file.string() + R"("}]})";
    SceneError e = errorOf(text);
    EXPECT_EQ(e.column(), columnOf(text, "\"/")) << obj << ": " << e.what();
    EXPECT_NE(e.message().find("algray_bad_numbers.obj:" + expected), std::string::npos)
        << obj << ": " << e.what();
    std::filesystem::remove(file);
  }
  // The forms OBJ allows load: w, vertex colours, uv and normal indices, negative indices.
  const std::filesystem::path file = dir / "algray_good_numbers.obj";
  std::ofstream(file) << "v 0 0 0 1\nv 1E+0 0 0 0.5 0.5 0.5 # red\nv 0 +1. -.0e-3\r\nvt 0.5\nvn 0 "
                         "0 1\n\tf 1/1/1 2//1 -1/1\n";
  EXPECT_NO_THROW(
      loadSceneText(R"({"meshes": [{"obj": ")" + file.string() + R"("}]})", "t.json", "."));
  std::filesystem::remove(file);
}

// An image with inf, NaN or negative values made the whole render black (an environment)
// or negative, with exit code 0.
TEST(SceneJson, ImagesWithNonFiniteOrNegativeValuesAreErrors) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "algray_bad_texels.exr";
  for (const float bad : {INFINITY, NAN, -0.5f}) {
    std::vector<float> pixels(2 * 2 * 3, 0.5f);
    pixels[3 * 3 + 1] = bad;  // texel (1, 1), green
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    ASSERT_TRUE(out->close());
    for (const std::string& text :
         {R"({"environment": {"image": ")" + file.string() + R"("}})",
          R"({"materials": {"m": {"texture": ")" + file.string() + R"("}}})"}) {
      SceneError e = errorOf(text);
      EXPECT_EQ(e.column(), columnOf(text, "\"/")) << bad << ": " << e.what();
      EXPECT_NE(e.message().find("texel (1, 1) is not a finite non-negative colour"),
                std::string::npos)
          << bad << ": " << e.what();
    }
  }
  std::filesystem::remove(file);
}

// A colour and an image each within float's range whose product is not rendered inf
// pixels with exit code 0; the product is refused at the image, below it accepted.
TEST(SceneJson, ColourTimesImageBeyondFloatIsAnError) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "algray_bright_texels.exr";
  std::vector<float> pixels(2 * 2 * 3, 1.0f);
  pixels[3 * 2] = 1e38f;  // texel (0, 1), red
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::FLOAT)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  ASSERT_TRUE(out->close());
  for (const double colour : {3.0, 4.0}) {  // 3e38 fits a float (3.4e38), 4e38 does not
    const std::string c = std::to_string(colour);
    for (const std::string& text :
         {R"({"environment": {"color": )" + c + R"(, "image": ")" + file.string() + R"("}})",
          R"({"materials": {"m": {"color": )" + c + R"(, "texture": ")" + file.string() +
              R"("}}})"}) {
      SceneError e = errorOf(text);
      if (colour == 3.0) {
        EXPECT_NE(e.message().find("no error"), std::string::npos) << e.what();
      } else {
        EXPECT_EQ(e.column(), columnOf(text, "\"/")) << e.what();
        EXPECT_NE(e.message().find("beyond 3.4e38"), std::string::npos) << e.what();
      }
    }
  }
  std::filesystem::remove(file);
}

// nlohmann keeps the last of repeated keys; the loader refuses them.
TEST(SceneJson, DuplicateKeysAreErrors) {
  SceneError e = errorOf("{\"camera\": {\"fov\": 30,\n  \"fov\": 40}}");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 3);
  EXPECT_NE(e.message().find("duplicate key 'fov'"), std::string::npos) << e.what();
  // The same key in different objects, and escapes spelling the same key.
  EXPECT_NO_THROW(loadSceneText(
      R"({"render": {"width": 8}, "camera": {"fov": 30}, "description": "width"})", "t.json", "."));
  EXPECT_EQ(errorOf(R"({"render": {"width": 8, "w\u0069dth": 9}})").column(), 25);
}

// A UTF-8 byte-order mark before the text: nlohmann skips it, and so must the position
// scanner, or the checks that need positions (duplicate keys, literals that underflow,
// every error's line and column) saw an empty table and let the file through.
TEST(SceneJson, ByteOrderMarkKeepsEveryCheck) {
  const std::string bom = "\xEF\xBB\xBF";
  const std::string dup = "{\"camera\": {\"fov\": 30,\n  \"fov\": 40}}";
  const std::string under =
      "{\"surfaces\": [{\"equation\": \"x^2+y^2+z^2-a\",\n"
      "  \"parameters\": {\"a\": 1e-400}, \"clip\": {\"sphere\": {\"radius\": 2}}}]}";
  const std::string fov = "{\"camera\":\n {\"fov\": 200}}";
  for (const std::string& text : {dup, under, fov}) {
    const SceneError plain = errorOf(text), marked = errorOf(bom + text);
    EXPECT_EQ(plain.message().find("no error"), std::string::npos);
    EXPECT_GT(plain.line(), 0) << plain.what();
    EXPECT_EQ(marked.line(), plain.line()) << marked.what();
    EXPECT_EQ(marked.column(), plain.column()) << marked.what();
    EXPECT_EQ(marked.message(), plain.message());
  }
  EXPECT_NE(errorOf(bom + under).message().find("underflows to 0"), std::string::npos);
  EXPECT_NE(errorOf(bom + dup).message().find("duplicate key 'fov'"), std::string::npos);
  const SceneDesc a = loadSceneText("{\"render\": {\"spp\": 3}}", "t.json", ".");
  const SceneDesc b = loadSceneText(bom + "{\"render\": {\"spp\": 3}}", "t.json", ".");
  EXPECT_EQ(a.settings.spp, 3);
  EXPECT_EQ(b.settings.spp, 3);
}

// 100000 nested '[' (or objects) overflowed the stack in nlohmann's parser and value
// destructor and in the position scanner (SIGSEGV); now an error at the bracket that
// goes one level too deep. Brackets inside strings do not count.
TEST(SceneJson, DeepNestingIsAnErrorNotACrash) {
  for (const std::string& open : {std::string("["), std::string("{\"a\":")}) {
    std::string text = "\n";
    for (int i = 0; i < 100000; ++i) text += open;
    text += "1" + std::string(100000, open == "[" ? ']' : '}');
    SceneError e = errorOf(text);
    EXPECT_EQ(e.line(), 2) << open;
    EXPECT_EQ(e.column(), 1 + 64 * static_cast<int>(open.size())) << open;
    EXPECT_NE(e.message().find("nesting deeper than 64"), std::string::npos) << e.what();
  }
  const std::string brackets(1000, '[');
  EXPECT_NO_THROW(loadSceneText(
      "{\"description\": \"" + brackets + "\", \"surfaces\": [{\"gallery\": \"torus\"}]}", "t.json",
      "."));
}

TEST(SceneJson, DirectoryIsNotASceneFile) {
  try {
    loadSceneFile(std::filesystem::temp_directory_path());
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

// Runs algray-render with `args`; returns the exit code (-1: killed by a signal) and the
// output (stdout and stderr).
std::pair<int, std::string> runRender(const std::string& args) {
  const std::string cmd = std::string(ALGRAY_RENDER_EXE) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-2, "popen failed"};
  std::string out;
  char buf[512];
  while (fgets(buf, sizeof buf, pipe)) out += buf;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// --list-gallery shows each surface's equation as algray reads it (the heart's was
// "9/4y^2", which --surface refused as "malformed number '4y'").
TEST(RenderProgram, ListedGalleryEquationsRenderAsTheSurface) {
  auto [code, out] = runRender("--list-gallery");
  ASSERT_EQ(code, 0) << out;
  int checked = 0;
  for (const GallerySurface& g : gallery()) {
    if (g.equation.empty()) continue;
    const size_t line = out.find(std::string(g.name) + " ");
    ASSERT_NE(line, std::string::npos) << g.name << ": " << out;
    const std::string text = out.substr(line, out.find('\n', line) - line);
    const size_t colon = text.rfind(": ");
    ASSERT_NE(colon, std::string::npos) << text;
    EXPECT_EQ(text.substr(colon + 2), g.equation);
    EXPECT_NO_THROW(parsePolynomial(text.substr(colon + 2))) << text;
    ++checked;
  }
  EXPECT_GE(checked, 5);
  EXPECT_EQ(out.find("9/4y"), std::string::npos) << out;
}

// A scene file of one sphere plus `extra` members, written to a temporary file.
std::filesystem::path sphereScene(const std::string& name, const std::string& extra) {
  std::filesystem::path file = std::filesystem::temp_directory_path() / name;
  std::ofstream(file) << "{\"surfaces\": [{\"equation\": \"x^2+y^2+z^2-1\", \"clip\": {\"sphere\": "
                         "{\"radius\": 2}}}]"
                      << (extra.empty() ? "" : ",\n") << extra << "}\n";
  return file;
}

// The adversarial sweep's reproducers: each aborted (exit 134), printed no position, or
// rendered inf pixels with exit code 0. Now: exit code 2 and file:line:column.
TEST(RenderProgram, OutOfRangeSceneValuesExitWithCode2AndLocation) {
  const std::pair<const char*, const char*> cases[] = {
      {R"("camera": {"position": [0, -1e19, 0]})", ":2:28:"},
      {R"("camera": {"aperture": 1e19})", ":2:24:"},
      {R"("camera": {"type": "orthographic", "height": 1e19})", ":2:46:"},
      {R"("camera": {"fov": 1e400})", ":2:19:"},
      {R"("environment": {"color": 1e308})", ":2:26:"},
      {R"("lights": [{"type": "directional", "direction": [0, 0, 0]}])", ":2:49:"},
  };
  for (const auto& [extra, where] : cases) {
    const std::filesystem::path file = sphereScene("algray_range_scene.json", extra);
    auto [code, out] = runRender(file.string() + " --width 8 --height 8 --spp 1 -q -o /dev/null");
    EXPECT_EQ(code, 2) << extra << ": " << out;
    EXPECT_NE(out.find(file.string() + where), std::string::npos) << extra << ": " << out;
    std::filesystem::remove(file);
  }
  // A tiny directional light direction renders (was an Embree abort from a NaN ray).
  const std::filesystem::path file =
      sphereScene("algray_range_scene.json",
                  R"("lights": [{"type": "directional", "direction": [1e-160, -1e-160, 1e-160]}])");
  const std::filesystem::path image =
      std::filesystem::temp_directory_path() / "algray_range_scene.png";
  auto [code, out] =
      runRender(file.string() + " --width 8 --height 8 --spp 1 -q -o " + image.string());
  EXPECT_EQ(code, 0) << out;
  std::filesystem::remove(file);
  std::filesystem::remove(image);
}

// A pixel whose radiance lies beyond float's range, from values each within it, is refused
// (exit 2, the pixel and its value) instead of written as inf with exit 0: a point light of
// intensity 1 at 1e-20 above a plane (2.5e39 below it, (0.8 / pi) / 1e-40), and two lights
// of irradiance 3e38 beside an environment of 3e38 (0.8 (6e38 / pi + 3e38) = 3.9e38). A light just within range renders.
TEST(RenderProgram, PixelsBeyondFloatAreRefused) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "algray_overflow_scene.json";
  const std::filesystem::path image =
      std::filesystem::temp_directory_path() / "algray_overflow_scene.exr";
  const auto scene = [&](const std::string& lights) {
    std::ofstream(file)
        << R"({"render": {"width": 15, "height": 15, "spp": 1, "integrator": "direct"},
 "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "up": [0, 1, 0]},
 "meshes": [{"shape": "plane", "size": 2}], )"
        << lights << "}";
  };
  for (const char* lights :
       {R"("lights": [{"type": "point", "position": [0, 0, 1e-20]}])",
        R"("lights": [{"type": "directional", "direction": [0, 0, 1], "irradiance": 3e38},
                      {"type": "directional", "direction": [0, 0, 1], "irradiance": 3e38}],
           "environment": {"color": 3e38})"}) {
    scene(lights);
    auto [code, out] = runRender(file.string() + " -q -o " + image.string());
    EXPECT_EQ(code, 2) << lights << ": " << out;
    EXPECT_NE(out.find("beyond the image's float range"), std::string::npos) << out;
  }
  scene(R"("lights": [{"type": "point", "position": [0, 0, 1e-3]}])");
  auto [code, out] = runRender(file.string() + " -q -o " + image.string());
  EXPECT_EQ(code, 0) << out;
  std::filesystem::remove(file);
  std::filesystem::remove(image);
}

// An output name near NAME_MAX (255 bytes) is written: the writability probe and the
// temporary file were OUT plus a suffix, past the limit ("File name too long").
TEST(RenderProgram, LongOutputNamesAreWritten) {
  const std::filesystem::path image =
      std::filesystem::temp_directory_path() / (std::string(240, 'a') + ".png");
  auto [code, out] =
      runRender("--surface torus --width 8 --height 8 --spp 1 -q -o " + image.string());
  EXPECT_EQ(code, 0) << out;
  EXPECT_TRUE(std::filesystem::exists(image));
  std::filesystem::remove(image);
}

// Integer options are decimal: CLI11 converted them with strtoll's base 0, so --width 010
// rendered 8 pixels wide, --height 0x10 16, and --width 08 was "not in range".
TEST(RenderProgram, IntegerOptionsAreDecimal) {
  const std::filesystem::path image =
      std::filesystem::temp_directory_path() / "algray_decimal_options.png";
  const auto [code, out] =
      runRender("--surface torus --width 010 --height ' 0008 ' --spp 01 -q -o " + image.string());
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find(", 10x8, 1 spp,"), std::string::npos) << out;
  for (const char* bad : {"--width 0x10", "--height 1e1", "--seed 0x2A", "--spp 1.0"}) {
    const auto [badCode, badOut] =
        runRender(std::string("--surface torus ") + bad + " -q -o " + image.string());
    EXPECT_EQ(badCode, 2) << bad << ": " << badOut;
    EXPECT_NE(badOut.find("is not a decimal integer"), std::string::npos) << bad << ": " << badOut;
  }
  std::filesystem::remove(image);
}

// Area lights smaller than 2^-44 of their coordinates are refused: a sphere light of radius
// 1e-12 at z = 1e5 (or 1e-16 at z = 1) had its vertices rounded onto a disc covered twice
// and shone 1.4-1.8 times as bright as the point light it stands for; a quad light 1e-15
// wide at y = 3, 11 % too dim. One of radius 1e-9 renders.
TEST(RenderProgram, UnresolvableAreaLightsAreRefused) {
  const std::filesystem::path image =
      std::filesystem::temp_directory_path() / "algray_small_light.png";
  for (const char* light :
       {R"("lights": [{"type": "sphere", "center": [0, 0, 1e5], "radius": 1e-12, "radiance": 1}])",
        R"("lights": [{"type": "sphere", "center": [0, 0, 1], "radius": 1e-16, "radiance": 1}])",
        R"("lights": [{"type": "quad", "corner": [0, 0, 1e5], "edge1": [1e-12, 0, 0],
                       "edge2": [0, 1e-12, 0], "radiance": 1}])",
        R"("lights": [{"type": "quad", "corner": [-0.5, 3, 3], "edge1": [1, 0, 0],
                       "edge2": [0, 1e-15, 0], "radiance": 1e15}])"}) {
    const std::filesystem::path file = sphereScene("algray_small_light.json", light);
    auto [code, out] =
        runRender(file.string() + " --width 8 --height 8 --spp 1 -q -o " + image.string());
    EXPECT_EQ(code, 2) << light << ": " << out;
    EXPECT_NE(out.find(file.string() + ":2:"), std::string::npos) << light << ": " << out;
    EXPECT_NE(out.find("below 2^-44 of them"), std::string::npos) << light << ": " << out;
    std::filesystem::remove(file);
  }
  const std::filesystem::path file = sphereScene(
      "algray_small_light.json",
      R"("lights": [{"type": "sphere", "center": [0, 0, 3], "radius": 1e-9, "radiance": 1e18}])");
  auto [code, out] =
      runRender(file.string() + " --width 8 --height 8 --spp 1 -q -o " + image.string());
  EXPECT_EQ(code, 0) << out;
  std::filesystem::remove(file);
  std::filesystem::remove(image);
}

// Errors the plugin raises while Scene builds a surface name the surface's position.
TEST(RenderProgram, SurfaceBuildErrorsHaveTheSurfacesLocation) {
  const char* surfaces[] = {
      R"({"equation": "1", "clip": {"sphere": {"radius": 2}}})",
      R"({"equation": "x^2+y^2+z^2-1", "clip": {"sphere": {"radius": 1e300}}})",
      R"({"equation": "x^2+y^2+z^2-1", "clip": {"sphere": {"radius": 2}}, "transform": {"scale": 1e200}})",
  };
  for (const char* surface : surfaces) {
    std::filesystem::path file =
        std::filesystem::temp_directory_path() / "algray_surface_error.json";
    std::ofstream(file) << "{\n  \"surfaces\": [\n    " << surface << "]}\n";
    auto [code, out] = runRender(file.string() + " --width 8 --height 8 --spp 1 -q -o /dev/null");
    EXPECT_EQ(code, 2) << surface << ": " << out;
    EXPECT_NE(out.find(file.string() + ":3:5: surface"), std::string::npos)
        << surface << ": " << out;
    std::filesystem::remove(file);
  }
}

// A surface with no point in its clip region renders (exit code 0) with a warning naming it:
// quick mode's default clip sphere (radius 2) misses a sphere of radius 10, a larger one
// holds it; a scene file's surface is named by its position.
TEST(RenderProgram, SurfacesOutsideTheirClipRegionAreNamed) {
  const std::string warning = "no point of the surface lies in its clip region";
  const std::string image = (std::filesystem::temp_directory_path() / "algray_empty.png").string();
  const std::string small = " --width 8 --height 8 --spp 1 -q -o " + image;
  auto [code, out] = runRender("--surface \"x^2+y^2+z^2-100\"" + small);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("warning: --surface: " + warning), std::string::npos) << out;
  EXPECT_NE(out.find("a larger --clip-sphere may reach it, if it has real points farther out"),
            std::string::npos)
      << out;
  std::tie(code, out) = runRender("--surface \"x^2+y^2+z^2-100\" --clip-sphere 20" + small);
  EXPECT_EQ(code, 0) << out;
  EXPECT_EQ(out.find(warning), std::string::npos) << out;
  // No real point at all, which the terms show: no larger sphere is suggested (it was, for
  // x^2+y^2+z^2+1).
  for (const char* none : {"(x^2+y^2+z^2)^2+1", "x^2+y^2+z^2+1"}) {
    std::tie(code, out) = runRender("--surface \"" + std::string(none) + "\"" + small);
    EXPECT_NE(out.find(warning + ", so none of it is drawn (nor anywhere: every term is an even "
                                 "power of x, y, z with the constant's sign)"),
              std::string::npos)
        << out;
    EXPECT_EQ(out.find("larger"), std::string::npos) << out;
  }
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "algray_empty_surface.json";
  std::ofstream(file)
      << "{\"surfaces\": [\n  {\"equation\": \"x^2+y^2+z^2-1\", \"clip\": {\"sphere\": "
         "{\"radius\": 2}}},\n  {\"equation\": \"x^2+y^2+z^2-100\", \"clip\": "
         "{\"sphere\": {\"radius\": 2}}}]}\n";
  std::tie(code, out) = runRender(file.string() + small);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find(file.string() + ":3:3: surface x^2+y^2+z^2-100: " + warning),
            std::string::npos)
      << out;
  EXPECT_EQ(out.find(":2:3:"), std::string::npos) << out;  // the first surface is drawn
  std::filesystem::remove(file);
  std::filesystem::remove(image);
}

// A surface in the picture that no camera ray hits (a tenth of a pixel across: the floor
// alone, without a word until session 53) gets a warning, and a smaller clip sphere, which
// frames it, none. A ball seen only through a glass shell is seen (the first version, which
// read the first hits alone, warned about it); inside an opaque shell it is hidden.
TEST(RenderProgram, SurfacesNoCameraRayHitsAreNamed) {
  const std::string warning = "no camera ray hit the surface";
  const std::string image = (std::filesystem::temp_directory_path() / "algray_tiny.png").string();
  const std::string small = " --width 40 --height 30 --spp 1 -q -o " + image;
  auto [code, out] = runRender("--surface \"x^2+y^2+z^2-1e-6\"" + small);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("warning: --surface: " + warning), std::string::npos) << out;
  EXPECT_NE(out.find("a smaller --clip-sphere frames a small surface closer"), std::string::npos)
      << out;
  std::tie(code, out) = runRender("--surface \"x^2+y^2+z^2-1e-6\" --clip-sphere 2e-3" + small);
  EXPECT_EQ(code, 0) << out;
  EXPECT_EQ(out.find(warning), std::string::npos) << out;
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "algray_glass_shell.json";
  for (const std::string shell : {"glass", "red"}) {
    for (const char* integrator : {"path", "direct"}) {
      std::ofstream(file)
          << "{\"camera\": {\"position\": [0, -6, 0], \"look_at\": [0, 0, 0], \"fov\": 30},\n"
             "\"materials\": {\"glass\": {\"type\": \"dielectric\", \"ior\": 1.5},\n"
             "  \"red\": {\"type\": \"diffuse\", \"color\": [0.8, 0.1, 0.1]}},\n"
             "\"surfaces\": [{\"equation\": \"x^2+y^2+z^2-1\", \"clip\": {\"sphere\": "
             "{\"radius\": 1.2}}, \"material\": \""
          << shell
          << "\"},\n"
             "  {\"equation\": \"x^2+y^2+z^2-0.25\", \"clip\": {\"sphere\": {\"radius\": "
             "0.6}}, \"material\": \"red\"}],\n"
             "\"lights\": [{\"type\": \"point\", \"position\": [2, -3, 5], \"intensity\": 40}]}\n";
      std::tie(code, out) = runRender(file.string() + " --integrator " + integrator + small);
      EXPECT_EQ(code, 0) << out;
      EXPECT_EQ(out.find(":5:3: surface x^2+y^2+z^2-0.25: " + warning) != std::string::npos,
                shell == "red")
          << shell << " " << integrator << ": " << out;
      EXPECT_EQ(out.find(":4:"), std::string::npos) << out;  // the shell is seen
    }
  }
  std::filesystem::remove(file);
  std::filesystem::remove(image);
}

// A surface that rounding noise fills through much of its clip region is named (session
// 54): the 20-fold sphere, whose noise band is 0.16 thick, and not the sphere itself.
TEST(RenderProgram, SurfacesLostInRoundingAreNamed) {
  const std::string warning = "f is within its own rounding error at";
  const std::string image = (std::filesystem::temp_directory_path() / "algray_noisy.png").string();
  const std::string small = " --clip-sphere 1.5 --width 16 --spp 1 -q -o " + image;
  auto [code, out] = runRender("--surface \"(x^2+y^2+z^2-1)^20\"" + small);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("warning: --surface in --clip-sphere: " + warning), std::string::npos) << out;
  std::tie(code, out) = runRender("--surface \"x^2+y^2+z^2-1\"" + small);
  EXPECT_EQ(code, 0) << out;
  EXPECT_EQ(out.find(warning), std::string::npos) << out;
  std::filesystem::remove(image);
}

// A --param value may be a constant as equations write it (session 53): the exported scene
// holds the surface with the constant's double, (1 + sqrt(5)) / 2 computed here.
TEST(RenderProgram, ParameterValuesMayBeConstants) {
  const std::filesystem::path pov = std::filesystem::temp_directory_path() / "algray_param.pov";
  const auto [code, out] = runRender("--surface \"x^2+y^2+z^2-a\" --param \"a=(1+sqrt(5))/2\" " +
                                     std::string("--export-pov ") + pov.string());
  ASSERT_EQ(code, 0) << out;
  std::ifstream in(pov);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(pov);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex(R"(xyz\(0, 0, 0\): ([-+0-9.eE]+))"))) << text;
  EXPECT_EQ(std::stod(m[1]), -(1 + std::sqrt(5.0)) / 2);
}

// An equation or a gallery name given where the scene file goes gets the command that
// renders it; a missing file that looks like neither is just missing.
TEST(RenderProgram, EquationsAndGalleryNamesInPlaceOfASceneFileGetTheCommand) {
  auto [code, out] = runRender("\"x^2+y^2+z^2-1\" -q -o /dev/null");
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("x^2+y^2+z^2-1: no such scene file (an equation is rendered with --surface: "
                     "algray-render --surface \"x^2+y^2+z^2-1\")"),
            std::string::npos)
      << out;
  std::tie(code, out) = runRender("Barth_Sextic -q -o /dev/null");
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("algray-render --surface Barth_Sextic"), std::string::npos) << out;
  std::tie(code, out) = runRender("no_such_scene.json -q -o /dev/null");
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("no_such_scene.json: cannot open the scene file"), std::string::npos) << out;
  EXPECT_EQ(out.find("--surface"), std::string::npos) << out;
}

TEST(RenderProgram, DirectoryAsSceneFileIsAnError) {
  const std::string dir = std::filesystem::temp_directory_path().string();
  auto [code, out] = runRender(dir + " -q -o /dev/null");
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("is a directory"), std::string::npos) << out;
}

// The program: a broken scene gives exit code 2 and "file:line:column: message".
TEST(RenderProgram, BadSceneExitsWithCode2AndLocation) {
  std::filesystem::path file = std::filesystem::temp_directory_path() / "algray_bad_scene.json";
  std::ofstream(file) << "{\n  \"camera\": {\"fov\": \"wide\"}\n}\n";
  const auto [code, out] = runRender(file.string() + " -o /dev/null");
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find(file.string() + ":2:21:"), std::string::npos) << out;
  std::filesystem::remove(file);
}

// Bad command-line input: exit code 2 and a message naming the option (never a render
// with a silently replaced value, never exit code 1 as for an internal failure).
TEST(RenderProgram, BadOptionsExitWithCode2) {
  const std::pair<const char*, const char*> cases[] = {
      {"--surface x^2+y^2+z^2-1 --clip-sphere 0", "--clip-sphere"},
      {"--surface x^2+y^2+z^2-1 --clip-sphere -1", "--clip-sphere"},
      {"--surface sphere --clip-sphere nan", "--clip-sphere"},
      {"--surface x^2+y^2+z^2-1 --clip-sphere 1e30", "scale the scene down"},
      {"--surface 0", "zero"},
      {"--surface x --exposure nan", "--exposure"},
      {"--surface x^41", "degree 41"},
      {"--surface sphere -o /nonexistent/dir/a.png", "cannot write there"},
      {"--surface sphere -o algray_test_image.xyz", "unsupported image format"},
      // A parameter named after a variable, or given twice: the option, not the equation.
      {"--surface x^2+y^2+z^2-1 --param x=1", "--param: x: "},
      {"--surface x^2+y^2+z^2-a --param a=1 --param a=2", "--param: a: given more than once"},
      // Out of double's range: named as such (std::stod called both "not a number").
      {"--surface x^2+y^2+z^2-a --param a=1e400", "'a=1e400' overflows double"},
      {"--surface x^2+y^2+z^2-a --param a=1e-400", "'a=1e-400' underflows to 0 in double"},
      // Quick-mode options without --surface, --sturm without --export-pov: refused, not
      // ignored (the default scene rendered with exit 0, whatever their values).
      {"--clip-sphere -5", "--clip-sphere requires --surface"},
      {"--param a=nan", "--param requires --surface"},
      {"--sturm", "--sturm requires --export-pov"},
      // A clip sphere too large for the scene names the option that set it (the library's
      // refusal did; since session 12 the quick scene's own range check comes first).
      {"--surface x^2+y^2+z^2-1 --clip-sphere 1e300", "--clip-sphere: beyond a radius"},
      {"--surface barth-sextic --clip-sphere 1e300", "--clip-sphere: beyond a radius"},
      // Session 12's sweep: an empty --surface or --export-pov was taken for none given (the
      // default scene rendered, its options ignored), an unwritable --export-pov and a
      // negative --seed (wrapped to 2^64 - 1) were accepted with exit code 0.
      {"--surface '' --param a=1", "--surface:1:1: empty equation"},
      // jsurf's shading needs a .jsurf file's materials and lights.
      {"--surface sphere --integrator surfer", "--integrator surfer: shades .jsurf files only"},
      // A --param value that is neither a number nor a constant the parser reads (a constant
      // such as pi/4 is taken since session 53).
      {"--surface x^2+y^2+z^2-a --param a=x",
       "--param: 'a=x': neither a number nor a constant (a parameter's value may not use x, y "
       "or z)"},
      {"--surface x^2+y^2+z^2-a --param a=zz", "neither a number nor a constant (column 1: "},
      // An equation with line breaks: the place in its own lines (it was "--surface:1:16:",
      // the code point counted through the line break; session 53).
      {"--surface \"x^2+y^2\n+z^2-1 q\"", "--surface:2:8: missing operator before 'q'"},
      {"--surface \"x^2+y^2+\n\"", "--surface:1:9: the equation ends after '+'"},
      {"--surface \"(x^2+y^2\r\n+z^2-1 = 3\"",
       "--surface:2:8: expected ')' to close '(' at line 1, column 1 but found '='"},
      {"--surface sphere --export-pov ''", "--export-pov: the file name is empty"},
      {"--surface sphere --export-pov /nonexistent/dir/a.pov", "cannot write there"},
      // Surfaces the plugin refuses were exported (exit code 0) as files POV-Ray cannot
      // parse: the export builds the scene first. And an -o that is a directory is named
      // before the render (it was "cannot rename the temporary file: Success" after it).
      {"--surface 0 --export-pov algray_test_zero.pov", "the polynomial is zero"},
      {"--surface 2 --export-pov algray_test_const.pov", "is a non-zero constant"},
      {"--surface sphere -o .", "-o .: is a directory"},
      {"--surface sphere --seed -1", "--seed"},
      {"--surface sphere --seed 1073741825", "--seed"},
      {"--surface sphere --aov depth -o algray_aov.png",
       "--aov: -o algray_aov.png cannot hold extra channels"},
      // The quick scene's floor beyond Embree's range (lost) or below its float triangles'
      // (the floor covered the surface), with exit code 0.
      {"--surface sphere --clip-sphere 1e-20", "--clip-sphere: below a radius of 2.5e-17"},
      {"--surface x^2+y^2+z^2-1 --clip-sphere 1e16", "--clip-sphere: beyond a radius of 5e15"},
  };
  for (const auto& [args, expected] : cases) {
    const std::string output =
        std::string(args).find(" -o ") == std::string::npos ? " -o /dev/null" : "";
    const auto [code, out] = runRender(std::string(args) + " --width 8 --height 8 -q" + output);
    EXPECT_EQ(code, 2) << args << ": " << out;
    EXPECT_NE(out.find(expected), std::string::npos) << args << ": " << out;
  }
}

// An -o format OpenImageIO cannot write stops the render once the image library has
// loaded (it was reported after the whole render); Ctrl-C stops within a tile (it waited
// for the tile, minutes at a high spp) and writes the partial image. Both renders below
// take minutes if not stopped; `timeout` turns that into a failure.
TEST(RenderProgram, BadFormatAndCtrlCStopTheRender) {
  const std::string slow =
      "--surface sarti-dodecic --width 16 --height 16 --spp 1048576 --threads 1 -q";
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  {
    const auto [code, out] =
        runRender(slow + " -o " + (dir / "algray_format.pgn").string() + " --seed 1");
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find("unsupported image format"), std::string::npos) << out;
  }
  const std::filesystem::path image = dir / "algray_interrupted.png";
  const std::string cmd = "timeout -s KILL 60 timeout --foreground --preserve-status -s INT 3 " +
                          std::string(ALGRAY_RENDER_EXE) + " " + slow + " -o " + image.string() +
                          " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_TRUE(pipe);
  std::string out;
  char buf[512];
  while (fgets(buf, sizeof buf, pipe)) out += buf;
  const int status = pclose(pipe);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << status << ": " << out;
  EXPECT_NE(out.find("interrupted: partial image"), std::string::npos) << out;
  EXPECT_TRUE(std::filesystem::exists(image));
  std::filesystem::remove(image);
}

// An image larger than the machine's memory is refused by name before any allocation
// (32768 x 32768 ended in std::bad_alloc or the OOM killer).
TEST(RenderProgram, ImageBeyondMemoryIsAnError) {
  const double memory =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  if (memory > 80.0 * (1 << 30)) GTEST_SKIP() << "this machine could hold the image";
  const auto [code, out] =
      runRender("--surface sphere --width 32768 --height 32768 -q -o /dev/null");
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("lower --width/--height"), std::string::npos) << out;
}

// A subnormal --param is its own value, as in algray-query (std::stod refused it as "not a
// number": it throws out_of_range for every ERANGE).
TEST(RenderProgram, SubnormalParameterIsAValue) {
  const std::filesystem::path image =
      std::filesystem::temp_directory_path() / "algray_subnormal_param.png";
  const auto [code, out] =
      runRender("--surface x^2+y^2+z^2-1+a --param a=1e-320 --width 8 --height 8 --spp 1 -q -o " +
                image.string());
  EXPECT_EQ(code, 0) << out;
  std::filesystem::remove(image);
}

// Spaces around a --param's name and value are quoting: "a= 1" was taken (strtod skips
// leading spaces), "a=1 " and " a=1" refused.
TEST(RenderProgram, SpacesAroundAParameterAreQuoting) {
  const std::filesystem::path image =
      std::filesystem::temp_directory_path() / "algray_spaced_param.png";
  for (const char* param : {"'a= 1'", "'a=1 '", "' a =1'"}) {
    const auto [code, out] = runRender("--surface x^2+y^2+z^2-a --param " + std::string(param) +
                                       " --width 8 --height 8 --spp 1 -q -o " + image.string());
    EXPECT_EQ(code, 0) << param << "\n" << out;
  }
  std::filesystem::remove(image);
}

}  // namespace
}  // namespace algray::render
