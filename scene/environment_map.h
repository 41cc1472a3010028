// environment_map.h — the environment map of the shaded frame's SRBF
// lighting (001 §4.5; docs/srbf-lighting.md) and of the ground truth's
// `trace --env`: an OpenEXR lat-long map in the equirect convention of
// common/srbf.h (y up, row 0 at the top, φ = atan2(z, x)), read and checked
// once for both.
#pragma once
#include <filesystem>

#include "image/image.h"

namespace ft {

// Reads `path` (readExr) and checks it: width = 2 × height, height ≥ 2, every
// r, g, b finite and ≥ 0 (alpha ignored). InputError naming `option`, the file
// and, for a bad value, the pixel (x, y), its channel and value.
ImageRgbaF readEnvironmentMap(const std::filesystem::path& path, const char* option = "--env");
// The same checks on an image in memory (`what` names it in the message).
void checkEnvironmentMap(const ImageRgbaF& map, const std::string& what);

}  // namespace ft
