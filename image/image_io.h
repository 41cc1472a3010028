// image_io.h — float images to and from files: OpenEXR (linear, half or
// float), PNG (8-bit sRGB, tone-mapped from linear). Errors name the file.
#pragma once
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "image/image.h"

namespace ft {

enum class ExrPixelType { Half, Float };

// Linear RGBA as written (no tone mapping). Float by default: half tops out
// at 65,504 and would turn brighter values into inf without a word. Half is
// refused (std::runtime_error naming the file and the value) when a finite
// value would not fit.
void writeExr(const std::filesystem::path& path, const ImageRgbaF& image, ExrPixelType type = ExrPixelType::Float);
// The largest finite half: values beyond it overflow a Half EXR.
inline constexpr float kHalfMax = 65504.0f;
// R, G, B (A = 1 when the file has none); std::invalid_argument naming the
// file when it cannot be read (the CLI reports it as bad input).
ImageRgbaF readExr(const std::filesystem::path& path);

// Display mapping for PNG: linear rgb × 2^exposure, then the tone curve, then
// sRGB encoding; alpha composites over nothing (written as the PNG's alpha
// only if `keepAlpha`, else opaque). Non-finite values are written as magenta
// so they cannot pass unseen (the render refuses them before this point).
enum class ToneMap { Clamp, Aces };
struct DisplayMapping {
  float exposure = 0.0f;  // stops
  ToneMap tone = ToneMap::Aces;
};
// The same mapping into RGBA8 bytes (alpha 255), row 0 at the top.
std::vector<uint8_t> tonemapToRgba8(const ImageRgbaF& image, const DisplayMapping& mapping = {});
void writePngTonemapped(const std::filesystem::path& path, const ImageRgbaF& image, const DisplayMapping& mapping = {});
// 8-bit RGBA bytes as given (4 per pixel, row 0 at the top): false-colour maps.
void writePngRgba8(const std::filesystem::path& path, int width, int height, std::span<const uint8_t> rgba);
// 8-bit RGBA → display-referred values in [0, 1] (no sRGB decoding; FLIP decodes itself).
ImageRgbaF readPng(const std::filesystem::path& path);

// sRGB transfer of one linear value in [0, 1].
float linearToSrgb(float v);
float srgbToLinear(float v);
// The ACES filmic fit (Narkowicz 2016) of one channel, clamped to [0, 1].
float tonemapAces(float v);

}  // namespace ft
