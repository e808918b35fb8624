#pragma once
#include <cstdint>

namespace carril::fw {

// Run-time faults. Each one latches, brings the robot to a safe stop and is counted.
enum class Fault : std::uint8_t {
  None,
  CameraTimeout,       // no new camera frame within camera_timeout_s
  CameraBadFrame,      // frame size differs from the configured camera
  ScannerTimeout,      // no new lidar scan within lidar.timeout_s
  DriveFault,          // a wheel drive reports Fault (its code is in the event)
  DriveEnableTimeout,  // drives did not reach Operation enabled in time
  LineNotFound,        // the search found no tape
  PathBlocked,         // an obstacle on the tape with no room to pass either side
  ScannerBlind,        // lidar scans keep coming, but too few beams are valid (health.scan)
  CameraBlank,         // camera frames keep coming, all one colour (health.frame)
  CameraFrozen,        // camera frames keep coming, the same image while the robot moves
  ImuOutOfRange,       // IMU reads NaN, inf or what the robot cannot do (health.imu)
  ImuFrozen,           // IMU sample no longer changes (same stamp, or same values while turning)
  ImuTimeout,          // a fitted IMU delivered no valid sample within watch.imu_timeout_s, or
                       // none at all by the end of start-up
  TickOverrun,         // more consecutive ticks than the overrun limit overran their budget or
                       // missed their deadline (the loop cannot keep its rate)
  NoPath,              // goto: no traversable path from the robot to the goal on the costmap
  GoalInvalid,         // goto: the goal is outside the costmap or inside an obstacle
  NoCoverageArea,      // coverage: no free cell to cover (no static map, or the area eroded by
                       // the robot's radius holds no cell where it fits)
  NotLocalised,        // on a map, the pose stayed unlocalised (the mission held) longer than
                       // runner.max_unlocalised_s
  Stalled,             // the mission made no progress for runner.stall_timeout_s while not
                       // deliberately waiting (turning in place at a fork, say)
  MotionBlocked,       // no safe motion (every turn, pivot or leg the robot needs is blocked
                       // on the costmap) for runner.blocked_timeout_s
  CheckFailed,         // a programming error: a CARRIL_CHECK failed (the event's code is its
                       // line; CheckFailures has the file)
  Count,
};

inline const char* fault_name(Fault f) {
  switch (f) {
    case Fault::None:
      return "none";
    case Fault::CameraTimeout:
      return "camera_timeout";
    case Fault::CameraBadFrame:
      return "camera_bad_frame";
    case Fault::ScannerTimeout:
      return "scanner_timeout";
    case Fault::DriveFault:
      return "drive_fault";
    case Fault::DriveEnableTimeout:
      return "drive_enable_timeout";
    case Fault::LineNotFound:
      return "line_not_found";
    case Fault::PathBlocked:
      return "path_blocked";
    case Fault::ScannerBlind:
      return "scanner_blind";
    case Fault::CameraBlank:
      return "camera_blank";
    case Fault::CameraFrozen:
      return "camera_frozen";
    case Fault::ImuOutOfRange:
      return "imu_out_of_range";
    case Fault::ImuFrozen:
      return "imu_frozen";
    case Fault::ImuTimeout:
      return "imu_timeout";
    case Fault::TickOverrun:
      return "tick_overrun";
    case Fault::NoPath:
      return "no_path";
    case Fault::GoalInvalid:
      return "goal_invalid";
    case Fault::NoCoverageArea:
      return "no_coverage_area";
    case Fault::NotLocalised:
      return "not_localised";
    case Fault::Stalled:
      return "stalled";
    case Fault::MotionBlocked:
      return "motion_blocked";
    case Fault::CheckFailed:
      return "check_failed";
    case Fault::Count:
      break;
  }
  return "?";
}

}  // namespace carril::fw
