// algray-render: the sample path tracer. See docs/scene-format.md and
// docs/render-summary.md. Exit codes: 0 done, 2 bad input (scene, file, option),
// 1 other failures, 130 interrupted (the partial image is still written).
#include "cli_text.h"
#include "equation_place.h"
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

#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::atomic<bool> gCancel{false};
// Set (with gCancel) when OpenImageIO, loaded during the render, cannot write -o's format:
// a typo such as "-o out.pgn" stops the render instead of being reported after it.
std::atomic<bool> gUnwritableFormat{false};
// The first Ctrl-C asks the render to stop (the finished pixels are written); a second
// one ends the program at once (signal() is async-signal-safe).
extern "C" void onInterrupt(int) {
  gCancel.store(true);
  std::signal(SIGINT, SIG_DFL);
}

// Case-insensitive: "SURFACE.JSURF" is a jsurf file too (it was parsed as JSON).
bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.begin(), suffix.end(),
                    s.end() - static_cast<std::ptrdiff_t>(suffix.size()), [](char a, char b) {
                      return std::tolower(static_cast<unsigned char>(a)) ==
                             std::tolower(static_cast<unsigned char>(b));
                    });
}

// For a scene argument that names no file: how to say what it looks like it means, a gallery
// surface or an equation (`algray-render "x^2+y^2+z^2-1"` was "cannot open the scene file"
// and nothing more); empty when it looks like neither.
std::string sceneArgumentHint(const std::string& input) {
  std::error_code ec;
  if (std::filesystem::exists(input, ec)) return "";
  if (algray::findGallerySurface(input))
    return " (a gallery surface is rendered with --surface: algray-render --surface " + input + ")";
  if (input.find_first_of("^*=+(") != std::string::npos)
    return " (an equation is rendered with --surface: algray-render --surface \"" + input + "\")";
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace algray::render;
  CLI::App app{"algray-render: path tracing of algebraic surfaces (algray) and meshes with Embree"};
  std::string input, output = "algray.png", integrator, aovList, surface, exportPov;
  std::optional<int> width, height, spp, threads, maxDepth;
  std::optional<long long> seed;  // signed: "-1" wrapped to 2^64 - 1 as an unsigned option
  std::optional<double> clipSphere, exposure;
  std::vector<std::string> params;
  bool quiet = false, listGallery = false, sturm = false;
  app.add_option("scene", input, "SCENE.json or SURFACE.jsurf (default: the built-in scene)");
  app.add_option("-o,--output", output,
                 "output image (default algray.png): .exr, .tif (linear, with AOVs), .hdr "
                 "(linear) or an 8-bit format OpenImageIO writes, as .png or .jpg "
                 "(tone-mapped sRGB)");
  app.add_option("--width", width, "image width")
      ->transform(algray::cli::decimal())
      ->check(CLI::Range(1, 1 << 15));
  app.add_option("--height", height, "image height")
      ->transform(algray::cli::decimal())
      ->check(CLI::Range(1, 1 << 15));
  app.add_option("--spp", spp, "samples per pixel")
      ->transform(algray::cli::decimal())
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--threads", threads, "worker threads (0 = all cores)")
      ->transform(algray::cli::decimal())
      ->check(CLI::Range(0, 1024));
  app.add_option("--integrator", integrator,
                 "path (default), direct, or surfer (.jsurf files' default: SURFER's shading)")
      ->check(CLI::IsMember({"path", "direct", "surfer"}));
  app.add_option("--max-depth", maxDepth, "maximum path length")
      ->transform(algray::cli::decimal())
      ->check(CLI::Range(0, 1000));
  app.add_option("--seed", seed, "random seed")
      ->transform(algray::cli::decimal())
      ->check(CLI::Range(0LL, 1LL << 30));  // as the JSON "seed"
  app.add_option("--exposure", exposure, "exposure in stops (PNG)");
  app.add_option(
      "--aov", aovList,
      "extra EXR channels, any of depth,normal,albedo,id (only those listed are written)");
  auto* surfaceOpt = app.add_option(
      "--surface", surface,
      "quick mode: an equation (x^2+y^2+z^2-1, or as typeset: x²+y²+z²−1) or a gallery name");
  // The quick-mode options mean nothing to a scene file: given without --surface they were
  // ignored, even when invalid (--clip-sphere -5 with a .jsurf file rendered with exit 0).
  app.add_option("--param", params, "quick mode: equation parameter NAME=VALUE (repeatable)")
      ->needs(surfaceOpt);
  app.add_option("--clip-sphere", clipSphere,
                 "quick mode: clip sphere radius (default: the gallery surface's, or 2)")
      ->needs(surfaceOpt);
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
  AovSet aovs;
  if (!aovList.empty()) {
    try {
      aovs = parseAovList(aovList);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "algray-render: --aov: %s\n", e.what());
      return 2;
    }
  }
  // The channels were silently dropped for an 8-bit or RGB-only output. (A TIFF holds
  // them too, but without their names.)
  if (aovs.any() && !holdsAovs(output)) {
    std::fprintf(stderr, "algray-render: --aov: -o %s cannot hold extra channels (use .exr)\n",
                 output.c_str());
    return 2;
  }
  if (listGallery) {
    // The equation as algray reads it, ready to paste into --surface or a scene file.
    for (const algray::GallerySurface& g : algray::gallery())
      std::printf("%-22s degree %2d  clip %.3g  %s%s%s\n", std::string(g.name).c_str(),
                  g.build().degree(), g.clipRadius, std::string(g.description).c_str(),
                  g.equation.empty() ? "" : ": ", std::string(g.equation).c_str());
    return 0;
  }

  // ---- The scene -------------------------------------------------------------------------
  SceneDesc desc;
  // An empty --surface or --export-pov was taken for an absent one: `--surface ""` rendered
  // the default scene with exit 0, its --param and --clip-sphere (even invalid ones)
  // ignored, and `--export-pov ""` rendered algray.png instead of exporting.
  if (exportOpt->count() > 0 && exportPov.empty()) {
    std::fprintf(stderr, "algray-render: --export-pov: the file name is empty\n");
    return 2;
  }
  try {
    if (surfaceOpt->count() > 0) {
      if (!input.empty())
        throw SceneError("--surface", 0, 0, "give either a scene file or --surface, not both");
      QuickOptions q;
      q.surface = surface;
      for (const std::string& p : params) {
        // The syntax is algray-query's (cli_text.h); inf and nan go on to the parser,
        // which names them as the parameter's value.
        using algray::cli::NumberProblem;
        algray::cli::Param param = algray::cli::readParam(p);
        if (param.name.empty())
          throw SceneError("--param", 0, 0, "expected NAME=VALUE, got '" + p + "'");
        switch (param.number.problem) {
          case NumberProblem::kNone:
            break;
          case NumberProblem::kNotANumber: {
            std::string problem;
            const std::optional<double> v =
                algray::cli::constantExpression(param.valueText, problem);
            if (!v)
              throw SceneError("--param", 0, 0,
                               "'" + p + "': neither a number nor a constant (" + problem + ")");
            param.number.value = *v;
            break;
          }
          case NumberProblem::kOverflows:
            throw SceneError("--param", 0, 0, "'" + p + "' overflows double");
          case NumberProblem::kUnderflows:
            throw SceneError("--param", 0, 0, "'" + p + "' underflows to 0 in double");
        }
        if (!q.parameters.emplace(param.name, param.number.value).second)
          throw SceneError("--param", 0, 0, param.name + ": given more than once");
      }
      if (clipSphere) q.clipRadius = *clipSphere;
      q.width = width;
      q.height = height;
      try {
        desc = quickScene(q);
      } catch (const algray::ParameterError& e) {
        throw SceneError("--param", 0, 0, e.name() + ": " + e.message());
      } catch (const algray::ParseError& e) {
        // The equation's own line and column where it has line breaks (a second place the
        // message names likewise).
        const algray::cli::EquationPlace at = algray::cli::equationPlace(surface, e.column());
        throw SceneError("--surface", at.line, at.column, algray::cli::placedMessage(e, surface));
      }
    } else if (input.empty()) {
      desc = defaultScene();
    } else if (endsWith(input, ".jsurf")) {
      desc = jsurfScene(input);
    } else {
      if (const std::string hint = sceneArgumentHint(input); !hint.empty())
        throw SceneError(input, 0, 0, "no such scene file" + hint);
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
  if (seed) s.seed = static_cast<std::uint64_t>(*seed);
  if (exposure) {
    if (!std::isfinite(*exposure)) {
      std::fprintf(stderr, "algray-render: --exposure must be a finite number of stops\n");
      return 2;
    }
    s.exposure = *exposure;
  }
  if (!integrator.empty()) {
    s.integrator = integrator == "direct"   ? IntegratorType::Direct
                   : integrator == "surfer" ? IntegratorType::Surfer
                                            : IntegratorType::Path;
    if (s.integrator == IntegratorType::Surfer && !desc.surfer) {
      std::fprintf(stderr,
                   "algray-render: --integrator surfer: shades .jsurf files only (it needs "
                   "their jsurf materials and lights)\n");
      return 2;
    }
    // ToneMap::None is for the surfer integrator's display values; path and direct compute
    // radiance, which the .jsurf import's PNGs showed through the clamp and sRGB curve.
    if (s.integrator != IntegratorType::Surfer && s.toneMap == ToneMap::None)
      s.toneMap = ToneMap::Clamp;
  }

  if (!exportPov.empty()) {
    try {
      // The scene is built as for a render, only to be checked: the plugin's refusals (a
      // zero or constant polynomial, a clip region beyond its range) exported a file that
      // POV-Ray cannot parse, with exit code 0.
      { const Scene checked(desc); }
      const std::string text = povrayScene(desc, sturm);
      // A file that cannot be written (missing directory, a directory, a full disk) was
      // reported as success with exit code 0.
      std::ofstream pov(exportPov);
      if (!pov) {
        std::fprintf(stderr, "algray-render: --export-pov %s: cannot write there (%s)\n",
                     exportPov.c_str(), std::strerror(errno));
        return 2;
      }
      pov << text;
      pov.close();
      if (!pov) {
        std::fprintf(stderr, "algray-render: --export-pov %s: error writing the file\n",
                     exportPov.c_str());
        return 1;
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "algray-render: %s\n", e.what());
      return 2;
    }
    return 0;
  }

  // ---- Build, render, write ------------------------------------------------------------
  // The output's directory is checked before the render (a typo in -o should not cost
  // the render); the format is the image library's to judge, as soon as it is loaded. The
  // probe has a name of its own ("OUT.tmp" removed a user's file of that name) and is
  // created only if absent.
  {
    // (The probe is made beside the name, so a directory named by -o passed it.)
    std::error_code ec;
    if (std::filesystem::is_directory(output, ec)) {
      std::fprintf(stderr, "algray-render: -o %s: is a directory\n", output.c_str());
      return 2;
    }
    // A short name beside it: OUT + a suffix passed NAME_MAX for a valid 244-byte name.
    const std::filesystem::path outPath(output);
    const std::string probe =
        (outPath.parent_path() / (".algray-probe-" + uniqueSuffix())).string();
    std::FILE* f = std::fopen(probe.c_str(), "wbx");
    if (!f && errno != EEXIST) {
      std::fprintf(stderr, "algray-render: -o %s: cannot write there (%s)\n", output.c_str(),
                   std::strerror(errno));
      return 2;
    }
    if (f) {
      std::fclose(f);
      std::remove(probe.c_str());
    }
  }
  // The image's buffers (colour, depth, normal, albedo, id: 44 bytes a pixel, and the
  // file's copy) beyond the machine's memory: refused by name before anything is
  // allocated (32768 x 32768 asked for 47 GB and ended in std::bad_alloc or the OOM killer).
  {
    const double bytes = static_cast<double>(s.width) * s.height * (44.0 + 44.0);
    const double memory =
        static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
    if (memory > 0 && bytes > memory) {
      std::fprintf(stderr,
                   "algray-render: an image of %d x %d needs about %.1f GiB, more than this "
                   "machine's %.1f GiB "
                   "(lower --width/--height or the scene's render size)\n",
                   s.width, s.height, bytes / (1 << 30), memory / (1 << 30));
      return 2;
    }
  }
  try {
    Scene scene(desc);
    // A surface that cannot be seen is worth a word (exit code 0: the picture is valid):
    // quick mode's default clip sphere (radius 2) holds no point of x^2+y^2+z^2 = 100.
    // In quick mode a larger --clip-sphere is the remedy when the surface lies farther
    // out; x^2+y^2+z^2+1 has no real point anywhere, which its terms may tell.
    const bool quick = surfaceOpt->count() > 0;
    for (const std::string& label : scene.emptySurfaces())
      std::fprintf(
          stderr,
          "algray-render: warning: %s: no point of the surface lies in its clip region, so none "
          "of it is drawn%s\n",
          label.c_str(),
          !quick ? ""
          : evidentlyHasNoRealPoints(desc.surfaces.front().polynomial)
              ? " (nor anywhere: every term is an even power of x, y, z with the constant's sign)"
              : " (a larger --clip-sphere may reach it, if it has real points farther out)");
    for (const std::string& noisy : scene.noisySurfaces())
      std::fprintf(stderr, "algray-render: warning: %s\n", noisy.c_str());
    // OpenImageIO loads (~0.35 s, image_backend.h) while the image renders. Not earlier:
    // while the loader runs, every thread creation waits for it (glibc's pthread_create
    // takes the loader's lock for the new thread's TLS), and building the scene starts
    // Embree's and TBB's threads (measured: the scene build then waited 0.23-0.28 s). A
    // render on one thread without a progress bar creates none and overlaps fully; the
    // others wait at their first thread creation, i.e. cost what loading at write did.
    startLoadingImageBackend([output](const ImageBackend* backend) {
      if (backend && !backend->canWrite(output)) {
        gUnwritableFormat.store(true);
        gCancel.store(true);
      }
    });
    Image image;
    RenderOptions options;
    options.progress = !quiet && isatty(STDERR_FILENO);
    options.cancel = &gCancel;
    std::signal(SIGINT, onInterrupt);
    RenderStats stats = render(scene, image, options);
    std::signal(SIGINT, SIG_DFL);
    // A pixel beyond float's range would be written as inf (exit 0): refused, as a colour
    // times its image beyond float is (scene-format.md).
    if (stats.overflowPixels > 0) {
      std::fprintf(stderr,
                   "algray-render: pixel (%d, %d) (and %llu more): radiance %.3g, beyond the "
                   "image's float range (3.4e38): lower the lights' intensities or move them "
                   "away from the surfaces\n",
                   stats.overflowX, stats.overflowY,
                   static_cast<unsigned long long>(stats.overflowPixels - 1), stats.overflowValue);
      return 2;
    }
    if (gUnwritableFormat.load()) {
      std::fprintf(stderr,
                   "algray-render: -o %s: unsupported image format (OpenImageIO cannot write it)\n",
                   output.c_str());
      return 2;
    }
    try {
      writeImage(image, output, s, aovs);
    } catch (const std::exception& e) {  // an unsupported format: bad input
      std::fprintf(stderr, "algray-render: %s\n", e.what());
      return 2;
    }
    // A surface no camera ray met is worth a word too (exit code 0): in quick mode
    // x^2+y^2+z^2 = 1e-6 in the default clip sphere covers a tenth of a pixel, and the
    // picture showed the floor alone without a message. Seen through glass is seen. The
    // first kListed are named, the rest counted: a scene of 1000 small surfaces on a plane
    // printed 37 such lines (session 56).
    if (!stats.interrupted) {
      constexpr int kListed = 8;
      int unseen = 0;
      for (const Scene::DrawnSurface& drawn : scene.drawnSurfaces()) {
        if (stats.wasSeen(drawn.geomID) || ++unseen > kListed) continue;
        std::fprintf(stderr,
                     "algray-render: warning: %s: no camera ray hit the surface (it is smaller "
                     "than a pixel, outside the view or hidden behind other objects)%s\n",
                     drawn.label.c_str(),
                     quick ? "; a smaller --clip-sphere frames a small surface closer" : "");
      }
      if (unseen > kListed)
        std::fprintf(stderr, "algray-render: warning: and %d more surfaces no camera ray hit\n",
                     unseen - kListed);
    }
    std::printf("algray-render: %s, %dx%d, %d spp, %s: %.2f s, %llu rays, %.2f Mrays/s -> %s%s\n",
                desc.name.c_str(), s.width, s.height, s.spp,
                s.integrator == IntegratorType::Path     ? "path"
                : s.integrator == IntegratorType::Surfer ? "surfer"
                                                         : "direct",
                stats.seconds, static_cast<unsigned long long>(stats.rays),
                stats.seconds > 0 ? stats.rays / stats.seconds * 1e-6 : 0.0, output.c_str(),
                stats.interrupted ? " (interrupted: partial image)" : "");
    return stats.interrupted ? 130 : 0;
  } catch (const algray::Error& e) {  // the plugin rejected a surface: bad input
    std::fprintf(stderr, "algray-render: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "algray-render: out of memory (image %d x %d, %d spp)\n", s.width,
                 s.height, s.spp);
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "algray-render: %s\n", e.what());
    return 1;
  }
}
