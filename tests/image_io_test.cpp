// OpenEXR output: float32 keeps every finite value (a path-traced pixel can
// exceed half's 65,504, which used to become inf with exit 0); half refuses
// such values with an error naming the file instead of writing inf.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>

#include "image/image_io.h"

namespace ft {
namespace {

namespace fs = std::filesystem;

fs::path tempExr(const char* tag) {
  return fs::temp_directory_path() / ("fibertwin-image-io-" + std::string(tag) + "-" + std::to_string(::getpid()) + ".exr");
}

ImageRgbaF bright() {
  ImageRgbaF img(3, 2);
  const float values[6] = {0.25f, 1.0f, 65504.0f, 70000.0f, 1.5e6f, 3.0e38f};
  for (int i = 0; i < 6; ++i) {
    float* p = img.at(i % 3, i / 3);
    p[0] = values[i], p[1] = 0.5f * values[i], p[2] = -values[i], p[3] = 1.0f;
  }
  return img;
}

TEST(ImageIo, FloatExrKeepsValuesBeyondTheHalfRange) {
  const fs::path path = tempExr("float");
  const ImageRgbaF img = bright();
  writeExr(path, img);  // the default is float
  const ImageRgbaF back = readExr(path);
  fs::remove(path);
  ASSERT_EQ(back.width, img.width);
  ASSERT_EQ(back.height, img.height);
  for (size_t i = 0; i < img.pixels.size(); ++i) EXPECT_EQ(back.pixels[i], img.pixels[i]) << "value " << i;
}

TEST(ImageIo, HalfExrRefusesValuesItCannotHold) {
  const fs::path path = tempExr("half");
  try {
    writeExr(path, bright(), ExrPixelType::Half);
    FAIL() << "70000 written as half without an error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find("70000"), std::string::npos) << what;
  }
  EXPECT_FALSE(fs::exists(path)) << "a file was left behind";
  // Within range it writes, and 65504 (the largest half) survives exactly.
  ImageRgbaF ok(1, 1);
  ok.at(0, 0)[0] = 65504.0f, ok.at(0, 0)[1] = -65504.0f, ok.at(0, 0)[2] = 0.5f, ok.at(0, 0)[3] = 1.0f;
  writeExr(path, ok, ExrPixelType::Half);
  const ImageRgbaF back = readExr(path);
  fs::remove(path);
  EXPECT_EQ(back.at(0, 0)[0], 65504.0f);
  EXPECT_EQ(back.at(0, 0)[1], -65504.0f);
  EXPECT_EQ(back.at(0, 0)[2], 0.5f);
}

}  // namespace
}  // namespace ft
