// bake.h — a bake: a deterministic computation split into independent shards
// that `fibertwin bake` runs in one process or across the ranks of an MPI job
// (bake/bake_runner.h, docs/bakes.md). The bakes are listed once, in
// bake/bakes.def; adding one is a line there and a file bake/<alg>_bake.cpp.
//
// The determinism contract (what makes `cmp` of two outputs the check):
//   * prepare() builds the same state on every rank from the options alone;
//   * runShard(k) depends on k and that state only, never on the rank, the
//     thread count or the time, so any process may run any shard;
//   * write() combines the shards in shard order (every sum in the same
//     order whatever ran where) and writes nothing that depends on rank
//     count, thread count, time or host.
#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace CLI {
class App;
}

namespace ft {

class Bake {
 public:
  virtual ~Bake() = default;

  // Its name and description, as bakes.def gives them (makeBake sets them).
  const std::string& name() const { return name_; }
  const std::string& description() const { return description_; }

  // Registers the bake's own options on its `fibertwin bake <name>` command.
  virtual void addOptions(CLI::App& app) = 0;
  // After parsing: checks the option values (InputError naming the option
  // and the value) and builds what every shard needs.
  virtual void prepare() = 0;
  virtual size_t shardCount() const = 0;
  // Deterministic, any process, any order; may use TBB inside. Throws on failure.
  virtual std::vector<std::byte> runShard(size_t shard) const = 0;
  // Rank 0 only: shards[k] is runShard(k); writes one file at `out`.
  virtual void write(std::span<const std::vector<std::byte>> shards, const std::filesystem::path& out) const = 0;

 protected:
  std::string name_, description_;
  friend std::unique_ptr<Bake> makeBake(std::string_view name);
};

// ---- the list (bakes.def) ----
#define FT_BAKE(name, factory, description) std::unique_ptr<Bake> factory();
#include "bake/bakes.def"
#undef FT_BAKE

struct BakeInfo {
  const char* name;  // `fibertwin bake <name>`
  const char* description;
  std::unique_ptr<Bake> (*factory)();
};

inline constexpr BakeInfo kBakes[] = {
#define FT_BAKE(name, factory, description) {name, description, &factory},
#include "bake/bakes.def"
#undef FT_BAKE
};

// The bake of that name (name and description set), or nullptr.
std::unique_ptr<Bake> makeBake(std::string_view name);
// "a, b, c": the known names, for error messages.
std::string bakeNames();

}  // namespace ft
