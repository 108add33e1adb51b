// libalgray_render_oiio.so: every OpenImageIO call of algray-render (image_backend.h).
#include "image_backend.h"

#include <OpenImageIO/imageio.h>

#include <memory>
#include <string>

namespace algray::render {

namespace {

constexpr int kPngFilterNone = 0x08;  // libpng's PNG_FILTER_NONE (png.h)

WriteStatus writeRaster(const std::string& formatPath, const std::string& filePath,
                        const RasterDesc& desc, const void* pixels, std::string& error) {
  auto out = OIIO::ImageOutput::create(formatPath);
  if (!out) return WriteStatus::UnsupportedFormat;
  const OIIO::TypeDesc type = desc.floating ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(desc.width, desc.height, static_cast<int>(desc.channels.size()), type);
  spec.channelnames = desc.channels;
  spec.alpha_channel = -1;
  spec.z_channel = desc.zChannel;
  if (!desc.floating) {
    spec.attribute("oiio:ColorSpace", "sRGB");
    // No PNG row filter (libpng's default tries all five per row): measured on the
    // 512x512 benchmark renders (sphere, Sarti), the write took 9-11 ms instead of
    // 23-26 ms and the files came out 4-22% smaller (flat shading compresses well as is).
    spec.attribute("png:filter", kPngFilterNone);
  }
  // For 8-bit files has_error() as well: the PNG writer reports a failed write of the file
  // (a full disk, a file size limit) only there, its open, write_image and close all
  // returning true (a 29908-byte picture came out 8192 bytes long under `ulimit -f 8`, exit
  // status 0). Not for the float formats, whose writers return false on such a failure
  // (tests/render/image_io_test.cpp), and where has_error() would refuse good files: the
  // TIFF writer of OpenImageIO 2.4 records a failed Exif directory on files it wrote well.
  if (out->open(filePath, spec) && out->write_image(type, pixels) && out->close() &&
      (desc.floating || !out->has_error()))
    return WriteStatus::Ok;
  error = out->geterror();
  if (error.empty()) error = "OpenImageIO gave no reason";
  return WriteStatus::Failed;
}

// Straight from the file (ImageInput, not the shared image cache, which kept a file's first
// size under its name), with the colour as stored: OpenImageIO multiplies a file's colour by
// its alpha on reading unless told not to, and the sRGB decoding must see the stored value
// (an RGBA texel (128, 128, 128, 77) read as 38 and decoded to 0.019 instead of 0.216).
bool readRaster(const std::string& path, Raster& out, std::string& error) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    error = OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  out.width = spec.width;
  out.height = spec.height;
  out.channels = spec.nchannels;
  // The file's own sample type (8/16-bit files are sRGB-encoded).
  out.encoded = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                spec.format.basetype == OIIO::TypeDesc::UINT16;
  if (out.width <= 0 || out.height <= 0 || out.channels <= 0) return true;
  // The buffer is sized from the header before any pixel is read: a 69-byte PNG whose
  // header said 20000 x 20000 took 6.4 GB and 42 s to fail ("Not enough image data"), a
  // 28-byte PGM of 100000 x 100000 ended in a bare std::bad_alloc. Beyond 2^30 values
  // (4 GiB as float; a 16k x 8k RGBA map is half that) the image is refused first.
  if (static_cast<double>(out.width) * out.height * out.channels > 0x1p30) {
    error = "its header says " + std::to_string(out.width) + " x " + std::to_string(out.height) +
            " pixels of " + std::to_string(out.channels) +
            " channels, more than 2^30 values (4 GiB as float): too large to read";
    return false;
  }
  out.pixels.resize(static_cast<size_t>(out.width) * out.height * out.channels);
  if (in->read_image(0, 0, 0, out.channels, OIIO::TypeDesc::FLOAT, out.pixels.data()) &&
      in->close())
    return true;
  error = in->geterror();
  return false;
}

bool canWriteFormat(const std::string& formatPath) {
  return OIIO::ImageOutput::create(formatPath) != nullptr;
}

constexpr ImageBackend kBackend{writeRaster, readRaster, canWriteFormat};

}  // namespace

}  // namespace algray::render

extern "C" const algray::render::ImageBackend* algrayRenderImageBackend() {
  return &algray::render::kBackend;
}
