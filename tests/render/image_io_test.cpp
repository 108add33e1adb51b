// Image output: the display transform against its closed forms, PNG and EXR files read
// back with OpenImageIO, atomic writing (no temporary file left behind).
#include "image_io.h"
#include "material.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace algray::render {
namespace {

TEST(Display, SrgbAndClampClosedForms) {
  // sRGB: 12.92 c below 0.0031308, 1.055 c^(1/2.4) - 0.055 above (IEC 61966-2-1).
  EXPECT_NEAR(toDisplay(glm::dvec3(0.5), 0.0, ToneMap::Clamp).r,
              1.055 * std::pow(0.5, 1 / 2.4) - 0.055, 1e-12);
  EXPECT_NEAR(toDisplay(glm::dvec3(0.001), 0.0, ToneMap::Clamp).g, 0.01292, 1e-12);
  EXPECT_EQ(toDisplay(glm::dvec3(7.0), 0.0, ToneMap::Clamp).b, 1.0);
  // One stop of exposure doubles the linear value.
  EXPECT_NEAR(toDisplay(glm::dvec3(0.25), 1.0, ToneMap::Clamp).r,
              toDisplay(glm::dvec3(0.5), 0.0, ToneMap::Clamp).r, 1e-12);
  // The filmic curve is monotone, maps 0 to 0 and saturates below 1 + rounding.
  double prev = -1;
  for (double x = 0; x < 20; x += 0.05) {
    double y = toDisplay(glm::dvec3(x), 0.0, ToneMap::Aces).r;
    EXPECT_GE(y, prev);
    EXPECT_LE(y, 1.0);
    prev = y;
  }
  EXPECT_EQ(toDisplay(glm::dvec3(0.0), 0.0, ToneMap::Aces).r, 0.0);
  // Non-finite input does not leak into the file.
  EXPECT_EQ(toDisplay(glm::dvec3(NAN), 0.0, ToneMap::Aces).r, 0.0);
  // An exposure whose 2^EV overflows saturates a lit pixel and keeps a black one black
  // (--exposure 1e308 turned every pixel black).
  for (const ToneMap map : {ToneMap::Aces, ToneMap::Clamp}) {
    EXPECT_EQ(toDisplay(glm::dvec3(0.5), 1e308, map).r, 1.0);
    EXPECT_EQ(toDisplay(glm::dvec3(INFINITY), 0.0, map).r, 1.0);
    EXPECT_EQ(toDisplay(glm::dvec3(0.0), 1e308, map).r, 0.0);
    EXPECT_EQ(toDisplayByte(0.5, 1e308, map), 255);
    EXPECT_EQ(toDisplayByte(0.0, 1e308, map), 0);
    EXPECT_EQ(toDisplayByte(0.5, -1e308, map), 0);
  }
}

TEST(Display, ByteIsRoundedDisplayValue) {
  // PNG bytes come from a threshold table (image_io.cpp); they must equal
  // lround(255 * toDisplay) for every input: dense near each rounding step of both
  // tone curves, plus random values over many magnitudes and the special values.
  std::vector<double> xs = {0.0, -0.0,  -1.0,     1e-300,    0.0031308,
                            1.0, 1e300, INFINITY, -INFINITY, NAN};
  std::uint64_t state = 12345;
  for (int i = 0; i < 200000; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    double u = static_cast<double>(state >> 11) * 0x1p-53;
    xs.push_back(std::exp2(-20.0 + 24.0 * u));
  }
  for (ToneMap toneMap : {ToneMap::Clamp, ToneMap::Aces})
    for (double exposure : {0.0, 1.5})
      for (double x : xs) {
        const auto expected = std::lround(255.0 * toDisplay(glm::dvec3(x), exposure, toneMap).r);
        ASSERT_EQ(toDisplayByte(x, exposure, toneMap), expected) << x << " exposure " << exposure;
      }
  // Exactly at the steps: the table's thresholds are the least values of each byte.
  for (int k = 0; k < 256; ++k) {
    double lo = 0, hi = 1;
    for (int it = 0; it < 80; ++it) {
      double mid = 0.5 * (lo + hi);
      (std::lround(255.0 * toDisplay(glm::dvec3(mid), 0.0, ToneMap::Clamp).r) >= k ? hi : lo) = mid;
    }
    for (double x : {std::nextafter(hi, 0.0), hi, std::nextafter(hi, 2.0)})
      ASSERT_EQ(toDisplayByte(x, 0.0, ToneMap::Clamp),
                std::lround(255.0 * toDisplay(glm::dvec3(x), 0.0, ToneMap::Clamp).r))
          << x;
  }
}

// ToneMap::None writes display values as jsurf does: (int) (255 v + 0.5) of v clamped to
// [0, 1] (java.awt.Color's float constructor), no tone curve, no sRGB curve.
TEST(Display, NoneIsJsurfsRounding) {
  const std::pair<double, int> cases[] = {{0.5, 128},      {0.25, 64}, {0.1, 26},   {1.0, 255},
                                          {1.7, 255},      {-0.3, 0},  {0.0, 0},    {NAN, 0},
                                          {INFINITY, 255}, {0.2, 51},  {0.998, 254}};
  for (const auto& [v, byte] : cases) {
    EXPECT_EQ(toDisplayByte(v, 0.0, ToneMap::None), byte) << v;
    if (std::isfinite(v)) {
      EXPECT_DOUBLE_EQ(toDisplay(glm::dvec3(v), 0.0, ToneMap::None).r, std::clamp(v, 0.0, 1.0));
    }
  }
  EXPECT_EQ(toDisplayByte(0.25, 1.0, ToneMap::None), 128);  // exposure still applies
}

Image gradient() {
  Image image;
  image.resize(8, 4);
  for (int i = 0; i < 32; ++i) {
    image.color[i] = glm::vec3(i / 31.0f, 0.5f, 1.0f - i / 31.0f);
    image.depth[i] = static_cast<float>(i);
    image.normal[i] = glm::vec3(0, 0, 1);
    image.albedo[i] = glm::vec3(0.25f);
    image.id[i] = static_cast<float>(i % 3);
  }
  return image;
}

// The index of a named channel (EXR stores them in its own order); fails the test if absent.
int channelIndex(const OIIO::ImageSpec& spec, const std::string& name) {
  for (int c = 0; c < spec.nchannels; ++c)
    if (spec.channelnames[c] == name) return c;
  ADD_FAILURE() << "no channel " << name;
  return 0;
}

TEST(ImageFile, ExrKeepsLinearValuesAndAovChannels) {
  auto path = (std::filesystem::temp_directory_path() / "algray_io_test.exr").string();
  Image image = gradient();
  writeImage(image, path, RenderSettings{}, AovSet::all());
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  ASSERT_EQ(spec.nchannels, 11);
  EXPECT_EQ(spec.channelnames[3], "Z");
  std::vector<float> data(32 * 11);
  ASSERT_TRUE(in->read_image(0, 0, 0, 11, OIIO::TypeDesc::FLOAT, data.data()));
  // EXR reorders channels alphabetically in the file; look them up by name.
  auto channel = [&](const std::string& name) { return channelIndex(spec, name); };
  for (int i = 0; i < 32; ++i) {
    EXPECT_FLOAT_EQ(data[i * 11 + channel("R")], image.color[i].r);
    EXPECT_FLOAT_EQ(data[i * 11 + channel("Z")], image.depth[i]);
    EXPECT_FLOAT_EQ(data[i * 11 + channel("id")], image.id[i]);
    EXPECT_FLOAT_EQ(data[i * 11 + channel("N.Z")], 1.0f);
  }
  in->close();
  std::filesystem::remove(path);
}

// The surfer integrator's colours are display values (ToneMap::None): a float file holds the
// linear values a viewer shows as the PNG's bytes, sRGB-decoded (they were written as if
// linear: 0.5 showed as 0.735, washed out), clamped to [0, 1] as the bytes are; the AOVs
// stay as they are.
TEST(ImageFile, DisplayValuesAreDecodedForFloatFiles) {
  auto path = (std::filesystem::temp_directory_path() / "algray_io_display.exr").string();
  Image image = gradient();
  image.color[0] = glm::vec3(0.5f, 1.7f, -0.2f);
  image.color[1] = glm::vec3(0.02f, 0.25f, 1.0f);
  RenderSettings settings;
  settings.toneMap = ToneMap::None;
  writeImage(image, path, settings, AovSet{});
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  std::vector<float> data(32 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, data.data()));
  in->close();
  std::filesystem::remove(path);
  const double expected[6] = {std::pow(0.555 / 1.055, 2.4), 1.0, 0.0, 0.02 / 12.92,
                              std::pow(0.305 / 1.055, 2.4), 1.0};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(data[static_cast<size_t>(i)], expected[i], 1e-6) << i;
}

// --aov depth,id writes R, G, B and just those two channels, with their values.
TEST(ImageFile, ExrWritesOnlyTheAovsAskedFor) {
  auto path = (std::filesystem::temp_directory_path() / "algray_io_subset_test.exr").string();
  Image image = gradient();
  writeImage(image, path, RenderSettings{}, parseAovList("id,depth"));
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  ASSERT_EQ(spec.nchannels, 5);
  std::vector<std::string> names(spec.channelnames.begin(), spec.channelnames.end());
  std::sort(names.begin(), names.end());
  ASSERT_EQ(names, (std::vector<std::string>{"B", "G", "R", "Z", "id"}));
  std::vector<float> data(32 * 5);
  ASSERT_TRUE(in->read_image(0, 0, 0, 5, OIIO::TypeDesc::FLOAT, data.data()));
  auto channel = [&](const std::string& name) { return channelIndex(spec, name); };
  for (int i = 0; i < 32; ++i) {
    EXPECT_FLOAT_EQ(data[i * 5 + channel("Z")], image.depth[i]);
    EXPECT_FLOAT_EQ(data[i * 5 + channel("id")], image.id[i]);
    EXPECT_FLOAT_EQ(data[i * 5 + channel("G")], image.color[i].g);
  }
  in->close();
  std::filesystem::remove(path);
}

TEST(ImageFile, AovListsAreParsedStrictly) {
  const AovSet s = parseAovList("normal,albedo");
  EXPECT_TRUE(s.normal && s.albedo && !s.depth && !s.id);
  EXPECT_TRUE(parseAovList("depth,normal,albedo,id").depth);
  for (const char* bad : {"", "depth,", ",id", "Depth", "depth,,id", "z"})
    EXPECT_THROW(parseAovList(bad), std::invalid_argument) << bad;
}

TEST(ImageFile, PngIsToneMappedSrgb) {
  auto path = (std::filesystem::temp_directory_path() / "algray_io_test.png").string();
  Image image = gradient();
  RenderSettings settings;
  settings.toneMap = ToneMap::Clamp;
  writeImage(image, path, settings);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  std::vector<unsigned char> data(32 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, data.data()));
  for (int i = 0; i < 32; ++i) {
    double expected = 255.0 * (1.055 * std::pow(0.5, 1 / 2.4) - 0.055);
    EXPECT_NEAR(data[i * 3 + 1], expected, 0.5 + 1e-9);
  }
  in->close();
  std::filesystem::remove(path);
}

// Textures and environment images stored as 8- or 16-bit integers are sRGB-encoded and
// are decoded on load (docs/scene-format.md); float files are linear as they are. Read
// back through Texture::load against the IEC 61966-2-1 decoding in double. (The reader
// judged the encoding from the float buffer it had made, so no file was ever decoded.)
TEST(ImageFile, IntegerTexturesAreDecodedFromSrgb) {
  auto decode = [](double c) {
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  const auto dir = std::filesystem::temp_directory_path();
  struct Case {
    const char* name;
    OIIO::TypeDesc type;
    std::vector<double> stored;  // the file's channel values (RGB or RGBA), in its own units
    double scale;                // their full-scale value (1 for float)
  };
  // (With alpha: the colour as stored, not multiplied by alpha, which OpenImageIO does on
  // reading by default: (128, 128, 128, 77) read as 38 and decoded to 0.019.)
  const Case cases[] = {
      {"algray_srgb_test8.png", OIIO::TypeDesc::UINT8, {128, 64, 192}, 255},
      {"algray_srgb_test16.png", OIIO::TypeDesc::UINT16, {32768, 1000, 65535}, 65535},
      {"algray_srgb_testa.png", OIIO::TypeDesc::UINT8, {128, 64, 192, 77}, 255},
      {"algray_srgb_testf.exr", OIIO::TypeDesc::FLOAT, {0.5, 0.25, 2.0}, 1}};
  for (const Case& c : cases) {
    const std::string path = (dir / c.name).string();
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out) << c.name;
    OIIO::ImageSpec spec(1, 1, static_cast<int>(c.stored.size()), c.type);
    if (c.stored.size() == 4) spec.attribute("oiio:UnassociatedAlpha", 1);
    ASSERT_TRUE(out->open(path, spec)) << c.name;
    // write_image maps float [0, 1] to the integer type's full range (the values above
    // come back exactly: rounding v / scale * scale)
    std::vector<float> pixel;
    for (double v : c.stored) pixel.push_back(static_cast<float>(v / c.scale));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixel.data())) << c.name;
    ASSERT_TRUE(out->close()) << c.name;
    const glm::dvec3 texel = Texture::load(path)->lookup({0.3, 0.7});
    for (int k = 0; k < 3; ++k) {
      const double v = c.stored[k] / c.scale;
      const double expected = c.type == OIIO::TypeDesc::FLOAT ? v : decode(v);
      EXPECT_NEAR(texel[k], expected, 1e-6 * std::max(1.0, expected)) << c.name << " " << k;
    }
    std::filesystem::remove(path);
  }
}

TEST(ImageFile, UnwritablePathThrowsWithTheName) {
  Image image = gradient();
  try {
    writeImage(image, "/nonexistent-dir/x.png", RenderSettings{});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.png"), std::string::npos);
  }
}

// The tool's files beside OUT (the temporary image, the writability probe) have names of
// their own per call, not per PID: two renders in different containers, both PID 1, wrote
// one directory's ".algray-1.tmp" and one renamed the other's image to its OUT.
TEST(ImageFile, TemporaryNamesDifferBetweenCalls) {
  const std::string a = uniqueSuffix(), b = uniqueSuffix();
  EXPECT_NE(a, b);
  EXPECT_TRUE(a.starts_with(std::to_string(getpid()) + "-")) << a;
}

// An image whose header claims more than 2^30 values is refused before its buffer is made:
// a 28-byte PGM of 100000 x 100000 ended in a bare std::bad_alloc (a 69-byte PNG of 20000 x
// 20000 took 6.4 GB and 42 s to fail). A small one of the same kind loads.
TEST(ImageFile, HeadersClaimingHugeImagesAreRefused) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "algray_huge.pgm";
  std::ofstream(path, std::ios::binary) << "P5\n100000 100000\n255\n" << std::string(6, '\x80');
  try {
    Texture::load(path.string());
    ADD_FAILURE() << "a 100000 x 100000 texture header was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("too large to read"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
  const std::filesystem::path small = std::filesystem::temp_directory_path() / "algray_small.pgm";
  std::ofstream(small, std::ios::binary) << "P5\n2 3\n255\n" << std::string(6, '\x80');
  EXPECT_NO_THROW(Texture::load(small.string()));
  std::filesystem::remove(small);
}

// The extension names the format whatever its case, and the float formats (.exr, .tif,
// .tiff) hold linear radiance as it is: no exposure (scene_desc.h: PNG only), no curve,
// with every tone map but None (whose colours are display values). .hdr (Radiance RGBE)
// stores R, G, B only, so it cannot hold the AOV channels.
TEST(ImageFile, FloatFormatsKeepLinearValuesWhateverTheCase) {
  for (const char* name : {"a.exr", "a.EXR", "a.tif", "a.tiff", "a.TIFF"})
    EXPECT_TRUE(holdsAovs(name)) << name;
  for (const char* name : {"a.hdr", "a.png", "a.PNG", "a.jpg", "a"})
    EXPECT_FALSE(holdsAovs(name)) << name;
  const Image image = gradient();
  for (const char* name : {"algray_io_case.EXR", "algray_io_float.tiff", "algray_io_float.TIF"})
    for (const ToneMap toneMap : {ToneMap::Clamp, ToneMap::Aces}) {
      const std::string path = (std::filesystem::temp_directory_path() / name).string();
      RenderSettings settings;
      settings.toneMap = toneMap;
      settings.exposure = 2.0;
      writeImage(image, path, settings);
      auto in = OIIO::ImageInput::open(path);
      ASSERT_TRUE(in) << name;
      EXPECT_EQ(in->spec().format, OIIO::TypeDesc::FLOAT) << name;
      ASSERT_EQ(in->spec().nchannels, 3) << name;
      std::vector<float> data(32 * 3);
      ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, data.data())) << name;
      in->close();
      std::filesystem::remove(path);
      for (int i = 0; i < 32; ++i)
        for (int k = 0; k < 3; ++k) ASSERT_EQ(data[3 * i + k], image.color[i][k]) << name << i;
    }
}

// A TIFF has no channel names, only an "extra sample" kind: the depth channel after R, G, B
// must not be marked as alpha (OpenImageIO's default for a 4th channel), or viewers and
// compositors take the depth for opacity.
TEST(ImageFile, TiffDepthIsNoAlpha) {
  const std::string path = (std::filesystem::temp_directory_path() / "algray_io_z.tif").string();
  const Image image = gradient();
  writeImage(image, path, RenderSettings{}, parseAovList("depth"));
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().alpha_channel, -1);
  ASSERT_EQ(in->spec().nchannels, 4);
  std::vector<float> data(32 * 4);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, data.data()));
  in->close();
  std::filesystem::remove(path);
  for (int i = 0; i < 32; ++i) EXPECT_EQ(data[4 * i + 3], image.depth[i]) << i;
}

// Each AOV component under its own name: a normal and an albedo whose components differ.
TEST(ImageFile, ExrAovComponentsKeepTheirNames) {
  const std::string path = (std::filesystem::temp_directory_path() / "algray_io_aov.exr").string();
  Image image = gradient();
  for (int i = 0; i < 32; ++i) {
    image.normal[i] = glm::vec3(0.6f, -0.8f, 0.0f);
    image.albedo[i] = glm::vec3(0.125f, 0.25f, 0.5f);
  }
  writeImage(image, path, RenderSettings{}, parseAovList("normal,albedo"));
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  ASSERT_EQ(spec.nchannels, 9);
  std::vector<float> data(32 * 9);
  ASSERT_TRUE(in->read_image(0, 0, 0, 9, OIIO::TypeDesc::FLOAT, data.data()));
  const std::pair<const char*, float> expected[] = {{"N.X", 0.6f},       {"N.Y", -0.8f},
                                                    {"N.Z", 0.0f},       {"albedo.R", 0.125f},
                                                    {"albedo.G", 0.25f}, {"albedo.B", 0.5f}};
  for (const auto& [name, value] : expected)
    for (int i = 0; i < 32; ++i)
      EXPECT_EQ(data[i * 9 + channelIndex(spec, name)], value) << name << " " << i;
  in->close();
  std::filesystem::remove(path);
}

// Every channel of a PNG in its place, with the exposure applied: the gradient's R = i / 31
// and B = 1 - i / 31 at +1 stop (twice the value), through IEC 61966-2-1's encoding
// computed here.
TEST(ImageFile, PngChannelsCarryTheExposure) {
  auto path = (std::filesystem::temp_directory_path() / "algray_io_exposure.png").string();
  const Image image = gradient();
  RenderSettings settings;
  settings.toneMap = ToneMap::Clamp;
  settings.exposure = 1.0;
  writeImage(image, path, settings);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  std::vector<unsigned char> data(32 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, data.data()));
  in->close();
  std::filesystem::remove(path);
  auto encode = [](double c) {
    c = std::min(c, 1.0);
    return 255.0 * (c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055);
  };
  for (int i = 0; i < 32; ++i) {
    EXPECT_NEAR(data[i * 3 + 0], encode(2.0 * image.color[i].r), 0.5 + 1e-9) << i;
    EXPECT_NEAR(data[i * 3 + 1], encode(2.0 * 0.5), 0.5 + 1e-9) << i;
    EXPECT_NEAR(data[i * 3 + 2], encode(2.0 * image.color[i].b), 0.5 + 1e-9) << i;
  }
}

// The PNG says its bytes are sRGB-encoded: an sRGB chunk (PNG specification, 11.3.3.5),
// which viewers read to show the colours as meant (without it, a gAMA-less PNG's encoding
// is unknown to colour-managed ones). Chunks: 4-byte big-endian length, 4-byte type, data,
// 4-byte CRC, after the 8-byte signature.
TEST(ImageFile, PngDeclaresSrgb) {
  auto path = (std::filesystem::temp_directory_path() / "algray_io_srgb.png").string();
  writeImage(gradient(), path, RenderSettings{});
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::filesystem::remove(path);
  std::vector<std::string> types;
  for (size_t i = 8; i + 8 <= bytes.size();) {
    size_t length = 0;
    for (int k = 0; k < 4; ++k) length = 256 * length + static_cast<unsigned char>(bytes[i + k]);
    types.push_back(bytes.substr(i + 4, 4));
    i += 12 + length;
  }
  EXPECT_NE(std::find(types.begin(), types.end(), "sRGB"), types.end());
  EXPECT_EQ(types.front(), "IHDR");
  EXPECT_EQ(types.back(), "IEND");
}

// OUT is a directory: the image is written to the temporary file, and rename(2) refuses
// to put a file in a directory's place (EISDIR, "Is a directory"). The message gives that
// reason, and the temporary file is removed: the directory holds what it held.
TEST(ImageFile, FailedRenameNamesTheReasonAndLeavesNoFile) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "algray_io_rename";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "out.png");
  try {
    writeImage(gradient(), (dir / "out.png").string(), RenderSettings{});
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "out.png").string() + ": cannot rename the temporary file: Is a directory");
  }
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"out.png"});
  std::filesystem::remove_all(dir);
}

// A write that fails part way (here the file size limit, RLIMIT_FSIZE, as a full disk
// would) is an error naming the file, and the partial temporary file is removed: the
// directory holds nothing after it. (write(2) past the limit fails with EFBIG once
// SIGXFSZ is ignored.) In every format: OpenImageIO's PNG writer reports such a failure
// only in has_error(), its open, write_image and close all returning true (a truncated
// PNG was renamed to OUT and the render exited 0, session 57).
TEST(ImageFile, FailedWriteLeavesNoFile) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "algray_io_full";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  Image image;
  image.resize(256, 256);
  std::uint32_t state = 1;
  for (glm::vec3& c : image.color) {
    state = state * 1664525u + 1013904223u;  // noise: a file of about 256 * 256 * 3 floats
    c = glm::vec3(static_cast<float>(state >> 8) * 0x1p-24f);
  }
  for (const char* name : {"out.exr", "out.png", "out.tif"}) {
    const std::string path = (dir / name).string();
    const auto oldHandler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit old{};
    ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
    rlimit small = old;
    small.rlim_cur = 4096;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    std::string error;
    try {
      writeImage(image, path, RenderSettings{});
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);
    EXPECT_EQ(error.rfind(path + ": cannot write image", 0), 0u) << name << ": " << error;
    EXPECT_TRUE(std::filesystem::is_empty(dir)) << name;
    // (The PNG of this noise takes ~190 kB, far past the limit: its failure is the write's.)
    if (std::string(name) == "out.png") {
      writeImage(image, path, RenderSettings{});
      EXPECT_GT(std::filesystem::file_size(path), 4096u * 8);
      std::filesystem::remove(path);
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace algray::render
