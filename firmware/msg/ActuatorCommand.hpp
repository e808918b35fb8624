#pragma once
// Message `command`: what one tick produces for the drives.
#include <array>
#include <cstdint>

#include "firmware/core/Geometry.hpp"
#include "hal/Types.hpp"

namespace carril::fw {

enum class DriveRequest : std::uint8_t {
  Disable,    // drives off
  Run,        // enable and follow wheel_radps
  QuickStop,  // brake to zero and hold (safe stop)
};

// Every one of the first `wheels` drives reports Operation enabled.
inline bool drives_enabled(const hal::WheelFeedbackSet& fb, int wheels) {
  if (fb.count < wheels) return false;
  for (int i = 0; i < wheels; ++i) {
    if (fb.wheel[i].state != hal::DriveState::Enabled) return false;
  }
  return true;
}

struct ActuatorCommand {
  DriveRequest drive = DriveRequest::QuickStop;
  std::uint8_t wheel_count = 0;
  std::array<float, hal::kMaxWheels> wheel_radps{};  // setpoints [rad/s]
  Twist twist;                                       // body twist these come from [m/s, rad/s]
};

// The safe stop, written once: brake to zero and hold, every setpoint and the twist zero.
inline void quick_stop(ActuatorCommand& c) {
  c.drive = DriveRequest::QuickStop;
  c.wheel_radps.fill(0.0F);
  c.twist = {};
}

}  // namespace carril::fw
