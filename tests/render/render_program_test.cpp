// algray-render end to end: the program run on small scenes, equations and options, its
// warnings, and bad input with exit code 2 and the location in the message.
#include "algray/gallery.h"
#include "algray/parser.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

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
// intensity 1e36 at 1e-3 above a plane (2.5e41 below it, (0.8 / pi) 1e36 / 1e-6), and two
// lights of irradiance 3e38 beside an environment of 3e38 (0.8 (6e38 / pi + 3e38) =
// 3.9e38). A light just within range renders. The light stands well above the hit point's
// rounding (Embree's float t, up to an ulp of 4 here): at 1e-20 it was within it, and on an
// AVX2 host, whose triangle test gave the centre pixel t one float below 4 (its hit 2.4e-7
// above the plane), every pixel but one saw the light from behind (exit 0; session 56).
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
       {R"("lights": [{"type": "point", "position": [0, 0, 1e-3], "intensity": 1e36}])",
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

// Beyond eight unseen surfaces the warning counts the rest (a scene of 1000 small surfaces
// printed 37 lines): n spheres behind the camera, named up to eight, then "and n - 8 more".
TEST(RenderProgram, ManyUnseenSurfacesAreCounted) {
  const std::string warning = "no camera ray hit the surface";
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "algray_unseen_scene.json";
  const std::string image = (std::filesystem::temp_directory_path() / "algray_unseen.png").string();
  const auto count = [](const std::string& text, const std::string& what) {
    int n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
      ++n;
    return n;
  };
  for (int n : {8, 11}) {
    std::ofstream scene(file);
    scene << R"({"camera": {"position": [0, -6, 0], "look_at": [0, 0, 0]}, "surfaces": [)";
    for (int i = 0; i < n; ++i)
      scene << (i ? ", " : "") << R"({"equation": "x^2+y^2+z^2-1", "clip": {"sphere": )"
            << R"({"radius": 1.2}}, "transform": {"translate": [)" << 3 * i << ", -20, 0]}}";
    scene << "]}";
    scene.close();
    auto [code, out] = runRender(file.string() + " --width 40 --height 30 --spp 1 -q -o " + image);
    EXPECT_EQ(code, 0) << out;
    EXPECT_EQ(count(out, warning), 8) << out;
    EXPECT_EQ(out.find("and 3 more surfaces no camera ray hit") != std::string::npos, n == 11)
        << out;
    EXPECT_EQ(count(out, "more surfaces"), n == 11 ? 1 : 0) << out;
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
