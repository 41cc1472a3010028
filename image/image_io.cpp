#include "image/image_io.h"

#include <ImfArray.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <half.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <stdexcept>

#define STB_IMAGE_WRITE_STATIC  // report.cpp has its own copy
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>



namespace ft {

float linearToSrgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

float tonemapAces(float v) {
  const float x = std::max(v, 0.0f);
  return std::clamp(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

void writeExr(const std::filesystem::path& path, const ImageRgbaF& image, ExrPixelType type) {
  if (type == ExrPixelType::Half)
    for (size_t i = 0; i < image.pixels.size(); ++i)
      if (std::isfinite(image.pixels[i]) && std::abs(image.pixels[i]) > kHalfMax)
        throw std::runtime_error(fmt::format("cannot write {} as half-float EXR: pixel ({}, {}) channel {} is {:g}, "
                                             "beyond the half range ±{:g}",
                                             path.string(), (i / 4) % image.width, (i / 4) / image.width, i % 4,
                                             image.pixels[i], kHalfMax));
  try {
    Imf::Header header(image.width, image.height);
    const Imf::PixelType pt = type == ExrPixelType::Half ? Imf::HALF : Imf::FLOAT;
    const char* names[4] = {"R", "G", "B", "A"};
    for (const char* n : names) header.channels().insert(n, Imf::Channel(pt));
    Imf::OutputFile file(path.string().c_str(), header);
    Imf::FrameBuffer fb;
    const size_t n = image.pixelCount();
    std::vector<half> halves;
    if (type == ExrPixelType::Half) {
      halves.resize(n * 4);
      for (size_t i = 0; i < n * 4; ++i) halves[i] = half(image.pixels[i]);
      for (int c = 0; c < 4; ++c)
        fb.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.data() + c), 4 * sizeof(half),
                                       4 * sizeof(half) * image.width));
    } else {
      for (int c = 0; c < 4; ++c)
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(image.pixels.data() + c)),
                                       4 * sizeof(float), 4 * sizeof(float) * image.width));
    }
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot write " + path.string() + ": " + e.what());
  }
}

ImageRgbaF readExr(const std::filesystem::path& path) {
  try {
    Imf::InputFile file(path.string().c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    ImageRgbaF img(w, h);
    Imf::FrameBuffer fb;
    const char* names[4] = {"R", "G", "B", "A"};
    char* base = reinterpret_cast<char*>(img.pixels.data()) -
                 (static_cast<ptrdiff_t>(dw.min.x) + static_cast<ptrdiff_t>(dw.min.y) * w) * 4 * sizeof(float);
    for (int c = 0; c < 4; ++c)
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), 4 * sizeof(float), 4 * sizeof(float) * w,
                                     1, 1, c == 3 ? 1.0 : 0.0));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return img;
  } catch (const std::exception& e) {
    throw std::invalid_argument(path.string() + ": not a readable OpenEXR file (" + e.what() + ")");
  }
}

std::vector<uint8_t> tonemapToRgba8(const ImageRgbaF& image, const DisplayMapping& mapping) {
  const float scale = std::exp2(mapping.exposure);
  std::vector<uint8_t> bytes(image.pixelCount() * 4);
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    const float* p = image.pixels.data() + i * 4;
    const bool finite = std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
    for (int c = 0; c < 3; ++c) {
      float v = finite ? p[c] * scale : (c == 1 ? 0.0f : 1.0f);
      if (finite) v = mapping.tone == ToneMap::Aces ? tonemapAces(v) : std::clamp(v, 0.0f, 1.0f);
      bytes[i * 4 + c] = static_cast<uint8_t>(std::lround(255.0f * linearToSrgb(v)));
    }
    bytes[i * 4 + 3] = 255;
  }
  return bytes;
}

void writePngTonemapped(const std::filesystem::path& path, const ImageRgbaF& image, const DisplayMapping& mapping) {
  const std::vector<uint8_t> bytes = tonemapToRgba8(image, mapping);
  if (!stbi_write_png(path.string().c_str(), image.width, image.height, 4, bytes.data(), image.width * 4))
    throw std::runtime_error("cannot write " + path.string());
}

void writePngRgba8(const std::filesystem::path& path, int width, int height, std::span<const uint8_t> rgba) {
  if (width <= 0 || height <= 0 || rgba.size() != static_cast<size_t>(width) * height * 4)
    throw std::invalid_argument(
        fmt::format("{}: {} bytes for a {}x{} RGBA image", path.string(), rgba.size(), width, height));
  if (!stbi_write_png(path.string().c_str(), width, height, 4, rgba.data(), width * 4))
    throw std::runtime_error("cannot write " + path.string());
}

ImageRgbaF readPng(const std::filesystem::path& path) {
  int w = 0, h = 0, channels = 0;
  uint8_t* data = stbi_load(path.string().c_str(), &w, &h, &channels, 4);
  if (!data) throw std::invalid_argument(path.string() + ": not a readable PNG file (" + stbi_failure_reason() + ")");
  ImageRgbaF img(w, h);
  for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = data[i] / 255.0f;
  stbi_image_free(data);
  return img;
}

}  // namespace ft
