// bcc_reader_test.cpp — BCC parsing: every malformed case is built from a small
// valid in-memory file and must throw InputError naming the source and the byte.
#include "scene/bcc_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "scene/input_error.h"
#include "tests/test_data.h"

namespace fs = std::filesystem;
using ft::InputError;
using ft::parseBcc;
using ft::YarnModel;

namespace {

constexpr const char* kSource = "mem.bcc";

struct RawCurve {
  int32_t count;              // as written: negative = closed
  std::vector<float> coords;  // 3 per point, written as is
};

// Assembles header + body bytes; every field can be overridden to break it.
struct BccBuilder {
  std::string signature = "BCC";
  uint8_t byteCounts = 0x44;
  std::string curveType = "C0";
  uint8_t dims = 3;
  uint8_t up = 1;
  std::optional<uint64_t> curveCount;  // default: curves.size()
  std::optional<uint64_t> pointCount;  // default: sum of |count|
  std::vector<RawCurve> curves;

  std::vector<std::byte> bytes() const {
    std::vector<std::byte> out(64, std::byte{0});
    std::memcpy(out.data(), signature.data(), 3);
    out[3] = std::byte{byteCounts};
    std::memcpy(out.data() + 4, curveType.data(), 2);
    out[6] = std::byte{dims};
    out[7] = std::byte{up};
    uint64_t total = 0;
    for (const auto& c : curves) total += c.coords.size() / 3;
    const uint64_t cc = curveCount.value_or(curves.size());
    const uint64_t pc = pointCount.value_or(total);
    std::memcpy(out.data() + 8, &cc, 8);
    std::memcpy(out.data() + 16, &pc, 8);
    std::memcpy(out.data() + 24, "test", 4);
    for (const auto& c : curves) {
      append(out, &c.count, 4);
      append(out, c.coords.data(), 4 * c.coords.size());
    }
    return out;
  }
  static void append(std::vector<std::byte>& out, const void* p, size_t n) {
    const auto* b = static_cast<const std::byte*>(p);
    out.insert(out.end(), b, b + n);
  }
};

// Valid base file: curve 0 open (3 points), curve 1 closed (4 points).
// Offsets: curve 0 count @64, points @68; curve 1 count @104, points @108; end @156.
BccBuilder baseFile() {
  BccBuilder b;
  b.curves.push_back({3, {0, 0, 0, 1, 0, 0, 2, 1, 0}});
  b.curves.push_back({-4, {0, 0, 5, 1, 0, 5, 1, 1, 5, 0, 1, 5}});
  return b;
}

// Expects InputError "<kSource>: byte <offset>: ..." whose text contains `key`.
void expectError(const std::vector<std::byte>& bytes, uint64_t offset, const std::string& key) {
  const std::string prefix = std::string(kSource) + ": byte " + std::to_string(offset) + ": ";
  try {
    parseBcc(bytes, kSource);
    ADD_FAILURE() << "no InputError; expected '" << prefix << "..." << key << "'";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "message: " << msg << "\nexpected prefix: " << prefix;
    EXPECT_NE(msg.find(key), std::string::npos) << "message: " << msg << "\nexpected key: " << key;
  }
}

void setFloat(std::vector<std::byte>& bytes, size_t offset, float v) { std::memcpy(&bytes[offset], &v, 4); }

fs::path tempPath(const std::string& stem) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return fs::temp_directory_path() / (stem + "-" + info->name() + "-" + std::to_string(::getpid()) + ".bcc");
}

std::vector<std::byte> readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::vector<char> c((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> out(c.size());
  std::memcpy(out.data(), c.data(), c.size());
  return out;
}

}  // namespace

TEST(BccReader, ParsesValidFile) {
  const YarnModel m = parseBcc(baseFile().bytes(), kSource);
  EXPECT_EQ(m.name, kSource);
  ASSERT_EQ(m.curves.size(), 2u);
  EXPECT_FALSE(m.curves[0].closed);
  EXPECT_TRUE(m.curves[1].closed);
  ASSERT_EQ(m.curves[0].points.size(), 3u);
  ASSERT_EQ(m.curves[1].points.size(), 4u);
  EXPECT_EQ(m.curves[0].points[2], glm::vec3(2, 1, 0));
  EXPECT_EQ(m.curves[1].points[3], glm::vec3(0, 1, 5));
  EXPECT_EQ(m.curves[0].basis, FT_BASIS_CATMULL_ROM);
}

TEST(BccReader, ConvertsZUpToYUp) {
  BccBuilder b = baseFile();
  b.up = 2;
  const YarnModel m = parseBcc(b.bytes(), kSource);
  // (x, y, z)_zup -> (x, z, -y): the file's point (2, 1, 0) becomes (2, 0, -1).
  EXPECT_EQ(m.curves[0].points[2], glm::vec3(2, 0, -1));
  EXPECT_EQ(m.curves[1].points[2], glm::vec3(1, 5, -1));
}

TEST(BccReader, HeaderErrors) {
  const auto good = baseFile().bytes();
  expectError({}, 0, "header");
  expectError(std::vector<std::byte>(good.begin(), good.begin() + 10), 10, "header");
  expectError(std::vector<std::byte>(good.begin(), good.begin() + 63), 63, "header");

  BccBuilder b = baseFile();
  b.signature = "BCD";
  expectError(b.bytes(), 0, "signature 'BCD'");
  b = baseFile();
  b.signature = std::string("\x01\xff", 2) + "C";
  expectError(b.bytes(), 0, "'\\x01\\xffC'");
  b = baseFile();
  b.byteCounts = 0x48;
  expectError(b.bytes(), 3, "byte counts 0x48");
  b = baseFile();
  b.curveType = "C1";
  expectError(b.bytes(), 4, "unsupported curve type 'C1'");
  b.curveType = "B0";
  expectError(b.bytes(), 4, "unsupported curve type 'B0'");
  b = baseFile();
  b.dims = 2;
  expectError(b.bytes(), 6, "dimension count 2");
  b = baseFile();
  b.up = 0;
  expectError(b.bytes(), 7, "up dimension 0");
  b.up = 3;
  expectError(b.bytes(), 7, "up dimension 3");
}

TEST(BccReader, CountsBoundedByFileSizeBeforeAllocation) {
  BccBuilder b = baseFile();
  b.curveCount = std::numeric_limits<uint64_t>::max();
  expectError(b.bytes(), 8, "curve count 18446744073709551615");
  b.curveCount = 1ull << 40;
  expectError(b.bytes(), 8, "curve count");
  b.curveCount = 0;
  expectError(b.bytes(), 8, "curve count 0");
  b = baseFile();
  b.pointCount = std::numeric_limits<uint64_t>::max();
  expectError(b.bytes(), 16, "point count 18446744073709551615");
  b.pointCount = 8;  // 7 points in the file, no room for an 8th
  expectError(b.bytes(), 16, "point count 8");
}

TEST(BccReader, BodyErrors) {
  const auto good = baseFile().bytes();
  ASSERT_EQ(good.size(), 156u);
  // Truncated inside curve 1's points: the header's point count no longer fits.
  expectError(std::vector<std::byte>(good.begin(), good.end() - 5), 16, "point count 7 exceeds");
  expectError(std::vector<std::byte>(good.begin(), good.end() - 5), 16, "truncated");
  // Trailing bytes after the last curve.
  auto trailing = good;
  trailing.resize(trailing.size() + 3);
  expectError(trailing, 156, "3 trailing bytes");

  // Truncated before a curve's point count: 2 curves declared, 1 present.
  BccBuilder b;
  b.curves.push_back({10, {}});
  for (int i = 0; i < 10; ++i) b.curves[0].coords.insert(b.curves[0].coords.end(), {float(i), 0, 0});
  b.curveCount = 2;
  expectError(b.bytes(), 16, "truncated");
  // A curve whose count runs past the end while the header fits: it claims the
  // next curve's points, so the header total is exceeded at that curve.
  b = baseFile();
  b.curves[0].count = 8;
  expectError(b.bytes(), 64, "exceed the header's 7 points");

  // Header total smaller than the curves' sum: caught at the curve that overflows it.
  b = baseFile();
  b.pointCount = 6;
  expectError(b.bytes(), 104, "header's 6 points");
  // Header total larger than the sum (room for it provided by trailing bytes).
  b.pointCount = 8;
  auto bytes = b.bytes();
  bytes.resize(bytes.size() + 12);
  expectError(bytes, 16, "header point count 8 != sum of the curves' point counts 7");
}

TEST(BccReader, CurveErrors) {
  BccBuilder b = baseFile();
  b.curves[0] = {1, {0, 0, 0}};
  expectError(b.bytes(), 64, "open curve with 1 point");
  b.curves[0] = {0, {}};
  expectError(b.bytes(), 64, "open curve with 0 point");
  b = baseFile();
  b.curves[1] = {-2, {0, 0, 5, 1, 0, 5}};
  expectError(b.bytes(), 104, "closed curve with 2 points");
  b = baseFile();
  b.curves[1].count = std::numeric_limits<int32_t>::min();
  expectError(b.bytes(), 104, "-2147483648");
  b = baseFile();
  b.curves[0].count = std::numeric_limits<int32_t>::max();
  expectError(b.bytes(), 64, "2147483647");
}

TEST(BccReader, NonFiniteCoordinates) {
  auto bytes = baseFile().bytes();
  // Curve 1, point 2, y coordinate: 108 + 2*12 + 4.
  setFloat(bytes, 136, std::numeric_limits<float>::quiet_NaN());
  expectError(bytes, 136, "coordinate y is nan");
  bytes = baseFile().bytes();
  setFloat(bytes, 68, std::numeric_limits<float>::infinity());
  expectError(bytes, 68, "coordinate x is inf");
  bytes = baseFile().bytes();
  setFloat(bytes, 76, -std::numeric_limits<float>::infinity());
  expectError(bytes, 76, "coordinate z is -inf");
}

TEST(BccReader, CoincidentPoints) {
  BccBuilder b = baseFile();
  b.curves[0].coords = {0, 0, 0, 1, 0, 0, 1, 0, 0};
  expectError(b.bytes(), 68 + 24, "point 2 (1, 0, 0) coincides with point 1");
  b = baseFile();
  b.curves[1].coords = {0, 0, 5, 0, 0, 5, 1, 1, 5, 0, 1, 5};
  expectError(b.bytes(), 108 + 12, "coincides with point 0");
  // -0 and +0 are the same position.
  b = baseFile();
  b.curves[0].coords = {0, 0, 0, -0.0f, 0, 0, 1, 0, 0};
  expectError(b.bytes(), 68 + 12, "coincides");
}

// A closed loop that repeats its first point at the end (as 8 curves of
// glove.bcc do) loses the copy: the wrap segment closes it already.
TEST(BccReader, ClosedCurveRepeatedClosingPointIsDropped) {
  BccBuilder b = baseFile();
  b.curves[1] = {-5, {0, 0, 5, 1, 0, 5, 1, 1, 5, 0, 1, 5, 0, 0, 5}};
  const YarnModel m = parseBcc(b.bytes(), kSource);
  ASSERT_EQ(m.curves[1].points.size(), 4u);
  EXPECT_TRUE(m.curves[1].closed);
  EXPECT_NE(m.curves[1].points.back(), m.curves[1].points.front());
  // Too few distinct points once the copy is gone.
  b.curves[1] = {-3, {0, 0, 5, 1, 0, 5, 0, 0, 5}};
  expectError(b.bytes(), 104, "closed curve with 2 distinct points");
  // On an open curve first == last is a legitimate (if odd) shape and stays.
  b = baseFile();
  b.curves[0] = {3, {0, 0, 0, 1, 0, 0, 0, 0, 0}};
  EXPECT_EQ(parseBcc(b.bytes(), kSource).curves[0].points.size(), 3u);
}

// Every proper prefix of a valid file is an error, never a crash or a model.
TEST(BccReader, EveryTruncationThrows) {
  const auto good = baseFile().bytes();
  for (size_t n = 0; n < good.size(); ++n) {
    EXPECT_THROW(parseBcc(std::span(good.data(), n), kSource), InputError) << "prefix " << n;
  }
}

// Single-byte corruption anywhere either parses or throws InputError.
TEST(BccReader, SingleByteMutationsStayContained) {
  const auto good = baseFile().bytes();
  for (size_t i = 0; i < good.size(); ++i) {
    for (int v : {0x00, 0x01, 0x7f, 0x80, 0xfe, 0xff}) {
      auto bytes = good;
      bytes[i] = static_cast<std::byte>(v);
      try {
        parseBcc(bytes, kSource);
      } catch (const InputError&) {
      }
    }
  }
}

TEST(BccReader, WriteReadRoundTrip) {
  YarnModel m;
  m.curves.resize(2);
  m.curves[0].points = {{0.5f, -1.25f, 3.0f}, {1e-7f, 2.0f, -0.0f}, {1e7f, 3.0f, 4.0f}};
  m.curves[1].closed = true;
  m.curves[1].points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const fs::path path = tempPath("roundtrip");
  ft::writeBcc(m, path);
  const auto bytes = readAll(path);
  ASSERT_EQ(bytes.size(), 64u + 2 * 4 + 7 * 12);
  EXPECT_EQ(std::memcmp(bytes.data(),
                        "BCC\x44"
                        "C0\x03\x01",
                        8),
            0);
  EXPECT_EQ(std::memcmp(bytes.data() + 24, "fibertwin", 9), 0);
  const YarnModel r = ft::readBcc(path);
  fs::remove(path);
  EXPECT_EQ(r.name, path.string());
  ASSERT_EQ(r.curves.size(), 2u);
  for (size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(r.curves[c].closed, m.curves[c].closed);
    ASSERT_EQ(r.curves[c].points.size(), m.curves[c].points.size());
    for (size_t i = 0; i < r.curves[c].points.size(); ++i) {
      EXPECT_EQ(std::memcmp(&r.curves[c].points[i], &m.curves[c].points[i], sizeof(glm::vec3)), 0)
          << "curve " << c << " point " << i;
    }
  }
}

TEST(BccReader, WriteRejectsUnrepresentableModels) {
  const fs::path path = tempPath("reject");
  EXPECT_THROW(ft::writeBcc(YarnModel{}, path), std::invalid_argument);
  YarnModel m;
  m.curves.resize(1);
  m.curves[0].points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  m.curves[0].basis = FT_BASIS_BEZIER;
  EXPECT_THROW(ft::writeBcc(m, path), std::invalid_argument);
  EXPECT_FALSE(fs::exists(path));
}

TEST(BccReader, ReadErrorsNameThePath) {
  const fs::path missing = fs::temp_directory_path() / "fibertwin-no-such-file.bcc";
  try {
    ft::readBcc(missing);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_THROW(ft::readBcc(fs::temp_directory_path()), InputError);
  // Parse errors from readBcc are named after the path too.
  const fs::path bad = tempPath("bad");
  { std::ofstream(bad, std::ios::binary) << "BCC"; }
  try {
    ft::readBcc(bad);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(bad.string() + ": byte 3: ", 0), 0u) << e.what();
  }
  fs::remove(bad);
}

namespace {
uint64_t headerU64(const fs::path& p, size_t offset) {
  const auto bytes = readAll(p);
  uint64_t v = 0;
  std::memcpy(&v, bytes.data() + offset, 8);
  return v;
}

size_t totalPoints(const YarnModel& m) {
  size_t n = 0;
  for (const auto& c : m.curves) n += c.points.size();
  return n;
}
}  // namespace

TEST(BccReaderRealFiles, Fiber) {
  const fs::path p = ft::test::yarnModel("fiber.bcc");
  const YarnModel m = ft::readBcc(p);
  ASSERT_EQ(m.curves.size(), 1u);
  EXPECT_FALSE(m.curves[0].closed);
  EXPECT_EQ(m.curves[0].points.size(), 19730u);
  // z-up file: the first point must land at (x, z, -y).
  const auto bytes = readAll(p);
  float xyz[3];
  std::memcpy(xyz, bytes.data() + 68, 12);
  EXPECT_EQ(m.curves[0].points[0], glm::vec3(xyz[0], xyz[2], -xyz[1]));
}

TEST(BccReaderRealFiles, Glove) {
  const fs::path p = ft::test::yarnModel("glove.bcc");
  EXPECT_EQ(headerU64(p, 8), 70u);
  EXPECT_EQ(headerU64(p, 16), 58545u);
  const YarnModel m = ft::readBcc(p);
  ASSERT_EQ(m.curves.size(), 70u);
  size_t shortest = SIZE_MAX, longest = 0;
  for (const auto& c : m.curves) {
    EXPECT_TRUE(c.closed);
    shortest = std::min(shortest, c.points.size());
    longest = std::max(longest, c.points.size());
  }
  // 8 loops repeat their first point at the end; the reader drops those copies.
  EXPECT_EQ(totalPoints(m), 58545u - 8u);
  EXPECT_GE(shortest, 298u);
  EXPECT_LE(longest, 1226u);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& c : m.curves) {
    for (const auto& q : c.points) {
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
  }
  const glm::vec3 ext = hi - lo;  // about 28 x 35 x 26 (reference-data §1)
  EXPECT_NEAR(ext.x, 28.0f, 3.0f);
  EXPECT_NEAR(ext.y, 35.0f, 3.0f);
  EXPECT_NEAR(ext.z, 26.0f, 3.0f);
}

// Seed corpus of the fuzzer (scripts/make_bcc_corpus.py): each file parses or
// throws InputError, nothing else.
TEST(BccReader, FuzzCorpusReplay) {
  const char* src = std::getenv("FT_SOURCE_DIR");
  const fs::path dir = fs::path(src ? src : ".") / "tests" / "fuzz_corpus" / "bcc";
  ASSERT_TRUE(fs::is_directory(dir)) << dir;
  size_t files = 0, parsed = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    ++files;
    const auto bytes = readAll(entry.path());
    try {
      parseBcc(bytes, entry.path().filename().string());
      ++parsed;
    } catch (const InputError&) {
    }
  }
  EXPECT_GE(files, 5u);
  EXPECT_GE(parsed, 1u);
}
