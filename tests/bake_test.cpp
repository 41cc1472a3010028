// The bake runner (bake/bake_runner.h) in its no-MPI mode with a test bake
// defined here (not in bakes.def): shards combined in shard order whatever
// order they ran in, errors naming the shard, the output checks, the launch
// detection; and the ambient-occlusion bake (bake/ambient_occlusion_bake.cpp)
// against bakeAmbientOcclusionCpu bit for bit for any shard split. The runs
// across MPI ranks are tests/bake_mpi_test.sh.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <thread>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bake/ambient_occlusion_bake.h"
#include "bake/bake.h"
#include "bake/bake_runner.h"
#include "reference/ambient_occlusion.h"
#include "scene/input_error.h"
#include "scene/yarn_density.h"
#include "scene/yarn_preset.h"

namespace ft {
namespace {

namespace fs = std::filesystem;

// The runner must take the no-MPI path here even if ctest itself was started by a launcher.
class BakeRunner : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) ::unsetenv(v);
    dir_ = fs::temp_directory_path() / fmt::format("ft-bake-test-{}", ::getpid());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string readFile(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// Shard k: k + 1 bytes of value k (shards of different sizes); write puts
// them one after the other with a '|' between, so the file shows the order.
class CountingBake final : public Bake {
 public:
  explicit CountingBake(size_t shards, long failAt = -1) : shards_(shards), failAt_(failAt) { name_ = "counting"; }
  void addOptions(CLI::App&) override {}
  void prepare() override { prepared_ = true; }
  size_t shardCount() const override { return shards_; }
  std::vector<std::byte> runShard(size_t k) const override {
    if (!prepared_) throw std::logic_error("runShard before prepare");
    if (long(k) == failAt_) throw std::runtime_error("planted failure");
    ran_.push_back(k);
    return std::vector<std::byte>(k + 1, std::byte(k));
  }
  void write(std::span<const std::vector<std::byte>> shards, const fs::path& out) const override {
    std::ofstream f(out, std::ios::binary);
    for (const auto& s : shards) {
      for (std::byte b : s) f << char('a' + int(b));
      f << '|';
    }
  }
  mutable std::vector<size_t> ran_;

 private:
  size_t shards_;
  long failAt_;
  bool prepared_ = false;
};

TEST_F(BakeRunner, NoMpiRunsEveryShardInOrderAndWritesInShardOrder) {
  CountingBake bake(5);
  std::ostringstream log;
  const BakeRunSummary s = runBake(bake, {dir_ / "out.txt", 1, false}, log);
  EXPECT_EQ(readFile(dir_ / "out.txt"), "a|bb|ccc|dddd|eeeee|");
  EXPECT_EQ(bake.ran_, (std::vector<size_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(s.shards, 5u);
  EXPECT_EQ(s.ranks, 1);
  EXPECT_EQ(s.shardsPerRank, (std::vector<size_t>{5}));
  EXPECT_TRUE(s.wroteOutput);
  EXPECT_NE(log.str().find("5 shards on 1 rank"), std::string::npos) << log.str();
  EXPECT_FALSE(fs::exists(dir_ / "out.txt.part"));
}

TEST_F(BakeRunner, QuietWritesNoSummary) {
  CountingBake bake(2);
  std::ostringstream log;
  runBake(bake, {dir_ / "q.txt", 1, true}, log);
  EXPECT_EQ(log.str(), "");
  EXPECT_EQ(readFile(dir_ / "q.txt"), "a|bb|");
}

TEST_F(BakeRunner, ShardErrorNamesBakeAndShardAndLeavesNoOutput) {
  CountingBake bake(5, 2);
  std::ostringstream log;
  try {
    runBake(bake, {dir_ / "fail.txt", 1, false}, log);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bake counting: shard 2 of 5: planted failure"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ / "fail.txt"));
  EXPECT_FALSE(fs::exists(dir_ / "fail.txt.part"));
}

TEST_F(BakeRunner, OutputChecksNameTheOption) {
  CountingBake bake(1);
  std::ostringstream log;
  for (const fs::path& bad : {dir_ / "no-such-folder" / "x.bin", dir_, fs::path()}) {
    try {
      runBake(bake, {bad, 1, true}, log);
      FAIL() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--out"), std::string::npos) << e.what();
      if (!bad.empty()) {
        EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
      }
    }
  }
  EXPECT_THROW(runBake(bake, {dir_ / "t.bin", -1, true}, log), InputError);
  EXPECT_TRUE(bake.ran_.empty());  // rejected before any shard ran
}

// Mode (c): started by a launcher, built without MPI: every rank would redo
// the whole bake, so it refuses before any shard runs.
TEST_F(BakeRunner, UnderALauncherWithoutMpiRefuses) {
  if (builtWithMpi()) GTEST_SKIP() << "built with MPI: tests/bake_mpi_test.sh runs the bake under mpirun";
  ::setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
  CountingBake bake(3);
  std::ostringstream log;
  try {
    runBake(bake, {dir_ / "x.txt", 1, true}, log);
    ADD_FAILURE() << "ran under a launcher without MPI";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("built without MPI"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("OMPI_COMM_WORLD_SIZE"), std::string::npos) << e.what();
  }
  ::unsetenv("OMPI_COMM_WORLD_SIZE");
  EXPECT_TRUE(bake.ran_.empty());
  EXPECT_FALSE(fs::exists(dir_ / "x.txt"));
}

TEST(BakeLaunch, DetectsTheLaunchersByTheirVariables) {
  auto env = [](std::map<std::string, std::string> m) {
    return [m](const char* v) -> const char* {
      auto it = m.find(v);
      return it == m.end() ? nullptr : it->second.c_str();
    };
  };
  EXPECT_FALSE(detectMpiLaunch(env({})).underLauncher);
  EXPECT_FALSE(detectMpiLaunch(env({{"SLURM_JOB_ID", "7"}, {"OMPI_MCA_btl", "self"}})).underLauncher);
  const MpiLaunch ompi = detectMpiLaunch(env({{"OMPI_COMM_WORLD_SIZE", "4"}, {"OMPI_COMM_WORLD_LOCAL_SIZE", "2"}}));
  EXPECT_TRUE(ompi.underLauncher);
  EXPECT_STREQ(ompi.variable, "OMPI_COMM_WORLD_SIZE");
  EXPECT_EQ(ompi.localRanks, 2);
  EXPECT_STREQ(detectMpiLaunch(env({{"PMIX_RANK", "0"}})).variable, "PMIX_RANK");  // srun --mpi=pmix, Open MPI 5
  EXPECT_STREQ(detectMpiLaunch(env({{"PMI_RANK", "3"}})).variable, "PMI_RANK");    // MPICH hydra, srun --mpi=pmi2
  EXPECT_STREQ(detectMpiLaunch(env({{"PMI_SIZE", "3"}})).variable, "PMI_SIZE");
  EXPECT_EQ(detectMpiLaunch(env({{"OMPI_COMM_WORLD_SIZE", "4"}, {"OMPI_COMM_WORLD_LOCAL_SIZE", "x"}})).localRanks, 0);
}

TEST(BakeLaunch, DefaultThreadsSplitTheNode) {
  const int hw = std::max(1, int(std::thread::hardware_concurrency())), cores = coresAvailable();
  ASSERT_GE(cores, 1);
  EXPECT_LE(cores, hw);
  EXPECT_EQ(defaultThreadsPerRank(1), std::min(hw, cores));
  EXPECT_EQ(defaultThreadsPerRank(0), std::min(hw, cores));
  EXPECT_EQ(defaultThreadsPerRank(2), std::max(1, std::min(hw / 2, cores)));
  EXPECT_EQ(defaultThreadsPerRank(4 * hw), 1);
}

TEST(BakeList, EveryLineMakesItsBake) {
  std::set<std::string> names;
  for (const BakeInfo& info : kBakes) {
    EXPECT_TRUE(names.insert(info.name).second) << "duplicate " << info.name;
    EXPECT_NE(std::string(info.description), "");
    const std::unique_ptr<Bake> b = makeBake(info.name);
    ASSERT_NE(b, nullptr) << info.name;
    EXPECT_EQ(b->name(), info.name);
    EXPECT_EQ(b->description(), info.description);
  }
  EXPECT_EQ(makeBake("no-such-bake"), nullptr);
}

// ---- the ambient-occlusion bake ----

std::unique_ptr<Bake> aoBake(std::vector<std::string> args) {
  std::unique_ptr<Bake> b = makeBake("ambient-occlusion");
  CLI::App app;
  b->addOptions(app);
  std::reverse(args.begin(), args.end());  // CLI11 parses a reversed vector
  app.parse(args);
  b->prepare();
  return b;
}

std::vector<float> aoTexels(const Bake& b, bool reverse) {
  std::vector<std::vector<std::byte>> shards(b.shardCount());
  for (size_t i = 0; i < shards.size(); ++i) {
    const size_t k = reverse ? shards.size() - 1 - i : i;  // any order: the shards are independent
    shards[k] = b.runShard(k);
  }
  const fs::path out = fs::temp_directory_path() / fmt::format("ft-bake-ao-{}.bin", ::getpid());
  b.write(shards, out);
  AoTextureFile f = readAoTextureFile(out);
  fs::remove(out);
  return f.ao;
}

TEST(AmbientOcclusionBake, AnyShardSplitEqualsTheCpuBakeBitForBit) {
  AoSettings s{};
  s.resolution = 24;
  s.directions = 8;
  const AoBakeCpu whole = bakeAmbientOcclusionCpu(makeAoParams(makeYarnDensity(findYarnPreset("rayon2")), s));
  for (const char* rows : {"1", "5", "7", "24", "0"}) {
    const auto b = aoBake({"--yarn", "rayon2", "--size", "24", "--directions", "8", "--rows-per-shard", rows});
    for (bool reverse : {false, true}) {
      const std::vector<float> ao = aoTexels(*b, reverse);
      ASSERT_EQ(ao.size(), whole.ao.size());
      EXPECT_EQ(std::memcmp(ao.data(), whole.ao.data(), ao.size() * sizeof(float)), 0)
          << "rows per shard " << rows << (reverse ? ", shards run in reverse" : "");
    }
  }
  EXPECT_EQ(aoBake({"--size", "24", "--rows-per-shard", "5"})->shardCount(), 5u);  // 4 × 5 rows + 4
  EXPECT_EQ(aoBake({"--size", "130"})->shardCount(), 44u);  // default: ⌈130/64⌉ = 3 rows a shard
}

TEST_F(BakeRunner, AmbientOcclusionFileIsSelfDescribingAndIndependentOfTheSplit) {
  std::ostringstream log;
  std::string first;
  for (const char* rows : {"1", "3", "16"}) {
    const auto b = aoBake({"--yarn", "cotton1", "--set", "ply_num=2", "--size", "16", "--directions", "4",
                           "--rows-per-shard", rows});
    const fs::path out = dir_ / fmt::format("ao-{}.bin", rows);
    runBake(*b, {out, 2, true}, log);
    const std::string bytes = readFile(out);
    if (first.empty()) first = bytes;
    EXPECT_EQ(bytes, first) << "rows per shard " << rows;  // the file is the same byte for byte
    const AoTextureFile f = readAoTextureFile(out);
    EXPECT_EQ(f.header["format"], kAoTextureFormat);
    EXPECT_EQ(f.header["yarn"], "cotton1");
    EXPECT_EQ(f.header["set"], nlohmann::json::array({"ply_num=2"}));
    EXPECT_EQ(f.header["resolution"], 16);
    EXPECT_EQ(f.header["directions"], 4);
    EXPECT_EQ(f.header["cubic"].size(), 4u);
    EXPECT_FALSE(f.header.contains("rows_per_shard"));
  }
}

TEST(AmbientOcclusionBake, BadOptionsNameTheOption) {
  EXPECT_THROW(aoBake({"--size", "1"}), CLI::ValidationError);
  EXPECT_THROW(aoBake({"--size", "7"}), CLI::ValidationError);  // 3 radial bins: no cubic fit
  EXPECT_NO_THROW(aoBake({"--size", "8"}));
  EXPECT_THROW(aoBake({"--directions", "0"}), CLI::ValidationError);
  EXPECT_THROW(aoBake({"--seed", "-1"}), CLI::ValidationError);
  try {
    aoBake({"--kappa", "nan"});
    FAIL() << "--kappa nan accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--kappa"), std::string::npos) << e.what();
  }
  try {
    aoBake({"--yarn", "nosuch"});
    FAIL() << "--yarn nosuch accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nosuch"), std::string::npos) << e.what();
  }
}

TEST(AmbientOcclusionBake, ReaderRejectsOtherFiles) {
  const fs::path p = fs::temp_directory_path() / fmt::format("ft-bake-bad-{}.bin", ::getpid());
  for (const std::string& text : {std::string(""), std::string("not json\n"),
                                  std::string("{\"format\":\"fibertwin-ao-texture\",\"version\":1,\"resolution\":2}\nabc")}) {
    std::ofstream(p, std::ios::binary) << text;
    EXPECT_THROW(readAoTextureFile(p), InputError) << text;
  }
  fs::remove(p);
}

}  // namespace
}  // namespace ft
