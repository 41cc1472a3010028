// bcc_reader.cpp — BCC parsing with byte-offset error messages (format: shared reference-data §1).
//
// The parser validates everything before it trusts a count: header counts are
// bounded by the file size before any allocation, every read goes through a
// bounds-checked memcpy (no aligned loads of the file image), and the model is
// only returned once the whole file has been checked.
#include "scene/bcc_reader.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "scene/input_error.h"
#include "scene/yarn_model.h"

namespace ft {
namespace {

static_assert(std::endian::native == std::endian::little, "BCC is little-endian; add byte swapping");
static_assert(sizeof(float) == 4 && std::numeric_limits<float>::is_iec559);

constexpr size_t kHeaderSize = 64;
constexpr uint8_t kByteCounts = 0x44;  // 4-byte integers, 4-byte floats
// Smallest curve record: its int32 point count. Bounding the header's curve
// count by this (not by the 28 bytes of a valid 2-point curve) lets a short
// curve reach its own check, whose message names it.
constexpr size_t kMinCurveBytes = 4;

[[noreturn]] void fail(std::string_view source, uint64_t offset, const std::string& what) {
  std::ostringstream s;
  s << source << ": byte " << offset << ": " << what;
  throw InputError(s.str());
}

// Bytes as text for messages: printable ASCII as is, others as \xNN.
std::string quoteBytes(const std::byte* p, size_t n) {
  static const char* hex = "0123456789abcdef";
  std::string out = "'";
  for (size_t i = 0; i < n; ++i) {
    auto c = static_cast<unsigned char>(p[i]);
    if (c >= 0x20 && c < 0x7f && c != '\'' && c != '\\') {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out + "'";
}

std::string hexByte(uint8_t v) {
  static const char* hex = "0123456789abcdef";
  return std::string("0x") + hex[v >> 4] + hex[v & 15];
}

std::string formatFloat(float v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

std::string formatDouble(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

std::string formatPoint(glm::vec3 p) {
  return "(" + formatFloat(p.x) + ", " + formatFloat(p.y) + ", " + formatFloat(p.z) + ")";
}

template <class T>
T load(std::span<const std::byte> bytes, size_t offset) {
  T v;
  std::memcpy(&v, bytes.data() + offset, sizeof(T));
  return v;
}

}  // namespace

YarnModel parseBcc(std::span<const std::byte> bytes, std::string_view sourceName) {
  const size_t size = bytes.size();
  if (size < kHeaderSize) {
    fail(sourceName, size, "file ends after " + std::to_string(size) + " bytes, inside the 64-byte header");
  }
  if (std::memcmp(bytes.data(), "BCC", 3) != 0) {
    fail(sourceName, 0, "bad signature " + quoteBytes(bytes.data(), 3) + " (expected 'BCC')");
  }
  const auto byteCounts = load<uint8_t>(bytes, 3);
  if (byteCounts != kByteCounts) {
    fail(
        sourceName, 3,
        "unsupported byte counts " + hexByte(byteCounts) + " (only 0x44: 4-byte integers and 4-byte floats)");
  }
  if (std::memcmp(bytes.data() + 4, "C0", 2) != 0) {
    // Other curve types exist in the format family but their codes are unconfirmed.
    fail(sourceName, 4, "unsupported curve type " + quoteBytes(bytes.data() + 4, 2));
  }
  const auto dims = load<uint8_t>(bytes, 6);
  if (dims != 3) fail(sourceName, 6, "unsupported dimension count " + std::to_string(dims) + " (only 3)");
  const auto up = load<uint8_t>(bytes, 7);
  if (up != 1 && up != 2) {
    fail(sourceName, 7, "unsupported up dimension " + std::to_string(up) + " (1 = y up, 2 = z up)");
  }
  const bool zUp = up == 2;

  const auto curveCount = load<uint64_t>(bytes, 8);
  const auto pointCount = load<uint64_t>(bytes, 16);
  const size_t body = size - kHeaderSize;
  // Bound both counts by the file size before reserving anything: they are
  // untrusted uint64 values and a hostile header must not drive allocation.
  if (curveCount == 0) fail(sourceName, 8, "curve count 0: the file holds no curves");
  if (curveCount > body / kMinCurveBytes) {
    fail(sourceName, 8,
         "curve count " + std::to_string(curveCount) + " exceeds what the " + std::to_string(body) +
             "-byte body can hold (at most " + std::to_string(body / kMinCurveBytes) +
             " curve records; file truncated, or the count is corrupt)");
  }
  const size_t pointBytes = body - 4 * curveCount;
  if (pointCount > pointBytes / 12) {
    fail(sourceName, 16,
         "point count " + std::to_string(pointCount) + " exceeds what the file can hold (at most " +
             std::to_string(pointBytes / 12) + " points next to " + std::to_string(curveCount) +
             " curve headers; file truncated, or the count is corrupt)");
  }
  // Curve and point tables index points with uint32 (common/yarn_buffers.h).
  if (pointCount > std::numeric_limits<uint32_t>::max()) {
    fail(sourceName, 16, "point count " + std::to_string(pointCount) + " exceeds the 2^32-1 supported");
  }

  YarnModel model;
  model.name = std::string(sourceName);
  model.curves.reserve(std::min<uint64_t>(curveCount, body / (4 + 2 * 12)));  // valid curves take >= 28 bytes
  uint64_t pointSum = 0;
  size_t off = kHeaderSize;
  for (uint64_t c = 0; c < curveCount; ++c) {
    const std::string curveTag = "curve " + std::to_string(c) + ": ";
    const size_t countOffset = off;
    // The header bounds above already guarantee the bytes read below; these
    // checks keep every read safe on their own should those bounds change.
    if (size - off < 4) {
      fail(sourceName, off,
           curveTag + "file truncated before its point count (" + std::to_string(curveCount) +
               " curves declared)");
    }
    const auto raw = load<int32_t>(bytes, off);
    off += 4;
    if (raw == std::numeric_limits<int32_t>::min()) {
      fail(sourceName, countOffset,
           curveTag + "point count " + std::to_string(raw) + " is not a valid length");
    }
    const bool closed = raw < 0;
    const uint32_t n = static_cast<uint32_t>(closed ? -raw : raw);
    if (!closed && n < 2) {
      fail(sourceName, countOffset,
           curveTag + "open curve with " + std::to_string(n) + " point(s) (needs at least 2)");
    }
    if (closed && n < 3) {
      fail(sourceName, countOffset,
           curveTag + "closed curve with " + std::to_string(n) + " points (count " + std::to_string(raw) +
               ", needs at least 3)");
    }
    if (pointSum + n > pointCount) {
      fail(sourceName, countOffset,
           curveTag + "point count " + std::to_string(raw) + " makes the curves' total exceed the header's " +
               std::to_string(pointCount) + " points");
    }
    pointSum += n;
    if ((size - off) / 12 < n) {
      fail(sourceName, countOffset,
           curveTag + "point count " + std::to_string(raw) + " needs " + std::to_string(uint64_t{n} * 12) +
               " bytes but only " + std::to_string(size - off) + " remain (file truncated)");
    }

    YarnCurve curve;
    curve.closed = closed;
    curve.basis = FT_BASIS_CATMULL_ROM;
    curve.points.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
      const size_t pointOffset = off + size_t{i} * 12;
      float xyz[3];
      for (int k = 0; k < 3; ++k) {
        xyz[k] = load<float>(bytes, pointOffset + 4 * k);
        if (!std::isfinite(xyz[k])) {
          fail(sourceName, pointOffset + 4 * k,
               curveTag + "point " + std::to_string(i) + ": coordinate " + "xyz"[k] + " is " +
                   formatFloat(xyz[k]) + " (non-finite)");
        }
        if (std::abs(xyz[k]) > kMaxCoordinate) {
          fail(sourceName, pointOffset + 4 * k,
               curveTag + "point " + std::to_string(i) + ": coordinate " + "xyz"[k] + " is " + formatFloat(xyz[k]) +
                   " (beyond ±1e18: too large for float32 frame arithmetic)");
        }
      }
      // z-up files are rotated to y-up: (x, y, z) -> (x, z, -y).
      const glm::vec3 p = zUp ? glm::vec3(xyz[0], xyz[2], -xyz[1]) : glm::vec3(xyz[0], xyz[1], xyz[2]);
      // A zero-length segment has no tangent, so the frames (and the fibers) are undefined there.
      if (i > 0 && p == curve.points[i - 1]) {
        fail(sourceName, pointOffset,
             curveTag + "point " + std::to_string(i) + " " + formatPoint({xyz[0], xyz[1], xyz[2]}) +
                 " coincides with point " + std::to_string(i - 1));
      }
      if (i > 0) {
        const double d = glm::distance(glm::dvec3(p), glm::dvec3(curve.points[i - 1]));
        if (d < kMinPointSpacing) {
          fail(sourceName, pointOffset,
               curveTag + "point " + std::to_string(i) + " " + formatPoint({xyz[0], xyz[1], xyz[2]}) + " is " +
                   formatDouble(d) + " from point " + std::to_string(i - 1) +
                   " (spacing below 1e-12: too small for float32 frame arithmetic)");
        }
      }
      curve.points[i] = p;
    }
    if (closed && curve.points.back() == curve.points.front()) {
      // Some real files (glove.bcc) repeat the first point at the end of a
      // closed loop; the wrap segment already closes it, so drop the copy.
      curve.points.pop_back();
      if (curve.points.size() < 3) {
        fail(sourceName, countOffset,
             curveTag + "closed curve with " + std::to_string(curve.points.size()) +
                 " distinct points after dropping its repeated closing point" + " (needs at least 3)");
      }
    }
    // No zero-length wrap segment remains: the dropped copy differed from its
    // predecessor, so the new last point differs from the first; but it may
    // lie closer than the spacing limit.
    if (closed) {
      const double d = glm::distance(glm::dvec3(curve.points.back()), glm::dvec3(curve.points.front()));
      if (d < kMinPointSpacing) {
        const size_t last = curve.points.size() - 1;
        fail(sourceName, off + last * 12,
             curveTag + "point " + std::to_string(last) + " is " + formatDouble(d) +
                 " from point 0, which closes the loop (spacing below 1e-12: too small for float32 frame arithmetic)");
      }
    }
    off += size_t{n} * 12;
    model.curves.push_back(std::move(curve));
  }
  if (pointSum != pointCount) {
    fail(sourceName, 16,
         "header point count " + std::to_string(pointCount) + " != sum of the curves' point counts " +
             std::to_string(pointSum));
  }
  if (off != size) {
    fail(sourceName, off, std::to_string(size - off) + " trailing bytes after the last curve");
  }
  return model;
}

YarnModel readBcc(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(name + ": is a directory, not a BCC file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name + ": cannot open for reading: " + std::strerror(errno));
  std::vector<std::byte> bytes;
  // Chunked reads: works for pipes too and never trusts a reported size.
  std::vector<char> chunk(1 << 16);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto got = static_cast<size_t>(in.gcount());
    const auto* p = reinterpret_cast<const std::byte*>(chunk.data());
    bytes.insert(bytes.end(), p, p + got);
  }
  if (in.bad() || !in.eof()) throw InputError(name + ": read error");
  return parseBcc(bytes, name);
}

void writeBcc(const YarnModel& model, const std::filesystem::path& path) {
  const std::string name = path.string();
  if (model.curves.empty()) throw std::invalid_argument(name + ": BCC needs at least one curve");
  uint64_t total = 0;
  for (size_t c = 0; c < model.curves.size(); ++c) {
    const YarnCurve& curve = model.curves[c];
    if (curve.basis != FT_BASIS_CATMULL_ROM) {
      throw std::invalid_argument(name + ": curve " + std::to_string(c) + " is not Catmull-Rom (BCC C0)");
    }
    if (curve.points.size() > static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
      throw std::invalid_argument(name + ": curve " + std::to_string(c) + " has too many points for BCC");
    }
    total += curve.points.size();
  }

  std::vector<std::byte> out(kHeaderSize, std::byte{0});
  auto put = [&](size_t at, const void* src, size_t n) { std::memcpy(out.data() + at, src, n); };
  put(0, "BCC", 3);
  out[3] = std::byte{kByteCounts};
  put(4, "C0", 2);
  out[6] = std::byte{3};
  out[7] = std::byte{1};  // y up: the model is y-up already
  const uint64_t curveCount = model.curves.size();
  put(8, &curveCount, 8);
  put(16, &total, 8);
  put(24, "fibertwin", 9);
  out.reserve(kHeaderSize + 4 * curveCount + 12 * total);
  for (const YarnCurve& curve : model.curves) {
    const auto n = static_cast<int32_t>(curve.points.size());
    const int32_t count = curve.closed ? -n : n;
    const size_t at = out.size();
    out.resize(at + 4 + 12 * curve.points.size());
    std::memcpy(out.data() + at, &count, 4);
    for (size_t i = 0; i < curve.points.size(); ++i) {
      const float xyz[3] = {curve.points[i].x, curve.points[i].y, curve.points[i].z};
      std::memcpy(out.data() + at + 4 + 12 * i, xyz, 12);
    }
  }

  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw InputError(name + ": cannot open for writing: " + std::strerror(errno));
  f.write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
  f.close();
  if (!f) throw InputError(name + ": write error");
}

}  // namespace ft
