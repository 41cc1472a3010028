// environment_map_test.cpp — `--env FILE` refuses bad maps with a message that
// names the file and, for a bad value, the pixel (scene/environment_map.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include "image/image_io.h"
#include "scene/environment_map.h"
#include "scene/input_error.h"
#include "scene/shading_inputs.h"

namespace ft {
namespace {

std::filesystem::path tempMap(const std::string& name, const ImageRgbaF& img) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() / ("ft_env_" + name + ".exr");
  writeExr(p, img, ExrPixelType::Float);
  return p;
}
ImageRgbaF grey(int w, int h) {
  ImageRgbaF m(w, h);
  for (float& v : m.pixels) v = 0.5f;
  return m;
}
// The InputError's message, or "" when none was thrown.
std::string refusal(const std::filesystem::path& p) {
  try {
    readEnvironmentMap(p);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(EnvironmentMap, AGoodMapIsRead) {
  const std::filesystem::path p = tempMap("good", grey(16, 8));
  const ImageRgbaF m = readEnvironmentMap(p);
  EXPECT_EQ(m.width, 16);
  EXPECT_EQ(m.height, 8);
  std::filesystem::remove(p);
}

TEST(EnvironmentMap, BadMapsAreRefusedNamingFileAndPixel) {
  const std::string missing = refusal("/nonexistent/sky.exr");
  EXPECT_NE(missing.find("/nonexistent/sky.exr"), std::string::npos) << missing;
  EXPECT_NE(missing.find("--env"), std::string::npos) << missing;

  ImageRgbaF neg = grey(16, 8);
  neg.at(3, 2)[1] = -1.0f;
  const std::filesystem::path pn = tempMap("negative", neg);
  const std::string n = refusal(pn);
  EXPECT_NE(n.find(pn.string()), std::string::npos) << n;
  EXPECT_NE(n.find("pixel (3, 2) g = -1"), std::string::npos) << n;

  ImageRgbaF inf = grey(16, 8);
  inf.at(15, 7)[2] = std::numeric_limits<float>::infinity();
  const std::filesystem::path pi = tempMap("inf", inf);
  EXPECT_NE(refusal(pi).find("pixel (15, 7) b = inf"), std::string::npos) << refusal(pi);

  ImageRgbaF nan = grey(16, 8);
  nan.at(0, 0)[0] = std::nanf("");
  const std::filesystem::path pq = tempMap("nan", nan);
  EXPECT_NE(refusal(pq).find("pixel (0, 0) r = nan"), std::string::npos) << refusal(pq);

  const std::filesystem::path pa = tempMap("aspect", grey(16, 16));
  const std::string a = refusal(pa);
  EXPECT_NE(a.find("16 x 16"), std::string::npos) << a;
  EXPECT_NE(a.find("twice the height"), std::string::npos) << a;

  const std::filesystem::path pt = std::filesystem::temp_directory_path() / "ft_env_text.exr";
  { std::FILE* f = std::fopen(pt.c_str(), "w"); std::fputs("not an exr", f); std::fclose(f); }
  EXPECT_NE(refusal(pt).find("not a readable OpenEXR file"), std::string::npos) << refusal(pt);
  for (const auto& p : {pn, pi, pq, pa, pt}) std::filesystem::remove(p);
}

TEST(EnvironmentMap, TableSizesOutsideTheirRangeAreRefused) {
  AppearanceOptions o;
  o.environmentImage = std::make_shared<ImageRgbaF>(grey(16, 8));
  o.environmentTableDims = glm::ivec4(16, 1, 8, 8);
  EXPECT_THROW(frameEnvironmentMap(o), InputError);
  o.environmentTableDims = glm::ivec4(16, 16, 8, 65);
  EXPECT_THROW(frameEnvironmentMap(o), InputError);
  o.environmentTableDims = glm::ivec4(2, 2, 2, 2);
  EXPECT_TRUE(frameEnvironmentMap(o).has_value());
  EXPECT_FALSE(frameEnvironmentMap(AppearanceOptions{}).has_value());
}

}  // namespace
}  // namespace ft
