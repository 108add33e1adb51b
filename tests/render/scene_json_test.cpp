// Scene files: what they mean, and errors that point at file:line:column.
#include "scene_json.h"

#include "json_locate.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>

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
  SceneError a = errorOf("{\n \"surfaces\": [\n  {\"gallery\": \"sphere\", \"material\": \"gold\"}]}");
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
  // No clip region for an equation.
  SceneError d = errorOf("{\"surfaces\": [{\"equation\": \"x^2 + y^2 - 1\"}]}");
  EXPECT_EQ(d.column(), 15);
  EXPECT_NE(d.message().find("clip"), std::string::npos);
  // A camera whose up is the view direction: the up value (the camera found it only when
  // the render started, without a position, exit code 1).
  SceneError u = errorOf("{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]}}");
  EXPECT_EQ(u.column(), 64);
  EXPECT_NE(u.message().find("parallel"), std::string::npos);
}

TEST(SceneJson, EquationErrorPointsIntoTheString) {
  // The '@' is the 7th character of the equation; the string starts at column 28.
  std::string text = "{\"surfaces\": [{\"equation\": \"x^2 + @\", \"clip\": {\"sphere\": {\"radius\": 1}}}]}";
  SceneError e = errorOf(text);
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(static_cast<size_t>(e.column()), text.find('@') + 1);
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

// The program: a broken scene gives exit code 2 and "file:line:column: message".
TEST(RenderProgram, BadSceneExitsWithCode2AndLocation) {
  std::filesystem::path file = std::filesystem::temp_directory_path() / "algray_bad_scene.json";
  std::ofstream(file) << "{\n  \"camera\": {\"fov\": \"wide\"}\n}\n";
  std::string cmd = std::string(ALGRAY_RENDER_EXE) + " " + file.string() + " -o /dev/null 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char buf[512];
  while (fgets(buf, sizeof buf, pipe)) out += buf;
  int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
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
  };
  for (const auto& [args, expected] : cases) {
    const std::string output = std::string(args).find(" -o ") == std::string::npos ? " -o /dev/null" : "";
    const std::string cmd = std::string(ALGRAY_RENDER_EXE) + " " + args + " --width 8 --height 8 -q" + output + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string out;
    char buf[512];
    while (fgets(buf, sizeof buf, pipe)) out += buf;
    const int status = pclose(pipe);
    ASSERT_TRUE(WIFEXITED(status)) << args;
    EXPECT_EQ(WEXITSTATUS(status), 2) << args << ": " << out;
    EXPECT_NE(out.find(expected), std::string::npos) << args << ": " << out;
  }
}

}  // namespace
}  // namespace algray::render
