// stitch_mesh_test.cpp — stitch meshes: generators, OBJ and sidecar input, every
// bad-input case (InputError naming the file and the element), frame sequences,
// built-in deformations and face deformation gradients.
#include "knit/stitch_mesh.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "scene/input_error.h"

namespace fs = std::filesystem;
using namespace ft;

namespace {

fs::path corpus(const std::string& name) {
  const char* src = std::getenv("FT_SOURCE_DIR");
  const fs::path root = src ? fs::path(src) : fs::path(__FILE__).parent_path().parent_path();
  return root / "tests" / "knit_corpus" / name;
}

// A fresh directory per test, removed at the end.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("ft_stitch_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path operator/(const std::string& name) const { return dir_ / name; }

 private:
  fs::path dir_;
};

void writeFile(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
}

// Runs fn, expects an InputError whose message holds every one of `parts`.
void expectInputError(const std::function<void()>& fn, const std::vector<std::string>& parts) {
  try {
    fn();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const auto& part : parts)
      EXPECT_NE(msg.find(part), std::string::npos) << "'" << part << "' not in: " << msg;
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return;
  }
  ADD_FAILURE() << "no InputError; expected one mentioning " << (parts.empty() ? "" : parts[0]);
}

void expectMatNear(const glm::dmat2& F, const glm::dmat2& want, double tol) {
  for (int c = 0; c < 2; ++c) {
    for (int r = 0; r < 2; ++r)
      EXPECT_NEAR(F[c][r], want[c][r], tol) << "F[col " << c << "][row " << r << "]";
  }
}

void expectVecNear(glm::dvec3 a, glm::dvec3 b) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-15) << "component " << k;
}

// A unit square's corners (OBJ vertices 1-4), the start of most bad-input texts.
const char* kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

}  // namespace

TEST(StitchType, NamesRoundTrip) {
  for (StitchType t : {StitchType::Knit, StitchType::Purl, StitchType::Decrease, StitchType::Increase,
                       StitchType::YarnOver}) {
    EXPECT_EQ(parseStitchType(stitchTypeName(t)), t);
  }
  EXPECT_FALSE(parseStitchType("Knit"));
  EXPECT_FALSE(parseStitchType("yarn-over"));
  EXPECT_TRUE(stitchTypeAcceptsCount(StitchType::YarnOver, 3));
  EXPECT_TRUE(stitchTypeAcceptsCount(StitchType::YarnOver, 4));
  EXPECT_FALSE(stitchTypeAcceptsCount(StitchType::Knit, 5));
  EXPECT_TRUE(stitchTypeAcceptsCount(StitchType::Decrease, 5));
}

TEST(Generators, StockinetteLayoutAndOrientation) {
  const int rows = 4, cols = 6;
  const double w = 0.5, h = 0.45;
  const StitchMesh m = makeStockinette(rows, cols, w, h);
  ASSERT_EQ(m.faces.size(), size_t(rows * cols));
  ASSERT_EQ(m.vertices.size(), size_t((rows + 1) * (cols + 1)));
  EXPECT_NO_THROW(validateStitchMesh(m));
  for (uint32_t f = 0; f < m.faces.size(); ++f) {
    const StitchFace& face = m.faces[f];
    ASSERT_EQ(face.count, 4u);
    EXPECT_EQ(face.type, StitchType::Knit);
    EXPECT_EQ(face.v[4], kNoVertex);
    const glm::dvec3 p0 = m.vertices[face.v[0]], p1 = m.vertices[face.v[1]], p2 = m.vertices[face.v[2]],
                     p3 = m.vertices[face.v[3]];
    // Row by row from the bottom; v0->v1 along +x (course), v1->v2 along +y (wale).
    EXPECT_DOUBLE_EQ(p0.x, (f % cols) * w);
    EXPECT_DOUBLE_EQ(p0.y, (f / cols) * h);
    expectVecNear(p1 - p0, glm::dvec3(w, 0, 0));
    expectVecNear(p2 - p1, glm::dvec3(0, h, 0));
    expectVecNear(p3 - p2, glm::dvec3(-w, 0, 0));
    expectVecNear(p0 - p3, glm::dvec3(0, -h, 0));
    const FaceFrame2D fr = faceFrame2D(m, f);
    EXPECT_EQ(fr.normal, glm::dvec3(0, 0, 1));
    EXPECT_EQ(fr.e1, glm::dvec3(1, 0, 0));
    EXPECT_NEAR(fr.area, w * h, 1e-15);
  }
  // Each undirected edge: boundary edges once, interior edges twice in opposite directions.
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const StitchFace& face : m.faces) {
    for (uint32_t i = 0; i < 4; ++i) ++directed[{face.v[i], face.v[(i + 1) % 4]}];
  }
  int interior = 0, boundary = 0;
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1) << "directed edge " << e.first << "->" << e.second << " used twice";
    if (directed.count({e.second, e.first})) {
      ++interior;
    } else {
      ++boundary;
    }
  }
  EXPECT_EQ(interior / 2, rows * (cols - 1) + (rows - 1) * cols);
  EXPECT_EQ(boundary, 2 * (rows + cols));
}

TEST(Generators, RibbingAlternatesColumns) {
  const StitchMesh m = makeRibbing1x1(3, 5);
  ASSERT_EQ(m.faces.size(), 15u);
  for (uint32_t f = 0; f < m.faces.size(); ++f) {
    EXPECT_EQ(m.faces[f].type, (f % 5) % 2 == 0 ? StitchType::Knit : StitchType::Purl) << "face " << f;
  }
  EXPECT_DOUBLE_EQ(m.vertices.back().x, 5 * kDefaultStitchWidth);
  EXPECT_DOUBLE_EQ(m.vertices.back().y, 3 * kDefaultStitchHeight);
  EXPECT_NO_THROW(validateStitchMesh(m));
}

TEST(Generators, RejectBadSizes) {
  expectInputError([] { makeStockinette(0, 4); }, {"built-in stockinette 0x4", "rows"});
  expectInputError([] { makeRibbing1x1(4, -1); }, {"built-in ribbing1x1 4x-1"});
  expectInputError([] { makeStockinette(2, 2, -0.5, 0.45); }, {"stitch width"});
  expectInputError([] { makeStockinette(2, 2, 0.5, NAN); }, {"stitch height"});
  expectInputError([] { makeStockinette(100000, 100000); }, {"stitches; at most"});
}

TEST(StitchObj, ReadsMixedTypes) {
  const StitchMesh m = readStitchObj(corpus("mixed_types.obj"));
  ASSERT_EQ(m.vertices.size(), 11u);
  ASSERT_EQ(m.faces.size(), 4u);
  EXPECT_EQ(m.faces[0].type, StitchType::Knit);
  EXPECT_EQ(m.faces[1].type, StitchType::Knit);
  EXPECT_EQ(m.faces[2].type, StitchType::Decrease);
  EXPECT_EQ(m.faces[3].type, StitchType::Increase);
  EXPECT_EQ(m.faces[1].v[0], 1u);  // "2/2/1"
  EXPECT_EQ(m.faces[3].v[0], 6u);  // "-5" with 11 vertices
  EXPECT_EQ(m.faces[3].v[2], 10u);
  EXPECT_EQ(m.faces[2].objLine, 19u);
  EXPECT_EQ(courseEdge(m.faces[2]), std::make_pair(0u, 2u));
  EXPECT_EQ(courseEdge(m.faces[3]), std::make_pair(0u, 1u));
  for (uint32_t f = 0; f < 4; ++f) {
    const FaceFrame2D fr = faceFrame2D(m, f);
    EXPECT_EQ(fr.e1, glm::dvec3(1, 0, 0)) << "face " << f;
    EXPECT_EQ(fr.normal, glm::dvec3(0, 0, 1)) << "face " << f;
    EXPECT_GT(fr.area, 0);
  }
}

TEST(StitchObj, AcceptedSyntax) {
  // CRLF, comments, tabs, vt/vn/o/s/usemtl, a/b/c and a//c, negative indices, w.
  const std::string text =
      "# header\r\nmtllib x.mtl\r\no patch\r\nv 0 0 0 1\r\nv\t1 0 0\r\nv 1 1 0 # trailing comment\r\n"
      "v +0 1e0 0\r\nvt 0 0\r\nvn 0 0 1\r\ns 1\r\nusemtl wool\r\ng yarnover\r\nf -4//1 -3//1 -2//1 -1//1\r\n";
  const StitchMesh m = parseStitchObj(text, "syntax.obj");
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0].type, StitchType::YarnOver);
  EXPECT_EQ(m.faces[0].v[3], 3u);
  EXPECT_EQ(m.vertices[3], glm::dvec3(0, 1, 0));
}

TEST(StitchObj, YarnOverTriangle) {
  // A yarn-over has no loop below: bottom point v0, top edge v2->v1 is the course.
  const StitchMesh m = parseStitchObj("v 0.5 0 0\nv 1 1 0\nv 0 1 0\ng yarnover\nf 1 2 3\n", "yo.obj");
  EXPECT_EQ(courseEdge(m.faces[0]), std::make_pair(2u, 1u));
  const FaceFrame2D fr = faceFrame2D(m, 0);
  EXPECT_EQ(fr.e1, glm::dvec3(1, 0, 0));
  EXPECT_GT(fr.area, 0);
}

TEST(StitchObj, RoundTrip) {
  TempDir dir;
  for (const StitchMesh& m : {makeRibbing1x1(3, 4, 0.31, 0.27), readStitchObj(corpus("mixed_types.obj")),
                              deform(makeStockinette(2, 3), {Deformation::Shear, 17.3})}) {
    const fs::path p = dir / "round.obj";
    writeStitchObj(m, p);
    const StitchMesh back = readStitchObj(p);
    EXPECT_EQ(back.name, p.string());
    ASSERT_EQ(back.vertices.size(), m.vertices.size());
    for (size_t i = 0; i < m.vertices.size(); ++i)
      EXPECT_EQ(back.vertices[i], m.vertices[i]) << "vertex " << i;
    ASSERT_EQ(back.faces.size(), m.faces.size());
    for (size_t f = 0; f < m.faces.size(); ++f) {
      EXPECT_EQ(back.faces[f].v, m.faces[f].v) << "face " << f;
      EXPECT_EQ(back.faces[f].count, m.faces[f].count);
      EXPECT_EQ(back.faces[f].type, m.faces[f].type);
    }
  }
}

TEST(StitchObj, SidecarOverridesGroups) {
  const StitchMesh m = readStitchObj(corpus("sidecar_types.obj"));
  ASSERT_EQ(m.faces.size(), 4u);
  EXPECT_EQ(m.faces[0].type, StitchType::Knit);
  EXPECT_EQ(m.faces[1].type, StitchType::Purl);
  EXPECT_EQ(m.faces[3].type, StitchType::YarnOver);

  // A group that would be an error without the sidecar is ignored with it.
  TempDir dir;
  const fs::path obj = dir / "g.obj";
  writeFile(obj, std::string(kSquare) + "g Cube\ng purl\nf 1 2 3 4\n");
  expectInputError([&] { readStitchObj(obj); }, {"g.obj", "line 5", "'Cube'"});
  writeFile(stitchSidecarPath(obj), R"({"types": ["yarnover"]})");
  EXPECT_EQ(readStitchObj(obj).faces[0].type, StitchType::YarnOver);
}

TEST(StitchObj, BadSidecars) {
  TempDir dir;
  const fs::path obj = dir / "s.obj";
  const std::string json = stitchSidecarPath(obj).filename().string();
  EXPECT_EQ(json, "s.obj.stitches.json");
  writeFile(obj, std::string(kSquare) + "v 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n");
  auto with = [&](const std::string& sidecar) {
    writeFile(stitchSidecarPath(obj), sidecar);
    return [&] { readStitchObj(obj); };
  };
  expectInputError(with(R"({"types": ["knit"]})"), {json, "1 types for the 2 faces", "s.obj"});
  expectInputError(with(R"({"types": ["knit", "cable"]})"), {json, "types[1]", "'cable'"});
  expectInputError(with(R"({"types": ["knit", 3]})"), {json, "types[1] is not a string"});
  expectInputError(with(R"({"types": "knit"})"), {json, "not an array"});
  expectInputError(with(R"(["knit", "knit"])"), {json, "expected an object"});
  expectInputError(with(R"({"types": ["knit", )"), {json, "not valid JSON"});
  expectInputError(with(R"({"types": ["knit", "increase"]})"),
                   {"s.obj: face 1 (line 8): 4 vertices", json + " types[1] is increase", "5 (a pentagon)"});
}

struct BadObj {
  const char* what;
  std::string text;
  std::vector<std::string> parts;  // besides the file name
};

class BadObjTest : public ::testing::TestWithParam<BadObj> {};

TEST_P(BadObjTest, RejectedWithFileAndElement) {
  const BadObj& c = GetParam();
  SCOPED_TRACE(c.what);
  std::vector<std::string> parts = c.parts;
  parts.insert(parts.begin(), "bad.obj: ");
  expectInputError([&] { parseStitchObj(c.text, "bad.obj"); }, parts);
}

const std::string kSq = kSquare;
// Two unit squares side by side: vertices 1..6 (OBJ).
const std::string kTwo = kSq + "v 2 0 0\nv 2 1 0\n";

INSTANTIATE_TEST_SUITE_P(
    StitchObj, BadObjTest,
    ::testing::Values(
        BadObj{"two vertices", kSq + "f 1 2\n", {"face 0 (line 5): 2 vertices; a stitch face has 3 to 5"}},
        BadObj{"six vertices",
               kSq + "v 2 0 0\nv 2 1 0\nf 1 2 5 6 3 4\n",
               {"face 0 (line 7): 6 vertices; a stitch face has 3 to 5"}},
        BadObj{"pentagon outside a group",
               kSq + "v 0.5 1.5 0\nf 1 2 3 5 4\n",
               {"face 0 (line 6): 5 vertices, but a knit stitch has 4", "increase or decrease"}},
        BadObj{"quad declared decrease",
               kSq + "g decrease\nf 1 2 3 4\n",
               {"face 0 (line 6): 4 vertices, but a decrease stitch has 5"}},
        BadObj{"purl triangle",
               kSq + "g purl\nf 1 2 3\n",
               {"face 0 (line 6): 3 vertices, but a purl stitch has 4"}},
        BadObj{"index out of range",
               kSq + "f 1 2 3 9\n",
               {"face 0 (line 5)", "OBJ index 9 out of range", "4 vertices"}},
        BadObj{"index zero", kSq + "f 0 1 2 3\n", {"face 0 (line 5): corner 0: OBJ index 0"}},
        BadObj{"relative index too far", kSq + "f -1 -2 -3 -5\n", {"face 0 (line 5): corner 3", "-5"}},
        BadObj{"non-numeric index",
               kSq + "f 1 2 x 4\n",
               {"face 0 (line 5): corner 2: 'x' is not a vertex index"}},
        BadObj{"NaN coordinate", "v 0 0 0\nv 1 nan 0\n", {"line 2: vertex 1: coordinate y is nan"}},
        BadObj{"Inf coordinate", "v 0 0 -inf\n", {"line 1: vertex 0: coordinate z is -inf"}},
        BadObj{"huge coordinate overflows", "v 0 0 1e999\n", {"line 1: vertex 0", "not a number"}},
        BadObj{"non-numeric coordinate", "v 0 0 0\nv 1 0 abc\n", {"line 2: vertex 1: 'abc' is not a number"}},
        BadObj{"missing coordinate", "v 0 0\n", {"line 1: vertex 0: 2 coordinates"}},
        BadObj{"repeated vertex",
               kSq + "f 1 2 3 1\n",
               {"face 0 (line 5): repeats vertex 0 (OBJ 1) (corners 0 and 3)"}},
        BadObj{"edge used by three faces",
               kTwo + "v 1 0 1\nv 1 1 1\nf 1 2 3 4\nf 2 5 6 3\nf 3 8 7 2\n",
               {"non-manifold: edge 1-2 (OBJ 2-3) is used by 3 faces", "face 0 (line 9)", "face 1 (line 10)",
                "face 2 (line 11)"}},
        BadObj{"inconsistent orientation",
               kTwo + "f 1 2 3 4\nf 2 3 6 5\n",
               {"inconsistent orientation", "face 0 (line 7) and face 1 (line 8)", "edge 1->2 (OBJ 2->3)"}},
        BadObj{"bow-tie vertex",
               kSq + "v 2 1 0\nv 2 2 0\nv 1 2 0\nf 1 2 3 4\nf 3 5 6 7\n",
               {"non-manifold: vertex 2 (OBJ 3)", "face 0 (line 8)", "face 1 (line 9)"}},
        BadObj{"zero area (collinear)",
               "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3 4\n",
               {"face 0 (line 5): degenerate: zero area"}},
        BadObj{"zero-length edge",
               kSq + "v 1 1 0\ng increase\nf 1 2 3 5 4\n",
               {"face 0 (line 7)", "degenerate: edge 2->4 (OBJ 3->5) (corners 2->3) has length 0"}},
        BadObj{"short edge below the relative tolerance",
               "v 0 0 0\nv 1e6 0 0\nv 1e6 1e-3 0\nv 0 1e-3 0\nf 1 2 3 4\n",
               {"face 0 (line 5): degenerate: edge 1->2 (OBJ 2->3)"}},
        BadObj{"sliver below the relative tolerance",
               "v 0 0 0\nv 1 0 0\nv 2 1e-7 0\nv 1 1e-7 0\nf 1 2 3 4\n",
               {"face 0 (line 5): degenerate: zero area"}},
        BadObj{"self-intersecting quad",
               "v 0 0 0\nv 2 0 0\nv 0 1 0\nv 1 2 0\nf 1 2 3 4\n",
               {"face 0 (line 5): self-intersecting"}},
        BadObj{"unknown group", kSq + "g rib\nf 1 2 3 4\n", {"line 5: unknown group 'rib'", "knit, purl"}},
        BadObj{"two group names", kSq + "g knit purl\nf 1 2 3 4\n", {"line 5: group line names 2 groups"}},
        BadObj{"no faces", kSq, {"empty stitch mesh: no faces (4 vertices)"}},
        BadObj{"empty file", "", {"empty stitch mesh"}},
        BadObj{"polyline", kSq + "l 1 2\n", {"line 5: unsupported statement 'l'"}},
        BadObj{"unused vertex", kSq + "v 5 5 5\nf 1 2 3 4\n", {"vertex 4 (OBJ 5) is used by no face"}}),
    [](const ::testing::TestParamInfo<BadObj>& info) {
      std::string n;
      for (char c : std::string(info.param.what)) n += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return n;
    });

TEST(StitchObj, FilesNamedInErrors) {
  expectInputError(
      [] { readStitchObj(corpus("nonmanifold_edge.obj")); },
      {"nonmanifold_edge.obj: non-manifold: edge 1-2 (OBJ 2-3) is used by 3 faces", "face 2 (line 12)"});
  expectInputError([] { readStitchObj(corpus("no_such_file.obj")); }, {"no_such_file.obj: cannot open"});
  expectInputError([] { readStitchObj(corpus("")); }, {"is a directory"});
}

TEST(Sequence, SameTopologyReads) {
  TempDir dir;
  std::vector<fs::path> paths;
  const auto frames = animate(readStitchObj(corpus("mixed_types.obj")), {Deformation::StretchWale, 1.3}, 3);
  for (size_t i = 0; i < frames.size(); ++i) {
    paths.push_back(dir / ("frame" + std::to_string(i) + ".obj"));
    writeStitchObj(frames[i], paths.back());
  }
  const auto seq = readStitchObjSequence(paths);
  ASSERT_EQ(seq.size(), 3u);
  EXPECT_DOUBLE_EQ(seq[2].vertices[10].y, 1.35 * 1.3);
  expectInputError([] { readStitchObjSequence({}); }, {"no frames"});
}

TEST(Sequence, MismatchedTopologyNamesFrameAndFace) {
  TempDir dir;
  const StitchMesh base = makeStockinette(2, 2);
  const fs::path f0 = dir / "f0.obj", f1 = dir / "f1.obj";
  writeStitchObj(base, f0);

  StitchMesh fewer = makeStockinette(1, 2);
  writeStitchObj(fewer, f1);
  expectInputError(
      [&] {
        readStitchObjSequence({f0, f1});
      },
      {"f1.obj (frame 1): 6 vertices", "f0.obj", "has 9"});

  // Same vertices, one more face: the last stitch split into two yarn-over triangles.
  StitchMesh split = base;
  const StitchFace last = split.faces.back();
  split.faces.back() = {{last.v[0], last.v[1], last.v[2], kNoVertex, kNoVertex}, 3, StitchType::YarnOver, 0};
  split.faces.push_back(
      {{last.v[0], last.v[2], last.v[3], kNoVertex, kNoVertex}, 3, StitchType::YarnOver, 0});
  writeStitchObj(split, f1);
  expectInputError(
      [&] {
        readStitchObjSequence({f0, f1});
      },
      {"f1.obj (frame 1): 5 faces", "f0.obj", "has 4"});

  // Same counts, different connectivity: face 3 uses other vertices.
  StitchMesh rewired = base;
  std::swap(rewired.vertices[0], rewired.vertices[8]);
  for (StitchFace& face : rewired.faces) {
    for (uint32_t i = 0; i < face.count; ++i) {
      if (face.v[i] == 0) {
        face.v[i] = 8;
      } else if (face.v[i] == 8) {
        face.v[i] = 0;
      }
    }
  }
  writeStitchObj(rewired, f1);
  expectInputError(
      [&] {
        readStitchObjSequence({f0, f1, f1});
      },
      {"f1.obj (frame 1): face 0 (line 12): vertices differ from frame 0", "f0.obj"});

  StitchMesh retyped = base;
  retyped.faces[2].type = StitchType::Purl;
  writeStitchObj(retyped, f1);
  expectInputError(
      [&] {
        readStitchObjSequence({f0, f1});
      },
      {"f1.obj (frame 1): face 2 (line 15): type purl", "has knit"});
}

TEST(Deformation, StretchCourseGradient) {
  for (const StitchMesh& rest :
       {makeStockinette(5, 7), makeRibbing1x1(4, 4, 0.3, 0.6), readStitchObj(corpus("mixed_types.obj"))}) {
    SCOPED_TRACE(rest.name);
    const StitchMesh d = deform(rest, {Deformation::StretchCourse, 1.4});
    const auto all = faceDeformationGradients(rest, d);
    for (uint32_t f = 0; f < rest.faces.size(); ++f) {
      expectMatNear(all[f], glm::dmat2(1.4, 0, 0, 1), 1e-12);
      expectMatNear(faceDeformationGradient(rest, d, f), all[f], 0);
    }
  }
}

TEST(Deformation, StretchWaleAndShearGradients) {
  const StitchMesh rest = readStitchObj(corpus("mixed_types.obj"));
  const auto wale = faceDeformationGradients(rest, deform(rest, {Deformation::StretchWale, 1.6}));
  for (const auto& F : wale) expectMatNear(F, glm::dmat2(1, 0, 0, 1.6), 1e-12);
  const double t30 = std::tan(std::numbers::pi / 6);
  for (const StitchMesh& r : {rest, makeStockinette(3, 3)}) {
    const auto shear = faceDeformationGradients(r, deform(r, {Deformation::Shear, 30}));
    // Column-major: glm::dmat2(c0r0, c0r1, c1r0, c1r1) = [[1, tan30], [0, 1]].
    for (const auto& F : shear) expectMatNear(F, glm::dmat2(1, 0, t30, 1), 1e-12);
  }
}

TEST(Deformation, GradientIgnoresRigidMotion) {
  // The frames are the faces' own: rotating the stretched patch in 3D changes nothing.
  const StitchMesh rest = makeStockinette(3, 4);
  StitchMesh d = deform(rest, {Deformation::StretchCourse, 1.25});
  const double a = 0.7;
  for (glm::dvec3& p : d.vertices) {
    p = glm::dvec3(p.x, std::cos(a) * p.y - std::sin(a) * p.z, std::sin(a) * p.y + std::cos(a) * p.z) +
        glm::dvec3(3, -2, 5);
  }
  for (const auto& F : faceDeformationGradients(rest, d)) expectMatNear(F, glm::dmat2(1.25, 0, 0, 1), 1e-12);
}

TEST(Deformation, AffineAboutBottomLeftCorner) {
  StitchMesh rest = makeStockinette(2, 2);
  for (glm::dvec3& p : rest.vertices) p += glm::dvec3(10, 20, 0);
  const StitchMesh d = deform(rest, {Deformation::StretchCourse, 1.5});
  EXPECT_EQ(d.vertices[0], rest.vertices[0]);
  EXPECT_DOUBLE_EQ(d.vertices[2].x, 10 + 1.5 * 2 * kDefaultStitchWidth);
  const StitchMesh s = deform(rest, {Deformation::Shear, 30});
  EXPECT_EQ(s.vertices[0], rest.vertices[0]);
  EXPECT_NEAR(s.vertices[6].x, 10 + std::tan(std::numbers::pi / 6) * 2 * kDefaultStitchHeight, 1e-12);
  EXPECT_EQ(deform(rest, {}).vertices, rest.vertices);
}

TEST(Deformation, RangeErrorsNameTheOption) {
  const StitchMesh rest = makeStockinette(2, 2);
  expectInputError(
      [&] {
        deform(rest, {Deformation::StretchCourse, 1.7});
      },
      {"stretch-course", "1.7", "[1.0, 1.6]"});
  expectInputError([&] { deform(rest, {Deformation::StretchWale, 0.9}); }, {"stretch-wale", "0.9"});
  expectInputError([&] { deform(rest, {Deformation::StretchWale, NAN}); }, {"stretch-wale", "nan"});
  expectInputError([&] { deform(rest, {Deformation::Shear, 30.5}); }, {"shear", "30.5", "[0, 30]"});
  expectInputError([&] { deform(rest, {Deformation::Shear, -1}); }, {"shear", "-1"});
  expectInputError([&] { animate(rest, {Deformation::Shear, 45}, 4); }, {"shear", "45"});
  expectInputError([&] { animate(rest, {Deformation::Shear, 10}, 1); }, {"frames: 1"});
  EXPECT_NO_THROW(deform(rest, {Deformation::StretchCourse, 1.0}));
  EXPECT_NO_THROW(deform(rest, {Deformation::StretchCourse, 1.6}));
  EXPECT_NO_THROW(deform(rest, {Deformation::Shear, 0}));
}

TEST(Deformation, ParseSpec) {
  EXPECT_EQ(parseDeformation("none").kind, Deformation::None);
  const Deformation d = parseDeformation("stretch-course=1.4");
  EXPECT_EQ(d.kind, Deformation::StretchCourse);
  EXPECT_EQ(d.amount, 1.4);
  EXPECT_EQ(parseDeformation("shear=30").kind, Deformation::Shear);
  expectInputError([] { parseDeformation("stretch-wale=2"); }, {"stretch-wale", "2"});
  expectInputError([] { parseDeformation("twist=3"); }, {"'twist=3'", "unknown kind"});
  expectInputError([] { parseDeformation("shear"); }, {"shear=<number>"});
  expectInputError([] { parseDeformation("shear=abc"); }, {"shear=<number>"});
}

TEST(Deformation, AnimateInterpolatesFromIdentity) {
  const StitchMesh rest = makeStockinette(2, 3);
  const auto frames = animate(rest, {Deformation::StretchCourse, 1.4}, 5);
  ASSERT_EQ(frames.size(), 5u);
  EXPECT_EQ(frames[0].vertices, rest.vertices);
  EXPECT_EQ(frames[4].vertices, deform(rest, {Deformation::StretchCourse, 1.4}).vertices);
  for (int i = 0; i < 5; ++i) {
    const double s = 1.0 + 0.1 * i;
    for (const auto& F : faceDeformationGradients(rest, frames[i]))
      expectMatNear(F, glm::dmat2(s, 0, 0, 1), 1e-12);
  }
  const auto shear = animate(rest, {Deformation::Shear, 30}, 3);
  const auto F = faceDeformationGradient(rest, shear[1], 0);
  EXPECT_NEAR(F[1][0], std::tan(std::numbers::pi / 12), 1e-12);  // 15 degrees halfway
}

TEST(Deformation, FlippedFaceIsAnError) {
  // Mirror the centre stitch of a 3x3 patch: it now faces -z among +z neighbours.
  const StitchMesh rest = makeStockinette(3, 3, 1.0, 1.0);
  StitchMesh d = rest;
  const StitchFace& c = rest.faces[4];
  std::swap(d.vertices[c.v[0]], d.vertices[c.v[1]]);
  std::swap(d.vertices[c.v[2]], d.vertices[c.v[3]]);
  d.name = "mirrored.obj";
  expectInputError([&] { faceDeformationGradient(rest, d, 4); },
                   {"mirrored.obj: face 4: flipped", "det F = -1"});
  expectInputError([&] { faceDeformationGradients(rest, d); }, {"mirrored.obj: face "});
  EXPECT_LT(faceFrame2D(d, 4).area, 0);
}

TEST(Deformation, DegenerateDeformedFacesAreErrors) {
  const StitchMesh rest = makeStockinette(2, 2, 1.0, 1.0);
  // Top row squashed flat onto the middle row: faces 2 and 3 have zero area.
  StitchMesh flat = rest;
  flat.name = "flat";
  for (uint32_t v = 6; v < 9; ++v) flat.vertices[v].y = 1.0;
  expectInputError([&] { faceDeformationGradient(rest, flat, 2); }, {"flat: face 2: degenerate"});
  expectInputError([&] { faceDeformationGradients(rest, flat); }, {"flat: face 2: degenerate"});
  // Centre vertex pushed past the right border: face 1 folds over itself.
  StitchMesh tangled = rest;
  tangled.name = "tangled";
  tangled.vertices[4].x = 2.5;
  expectInputError([&] { faceDeformationGradient(rest, tangled, 1); },
                   {"tangled: face 1: self-intersecting"});
  // Shrunk a thousandfold per side: a millionth of the area.
  StitchMesh tiny = rest;
  tiny.name = "tiny";
  for (glm::dvec3& p : tiny.vertices) p *= 5e-4;
  expectInputError([&] { faceDeformationGradient(rest, tiny, 0); }, {"tiny: face 0: collapsed"});
  // NaN positions are reported, never turned into an F.
  StitchMesh nan = rest;
  nan.name = "nan";
  nan.vertices[4].z = NAN;
  expectInputError([&] { faceDeformationGradient(rest, nan, 0); }, {"nan: face 0: vertex 4 is not finite"});
  // A broken face elsewhere is reported, not read past.
  StitchMesh broken = rest;
  broken.name = "broken";
  broken.faces[3].v[2] = 99;
  expectInputError([&] { faceDeformationGradient(rest, broken, 0); },
                   {"broken: face 3: vertex 99 out of range"});
  broken.faces[3].v[2] = 8;
  broken.vertices[8].x = NAN;
  expectInputError([&] { faceFrame2D(broken, 0); }, {"broken: face 3: vertex 8 is not finite"});
  // Topology must match the rest mesh.
  expectInputError([&] { faceDeformationGradient(rest, makeStockinette(2, 3), 0); }, {"rest mesh"});
  StitchMesh rewired = rest;
  rewired.name = "rewired";
  std::swap(rewired.faces[0].v[0], rewired.faces[0].v[1]);
  expectInputError([&] { faceDeformationGradients(rest, rewired); }, {"rewired: face 0: vertices differ"});
}

TEST(Validate, GeneratedAndDeformedMeshes) {
  StitchMesh m = makeStockinette(2, 2);
  m.vertices[3].y = INFINITY;
  expectInputError([&] { validateStitchMesh(m); },
                   {"built-in stockinette 2x2: vertex 3: coordinate y is inf"});
  StitchMesh none;
  none.name = "nothing";
  expectInputError([&] { validateStitchMesh(none); }, {"nothing: empty stitch mesh"});
}
