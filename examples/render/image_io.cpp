#include "image_io.h"

#include "image_backend.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

namespace algray::render {

namespace {

// Narkowicz's fit of the ACES filmic reference tone curve ("ACES Filmic Tone Mapping
// Curve", 2015): keeps highlights from clipping abruptly.
double aces(double x) {
  x = std::max(0.0, x);
  if (x > 1e100) return 1.0;  // the limit (2.51 / 2.43, clamped); x * x would overflow
  return std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// sRGB transfer function (IEC 61966-2-1).
double srgbEncode(double c) {
  c = std::clamp(c, 0.0, 1.0);
  if (c >= 1.0) return 1.0;  // exactly: 1.055 - 0.055 rounds below 1
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

// The file name's extension in lower case (".EXR" names the same format as ".exr").
std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return std::tolower(ch); });
  return ext;
}

bool isFloatFormat(const std::string& ext) {
  return ext == ".exr" || ext == ".hdr" || ext == ".tif" || ext == ".tiff";
}

// lround(255 * srgbEncode(v)) without std::pow per call (~25 ms of a 512x512 PNG write,
// perf): thresholds[k] is the least double whose byte is > k, so the byte is the number
// of thresholds <= v (the byte does not decrease with v). Exact: the same bytes.
class EncodeTable {
 public:
  static const EncodeTable& instance() {
    static const EncodeTable table;
    return table;
  }
  std::uint8_t operator()(double v) const {  // NaN: 0
    return static_cast<std::uint8_t>(std::upper_bound(thresholds_.begin(), thresholds_.end(), v) -
                                     thresholds_.begin());
  }

 private:
  // Bisection on the bit patterns of [0, 1] (ordered like the values for non-negative
  // doubles): 255 x 62 curve evaluations, well under a millisecond.
  EncodeTable() {
    for (long k = 1; k <= 255; ++k) {
      std::uint64_t lo = std::bit_cast<std::uint64_t>(0.0), hi = std::bit_cast<std::uint64_t>(1.0);
      while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (std::lround(255.0 * srgbEncode(std::bit_cast<double>(mid))) >= k)
          hi = mid;
        else
          lo = mid + 1;
      }
      thresholds_[k - 1] = std::bit_cast<double>(lo);
    }
  }
  std::array<double, 255> thresholds_{};
};

// An exposed value the curves can take: NaN (0 times an infinite exposure) is black, +inf
// (a huge --exposure times a lit pixel) saturates instead of turning black as NaN does.
double finiteExposed(double exposed) {
  return std::isnan(exposed) ? 0.0 : std::clamp(exposed, -1e300, 1e300);
}

// One channel of toDisplay, 8 bits, from the exposed linear value. ToneMap::None: jsurf's
// round(255 * clamp(v)) (java.awt.Color(float, float, float): (int) (255 v + 0.5)).
std::uint8_t encodeByte(double exposed, ToneMap toneMap) {
  const double v = finiteExposed(exposed);
  if (toneMap == ToneMap::None)
    return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
  return EncodeTable::instance()(toneMap == ToneMap::Aces ? aces(v) : v);
}

}  // namespace

double srgbDecode(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

glm::dvec3 toDisplay(const glm::dvec3& linear, double exposure, ToneMap toneMap) {
  glm::dvec3 c = linear * std::exp2(exposure);
  glm::dvec3 out;
  for (int k = 0; k < 3; ++k) {
    const double v = finiteExposed(c[k]);
    out[k] = toneMap == ToneMap::None ? std::clamp(v, 0.0, 1.0)
                                      : srgbEncode(toneMap == ToneMap::Aces ? aces(v) : v);
  }
  return out;
}

std::uint8_t toDisplayByte(double linear, double exposure, ToneMap toneMap) {
  return encodeByte(linear * std::exp2(exposure), toneMap);
}

bool holdsAovs(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return isFloatFormat(ext) && ext != ".hdr";
}

AovSet parseAovList(const std::string& list) {
  AovSet set;
  for (size_t start = 0; start <= list.size();) {
    const size_t comma = list.find(',', start);
    const std::string name =
        list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (name == "depth")
      set.depth = true;
    else if (name == "normal")
      set.normal = true;
    else if (name == "albedo")
      set.albedo = true;
    else if (name == "id")
      set.id = true;
    else
      throw std::invalid_argument("unknown channel '" + name + "' (depth, normal, albedo, id)");
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return set;
}

std::string uniqueSuffix() {
  std::random_device random;
  const std::uint64_t bits = (std::uint64_t{random()} << 32) ^ random();
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(bits));
  return std::to_string(getpid()) + "-" + hex;
}

void writeImage(const Image& image, const std::string& path, const RenderSettings& settings,
                const AovSet& aovs) {
  namespace fs = std::filesystem;
  const std::string ext = lowerExtension(path);
  const ImageBackend& backend = imageBackend();
  RasterDesc desc;
  desc.width = image.width;
  desc.height = image.height;
  desc.floating = isFloatFormat(ext);
  desc.channels = {"R", "G", "B"};
  size_t n = static_cast<size_t>(image.width) * image.height;
  std::vector<float> floats;
  std::vector<unsigned char> bytes;
  if (desc.floating) {
    // Only the channels asked for, in the order depth, normal, albedo, id.
    if (aovs.depth) {
      desc.zChannel = static_cast<int>(desc.channels.size());
      desc.channels.push_back("Z");
    }
    if (aovs.normal) desc.channels.insert(desc.channels.end(), {"N.X", "N.Y", "N.Z"});
    if (aovs.albedo)
      desc.channels.insert(desc.channels.end(), {"albedo.R", "albedo.G", "albedo.B"});
    if (aovs.id) desc.channels.push_back("id");
    size_t nc = desc.channels.size();
    floats.resize(n * nc);
    // ToneMap::None's colours are display values (the surfer integrator's, as jsurf writes
    // them to 8-bit files, which viewers read as sRGB): a float file holds the linear values
    // that show the same, not the display values as if they were linear (washed out).
    const bool display = settings.toneMap == ToneMap::None;
    for (size_t i = 0; i < n; ++i) {
      float* d = &floats[i * nc];
      for (int k = 0; k < 3; ++k) {
        const double v = image.color[i][k];
        *d++ = display ? static_cast<float>(srgbDecode(std::clamp(finiteExposed(v), 0.0, 1.0)))
                       : image.color[i][k];
      }
      if (aovs.depth) *d++ = image.depth[i];
      if (aovs.normal) *d++ = image.normal[i].x, *d++ = image.normal[i].y, *d++ = image.normal[i].z;
      if (aovs.albedo) *d++ = image.albedo[i].r, *d++ = image.albedo[i].g, *d++ = image.albedo[i].b;
      if (aovs.id) *d++ = image.id[i];
    }
  } else {
    const double scale = std::exp2(settings.exposure);
    bytes.resize(n * 3);
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k)
        bytes[3 * i + k] =
            encodeByte(static_cast<double>(image.color[i][k]) * scale, settings.toneMap);
  }
  // The format comes from the final name; the bytes go to the temporary one.
  // (A name of this process's own: "OUT.tmp" replaced and removed a user's file; a short
  // one beside OUT: OUT + a suffix passed NAME_MAX for a valid 244-byte name; random, not
  // the PID alone: two containers' renders, both PID 1, wrote one directory's file.)
  std::string tmp =
      (fs::path(path).parent_path() / (".algray-" + uniqueSuffix() + ".tmp")).string();
  std::string error;
  const void* pixels = desc.floating ? static_cast<const void*>(floats.data()) : bytes.data();
  const WriteStatus status = backend.write(path, tmp, desc, pixels, error);
  if (status == WriteStatus::UnsupportedFormat)
    throw std::runtime_error(path + ": unsupported image format '" + ext + "'");
  if (status != WriteStatus::Ok) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot write image: " + error);
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    const std::string why = ec.message();  // (remove() below clears ec: "Success" was shown)
    fs::remove(tmp, ec);
    throw std::runtime_error(path + ": cannot rename the temporary file: " + why);
  }
}

}  // namespace algray::render
