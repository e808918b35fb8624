#pragma once
// Where components report run-time faults. The Controller implements it: the first fault latches,
// is counted and logged, and brings the robot to a safe stop; later ones are ignored (the first
// is the one reported).
#include <cstdint>

#include "firmware/core/Faults.hpp"

namespace carril::fw {

class FaultSink {
 public:
  // Reports fault `f` (`code`: the drive's fault code for DriveFault). `in_state`: the mission
  // state it struck in (nullptr: the current one).
  virtual void raise(Fault f, std::uint16_t code = 0, const char* in_state = nullptr) = 0;
  // A fault has latched: the robot is in its safe stop.
  virtual bool latched() const = 0;

 protected:
  ~FaultSink() = default;
};

}  // namespace carril::fw
