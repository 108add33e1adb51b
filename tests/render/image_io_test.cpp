// Image output: the display transform against its closed forms, PNG and EXR files read
// back with OpenImageIO, atomic writing (no temporary file left behind).
#include "image_io.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>

namespace algray::render {
namespace {

TEST(Display, SrgbAndClampClosedForms) {
  // sRGB: 12.92 c below 0.0031308, 1.055 c^(1/2.4) - 0.055 above (IEC 61966-2-1).
  EXPECT_NEAR(toDisplay(glm::dvec3(0.5), 0.0, ToneMap::Clamp).r, 1.055 * std::pow(0.5, 1 / 2.4) - 0.055, 1e-12);
  EXPECT_NEAR(toDisplay(glm::dvec3(0.001), 0.0, ToneMap::Clamp).g, 0.01292, 1e-12);
  EXPECT_EQ(toDisplay(glm::dvec3(7.0), 0.0, ToneMap::Clamp).b, 1.0);
  // One stop of exposure doubles the linear value.
  EXPECT_NEAR(toDisplay(glm::dvec3(0.25), 1.0, ToneMap::Clamp).r, toDisplay(glm::dvec3(0.5), 0.0, ToneMap::Clamp).r, 1e-12);
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

TEST(ImageFile, ExrKeepsLinearValuesAndAovChannels) {
  auto path = (std::filesystem::temp_directory_path() / "algray_io_test.exr").string();
  Image image = gradient();
  writeImage(image, path, RenderSettings{}, true);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  ASSERT_EQ(spec.nchannels, 11);
  EXPECT_EQ(spec.channelnames[3], "Z");
  std::vector<float> data(32 * 11);
  ASSERT_TRUE(in->read_image(0, 0, 0, 11, OIIO::TypeDesc::FLOAT, data.data()));
  // EXR reorders channels alphabetically in the file; look them up by name.
  auto channel = [&](const std::string& name) {
    for (int c = 0; c < spec.nchannels; ++c)
      if (spec.channelnames[c] == name) return c;
    return -1;
  };
  for (int i = 0; i < 32; ++i) {
    EXPECT_FLOAT_EQ(data[i * 11 + channel("R")], image.color[i].r);
    EXPECT_FLOAT_EQ(data[i * 11 + channel("Z")], image.depth[i]);
    EXPECT_FLOAT_EQ(data[i * 11 + channel("id")], image.id[i]);
    EXPECT_FLOAT_EQ(data[i * 11 + channel("N.Z")], 1.0f);
  }
  in->close();
  std::filesystem::remove(path);
}

TEST(ImageFile, PngIsToneMappedSrgb) {
  auto path = (std::filesystem::temp_directory_path() / "algray_io_test.png").string();
  Image image = gradient();
  RenderSettings settings;
  settings.toneMap = ToneMap::Clamp;
  writeImage(image, path, settings, false);
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

TEST(ImageFile, UnwritablePathThrowsWithTheName) {
  Image image = gradient();
  try {
    writeImage(image, "/nonexistent-dir/x.png", RenderSettings{}, false);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.png"), std::string::npos);
  }
}

}  // namespace
}  // namespace algray::render
