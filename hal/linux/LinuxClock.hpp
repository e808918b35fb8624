#pragma once
#include "hal/Clock.hpp"

namespace carril::hal {

// CLOCK_MONOTONIC for loop time, absolute-deadline sleeps with clock_nanosleep(TIMER_ABSTIME).
class LinuxClock final : public Clock {
 public:
  TimeNs now_ns() const override;
  TimeNs cpu_now_ns() const override;
  void sleep_until_ns(TimeNs t) override;
};

}  // namespace carril::hal
