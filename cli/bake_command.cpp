#include "cli/bake_command.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <ostream>

#include "scene/input_error.h"

namespace ft {

CLI::App* addBakeCommand(CLI::App& app, BakeCommandOptions& o) {
  CLI::App* bake = app.add_subcommand(
      "bake", "run a bake (bake --list), in one process or across MPI ranks (mpirun -np N fibertwin bake ...)");
  bake->add_flag("--list", o.list, "list the bakes");
  for (const BakeInfo& info : kBakes) {
    std::unique_ptr<Bake> b = makeBake(info.name);
    CLI::App* sub = bake->add_subcommand(info.name, info.description);
    b->addOptions(*sub);
    sub->add_option("--out", o.run.out, "output file (written by rank 0)")->required();
    sub->add_option("--threads", o.run.threads, "TBB threads per rank (default: hardware threads / ranks on the node)")
        ->check(CLI::Range(1, 4096));
    sub->add_flag("--quiet", o.run.quiet, "no progress lines, no summary");
    o.bakes.emplace_back(sub, std::move(b));
  }
  // A name that is no bake: caught here (with the known names), not by CLI11's "not expected".
  bake->add_option("name", o.unknown, "bake name (bake --list)");
  bake->allow_extras();
  for (auto& [sub, b] : o.bakes) sub->allow_extras(false);
  return bake;
}

int runBakeCommand(BakeCommandOptions& o, std::ostream& out) {
  if (o.list) {
    for (const BakeInfo& b : kBakes) out << fmt::format("{:<20} {}\n", b.name, b.description);
    return 0;
  }
  for (auto& [sub, b] : o.bakes)
    if (sub->parsed()) {
      runBake(*b, o.run, out);  // failures throw (no MPI) or abort the job (MPI)
      return 0;
    }
  if (!o.unknown.empty())
    throw InputError(fmt::format("bake: unknown bake '{}' (known: {}; fibertwin bake --list)", o.unknown.front(),
                                 bakeNames()));
  throw InputError(fmt::format("bake: name a bake (known: {}; fibertwin bake --list)", bakeNames()));
}

}  // namespace ft
