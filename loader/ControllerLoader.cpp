#include "loader/ControllerLoader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>

#include "loader/StrictYaml.hpp"

namespace carril::loader {

using strict::Node;
using strict::Range;

namespace {

constexpr const char* kWheelNames4 = "front_left, front_right, rear_left, rear_right";
constexpr const char* kWheelNames2 = "left, right";

// A SocketCAN interface name: what `ip link` accepts (IFNAMSIZ - 1 characters).
std::string parse_interface(const Node& n) {
  const std::string s = n.string();
  const bool ok_chars = std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
  if (s.empty() || s.size() > 15 || !ok_chars) {
    n.expected("a network interface name of 1 to 15 letters, digits, '_', '-' or '.' (can0)",
               "\"" + s + "\"");
  }
  return s;
}

// An IPv4 address in dotted decimal (what a Hokuyo UST is configured with).
std::string parse_ipv4(const Node& n) {
  const std::string s = n.string();
  int parts = 0;
  std::size_t i = 0;
  bool ok = !s.empty();
  while (ok && i <= s.size()) {
    std::size_t j = i;
    int value = 0;
    while (j < s.size() && s[j] >= '0' && s[j] <= '9' && j - i < 3) {
      value = value * 10 + (s[j] - '0');
      ++j;
    }
    ok = j > i && value <= 255;
    ++parts;
    if (j == s.size()) break;
    ok = ok && s[j] == '.';
    i = j + 1;
  }
  if (!ok || parts != 4) n.expected("an IPv4 address (192.168.0.10)", "\"" + s + "\"");
  return s;
}

// A POSIX shared memory object name: "/" then 1 to 63 characters, no other '/'.
std::string parse_shm_name(const Node& n) {
  const std::string s = n.string();
  const bool chars = std::all_of(s.begin() + (s.empty() ? 0 : 1), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
  if (s.size() < 2 || s.size() > 63 || s[0] != '/' || !chars || s == "/." || s == "/..") {
    n.expected(
        "a shared memory name: '/' and 1 to 62 letters, digits, '_', '-' or '.', not /. or /.. "
        "(/carril_camera)",
        "\"" + s + "\"");
  }
  return s;
}

ControllerDriveSpec parse_drive(const Node& m) {
  m.expect_map({"name", "node", "counts_per_rev", "gear_ratio", "inverted"});
  ControllerDriveSpec d;
  d.name = strict::parse_name(m.at("name"));
  d.node = static_cast<int>(m.at("node").integer(1, 127));
  d.counts_per_rev = m.at("counts_per_rev").number(Range::closed(1.0, 1e7));
  d.gear_ratio = m.at("gear_ratio").number(Range::closed(0.01, 1000.0));
  if (auto n = m.get("inverted")) d.inverted = n->boolean();
  return d;
}

// Velocity actual and target velocity are 32-bit counts/s on the bus: the robot's fastest wheel
// (with the 1.5x the feedback watchdog allows) must fit, and one count/s must be a small step of
// it (at most 1 %), or the drive cannot carry the speed range.
void check_pdo_scale(const Node& item, const ControllerDriveSpec& d, const RobotSpec& robot) {
  const double counts_per_rad = d.counts_per_rev * d.gear_ratio / (2.0 * std::numbers::pi);
  const double fastest = robot.limits.max_wheel_speed_radps * 1.5 * counts_per_rad;
  char text[240];
  if (fastest > 2147483647.0) {
    std::snprintf(text, sizeof text,
                  "counts_per_rev x gear_ratio that keep 1.5 x limits.max_wheel_speed_radps "
                  "(%g rad/s) within a 32-bit PDO (%.4g counts/s > 2147483647)",
                  robot.limits.max_wheel_speed_radps * 1.5, fastest);
    item.at("counts_per_rev").expected(text, item.at("counts_per_rev").raw());
  }
  if (robot.limits.max_wheel_speed_radps * counts_per_rad < 100.0) {
    std::snprintf(text, sizeof text,
                  "counts_per_rev x gear_ratio that resolve limits.max_wheel_speed_radps "
                  "(%g rad/s) in at least 100 counts/s (%.3g)",
                  robot.limits.max_wheel_speed_radps,
                  robot.limits.max_wheel_speed_radps * counts_per_rad);
    item.at("counts_per_rev").expected(text, item.at("counts_per_rev").raw());
  }
}

void parse_can(const Node& m, const RobotSpec& robot, CanSpec& c) {
  m.expect_map({"interface", "master_node", "master_heartbeat_ms", "drive_heartbeat_ms",
                "drive_timeout_ms", "master_timeout_ms", "sdo_timeout_s", "boot_timeout_s",
                "enable_timeout_s", "max_reads_per_tick", "feedback_missed_syncs", "ramps",
                "drives"});
  c.interface = parse_interface(m.at("interface"));
  c.master_node = static_cast<int>(m.at("master_node").integer(1, 127));
  c.master_heartbeat_ms = static_cast<int>(m.at("master_heartbeat_ms").integer(10, 10000));
  c.drive_heartbeat_ms = static_cast<int>(m.at("drive_heartbeat_ms").integer(10, 10000));
  // The contract: every wheel stopped within 3 of a drive's heartbeat periods after its last
  // heartbeat. The master notices a loss at a control tick, so the consumer time plus two
  // control periods must fit in 3 heartbeat periods; at or under one period a heartbeat merely
  // late by jitter would count as lost.
  const Node dt = m.at("drive_timeout_ms");
  c.drive_timeout_ms = static_cast<int>(dt.integer(1, 65535));
  const int period_ms = static_cast<int>(std::ceil(1000.0 / robot.control_rate_hz));
  const int hi = 3 * c.drive_heartbeat_ms - 2 * period_ms;
  if (c.drive_timeout_ms <= c.drive_heartbeat_ms || c.drive_timeout_ms > hi) {
    dt.expected(
        "more than one drive_heartbeat_ms period and at most three less two control "
        "periods of " +
            robot.preset + " (" + std::to_string(c.drive_heartbeat_ms + 1) + " to " +
            std::to_string(hi) + " ms)",
        dt.raw());
  }
  // 0x1016's consumer time is 16 bits of milliseconds; at or under one period of the master's
  // heartbeat the drives would stop on jitter.
  const Node mt = m.at("master_timeout_ms");
  c.master_timeout_ms = static_cast<int>(mt.integer(1, 65535));
  if (c.master_timeout_ms <= c.master_heartbeat_ms) {
    mt.expected("more than master_heartbeat_ms (" + std::to_string(c.master_heartbeat_ms) +
                    " ms) and at most 65535 ms",
                mt.raw());
  }
  c.sdo_timeout_s = m.at("sdo_timeout_s").number(Range::closed(0.005, 5.0));
  c.boot_timeout_s = m.at("boot_timeout_s").number(Range::closed(0.01, 60.0));
  c.enable_timeout_s = m.at("enable_timeout_s").number(Range::closed(0.01, 60.0));
  const Node ramps = m.at("ramps");
  ramps.expect_map({"accel_radps2", "decel_radps2", "quick_stop_decel_radps2"});
  const Range ramp = Range::closed(0.1, 1000.0);
  c.accel_radps2 = ramps.at("accel_radps2").number(ramp);
  c.decel_radps2 = ramps.at("decel_radps2").number(ramp);
  c.quick_stop_decel_radps2 = ramps.at("quick_stop_decel_radps2").number(ramp);

  const Node drives = m.at("drives");
  const auto items = drives.items();
  const int wheels = wheel_count(robot);
  if (static_cast<int>(items.size()) != wheels) {
    drives.expected(std::to_string(wheels) + " drives, one per wheel of " + robot.preset + " (" +
                        (wheels == 4 ? kWheelNames4 : kWheelNames2) + ")",
                    std::to_string(items.size()));
  }
  c.drives.clear();
  for (const Node& item : items) {
    ControllerDriveSpec d = parse_drive(item);
    check_pdo_scale(item, d, robot);
    const Node node = item.at("node");
    if (d.node == c.master_node) {
      node.expected("a node id other than can.master_node (" + std::to_string(c.master_node) + ")",
                    node.raw());
    }
    for (const ControllerDriveSpec& other : c.drives) {
      if (other.node == d.node) {
        node.expected("a node id no other drive has (" + other.name + " has it)", node.raw());
      }
      if (other.name == d.name) {
        item.at("name").expected("a name no other drive has", "\"" + d.name + "\"");
      }
    }
    c.drives.push_back(d);
  }
  // Each period brings two TPDOs per drive plus heartbeats and EMCY: reading fewer would let the
  // receive queue grow without bound.
  const int min_reads = 4 * wheels;
  c.max_reads_per_tick = static_cast<int>(m.at("max_reads_per_tick").integer(min_reads, 1024));
  // Optional: one late frame must not stop the robot, and a drive must not run on stale
  // feedback longer than a lost heartbeat would let it. Default and bound: drive_timeout_ms in
  // control periods (a silent drive faults on both at about the same time).
  const int most = std::max(2, int(c.drive_timeout_ms / (1000.0 / robot.control_rate_hz)));
  c.feedback_missed_syncs = most;
  if (auto n = m.get("feedback_missed_syncs")) {
    c.feedback_missed_syncs = static_cast<int>(n->integer(2, most));
  }
}

void parse_sensors(const Node& m, ControllerSpec& c) {
  m.expect_map({"lidar", "camera", "imu"});
  const Node lidar = m.at("lidar");
  lidar.expect_map({"source", "host", "port"});
  const std::string ls = lidar.at("source").one_of({"none", "scip"});
  if (ls == "scip") {
    c.lidar.source = SensorSource::Scip;
    c.lidar.host = parse_ipv4(lidar.at("host"));
    c.lidar.port = static_cast<int>(lidar.at("port").integer(1, 65535));
  } else {
    c.lidar.source = SensorSource::None;
  }
  for (auto [key, out] : {std::pair{"camera", &c.camera}, std::pair{"imu", &c.imu}}) {
    const Node s = m.at(key);
    s.expect_map({"source", "name"});
    if (s.at("source").one_of({"none", "shm"}) == "shm") {
      out->source = SensorSource::Shm;
      out->name = parse_shm_name(s.at("name"));
    } else {
      out->source = SensorSource::None;
    }
  }
}

void parse_loop(const Node& m, LoopSpec& l) {
  m.expect_map({"priority", "mlockall", "overrun_limit"});
  l.priority = static_cast<int>(m.at("priority").integer(0, 98));
  l.mlockall = m.at("mlockall").boolean();
  l.overrun_limit = static_cast<int>(m.at("overrun_limit").integer(1, 1000));
}

ControllerSpec read_controller_file(const std::string& path, const RobotSpec& robot) {
  const std::string text = strict::read_file(path);
  const Node root = strict::parse_document(text, &path);
  root.expect_map({"can", "sensors", "loop"});
  ControllerSpec c;
  c.source_path = path;
  parse_can(root.at("can"), robot, c.can);
  parse_sensors(root.at("sensors"), c);
  parse_loop(root.at("loop"), c.loop);
  return c;
}

}  // namespace

int wheel_count(const RobotSpec& robot) {
  return robot.drive == DriveType::Mecanum ? 4 : 2;
}

bool load_controller(const std::string& path, const RobotSpec& robot, ControllerSpec& out,
                     std::string& error) {
  ControllerSpec spec;
  if (!strict::guarded(path, error, [&] { spec = read_controller_file(path, robot); })) {
    return false;
  }
  out = spec;
  return true;
}

}  // namespace carril::loader
