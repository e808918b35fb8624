// The local runner with a stand-in simulator (a shell script that behaves as told by its
// scenario's seed): statuses for a pass, a failed expectation, a refused input and a crash;
// finished variants are not run again; a stopped campaign leaves no status for the variants it
// stopped and resumes them; another campaign's folder is refused; the CSV has a row per run.
#include "host_sim/campaign/Runner.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "host_sim/campaign/Results.hpp"
#include "host_sim/campaign/Variant.hpp"

namespace carril::sim::campaign {
namespace {
namespace fs = std::filesystem;

const std::string kSrc = CARRIL_SOURCE_DIR;

// The stand-in: counts its runs in $FAKE_SIM_COUNT, then by the seed's value modulo 5 passes,
// fails, refuses its input, crashes, or (4) sleeps until stopped (SIGTERM).
const char* kFakeSim = R"(#!/bin/bash
scenario=$2; out=$4
echo run >> "$FAKE_SIM_COUNT"
if [ -n "$FAKE_SIM_PIDS" ]; then echo $$ >> "$FAKE_SIM_PIDS"; fi
seed=$(sed -n 's/^seed: //p' "$scenario")
mkdir -p "$out"
printf '{\n  "scenario": "fake",\n  "seed_mod": %d,\n  "counters": {"a": 1}\n}\n' $((seed % 5)) > "$out/summary.json"
case $((seed % 5)) in
  0) exit 0 ;;
  1) exit 1 ;;
  2) exit 2 ;;
  3) kill -SEGV $$ ;;
  4) if [ -n "$FAKE_SIM_HANG" ]; then exec sleep 30; fi; exit 0 ;;
esac
)";

class RunnerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("carril_runner_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    sim_ = (dir_ / "fake_sim.sh").string();
    std::ofstream(sim_) << kFakeSim;
    fs::permissions(sim_, fs::perms::owner_all);
    count_ = (dir_ / "count").string();
    ::setenv("FAKE_SIM_COUNT", count_.c_str(), 1);
    ::unsetenv("FAKE_SIM_HANG");
    ::unsetenv("FAKE_SIM_PIDS");
    const CampaignLoad r = load_campaign_text(text_, kSrc + "/scenarios/campaigns/test.yaml");
    ASSERT_TRUE(r.ok) << r.error;
    spec_ = r.spec;
    opt_.out_dir = (dir_ / "out").string();
    opt_.sim_path = sim_;
    opt_.jobs = 3;
    opt_.progress = false;
  }
  void TearDown() override { fs::remove_all(dir_); }

  int runs_counted() const {
    std::ifstream in(count_);
    int n = 0;
    for (std::string line; std::getline(in, line);) ++n;
    return n;
  }
  std::vector<std::uint64_t> all() const {
    std::vector<std::uint64_t> v(spec_.variant_count());
    for (std::uint64_t i = 0; i < v.size(); ++i) v[i] = i;
    return v;
  }
  std::string expected_status(std::uint64_t i) const {
    static const char* kByMod[] = {"exit 0", "exit 1", "exit 2", "signal 11", "exit 0"};
    return kByMod[make_variant(spec_, i).seed % 5];
  }

  const std::string text_ =
      "name: t\nseed: 5\nscenarios: [../circle.yaml]\nvariants: 12\n"
      "perturbations: {wheel_slip: {uniform: [0, 0.05]}}\n";
  fs::path dir_;
  std::string sim_, count_;
  CampaignSpec spec_;
  RunnerOptions opt_;
};

TEST_F(RunnerTest, EveryVariantRunsOnceWithItsStatus) {
  std::string error;
  ASSERT_TRUE(prepare_campaign_dir(spec_, text_, opt_.out_dir, error)) << error;
  const RunCounts c = run_variants(spec_, all(), opt_);
  EXPECT_TRUE(c.error.empty()) << c.error;
  EXPECT_FALSE(c.interrupted);
  EXPECT_EQ(c.ran, 12u);
  EXPECT_EQ(c.skipped, 0u);
  EXPECT_EQ(c.passed + c.failed + c.errors, 12u);
  std::set<std::string> kinds;
  for (std::uint64_t i = 0; i < 12; ++i) {
    EXPECT_EQ(variant_status(opt_.out_dir, i), expected_status(i)) << i;
    kinds.insert(expected_status(i));
    EXPECT_TRUE(fs::exists(fs::path(variant_dir(opt_.out_dir, i)) / "scenario.yaml"));
  }
  EXPECT_GE(kinds.size(), 3u);  // the seeds cover several outcomes
  EXPECT_EQ(runs_counted(), 12);
  // Nothing finished runs twice.
  const RunCounts again = run_variants(spec_, all(), opt_);
  EXPECT_EQ(again.ran, 0u);
  EXPECT_EQ(again.skipped, 12u);
  EXPECT_EQ(runs_counted(), 12);
  // The CSV: a header and a row per variant.
  const CollectResult r = collect_results(spec_, opt_.out_dir);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.rows, 12u);
  std::ifstream in(fs::path(opt_.out_dir) / "results.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header,
            "index,base_scenario,preset,strategy,seed,wheel_slip,status,scenario,seed_mod,"
            "counters.a");
  int lines = 0;
  for (std::string l; std::getline(in, l);) ++lines;
  EXPECT_EQ(lines, 12);
}

TEST_F(RunnerTest, AStoppedCampaignResumesWhatItStopped) {
  std::string error;
  ASSERT_TRUE(prepare_campaign_dir(spec_, text_, opt_.out_dir, error)) << error;
  ::setenv("FAKE_SIM_HANG", "1", 1);
  opt_.jobs = 12;
  // Stop the campaign (as Ctrl-C does) once every fast variant has finished.
  std::thread stopper([&] {
    for (int k = 0; k < 500; ++k) {
      int finished = 0;
      for (std::uint64_t i = 0; i < 12; ++i) finished += !variant_status(opt_.out_dir, i).empty();
      int hanging = 0;
      for (std::uint64_t i = 0; i < 12; ++i) hanging += make_variant(spec_, i).seed % 5 == 4;
      if (finished == 12 - hanging) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    std::raise(SIGINT);
  });
  const RunCounts c = run_variants(spec_, all(), opt_);
  stopper.join();
  EXPECT_TRUE(c.interrupted);
  int hanging = 0;
  for (std::uint64_t i = 0; i < 12; ++i) {
    const bool hangs = make_variant(spec_, i).seed % 5 == 4;
    hanging += hangs;
    EXPECT_EQ(variant_status(opt_.out_dir, i).empty(), hangs) << i;
  }
  ASSERT_GT(hanging, 0);  // the seeds include a variant that hangs
  EXPECT_EQ(c.ran, 12u - std::uint64_t(hanging));
  // Resumed: only the stopped ones run again.
  ::unsetenv("FAKE_SIM_HANG");
  const RunCounts r = run_variants(spec_, all(), opt_);
  EXPECT_FALSE(r.interrupted);
  EXPECT_EQ(r.ran, std::uint64_t(hanging));
  EXPECT_EQ(r.skipped, 12u - std::uint64_t(hanging));
  EXPECT_EQ(runs_counted(), 12 + hanging);
  for (std::uint64_t i = 0; i < 12; ++i)
    EXPECT_EQ(variant_status(opt_.out_dir, i), expected_status(i));
}

// Issue 46 item 6: a closed terminal (SIGHUP) stops the campaign as Ctrl-C does, resumable.
TEST_F(RunnerTest, AHangupStopsTheCampaignLikeCtrlC) {
  std::string error;
  ASSERT_TRUE(prepare_campaign_dir(spec_, text_, opt_.out_dir, error)) << error;
  ::setenv("FAKE_SIM_HANG", "1", 1);
  opt_.jobs = 12;
  std::thread stopper([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    std::raise(SIGHUP);
  });
  const RunCounts c = run_variants(spec_, all(), opt_);
  stopper.join();
  EXPECT_TRUE(c.interrupted);
  EXPECT_TRUE(c.error.empty()) << c.error;
  for (std::uint64_t i = 0; i < 12; ++i) {
    if (make_variant(spec_, i).seed % 5 == 4) EXPECT_EQ(variant_status(opt_.out_dir, i), "") << i;
  }
}

// A second runner on the same folder is refused; a Slurm array's tasks share the folder.
TEST_F(RunnerTest, ASecondRunnerOnTheSameFolderIsRefused) {
  std::string error;
  ASSERT_TRUE(prepare_campaign_dir(spec_, text_, opt_.out_dir, error)) << error;
  const std::string lock_path = (fs::path(opt_.out_dir) / ".lock").string();
  const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);  // a runner holds the folder
  RunCounts c = run_variants(spec_, all(), opt_);
  EXPECT_EQ(c.error, opt_.out_dir + ": another carril_campaign is running on this folder (" +
                         lock_path + " is locked); wait for it or stop it first");
  EXPECT_EQ(c.ran, 0u);
  EXPECT_EQ(runs_counted(), 0);
  ASSERT_EQ(::flock(fd, LOCK_SH), 0);  // now an array task holds it
  opt_.shared_lock = true;             // another array task: welcome
  c = run_variants(spec_, all(), opt_);
  EXPECT_TRUE(c.error.empty()) << c.error;
  EXPECT_EQ(c.ran, 12u);
  opt_.shared_lock = false;  // a local run beside the array: refused
  EXPECT_FALSE(run_variants(spec_, all(), opt_).error.empty());
  ::close(fd);
}

// A runner killed with SIGKILL takes its simulators with it: none is left to write into the
// folders a resumed campaign uses.
TEST_F(RunnerTest, AKilledRunnerLeavesNoSimulatorBehind) {
  std::string error;
  ASSERT_TRUE(prepare_campaign_dir(spec_, text_, opt_.out_dir, error)) << error;
  const std::string pids = (dir_ / "pids").string();
  ::setenv("FAKE_SIM_PIDS", pids.c_str(), 1);
  ::setenv("FAKE_SIM_HANG", "1", 1);
  opt_.jobs = 12;
  const pid_t runner = ::fork();
  ASSERT_GE(runner, 0);
  if (runner == 0) {
    run_variants(spec_, all(), opt_);
    ::_exit(0);
  }
  auto started = [&] {
    std::ifstream in(pids);
    std::vector<pid_t> v;
    for (pid_t p = 0; in >> p;) v.push_back(p);
    return v;
  };
  for (int k = 0; k < 500 && started().size() < 12; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const std::vector<pid_t> sims = started();
  ASSERT_EQ(sims.size(), 12u);
  ::kill(runner, SIGKILL);
  ::waitpid(runner, nullptr, 0);
  // Gone, or a zombie waiting for init: either way it runs no more.
  auto running = [](pid_t p) {
    std::ifstream stat("/proc/" + std::to_string(p) + "/stat");
    std::string pid, comm, state;
    if (!(stat >> pid >> comm >> state)) return false;
    return state != "Z" && state != "X";
  };
  int alive = 0;
  for (int k = 0; k < 200; ++k) {
    alive = 0;
    for (const pid_t p : sims) alive += running(p);
    if (alive == 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(alive, 0) << "simulators still running after their runner was killed";
}

TEST_F(RunnerTest, AnotherCampaignsFolderIsRefused) {
  std::string error;
  ASSERT_TRUE(prepare_campaign_dir(spec_, text_, opt_.out_dir, error)) << error;
  ASSERT_TRUE(prepare_campaign_dir(spec_, text_, opt_.out_dir, error)) << error;  // a resume
  EXPECT_FALSE(prepare_campaign_dir(spec_, text_ + "# changed\n", opt_.out_dir, error));
  EXPECT_NE(error.find("another campaign"), std::string::npos) << error;
  const fs::path other = dir_ / "other";
  fs::create_directories(other);
  std::ofstream(other / "x.txt") << "x";
  EXPECT_FALSE(prepare_campaign_dir(spec_, text_, other.string(), error));
  EXPECT_NE(error.find("not a campaign's folder"), std::string::npos) << error;
}

TEST_F(RunnerTest, AMissingSimulatorIsAnError) {
  std::string error;
  ASSERT_TRUE(prepare_campaign_dir(spec_, text_, opt_.out_dir, error)) << error;
  opt_.sim_path = (dir_ / "no_such_sim").string();
  const RunCounts c = run_variants(spec_, all(), opt_);
  // posix_spawn reports a missing file either at once or as the child's exit 127.
  if (c.error.empty()) {
    EXPECT_EQ(c.errors, 12u);
    EXPECT_EQ(variant_status(opt_.out_dir, 0), "exit 127");
  } else {
    EXPECT_NE(c.error.find("no_such_sim"), std::string::npos) << c.error;
  }
}

}  // namespace
}  // namespace carril::sim::campaign
