// yarn_preset_test.cpp — the yarn-presets table: built-in table, column order,
// and errors naming source, line, column and value.
#include "scene/yarn_preset.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "scene/input_error.h"

namespace fs = std::filesystem;
using ft::InputError;
using ft::parseYarnPresets;
using ft::YarnPreset;

namespace {

constexpr const char* kSource = "t.tsv";

const std::vector<std::string> kHeader = {
    "name",          "ply_num",      "fiber_num",     "yarn_clock_wise", "fiber_clock_wise", "yarn_alpha",
    "alpha",         "yarn_radius",  "ellipse_long",  "ellipse_short",   "epsilon",          "beta",
    "R_max",         "s_i",          "rho_min",       "rho_max",         "hair_density",     "hair_ze_mu",
    "hair_ze_sigma", "hair_r0_mu",   "hair_r0_sigma", "hair_re_mu",      "hair_re_sigma",    "hair_pe_mu",
    "hair_pe_sigma", "loop_density", "loop_r1_mu",    "loop_r1_sigma"};
// polyester1 of data/yarn-presets.tsv (has a negative mean, hair_ze_mu).
const std::vector<std::string> kRow = {
    "polyester1", "2",          "60",        "0",           "1",        "0.370407",  "0.379643",
    "0.0287052",  "0.0285371",  "0.0210996", "0.338509",    "0.422896", "1",         "1.1",
    "0.7",        "1",          "31.4907",   "-0.00543297", "0.050999", "0.0208203", "0.00488699",
    "0.0118821",  "0.00855442", "0.408089",  "0.450913",    "34.1149",  "0.0270006", "0.00398517"};

std::string join(const std::vector<std::string>& fields) {
  std::string s;
  for (size_t i = 0; i < fields.size(); ++i) s += (i ? "\t" : "") + fields[i];
  return s + "\n";
}

size_t col(const std::string& name) {
  for (size_t i = 0; i < kHeader.size(); ++i) {
    if (kHeader[i] == name) return i;
  }
  ADD_FAILURE() << "no column " << name;
  return 0;
}

// Header + the polyester1 row with one field replaced.
std::string tableWith(const std::string& column, const std::string& value) {
  auto row = kRow;
  row[col(column)] = value;
  return join(kHeader) + join(row);
}

void expectError(const std::string& text, const std::string& expectedPrefix, const std::string& key = "") {
  try {
    parseYarnPresets(text, kSource);
    ADD_FAILURE() << "no InputError; expected " << expectedPrefix;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(expectedPrefix, 0), 0u)
        << "message: " << msg << "\nexpected prefix: " << expectedPrefix;
    EXPECT_NE(msg.find(key), std::string::npos) << "message: " << msg << "\nexpected key: " << key;
  }
}

// Error on row 2 for one column/value.
void expectFieldError(const std::string& column, const std::string& value, const std::string& key) {
  SCOPED_TRACE(column + "=" + value);
  expectError(tableWith(column, value),
              std::string(kSource) + ": line 2: column " + column + ": value '" + value + "': ", key);
}

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expectSame(const YarnPreset& a, const YarnPreset& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.plyNum, b.plyNum);
  EXPECT_EQ(a.fiberNum, b.fiberNum);
  EXPECT_EQ(a.yarnClockWise, b.yarnClockWise);
  EXPECT_EQ(a.fiberClockWise, b.fiberClockWise);
  const double fa[] = {a.yarnAlpha,    a.alpha,       a.yarnRadius,   a.ellipseLong,  a.ellipseShort,
                       a.epsilon,      a.beta,        a.rMax,         a.sI,           a.rhoMin,
                       a.rhoMax,       a.hairDensity, a.hairZe.mu,    a.hairZe.sigma, a.hairR0.mu,
                       a.hairR0.sigma, a.hairRe.mu,   a.hairRe.sigma, a.hairPe.mu,    a.hairPe.sigma,
                       a.loopDensity,  a.loopR1.mu,   a.loopR1.sigma};
  const double fb[] = {b.yarnAlpha,    b.alpha,       b.yarnRadius,   b.ellipseLong,  b.ellipseShort,
                       b.epsilon,      b.beta,        b.rMax,         b.sI,           b.rhoMin,
                       b.rhoMax,       b.hairDensity, b.hairZe.mu,    b.hairZe.sigma, b.hairR0.mu,
                       b.hairR0.sigma, b.hairRe.mu,   b.hairRe.sigma, b.hairPe.mu,    b.hairPe.sigma,
                       b.loopDensity,  b.loopR1.mu,   b.loopR1.sigma};
  for (size_t i = 0; i < std::size(fa); ++i) EXPECT_EQ(fa[i], fb[i]) << a.name << " field " << i;
}

}  // namespace

TEST(YarnPreset, BuiltinTable) {
  const auto& presets = ft::builtinYarnPresets();
  const std::vector<std::string> names = {"cotton1", "cotton2", "polyester1", "rayon1", "rayon2",
                                          "rayon3",  "rayon4",  "silk1",      "silk2"};
  ASSERT_EQ(presets.size(), names.size());
  for (size_t i = 0; i < names.size(); ++i) EXPECT_EQ(presets[i].name, names[i]);
  const YarnPreset& c = ft::findYarnPreset("cotton1");
  EXPECT_EQ(c.plyNum, 3);
  EXPECT_EQ(c.fiberNum, 75);
  EXPECT_FALSE(c.yarnClockWise);
  EXPECT_TRUE(c.fiberClockWise);
  EXPECT_EQ(c.yarnAlpha, 0.452737);
  EXPECT_EQ(c.alpha, 0.366114);
  EXPECT_EQ(c.yarnRadius, 0.0378238);
  EXPECT_EQ(c.ellipseLong, 0.0257183);
  EXPECT_EQ(c.ellipseShort, 0.0200419);
  EXPECT_EQ(c.epsilon, 0.0);
  EXPECT_EQ(c.beta, 0.200965);
  EXPECT_EQ(c.rMax, 1.0);
  EXPECT_EQ(c.sI, 1.0);
  EXPECT_EQ(c.rhoMin, 0.85);
  EXPECT_EQ(c.rhoMax, 1.0);
  EXPECT_EQ(c.hairDensity, 30.3559);
  EXPECT_EQ(c.hairZe.mu, 0.002419);
  EXPECT_EQ(c.hairZe.sigma, 0.0631994);
  EXPECT_EQ(c.hairR0.mu, 0.0203949);
  EXPECT_EQ(c.hairR0.sigma, 0.0055814);
  EXPECT_EQ(c.hairRe.mu, 0.0166551);
  EXPECT_EQ(c.hairRe.sigma, 0.00949242);
  EXPECT_EQ(c.hairPe.mu, 0.390188);
  EXPECT_EQ(c.hairPe.sigma, 0.342302);
  EXPECT_EQ(c.loopDensity, 19.1003);
  EXPECT_EQ(c.loopR1.mu, 0.0245694);
  EXPECT_EQ(c.loopR1.sigma, 0.00522926);
  const YarnPreset& r = ft::findYarnPreset("rayon1");
  EXPECT_TRUE(r.yarnClockWise);
  EXPECT_FALSE(r.fiberClockWise);
  EXPECT_EQ(ft::findYarnPreset("polyester1").hairZe.mu, -0.00543297);
}

// The embedded copy matches the repository file.
TEST(YarnPreset, BuiltinMatchesDataFiles) {
  const auto& builtin = ft::builtinYarnPresets();
  const char* src = std::getenv("FT_SOURCE_DIR");
  const fs::path repoFile = fs::path(src ? src : ".") / "data" / "yarn-presets.tsv";
  ASSERT_TRUE(fs::exists(repoFile)) << repoFile;
  const auto fromRepo = parseYarnPresets(readText(repoFile), repoFile.string());
  ASSERT_EQ(fromRepo.size(), builtin.size());
  for (size_t i = 0; i < builtin.size(); ++i) expectSame(fromRepo[i], builtin[i]);
}

TEST(YarnPreset, FindUnknownListsKnownNames) {
  try {
    ft::findYarnPreset("wool9");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("built-in yarn-presets.tsv"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'wool9'"), std::string::npos) << msg;
    for (const auto& p : ft::builtinYarnPresets()) EXPECT_NE(msg.find(p.name), std::string::npos) << msg;
  }
}

TEST(YarnPreset, AnyColumnOrderAndLineEndings) {
  const YarnPreset ref = parseYarnPresets(join(kHeader) + join(kRow), kSource).at(0);
  auto header = kHeader;
  auto row = kRow;
  std::reverse(header.begin(), header.end());
  std::reverse(row.begin(), row.end());
  const auto reversed = parseYarnPresets(join(header) + join(row), kSource);
  ASSERT_EQ(reversed.size(), 1u);
  expectSame(reversed[0], ref);
  // CRLF, blank lines and no final newline are fine.
  std::string crlf = join(kHeader) + "\n" + join(kRow);
  for (size_t pos = 0; (pos = crlf.find('\n', pos)) != std::string::npos; pos += 2) crlf.insert(pos, "\r");
  crlf.pop_back();
  crlf.pop_back();
  expectSame(parseYarnPresets(crlf, kSource).at(0), ref);
}

TEST(YarnPreset, HeaderErrors) {
  expectError("", std::string(kSource) + ": line 1: ", "empty");
  expectError("\n\n", std::string(kSource) + ": line 1: ", "empty");
  expectError(join(kHeader), std::string(kSource) + ": line 1: ", "no presets");

  auto header = kHeader;
  header.erase(header.begin() + col("s_i"));
  auto row = kRow;
  row.erase(row.begin() + col("s_i"));
  expectError(join(header) + join(row), std::string(kSource) + ": line 1: ", "missing column s_i");

  header = kHeader;
  header.push_back("colour");
  row = kRow;
  row.push_back("red");
  expectError(join(header) + join(row),
              std::string(kSource) + ": line 1: column colour: value 'colour': ", "unknown column");

  header = kHeader;
  header[col("alpha")] = "beta";
  expectError(join(header) + join(kRow),
              std::string(kSource) + ": line 1: column beta: ", "duplicate column");
}

TEST(YarnPreset, RowErrors) {
  auto row = kRow;
  row.pop_back();
  expectError(join(kHeader) + join(row), std::string(kSource) + ": line 2: ", "27 fields, the header has 28");
  row = kRow;
  row.push_back("x");
  expectError(join(kHeader) + join(row), std::string(kSource) + ": line 2: ", "29 fields");
  // Line numbers count blank lines.
  auto dup = kRow;
  expectError(join(kHeader) + join(kRow) + "\n" + join(dup),
              std::string(kSource) + ": line 4: column name: value 'polyester1': ", "duplicate preset name");
  expectFieldError("name", "two words", "preset names");
  expectFieldError("name", "", "preset names");
}

TEST(YarnPreset, NumberErrors) {
  expectFieldError("yarn_alpha", "abc", "expected a number");
  expectFieldError("yarn_alpha", "0.3x", "expected a number");
  expectFieldError("yarn_alpha", "0x1p-2", "expected a number");
  expectFieldError("yarn_alpha", "+0.3", "expected a number");
  expectFieldError("yarn_alpha", "1e999", "expected a number");
  expectFieldError("beta", "nan", "finite");
  expectFieldError("beta", "inf", "finite");
  expectFieldError("hair_ze_mu", "-infinity", "finite");
  expectFieldError("ply_num", "3.0", "expected an integer");
  expectFieldError("ply_num", "99999999999999999999", "expected an integer");
  expectFieldError("yarn_clock_wise", "2", "0 or 1");
  expectFieldError("fiber_clock_wise", "yes", "0 or 1");
}

TEST(YarnPreset, RangeErrors) {
  expectFieldError("ply_num", "0", "1..8");
  expectFieldError("ply_num", "9", "1..8");
  expectFieldError("fiber_num", "0", "1..4096");
  expectFieldError("fiber_num", "4097", "1..4096");
  for (const char* c : {"yarn_alpha", "alpha", "yarn_radius", "ellipse_long", "R_max"}) {
    expectFieldError(c, "0", "> 0");
    expectFieldError(c, "-0.1", "> 0");
  }
  expectFieldError("ellipse_short", "-0.01", "> 0");
  for (const char* c : {"hair_density", "loop_density", "hair_ze_sigma", "hair_r0_sigma", "hair_re_sigma",
                        "hair_pe_sigma", "loop_r1_sigma", "rho_min", "beta", "s_i"}) {
    expectFieldError(c, "-0.5", ">= 0");
  }
  expectFieldError("epsilon", "0.6", "[0, 0.5]");
  expectFieldError("epsilon", "-0.01", "[0, 0.5]");
  expectFieldError("rho_min", "1.5", "<= rho_max (1)");
  expectFieldError("ellipse_short", "0.05", "<= ellipse_long (0.0285371)");
  // Boundary values are accepted.
  for (auto [c, v] : std::vector<std::pair<std::string, std::string>>{{"ply_num", "1"},
                                                                      {"ply_num", "8"},
                                                                      {"fiber_num", "4096"},
                                                                      {"epsilon", "0.5"},
                                                                      {"rho_min", "1"},
                                                                      {"hair_density", "0"},
                                                                      {"hair_ze_mu", "-3"}}) {
    EXPECT_NO_THROW(parseYarnPresets(tableWith(c, v), kSource)) << c << "=" << v;
  }
}

TEST(YarnPreset, ControlBytesAreEscapedInMessages) {
  try {
    parseYarnPresets(tableWith("beta", std::string("\x01z", 2)), kSource);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("value '\\x01z'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseYarnPresets(std::string("name\0x", 6), kSource), InputError);
}

// --set name=value (issue 14, deliverable 10): any column, the loader's range
// checks, later assignments win, the base preset untouched.
TEST(YarnPresetOverride, SetsColumnsByName) {
  const YarnPreset& base = ft::findYarnPreset("cotton1");
  const YarnPreset p = ft::overrideYarnPreset(
      base, {"ply_num=4", "fiber_num=12", "alpha=0.25", "yarn_clock_wise=1", "hair_pe_sigma=0", "rho_min = 0.5",
             "ply_num=5"});
  EXPECT_EQ(p.plyNum, 5);
  EXPECT_EQ(p.fiberNum, 12);
  EXPECT_EQ(p.alpha, 0.25);
  EXPECT_TRUE(p.yarnClockWise);
  EXPECT_EQ(p.hairPe.sigma, 0.0);
  EXPECT_EQ(p.rhoMin, 0.5);
  EXPECT_EQ(p.name, "cotton1");
  EXPECT_EQ(p.yarnRadius, base.yarnRadius);
  EXPECT_EQ(base.plyNum, 3);  // the built-in table is not changed
  EXPECT_EQ(ft::findYarnPreset("cotton1").plyNum, 3);
  // Every column of the table can be set (the header, name excluded).
  for (size_t i = 1; i < kHeader.size(); ++i) {
    const std::string& c = kHeader[i];
    const bool flag = c == "yarn_clock_wise" || c == "fiber_clock_wise";
    const bool count = c == "ply_num" || c == "fiber_num";
    EXPECT_NO_THROW(ft::overrideYarnPreset(base, {c + "=" + (flag ? "1" : count ? "2" : c == "rho_min" ? "0.9" : c == "rho_max" ? "1.5" : c == "ellipse_short" ? "0.01" : "0.3")}))
        << c;
  }
}

void expectSetRefused(const std::vector<std::string>& sets, const std::vector<std::string>& parts) {
  try {
    ft::overrideYarnPreset(ft::findYarnPreset("cotton1"), sets);
    ADD_FAILURE() << "accepted " << sets.back();
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--set"), std::string::npos) << what;
    for (const std::string& s : parts) EXPECT_NE(what.find(s), std::string::npos) << "missing '" << s << "': " << what;
  }
}

TEST(YarnPresetOverride, RefusesWhatTheLoaderRefuses) {
  expectSetRefused({"ply_num=9"}, {"ply_num", "'9'", "1..8"});
  expectSetRefused({"ply_num=0"}, {"ply_num", "1..8"});
  expectSetRefused({"fiber_num=4097"}, {"fiber_num", "4097", "1..4096"});
  expectSetRefused({"ply_num=2.5"}, {"ply_num", "2.5", "integer"});
  expectSetRefused({"alpha=0"}, {"alpha", "> 0"});
  expectSetRefused({"alpha=nan"}, {"alpha", "nan"});
  expectSetRefused({"alpha=inf"}, {"alpha", "inf"});
  expectSetRefused({"hair_density=-1"}, {"hair_density", "-1", ">= 0"});
  expectSetRefused({"epsilon=0.7"}, {"epsilon", "0.7", "[0, 0.5]"});
  expectSetRefused({"yarn_clock_wise=2"}, {"yarn_clock_wise", "0 or 1"});
  expectSetRefused({"beta=abc"}, {"beta", "abc", "number"});
  expectSetRefused({"rho_min=2"}, {"rho_min", "'2'", "rho_max"});                  // cross-column, against the preset
  expectSetRefused({"rho_max=0.5"}, {"rho_min", "rho_max (0.5)"});                 // the other side of it
  expectSetRefused({"ellipse_short=1"}, {"ellipse_short", "ellipse_long"});
  expectSetRefused({"nosuch=1"}, {"nosuch", "unknown", "ply_num", "loop_r1_sigma"});
  expectSetRefused({"name=x"}, {"unknown preset parameter 'name'"});
  expectSetRefused({"ply_num"}, {"ply_num", "name=value"});
  expectSetRefused({"ply_num=4", "fiber_num=0"}, {"fiber_num=0"});
  // A combination valid only together is accepted in any order.
  EXPECT_NO_THROW(ft::overrideYarnPreset(ft::findYarnPreset("cotton1"), {"rho_max=2", "rho_min=1.5"}));
}
