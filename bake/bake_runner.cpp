// bake_runner.cpp — see bake_runner.h. This is the only file that includes
// <mpi.h>; everything else of fibertwin builds and runs without MPI.
#include "bake/bake_runner.h"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <mutex>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <thread>

#include "scene/input_error.h"

#ifndef FT_WITH_MPI
#define FT_WITH_MPI 0  // bake/CMakeLists.txt defines it 1 when CMake found MPI
#endif
#if FT_WITH_MPI
#include <mpi.h>
#endif

namespace ft {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string shardError(const Bake& bake, size_t shard, size_t shards, const char* what) {
  return fmt::format("bake {}: shard {} of {}: {}", bake.name(), shard, shards, what);
}

// The test hook of tests/bake_mpi_test.sh (like --inject for the shaders):
// FT_BAKE_FAIL_RANK=R makes the first shard rank R runs throw, so a failure
// on a worker rank and on rank 0's worker thread can each be planted.
std::vector<std::byte> runShardOn(const Bake& bake, size_t shard, int rank) {
  static std::atomic<bool> planted{false};
  const char* fail = std::getenv("FT_BAKE_FAIL_RANK");
  if (fail && std::string(fail) == std::to_string(rank) && !planted.exchange(true))
    throw std::runtime_error(fmt::format("planted failure on rank {} (FT_BAKE_FAIL_RANK)", rank));
  return bake.runShard(shard);
}

// "shard k/N done, elapsed, ETA" on stderr, at most once a second and at the
// end: a long bake on many ranks says how far it is without flooding the log.
class Progress {
 public:
  Progress(const Bake& bake, size_t total, bool quiet) : bake_(bake), total_(total), quiet_(quiet) {}
  void update(size_t done) {
    if (quiet_ || done == reported_) return;
    const auto now = Clock::now();
    if (done < total_ && now - last_ < std::chrono::seconds(1)) return;
    last_ = now;
    reported_ = done;
    const double elapsed = secondsSince(start_);
    const double eta = done > 0 ? elapsed / double(done) * double(total_ - done) : 0.0;
    std::cerr << fmt::format("bake {}: shard {}/{} done, {:.1f} s elapsed, ETA {:.1f} s\n", bake_.name(), done, total_,
                             elapsed, eta)
              << std::flush;
  }
  double elapsed() const { return secondsSince(start_); }

 private:
  const Bake& bake_;
  size_t total_, reported_ = 0;
  bool quiet_;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
};

// Writes through a temporary file beside `out`, renamed at the end: a failed
// or aborted bake leaves no half-written output under the requested name.
void writeOutput(const Bake& bake, std::span<const std::vector<std::byte>> shards, const std::filesystem::path& out) {
  std::filesystem::path part = out;
  part += ".part";
  try {
    bake.write(shards, part);
    std::filesystem::rename(part, out);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(part, ec);
    throw;
  }
}

void printSummary(const Bake& bake, const BakeRunSummary& s, std::ostream& log) {
  std::string perRank;
  for (size_t r = 0; r < s.shardsPerRank.size(); ++r) perRank += fmt::format("{}{}", r ? " " : "", s.shardsPerRank[r]);
  log << fmt::format("bake {}: {} shards on {} rank{} × {} thread{} in {:.2f} s (shards per rank: {}) → {}\n",
                     bake.name(), s.shards, s.ranks, s.ranks == 1 ? "" : "s", s.threads, s.threads == 1 ? "" : "s",
                     s.seconds, perRank, s.out.string());
}

BakeRunSummary runLocal(Bake& bake, const BakeRunOptions& o, int threads, std::ostream& log) {
  checkBakeOutput(o.out);
  BakeRunSummary s;
  s.threads = threads;
  s.shards = bake.shardCount();
  Progress progress(bake, s.shards, o.quiet);
  std::vector<std::vector<std::byte>> results(s.shards);
  for (size_t k = 0; k < s.shards; ++k) {
    try {
      results[k] = runShardOn(bake, k, 0);
    } catch (const std::exception& e) {
      throw std::runtime_error(shardError(bake, k, s.shards, e.what()));
    }
    progress.update(k + 1);
  }
  writeOutput(bake, results, o.out);
  s.seconds = progress.elapsed();
  s.shardsPerRank = {s.shards};
  s.wroteOutput = true;
  s.out = o.out;
  if (!o.quiet) printSummary(bake, s, log);
  return s;
}

#if FT_WITH_MPI

constexpr int kTagReady = 1;   // worker → 0: first request, empty
constexpr int kTagResult = 2;  // worker → 0: 8-byte shard index + the shard's bytes; also the next request
constexpr int kTagWork = 3;    // 0 → worker: a shard index
constexpr int kTagStop = 4;    // 0 → worker: no shards left

[[noreturn]] void abortRun(const std::string& message, int code) {
  std::cerr << "fibertwin: " << message << "\n" << std::flush;
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();  // MPI_Abort does not return
}

// Open MPI's blocking calls poll a core while they wait; a rank waiting for
// its next shard (or for the other ranks at the end) must not take the core
// a worker needs, so: MPI_Test, then a short sleep.
void waitPolitely(MPI_Request& request, MPI_Status* status) {
  for (;;) {
    int done = 0;
    MPI_Test(&request, &done, status);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

void workerRank(const Bake& bake, int rank) {
  const size_t n = bake.shardCount();
  MPI_Send(nullptr, 0, MPI_BYTE, 0, kTagReady, MPI_COMM_WORLD);
  std::vector<std::byte> message;
  for (;;) {
    uint64_t shard = 0;
    MPI_Request request;
    MPI_Status status;
    MPI_Irecv(&shard, 1, MPI_UINT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &request);
    waitPolitely(request, &status);
    if (status.MPI_TAG == kTagStop) return;
    std::vector<std::byte> result;
    try {
      result = runShardOn(bake, size_t(shard), rank);
    } catch (const std::exception& e) {
      abortRun(fmt::format("rank {}: {}", rank, shardError(bake, size_t(shard), n, e.what())), 3);
    }
    if (result.size() > size_t(INT_MAX) - sizeof shard)
      abortRun(fmt::format("rank {}: {}", rank, shardError(bake, size_t(shard), n, "more than 2 GiB: split it finer")), 3);
    message.resize(sizeof shard + result.size());
    std::memcpy(message.data(), &shard, sizeof shard);  // same host byte order on every rank (docs/bakes.md)
    if (!result.empty()) std::memcpy(message.data() + sizeof shard, result.data(), result.size());
    MPI_Isend(message.data(), int(message.size()), MPI_BYTE, 0, kTagResult, MPI_COMM_WORLD, &request);
    waitPolitely(request, MPI_STATUS_IGNORE);
  }
}

// Rank 0: the coordinator (this thread, the only one calling MPI) and a
// worker thread taking shards from the same queue.
BakeRunSummary coordinatorRank(const Bake& bake, const BakeRunOptions& o, int ranks, int threads, std::ostream& log) {
  BakeRunSummary s;
  s.ranks = ranks;
  s.threads = threads;
  s.shards = bake.shardCount();
  s.shardsPerRank.assign(size_t(ranks), 0);
  const size_t n = s.shards;

  std::mutex mutex;  // guards everything below that the worker thread touches
  size_t next = 0, done = 0;
  std::vector<std::vector<std::byte>> results(n);
  std::vector<bool> have(n, false);
  std::string workerError;
  auto take = [&]() -> std::optional<size_t> {
    std::lock_guard lock(mutex);
    if (next >= n) return std::nullopt;
    return next++;
  };

  Progress progress(bake, n, o.quiet);
  std::thread worker([&] {
    while (const std::optional<size_t> k = take()) {
      try {
        std::vector<std::byte> r = runShardOn(bake, *k, 0);
        std::lock_guard lock(mutex);
        results[*k] = std::move(r);
        have[*k] = true;
        ++s.shardsPerRank[0];
        ++done;
      } catch (const std::exception& e) {
        std::lock_guard lock(mutex);
        workerError = shardError(bake, *k, n, e.what());
        return;
      }
    }
  });

  int active = ranks - 1;  // ranks not yet told to stop
  std::vector<std::byte> buffer;
  for (;;) {
    size_t finished;
    {
      std::lock_guard lock(mutex);
      if (!workerError.empty()) abortRun("rank 0: " + workerError, 3);
      finished = done;
    }
    progress.update(finished);
    if (finished == n && active == 0) break;
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    buffer.resize(size_t(count));
    MPI_Recv(buffer.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (status.MPI_TAG == kTagResult) {
      uint64_t k = 0;
      if (buffer.size() >= sizeof k) std::memcpy(&k, buffer.data(), sizeof k);
      std::lock_guard lock(mutex);
      if (buffer.size() < sizeof k || k >= n || have[k])
        abortRun(fmt::format("rank 0: bake {}: malformed result from rank {} ({} bytes, shard {})", bake.name(),
                             status.MPI_SOURCE, buffer.size(), k),
                 3);
      results[k].assign(buffer.begin() + sizeof k, buffer.end());
      have[k] = true;
      ++s.shardsPerRank[size_t(status.MPI_SOURCE)];
      ++done;
    } else if (status.MPI_TAG != kTagReady) {
      abortRun(fmt::format("rank 0: bake {}: unexpected message tag {} from rank {}", bake.name(), status.MPI_TAG,
                           status.MPI_SOURCE),
               3);
    }
    // The reply to a request: the next shard, or stop (a dummy index).
    const std::optional<size_t> k = take();
    const uint64_t shard = k ? uint64_t(*k) : 0;
    MPI_Send(&shard, 1, MPI_UINT64_T, status.MPI_SOURCE, k ? kTagWork : kTagStop, MPI_COMM_WORLD);
    if (!k) --active;
  }
  worker.join();
  writeOutput(bake, results, o.out);
  s.seconds = progress.elapsed();
  s.wroteOutput = true;
  s.out = o.out;
  if (!o.quiet) printSummary(bake, s, log);
  return s;
}

// MPI_Init_thread … MPI_Finalize. Any error after MPI_Init aborts the whole
// job with its message: a rank that threw and returned would leave the
// others waiting for it.
BakeRunSummary runMpi(Bake& bake, const BakeRunOptions& o, int localRanksFromEnv, std::ostream& log) {
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  if (provided < MPI_THREAD_FUNNELED)
    abortRun("bake: the MPI library does not provide MPI_THREAD_FUNNELED (rank 0 runs a worker thread)", 3);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  BakeRunSummary s;
  try {
    int localRanks = localRanksFromEnv;
    if (localRanks <= 0) {  // launchers other than Open MPI's: ask MPI which ranks share this node
      MPI_Comm node;
      MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
      MPI_Comm_size(node, &localRanks);
      MPI_Comm_free(&node);
    }
    const int threads = o.threads > 0 ? o.threads : defaultThreadsPerRank(localRanks);
    tbb::global_control control(tbb::global_control::max_allowed_parallelism, size_t(threads));
    if (rank == 0) {
      checkBakeOutput(o.out);
      if (threads > coresAvailable() && !o.quiet)  // Open MPI binds 1 or 2 ranks to one core each by default
        std::cerr << fmt::format("fibertwin: warning: --threads {} but rank 0 may run on {} core{} only (mpirun binds "
                                 "ranks to cores: add --bind-to none)\n",
                                 threads, coresAvailable(), coresAvailable() == 1 ? "" : "s");
      s = coordinatorRank(bake, o, ranks, threads, log);
    } else {
      workerRank(bake, rank);
      s.ranks = ranks;
      s.threads = threads;
      s.shards = bake.shardCount();
    }
  } catch (const std::exception& e) {
    abortRun(fmt::format("rank {}: {}", rank, e.what()), dynamic_cast<const InputError*>(&e) ? 2 : 3);
  }
  MPI_Finalize();
  return s;
}

#endif  // FT_WITH_MPI

int envInt(const std::function<const char*(const char*)>& getenv, const char* name) {
  const char* v = getenv(name);
  if (!v || !*v) return 0;
  char* end = nullptr;
  const long x = std::strtol(v, &end, 10);
  return *end == '\0' && x > 0 && x < INT_MAX ? int(x) : 0;
}

}  // namespace

MpiLaunch detectMpiLaunch(const std::function<const char*(const char*)>& getenv) {
  MpiLaunch l;
  // Open MPI's mpirun; PMIx launchers (Open MPI 5, srun --mpi=pmix); PMI-1/2 (MPICH hydra, srun --mpi=pmi2).
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    if (getenv(v)) {
      l.underLauncher = true;
      l.variable = v;
      break;
    }
  }
  l.localRanks = envInt(getenv, "OMPI_COMM_WORLD_LOCAL_SIZE");
  return l;
}

bool builtWithMpi() { return FT_WITH_MPI != 0; }

int coresAvailable() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return int(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(1, CPU_COUNT(&set));
}

int defaultThreadsPerRank(int localRanks) {
  const int hw = int(std::max(1u, std::thread::hardware_concurrency()));
  return std::max(1, std::min(hw / std::max(1, localRanks), coresAvailable()));
}

void checkBakeOutput(const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  if (out.empty()) throw InputError("--out: empty path");
  std::error_code ec;
  if (fs::is_directory(out, ec))
    throw InputError(fmt::format("--out: '{}' is a directory, not a file", out.string()));
  const fs::path folder = out.has_parent_path() ? out.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, ec))
    throw InputError(fmt::format("--out: '{}': the folder '{}' does not exist", out.string(), folder.string()));
  if (::access(folder.c_str(), W_OK) != 0)
    throw InputError(fmt::format("--out: '{}': the folder '{}' is not writable", out.string(), folder.string()));
}

BakeRunSummary runBake(Bake& bake, const BakeRunOptions& o, std::ostream& log) {
  const MpiLaunch launch = detectMpiLaunch([](const char* v) { return std::getenv(v); });
  if (o.threads < 0 || o.threads > 4096)
    throw InputError(fmt::format("--threads: {} is out of range (1 to 4096; 0: the default)", o.threads));
  if (launch.underLauncher && !builtWithMpi())
    throw InputError(fmt::format(
        "bake: started by an MPI launcher ({} is set) but this fibertwin was built without MPI, so every rank "
        "would redo the whole bake; rebuild with libopenmpi-dev installed, or run it without mpirun/srun",
        launch.variable));
  bake.prepare();  // every rank, before MPI: bad options fail the same way everywhere
#if FT_WITH_MPI
  if (launch.underLauncher) return runMpi(bake, o, launch.localRanks, log);
#endif
  const int threads = o.threads > 0 ? o.threads : defaultThreadsPerRank(1);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, size_t(threads));
  return runLocal(bake, o, threads, log);
}

}  // namespace ft
