#pragma once
// OpenImageIO, loaded on a background thread.
//
// Why: linking OpenImageIO (Debian's 2.4) makes the dynamic loader map and relocate 264
// shared libraries before main: 0.33-0.37 s of one core for every algray-render process
// (an empty program linked to OIIO takes 0.37 s, one linked to Embree and TBB 0.005 s;
// `perf`: ~65% of it in ld.so's symbol lookup, the rest static initialisers of OIIO's
// dependencies, e.g. OpenBLAS starting its thread pool). The quick benchmark render of
// the sphere takes 0.2 s, so that was most of the whole-process time. All OIIO calls
// therefore live in a module (libalgray_render_oiio.so, oiio_backend.cpp) that main
// starts loading before the scene is built; the first image read or write waits for it.
// OpenImageIO stays the only image reader and writer.
#include <functional>
#include <string>
#include <vector>

namespace algray::render {

// Pixels handed to the writer: interleaved, width * height * channels.size() values.
struct RasterDesc {
  int width = 0, height = 0;
  std::vector<std::string> channels;  // names; 3 = R, G, B
  int zChannel = -1;                  // index of the depth channel, or -1
  bool floating = false;              // float samples (linear) or 8-bit (sRGB-encoded)
};

// Pixels read from a file, converted to float.
struct Raster {
  int width = 0, height = 0, channels = 0;
  bool encoded = false;  // the file stored 8- or 16-bit integers (sRGB-encoded)
  std::vector<float> pixels;
};

enum class WriteStatus { Ok, UnsupportedFormat, Failed };

// The module's entry points (same compiler and libstdc++ as the program: C++ types are
// fine across the boundary). On failure they set `error`.
struct ImageBackend {
  // Writes `pixels` to filePath in the format that formatPath's extension names.
  WriteStatus (*write)(const std::string& formatPath, const std::string& filePath,
                       const RasterDesc& desc, const void* pixels, std::string& error);
  bool (*read)(const std::string& path, Raster& out, std::string& error);
  // Whether OpenImageIO can write the format that formatPath's extension names.
  bool (*canWrite)(const std::string& formatPath);
};

// Starts loading the module on a background thread (once; later calls do nothing).
// whenLoaded, if given, runs on that thread once the module is loaded (with nullptr if it
// could not be): work that needs OpenImageIO without making the caller wait for it.
void startLoadingImageBackend(std::function<void(const ImageBackend*)> whenLoaded = {});

// The loaded module (starts loading if needed and waits). Throws std::runtime_error
// naming the paths tried if the module cannot be loaded.
const ImageBackend& imageBackend();

}  // namespace algray::render

// The module exports this one symbol.
extern "C" const algray::render::ImageBackend* algrayRenderImageBackend();
