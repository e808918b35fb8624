#pragma once
// The mission interface. A mission turns what the robot perceives into a motion request, as an
// explicit state machine with named states and phases; the MissionRunner runs one, owns the
// obstacle stop, reports its faults and holds the safe stop. The simulator's scoring, the event
// log and the telemetry see only what is declared here, so goto or coverage missions plug in
// beside follow_line without touching them.
#include <cstdint>

#include "firmware/core/Faults.hpp"
#include "firmware/core/Geometry.hpp"
#include "firmware/core/StaticVector.hpp"
#include "firmware/msg/MissionState.hpp"
#include "firmware/msg/MotionRequest.hpp"

namespace carril::fw {

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

// state() and take_phase_change() come from MissionStateSource.
class Mission : public MissionStateSource {
 public:
  // Mission name, e.g. "follow_line".
  virtual const char* name() const = 0;
  // Called once, before the first update.
  virtual void enter(const MissionContext& ctx) = 0;
  // Called once when the runner stops the mission (fault, safe stop).
  virtual void exit() = 0;
  // One control period: inputs in, motion request out.
  virtual MissionOutput update(const MissionContext& ctx) = 0;
  virtual void counters(MissionCounters& out) const = 0;
  // The pose jumped (the localisation was regained after being lost): whatever the mission
  // planned from the old pose is void. Called before the next update.
  virtual void relocalised() {}
};

}  // namespace carril::fw
