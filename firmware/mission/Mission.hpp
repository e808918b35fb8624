#pragma once
// The mission interface. A mission turns what the robot perceives into a motion request, as an
// explicit state machine with named states and phases; the MissionRunner runs one, owns the
// obstacle stop, reports its faults and holds the safe stop. The simulator's scoring, the event
// log and the telemetry see only what is declared here, so goto or coverage missions plug in
// beside follow_line without touching them.
#include <cstdint>

#include "firmware/control/MotionRequest.hpp"
#include "firmware/core/Faults.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"

namespace carril::fw {

// Where a mission is in its life, whatever its own states are called.
enum class MissionStatus : std::uint8_t {
  Starting,   // waiting for devices, finding its way onto the task
  Active,     // doing the task
  Finishing,  // the goal is in reach: driving onto it
  Done,       // goal reached, stopped
  Failed,     // gave up (its fault is in the event log)
};

inline const char* mission_status_name(MissionStatus s) {
  switch (s) {
    case MissionStatus::Starting:
      return "starting";
    case MissionStatus::Active:
      return "active";
    case MissionStatus::Finishing:
      return "finishing";
    case MissionStatus::Done:
      return "done";
    case MissionStatus::Failed:
      return "failed";
  }
  return "?";
}

// A mission's state as everyone outside it sees it. Names are static strings.
struct MissionState {
  MissionStatus status = MissionStatus::Starting;
  std::uint8_t id = 0;     // the mission's own state number (changes are logged)
  const char* name = "";   // e.g. "FOLLOW"
  const char* phase = "";  // e.g. "track"
  bool on_path = false;    // tracking its reference path (the simulator scores cross-track then)
  // Deliberately standing still (waiting for the drives, for a path to clear): the runner's stall
  // watch does not count it as a stall (the state has a timeout of its own).
  bool waiting = false;
};

// A named count a mission keeps (e.g. line_lost_events); reported in telemetry and summaries.
struct MissionCounter {
  const char* name = "";
  std::uint32_t value = 0;
};
using MissionCounters = StaticVector<MissionCounter, 12>;

struct MissionOutput {
  MotionRequest motion;
  Fault fault = Fault::None;  // the mission gives up: latched by the runner, safe stop
};

class ObstacleGuard;

// What the runner hands the mission every tick.
struct MissionContext {
  double t_s = 0.0;           // loop time [s]
  double dt_s = 0.0;          // control period [s]
  bool drives_ready = false;  // every drive reports Operation enabled
  bool imu_ready = true;      // a valid IMU sample has arrived (or no IMU is fitted)
  const ObstacleGuard* guard = nullptr;

  // An obstacle stands ahead, inside the stopping corridor (computed once per tick, on demand).
  bool obstacle_ahead() const;
};

class Mission {
 public:
  virtual ~Mission() = default;
  // Mission name, e.g. "follow_line".
  virtual const char* name() const = 0;
  // Called once, before the first update.
  virtual void enter(const MissionContext& ctx) = 0;
  // Called once when the runner stops the mission (fault, safe stop).
  virtual void exit() = 0;
  // One control period: inputs in, motion request out.
  virtual MissionOutput update(const MissionContext& ctx) = 0;
  virtual MissionState state() const = 0;
  // The phase entered since the last call (static string), or nullptr.
  virtual const char* take_phase_change() = 0;
  virtual void counters(MissionCounters& out) const = 0;
  // The pose jumped (the localisation was regained after being lost): whatever the mission
  // planned from the old pose is void. Called before the next update.
  virtual void relocalised() {}
};

}  // namespace carril::fw
