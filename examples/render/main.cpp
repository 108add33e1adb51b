// algray-render: the sample path tracer. See docs/scene-format.md and
// docs/render-summary.md. Exit codes: 0 done, 2 bad input (scene, file, option),
// 1 other failures, 130 interrupted (the partial image is still written).
#include "image_backend.h"
#include "image_io.h"
#include "pov_export.h"
#include "render.h"
#include "scene.h"
#include "scene_builders.h"
#include "scene_json.h"

#include <algray/gallery.h>
#include <algray/parser.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

std::atomic<bool> gCancel{false};
extern "C" void onInterrupt(int) { gCancel.store(true); }

// Case-insensitive: "SURFACE.JSURF" is a jsurf file too (it was parsed as JSON).
bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.begin(), suffix.end(), s.end() - static_cast<std::ptrdiff_t>(suffix.size()),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b)); });
}

}  // namespace

int main(int argc, char** argv) {
  using namespace algray::render;
  CLI::App app{"algray-render: path tracing of algebraic surfaces (algray) and meshes with Embree"};
  std::string input, output = "algray.png", integrator, aovList, surface, exportPov;
  std::optional<int> width, height, spp, threads, maxDepth;
  std::optional<std::uint64_t> seed;
  std::optional<double> clipSphere, exposure;
  std::vector<std::string> params;
  bool quiet = false, listGallery = false, sturm = false;
  app.add_option("scene", input, "SCENE.json or SURFACE.jsurf (default: the built-in scene)");
  app.add_option("-o,--output", output, "output image: .png (tone-mapped sRGB) or .exr (linear + AOVs)");
  app.add_option("--width", width, "image width")->check(CLI::Range(1, 1 << 15));
  app.add_option("--height", height, "image height")->check(CLI::Range(1, 1 << 15));
  app.add_option("--spp", spp, "samples per pixel")->check(CLI::Range(1, 1 << 20));
  app.add_option("--threads", threads, "worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
  app.add_option("--integrator", integrator, "path (default) or direct")->check(CLI::IsMember({"path", "direct"}));
  app.add_option("--max-depth", maxDepth, "maximum path length")->check(CLI::Range(0, 1000));
  app.add_option("--seed", seed, "random seed");
  app.add_option("--exposure", exposure, "exposure in stops (PNG)");
  app.add_option("--aov", aovList, "extra EXR channels: depth,normal,albedo,id (any of them: all are written)");
  auto* surfaceOpt =
      app.add_option("--surface", surface, "quick mode: an equation or a gallery name");
  // The quick-mode options mean nothing to a scene file: given without --surface they were
  // ignored, even when invalid (--clip-sphere -5 with a .jsurf file rendered with exit 0).
  app.add_option("--param", params, "quick mode: equation parameter NAME=VALUE (repeatable)")
      ->needs(surfaceOpt);
  app.add_option("--clip-sphere", clipSphere, "quick mode: clip sphere radius")->needs(surfaceOpt);
  auto* exportOpt = app.add_option("--export-pov", exportPov,
                                   "write the scene as a POV-Ray scene to this file and exit");
  app.add_flag("--sturm", sturm, "with --export-pov: ask POV-Ray for Sturm root isolation")
      ->needs(exportOpt);
  app.add_flag("-q,--quiet", quiet, "no progress bar");
  app.add_flag("--list-gallery", listGallery, "list the gallery surfaces and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  for (size_t start = 0; !aovList.empty() && start <= aovList.size();) {
    size_t comma = aovList.find(',', start);
    std::string name = aovList.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (name != "depth" && name != "normal" && name != "albedo" && name != "id") {
      std::fprintf(stderr, "algray-render: --aov: unknown channel '%s' (depth, normal, albedo, id)\n", name.c_str());
      return 2;
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (listGallery) {
    for (const algray::GallerySurface& g : algray::gallery())
      std::printf("%-22s degree %2d  clip %.3g  %.*s\n", std::string(g.name).c_str(), g.build().degree(),
                  g.clipRadius, static_cast<int>(g.description.size()), g.description.data());
    return 0;
  }

  // ---- The scene -------------------------------------------------------------------------
  SceneDesc desc;
  try {
    if (!surface.empty()) {
      if (!input.empty()) throw SceneError("--surface", 0, 0, "give either a scene file or --surface, not both");
      QuickOptions q;
      q.surface = surface;
      for (const std::string& p : params) {
        auto eq = p.find('=');
        if (eq == std::string::npos || eq == 0) throw SceneError("--param", 0, 0, "expected NAME=VALUE, got '" + p + "'");
        // strtod, not std::stod: stod throws out_of_range for every ERANGE, so a subnormal
        // value (--param a=1e-320, its own value, as in algray-query) was "not a number",
        // and so were an overflow and an underflow to 0, which are refused by name.
        const std::string text = p.substr(eq + 1);
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size())
          throw SceneError("--param", 0, 0, "not a number in '" + p + "'");
        if (errno == ERANGE && std::isinf(v))
          throw SceneError("--param", 0, 0, "'" + p + "' overflows double");
        if (errno == ERANGE && v == 0.0)
          throw SceneError("--param", 0, 0, "'" + p + "' underflows to 0 in double");
        if (!q.parameters.emplace(p.substr(0, eq), v).second)
          throw SceneError("--param", 0, 0, p.substr(0, eq) + ": given more than once");
      }
      if (clipSphere) q.clipRadius = *clipSphere;
      try {
        desc = quickScene(q);
      } catch (const algray::ParameterError& e) {
        throw SceneError("--param", 0, 0, e.name() + ": " + e.message());
      } catch (const algray::ParseError& e) {
        throw SceneError("--surface", 1, e.column(), e.message());
      }
    } else if (input.empty()) {
      desc = defaultScene();
    } else if (endsWith(input, ".jsurf")) {
      desc = jsurfScene(input);
    } else {
      desc = loadSceneFile(input);
    }
  } catch (const SceneError& e) {
    std::fprintf(stderr, "algray-render: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {  // algray::Error (jsurf, gallery), file errors
    std::fprintf(stderr, "algray-render: %s\n", e.what());
    return 2;
  }
  RenderSettings& s = desc.settings;
  if (width) s.width = *width;
  if (height) s.height = *height;
  if (spp) s.spp = *spp;
  if (threads) s.threads = *threads;
  if (maxDepth) s.maxDepth = *maxDepth;
  if (seed) s.seed = *seed;
  if (exposure) {
    if (!std::isfinite(*exposure)) {
      std::fprintf(stderr, "algray-render: --exposure must be a finite number of stops\n");
      return 2;
    }
    s.exposure = *exposure;
  }
  if (!integrator.empty()) s.integrator = integrator == "direct" ? IntegratorType::Direct : IntegratorType::Path;

  if (!exportPov.empty()) {
    try {
      std::ofstream(exportPov) << povrayScene(desc, sturm);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "algray-render: %s\n", e.what());
      return 2;
    }
    return 0;
  }

  // ---- Build, render, write ------------------------------------------------------------
  // The output's directory is checked before the render (a typo in -o should not cost
  // the render); the format is the image library's to judge, when it writes.
  {
    const std::string probe = output + ".tmp";
    std::FILE* f = std::fopen(probe.c_str(), "wb");
    if (!f) {
      std::fprintf(stderr, "algray-render: -o %s: cannot write there (%s)\n", output.c_str(), std::strerror(errno));
      return 2;
    }
    std::fclose(f);
    std::remove(probe.c_str());
  }
  try {
    Scene scene(desc);
    // OpenImageIO loads (~0.35 s, image_backend.h) while the image renders. Not earlier:
    // while the loader runs, every thread creation waits for it (glibc's pthread_create
    // takes the loader's lock for the new thread's TLS), and building the scene starts
    // Embree's and TBB's threads (measured: the scene build then waited 0.23-0.28 s). A
    // render on one thread without a progress bar creates none and overlaps fully; the
    // others wait at their first thread creation, i.e. cost what loading at write did.
    startLoadingImageBackend();
    Image image;
    RenderOptions options;
    options.progress = !quiet && isatty(STDERR_FILENO);
    options.cancel = &gCancel;
    std::signal(SIGINT, onInterrupt);
    RenderStats stats = render(scene, image, options);
    std::signal(SIGINT, SIG_DFL);
    try {
      writeImage(image, output, s, !aovList.empty());
    } catch (const std::exception& e) {  // an unsupported format: bad input
      std::fprintf(stderr, "algray-render: %s\n", e.what());
      return 2;
    }
    std::printf("algray-render: %s, %dx%d, %d spp, %s: %.2f s, %llu rays, %.2f Mrays/s -> %s%s\n",
                desc.name.c_str(), s.width, s.height, s.spp,
                s.integrator == IntegratorType::Path ? "path" : "direct", stats.seconds,
                static_cast<unsigned long long>(stats.rays),
                stats.seconds > 0 ? stats.rays / stats.seconds * 1e-6 : 0.0, output.c_str(),
                stats.interrupted ? " (interrupted: partial image)" : "");
    return stats.interrupted ? 130 : 0;
  } catch (const algray::Error& e) {  // the plugin rejected a surface: bad input
    std::fprintf(stderr, "algray-render: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "algray-render: %s\n", e.what());
    return 1;
  }
}
