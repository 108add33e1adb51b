#include "image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace algray::render {

namespace {

// Narkowicz's fit of the ACES filmic reference tone curve ("ACES Filmic Tone Mapping
// Curve", 2015): keeps highlights from clipping abruptly.
double aces(double x) {
  x = std::max(0.0, x);
  return std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// sRGB transfer function (IEC 61966-2-1).
double srgbEncode(double c) {
  c = std::clamp(c, 0.0, 1.0);
  if (c >= 1.0) return 1.0;  // exactly: 1.055 - 0.055 rounds below 1
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

bool isFloatFormat(const std::string& ext) {
  return ext == ".exr" || ext == ".hdr" || ext == ".tif" || ext == ".tiff";
}

}  // namespace

glm::dvec3 toDisplay(const glm::dvec3& linear, double exposure, ToneMap toneMap) {
  glm::dvec3 c = linear * std::exp2(exposure);
  glm::dvec3 out;
  for (int k = 0; k < 3; ++k) {
    double v = std::isfinite(c[k]) ? c[k] : 0.0;
    out[k] = srgbEncode(toneMap == ToneMap::Aces ? aces(v) : v);
  }
  return out;
}

void writeImage(const Image& image, const std::string& path, const RenderSettings& settings,
                bool aovs) {
  namespace fs = std::filesystem;
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
  bool floating = isFloatFormat(ext);
  std::string tmp = path + ".tmp";
  // The format comes from the final name; the bytes go to the temporary one.
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error(path + ": unsupported image format '" + ext + "'");
  size_t n = static_cast<size_t>(image.width) * image.height;
  bool ok = false;
  if (floating) {
    std::vector<std::string> names = {"R", "G", "B"};
    if (aovs)
      names.insert(names.end(), {"Z", "N.X", "N.Y", "N.Z", "albedo.R", "albedo.G", "albedo.B", "id"});
    auto nc = static_cast<int>(names.size());
    OIIO::ImageSpec spec(image.width, image.height, nc, OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.alpha_channel = -1;
    if (aovs) spec.z_channel = 3;
    std::vector<float> data(n * nc);
    for (size_t i = 0; i < n; ++i) {
      float* d = &data[i * nc];
      d[0] = image.color[i].r, d[1] = image.color[i].g, d[2] = image.color[i].b;
      if (aovs) {
        d[3] = image.depth[i];
        d[4] = image.normal[i].x, d[5] = image.normal[i].y, d[6] = image.normal[i].z;
        d[7] = image.albedo[i].r, d[8] = image.albedo[i].g, d[9] = image.albedo[i].b;
        d[10] = image.id[i];
      }
    }
    ok = out->open(tmp, spec) && out->write_image(OIIO::TypeDesc::FLOAT, data.data()) && out->close();
  } else {
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    std::vector<unsigned char> data(n * 3);
    for (size_t i = 0; i < n; ++i) {
      glm::dvec3 c = toDisplay(glm::dvec3(image.color[i]), settings.exposure, settings.toneMap);
      for (int k = 0; k < 3; ++k)
        data[3 * i + k] = static_cast<unsigned char>(std::lround(255.0 * c[k]));
    }
    ok = out->open(tmp, spec) && out->write_image(OIIO::TypeDesc::UINT8, data.data()) && out->close();
  }
  if (!ok) {
    std::string err = out->geterror();
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write image: " + err);
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot rename the temporary file: " + ec.message());
  }
}

}  // namespace algray::render
