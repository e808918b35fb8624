#pragma once
// carril_sim --hil: the simulator as the world for an external controller (carril_controller,
// another process, maybe inside user-mode-linux on vcan0). No firmware runs here. The scenario's
// Box2D world moves under one emulated CiA 402 drive per wheel (host_sim/drives), which speak
// CANopen on the bus the caller gives (SocketCAN in carril_sim, the loopback bus in tests); the
// lidar is served as a Hokuyo SCIP 2.0 device over TCP and the camera and IMU through shared
// memory. The caller paces step() (real time in carril_sim, as fast as it likes in tests).
//
// The drives sit on an in-process bus with a bridge to the caller's bus: one socket carries every
// drive's frames, and the bridge sees every frame both ways (the --can-log capture).
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "hal/CanBus.hpp"
#include "hal/can/LoopbackCanBus.hpp"
#include "hal/linux/ShmSensorLink.hpp"
#include "host_sim/drives/DriveEmulator.hpp"
#include "host_sim/hil/ScipServer.hpp"
#include "host_sim/metrics/RunMetrics.hpp"
#include "host_sim/scenario/Scenario.hpp"
#include "host_sim/sensors/CameraRenderer.hpp"
#include "host_sim/sensors/GyroSim.hpp"
#include "host_sim/sensors/LidarSim.hpp"
#include "host_sim/world/SimWorld.hpp"
#include "loader/ControllerSpec.hpp"

namespace carril::sim {

// A fault given to emulated drives at a time: --inject T:DRIVE:WHAT.
struct HilInjection {
  enum class What : std::uint8_t {
    HeartbeatSilence,  // the drive stops producing heartbeats
    BusSilence,        // the drive sends nothing at all
    Fault,             // EMCY `code` and FAULT
    RefuseEnable,      // stuck in Switch on disabled
    Corrupt,           // TPDOs one byte short at the next `count` SYNCs
    Unknown,           // an unknown COB-ID at the next `count` SYNCs
  };
  double t_s = 0.0;  // seconds after the start
  int drive = -1;    // wheel index; -1: every drive
  What what = What::HeartbeatSilence;
  std::uint16_t code = 0x2310;  // Fault: the EMCY error code
  int count = 1;                // Corrupt, Unknown: SYNCs
  std::string text;             // as given on the command line
};

// Parses "T:DRIVE:WHAT" (WHAT: heartbeat_silence, bus_silence, fault:0xCODE, refuse_enable,
// corrupt:N, unknown:N; DRIVE: a wheel index below `wheels` or "all"). False with `why`.
bool parse_injection(const std::string& text, int wheels, HilInjection& out, std::string& why);

struct HilConfig {
  // The controller file carril_controller uses: node ids, counts per revolution, gear ratio and
  // mounting of each drive, so both sides agree by construction.
  loader::ControllerSpec controller;
  std::uint16_t scip_port = 10940;           // the lidar's SCIP 2.0 port on 127.0.0.1; 0: none
  std::string shm_name = "/carril_sensors";  // camera and IMU shared memory; "": none
  std::vector<HilInjection> injections;
  std::FILE* can_log = nullptr;  // every frame on the bus, candump -l lines (not owned)
  std::string can_log_iface = "vcan0";
};

class HilRun {
 public:
  static constexpr double kStepS = 0.01;     // the nominal world step [s]
  static constexpr double kMaxStepS = 0.03;  // the longest step physics takes at once [s]

  // `wire`: the bus to the controller; the run keeps a reference (and to `scenario`).
  HilRun(const Scenario& scenario, std::uint64_t seed, hal::CanBus& wire, const HilConfig& cfg);
  ~HilRun();
  HilRun(const HilRun&) = delete;
  HilRun& operator=(const HilRun&) = delete;

  // Starts the SCIP server and creates the shared memory. False with `error` naming which.
  bool open(std::string& error);
  // One world step of dt_s (at most kMaxStepS; the caller passes the wall time that went by, so
  // the world keeps the controller's time): frames across the bridge, the drives, physics,
  // sensors, metrics.
  void step(double dt_s = kStepS);

  double sim_time_s() const { return t_s_; }
  int wheels() const { return world_.wheel_count(); }
  const DriveEmulator& drive(int i) const { return *drives_[std::size_t(i)]; }
  const RunMetrics& metrics() const { return metrics_; }
  Pose2 pose() const { return world_.pose(); }
  // The largest wheel speed a drive produces [rad/s].
  double max_wheel_speed() const;
  // "t 12.0 s: laps 0, progress 0.31; drives OE OE OE OE; wheels 3.9 3.9 3.9 3.9 rad/s".
  std::string status_line() const;
  // The run's figures as a JSON object (hil_summary.json).
  std::string summary_json() const;
  // SYNCs each drive handled per second and TPDOs it sent per second, over the time since the
  // first SYNC [1/s].
  double sync_rate_hz() const;
  double tpdo_rate_hz() const;
  std::uint64_t frames_from_wire() const { return from_wire_; }
  std::uint64_t frames_to_wire() const { return to_wire_; }
  std::uint64_t wire_refused() const { return wire_refused_; }

 private:
  struct InjectionOutcome {
    const HilInjection* injection = nullptr;
    bool applied = false;
    double stopped_after_s = -1.0;  // first time every wheel < 0.01 rad/s after it [s]
  };
  void bridge();
  void log(const hal::CanFrame& f);
  void apply_injections();
  void publish_sensors();

  const Scenario& scenario_;
  hal::CanBus& wire_;
  HilConfig cfg_;
  SimWorld world_;
  RunMetrics metrics_;
  CameraRenderer camera_;
  LidarSim lidar_;
  GyroSim gyro_;  // the IMU's yaw rate with the robot file's gyro errors, as in SimRun
  hal::LoopbackCanBus drive_bus_;
  std::vector<std::unique_ptr<DriveEmulator>> drives_;
  ScipServer scip_;
  hal::ShmSensorWriter shm_;
  bool shm_open_ = false;
  std::unique_ptr<hal::LaserScan> scan_;
  std::vector<InjectionOutcome> outcomes_;

  double t_s_ = 0.0;  // world time [s]
  double next_cam_s_ = 0.0, next_scan_s_ = 0.0, next_imu_s_ = 0.0;
  double first_sync_s_ = -1.0;
  double master_lost_at_s_ = -1.0;        // first drive that lost the controller's heartbeat
  double stopped_after_master_s_ = -1.0;  // every wheel still, after that [s]
  std::uint64_t from_wire_ = 0, to_wire_ = 0, wire_refused_ = 0;
};

}  // namespace carril::sim
