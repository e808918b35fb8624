#include "host_sim/output/RunOutputs.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <regex>
#include <sstream>

namespace carril::sim {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A fresh, empty directory per test.
class RunOutputsTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() / ("carril_output_test_" + std::to_string(::getpid()) + "_" +
                                     testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(RunOutputsTest, CsvHeaderAndRowFormat) {
  TrajectoryRow r;
  r.t = 1.23456;
  r.x = 1.0;
  r.y = -2.5;
  r.yaw = 0.123456789;
  r.vx = 0.5;
  r.vy = 0.0;
  r.wz = -0.25;
  r.state = "FOLLOW";
  r.cross_track_m = 0.012345;
  const std::string csv = trajectory_to_csv({r});
  EXPECT_EQ(csv,
            "t,x,y,yaw,vx,vy,wz,state,cross_track_m\n"
            "1.235,1.00000,-2.50000,0.12346,0.50000,0.00000,-0.25000,FOLLOW,0.01235\n");
  EXPECT_EQ(trajectory_to_csv({}), "t,x,y,yaw,vx,vy,wz,state,cross_track_m\n");
}

TEST_F(RunOutputsTest, JsonHasContractKeysInOrder) {
  RunSummary s;
  s.scenario = "straight";
  s.unmet_expectations = {"progress 0.5 < 0.9", "collisions 2 > 0"};
  const std::string json = summary_to_json(s);
  std::vector<std::string> keys;
  const std::regex key_re(R"re(^  "([^"]+)":)re");
  std::istringstream lines(json);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_search(line, m, key_re)) keys.push_back(m[1]);
  }
  const std::vector<std::string> expected = {"scenario",
                                             "result",
                                             "passed",
                                             "sim_time_s",
                                             "wall_time_s",
                                             "real_time_factor",
                                             "ticks",
                                             "tick_period_s",
                                             "tick_overruns",
                                             "tick_compute_p50_us",
                                             "tick_compute_p99_us",
                                             "tick_compute_max_us",
                                             "heap_allocations_after_init",
                                             "collisions",
                                             "mover_contacts",
                                             "progress",
                                             "laps",
                                             "cross_track_rms_m",
                                             "cross_track_max_m",
                                             "line_lost_events",
                                             "line_reacquired_events",
                                             "obstacles_avoided",
                                             "end_reached",
                                             "end_stop_error_m",
                                             "path_length_m",
                                             "mean_speed_mps",
                                             "max_abs_wz_radps",
                                             "final_state",
                                             "unmet_expectations",
                                             "fault",
                                             "mission",
                                             "mission_status",
                                             "mission_counters",
                                             "task_overrun_events",
                                             "falls",
                                             "goal_reached",
                                             "goal_error_m",
                                             "goal_yaw_error_deg",
                                             "replans",
                                             "cells_checked",
                                             "coverage",
                                             "coverage_overlap",
                                             "coverage_area_m2",
                                             "coverage_lower_bound_s",
                                             "coverage_time_ratio",
                                             "localisation_rmse_m",
                                             "localisation_max_error_m",
                                             "yaw_rmse_deg",
                                             "time_to_converge_s",
                                             "relocalised_after_kidnap_s",
                                             "relocalised_after_kidnaps_s",
                                             "localisation_counters",
                                             "safety_counters",
                                             "tasks"};
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(json.front(), '{');
  EXPECT_NE(json.find("\"progress 0.5 < 0.9\""), std::string::npos);
}

TEST_F(RunOutputsTest, JsonValues) {
  RunSummary s;
  s.scenario = "say \"hi\"\\ now\n";
  s.ticks = 6000;
  s.progress = 0.123456789123;
  s.sim_time_s = 60.0;
  s.real_time_factor = std::numeric_limits<double>::infinity();
  s.passed = true;
  const std::string json = summary_to_json(s);
  EXPECT_NE(json.find(R"("scenario": "say \"hi\"\\ now\n",)"), std::string::npos) << json;
  EXPECT_NE(json.find("\"end_stop_error_m\": null,"), std::string::npos);
  EXPECT_NE(json.find("\"fault\": null,\n"), std::string::npos);
  EXPECT_NE(json.find("\"unmet_expectations\": [],"), std::string::npos);
  EXPECT_NE(json.find("\"ticks\": 6000,"), std::string::npos);
  EXPECT_NE(json.find("\"sim_time_s\": 60,"), std::string::npos);
  EXPECT_NE(json.find("\"progress\": 0.123456789,"), std::string::npos);
  EXPECT_NE(json.find("\"real_time_factor\": null,"), std::string::npos);
  EXPECT_NE(json.find("\"passed\": true,"), std::string::npos);

  s.end_stop_error_m = 0.02;
  s.fault = "watchdog";
  const std::string json2 = summary_to_json(s);
  EXPECT_NE(json2.find("\"end_stop_error_m\": 0.02,"), std::string::npos);
  EXPECT_NE(json2.find("\"fault\": \"watchdog\",\n"), std::string::npos);
  s.mission = "follow_line";
  s.mission_status = "done";
  s.mission_counters = {{"line_lost_events", 2}, {"obstacles_avoided", 1}};
  const std::string json3 = summary_to_json(s);
  EXPECT_NE(json3.find("\"mission\": \"follow_line\",\n"), std::string::npos) << json3;
  EXPECT_NE(json3.find("\"mission_status\": \"done\",\n"), std::string::npos) << json3;
  EXPECT_NE(
      json3.find("\"mission_counters\": {\"line_lost_events\": 2, \"obstacles_avoided\": 1},\n"),
      std::string::npos)
      << json3;
}

TEST_F(RunOutputsTest, AtomicWriteReplacesAndLeavesNoTemp) {
  const std::string path = (dir_ / "f.txt").string();
  std::string error;
  ASSERT_TRUE(write_file_atomic(path, "first version, longer", error)) << error;
  ASSERT_TRUE(write_file_atomic(path, "second", error)) << error;
  EXPECT_EQ(read_all(path), "second");
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) {
    ++files;
    EXPECT_EQ(e.path().filename(), "f.txt");
  }
  EXPECT_EQ(files, 1);
}

TEST_F(RunOutputsTest, AtomicWriteFailsNamingPath) {
  std::string error;
  EXPECT_FALSE(write_file_atomic("/proc/nonexistent/x", "data", error));
  EXPECT_NE(error.find("/proc/nonexistent/x"), std::string::npos) << error;
}

Scenario demo_scenario() {
  Scenario sc;
  sc.name = "demo";
  sc.floor = {90, 90, 100};
  LineSpec tape;
  tape.color = {255, 255, 255};
  tape.points = {{0, 0}, {4, 0}, {4, 2}};
  sc.lines.push_back(tape);
  MarkSpec mark;
  mark.color = {255, 255, 0};
  mark.center = {4, 2};
  sc.marks.push_back(mark);
  ObstacleSpec box;
  box.center = {2, 1};
  box.yaw_rad = 0.4;
  box.size_x_m = 0.6;
  box.size_y_m = 0.3;
  sc.obstacles.push_back(box);
  ObstacleSpec cyl;
  cyl.shape = ObstacleShape::Cylinder;
  cyl.center = {1, -1};
  cyl.radius_m = 0.2;
  sc.obstacles.push_back(cyl);
  sc.walls.push_back(WallSpec{{{-1, -2}, {6, -2}, {6, 3}}, 0.1});
  TerrainSpec ramp;
  ramp.center = {3, -1};
  ramp.angle_deg = 10;
  sc.terrain.push_back(ramp);
  TerrainSpec step;
  step.type = TerrainType::Step;
  step.center = {5, 1};
  step.height_m = 0.05;
  sc.terrain.push_back(step);
  return sc;
}

TEST_F(RunOutputsTest, WritesFourFilesAndDecodablePngs) {
  const Scenario sc = demo_scenario();
  std::vector<TrajectoryRow> rows;
  for (int i = 0; i <= 400; ++i) {
    TrajectoryRow r;
    r.t = 0.01 * i;
    r.x = 0.01 * i;
    r.y = 0.05 * std::sin(r.t);
    r.vx = 0.5;
    r.wz = 0.1 * std::cos(r.t);
    r.state = i < 200 ? "FOLLOW" : "AVOID";
    rows.push_back(r);
  }
  RunSummary s;
  s.scenario = "demo";
  s.result = "time_limit";
  std::string error;
  const fs::path out = dir_ / "nested" / "run";
  ASSERT_TRUE(write_run_outputs(out.string(), sc, rows, {{1.0, 1.5, 0.0}}, s, error)) << error;
  for (const char* f : {"trajectory.csv", "summary.json", "trajectory.png", "velocities.png"})
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(out)) ++files;
  EXPECT_EQ(files, 4);  // no temporaries left

  const cv::Mat top = cv::imread((out / "trajectory.png").string());
  ASSERT_FALSE(top.empty());
  EXPECT_LE(top.cols, 1200);
  EXPECT_LE(top.rows, 1200);
  EXPECT_GE(std::max(top.cols, top.rows), 600);
  const cv::Mat vel = cv::imread((out / "velocities.png").string());
  ASSERT_FALSE(vel.empty());
  EXPECT_GE(vel.cols, 800);
  EXPECT_GE(vel.rows, 500);
}

TEST_F(RunOutputsTest, EmptyRunStillWritesValidImages) {
  const Scenario sc;  // no geometry at all
  RunSummary s;
  std::string error;
  ASSERT_TRUE(write_run_outputs(dir_.string(), sc, {}, {}, s, error)) << error;
  EXPECT_FALSE(cv::imread((dir_ / "trajectory.png").string()).empty());
  EXPECT_FALSE(cv::imread((dir_ / "velocities.png").string()).empty());
  EXPECT_EQ(read_all(dir_ / "trajectory.csv"), "t,x,y,yaw,vx,vy,wz,state,cross_track_m\n");
}

// --no-plots (campaigns): the two data files only, and a later full run replaces that set.
TEST_F(RunOutputsTest, WithoutPlotsOnlyTheDataFilesAreWritten) {
  const Scenario sc = demo_scenario();
  RunSummary s;
  std::string error;
  ASSERT_TRUE(write_run_outputs(dir_.string(), sc, {}, {}, s, error, {}, false)) << error;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"summary.json", "trajectory.csv"}));
  ASSERT_TRUE(write_run_outputs(dir_.string(), sc, {}, {}, s, error)) << error;
  EXPECT_TRUE(fs::exists(dir_ / "trajectory.png"));
  EXPECT_TRUE(fs::exists(dir_ / "velocities.png"));
}

TEST_F(RunOutputsTest, NonFiniteSamplesDoNotBreakThePlots) {
  const Scenario sc = demo_scenario();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<TrajectoryRow> rows(3);
  rows[1].t = 0.1;
  rows[1].x = nan;
  rows[1].vx = nan;
  rows[2].t = 0.2;
  rows[2].x = 0.1;
  RunSummary s;
  s.progress = nan;
  std::string error;
  ASSERT_TRUE(write_run_outputs(dir_.string(), sc, rows, {}, s, error)) << error;
  EXPECT_NE(read_all(dir_ / "summary.json").find("\"progress\": null"), std::string::npos);
}

// The four outputs of a small run; `variant` changes every file's content.
struct SmallRun {
  explicit SmallRun(int variant) {
    for (int i = 0; i <= 50; ++i) {
      TrajectoryRow r;
      r.t = 0.02 * i;
      r.x = 0.01 * i * (1 + variant);
      r.y = 0.1 * variant;
      r.vx = 0.3 + 0.1 * variant;
      r.wz = 0.05 * variant;
      r.state = "FOLLOW";
      rows.push_back(r);
    }
    summary.scenario = "demo";
    summary.result = variant == 0 ? "time_limit" : "end_reached";
    summary.ticks = 50 + variant;
  }
  bool write(const fs::path& dir, std::string& error) const {
    return write_run_outputs(dir.string(), demo_scenario(), rows, {}, summary, error);
  }
  std::vector<TrajectoryRow> rows;
  RunSummary summary;
};

const std::vector<std::string> kFour = {"trajectory.csv", "trajectory.png", "velocities.png",
                                        "summary.json"};

std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    files[e.path().filename().string()] = read_all(e.path());
  }
  return files;
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class OutputSetTest : public RunOutputsTest {
 protected:
  void TearDown() override {
    set_output_fault_for_test("");
    RunOutputsTest::TearDown();
  }
  fs::path out() const { return dir_ / "out"; }
};

TEST_F(OutputSetTest, SuccessfulWriteReplacesAllFour) {
  std::string error;
  ASSERT_TRUE(SmallRun(0).write(out(), error)) << error;
  const auto first = snapshot(out());
  const SmallRun second_run(1);
  ASSERT_TRUE(second_run.write(out(), error)) << error;
  const auto second = snapshot(out());
  ASSERT_EQ(second.size(), 4u);
  for (const std::string& f : kFour) {
    ASSERT_EQ(second.count(f), 1u) << f;
    EXPECT_NE(second.at(f), first.at(f)) << f << " was not replaced";
  }
  EXPECT_EQ(second.at("trajectory.csv"), trajectory_to_csv(second_run.rows));
  EXPECT_EQ(second.at("summary.json"), summary_to_json(second_run.summary));
  // Nothing left beside it: no staging or set-aside directory.
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"out"});
}

TEST_F(OutputSetTest, FallbackWithoutRenameExchangeReplacesAllFour) {
  std::string error;
  ASSERT_TRUE(SmallRun(0).write(out(), error)) << error;
  const auto first = snapshot(out());
  set_output_fault_for_test("no_exchange");
  const SmallRun second_run(1);
  ASSERT_TRUE(second_run.write(out(), error)) << error;
  const auto second = snapshot(out());
  ASSERT_EQ(second.size(), 4u);
  for (const std::string& f : kFour) EXPECT_NE(second.at(f), first.at(f)) << f;
  EXPECT_EQ(second.at("trajectory.csv"), trajectory_to_csv(second_run.rows));
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"out"});
}

TEST_F(OutputSetTest, FailureAtAnyStepLeavesTheOldSetByteIdentical) {
  std::string error;
  ASSERT_TRUE(SmallRun(0).write(out(), error)) << error;
  const auto before = snapshot(out());
  ASSERT_EQ(before.size(), 4u);
  for (const char* step :
       {"trajectory.csv", "trajectory.png", "velocities.png", "summary.json", "swap"}) {
    set_output_fault_for_test(step);
    error.clear();
    EXPECT_FALSE(SmallRun(1).write(out(), error)) << step;
    EXPECT_NE(error.find("injected failure"), std::string::npos) << step << ": " << error;
    EXPECT_EQ(snapshot(out()), before) << "after a failure at " << step;
    EXPECT_EQ(names_in(dir_), std::vector<std::string>{"out"}) << "staging left after " << step;
  }
}

TEST_F(OutputSetTest, FailedFirstWriteCreatesNothing) {
  set_output_fault_for_test("summary.json");
  std::string error;
  EXPECT_FALSE(SmallRun(0).write(out(), error));
  EXPECT_TRUE(names_in(dir_).empty());
}

TEST_F(OutputSetTest, RefusesADirectoryWithOtherFiles) {
  std::string error;
  ASSERT_TRUE(SmallRun(0).write(out(), error)) << error;
  std::ofstream(out() / "notes.txt") << "mine";
  const auto before = snapshot(out());
  EXPECT_FALSE(prepare_output_dir(out().string(), error));
  EXPECT_NE(error.find("notes.txt"), std::string::npos) << error;
  EXPECT_NE(error.find(out().string()), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(SmallRun(1).write(out(), error));
  EXPECT_NE(error.find("notes.txt"), std::string::npos) << error;
  EXPECT_EQ(snapshot(out()), before);
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"out"});

  // A subdirectory, even one named like an output, is not a previous run's.
  const fs::path other = dir_ / "other";
  fs::create_directories(other / "trajectory.csv");
  EXPECT_FALSE(prepare_output_dir(other.string(), error));
  EXPECT_TRUE(fs::is_directory(other / "trajectory.csv"));

  // A regular file where the directory should be.
  std::ofstream(dir_ / "file") << "x";
  EXPECT_FALSE(prepare_output_dir((dir_ / "file").string(), error));
  EXPECT_NE(error.find("not a directory"), std::string::npos) << error;
}

TEST_F(OutputSetTest, AcceptsEmptyDirectoriesAndStaleLeftovers) {
  std::string error;
  fs::create_directories(out());
  EXPECT_TRUE(prepare_output_dir(out().string(), error)) << error;
  // A per-file temporary of an interrupted older write, and a staging directory of a dead run.
  std::ofstream(out() / "summary.json.tmp.12345") << "{";
  const fs::path stale = dir_ / ".out.tmp.999999999";
  fs::create_directories(stale);
  std::ofstream(stale / "trajectory.csv") << "t\n";
  EXPECT_TRUE(prepare_output_dir((out().string() + "/"), error)) << error;
  EXPECT_FALSE(fs::exists(stale));
  ASSERT_TRUE(SmallRun(0).write(out(), error)) << error;
  EXPECT_EQ(names_in(out()), (std::vector<std::string>{"summary.json", "trajectory.csv",
                                                       "trajectory.png", "velocities.png"}));
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"out"});
}

TEST_F(OutputSetTest, PrepareCreatesParentsAndLeavesNoTrace) {
  std::string error;
  const fs::path deep = dir_ / "a" / "b" / "run";
  EXPECT_TRUE(prepare_output_dir(deep.string(), error)) << error;
  EXPECT_TRUE(fs::is_directory(dir_ / "a" / "b"));
  EXPECT_TRUE(names_in(dir_ / "a" / "b").empty());
}

TEST_F(OutputSetTest, PrepareNamesPathAndReasonOnFailure) {
  std::ofstream(dir_ / "file") << "x";
  std::string error;
  const fs::path under_file = dir_ / "file" / "sub" / "run";
  EXPECT_FALSE(prepare_output_dir(under_file.string(), error));
  EXPECT_NE(error.find((dir_ / "file").string()), std::string::npos) << error;
  EXPECT_NE(error.find("Not a directory"), std::string::npos) << error;
}

}  // namespace
}  // namespace carril::sim
