#pragma once
// What the map missions (goto, waypoints, coverage) share in reporting their state: a start-up
// wait, a running part and two ends. One place for the state-to-status rule that each mission's
// state() used to write out, and for the output of a fault.
#include <cstdint>

#include "firmware/mission/Mission.hpp"
#include "firmware/mission/MissionPhase.hpp"

namespace carril::fw {

// The MissionState of state `s` of a mission whose State has Wait (for the drives and the first
// pose: Starting, and waiting, a timeout of its own), Done and Failed; every other state is
// `running` (Active, or Finishing on the way onto the last goal).
template <class State>
MissionState report_state(State s, const char* name, const MissionPhase& phase,
                          MissionStatus running, bool on_path = false) {
  MissionState m;
  m.id = static_cast<std::uint8_t>(s);
  m.name = name;
  m.phase = phase.current();
  m.on_path = on_path;
  if (s == State::Wait) {
    m.status = MissionStatus::Starting;
    m.waiting = true;
  } else if (s == State::Done) {
    m.status = MissionStatus::Done;
  } else if (s == State::Failed) {
    m.status = MissionStatus::Failed;
  } else {
    m.status = running;
  }
  return m;
}

// The output of a tick that ends the mission with fault `f` (the runner stops the robot safely).
inline MissionOutput fault_output(Fault f) {
  MissionOutput out;
  out.fault = f;
  return out;
}

}  // namespace carril::fw
