// Scene files: what they mean, and errors that point at file:line:column.
#include "scene_json.h"

#include "json_locate.h"

#include "algray/gallery.h"
#include "algray/parser.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
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
  // A surrogate pair (\uD835\uDC65, the italic x U+1D465) is one character of the
  // equation: the '@' is its 7th, and the file's column of the '@' (all ASCII before it).
  text = R"({"surfaces": [{"equation": "\uD835\uDC65^2 + @", "clip": {"sphere": {"radius": 1}}}]})";
  e = errorOf(text);
  EXPECT_EQ(static_cast<size_t>(e.column()), text.find('@') + 1) << e.message();
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
  // Nor behind an escaped quote, which does not end the string.
  const std::string g = R"({"description": "a\" 1e400", "camera": {"fov": 1e400}})";
  EXPECT_EQ(static_cast<size_t>(errorOf(g).column()), g.rfind("1e400") + 1) << errorOf(g).what();
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
  // Upper-case hex digits, and a surrogate pair (U+1F600), decoded as nlohmann decodes them.
  const std::string e = R"({"materials": {"\u00C9": {"type": "bogus"}}})";
  EXPECT_EQ(errorOf(e).column(), columnOf(e, "\"bogus\"")) << errorOf(e).what();
  const std::string f = R"({"materials": {"\uD83D\uDE00": {"type": "bogus"}}})";
  EXPECT_EQ(errorOf(f).column(), columnOf(f, "\"bogus\"")) << errorOf(f).what();
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
      // Exponents without digits and a normal of 4 numbers (OBJ: "vn i j k").
      {tri + "v 1e 0 0\nf 1 2 3\n", "4: '1e' is not a finite decimal number"},
      {tri + "vt 0.5 2E+\nf 1 2 3\n", "4: '2E+' is not a finite decimal number"},
      {tri + "vn 0 0 1 1\nf 1 2 3\n", "4: 'vn' with 4 numbers"},
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
  // The bad value in each channel in turn: every channel's check is needed (a bad green
  // alone would leave a dropped check of red or blue unnoticed).
  for (const int channel : {0, 1, 2})
    for (const float bad : {INFINITY, NAN, -0.5f}) {
      std::vector<float> pixels(2 * 2 * 3, 0.5f);
      pixels[3 * 3 + channel] = bad;  // texel (1, 1)
      auto out = OIIO::ImageOutput::create(file.string());
      ASSERT_TRUE(out);
      ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::FLOAT)));
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
      ASSERT_TRUE(out->close());
      for (const std::string& text :
           {R"({"environment": {"image": ")" + file.string() + R"("}})",
            R"({"materials": {"m": {"texture": ")" + file.string() + R"("}}})"}) {
        SceneError e = errorOf(text);
        EXPECT_EQ(e.column(), columnOf(text, "\"/")) << bad << " " << channel << ": " << e.what();
        EXPECT_NE(e.message().find("texel (1, 1) is not a finite non-negative colour"),
                  std::string::npos)
            << bad << " " << channel << ": " << e.what();
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
  // The first "fov", counted by hand: '{' is column 1, "camera" 2-9, ':' 10, ' ' 11, '{' 12.
  EXPECT_NE(e.message().find("(first at line 1, column 13)"), std::string::npos) << e.what();
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
  // Nor after an escaped quote, which does not end the string.
  EXPECT_NO_THROW(loadSceneText("{\"description\": \"\\\"" + brackets + "\"}", "t.json", "."));
}

// Values outside the ranges docs/scene-format.md gives, each refused at the value: an image
// 0 pixels wide, a fov outside (0, 180) degrees, a negative clamp or aperture, a roughness
// beyond [0, 1], a clip sphere of negative radius, a clip box empty in z, a zero scale in z
// (each was accepted when its check was dropped: a mutation round).
TEST(SceneJson, ValuesOutsideTheirDocumentedRangesAreErrors) {
  const std::pair<std::string, std::string> cases[] = {
      {R"({"render": {"width": 0}})", "0}"},
      {R"({"camera": {"fov": -30}})", "-30"},
      {R"({"camera": {"fov": 180}})", "180"},
      {R"({"render": {"clamp": -0.5}})", "-0.5"},
      {R"({"camera": {"aperture": -0.5}})", "-0.5"},
      {R"({"materials": {"m": {"type": "conductor", "roughness": 1.5}}})", "1.5"},
      {R"({"surfaces": [{"gallery": "torus", "clip": {"sphere": {"radius": -1}}}]})", "-1"},
      {R"({"surfaces": [{"equation": "x", "clip": {"box": {"min": [0,0,1], "max": [1,1,1]}}}]})",
       "{\"min\""},
      {R"({"meshes": [{"shape": "box", "transform": {"scale": [1, 1, 0]}}]})", "[1, 1, 0]"},
  };
  for (const auto& [text, value] : cases) {
    SceneError e = errorOf(text);
    EXPECT_EQ(e.line(), 1) << text << ": " << e.what();
    EXPECT_EQ(e.column(), columnOf(text, value)) << text << ": " << e.what();
  }
}

// What keys set, in x, y, z order, and the defaults docs/scene-format.md gives for keys
// left out: environment colour 1, point light intensity 1, icosphere subdivisions 4 and
// size 1; a dielectric without "color" is untinted (its tint multiplies, so 1 = clear).
TEST(SceneJson, KeysSetTheirDocumentedValuesAndDefaults) {
  const SceneDesc s = loadSceneText(R"({
    "render": {"max_depth": 2, "tone_map": "clamp"},
    "camera": {"position": [1, -4, 2], "look_at": [0, 0, 0.5]},
    "background": [0.1, 0.2, 0.3],
    "environment": {},
    "materials": {"glass": {"type": "dielectric"}, "red": {"color": [0.7, 0.1, 0.2]}},
    "surfaces": [{"gallery": "torus", "material": "glass", "back_material": "red"}],
    "meshes": [{"shape": "icosphere"}],
    "lights": [{"type": "point", "position": [1, 2, 3]},
               {"type": "sphere", "center": [0, 0, 5], "radius": 0.5, "radiance": 1}]
  })",
                                    "t.json", ".");
  EXPECT_EQ(s.settings.maxDepth, 2);
  EXPECT_EQ(s.settings.toneMap, ToneMap::Clamp);
  EXPECT_EQ(s.camera.position, glm::dvec3(1, -4, 2));
  EXPECT_TRUE(s.hasBackground);
  EXPECT_EQ(s.background, glm::dvec3(0.1, 0.2, 0.3));
  EXPECT_EQ(s.environment.color, glm::dvec3(1.0));
  ASSERT_EQ(s.surfaces.size(), 1u);
  const Material& front = s.materials[s.surfaces[0].material];
  EXPECT_EQ(front.type, MaterialType::Dielectric);
  EXPECT_EQ(front.color, glm::dvec3(1.0));
  ASSERT_GE(s.surfaces[0].backMaterial, 0);
  EXPECT_EQ(s.materials[s.surfaces[0].backMaterial].color, glm::dvec3(0.7, 0.1, 0.2));
  ASSERT_EQ(s.pointLights.size(), 1u);
  EXPECT_EQ(s.pointLights[0].position, glm::dvec3(1, 2, 3));
  EXPECT_EQ(s.pointLights[0].intensity, glm::dvec3(1.0));
  ASSERT_EQ(s.meshes.size(), 2u);  // the icosphere and the sphere light
  // Each subdivision splits every face of the icosahedron's 20 in 4: 20 * 4^4 triangles,
  // on the unit sphere.
  EXPECT_EQ(s.meshes[0].mesh.triangles.size(), 20u * 256u);
  for (const glm::dvec3& v : s.meshes[0].mesh.positions)
    EXPECT_NEAR(glm::length(glm::dvec3(s.meshes[0].transform * glm::dvec4(v, 1.0))), 1.0, 1e-12);
  // The sphere light: every vertex at distance "radius" from "center" in scene space.
  for (const glm::dvec3& v : s.meshes[1].mesh.positions)
    EXPECT_NEAR(
        glm::length(glm::dvec3(s.meshes[1].transform * glm::dvec4(v, 1.0)) - glm::dvec3(0, 0, 5)),
        0.5, 1e-12);
}

// "rotate": [x, y, z] in degrees about x, then y, then z; "matrix": 16 numbers row-major
// (docs/scene-format.md). By the right-hand rule 90 degrees about x take +y to +z, and 90
// about y then take +z to +x; row-major puts the translation in the last column.
TEST(SceneJson, TransformsFollowTheDocumentedConventions) {
  const auto transformOf = [](const std::string& transform) {
    return loadSceneText(R"({"meshes": [{"shape": "box", "transform": )" + transform + "}]}",
                         "t.json", ".")
        .meshes.at(0)
        .transform;
  };
  const auto expectNear = [](const glm::dvec4& got, const glm::dvec3& want) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], 1e-12) << i;
  };
  expectNear(transformOf(R"({"rotate": [90, 0, 0]})") * glm::dvec4(0, 1, 0, 0), {0, 0, 1});
  expectNear(transformOf(R"({"rotate": [90, 90, 0]})") * glm::dvec4(0, 1, 0, 0), {1, 0, 0});
  // diag(2, 3, 4) and translation (5, 6, 7): (1, 1, 1) goes to (7, 9, 11).
  expectNear(transformOf(R"({"matrix": [2, 0, 0, 5, 0, 3, 0, 6, 0, 0, 4, 7, 0, 0, 0, 1]})") *
                 glm::dvec4(1, 1, 1, 1),
             {7, 9, 11});
}

// Tabs and CR LF line ends are JSON whitespace: the position scanner skips them too (it
// stopped at them, and every later value had no position). A tab is one character.
TEST(SceneJson, TabsAndCrLfKeepPositions) {
  // Counted by hand: line 2 is TAB "render": {"width": "wide"}; the TAB is column 1, the
  // opening quote of "wide" column 22.
  SceneError e = errorOf("{\r\n\t\"render\": {\"width\": \"wide\"}\r\n}");
  EXPECT_EQ(e.line(), 2) << e.what();
  EXPECT_EQ(e.column(), 22) << e.what();
}

TEST(SceneJson, DirectoryIsNotASceneFile) {
  try {
    loadSceneFile(std::filesystem::temp_directory_path());
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace algray::render
