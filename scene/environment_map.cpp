#include "scene/environment_map.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "image/image_io.h"
#include "scene/input_error.h"

namespace ft {

void checkEnvironmentMap(const ImageRgbaF& map, const std::string& what) {
  if (map.height < 2 || map.width != 2 * map.height || map.pixels.size() != map.pixelCount() * 4)
    throw InputError(fmt::format("{}: {} x {} is not a lat-long map (width must be twice the height, height >= 2)",
                                 what, map.width, map.height));
  static const char* kChannel[3] = {"r", "g", "b"};
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = map.pixels[(size_t(y) * map.width + x) * 4 + c];
        if (!std::isfinite(v) || v < 0.0f)
          throw InputError(fmt::format("{}: pixel ({}, {}) {} = {}: radiance must be finite and >= 0", what, x, y,
                                       kChannel[c], v));
      }
}

ImageRgbaF readEnvironmentMap(const std::filesystem::path& path, const char* option) {
  const std::string what = fmt::format("{} {}", option, path.string());
  if (!std::filesystem::is_regular_file(path)) throw InputError(fmt::format("{}: no such file", what));
  ImageRgbaF map;
  try {
    map = readExr(path);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: not a readable OpenEXR file ({})", what, e.what()));
  }
  checkEnvironmentMap(map, what);
  return map;
}

}  // namespace ft
