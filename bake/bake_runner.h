// bake_runner.h — runs a Bake (bake/bake.h) in one of three modes:
//   * no MPI: the process was not started by an MPI launcher (no
//     OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_RANK or PMI_SIZE in the
//     environment): MPI is never called; every shard runs here, in order;
//   * MPI, N ranks: dynamic self-scheduling. Rank 0's main thread is the
//     coordinator, the only thread that calls MPI (MPI_THREAD_FUNNELED): it
//     hands out shard indices on request and receives the results; a worker
//     thread on rank 0 takes shards from the same queue (so 2 ranks are 2
//     workers), the other ranks loop request → run → send. Rank 0 writes;
//   * started by a launcher but built without MPI: an InputError (each rank
//     would redo the whole bake).
// Progress (rank 0, stderr, at most once a second) and a summary (stdout);
// the output does not depend on the mode, the rank count or the threads.
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <vector>

#include "bake/bake.h"

namespace ft {

struct BakeRunOptions {
  std::filesystem::path out;
  int threads = 0;  // TBB threads per rank; 0: hardware threads / ranks on this node
  bool quiet = false;
};

// What the environment says about the launch. `getenv` is injectable for tests.
struct MpiLaunch {
  bool underLauncher = false;
  const char* variable = nullptr;  // the variable that said so
  int localRanks = 0;              // OMPI_COMM_WORLD_LOCAL_SIZE when set, else 0
};
MpiLaunch detectMpiLaunch(const std::function<const char*(const char*)>& getenv);
bool builtWithMpi();

// Cores this process may run on (its affinity mask: mpirun binds ranks).
int coresAvailable();
// min(hardware threads / localRanks, coresAvailable()), at least 1.
int defaultThreadsPerRank(int localRanks);

// The checks before any work: --out names a file in an existing, writable
// folder (InputError naming --out and the path otherwise).
void checkBakeOutput(const std::filesystem::path& out);

struct BakeRunSummary {
  size_t shards = 0;
  int ranks = 1, threads = 1;
  double seconds = 0.0;
  std::vector<size_t> shardsPerRank;  // rank 0 only
  bool wroteOutput = false;           // false on ranks other than 0
  std::filesystem::path out;          // what rank 0 wrote
};

// Runs `bake` (options already parsed) and writes options.out (rank 0, via a
// temporary file renamed at the end). No MPI: a shard's exception comes back
// as std::runtime_error naming the bake and the shard; under MPI the failing
// rank prints it and calls MPI_Abort (no rank is left waiting).
BakeRunSummary runBake(Bake& bake, const BakeRunOptions& options, std::ostream& log);

}  // namespace ft
