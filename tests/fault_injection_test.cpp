// Fault injection: every planted shader bug of validation/faults.h must be
// *detected* by the harness — some case fails on each GPU path it lives on
// (Fault::paths), within the cases that can see it (Fault::filter), the fault's
// `caughtBy` metric is among the failures, and no case merely crashed (an
// exception is not a detection). The unmodified build must pass. One test per
// entry of ft::kFaults, so adding a fault adds a test.
// Names start with a lower-case "fault" so that `ctest -R fault` selects them
// (ctest -R is case-sensitive); `ctest -L fault` does too.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cctype>
#include <filesystem>
#include <sstream>
#include <string>
#include <unistd.h>

#include <fmt/format.h>

#include "gpu/gl_context.h"
#include "scene/input_error.h"
#include "validation/faults.h"
#include "validation/harness.h"

namespace ft {
namespace {

namespace fs = std::filesystem;

// A fresh report folder per run, removed when the test is done.
class TempReportDir {
 public:
  explicit TempReportDir(const std::string& tag) {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("fibertwin-fault-test-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(path_);
  }
  ~TempReportDir() {
    std::error_code ec;
    if (!keep_) fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  void keep() { keep_ = true; }

 private:
  fs::path path_;
  bool keep_ = false;
};

HarnessOptions optionsFor(const std::string& inject, const fs::path& reportDir, const std::string& filter = "",
                          const char* model = nullptr) {
  HarnessOptions o;
  o.filter = filter;
  // A fault that only shows on some geometry (Fault::model) runs on that file.
  if (model) {
    const char* src = std::getenv("FT_SOURCE_DIR");
    o.model = fs::path(src ? src : ".") / model;
  }
  o.yarns = {"cotton1"};
  o.images = false;
  o.inject = inject;
  o.reportDir = reportDir;
  o.backend = glBackendFromEnv();
  return o;
}

std::string failingMetrics(const CaseResult& r) {
  std::string s;
  for (const Metric& m : r.metrics)
    if (!m.pass()) s += fmt::format(" {}={:.3g}>{:.3g}", m.name, m.value, m.tolerance);
  return s;
}

// Every case on one line: pass/FAIL, path, failing metrics, error.
std::string describe(const RunSummary& run) {
  std::ostringstream s;
  s << run.results.size() << " cases:\n";
  for (const CaseResult& r : run.results) {
    s << "  " << (r.pass ? "ok  " : "FAIL") << " " << r.name << " [" << (r.path.empty() ? "-" : r.path) << "]"
      << failingMetrics(r);
    if (!r.error.empty()) s << "  error: " << r.error;
    s << "\n";
  }
  return s.str();
}

struct Outcome {
  RunSummary run;
  std::string log;
};

Outcome runHarness(const std::string& inject, TempReportDir& dir, const std::string& filter = "",
                   const char* model = nullptr) {
  std::ostringstream log;
  Outcome o;
  o.run = runValidation(optionsFor(inject, dir.path(), filter, model), log);
  o.log = log.str();
  return o;
}

// ---- the unmodified GPU side -------------------------------------------------
// That every case passes without a fault is validate_default's job: it runs the
// same harness on every preset, cotton1 (the preset used here) among them, in the
// same ctest run. A copy here cost CI 100 s of its 25-minute budget for no check
// validate_default does not already make.

// ---- one test per planted fault ---------------------------------------------

class PlantedFault : public ::testing::TestWithParam<Fault> {};

}  // namespace

// How GoogleTest shows a parameter (found by argument-dependent lookup).
void PrintTo(const Fault& f, std::ostream* os) { *os << f.name << " (" << f.define << ")"; }

namespace {

TEST_P(PlantedFault, IsDetectedOnEveryPathItCanReach) {
  const Fault& fault = GetParam();
  TempReportDir dir(fault.name);
  const Outcome o = runHarness(fault.name, dir, fault.filter, fault.model);
  const std::string all = describe(o.run) + "report: " + dir.path().string() + "\n";
  const std::string intro = std::string("fault ") + fault.name + " (" + fault.description + ")";

  ASSERT_GT(o.run.results.size(), 0u) << intro << ": the harness ran no case\n" << o.log;
  EXPECT_FALSE(o.run.allPassed) << intro << " went undetected: every case passed\n" << all;

  // A crash or exception is not a detection.
  std::string errors;
  for (const CaseResult& r : o.run.results)
    if (!r.error.empty()) errors += "  " + r.name + ": " + r.error + "\n";
  EXPECT_TRUE(errors.empty()) << intro << ": cases threw instead of failing a metric:\n" << errors << all;

  // Every GPU path the fault lives on must catch it (the fiber faults: the
  // tessellation and compute paths; the knit faults: the knit kernel; the
  // ambient-occlusion faults: path "ao", CPU-side checks included).
  std::string failingByPath;
  for (std::string_view rest = fault.paths; !rest.empty();) {
    const size_t comma = rest.find(',');
    const std::string path(rest.substr(0, comma));
    rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    std::string failing;
    for (const CaseResult& r : o.run.results)
      if (!r.pass && r.path == path) failing += " " + r.name;
    EXPECT_FALSE(failing.empty()) << intro << ": no " << path << "-path case failed\n" << all;
    failingByPath += "; " + path + ":" + failing;
  }

  // ... with the metric the fault is documented to trip.
  std::string caughtIn;
  bool metricSeen = false;
  for (const CaseResult& r : o.run.results)
    for (const Metric& m : r.metrics) {
      if (m.name != fault.caughtBy) continue;
      metricSeen = true;
      if (!m.pass()) caughtIn += " " + r.name;
    }
  EXPECT_TRUE(metricSeen) << intro << ": no case reports the metric " << fault.caughtBy << "\n" << all;
  EXPECT_FALSE(caughtIn.empty()) << intro << ": its caughtBy metric " << fault.caughtBy
                                 << " passed in every case (failing elsewhere" << failingByPath << ")\n"
                                 << all;
  if (::testing::Test::HasFailure()) dir.keep();
}

std::string faultTestName(const ::testing::TestParamInfo<Fault>& info) {
  std::string s = info.param.name;
  std::replace_if(s.begin(), s.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
  return s;
}

INSTANTIATE_TEST_SUITE_P(fault, PlantedFault, ::testing::ValuesIn(kFaults), faultTestName);

// ---- shared faults switch their CPU side off again -------------------------

// Each shared fault's CPU switch is on while a run that plants it lives and
// off once it ends (ValidationContext), and no other switch moves with it.
TEST(fault_injection, SharedFaultSwitchIsOnlyOnDuringItsRun) {
  auto switchesOn = [] {
    std::string on;
    for (const Fault& f : kFaults)
      if (f.cpuSwitch && *f.cpuSwitch) on += std::string(" ") + f.name;
    return on;
  };
  for (const Fault& f : kFaults) {
    EXPECT_EQ(f.shared, f.cpuSwitch != nullptr) << f.name << ": a shared fault needs its <DEFINE>_ON switch";
    if (!f.shared) continue;
    TempReportDir dir(std::string(f.name) + "-switch");
    {
      ValidationContext context(optionsFor(f.name, dir.path(), f.filter, f.model));
      EXPECT_EQ(switchesOn(), std::string(" ") + f.name) << "during the run of " << f.name;
    }
    EXPECT_EQ(switchesOn(), "") << "after the run of " << f.name;
  }
}

// End to end, once: after a shared fault's run has failed its cases, the same
// cases pass in the same process (the CPU side really is back to normal).
TEST(fault_injection, SharedFaultIsOffAfterItsRun) {
  const Fault* f = findFault("bcsdf-norm-theta-i");  // shared, and its cases are among the cheapest
  ASSERT_NE(f, nullptr);
  ASSERT_TRUE(f->shared);
  TempReportDir dir(std::string(f->name) + "-off");
  const Outcome with = runHarness(f->name, dir, f->filter, f->model);
  EXPECT_FALSE(with.run.allPassed) << f->name << "\n" << describe(with.run);
  const Outcome without = runHarness("", dir, f->filter, f->model);
  EXPECT_TRUE(without.run.allPassed) << f->name << " stayed on after its run\n" << describe(without.run);
}

// ---- bad --inject names ------------------------------------------------------

TEST(fault_injection, UnknownFaultNameIsAnInputErrorListingTheKnownNames) {
  TempReportDir dir("unknown");
  std::ostringstream log;
  try {
    runValidation(optionsFor("no-such-fault", dir.path()), log);
    FAIL() << "--inject no-such-fault did not throw";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no-such-fault"), std::string::npos) << what;
    for (const Fault& f : kFaults) EXPECT_NE(what.find(f.name), std::string::npos) << "missing " << f.name << ": " << what;
  } catch (const std::exception& e) {
    FAIL() << "expected ft::InputError, got another exception: " << e.what();
  }
  EXPECT_FALSE(fs::exists(dir.path() / "report.json")) << "a report was written for an invalid run";
}

}  // namespace
}  // namespace ft
