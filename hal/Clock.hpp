#pragma once
#include "hal/Types.hpp"

namespace carril::hal {

class Clock {
 public:
  virtual ~Clock() = default;
  // Loop time: what deadlines and sensor stamps are measured in (simulated time in the sim) [ns].
  virtual TimeNs now_ns() const = 0;
  // High-resolution time for measuring compute cost; always real time [ns].
  virtual TimeNs cpu_now_ns() const = 0;
  // Block until now_ns() >= t. Called by the loop between ticks, never inside one.
  virtual void sleep_until_ns(TimeNs t) = 0;
};

}  // namespace carril::hal
