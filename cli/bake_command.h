// bake_command.h — `fibertwin bake <name> [bake options] --out FILE` and
// `fibertwin bake --list`: the bakes of bake/bakes.def, one subcommand each,
// run in one process or across MPI ranks (bake/bake_runner.h, docs/bakes.md).
#pragma once
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bake/bake.h"
#include "bake/bake_runner.h"

namespace CLI {
class App;
}

namespace ft {

struct BakeCommandOptions {
  bool list = false;
  std::vector<std::string> unknown;  // what followed `bake` that is not a bake's name
  BakeRunOptions run;                // --out, --threads, --quiet (every bake has them)
  std::vector<std::pair<CLI::App*, std::unique_ptr<Bake>>> bakes;  // one per bakes.def line
};

// Registers `bake` and one subcommand per bake with its own and the common options.
CLI::App* addBakeCommand(CLI::App& app, BakeCommandOptions& options);

// Returns the exit status; throws InputError for bad input (an unknown name,
// bad option values, an unwritable --out).
int runBakeCommand(BakeCommandOptions& options, std::ostream& out);

}  // namespace ft
