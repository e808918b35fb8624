#pragma once
// The mission's state as everyone outside it sees it (the schedule, the event log, telemetry, the
// simulator's scoring), whatever its own states are called; and the view the schedule reads it
// through, so that it depends on no mission.
#include <cstdint>

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

// Read-only view of the running mission's state: implemented by every Mission and by the
// MissionRunner (which reports the mission it runs); read by the Controller.
class MissionStateSource {
 public:
  virtual ~MissionStateSource() = default;
  virtual MissionState state() const = 0;
  // The phase entered since the last call (static string), or nullptr.
  virtual const char* take_phase_change() = 0;
};

}  // namespace carril::fw
