#pragma once
// What carril_controller needs beyond the robot description (config/controller/<name>.yaml): the
// CAN bus and the CANopen drives on it, where each sensor's data comes from, and the real-time
// loop's settings. Units as in the file: milliseconds and seconds for times.
#include <string>
#include <vector>

namespace carril::loader {

// One CiA 402 wheel drive, in the robot's wheel order (front-left, front-right, rear-left,
// rear-right; differential: left, right).
struct ControllerDriveSpec {
  std::string name;              // "front_left": named in every message about the drive
  int node = 1;                  // CANopen node id, 1 to 127
  double counts_per_rev = 4096;  // encoder counts per motor revolution
  double gear_ratio = 1.0;       // motor revolutions per wheel revolution
  bool inverted = false;         // mounted mirrored: positive motor speed turns the wheel back
};

struct CanSpec {
  std::string interface = "can0";  // SocketCAN interface name (ip link), 1 to 15 characters
  int master_node = 127;           // the controller's own node id (its heartbeat)
  int master_heartbeat_ms = 50;    // the controller's heartbeat period [ms]
  int drive_heartbeat_ms = 50;     // each drive's heartbeat period, written to 0x1017 [ms]
  int drive_timeout_ms = 150;      // a drive is lost after this silence [ms]
  int master_timeout_ms = 150;     // each drive stops after this silence of the master, 0x1016 [ms]
  double sdo_timeout_s = 0.1;      // one SDO transfer's answer [s]
  double boot_timeout_s = 2.0;     // a drive's boot-up message after reset communication [s]
  double enable_timeout_s = 1.0;   // the CiA 402 enable sequence [s]
  int max_reads_per_tick = 32;     // frames read per control period at most
  int feedback_missed_syncs = 12;  // SYNC periods of missing or bad TPDOs that fault a drive;
                                   // default drive_timeout_ms in control periods
  double accel_radps2 = 25.0;      // profile acceleration 0x6083 [wheel rad/s^2]
  double decel_radps2 = 25.0;      // profile deceleration 0x6084 [wheel rad/s^2]
  double quick_stop_decel_radps2 = 50.0;  // quick stop deceleration 0x6085 [wheel rad/s^2]
  std::vector<ControllerDriveSpec> drives;
};

// Where a sensor's data comes from.
enum class SensorSource { None, Scip, Shm };

struct LidarSourceSpec {
  SensorSource source = SensorSource::None;  // none | scip (Hokuyo SCIP 2.0 over TCP)
  std::string host = "192.168.0.10";         // scip: the sensor's address (UST-10LX default)
  int port = 10940;                          // scip: TCP port
};

struct ShmSourceSpec {
  SensorSource source = SensorSource::None;  // none | shm (the simulator's shared memory link)
  std::string name;                          // shm: POSIX shared memory name, "/carril_camera"
};

struct LoopSpec {
  int priority = 50;      // SCHED_FIFO priority of the control loop, 1 to 98; 0: SCHED_OTHER
  bool mlockall = true;   // lock all pages in memory (no page faults in the loop)
  int overrun_limit = 5;  // consecutive tick overruns that bring a safe stop, 1 to 1000
};

struct ControllerSpec {
  std::string source_path;  // the file it was read from
  CanSpec can;
  LidarSourceSpec lidar;
  ShmSourceSpec camera;
  ShmSourceSpec imu;
  LoopSpec loop;
};

}  // namespace carril::loader
