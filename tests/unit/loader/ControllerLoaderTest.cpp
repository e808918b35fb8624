// The controller file (config/controller/*.yaml): the shipped files load for their robots, and
// every wrong value is refused with the file, line and key named.
#include <gtest/gtest.h>

#include <string>

#include "loader/ControllerLoader.hpp"
#include "tests/unit/loader/LoaderTestUtil.hpp"

namespace carril::loader {
namespace {

using test::edit;
using test::read_text;
using test::robot;
using test::source_path;
using test::write_file;

std::string campero_text() {
  return read_text(source_path("config/controller/campero.yaml"));
}

// Loads `text` (written to a file) for `r`; returns the error, "" when it loaded.
std::string error_of(const std::string& text, const RobotSpec& r, ControllerSpec* out = nullptr) {
  const std::string path = write_file("controller.yaml", text);
  ControllerSpec spec;
  std::string error;
  const bool ok = load_controller(path, r, spec, error);
  EXPECT_EQ(ok, error.empty()) << error;
  if (out != nullptr) *out = spec;
  return error;
}

TEST(ControllerLoader, ShippedCamperoFile) {
  ControllerSpec c;
  std::string error;
  ASSERT_TRUE(
      load_controller(source_path("config/controller/campero.yaml"), robot("campero"), c, error))
      << error;
  EXPECT_EQ(c.can.interface, "can0");
  EXPECT_EQ(c.can.master_node, 127);
  ASSERT_EQ(c.can.drives.size(), 4U);
  EXPECT_EQ(c.can.drives[0].name, "front_left");
  EXPECT_EQ(c.can.drives[3].node, 4);
  EXPECT_DOUBLE_EQ(c.can.drives[2].gear_ratio, 12.52);
  EXPECT_FALSE(c.can.drives[0].inverted);
  EXPECT_TRUE(c.can.drives[1].inverted);
  EXPECT_EQ(c.can.drive_timeout_ms, 120);
  EXPECT_EQ(c.can.feedback_missed_syncs, 12);  // its default: 120 ms in 10 ms periods
  EXPECT_DOUBLE_EQ(c.can.sdo_timeout_s, 0.1);
  EXPECT_DOUBLE_EQ(c.can.quick_stop_decel_radps2, 50.0);
  EXPECT_EQ(c.lidar.source, SensorSource::Scip);
  EXPECT_EQ(c.lidar.host, "192.168.0.10");
  EXPECT_EQ(c.lidar.port, 10940);
  EXPECT_EQ(c.camera.source, SensorSource::Shm);
  EXPECT_EQ(c.camera.name, "/carril_sensors");
  EXPECT_EQ(c.imu.name, "/carril_sensors");
  EXPECT_EQ(c.loop.priority, 50);
  EXPECT_TRUE(c.loop.mlockall);
  EXPECT_EQ(c.loop.overrun_limit, 5);
}

TEST(ControllerLoader, ShippedPioneerAndHilFiles) {
  ControllerSpec c;
  std::string error;
  ASSERT_TRUE(load_controller(source_path("config/controller/pioneer3at.yaml"), robot("pioneer3at"),
                              c, error))
      << error;
  ASSERT_EQ(c.can.drives.size(), 2U);
  EXPECT_EQ(c.lidar.source, SensorSource::None);
  EXPECT_DOUBLE_EQ(c.can.drives[1].counts_per_rev, 2000.0);
  ASSERT_TRUE(load_controller(source_path("config/controller/campero_hil.yaml"), robot("campero"),
                              c, error))
      << error;
  EXPECT_EQ(c.can.interface, "vcan0");
  EXPECT_EQ(c.lidar.host, "127.0.0.1");
  EXPECT_FALSE(c.loop.mlockall);
}

TEST(ControllerLoader, MissingFileIsNamed) {
  ControllerSpec c;
  std::string error;
  EXPECT_FALSE(load_controller("/no/such/controller.yaml", robot("campero"), c, error));
  EXPECT_EQ(error, "/no/such/controller.yaml: cannot open");
}

TEST(ControllerLoader, OneDrivePerWheel) {
  const std::string e = error_of(campero_text(), robot("pioneer3at"));
  EXPECT_NE(e.find("controller.yaml:19: can.drives: expected 2 drives, one per wheel of "
                   "pioneer3at (left, right), got 4"),
            std::string::npos)
      << e;
}

struct BadCase {
  const char* from;
  const char* to;
  const char* expect;  // the message after "<file>:"
};

class ControllerLoaderBad : public ::testing::TestWithParam<BadCase> {};

TEST_P(ControllerLoaderBad, NamesLineKeyAndExpectation) {
  const BadCase& c = GetParam();
  const std::string e = error_of(edit(campero_text(), c.from, c.to), robot("campero"));
  EXPECT_NE(e.find(c.expect), std::string::npos) << "got: " << e;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ControllerLoaderBad,
    ::testing::Values(
        BadCase{"interface: can0", "interface: can0-with-a-long-name",
                ":5: can.interface: expected a network interface name of 1 to 15 letters"},
        BadCase{"interface: can0", "interface: \"can 0\"", ":5: can.interface: expected"},
        BadCase{"node: 2,", "node: 1,",
                ":20: can.drives[1].node: expected a node id no other drive has (front_left "
                "has it), got 1"},
        BadCase{"node: 4,", "node: 127,",
                ":22: can.drives[3].node: expected a node id other than can.master_node (127), "
                "got 127"},
        BadCase{"node: 3,", "node: 128,",
                ":21: can.drives[2].node: expected an integer in [1, 127], got 128"},
        BadCase{"drive_timeout_ms: 120", "drive_timeout_ms: 131",
                ":9: can.drive_timeout_ms: expected more than one drive_heartbeat_ms period and "
                "at most three less two control periods of campero (51 to 130 ms), got 131"},
        BadCase{"drive_timeout_ms: 120", "drive_timeout_ms: 50",
                ":9: can.drive_timeout_ms: expected more than one"},
        BadCase{"master_timeout_ms: 150", "master_timeout_ms: 40",
                ":10: can.master_timeout_ms: expected more than master_heartbeat_ms (50 ms)"},
        BadCase{"max_reads_per_tick: 32", "max_reads_per_tick: 8",
                ":14: can.max_reads_per_tick: expected an integer in [16, 1024], got 8"},
        // At most the drive timeout in control periods (120 ms at 100 Hz): never longer on
        // stale feedback than a lost heartbeat allows.
        BadCase{"max_reads_per_tick: 32", "max_reads_per_tick: 32\n  feedback_missed_syncs: 13",
                ":15: can.feedback_missed_syncs: expected an integer in [2, 12], got 13"},
        BadCase{"max_reads_per_tick: 32", "max_reads_per_tick: 32\n  feedback_missed_syncs: 1",
                ":15: can.feedback_missed_syncs: expected an integer in [2, 12], got 1"},
        // 1e7 x 1000 counts per wheel turn: 1.6e9 counts per rad, beyond int32 at any speed.
        BadCase{"{name: rear_left, node: 3, counts_per_rev: 4096, gear_ratio: 12.52}",
                "{name: rear_left, node: 3, counts_per_rev: 10000000, gear_ratio: 1000}",
                ":21: can.drives[2].counts_per_rev: expected counts_per_rev x gear_ratio that "
                "keep 1.5 x limits.max_wheel_speed_radps"},
        BadCase{"{name: rear_left, node: 3, counts_per_rev: 4096, gear_ratio: 12.52}",
                "{name: rear_left, node: 3, counts_per_rev: 1, gear_ratio: 0.5}",
                ":21: can.drives[2].counts_per_rev: expected counts_per_rev x gear_ratio that "
                "resolve limits.max_wheel_speed_radps"},
        BadCase{"gear_ratio: 12.52}", "gear_ratio: 0}",
                ":19: can.drives[0].gear_ratio: expected a number in [0.01, 1000], got 0"},
        BadCase{"inverted: true}", "inverted: yes}",
                ":20: can.drives[1].inverted: expected true or false"},
        BadCase{"sdo_timeout_s: 0.1", "sdo_timeout: 0.1", ":11: can.sdo_timeout: unknown key"},
        BadCase{"host: 192.168.0.10", "host: 192.168.0.300",
                ":24: sensors.lidar.host: expected an IPv4 address (192.168.0.10), got "
                "\"192.168.0.300\""},
        BadCase{"host: 192.168.0.10", "host: lidar.local",
                ":24: sensors.lidar.host: expected an IPv4 address"},
        BadCase{"port: 10940", "port: 70000",
                ":24: sensors.lidar.port: expected an integer in [1, 65535], got 70000"},
        BadCase{"source: scip", "source: usb",
                ":24: sensors.lidar.source: expected one of none, scip, got \"usb\""},
        BadCase{"name: /carril_sensors}\n  imu", "name: carril_sensors}\n  imu",
                ":25: sensors.camera.name: expected a shared memory name"},
        BadCase{"camera: {source: shm, name: /carril_sensors}", "camera: {source: shm, name: /..}",
                ":25: sensors.camera.name: expected a shared memory name: '/' and 1 to 62 letters, "
                "digits, '_', '-' or '.', not /. or /.."},
        BadCase{"priority: 50", "priority: 99",
                ":27: loop.priority: expected an integer in [0, 98], got 99"},
        BadCase{"overrun_limit: 5", "overrun_limit: 0",
                ":27: loop.overrun_limit: expected an integer in [1, 1000], got 0"}));

}  // namespace
}  // namespace carril::loader
