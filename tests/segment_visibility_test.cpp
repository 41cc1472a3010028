// segment_visibility_test.cpp — the exemplar of 004 §2 / notes A1
// (reference/exemplar.h) and the segment visibility bake of 004 §4.1
// (bake/segment_visibility_bake.cpp): periodicity and segment statistics
// against the preset, the image convention against formulas written here,
// the bake's file equal for any shard split and its reader refusing
// malformed files. The analytic toys and CPU-vs-GPU live in the harness
// (validation/segment_visibility_cases.cpp).
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "bake/bake.h"
#include "bake/bake_runner.h"
#include "bake/segment_visibility_bake.h"
#include "common/segment_visibility.h"
#include "reference/exemplar.h"
#include "reference/segment_visibility.h"
#include "scene/input_error.h"
#include "scene/yarn_preset.h"

namespace ft {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

ExemplarSettings small() {
  ExemplarSettings s;
  s.fibersPerPly = 3;
  s.spansPerYarn = 4;
  s.subdivisions = 2;
  return s;
}

TEST(Exemplar, PlainWeaveSegmentsMatchThePresetAndTheWeave) {
  const ExemplarSettings s = small();
  const Exemplar e = makePlainWeaveExemplar(s);
  const YarnPreset& preset = findYarnPreset(s.yarn);
  // 4 yarns × plies × fibers per ply, each cut into spans × subdivisions segments.
  EXPECT_EQ(e.fibers, uint32_t(4 * preset.plyNum * s.fibersPerPly));
  EXPECT_EQ(e.segments.size(), size_t(e.fibers) * size_t(s.spansPerYarn * s.subdivisions));
  std::map<uint32_t, int> perFiber;
  for (const ExemplarSegment& g : e.segments) {
    ++perFiber[g.fiber];
    EXPECT_FLOAT_EQ(g.radius, s.fiberRadius);
    EXPECT_GT(glm::distance(g.a, g.b), 0.0f);
    // Inside the block (fibers reach ρ beyond the centre lines) and within ±(h + ρ) of z = 0.
    const glm::vec3 m = g.mid();
    EXPECT_GE(m.x, -e.reach * 1.01f);
    EXPECT_LE(m.x, e.period + e.reach * 1.01f);
    EXPECT_GE(m.y, -e.reach * 1.01f);
    EXPECT_LE(m.y, e.period + e.reach * 1.01f);
    EXPECT_LE(std::abs(m.z), (e.amplitude + e.reach) * 1.01f);
  }
  for (auto [fiber, n] : perFiber) EXPECT_EQ(n, s.spansPerYarn * s.subdivisions) << "fiber " << fiber;
  // Each fiber's segments form one polyline along its yarn: consecutive endpoints meet.
  for (size_t k = 0; k + 1 < e.segments.size(); ++k) {
    if (e.segments[k].fiber == e.segments[k + 1].fiber) {
      EXPECT_LT(glm::distance(e.segments[k].b, e.segments[k + 1].a), 1e-6f);
    }
  }
  // P = 4ρ, h = ρ with ρ = yarn radius + the ply's larger half-axis (reference/exemplar.h).
  const double rho = preset.yarnRadius + std::max(preset.ellipseLong, preset.ellipseShort) * preset.rMax;
  EXPECT_NEAR(e.period, 4.0 * rho, 1e-6);
  EXPECT_NEAR(e.amplitude, rho, 1e-6);
  // Warp fibers (x-running) follow z = ±h sin(2πx/P) within the yarn's reach.
  size_t checked = 0;
  for (const ExemplarSegment& g : e.segments) {
    const glm::vec3 d = g.b - g.a, m = g.mid();
    if (std::abs(d.x) < 4.0f * std::abs(d.y)) continue;  // not a warp fiber's segment
    const double sign = m.y < 0.5 * e.period ? 1.0 : -1.0;
    EXPECT_LE(std::abs(m.z - sign * e.amplitude * std::sin(2.0 * kPi * m.x / e.period)), 1.05 * rho);
    ++checked;
  }
  EXPECT_GT(checked, e.segments.size() / 4);
}

TEST(Exemplar, TilingIsPeriodicWithDistinctFibers) {
  const Exemplar e = makePlainWeaveExemplar(small());
  const int N = 3;
  const std::vector<ExemplarSegment> t = tileExemplar(e, N);
  const size_t S = e.segments.size();
  ASSERT_EQ(t.size(), S * N * N);
  std::set<uint32_t> fibers;
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) {
      const size_t c = size_t(j * N + i);
      const glm::vec3 off(float(i - N / 2) * e.period, float(j - N / 2) * e.period, 0.0f);
      for (size_t k = 0; k < S; ++k) {
        const ExemplarSegment& g = t[c * S + k];
        EXPECT_LT(glm::distance(g.a - off, e.segments[k].a), 1e-6f);
        EXPECT_LT(glm::distance(g.b - off, e.segments[k].b), 1e-6f);
        EXPECT_EQ(g.fiber, uint32_t(c) * e.fibers + e.segments[k].fiber);
        fibers.insert(g.fiber);
      }
    }
  EXPECT_EQ(fibers.size(), size_t(e.fibers) * N * N);
  // The centre copy is the untranslated block.
  EXPECT_EQ(t[centreCopy(N) * S].a, e.segments[0].a);
  EXPECT_THROW(tileExemplar(e, 0), InputError);
}

TEST(Exemplar, BadSettingsNameTheOption) {
  auto msg = [](ExemplarSettings s) {
    try {
      makePlainWeaveExemplar(s);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ExemplarSettings s = small();
  s.subdivisions = 0;
  EXPECT_NE(msg(s).find("--subdivisions"), std::string::npos);
  s = small();
  s.spansPerYarn = 1;
  EXPECT_NE(msg(s).find("--spans"), std::string::npos);
  s = small();
  s.fiberRadius = std::nanf("");
  EXPECT_NE(msg(s).find("--fiber-radius"), std::string::npos);
  s = small();
  s.yarn = "no-such-yarn";
  EXPECT_NE(msg(s).find("no-such-yarn"), std::string::npos);
}

// The image convention (common/segment_visibility.h) against formulas written here.
TEST(SegmentVisibility, PixelDirectionsAndSolidAnglesFollowTheConvention) {
  const int W = 16, H = 8;
  double total = 0.0, upper = 0.0;
  for (int y = 0; y < H; ++y) {
    const double omega = 2.0 * kPi / W * (std::cos(kPi * y / H) - std::cos(kPi * (y + 1) / H));
    EXPECT_NEAR(ftSvfPixelSolidAngle(y, W, H), omega, 1e-6);
    total += ftSvfPixelSolidAngle(y, W, H) * W;
    if (y < H / 2) upper += ftSvfPixelSolidAngle(y, W, H) * W;
    for (int x = 0; x < W; ++x) {
      const double t = kPi * (y + 0.5) / H, p = 2.0 * kPi * (x + 0.5) / W - kPi;
      const glm::vec3 w = ftSvfPixelDirection(x, y, W, H);
      EXPECT_NEAR(w.x, std::sin(t) * std::cos(p), 1e-6);
      EXPECT_NEAR(w.y, std::sin(t) * std::sin(p), 1e-6);
      EXPECT_NEAR(w.z, std::cos(t), 1e-6);
    }
  }
  EXPECT_NEAR(total, 4.0 * kPi, 1e-5);
  EXPECT_NEAR(upper, 2.0 * kPi, 1e-5);
}

// SSDF of a half-sphere image (visible iff z > 0): the distance to the
// nearest opposite pixel centre is, for pixel row y of the upper half, the
// angle to the first row below the equator at the same φ: θ_{H/2} − θ_y.
TEST(SegmentVisibility, SsdfOfTheUpperHemisphereIsTheRowDistance) {
  const int W = 32, H = 32;
  std::vector<uint8_t> img(size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) img[size_t(y) * W + x] = y < H / 2;
  const std::vector<float> d = svfSsdfCpu(img, W, H);
  for (int y = 0; y < H; ++y) {
    const double expected = y < H / 2 ? kPi * (H / 2 - y) / H : -kPi * (y - H / 2 + 1) / H;
    for (int x = 0; x < W; ++x) EXPECT_NEAR(d[size_t(y) * W + x], expected, 2e-6) << x << ", " << y;
  }
  // One value only: ±π.
  std::fill(img.begin(), img.end(), uint8_t(0));
  for (float v : svfSsdfCpu(img, W, H)) EXPECT_FLOAT_EQ(v, -float(kPi));
}

TEST(SegmentVisibility, PcaErrorFallsWithComponentsAndIsExactAtFullRank) {
  // 40 SSDFs of caps of different sizes about different axes (made here).
  const int W = 16, H = 16, rows = 40;
  std::vector<float> ssdf;
  for (int k = 0; k < rows; ++k) {
    std::vector<uint8_t> img(size_t(W) * H);
    const glm::vec3 axis = glm::normalize(glm::vec3(std::cos(0.7 * k), std::sin(0.7 * k), 0.5 + 0.02 * k));
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) img[size_t(y) * W + x] = glm::dot(ftSvfPixelDirection(x, y, W, H), axis) > 0.3f - 0.01f * k;
    const std::vector<float> d = svfSsdfCpu(img, W, H);
    ssdf.insert(ssdf.end(), d.begin(), d.end());
  }
  const SvfPca pca = svfPcaCpu(ssdf, rows, W * H, 48);
  ASSERT_EQ(pca.components, rows);  // clamped to the rank bound
  double last = 1e30;
  for (int use : {1, 2, 4, 8, 16, 32, 40}) {
    double e2 = 0.0;
    for (int k = 0; k < rows; ++k) {
      const std::vector<double> r = svfPcaReconstruct(pca, size_t(k), use);
      for (int p = 0; p < W * H; ++p) e2 += std::pow(r[size_t(p)] - ssdf[size_t(k) * W * H + size_t(p)], 2);
    }
    EXPECT_LE(e2, last * (1.0 + 1e-9)) << use << " components";
    last = e2;
  }
  EXPECT_LT(std::sqrt(last / (rows * W * H)), 1e-5);  // all components: exact (float input)
  for (size_t c = 1; c < pca.eigenvalues.size(); ++c) EXPECT_LE(pca.eigenvalues[c], pca.eigenvalues[c - 1]);
}

// ---- the bake ------------------------------------------------------------------
const std::vector<std::string> kBakeArgs = {"--fibers-per-ply", "2", "--spans", "4", "--subdivisions", "1", "--tiles",
                                            "3", "--width", "16", "--height", "16", "--components", "16"};

std::unique_ptr<Bake> svfBake(std::vector<std::string> args) {
  std::unique_ptr<Bake> b = makeBake("segment-visibility");
  CLI::App app;
  b->addOptions(app);
  std::reverse(args.begin(), args.end());  // CLI11 parses a reversed vector
  app.parse(args);
  b->prepare();
  return b;
}

std::string readFile(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

class SvfBakeFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / fmt::format("fibertwin-svf-{}", ::testing::UnitTest::GetInstance()->random_seed());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(SvfBakeFile, AnyShardSplitGivesTheSameFileAndTheReaderReadsIt) {
  std::ostringstream log;
  std::string first;
  for (const char* per : {"1", "7", "0"}) {
    std::vector<std::string> args = kBakeArgs;
    args.insert(args.end(), {"--segments-per-shard", per});
    const auto b = svfBake(args);
    const fs::path out = dir_ / fmt::format("svf-{}.bin", per);
    runBake(*b, {out, 2, true}, log);
    const std::string bytes = readFile(out);
    if (first.empty()) first = bytes;
    EXPECT_EQ(bytes, first) << "segments per shard " << per;
  }
  const fs::path out = dir_ / "svf-1.bin";
  const SvfFile f = readSegmentVisibilityFile(out);
  EXPECT_EQ(f.width, 16);
  EXPECT_EQ(f.axes, 48);
  EXPECT_EQ(f.components, 16);
  // Every segment: Σ_q w = the visible z > 0 solid angle of its own image (formula here).
  for (size_t k = 0; k < f.segments; ++k) {
    double visible = 0.0, wsum = 0.0;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x)
        if (f.images[k * 256 + size_t(y) * 16 + x])
          visible += 2.0 * kPi / 16 * (std::cos(kPi * y / 16) - std::cos(kPi * (y + 1) / 16));
    for (int q = 0; q < 48; ++q) wsum += f.weights[k * 48 + size_t(q)];
    EXPECT_NEAR(wsum, visible, 1e-5) << "segment " << k;
  }
  // Malformed files: truncated, a non-finite weight, a bad header field.
  auto message = [&](const std::string& bytes) {
    const fs::path bad = dir_ / "bad.bin";
    std::ofstream(bad, std::ios::binary) << bytes;
    try {
      readSegmentVisibilityFile(bad);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(first.substr(0, first.size() - 1)).find("expected exactly"), std::string::npos);
  const size_t header = first.find('\n') + 1;
  std::string nanWeight = first;
  const size_t S = f.segments;
  const float nan = std::nanf("");
  std::memcpy(&nanWeight[header + S * 32 + 4], &nan, 4);  // segment 0, weight 0
  EXPECT_NE(message(nanWeight).find("svf (weight)"), std::string::npos);
  std::string badHeader = first;
  badHeader.replace(badHeader.find("\"width\":16"), 10, "\"width\":-1");
  EXPECT_NE(message(badHeader).find("\"width\""), std::string::npos);
  EXPECT_NE(message("not json\n").find("header line is not JSON"), std::string::npos);
  // A header that claims far more data than the file holds: refused before any allocation.
  std::string huge = first;
  huge.replace(huge.find("\"segments\":"), 11, "\"segments\":67108864,\"x\":");
  EXPECT_NE(message(huge).find("expected exactly"), std::string::npos);
}

TEST(SvfBake, BadOptionsNameTheOption) {
  auto msg = [](std::vector<std::string> args) {
    try {
      svfBake(args);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(msg({"--width", "15"}).find("--width"), std::string::npos);
  EXPECT_NE(msg({"--axes", "65"}).find("--axes"), std::string::npos);
  EXPECT_NE(msg({"--lambda", "-1"}).find("--lambda"), std::string::npos);
  EXPECT_NE(msg({"--components", "0"}).find("--components"), std::string::npos);
  EXPECT_NE(msg({"--tiles", "0"}).find("--tiles"), std::string::npos);
}

}  // namespace
}  // namespace ft
