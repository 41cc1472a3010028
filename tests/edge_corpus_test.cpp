// The geometric edge-case corpus (tests/edge_corpus.h) on the CPU side: the
// committed files match the generator, the reader refuses what float32 cannot
// carry (naming curve, point and value), and the frames are defined at every
// knot — exact back-tracks included — with properties checked against the
// geometry, not against the implementation. The GPU paths run the same files
// through `fibertwin validate` (tests/CMakeLists.txt: validate_edge_corpus…).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

#include "common/yarn_frame.h"
#include "reference/fiber_reference.h"
#include "scene/bcc_reader.h"
#include "scene/input_error.h"
#include "tests/edge_corpus.h"

namespace ft {
namespace {

namespace fs = std::filesystem;

fs::path sourceDir() {
  const char* src = std::getenv("FT_SOURCE_DIR");
  return src ? fs::path(src) : fs::path(".");
}

std::string fileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct CorpusFile {
  const char* path;  // relative to the repository root
  YarnModel (*make)();
};

const CorpusFile kFiles[] = {
    {"tests/edge_corpus/edges.bcc", test::edgeCorpus},
    {"tests/edge_corpus/long-segments.bcc", test::longSegments},
    {"tests/edge_corpus/helix-cusp.bcc", test::helixCusp},
    {"tests/fuzz_corpus/bcc/bad-huge-coordinate.bcc", test::hugeCoordinate},
    {"tests/fuzz_corpus/bcc/bad-tiny-spacing.bcc", test::tinySpacing},
    {"tests/fuzz_corpus/bcc/bad-one-point-curve.bcc", test::onePointCurve},
};

TEST(EdgeCorpus, CommittedFilesMatchTheGenerator) {
  const bool rewrite = std::getenv("FT_WRITE_EDGE_CORPUS") != nullptr;
  for (const CorpusFile& f : kFiles) {
    const fs::path committed = sourceDir() / f.path;
    if (rewrite) {
      fs::create_directories(committed.parent_path());
      writeBcc(f.make(), committed);
      continue;
    }
    const fs::path fresh = fs::temp_directory_path() / ("edge-corpus-" + std::to_string(::getpid()) + ".bcc");
    writeBcc(f.make(), fresh);
    ASSERT_TRUE(fs::exists(committed)) << committed << " missing (FT_WRITE_EDGE_CORPUS=1 writes it)";
    EXPECT_EQ(fileBytes(committed), fileBytes(fresh)) << committed << " differs from tests/edge_corpus.h";
    fs::remove(fresh);
  }
}

// The reader names the file, curve, point and value of what it refuses.
void expectRefused(const YarnModel& m, const std::vector<std::string>& parts) {
  const fs::path p = fs::temp_directory_path() / (m.name + "-" + std::to_string(::getpid()) + ".bcc");
  writeBcc(m, p);
  try {
    readBcc(p);
    ADD_FAILURE() << m.name << " was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(p.string()), std::string::npos) << what;
    for (const std::string& s : parts) EXPECT_NE(what.find(s), std::string::npos) << "missing '" << s << "': " << what;
  }
  fs::remove(p);
}

TEST(EdgeCorpus, ReaderRefusesWhatFloat32CannotCarry) {
  expectRefused(test::hugeCoordinate(), {"curve 1", "point 2", "coordinate x", "e+30", "1e18"});
  expectRefused(test::tinySpacing(), {"curve 0", "point 1", "1e-30", "from point 0", "1e-12"});
  expectRefused(test::onePointCurve(), {"curve 1", "1 point"});
  // The in-memory path (knit output, built-in scenes) applies the same limits.
  EXPECT_THROW(buildYarnBuffers(test::hugeCoordinate()), InputError);
  EXPECT_THROW(buildYarnBuffers(test::tinySpacing()), InputError);
  // Just inside the limits is accepted.
  YarnModel edge = test::tinySpacing();
  edge.curves[0].points = {{0, 0, 0}, {2e-12f, 0, 0}, {1, 0, 0}};
  EXPECT_NO_THROW(buildYarnBuffers(edge));
  edge.curves[0].points = {{-1e18f, 0, 0}, {0, 0, 0}, {1e18f, 0, 0}};
  EXPECT_NO_THROW(buildYarnBuffers(edge));
}

// Back-tracks counted from the points alone: p[i+1] == p[i-1] (wrapping on
// closed curves, end points reflected on open ones, which never back-track).
size_t countBackTracks(const YarnModel& m) {
  size_t n = 0;
  for (const YarnCurve& c : m.curves) {
    const size_t k = c.points.size();
    for (size_t i = 0; i < k; ++i) {
      if (!c.closed && (i == 0 || i + 1 == k)) continue;
      if (c.points[(i + 1) % k] == c.points[(i + k - 1) % k]) ++n;
    }
  }
  return n;
}

bool finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

TEST(EdgeCorpus, FramesAreDefinedAtEveryKnot) {
  for (YarnModel (*make)() : {test::edgeCorpus, test::longSegments}) {
    const YarnModel m = make();
    const YarnBuffers y = buildYarnBuffers(m);
    const std::vector<FrameNormal> frames = computeKnotFramesCpu(y);
    size_t cusps = 0, acute = 0;
    for (size_t ci = 0; ci < y.curves.size(); ++ci) {
      const CurveInfo& c = y.curves[ci];
      for (uint32_t k = 0; k < ftCurveKnotCount(c); ++k) {
        const Knot knot = knotCpu(y, c, k);
        const vec3 n = vec3(frames[c.frameBase + k].normal);
        cusps += knot.cusp;
        acute += knot.cusp && glm::dot(knot.tangentIn, knot.tangent) >= 0.0f;
        ASSERT_TRUE(finite(n)) << m.name << " curve " << ci << " knot " << k;
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f) << m.name << " curve " << ci << " knot " << k;
        // Both tangents are unit and the stored normal is at most 45° from ⟂
        // either of them (|n·t| <= sin 45°), so both segments' frames exist.
        for (vec3 t : {knot.tangent, knot.tangentIn}) {
          EXPECT_NEAR(glm::length(t), 1.0f, 1e-5f) << m.name << " curve " << ci << " knot " << k;
          EXPECT_LE(std::abs(glm::dot(n, t)), 0.7072f) << m.name << " curve " << ci << " knot " << k;
        }
      }
      // Frames inside every segment: finite, orthonormal, right-handed.
      for (uint32_t s = 0; s < ftCurveSegmentCount(c); ++s) {
        const YarnSegment seg = loadSegmentCpu(y, frames, c.firstSegment + s);
        for (float t : {0.0f, 1e-3f, 0.5f, 0.999f, 1.0f}) {
          const YarnFrame f = ftYarnFrameAt(seg, t);
          ASSERT_TRUE(finite(f.T) && finite(f.N) && finite(f.B))
              << m.name << " curve " << ci << " segment " << s << " t " << t;
          EXPECT_NEAR(glm::length(f.T), 1.0f, 1e-5f);
          EXPECT_NEAR(glm::length(f.N), 1.0f, 1e-5f);
          EXPECT_NEAR(glm::dot(f.N, f.T), 0.0f, 1e-5f) << m.name << " curve " << ci << " segment " << s << " t " << t;
        }
      }
    }
    // Every back-track of the points is a cusp of the frames, and nothing else is.
    EXPECT_EQ(cusps, countBackTracks(m)) << m.name;
    EXPECT_GT(cusps, 0u) << m.name;
    // Both branches of the cusp turn are exercised (edges.bcc curve 13 is the < 90° one).
    if (m.name == "edges") {
      EXPECT_GT(acute, 0u);
      EXPECT_GT(cusps - acute, 0u);
    }
  }
}

glm::dvec3 bezier(const YarnSegment& s, double t) {
  const double u = 1.0 - t;
  return glm::dvec3(vec3(s.b0)) * (u * u * u) + glm::dvec3(vec3(s.b1)) * (3.0 * u * u * t) +
         glm::dvec3(vec3(s.b2)) * (3.0 * u * t * t) + glm::dvec3(vec3(s.b3)) * (t * t * t);
}

// The fallback tangent at a back-track is the direction the curve actually
// takes: the limit of the normalized derivative as t -> 0+ (resp. 1-),
// estimated here by finite differences of positions, not by the code under test.
TEST(EdgeCorpus, CuspTangentsAreTheOneSidedLimits) {
  const YarnModel m = test::edgeCorpus();
  const YarnBuffers y = buildYarnBuffers(m);
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(y);
  size_t checked = 0;
  for (const CurveInfo& c : y.curves)
    for (uint32_t k = 0; k < ftCurveKnotCount(c); ++k) {
      const Knot knot = knotCpu(y, c, k);
      if (!knot.cusp) continue;
      const YarnSegment after = loadSegmentCpu(y, frames, c.firstSegment + ftKnotSegmentAfter(c, k));
      const YarnSegment before = loadSegmentCpu(y, frames, c.firstSegment + ftKnotSegmentBefore(c, k));
      // Secants over a parameter step h, in double (a float secant this short
      // is rounding noise): they differ from the limit by an angle of order h.
      const double h = 1e-5;
      const glm::dvec3 out = glm::normalize(bezier(after, h) - bezier(after, 0.0));
      const glm::dvec3 in = glm::normalize(bezier(before, 1.0) - bezier(before, 1.0 - h));
      EXPECT_GT(glm::dot(out, glm::dvec3(knot.tangent)), 0.9999) << "knot " << k;
      EXPECT_GT(glm::dot(in, glm::dvec3(knot.tangentIn)), 0.9999) << "knot " << k;
      ++checked;
    }
  EXPECT_GT(checked, 8u);
}

// A planar curve's rotation-minimizing frame keeps the normal's component
// along the plane normal (the frame only turns in the plane); reflections
// about in-plane axes at cusps keep it too, and the stored cusp normal
// (projected ⟂ an in-plane axis) can only get closer to the plane normal.
TEST(EdgeCorpus, PlanarCurvesKeepTheOutOfPlaneComponentThroughCusps) {
  YarnModel m;
  m.name = "planar";
  std::vector<glm::vec3> p;
  for (int i = 0; i < 7; ++i) p.push_back({0.05f * i, 0.03f * std::sin(0.9f * i), 0.0f});
  p.push_back(p[5]);  // cusp at knot 6
  for (int i = 1; i <= 5; ++i) p.push_back(p[5] + glm::vec3(-0.02f * i, 0.04f * i + 0.01f * (i % 2), 0.0f));
  m.curves.push_back(test::openCurve(p));
  const YarnBuffers y = buildYarnBuffers(m);
  const std::vector<FrameNormal> frames = computeKnotFramesCpu(y);
  const CurveInfo& c = y.curves[0];
  const float z0 = std::abs(frames[0].normal.z);
  ASSERT_GT(z0, 0.1f);
  ASSERT_LT(z0, 0.99f);  // a start normal neither in nor ⟂ the plane: the test can fail
  size_t cusps = 0;
  for (uint32_t k = 1; k < ftCurveKnotCount(c); ++k) {
    const Knot knot = knotCpu(y, c, k);
    const float z = std::abs(frames[c.frameBase + k].normal.z);
    if (knot.cusp) {
      ++cusps;
      EXPECT_GE(z, z0 - 1e-5f) << "knot " << k;
    } else {
      EXPECT_NEAR(z, z0, 1e-5f) << "knot " << k;
    }
  }
  EXPECT_EQ(cusps, 1u);
}

}  // namespace
}  // namespace ft
